//! OBJ statements → a [`Mesh`] whose streams mirror the file: positions as
//! `v`, UV set 0 as `vt` (v flipped to the model's top-left origin, see
//! `text::v_from_file`), normals as `vn`, and per-corner indices taken from
//! the `v/vt/vn` triplets. Faces keep their arity.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Part, Scene, Semantic, ABSENT};

use super::mtl;
use super::text::{
    self, cut_comment, parse_f32, parse_f64, parse_i64, show, split_keyword, tokens, v_from_file,
    Lines,
};
use crate::ErrorKind;

/// Statements that carry no polygon data we keep (lines, points,
/// free-form geometry, display attributes). They are skipped
/// and reported together in one warning.
const KNOWN_IGNORED: &str = "l p vp curv curv2 surf parm trim hole scrv sp end con cstype deg \
                             bmat step mg lod bevel c_interp d_interp usemap maplib shadow_obj \
                             trace_obj ctech stech call csh";

/// Reads an OBJ file and the MTL files it names.
pub(crate) fn read(
    path: &Path,
    data: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Scene, ErrorKind> {
    let parsed = parse(data, warnings)?;
    let dir = super::absolute_dir(path);
    let lib = mtl::load(&dir, &parsed.mtllibs, &parsed.used_materials, warnings)?;
    let mut mesh = parsed.mesh;
    mesh.name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut scene = Scene::from_mesh(mesh);
    if let Some(o) = parsed.origin {
        // Positions relative to a far point: the node puts them back.
        scene.nodes[0].matrix[12..15].copy_from_slice(&o);
    }
    scene.materials = lib.materials;
    scene.textures = lib.textures;
    Ok(scene)
}

/// The mesh of an OBJ file before its materials are resolved.
pub(crate) struct Parsed {
    /// Positions, faces, parts and streams; `Part::material` indexes
    /// `used_materials`.
    pub mesh: Mesh,
    /// `usemtl` names in order of first use by a face.
    pub used_materials: Vec<String>,
    /// `mtllib` arguments with their line numbers.
    pub mtllibs: Vec<(usize, Vec<u8>)>,
    /// Where the positions are relative to, when the file's coordinates
    /// lie so far from the origin that f32 would round them visibly (see
    /// [`crate::far::far_origin`]); exactly representable in f32.
    pub origin: Option<[f32; 3]>,
}

/// A vertex or attribute index seen before its pool was complete: OBJ
/// allows forward references in practice, so range checks on positive
/// indices wait for the end of the file. Keeps the largest index and where
/// it was used.
#[derive(Default)]
struct MaxRef {
    index: Option<(u32, usize)>,
}

impl MaxRef {
    #[inline]
    fn note(&mut self, index: u32, line: usize) {
        match self.index {
            Some((i, _)) if i >= index => {}
            _ => self.index = Some((index, line)),
        }
    }

    fn check(&self, count: usize, what: &str, statement: &str) -> Result<(), ErrorKind> {
        match self.index {
            Some((i, line)) if i as usize >= count => Err(ErrorKind::syntax(
                line,
                format!(
                    "{what} index {} is out of range: the file has {count} {statement} statements",
                    i as u64 + 1
                ),
            )),
            _ => Ok(()),
        }
    }
}

/// Parser state: pools, faces and the current grouping.
#[derive(Default)]
struct State {
    positions: Vec<[f32; 3]>,
    /// The positions' bounds as written (f64), before rounding to f32.
    lo: [f64; 3],
    hi: [f64; 3],
    /// Per-position colors, created at the first colored `v`.
    colors: Vec<[f32; 4]>,
    has_color: Vec<bool>,
    color_components: u8,
    uvs: Vec<f32>,
    normals: Vec<f32>,
    faces: Faces,
    corner_uv: Vec<u32>,
    corner_normal: Vec<u32>,
    face_parts: Vec<u32>,
    parts: Vec<Part>,
    part_ids: HashMap<(String, Option<u32>), u32>,
    /// Object name (`o`), and group name (`g`) since the last `o`.
    object: String,
    group: Option<String>,
    /// Index into `material_names` of the current `usemtl`.
    material: Option<u32>,
    material_names: Vec<String>,
    material_ids: HashMap<String, u32>,
    /// Part of the next face; `None` after a grouping statement.
    current_part: Option<u32>,
    max_v: MaxRef,
    max_vt: MaxRef,
    max_vn: MaxRef,
    mtllibs: Vec<(usize, Vec<u8>)>,
    ignored: BTreeMap<String, usize>,
    /// Faces skipped for having fewer than three distinct vertices.
    skipped_faces: usize,
}

/// Parses OBJ text into a mesh; materials stay names.
pub(crate) fn parse(data: &[u8], warnings: &mut Vec<String>) -> Result<Parsed, ErrorKind> {
    let mut st = State::default();
    let mut lines = Lines::new(data, true);
    while let Some((ln, line)) = lines.next_line() {
        let line = text::trim_start(line);
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (kw, rest) = split_keyword(line);
        match kw {
            b"v" => st.vertex(ln, cut_comment(rest))?,
            b"vt" => st.tex_coord(ln, cut_comment(rest))?,
            b"vn" => st.normal(ln, cut_comment(rest))?,
            b"f" | b"fo" => st.face(ln, cut_comment(rest))?,
            b"o" => {
                st.object = text::name(rest);
                st.group = None;
                st.current_part = None;
            }
            b"g" => {
                st.group = Some(text::name(rest));
                st.current_part = None;
            }
            b"usemtl" => {
                let name = text::name(rest);
                // A bare `usemtl` ends the current material: the writer uses
                // it for parts without one, since OBJ has no other way back.
                st.material = if name.is_empty() {
                    None
                } else {
                    let next = st.material_names.len() as u32;
                    let id = *st.material_ids.entry(name.clone()).or_insert(next);
                    if id == next {
                        st.material_names.push(name);
                    }
                    Some(id)
                };
                st.current_part = None;
            }
            b"mtllib" => st.mtllibs.push((ln, text::trim(rest).to_vec())),
            // Smoothing groups are ordinary OBJ and only say how to shade:
            // accepted without a warning (no normals are derived from them;
            // a file without `vn` is read without normals, as before).
            b"s" => {}
            _ => st.ignore(ln, kw, line)?,
        }
    }
    if st.skipped_faces > 0 {
        warnings.push(crate::skipped_faces_warning(st.skipped_faces));
    }
    if !st.ignored.is_empty() {
        let list: Vec<String> = st
            .ignored
            .iter()
            .map(|(k, n)| format!("'{k}' ×{n}"))
            .collect();
        warnings.push(format!(
            "ignored OBJ statements that carry no polygon data: {}",
            list.join(", ")
        ));
    }
    let origin = crate::far::far_origin(st.lo, st.hi);
    if let Some(o) = origin {
        reread_relative(data, o, &mut st.positions);
    }
    let mut parsed = st.finish()?;
    parsed.origin = origin;
    Ok(parsed)
}

impl State {
    fn vertex(&mut self, ln: usize, rest: &[u8]) -> Result<(), ErrorKind> {
        let mut vals = [0f32; 7];
        let mut n = 0;
        for tok in tokens(rest) {
            if n == vals.len() {
                return Err(ErrorKind::syntax(
                    ln,
                    "a vertex has at most 7 values: x y z, then w or r g b [a]",
                ));
            }
            vals[n] = parse_f32(tok).map_err(|e| ErrorKind::syntax(ln, format!("vertex: {e}")))?;
            n += 1;
        }
        // Bounds, to see whether f32 loses the coordinates (see
        // `far_origin`; the f32 values tell as well as the f64 ones).
        let p: [f64; 3] = std::array::from_fn(|k| f64::from(vals[k]));
        if self.positions.is_empty() {
            (self.lo, self.hi) = (p, p);
        } else {
            for (k, &x) in p.iter().enumerate() {
                self.lo[k] = self.lo[k].min(x);
                self.hi[k] = self.hi[k].max(x);
            }
        }
        if n < 3 {
            return Err(ErrorKind::syntax(
                ln,
                format!("a vertex needs 3 coordinates, found {n}"),
            ));
        }
        // 4 values: x y z w (w is a rational weight, dropped); 6 or 7:
        // x y z r g b [a], the common vertex-color extension.
        if n >= 6 {
            if self.has_color.is_empty() {
                self.has_color = vec![false; self.positions.len()];
                self.colors = vec![[0.0; 4]; self.positions.len()];
                self.color_components = 3;
            }
            let alpha = if n == 7 {
                self.color_components = 4;
                vals[6]
            } else {
                1.0
            };
            self.colors.push([vals[3], vals[4], vals[5], alpha]);
            self.has_color.push(true);
        } else if n == 5 {
            return Err(ErrorKind::syntax(
                ln,
                "a vertex has 3, 4, 6 or 7 values, found 5",
            ));
        } else if !self.has_color.is_empty() {
            self.colors.push([0.0; 4]);
            self.has_color.push(false);
        }
        self.positions.push([vals[0], vals[1], vals[2]]);
        Ok(())
    }

    fn tex_coord(&mut self, ln: usize, rest: &[u8]) -> Result<(), ErrorKind> {
        // A missing v is 0, the bottom of the image.
        let mut uv = [0f32, v_from_file(0.0)];
        let mut n = 0;
        for tok in tokens(rest) {
            let bad = |e: String| ErrorKind::syntax(ln, format!("texture coordinate: {e}"));
            match n {
                0 => uv[0] = parse_f32(tok).map_err(bad)?,
                1 => {
                    uv[1] = v_from_file(parse_f64(tok).map_err(bad)?);
                    if !uv[1].is_finite() {
                        return Err(bad(format!("'{}' is not a finite number", show(tok))));
                    }
                }
                // A third component (w) is legal and dropped.
                2 => {
                    parse_f32(tok).map_err(bad)?;
                }
                _ => {
                    return Err(ErrorKind::syntax(
                        ln,
                        "a texture coordinate has at most 3 values",
                    ))
                }
            }
            n += 1;
        }
        if n == 0 {
            return Err(ErrorKind::syntax(ln, "a texture coordinate needs a value"));
        }
        self.uvs.extend_from_slice(&uv);
        Ok(())
    }

    fn normal(&mut self, ln: usize, rest: &[u8]) -> Result<(), ErrorKind> {
        let mut nrm = [0f32; 3];
        let mut n = 0;
        for tok in tokens(rest) {
            if n == 3 {
                return Err(ErrorKind::syntax(ln, "a normal has 3 values"));
            }
            nrm[n] = parse_f32(tok).map_err(|e| ErrorKind::syntax(ln, format!("normal: {e}")))?;
            n += 1;
        }
        if n != 3 {
            return Err(ErrorKind::syntax(
                ln,
                format!("a normal needs 3 values, found {n}"),
            ));
        }
        self.normals.extend_from_slice(&nrm);
        Ok(())
    }

    fn face(&mut self, ln: usize, rest: &[u8]) -> Result<(), ErrorKind> {
        let start = self.faces.indices.len();
        let (nv, nt, nn) = (
            self.positions.len(),
            self.uvs.len() / 2,
            self.normals.len() / 3,
        );
        for tok in tokens(rest) {
            let mut parts = tok.split(|&b| b == b'/');
            let v = parts.next().unwrap_or_default();
            if v.is_empty() {
                return Err(ErrorKind::syntax(
                    ln,
                    format!("face corner '{}' has no vertex index", show(tok)),
                ));
            }
            let v = resolve(v, nv, ln, "vertex", &mut self.max_v)?;
            let vt = match parts.next() {
                Some(t) if !t.is_empty() => {
                    resolve(t, nt, ln, "texture coordinate", &mut self.max_vt)?
                }
                _ => ABSENT,
            };
            let vn = match parts.next() {
                Some(t) if !t.is_empty() => resolve(t, nn, ln, "normal", &mut self.max_vn)?,
                _ => ABSENT,
            };
            if parts.next().is_some() {
                return Err(ErrorKind::syntax(
                    ln,
                    format!("face corner '{}' has more than v/vt/vn", show(tok)),
                ));
            }
            self.faces.indices.push(v);
            self.corner_uv.push(vt);
            self.corner_normal.push(vn);
        }
        if !crate::has_three_distinct(&self.faces.indices[start..]) {
            // No area: skipped, counted, warned about once (see
            // `has_three_distinct`).
            self.faces.indices.truncate(start);
            self.corner_uv.truncate(start);
            self.corner_normal.truncate(start);
            self.skipped_faces += 1;
            return Ok(());
        }
        let end = u32::try_from(self.faces.indices.len())
            .map_err(|_| ErrorKind::syntax(ln, "more face corners than wildlod holds (2³² − 1)"))?;
        self.faces.offsets.push(end);
        let part = match self.current_part {
            Some(p) => p,
            None => {
                let p = self.part_id();
                self.current_part = Some(p);
                p
            }
        };
        self.face_parts.push(part);
        Ok(())
    }

    /// The part of the current (object or group, material), reused when
    /// the same pair occurred before.
    fn part_id(&mut self) -> u32 {
        let name = self.group.clone().unwrap_or_else(|| self.object.clone());
        let key = (name, self.material);
        let next = self.parts.len() as u32;
        let id = *self.part_ids.entry(key.clone()).or_insert(next);
        if id == next {
            self.parts.push(Part {
                name: key.0,
                material: key.1,
            });
        }
        id
    }

    fn ignore(&mut self, ln: usize, kw: &[u8], line: &[u8]) -> Result<(), ErrorKind> {
        let word = kw
            .first()
            .is_some_and(|b| b.is_ascii_alphabetic() || *b == b'_')
            && kw.iter().all(|b| b.is_ascii_alphanumeric() || *b == b'_');
        if !word || line.contains(&0) {
            return Err(ErrorKind::syntax(
                ln,
                format!(
                    "'{}' is not an OBJ statement (is this a text OBJ file?)",
                    show(kw)
                ),
            ));
        }
        let kw = String::from_utf8_lossy(kw).into_owned();
        let known = KNOWN_IGNORED.split_whitespace().any(|k| k == kw);
        // Unknown words are ignored too (exporters invent statements), but a
        // file of nothing else is probably not OBJ; the distinct names kept
        // for the warning are bounded.
        if known || self.ignored.len() < 32 || self.ignored.contains_key(&kw) {
            *self.ignored.entry(kw).or_insert(0) += 1;
        }
        Ok(())
    }

    fn finish(self) -> Result<Parsed, ErrorKind> {
        if self.faces.is_empty() {
            return Err(ErrorKind::malformed(
                "OBJ",
                "the file has no faces ('f' statements)",
            ));
        }
        self.max_v.check(self.positions.len(), "vertex", "'v'")?;
        self.max_vt
            .check(self.uvs.len() / 2, "texture coordinate", "'vt'")?;
        self.max_vn
            .check(self.normals.len() / 3, "normal", "'vn'")?;

        // Materials are numbered by first use in a face, so that unused
        // `usemtl` names do not become materials (and round trips keep
        // the material list).
        let mut remap = vec![u32::MAX; self.material_names.len()];
        let mut used_materials = Vec::new();
        let mut parts = self.parts;
        for part in &mut parts {
            if let Some(m) = part.material {
                let slot = &mut remap[m as usize];
                if *slot == u32::MAX {
                    *slot = used_materials.len() as u32;
                    used_materials.push(self.material_names[m as usize].clone());
                }
                part.material = Some(*slot);
            }
        }

        let mut attributes = Vec::new();
        if !self.uvs.is_empty() {
            attributes.push(Attribute {
                semantic: Semantic::TexCoord(0),
                components: 2,
                values: self.uvs,
                indices: self.corner_uv,
                format: ComponentFormat::F32,
            });
        }
        if !self.normals.is_empty() {
            attributes.push(Attribute {
                semantic: Semantic::Normal,
                components: 3,
                values: self.normals,
                indices: self.corner_normal,
                format: ComponentFormat::F32,
            });
        }
        if self.has_color.iter().any(|&c| c) {
            let k = self.color_components as usize;
            let mut values = Vec::with_capacity(self.colors.len() * k);
            for c in &self.colors {
                values.extend_from_slice(&c[..k]);
            }
            let indices = self
                .faces
                .indices
                .iter()
                .map(|&v| {
                    if self.has_color.get(v as usize).copied().unwrap_or(false) {
                        v
                    } else {
                        ABSENT
                    }
                })
                .collect();
            attributes.push(Attribute {
                semantic: Semantic::Color(0),
                components: self.color_components,
                values,
                indices,
                format: ComponentFormat::F32,
            });
        }
        let mesh = Mesh {
            name: String::new(),
            positions: self.positions,
            faces: self.faces,
            face_parts: self.face_parts,
            parts,
            attributes,
            skinning: None,
        };
        Ok(Parsed {
            mesh,
            used_materials,
            mtllibs: self.mtllibs,
            origin: None,
        })
    }
}

/// Reads every `v` line's coordinates again, in f64, into `positions`
/// relative to `origin` (same order as the first pass, which checked them).
fn reread_relative(data: &[u8], origin: [f32; 3], positions: &mut [[f32; 3]]) {
    let o = origin.map(f64::from);
    let mut lines = Lines::new(data, true);
    let mut k = 0;
    while let Some((_, line)) = lines.next_line() {
        let line = text::trim_start(line);
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (kw, rest) = split_keyword(line);
        if kw != b"v" {
            continue;
        }
        let Some(p) = positions.get_mut(k) else {
            return;
        };
        for (c, tok) in tokens(cut_comment(rest)).take(3).enumerate() {
            if let Ok(x) = parse_f64(tok) {
                p[c] = (x - o[c]) as f32;
            }
        }
        k += 1;
    }
}

/// Resolves one index of a face corner: 1-based, or negative counting back
/// from the last element defined so far.
#[inline]
fn resolve(
    tok: &[u8],
    defined: usize,
    ln: usize,
    what: &str,
    max: &mut MaxRef,
) -> Result<u32, ErrorKind> {
    let i = parse_i64(tok).ok_or_else(|| {
        ErrorKind::syntax(
            ln,
            format!("{what} index '{}' is not an integer", show(tok)),
        )
    })?;
    if i > 0 {
        let idx = u32::try_from(i - 1)
            .ok()
            .filter(|&x| x != ABSENT)
            .ok_or_else(|| ErrorKind::syntax(ln, format!("{what} index {i} is out of range")))?;
        max.note(idx, ln);
        Ok(idx)
    } else if i < 0 {
        let idx = (defined as i64).checked_add(i).filter(|&x| x >= 0).ok_or_else(|| {
            ErrorKind::syntax(
                ln,
                format!("relative {what} index {i} reaches before the first one ({defined} defined so far)"),
            )
        })?;
        // In range by construction: idx < defined ≤ u32 pool sizes.
        u32::try_from(idx)
            .map_err(|_| ErrorKind::syntax(ln, format!("{what} index {i} is out of range")))
    } else {
        Err(ErrorKind::syntax(
            ln,
            format!("{what} index 0 is invalid: OBJ indices start at 1"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(s: &str) -> (Parsed, Vec<String>) {
        let mut w = Vec::new();
        let p = parse(s.as_bytes(), &mut w).unwrap();
        (p, w)
    }

    #[test]
    fn same_group_and_material_pair_reuses_its_part() {
        let (p, _) = parse_ok(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n\
             g a\nusemtl m\nf 1 2 3\ng b\nf 1 2 3\ng a\nf 1 2 3\nusemtl n\nf 1 2 3\n",
        );
        let names: Vec<_> = p
            .mesh
            .parts
            .iter()
            .map(|p| (p.name.as_str(), p.material))
            .collect();
        assert_eq!(names, vec![("a", Some(0)), ("b", Some(0)), ("a", Some(1))]);
        assert_eq!(p.mesh.face_parts, vec![0, 1, 0, 2]);
        assert_eq!(p.used_materials, vec!["m", "n"]);
    }

    #[test]
    fn usemtl_without_faces_is_not_a_material() {
        let (p, _) = parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl unused\nusemtl used\nf 1 2 3\n");
        assert_eq!(p.used_materials, vec!["used"]);
        assert_eq!(p.mesh.parts[0].material, Some(0));
    }

    #[test]
    fn object_name_names_parts_until_a_group_follows() {
        let (p, _) = parse_ok(
            "o obj\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng grp\nf 1 2 3\no next\nf 1 2 3\n",
        );
        let names: Vec<_> = p.mesh.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, vec!["obj", "grp", "next"]);
    }

    #[test]
    fn forward_reference_is_accepted_when_defined_later() {
        let (p, _) = parse_ok("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
        assert_eq!(p.mesh.faces.face(0), &[0, 1, 2]);
    }
}
