//! From bytes to a validated glTF document with its buffers loaded: GLB
//! framing or JSON, validation by `gltf-json` (collecting every problem
//! with its JSON path), required extensions, and buffers from the BIN
//! chunk, data URIs or files beside the glTF.

use std::path::{Path, PathBuf};

use gltf_json::validation::{Error as VError, Validate};
use gltf_json::Root;
use serde_json::Value;

use super::glb;
use super::meshopt_decode;
use super::uri::{self, UriKind};
use crate::ErrorKind;

/// Extensions whose data we cannot decode: the geometry is compressed.
/// (Meshopt compression is decoded, `meshopt_decode.rs`.)
const COMPRESSION: &[&str] = &["KHR_draco_mesh_compression"];

/// Extensions that only change meaning of data we keep as is (materials,
/// textures, node data): required or not, passing them through is right.
const PASSTHROUGH_SAFE_PREFIXES: &[&str] = &["KHR_materials_", "KHR_texture_", "EXT_texture_"];

/// Extensions the reader itself interprets.
pub(crate) const QUANTIZATION: &str = "KHR_mesh_quantization";

/// At most this many validation problems are listed in one error.
const MAX_LISTED: usize = 8;

/// A parsed, validated glTF document and its buffers.
pub(crate) struct Loaded {
    /// The JSON as found in the file.
    pub json: Value,
    /// Typed view of the JSON (after [`sanitize`]), indices validated.
    pub root: Root,
    /// Every buffer's bytes, `byteLength` long.
    pub buffers: Vec<Vec<u8>>,
    /// External files the document references (buffers), absolute.
    pub external: Vec<PathBuf>,
}

/// Reads the document, its buffers and the files they live in.
pub(crate) fn load(
    path: &Path,
    data: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Loaded, ErrorKind> {
    if data.is_empty() {
        return Err(ErrorKind::EmptyFile);
    }
    let is_glb = data.starts_with(glb::MAGIC);
    let is_glb_ext = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json_bytes, bin) = if is_glb || is_glb_ext {
        let g = glb::parse(data)?;
        warnings.extend(g.warnings);
        (g.json, g.bin)
    } else {
        (data, None)
    };
    // A UTF-8 byte order mark is forbidden by the specification but common.
    let json_bytes = json_bytes
        .strip_prefix(b"\xEF\xBB\xBF")
        .unwrap_or(json_bytes);
    let json: Value = serde_json::from_slice(json_bytes)
        .map_err(|e| ErrorKind::malformed("glTF JSON", format!("not valid JSON: {e}")))?;
    if !json.is_object() {
        return Err(ErrorKind::malformed(
            "glTF JSON",
            "the top level is not a JSON object",
        ));
    }
    let version = json
        .pointer("/asset/version")
        .and_then(Value::as_str)
        .ok_or_else(|| {
            ErrorKind::malformed(
                "glTF JSON",
                "no asset.version: this JSON is not a glTF 2.0 asset",
            )
        })?;
    if !version.starts_with("2.") {
        return Err(ErrorKind::Unsupported(format!(
            "glTF version {version}: only glTF 2.0 is supported"
        )));
    }
    check_extensions(&json, warnings)?;
    let root = typed(&json, "glTF", warnings)?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut buffers = Vec::with_capacity(root.buffers.len());
    let mut external = Vec::new();
    let compressed = meshopt_decode::compressed_bytes(&json);
    for (i, b) in root.buffers.iter().enumerate() {
        let name = format!("buffer {i}");
        let declared = b.byte_length.0;
        let fallback = json
            .pointer(&format!("/buffers/{i}"))
            .is_some_and(meshopt_decode::is_fallback);
        let bytes: Vec<u8> = match b.uri.as_deref() {
            // Filled by the compressed views below.
            None if fallback && !(i == 0 && bin.is_some()) => {
                let size = meshopt_decode::fallback_size(declared, compressed)
                    .map_err(|m| ErrorKind::malformed(name.clone(), m))?;
                vec![0; size]
            }
            None => match (i, bin) {
                (0, Some(bin)) => bin.to_vec(),
                (0, None) if is_glb => {
                    return Err(ErrorKind::malformed(
                        name,
                        "has no uri and the GLB has no BIN chunk",
                    ))
                }
                _ => {
                    return Err(ErrorKind::malformed(
                        name,
                        "has no uri (only buffer 0 of a GLB may omit it)",
                    ))
                }
            },
            Some(u) => match uri::classify(u) {
                UriKind::Data { base64: None, .. } => {
                    return Err(ErrorKind::malformed(
                        name,
                        "its data URI is not base64-encoded",
                    ))
                }
                UriKind::Data {
                    base64: Some(p), ..
                } => {
                    // The decoded size is bounded by the URI's, which is
                    // bounded by the file's.
                    uri::decode_base64(p).map_err(|m| ErrorKind::malformed(name.clone(), m))?
                }
                UriKind::Remote => {
                    return Err(ErrorKind::Unsupported(format!(
                        "{name}: remote URI {u:?} is not fetched; download it next to the glTF"
                    )))
                }
                UriKind::Relative(rel) => {
                    let file = uri::resolve(&dir, &rel);
                    let bytes = read_external(&file, declared).map_err(|e| {
                        ErrorKind::malformed(
                            name.clone(),
                            format!("cannot read {}: {e}", file.display()),
                        )
                    })?;
                    external.push(absolute(&file));
                    bytes
                }
            },
        };
        if (bytes.len() as u64) < declared {
            return Err(ErrorKind::malformed(
                format!("buffer {i}"),
                format!(
                    "declares byteLength {declared}, but its data holds only {} bytes",
                    bytes.len()
                ),
            ));
        }
        let mut bytes = bytes;
        bytes.truncate(declared as usize);
        buffers.push(bytes);
    }
    let (json, root) = if meshopt_decode::declared(&json) {
        let mut json = json;
        meshopt_decode::decode_views(&mut json, &mut buffers)?;
        let root = typed(&json, "glTF", &mut Vec::new())?;
        (json, root)
    } else {
        (json, root)
    };
    Ok(Loaded {
        json,
        root,
        buffers,
        external,
    })
}

/// Reads an external buffer, refusing a file larger than any mesh file we
/// accept before allocating for it.
fn read_external(file: &Path, declared: u64) -> Result<Vec<u8>, String> {
    crate::regular::not_regular(file).map_err(|e| e.to_string())?;
    let meta = std::fs::metadata(file).map_err(|e| e.to_string())?;
    if meta.len() > crate::MAX_FILE_BYTES {
        return Err(format!("{} bytes is more than wildlod reads", meta.len()));
    }
    if meta.len() < declared {
        return Err(format!(
            "the file has {} bytes, but the buffer declares byteLength {declared}",
            meta.len()
        ));
    }
    std::fs::read(file).map_err(|e| e.to_string())
}

/// The absolute form of a path, for comparing and protecting inputs.
pub(crate) fn absolute(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir()
            .map(|d| d.join(p))
            .unwrap_or_else(|_| p.to_path_buf())
    }
}

/// The typed, validated form of a glTF JSON document. `label` names the
/// document in errors ("glTF" for input, "written glTF" for output).
pub(crate) fn typed(
    json: &Value,
    label: &str,
    warnings: &mut Vec<String>,
) -> Result<Root, ErrorKind> {
    let root: Root = serde_json::from_value(sanitize(json, warnings)).map_err(|e| {
        ErrorKind::malformed(
            format!("{label} JSON"),
            format!("not a valid glTF 2.0 document: {e}"),
        )
    })?;
    validate(&root, label, warnings)?;
    Ok(root)
}

/// Required extensions: compression is refused with a clear message;
/// anything else unknown is kept as is, with a warning when required.
fn check_extensions(json: &Value, warnings: &mut Vec<String>) -> Result<(), ErrorKind> {
    let names = |key: &str| -> Vec<String> {
        json.get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default()
    };
    let required = names("extensionsRequired");
    for ext in &required {
        if COMPRESSION.contains(&ext.as_str()) {
            return Err(ErrorKind::Unsupported(format!(
                "the file requires {ext}: its meshes are compressed, which wildlod cannot \
                 decode; decompress it first (for example `gltf-transform copy` or \
                 `gltfpack -noq`)"
            )));
        }
    }
    for ext in &required {
        let known = meshopt_decode::MESHOPT.contains(&ext.as_str())
            || ext == QUANTIZATION
            || PASSTHROUGH_SAFE_PREFIXES.iter().any(|p| ext.starts_with(p));
        if !known {
            warnings.push(format!(
                "the file requires extension {ext}, which wildlod does not interpret; it is \
                 written back unchanged"
            ));
        }
    }
    Ok(())
}

/// A copy of the JSON that `gltf-json` accepts without giving up on data we
/// handle ourselves: required extensions (checked above), non-standard
/// attribute names (read as custom attributes), and textures whose image
/// is only named by an extension.
fn sanitize(json: &Value, warnings: &mut Vec<String>) -> Value {
    let mut j = json.clone();
    if let Some(o) = j.as_object_mut() {
        o.remove("extensionsRequired");
    }
    if let Some(meshes) = j.get_mut("meshes").and_then(Value::as_array_mut) {
        for (mi, mesh) in meshes.iter_mut().enumerate() {
            let Some(prims) = mesh.get_mut("primitives").and_then(Value::as_array_mut) else {
                continue;
            };
            for (pi, prim) in prims.iter_mut().enumerate() {
                if let Some(attrs) = prim.get_mut("attributes").and_then(Value::as_object_mut) {
                    let odd: Vec<String> = attrs
                        .keys()
                        .filter(|k| !is_standard_semantic(k))
                        .cloned()
                        .collect();
                    for k in odd {
                        warnings.push(format!(
                            "mesh {mi} primitive {pi}: attribute {k:?} is not a glTF semantic; \
                             kept as custom attribute _{k}"
                        ));
                        if let Some(v) = attrs.remove(&k) {
                            attrs.insert(format!("_{k}"), v);
                        }
                    }
                }
            }
        }
    }
    if let Some(textures) = j.get_mut("textures").and_then(Value::as_array_mut) {
        for t in textures.iter_mut() {
            if t.get("source").is_some() {
                continue;
            }
            let from_ext = t
                .get("extensions")
                .and_then(Value::as_object)
                .and_then(|e| e.values().find_map(|x| x.get("source").cloned()));
            if let (Some(s), Some(o)) = (from_ext, t.as_object_mut()) {
                o.insert("source".into(), s);
            }
        }
    }
    j
}

/// Whether a primitive attribute name is one glTF defines, or an
/// application-specific `_NAME`.
pub(crate) fn is_standard_semantic(k: &str) -> bool {
    let numbered = |prefix: &str| {
        k.strip_prefix(prefix)
            .is_some_and(|n| !n.is_empty() && n.parse::<u32>().is_ok())
    };
    matches!(k, "POSITION" | "NORMAL" | "TANGENT")
        || k.starts_with('_')
        || numbered("TEXCOORD_")
        || numbered("COLOR_")
        || numbered("JOINTS_")
        || numbered("WEIGHTS_")
}

/// Runs `gltf-json` validation, collecting every problem with its JSON
/// path. Missing POSITION bounds (required, but only a hint to renderers)
/// are a warning; the writer recomputes them.
fn validate(root: &Root, label: &str, warnings: &mut Vec<String>) -> Result<(), ErrorKind> {
    // gltf-json's primitive check indexes `accessors` with the POSITION
    // index before checking it: check it here so that it cannot panic.
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            for (sem, idx) in &prim.attributes {
                if idx.value() >= root.accessors.len() {
                    return Err(ErrorKind::malformed(
                        format!("mesh {mi} primitive {pi}"),
                        format!(
                            "attribute {} refers to accessor {}, but there are {} accessors",
                            semantic_name(sem),
                            idx.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    let mut problems: Vec<String> = Vec::new();
    root.validate(root, gltf_json::Path::new, &mut |path, err| {
        let p = path().to_string();
        let bounds = p.ends_with("[\"POSITION\"].min") || p.ends_with("[\"POSITION\"].max");
        if bounds && err == VError::Missing {
            warnings.push(format!("{p}: missing (POSITION bounds are required)"));
            return;
        }
        // glTF 2.0 §3.6.2.3: an accessor without a buffer view holds zeros
        // (possibly overridden by sparse values); gltf-json calls it missing.
        if err == VError::Missing && p.starts_with("accessors[") && p.ends_with("].bufferView") {
            return;
        }
        problems.push(format!("{p}: {}", describe(err)));
    });
    if problems.is_empty() {
        return Ok(());
    }
    let total = problems.len();
    problems.truncate(MAX_LISTED);
    let mut msg = problems.join("; ");
    if total > MAX_LISTED {
        msg.push_str(&format!("; and {} more", total - MAX_LISTED));
    }
    Err(ErrorKind::malformed(format!("{label} validation"), msg))
}

fn semantic_name(s: &gltf_json::validation::Checked<gltf_json::mesh::Semantic>) -> String {
    match s {
        gltf_json::validation::Checked::Valid(s) => s.to_string(),
        gltf_json::validation::Checked::Invalid => "(invalid)".into(),
    }
}

fn describe(e: VError) -> &'static str {
    match e {
        VError::IndexOutOfBounds => "index out of range",
        VError::Invalid => "invalid value",
        VError::Missing => "missing",
        VError::Oversize => "size exceeds this system's limits",
        VError::Unsupported => "unsupported extension",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_semantics_are_recognized() {
        for k in ["POSITION", "TEXCOORD_1", "COLOR_0", "JOINTS_2", "_BATCHID"] {
            assert!(is_standard_semantic(k), "{k}");
        }
        for k in ["TEXCOORD", "TEXCOORD_x", "BATCHID", "color_0"] {
            assert!(!is_standard_semantic(k), "{k}");
        }
    }

    #[test]
    fn odd_attribute_names_become_custom_in_the_typed_copy() {
        let j: Value = serde_json::json!({
            "asset": {"version": "2.0"},
            "extensionsRequired": ["KHR_mesh_quantization"],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "BATCHID": 1}}]}]
        });
        let mut w = Vec::new();
        let s = sanitize(&j, &mut w);
        assert!(s.get("extensionsRequired").is_none());
        assert_eq!(
            s.pointer("/meshes/0/primitives/0/attributes/_BATCHID"),
            Some(&Value::from(1))
        );
        assert_eq!(w.len(), 1);
        // The original is untouched.
        assert!(j
            .pointer("/meshes/0/primitives/0/attributes/BATCHID")
            .is_some());
    }
}
