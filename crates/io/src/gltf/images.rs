//! Where a written glTF's images go: into the BIN chunk for `.glb`; for
//! `.gltf`, kept where they are when the output sits beside the source,
//! else copied next to the output under the same relative path.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::{json, Map, Value};

use super::bin::Bin;
use super::load::absolute;
use super::uri::{self, UriKind};
use crate::{ErrorKind, Format};

/// Places images for one write and collects the files to copy.
pub(crate) struct ImageWriter {
    format: Format,
    out_dir: PathBuf,
    source_dir: Option<PathBuf>,
    /// Image files to write beside the output.
    pub sidecars: Vec<(PathBuf, Vec<u8>)>,
    /// Output path of every copied image → the file it was copied from.
    copied: HashMap<PathBuf, PathBuf>,
    /// Problems that do not stop the write.
    pub warnings: Vec<String>,
    /// Output paths of images written from memory.
    written: std::collections::HashSet<PathBuf>,
    /// Views already holding an image, by a hash of its bytes: an image
    /// two materials (or two image objects) share is stored once.
    image_views: HashMap<u64, Vec<usize>>,
}

impl ImageWriter {
    /// A writer for output `path` of `format`; `source_dir` is where
    /// relative paths of the source document resolve.
    pub(crate) fn new(path: &Path, format: Format, source_dir: Option<&Path>) -> Self {
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        ImageWriter {
            format,
            out_dir: absolute(dir.unwrap_or(Path::new("."))),
            source_dir: source_dir.map(absolute),
            sidecars: Vec::new(),
            copied: HashMap::new(),
            warnings: Vec::new(),
            written: std::collections::HashSet::new(),
            image_views: HashMap::new(),
        }
    }

    /// A view holding `bytes`: an earlier image view with the same bytes,
    /// or a new one.
    fn image_view(&mut self, bin: &mut Bin, bytes: &[u8]) -> usize {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        bytes.hash(&mut h);
        let key = h.finish();
        let same = |v: usize| {
            let o = &bin.views[v];
            let at = o.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
            let len = o.get("byteLength").and_then(Value::as_u64).unwrap_or(0) as usize;
            bin.data.get(at..at + len) == Some(bytes)
        };
        if let Some(&v) = self
            .image_views
            .get(&key)
            .and_then(|vs| vs.iter().find(|&&v| same(v)))
        {
            return v;
        }
        let v = bin.view(bytes, None, None);
        self.image_views.entry(key).or_default().push(v);
        v
    }

    /// The location properties (`uri`, or `bufferView` and `mimeType`) of
    /// an image held in memory.
    pub(crate) fn embedded(
        &mut self,
        bin: &mut Bin,
        bytes: &[u8],
        mime: &str,
    ) -> Map<String, Value> {
        let mut m = Map::new();
        let v = self.image_view(bin, bytes);
        m.insert("bufferView".into(), json!(v));
        m.insert("mimeType".into(), json!(mime));
        m
    }

    /// The location properties of an image held in memory under a name (a
    /// re-baked texture): in a `.glb` embedded; beside a `.gltf` as the file
    /// `<name>.<ext>` (`<name>_2.<ext>`… when taken), so that artists see
    /// the images as files.
    pub(crate) fn named(
        &mut self,
        bin: &mut Bin,
        name: &str,
        bytes: &[u8],
        mime: &str,
    ) -> Map<String, Value> {
        let ext = match mime {
            "image/png" => "png",
            "image/jpeg" => "jpg",
            _ => "",
        };
        let safe: String = name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if self.format == Format::Glb || ext.is_empty() || safe.trim_matches('.').is_empty() {
            return self.embedded(bin, bytes, mime);
        }
        let mut k = 1;
        let file = loop {
            let f = if k == 1 {
                format!("{safe}.{ext}")
            } else {
                format!("{safe}_{k}.{ext}")
            };
            let target = self.out_dir.join(&f);
            if !self.written.contains(&target) && !self.copied.contains_key(&target) {
                break f;
            }
            k += 1;
        };
        let target = self.out_dir.join(&file);
        self.written.insert(target.clone());
        self.sidecars.push((target, bytes.to_vec()));
        let mut m = Map::new();
        m.insert(
            "uri".into(),
            json!(uri::percent_encode_path(Path::new(&file))),
        );
        m
    }

    /// The location properties of an image file. `source_uri` is the URI
    /// the source glTF used for it, kept whenever it still resolves.
    pub(crate) fn file(
        &mut self,
        bin: &mut Bin,
        label: &str,
        path: &Path,
        source_uri: Option<&str>,
        mime: Option<&str>,
    ) -> Result<Map<String, Value>, ErrorKind> {
        if self.format == Format::Glb {
            match crate::regular::read(path, crate::MAX_FILE_BYTES) {
                Ok(bytes) => {
                    let mime = mime
                        .map(str::to_string)
                        .or_else(|| uri::sniff_image_mime(&bytes).map(str::to_string))
                        .or_else(|| uri::mime_from_extension(path).map(str::to_string));
                    if let Some(mime) = mime {
                        return Ok(self.embedded(bin, &bytes, &mime));
                    }
                    self.warnings.push(format!(
                        "{label}: {} is not a PNG, JPEG, WebP or KTX2 image; referenced by URI instead of embedded",
                        path.display()
                    ));
                }
                Err(e) => self.warnings.push(format!(
                    "{label}: cannot read {} ({e}); referenced by URI instead of embedded",
                    path.display()
                )),
            }
        }
        let uri = self.place(label, path, source_uri)?;
        let mut m = Map::new();
        m.insert("uri".into(), json!(uri));
        Ok(m)
    }

    /// The URI of an image file seen from the output, copying the file
    /// next to the output when it is not reachable already.
    fn place(
        &mut self,
        label: &str,
        path: &Path,
        source_uri: Option<&str>,
    ) -> Result<String, ErrorKind> {
        let same_dir = self.source_dir.as_deref() == Some(self.out_dir.as_path());
        let from_uri = source_uri.and_then(|u| match uri::classify(u) {
            UriKind::Relative(r) => uri::contained_relative(&r),
            _ => None,
        });
        if same_dir {
            if let Some(u) = source_uri {
                return Ok(u.to_string());
            }
        }
        let abs = absolute(path);
        if abs.parent() == Some(self.out_dir.as_path()) {
            if let Some(name) = abs.file_name() {
                return Ok(uri::percent_encode_path(Path::new(name)));
            }
        }
        let rel = from_uri.or_else(|| {
            let d = self.source_dir.as_deref()?;
            let r = abs.strip_prefix(d).ok()?;
            uri::contained_relative(&r.to_string_lossy())
        });
        if same_dir {
            if let Some(r) = &rel {
                return Ok(uri::percent_encode_path(r));
            }
        }
        let name = abs
            .file_name()
            .map(PathBuf::from)
            .unwrap_or_else(|| PathBuf::from("image"));
        // OutputFiles cannot create directories: keep the relative path
        // only when its directory exists beside the output.
        let rel = rel
            .filter(|r| self.out_dir.join(r).parent().is_some_and(Path::is_dir))
            .unwrap_or(name);
        let rel = self.free_name(rel, &abs);
        let target = self.out_dir.join(&rel);
        if !self.copied.contains_key(&target) {
            match crate::regular::read(&abs, crate::MAX_FILE_BYTES) {
                Ok(bytes) => self.sidecars.push((target.clone(), bytes)),
                Err(e) => self.warnings.push(format!(
                    "{label}: cannot read {} ({e}); its URI is written but the file is not copied",
                    abs.display()
                )),
            }
            self.copied.insert(target, abs);
        }
        Ok(uri::percent_encode_path(&rel))
    }

    /// `rel`, or `stem_2.ext`, `stem_3.ext`… when another image already
    /// took that output path.
    fn free_name(&self, rel: PathBuf, source: &Path) -> PathBuf {
        let taken = |r: &Path| {
            self.copied
                .get(&self.out_dir.join(r))
                .is_some_and(|s| s != source)
        };
        if !taken(&rel) {
            return rel;
        }
        let stem = rel
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let ext = rel
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        let mut k = 2;
        loop {
            let cand = rel.with_file_name(format!("{stem}_{k}{ext}"));
            if !taken(&cand) {
                return cand;
            }
            k += 1;
        }
    }

    /// A source glTF image object, placed for the output: bufferView
    /// images are copied into the new buffer, data URIs and files are
    /// embedded in a GLB, files are kept or copied for a `.gltf`.
    pub(crate) fn passthrough(
        &mut self,
        bin: &mut Bin,
        index: usize,
        image: &Value,
        view_bytes: &dyn Fn(usize) -> Option<Vec<u8>>,
    ) -> Result<Value, ErrorKind> {
        let label = format!("image {index}");
        let mut out = image.as_object().cloned().unwrap_or_default();
        let mime = out
            .get("mimeType")
            .and_then(Value::as_str)
            .map(str::to_string);
        if let Some(v) = out.get("bufferView").and_then(Value::as_u64) {
            let bytes = view_bytes(v as usize).ok_or_else(|| {
                ErrorKind::malformed(
                    label.clone(),
                    format!("bufferView {v} lies outside its buffer"),
                )
            })?;
            let nv = self.image_view(bin, &bytes);
            out.insert("bufferView".into(), json!(nv));
            return Ok(Value::Object(out));
        }
        let Some(u) = out.get("uri").and_then(Value::as_str).map(str::to_string) else {
            return Ok(Value::Object(out));
        };
        let placed = match uri::classify(&u) {
            UriKind::Data {
                base64: Some(p),
                mime: m,
            } if self.format == Format::Glb => {
                let bytes =
                    uri::decode_base64(p).map_err(|e| ErrorKind::malformed(label.clone(), e))?;
                let mime = mime
                    .clone()
                    .or_else(|| (!m.is_empty()).then(|| m.to_string()))
                    .or_else(|| uri::sniff_image_mime(&bytes).map(str::to_string))
                    .unwrap_or_else(|| "image/png".into());
                self.embedded(bin, &bytes, &mime)
            }
            UriKind::Relative(rel) => {
                let Some(dir) = self.source_dir.clone() else {
                    return Ok(Value::Object(out));
                };
                let path = uri::resolve(&dir, &rel);
                self.file(bin, &label, &path, Some(&u), mime.as_deref())?
            }
            // Data URIs in a .gltf and remote URIs stay as they are.
            _ => return Ok(Value::Object(out)),
        };
        out.remove("uri");
        out.remove("bufferView");
        out.extend(placed);
        Ok(Value::Object(out))
    }
}
