//! MTL material libraries → [`Material`]s and [`Texture`]s.
//!
//! MTL describes Phong materials; the fields that have a counterpart in the
//! metallic-roughness model are kept: `Kd` (base color), `d`/`Tr` (alpha),
//! `Ke` (emission), the PBR extension `Pr`/`Pm`, and the maps `map_Kd`,
//! `map_Bump`/`bump`/`norm`, `map_Ke`, `map_Pr`/`map_Pm`. Materials are
//! optional decoration of the geometry, so every problem here (a missing
//! library, a bad number, a missing image) is a warning, never an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use wildlod_mesh::{AlphaMode, ImageSource, Material, Texture, TextureRef};

use crate::error::ErrorKind;

use super::text::{self, parse_f32, split_keyword, tokens, trim, trim_start, Lines};

/// What an OBJ material is before any MTL statement: white, dielectric,
/// rough. (glTF's default metallic factor of 1 would turn every OBJ
/// material into metal.)
pub(crate) fn obj_default(name: &str) -> Material {
    Material {
        name: name.to_string(),
        metallic: 0.0,
        roughness: 1.0,
        ..Material::default()
    }
}

/// The texture slots an MTL map statement can fill.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    BaseColor,
    Normal,
    Emissive,
    Roughness,
    Metallic,
}

/// One `newmtl` block as read.
struct Definition {
    material: Material,
    dissolve: Option<f32>,
    transparency: Option<f32>,
    /// (slot, absolute image path, MTL line) in file order.
    maps: Vec<(Slot, PathBuf, usize)>,
    file: PathBuf,
}

/// The materials a file uses, in order of first use, and their textures.
pub(crate) struct Library {
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
}

/// Loads the `mtllib`s of an OBJ in `obj_dir` and builds the materials named
/// in `used`, in that order.
///
/// A library or image that is missing is a warning (assets often travel
/// without them); one that exists but cannot be read as a regular file (a
/// FIFO, a device, a folder, a symlink loop, no permission) is an error:
/// the files are broken or hostile, and reading on could block forever.
pub(crate) fn load(
    obj_dir: &Path,
    mtllibs: &[(usize, Vec<u8>)],
    used: &[String],
    warnings: &mut Vec<String>,
) -> Result<Library, ErrorKind> {
    let mut defs: HashMap<String, Definition> = HashMap::new();
    for (ln, arg) in mtllibs {
        for file in library_paths(obj_dir, arg) {
            match crate::regular::read(&file, crate::MAX_FILE_BYTES) {
                Ok(data) => parse(&file, &data, &mut defs, warnings),
                Err(ErrorKind::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => {
                    warnings.push(format!(
                        "line {ln}: material library {} cannot be read ({e}); its materials get defaults",
                        file.display()
                    ))
                }
                Err(e) => {
                    return Err(ErrorKind::syntax(
                        *ln,
                        format!("material library {}: {e}", file.display()),
                    ))
                }
            }
        }
    }
    let mut lib = Library {
        materials: Vec::with_capacity(used.len()),
        textures: Vec::new(),
    };
    let mut texture_ids: HashMap<PathBuf, u32> = HashMap::new();
    let mut unknown = Vec::new();
    for name in used {
        let Some(def) = defs.get(name) else {
            unknown.push(name.as_str());
            lib.materials.push(obj_default(name));
            continue;
        };
        let mut m = def.material.clone();
        m.base_color[3] = alpha(def, warnings);
        if m.base_color[3] < 1.0 {
            m.alpha_mode = AlphaMode::Blend;
        }
        let mut texture =
            |path: &Path, ln: usize, warnings: &mut Vec<String>| -> Result<TextureRef, ErrorKind> {
                let next = lib.textures.len() as u32;
                let id = *texture_ids.entry(path.to_path_buf()).or_insert(next);
                if id == next {
                    refuse_unreadable_image(&def.file, ln, path)?;
                    let source = existing_image(path).unwrap_or_else(|| {
                        warnings.push(format!(
                            "{} line {ln}: image {} of material '{name}' is not on disk",
                            def.file.display(),
                            path.display()
                        ));
                        path.to_path_buf()
                    });
                    lib.textures.push(Texture {
                        name: source
                            .file_name()
                            .map(|n| n.to_string_lossy().into_owned())
                            .unwrap_or_default(),
                        source: ImageSource::Path(source),
                        // OBJ textures tile.
                        sampler: Default::default(),
                    });
                }
                Ok(TextureRef {
                    texture: id,
                    tex_coord: 0,
                })
            };
        let (mut rough, mut metal) = (None, None);
        for (slot, path, ln) in &def.maps {
            let r = texture(path, *ln, warnings)?;
            match slot {
                Slot::BaseColor => m.base_color_texture = Some(r),
                Slot::Normal => m.normal_texture = Some(r),
                Slot::Emissive => m.emissive_texture = Some(r),
                Slot::Roughness => rough = Some(r),
                Slot::Metallic => metal = Some(r),
            }
        }
        // glTF packs metallic and roughness in one image; MTL names two. The
        // same image under both (an ORM texture) fits exactly; two different
        // images cannot both be kept.
        if let (Some(r), Some(mt)) = (rough, metal) {
            if r.texture != mt.texture {
                warnings.push(format!(
                    "material '{name}': map_Pr and map_Pm name different images; glTF-style materials \
                     hold one metallic-roughness image, map_Pr is kept"
                ));
            }
        }
        m.metallic_roughness_texture = rough.or(metal);
        lib.materials.push(m);
    }
    if !unknown.is_empty() {
        warnings.push(format!(
            "usemtl names no material of the material libraries, default materials used: {}",
            unknown.join(", ")
        ));
    }
    Ok(lib)
}

/// An image path that exists but is no regular file (a FIFO, a device, a
/// folder, a link loop) is refused at once: writing the output would read
/// it. A missing one is left to the caller's warning.
fn refuse_unreadable_image(mtl: &Path, ln: usize, path: &Path) -> Result<(), ErrorKind> {
    match crate::regular::not_regular(path) {
        Ok(()) => Ok(()),
        Err(ErrorKind::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(ErrorKind::malformed(
            format!("{} line {ln}", mtl.display()),
            format!("image {}: {e}", path.display()),
        )),
    }
}

/// Alpha from `d` (opacity) or `Tr` (transparency, 1 − d); `d` wins.
fn alpha(def: &Definition, warnings: &mut Vec<String>) -> f32 {
    match (def.dissolve, def.transparency) {
        (Some(d), _) => d,
        // Some exporters write `Tr 1` meaning opaque (they took Tr for
        // opacity). A fully invisible material is never what such a file
        // means, so it is read as opaque, and said so.
        (None, Some(t)) if t >= 1.0 => {
            warnings.push(format!(
                "{}: material '{}' has 'Tr {t}' (fully transparent); read as opaque, the usual \
                 intent of exporters that write Tr as opacity",
                def.file.display(),
                def.material.name
            ));
            1.0
        }
        (None, Some(t)) => 1.0 - t,
        (None, None) => 1.0,
    }
}

/// The image at `path`, or a file in the same folder whose name differs
/// only in letter case (assets made on Windows often disagree on case).
pub(crate) fn existing_image(path: &Path) -> Option<PathBuf> {
    if path.is_file() {
        return Some(path.to_path_buf());
    }
    let name = path.file_name()?.to_str()?;
    let dir = path.parent()?;
    std::fs::read_dir(dir)
        .ok()?
        .flatten()
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.eq_ignore_ascii_case(name))
                && p.is_file()
        })
}

/// The files named by one `mtllib` statement. The argument is a list of
/// file names, but exporters also write one name containing spaces, or
/// quote names: a whole argument naming an existing file wins, then quoted
/// names, then a split on whitespace.
pub(crate) fn library_paths(dir: &Path, arg: &[u8]) -> Vec<PathBuf> {
    let arg = trim(arg);
    if arg.is_empty() {
        return Vec::new();
    }
    let whole = super::resolve_path(dir, &String::from_utf8_lossy(unquote(arg)));
    if whole.is_file() {
        return vec![whole];
    }
    if arg.contains(&b'"') {
        return arg
            .split(|&b| b == b'"')
            .skip(1)
            .step_by(2)
            .filter(|s| !trim(s).is_empty())
            .map(|s| super::resolve_path(dir, &String::from_utf8_lossy(s)))
            .collect();
    }
    tokens(arg)
        .map(|t| super::resolve_path(dir, &String::from_utf8_lossy(t)))
        .collect()
}

fn unquote(s: &[u8]) -> &[u8] {
    match s {
        [b'"', inner @ .., b'"'] => inner,
        _ => s,
    }
}

/// Parses one MTL file into `defs` (the first definition of a name wins).
fn parse(
    file: &Path,
    data: &[u8],
    defs: &mut HashMap<String, Definition>,
    warnings: &mut Vec<String>,
) {
    let dir = file.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut current: Option<Definition> = None;
    let mut commit = |def: Option<Definition>, warnings: &mut Vec<String>| {
        if let Some(d) = def {
            if defs.contains_key(&d.material.name) {
                warnings.push(format!(
                    "{}: material '{}' is defined again; the first definition is kept",
                    file.display(),
                    d.material.name
                ));
            } else {
                defs.insert(d.material.name.clone(), d);
            }
        }
    };
    let mut lines = Lines::new(data, true);
    while let Some((ln, line)) = lines.next_line() {
        let line = trim_start(line);
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (kw, rest) = split_keyword(line);
        let kw = String::from_utf8_lossy(kw).to_ascii_lowercase();
        if kw == "newmtl" {
            commit(current.take(), warnings);
            current = Some(Definition {
                material: obj_default(&text::name(rest)),
                dissolve: None,
                transparency: None,
                maps: Vec::new(),
                file: file.to_path_buf(),
            });
            continue;
        }
        let Some(def) = current.as_mut() else {
            continue;
        };
        let mut warn = |msg: String| {
            warnings.push(format!("{} line {ln}: {kw}: {msg}", file.display()));
        };
        match kw.as_str() {
            "kd" => match color(rest) {
                Ok(c) => def.material.base_color[..3].copy_from_slice(&c),
                Err(e) => warn(e),
            },
            "ke" => match color(rest) {
                Ok(c) => def.material.emissive = c,
                Err(e) => warn(e),
            },
            "d" | "tr" | "pr" | "pm" => match scalar(rest) {
                Ok(v) => match kw.as_str() {
                    "d" => def.dissolve = Some(v),
                    "tr" => def.transparency = Some(v),
                    "pr" => def.material.roughness = v,
                    _ => def.material.metallic = v,
                },
                Err(e) => warn(e),
            },
            "map_kd" | "map_bump" | "bump" | "norm" | "map_ke" | "map_pr" | "map_pm" => {
                let slot = match kw.as_str() {
                    "map_kd" => Slot::BaseColor,
                    "map_ke" => Slot::Emissive,
                    "map_pr" => Slot::Roughness,
                    "map_pm" => Slot::Metallic,
                    _ => Slot::Normal,
                };
                let f = map_file(rest);
                if f.is_empty() {
                    warn("no image file named".into());
                } else {
                    let path = super::resolve_path(&dir, &String::from_utf8_lossy(f));
                    def.maps.retain(|(s, _, _)| *s != slot);
                    def.maps.push((slot, path, ln));
                }
            }
            _ => {}
        }
    }
    commit(current.take(), warnings);
}

/// `r [g b]`: one value means gray.
fn color(rest: &[u8]) -> Result<[f32; 3], String> {
    let mut c = [0f32; 3];
    let mut n = 0;
    for tok in tokens(rest) {
        if n == 3 {
            return Err("more than 3 values".into());
        }
        c[n] = parse_f32(tok)?;
        n += 1;
    }
    match n {
        1 => Ok([c[0]; 3]),
        3 => Ok(c),
        _ => Err(format!("expected r g b, found {n} values")),
    }
}

fn scalar(rest: &[u8]) -> Result<f32, String> {
    // `d -halo 0.5`: the halo option has no counterpart; take the number.
    let tok = tokens(rest)
        .find(|t| !t.starts_with(b"-") || parse_f32(t).is_ok())
        .ok_or_else(|| "expected a number".to_string())?;
    parse_f32(tok)
}

/// The image file of a map statement, after its options (`-bm 1`,
/// `-s 1 1 1`…). The rest of the line is the name, spaces included.
pub(crate) fn map_file(rest: &[u8]) -> &[u8] {
    let mut s = trim(rest);
    while s.first() == Some(&b'-') {
        let (opt, after) = split_keyword(s);
        let (min, max) = match String::from_utf8_lossy(opt).to_ascii_lowercase().as_str() {
            "-blendu" | "-blendv" | "-cc" | "-clamp" | "-bm" | "-boost" | "-texres"
            | "-imfchan" | "-type" => (1, 1),
            "-mm" => (2, 2),
            "-o" | "-s" | "-t" => (1, 3),
            // Not an option we know: a file name that starts with '-'.
            _ => break,
        };
        s = trim_start(after);
        for i in 0..max {
            let (arg, after) = split_keyword(s);
            if arg.is_empty() || (i >= min && parse_f32(arg).is_err()) {
                break;
            }
            s = trim_start(after);
        }
    }
    unquote(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_options_before_the_file_are_skipped() {
        assert_eq!(map_file(b" -bm 1 -s 1 1 1 tex.png"), b"tex.png");
        assert_eq!(map_file(b"-o 0.5 my tex.png"), b"my tex.png");
        assert_eq!(map_file(b"-clamp on \"a b.jpg\""), b"a b.jpg");
        assert_eq!(map_file(b"-weird.png"), b"-weird.png");
    }

    #[test]
    fn single_value_color_is_gray() {
        assert_eq!(color(b" 0.5").unwrap(), [0.5; 3]);
        assert!(color(b" 0.5 0.1").is_err());
        assert!(color(b" spectral file.rfl").is_err());
    }
}
