//! Accessors: decoding with every offset, stride and count checked against
//! the bytes that exist (no trust in the JSON), and encoding back.
//!
//! Quantized data (normalized or plain integers, KHR_mesh_quantization) is
//! turned into `f32` here, with the glTF normalization rules, and the
//! source encoding is reported as a [`ComponentFormat`] so that writers can
//! encode it back the same way.

use gltf_json::accessor::{ComponentType, Type};
use gltf_json::validation::Checked;
use gltf_json::Root;
use wildlod_mesh::ComponentFormat;

use crate::ErrorKind;

/// A glTF component type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Component {
    I8,
    U8,
    I16,
    U16,
    U32,
    F32,
}

impl Component {
    fn from_json(c: ComponentType) -> Self {
        match c {
            ComponentType::I8 => Component::I8,
            ComponentType::U8 => Component::U8,
            ComponentType::I16 => Component::I16,
            ComponentType::U16 => Component::U16,
            ComponentType::U32 => Component::U32,
            ComponentType::F32 => Component::F32,
        }
    }

    /// The GL enum written as `componentType`.
    pub(crate) fn gl(self) -> u32 {
        match self {
            Component::I8 => 5120,
            Component::U8 => 5121,
            Component::I16 => 5122,
            Component::U16 => 5123,
            Component::U32 => 5125,
            Component::F32 => 5126,
        }
    }

    /// Bytes per component.
    pub(crate) fn size(self) -> usize {
        match self {
            Component::I8 | Component::U8 => 1,
            Component::I16 | Component::U16 => 2,
            Component::U32 | Component::F32 => 4,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Component::I8 => "byte",
            Component::U8 => "unsigned byte",
            Component::I16 => "short",
            Component::U16 => "unsigned short",
            Component::U32 => "unsigned int",
            Component::F32 => "float",
        }
    }

    /// Reads one little-endian component as an integer (`None` for floats).
    fn int(self, b: &[u8]) -> Option<i64> {
        Some(match self {
            Component::I8 => i8::from_le_bytes([*b.first()?]) as i64,
            Component::U8 => *b.first()? as i64,
            Component::I16 => i16::from_le_bytes([*b.first()?, *b.get(1)?]) as i64,
            Component::U16 => u16::from_le_bytes([*b.first()?, *b.get(1)?]) as i64,
            Component::U32 => {
                u32::from_le_bytes([*b.first()?, *b.get(1)?, *b.get(2)?, *b.get(3)?]) as i64
            }
            Component::F32 => return None,
        })
    }

    /// Reads one component as `f32`, normalized by the glTF rules when asked.
    fn float(self, b: &[u8], normalized: bool) -> Option<f32> {
        if self == Component::F32 {
            return Some(f32::from_le_bytes([
                *b.first()?,
                *b.get(1)?,
                *b.get(2)?,
                *b.get(3)?,
            ]));
        }
        let v = self.int(b)?;
        if !normalized {
            return Some(v as f32);
        }
        // glTF 2.0 §3.11: signed values clamp at -1 so that both -127 and
        // -128 map to -1.
        Some(match self {
            Component::I8 => (v as f32 / 127.0).max(-1.0),
            Component::U8 => v as f32 / 255.0,
            Component::I16 => (v as f32 / 32767.0).max(-1.0),
            Component::U16 => v as f32 / 65535.0,
            _ => (v as f64 / u32::MAX as f64) as f32,
        })
    }
}

/// The format a component type and `normalized` flag decode from.
pub(crate) fn format_of(c: Component, normalized: bool) -> ComponentFormat {
    match (c, normalized) {
        (Component::F32, _) => ComponentFormat::F32,
        (Component::U8, true) => ComponentFormat::U8Norm,
        (Component::U16, true) => ComponentFormat::U16Norm,
        (Component::I8, true) => ComponentFormat::I8Norm,
        (Component::I16, true) => ComponentFormat::I16Norm,
        (Component::U8, false) => ComponentFormat::U8,
        (Component::U16, false) => ComponentFormat::U16,
        (Component::I8, false) => ComponentFormat::I8,
        (Component::I16, false) => ComponentFormat::I16,
        (Component::U32, _) => ComponentFormat::U32,
    }
}

/// The component type and `normalized` flag that encode a format.
pub(crate) fn component_of(f: ComponentFormat) -> (Component, bool) {
    match f {
        ComponentFormat::F32 => (Component::F32, false),
        ComponentFormat::U8Norm => (Component::U8, true),
        ComponentFormat::U16Norm => (Component::U16, true),
        ComponentFormat::I8Norm => (Component::I8, true),
        ComponentFormat::I16Norm => (Component::I16, true),
        ComponentFormat::U8 => (Component::U8, false),
        ComponentFormat::U16 => (Component::U16, false),
        ComponentFormat::I8 => (Component::I8, false),
        ComponentFormat::I16 => (Component::I16, false),
        ComponentFormat::U32 => (Component::U32, false),
    }
}

/// Components per element, and the layout of matrix columns.
fn shape(t: Type) -> (usize, usize) {
    // (columns, rows)
    match t {
        Type::Scalar => (1, 1),
        Type::Vec2 => (1, 2),
        Type::Vec3 => (1, 3),
        Type::Vec4 => (1, 4),
        Type::Mat2 => (2, 2),
        Type::Mat3 => (3, 3),
        Type::Mat4 => (4, 4),
    }
}

/// Bytes of one element of an accessor given by its JSON `componentType`
/// and `type`, or `None` when either is not a glTF value.
pub(crate) fn element_size(component_type: u64, type_name: &str) -> Option<usize> {
    let component = match component_type {
        5120 => Component::I8,
        5121 => Component::U8,
        5122 => Component::I16,
        5123 => Component::U16,
        5125 => Component::U32,
        5126 => Component::F32,
        _ => return None,
    };
    let t = match type_name {
        "SCALAR" => Type::Scalar,
        "VEC2" => Type::Vec2,
        "VEC3" => Type::Vec3,
        "VEC4" => Type::Vec4,
        "MAT2" => Type::Mat2,
        "MAT3" => Type::Mat3,
        "MAT4" => Type::Mat4,
        _ => return None,
    };
    Some(Layout::new(component, t).size)
}

/// The JSON name of an accessor type with `n` components (vectors only).
pub(crate) fn type_name(n: usize) -> &'static str {
    match n {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        _ => "VEC4",
    }
}

/// Byte layout of one element.
#[derive(Clone, Copy)]
struct Layout {
    component: Component,
    columns: usize,
    rows: usize,
    /// Bytes from one column to the next: matrix columns start on 4-byte
    /// boundaries (glTF 2.0 §3.6.2.4), vectors are packed.
    column_stride: usize,
    size: usize,
}

impl Layout {
    fn new(component: Component, t: Type) -> Self {
        let (columns, rows) = shape(t);
        let packed = rows * component.size();
        let column_stride = if columns > 1 {
            packed.div_ceil(4) * 4
        } else {
            packed
        };
        Layout {
            component,
            columns,
            rows,
            column_stride,
            size: column_stride * (columns - 1) + packed,
        }
    }

    fn components(&self) -> usize {
        self.columns * self.rows
    }

    /// Byte offsets of the components of an element, relative to its start.
    fn offsets(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.columns).flat_map(move |c| {
            (0..self.rows).map(move |r| c * self.column_stride + r * self.component.size())
        })
    }
}

/// Decoded accessor data.
pub(crate) struct Decoded<T> {
    /// Components per element.
    pub components: usize,
    /// Flat values, `components` per element.
    pub values: Vec<T>,
    /// The source encoding.
    pub format: ComponentFormat,
}

impl<T> Decoded<T> {
    /// Number of elements.
    pub(crate) fn count(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }
}

/// The document and its loaded buffers, for decoding accessors.
pub(crate) struct Data<'a> {
    pub root: &'a Root,
    pub buffers: &'a [Vec<u8>],
    /// Most values (elements × components) accepted for an accessor
    /// without a buffer view (sparse-only or all zeros), whose count no
    /// bytes back.
    pub max_unbacked: u64,
}

fn accessor_name(i: usize) -> String {
    format!("accessor {i}")
}

impl Data<'_> {
    /// Decodes accessor `index` into `f32` values.
    pub(crate) fn floats(&self, index: usize) -> Result<Decoded<f32>, ErrorKind> {
        self.decode(index, |c, b, n| c.float(b, n))
    }

    /// Decodes accessor `index`, which must hold unsigned integers (indices,
    /// joints).
    pub(crate) fn uints(&self, index: usize) -> Result<Decoded<u32>, ErrorKind> {
        let (c, _, _) = self.kind(index)?;
        if !matches!(c, Component::U8 | Component::U16 | Component::U32) {
            return Err(ErrorKind::malformed(
                accessor_name(index),
                format!(
                    "component type {} cannot hold indices (unsigned integers needed)",
                    c.name()
                ),
            ));
        }
        self.decode(index, |c, b, _| c.int(b).map(|v| v as u32))
    }

    /// Checks that accessor `index` lies inside its buffer views, without
    /// keeping its values (a vector of `()` allocates nothing).
    pub(crate) fn check(&self, index: usize) -> Result<(), ErrorKind> {
        self.decode(index, |_, _, _| Some(())).map(|_| ())
    }

    /// Component type, accessor type and `normalized` flag of an accessor.
    fn kind(&self, index: usize) -> Result<(Component, Type, bool), ErrorKind> {
        let acc = self
            .root
            .accessors
            .get(index)
            .ok_or_else(|| ErrorKind::malformed(accessor_name(index), "does not exist"))?;
        let Checked::Valid(ct) = acc.component_type else {
            return Err(ErrorKind::malformed(
                accessor_name(index),
                "invalid componentType",
            ));
        };
        let Checked::Valid(t) = acc.type_ else {
            return Err(ErrorKind::malformed(accessor_name(index), "invalid type"));
        };
        Ok((Component::from_json(ct.0), t, acc.normalized))
    }

    /// The bytes of buffer view `view`, checked against its buffer.
    pub(crate) fn view(&self, view: usize) -> Result<&[u8], ErrorKind> {
        self.view_bytes(view).map(|(b, _)| b)
    }

    /// The bytes and byte stride of buffer view `view`.
    fn view_bytes(&self, view: usize) -> Result<(&[u8], Option<usize>), ErrorKind> {
        let name = || format!("bufferView {view}");
        let v = self
            .root
            .buffer_views
            .get(view)
            .ok_or_else(|| ErrorKind::malformed(name(), "does not exist"))?;
        let b = v.buffer.value();
        let buf = self.buffers.get(b).ok_or_else(|| {
            ErrorKind::malformed(
                name(),
                format!("refers to buffer {b}, which does not exist"),
            )
        })?;
        let start = v.byte_offset.map(|o| o.0).unwrap_or(0);
        let len = v.byte_length.0;
        let end = start.checked_add(len);
        match end.filter(|&e| e <= buf.len() as u64) {
            Some(end) => Ok((
                &buf[start as usize..end as usize],
                v.byte_stride.map(|s| s.0),
            )),
            None => Err(ErrorKind::malformed(
                name(),
                format!(
                    "bytes {start}..{} lie beyond the end of buffer {b} ({} bytes)",
                    start as u128 + len as u128,
                    buf.len()
                ),
            )),
        }
    }

    fn decode<T: Copy + Default>(
        &self,
        index: usize,
        read: impl Fn(Component, &[u8], bool) -> Option<T>,
    ) -> Result<Decoded<T>, ErrorKind> {
        let name = || accessor_name(index);
        let (component, t, normalized) = self.kind(index)?;
        let acc = &self.root.accessors[index];
        let layout = Layout::new(component, t);
        let n = layout.components();
        let count = acc.count.0;
        let corrupt = || ErrorKind::malformed(name(), "element outside its buffer view");
        let mut values: Vec<T>;
        if let Some(view) = acc.buffer_view {
            let (bytes, stride) = self.view_bytes(view.value())?;
            let stride = stride.unwrap_or(layout.size);
            if stride < layout.size {
                return Err(ErrorKind::malformed(
                    format!("bufferView {}", view.value()),
                    format!(
                        "byteStride {stride} is smaller than the {}-byte elements of accessor {index}",
                        layout.size
                    ),
                ));
            }
            let offset = acc.byte_offset.map(|o| o.0).unwrap_or(0);
            // Elements that fit: the first at `offset`, one every `stride`.
            let room = (bytes.len() as u64).checked_sub(offset);
            let fits = match room {
                Some(r) if r >= layout.size as u64 => (r - layout.size as u64) / stride as u64 + 1,
                _ => 0,
            };
            if count > fits {
                return Err(ErrorKind::ImplausibleCount {
                    element: format!(
                        "{} (bufferView {}, {} bytes, byteOffset {offset})",
                        name(),
                        view.value(),
                        bytes.len()
                    ),
                    count,
                    max: fits,
                });
            }
            values = Vec::with_capacity(count as usize * n);
            let offsets: Vec<usize> = layout.offsets().collect();
            let size = component.size();
            for i in 0..count as usize {
                let base = offset as usize + i * stride;
                for &o in &offsets {
                    let at = base + o;
                    let b = bytes.get(at..at + size).ok_or_else(corrupt)?;
                    values.push(read(component, b, normalized).ok_or_else(corrupt)?);
                }
            }
        } else {
            if count.saturating_mul(n as u64) > self.max_unbacked {
                return Err(ErrorKind::ImplausibleCount {
                    element: format!("{} (no bufferView)", name()),
                    count,
                    max: self.max_unbacked / n as u64,
                });
            }
            values = vec![T::default(); count as usize * n];
        }
        if let Some(sparse) = &acc.sparse {
            self.apply_sparse(index, sparse, layout, normalized, &mut values, &read)?;
        }
        Ok(Decoded {
            components: n,
            values,
            format: format_of(component, normalized),
        })
    }

    fn apply_sparse<T: Copy>(
        &self,
        index: usize,
        sparse: &gltf_json::accessor::sparse::Sparse,
        layout: Layout,
        normalized: bool,
        values: &mut [T],
        read: &impl Fn(Component, &[u8], bool) -> Option<T>,
    ) -> Result<(), ErrorKind> {
        let name = || format!("accessor {index} sparse");
        let n = layout.components();
        let count = values.len() / n.max(1);
        let k = sparse.count.0;
        if k > count as u64 {
            return Err(ErrorKind::ImplausibleCount {
                element: name(),
                count: k,
                max: count as u64,
            });
        }
        let k = k as usize;
        let Checked::Valid(ict) = sparse.indices.component_type else {
            return Err(ErrorKind::malformed(
                name(),
                "invalid indices componentType",
            ));
        };
        let ic = Component::from_json(ict.0);
        let (ibytes, _) = self.view_bytes(sparse.indices.buffer_view.value())?;
        let (vbytes, _) = self.view_bytes(sparse.values.buffer_view.value())?;
        let ioff = sparse.indices.byte_offset.0 as usize;
        let voff = sparse.values.byte_offset.0 as usize;
        let short = |what: &str, have: usize, need: u128| {
            ErrorKind::malformed(
                name(),
                format!("{k} {what} need {need} bytes, but their buffer view holds {have}"),
            )
        };
        let ineed = ioff as u128 + k as u128 * ic.size() as u128;
        if ineed > ibytes.len() as u128 {
            return Err(short("indices", ibytes.len(), ineed));
        }
        let vneed = voff as u128 + k as u128 * layout.size as u128;
        if vneed > vbytes.len() as u128 {
            return Err(short("values", vbytes.len(), vneed));
        }
        let offsets: Vec<usize> = layout.offsets().collect();
        let size = layout.component.size();
        let corrupt = || ErrorKind::malformed(name(), "element outside its buffer view");
        for s in 0..k {
            let at = ioff + s * ic.size();
            let target = ibytes
                .get(at..at + ic.size())
                .and_then(|b| ic.int(b))
                .ok_or_else(corrupt)?;
            if target < 0 || target as u64 >= count as u64 {
                return Err(ErrorKind::malformed(
                    name(),
                    format!("index {s} is {target}, beyond the accessor's {count} elements"),
                ));
            }
            let base = voff + s * layout.size;
            for (j, &o) in offsets.iter().enumerate() {
                let b = vbytes.get(base + o..base + o + size).ok_or_else(corrupt)?;
                let v = read(layout.component, b, normalized).ok_or_else(corrupt)?;
                values[target as usize * n + j] = v;
            }
        }
        Ok(())
    }
}

/// Whether `v` can be stored in `format` (normalized formats round; plain
/// integer formats must hold the value exactly).
pub(crate) fn representable(v: f32, format: ComponentFormat) -> bool {
    if !v.is_finite() {
        return false;
    }
    let int = |lo: f32, hi: f32| v.fract() == 0.0 && (lo..=hi).contains(&v);
    match format {
        ComponentFormat::F32 => true,
        ComponentFormat::U8Norm | ComponentFormat::U16Norm => (0.0..=1.0).contains(&v),
        ComponentFormat::I8Norm | ComponentFormat::I16Norm => (-1.0..=1.0).contains(&v),
        ComponentFormat::U8 => int(0.0, 255.0),
        ComponentFormat::U16 => int(0.0, 65535.0),
        ComponentFormat::I8 => int(-128.0, 127.0),
        ComponentFormat::I16 => int(-32768.0, 32767.0),
        // Beyond 2^24 an f32 no longer holds every integer: stay exact.
        ComponentFormat::U32 => int(0.0, 16_777_216.0),
    }
}

/// The raw component value `v` encodes to (the integer for integer
/// formats, the float itself for `F32`). Assumes [`representable`].
pub(crate) fn raw(v: f32, format: ComponentFormat) -> f64 {
    let q = |scale: f32, lo: f32, hi: f32| (v * scale).round().clamp(lo, hi) as f64;
    match format {
        ComponentFormat::F32 => v as f64,
        ComponentFormat::U8Norm => q(255.0, 0.0, 255.0),
        ComponentFormat::U16Norm => q(65535.0, 0.0, 65535.0),
        ComponentFormat::I8Norm => q(127.0, -127.0, 127.0),
        ComponentFormat::I16Norm => q(32767.0, -32767.0, 32767.0),
        _ => v as f64,
    }
}

/// Appends the little-endian bytes of raw value `r` as component `c`.
pub(crate) fn push_raw(out: &mut Vec<u8>, r: f64, c: Component) {
    match c {
        Component::F32 => out.extend_from_slice(&(r as f32).to_le_bytes()),
        Component::I8 => out.extend_from_slice(&(r as i8).to_le_bytes()),
        Component::U8 => out.push(r as u8),
        Component::I16 => out.extend_from_slice(&(r as i16).to_le_bytes()),
        Component::U16 => out.extend_from_slice(&(r as u16).to_le_bytes()),
        Component::U32 => out.extend_from_slice(&(r as u32).to_le_bytes()),
    }
}

/// Vertex attribute elements start on 4-byte boundaries (glTF 2.0
/// §3.6.2.4): the stride of `n` components of `c`.
pub(crate) fn vertex_stride(c: Component, n: usize) -> usize {
    (c.size() * n).div_ceil(4) * 4
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_components_follow_the_gltf_rules() {
        assert_eq!(Component::U8.float(&[255], true), Some(1.0));
        assert_eq!(Component::I8.float(&[0x80], true), Some(-1.0));
        assert_eq!(Component::I8.float(&[0x81], true), Some(-1.0));
        assert_eq!(Component::U16.float(&[0xFF, 0xFF], true), Some(1.0));
        assert_eq!(Component::I16.float(&[0x01, 0x80], false), Some(-32767.0));
        assert_eq!(Component::U8.float(&[7], false), Some(7.0));
    }

    #[test]
    fn every_normalized_value_encodes_back_to_its_integer() {
        for c in 0..=255u8 {
            let v = Component::U8.float(&[c], true).unwrap();
            assert_eq!(raw(v, ComponentFormat::U8Norm), c as f64);
        }
        for c in [0u16, 1, 2, 1000, 32767, 65534, 65535] {
            let v = Component::U16.float(&c.to_le_bytes(), true).unwrap();
            assert_eq!(raw(v, ComponentFormat::U16Norm), c as f64);
        }
        for c in -127i16..=127 {
            let v = Component::I8.float(&(c as i8).to_le_bytes(), true).unwrap();
            assert_eq!(raw(v, ComponentFormat::I8Norm), c as f64);
        }
        for c in [-32767i16, -1, 0, 1, 12345, 32767] {
            let v = Component::I16.float(&c.to_le_bytes(), true).unwrap();
            assert_eq!(raw(v, ComponentFormat::I16Norm), c as f64);
        }
    }

    #[test]
    fn representable_rejects_out_of_range_and_fractions() {
        assert!(representable(0.5, ComponentFormat::U8Norm));
        assert!(!representable(1.5, ComponentFormat::U8Norm));
        assert!(!representable(-0.1, ComponentFormat::U16Norm));
        assert!(representable(-1.0, ComponentFormat::I16Norm));
        assert!(!representable(2.5, ComponentFormat::U16));
        assert!(!representable(256.0, ComponentFormat::U8));
        assert!(!representable(f32::NAN, ComponentFormat::F32));
    }

    #[test]
    fn matrix_columns_of_small_components_are_padded() {
        let l = Layout::new(Component::U8, Type::Mat3);
        assert_eq!(l.column_stride, 4);
        assert_eq!(l.size, 11);
        assert_eq!(
            l.offsets().collect::<Vec<_>>(),
            vec![0, 1, 2, 4, 5, 6, 8, 9, 10]
        );
        assert_eq!(Layout::new(Component::F32, Type::Mat4).size, 64);
        assert_eq!(vertex_stride(Component::I16, 3), 8);
        assert_eq!(vertex_stride(Component::U8, 4), 4);
    }
}
