//! `EXT_meshopt_compression` (and its ratified successor
//! `KHR_meshopt_compression`) decoded when a file is read: what
//! `gltfpack -c` writes for the web.
//!
//! A compressed buffer view keeps its place in a *fallback* buffer (whose
//! bytes the file may omit) and carries, in the extension, where its
//! compressed bytes are and how to decode them: a mode (vertex attributes,
//! triangle indices, index sequences), an element count and stride, and a
//! filter applied after decoding (octahedral normals, quaternions,
//! exponent-mantissa floats, YCoCg colors). Decoding writes every view's
//! elements to its place in the fallback buffer; the document then reads
//! as if it had never been compressed, and the extension is removed from
//! it (outputs are written uncompressed). The decoder is meshoptimizer's
//! own, through the `meshopt` crate: it is safe on untrusted input (a bad
//! stream is an error, or garbage values the reader's checks catch).

use serde_json::Value;

use crate::ErrorKind;

/// The extension names, as used on buffers, buffer views and in the
/// document's extension lists.
pub(crate) const MESHOPT: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// At most this many decoded bytes per compressed byte (plus a fixed
/// allowance): index sequences and constant streams compress far, but a
/// file claiming more is hostile, and its buffers are not allocated.
const MAX_EXPANSION: u64 = 256;
const EXPANSION_ALLOWANCE: u64 = 64 << 20;

/// The compression extension object of `v` (a buffer or a buffer view).
fn extension(v: &Value) -> Option<&Value> {
    let e = v.get("extensions")?;
    MESHOPT.iter().find_map(|n| e.get(*n))
}

/// Whether buffer `b` is a fallback buffer (its data may be absent: the
/// compressed views fill it).
pub(crate) fn is_fallback(buffer: &Value) -> bool {
    extension(buffer)
        .and_then(|e| e.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// Whether the document uses either compression extension.
pub(crate) fn declared(json: &Value) -> bool {
    ["extensionsUsed", "extensionsRequired"].iter().any(|k| {
        json.get(*k).and_then(Value::as_array).is_some_and(|a| {
            a.iter()
                .any(|e| MESHOPT.iter().any(|n| e.as_str() == Some(*n)))
        })
    })
}

/// The size a fallback buffer's bytes must have: its declared length,
/// when the compressed data can plausibly expand to it.
pub(crate) fn fallback_size(declared: u64, compressed_total: u64) -> Result<usize, String> {
    let limit = compressed_total
        .saturating_mul(MAX_EXPANSION)
        .saturating_add(EXPANSION_ALLOWANCE);
    if declared > limit {
        return Err(format!(
            "declares {declared} bytes to be decoded from {compressed_total} compressed bytes; \
             refusing to allocate them"
        ));
    }
    usize::try_from(declared).map_err(|_| format!("declares {declared} bytes"))
}

/// Total compressed bytes the views of `json` name (for [`fallback_size`]).
pub(crate) fn compressed_bytes(json: &Value) -> u64 {
    json.get("bufferViews")
        .and_then(Value::as_array)
        .map(|views| {
            views
                .iter()
                .filter_map(extension)
                .filter_map(|e| e.get("byteLength").and_then(Value::as_u64))
                .fold(0u64, u64::saturating_add)
        })
        .unwrap_or(0)
}

/// Decodes every compressed view of `json` into its fallback buffer in
/// `buffers` and removes the extension from the document. `buffers` are
/// the loaded buffers (fallback ones already sized to their declared
/// length, zero-filled when the file omits them).
pub(crate) fn decode_views(json: &mut Value, buffers: &mut [Vec<u8>]) -> Result<(), ErrorKind> {
    let count = json
        .get("bufferViews")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    for v in 0..count {
        let view = &json["bufferViews"][v];
        let Some(ext) = extension(view).cloned() else {
            continue;
        };
        let here = || format!("bufferView {v} ({})", MESHOPT[0]);
        let num = |o: &Value, k: &str, default: Option<u64>| -> Result<usize, ErrorKind> {
            o.get(k)
                .and_then(Value::as_u64)
                .or(default)
                .and_then(|x| usize::try_from(x).ok())
                .ok_or_else(|| ErrorKind::malformed(here(), format!("{k} missing or invalid")))
        };
        let source = num(&ext, "buffer", None)?;
        let offset = num(&ext, "byteOffset", Some(0))?;
        let length = num(&ext, "byteLength", None)?;
        let stride = num(&ext, "byteStride", None)?;
        let elements = num(&ext, "count", None)?;
        let mode = ext.get("mode").and_then(Value::as_str).unwrap_or("");
        let filter = ext.get("filter").and_then(Value::as_str).unwrap_or("NONE");
        let target = num(view, "buffer", None)?;
        let at = num(view, "byteOffset", Some(0))?;
        let size = elements
            .checked_mul(stride)
            .ok_or_else(|| ErrorKind::malformed(here(), "count × byteStride overflows"))?;
        if num(view, "byteLength", None)? < size {
            return Err(ErrorKind::malformed(
                here(),
                format!("byteLength is below count {elements} × byteStride {stride}"),
            ));
        }
        let encoded = buffers
            .get(source)
            .and_then(|b| b.get(offset..offset.checked_add(length)?))
            .ok_or_else(|| {
                ErrorKind::malformed(
                    here(),
                    format!("compressed bytes lie outside buffer {source}"),
                )
            })?;
        let decoded = decode(encoded, mode, filter, elements, stride)
            .map_err(|m| ErrorKind::malformed(here(), m))?;
        let place = buffers
            .get_mut(target)
            .and_then(|b| b.get_mut(at..at.checked_add(size)?))
            .ok_or_else(|| {
                ErrorKind::malformed(here(), format!("its place lies outside buffer {target}"))
            })?;
        place.copy_from_slice(&decoded);
        if let Some(e) = json["bufferViews"][v]
            .get_mut("extensions")
            .and_then(Value::as_object_mut)
        {
            for n in MESHOPT {
                e.remove(n);
            }
        }
    }
    strip(json);
    Ok(())
}

/// Removes the extensions from buffers, views and the document's lists.
fn strip(json: &mut Value) {
    for key in ["buffers", "bufferViews"] {
        if let Some(items) = json.get_mut(key).and_then(Value::as_array_mut) {
            for item in items {
                let Some(o) = item.as_object_mut() else {
                    continue;
                };
                if let Some(e) = o.get_mut("extensions").and_then(Value::as_object_mut) {
                    for n in MESHOPT {
                        e.remove(n);
                    }
                    if e.is_empty() {
                        o.remove("extensions");
                    }
                }
            }
        }
    }
    for key in ["extensionsUsed", "extensionsRequired"] {
        if let Some(list) = json.get_mut(key).and_then(Value::as_array_mut) {
            list.retain(|e| !MESHOPT.iter().any(|n| e.as_str() == Some(*n)));
        }
    }
}

/// One view's elements, decoded and filtered, `count × stride` bytes.
fn decode(
    encoded: &[u8],
    mode: &str,
    filter: &str,
    count: usize,
    stride: usize,
) -> Result<Vec<u8>, String> {
    let failed = |e: meshopt::Error| format!("cannot be decoded: {e}");
    let out = match (mode, stride) {
        ("TRIANGLES", 2) => {
            bytes(&meshopt::decode_index_buffer::<u16>(encoded, count).map_err(failed)?)
        }
        ("TRIANGLES", 4) => {
            bytes(&meshopt::decode_index_buffer::<u32>(encoded, count).map_err(failed)?)
        }
        ("INDICES", 2) => {
            bytes(&meshopt::decode_index_sequence::<u16>(encoded, count).map_err(failed)?)
        }
        ("INDICES", 4) => {
            bytes(&meshopt::decode_index_sequence::<u32>(encoded, count).map_err(failed)?)
        }
        ("ATTRIBUTES", s) if s % 4 == 0 => vertices(encoded, count, s / 4)?,
        _ => {
            return Err(format!(
                "mode {mode:?} with byteStride {stride} is not a valid combination"
            ))
        }
    };
    let mut out = out;
    match (filter, mode, stride) {
        ("NONE", _, _) => {}
        ("OCTAHEDRAL", "ATTRIBUTES", 4) => in_place(&mut out, meshopt::decode_filter_oct::<i8>),
        ("OCTAHEDRAL", "ATTRIBUTES", 8) => in_place(&mut out, meshopt::decode_filter_oct::<i16>),
        ("QUATERNION", "ATTRIBUTES", 8) => in_place(&mut out, meshopt::decode_filter_quat),
        ("COLOR", "ATTRIBUTES", 4) => in_place(&mut out, meshopt::decode_filter_color::<u8>),
        ("COLOR", "ATTRIBUTES", 8) => in_place(&mut out, meshopt::decode_filter_color::<u16>),
        ("EXPONENTIAL", "ATTRIBUTES", s) if s % 4 == 0 => exponential(&mut out, s / 4),
        _ => {
            return Err(format!(
                "filter {filter:?} with mode {mode:?} and byteStride {stride} is not supported"
            ))
        }
    }
    Ok(out)
}

/// The native bytes of plain values.
fn bytes<T: Copy + NativeBytes>(values: &[T]) -> Vec<u8> {
    values.iter().flat_map(|v| v.native()).collect()
}

/// Values that are their bytes (integers and arrays of them).
trait NativeBytes {
    fn native(&self) -> Vec<u8>;
    fn from_native(b: &[u8]) -> Self;
}

macro_rules! native_int {
    ($($t:ty),*) => {$(
        impl NativeBytes for $t {
            fn native(&self) -> Vec<u8> {
                self.to_ne_bytes().to_vec()
            }
            fn from_native(b: &[u8]) -> Self {
                const N: usize = std::mem::size_of::<$t>();
                let mut a = [0u8; N];
                a.copy_from_slice(&b[..N]);
                <$t>::from_ne_bytes(a)
            }
        }
    )*};
}
native_int!(u8, i8, u16, i16, u32);

impl<T: NativeBytes + Copy + Default, const N: usize> NativeBytes for [T; N] {
    fn native(&self) -> Vec<u8> {
        self.iter().flat_map(|v| v.native()).collect()
    }
    fn from_native(b: &[u8]) -> Self {
        let size = b.len() / N;
        let mut out = [T::default(); N];
        for (k, slot) in out.iter_mut().enumerate() {
            *slot = T::from_native(&b[k * size..(k + 1) * size]);
        }
        out
    }
}

/// Runs a filter over `data` viewed as elements of type `E`.
fn in_place<E: NativeBytes + Copy + Default>(data: &mut [u8], filter: fn(&mut [E])) {
    let size = std::mem::size_of::<E>();
    let mut elements: Vec<E> = data.chunks_exact(size).map(E::from_native).collect();
    filter(&mut elements);
    for (chunk, e) in data.chunks_exact_mut(size).zip(&elements) {
        chunk.copy_from_slice(&e.native());
    }
}

/// One vertex of `K` 4-byte words, as the decoder fills it (arrays above
/// 32 elements have no `Default`).
#[derive(Clone, Copy)]
#[repr(transparent)]
struct Words<const K: usize>([u32; K]);

impl<const K: usize> Default for Words<K> {
    fn default() -> Self {
        Words([0; K])
    }
}

/// Decodes a vertex stream of `words` 4-byte words per element (1 to 64:
/// the extension's strides, 4 to 256 bytes).
fn vertices(encoded: &[u8], count: usize, words: usize) -> Result<Vec<u8>, String> {
    fn run<const K: usize>(encoded: &[u8], count: usize) -> Result<Vec<u8>, String> {
        let v = meshopt::decode_vertex_buffer::<Words<K>>(encoded, count)
            .map_err(|e| format!("cannot be decoded: {e}"))?;
        Ok(v.iter().flat_map(|w| w.0.native()).collect())
    }
    macro_rules! dispatch {
        ($($k:literal)*) => {
            match words {
                $($k => run::<$k>(encoded, count),)*
                _ => Err(format!(
                    "byteStride {} is outside the extension's 4 to 256 bytes",
                    4 * words
                )),
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30
        31 32 33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 49 50 51 52 53 54 55 56 57 58 59
        60 61 62 63 64)
}

/// The exponential filter over elements of `words` 4-byte words (each
/// word decoded on its own, so one word at a time is the same).
fn exponential(data: &mut [u8], _words: usize) {
    in_place(data, meshopt::decode_filter_exp::<1>);
}
