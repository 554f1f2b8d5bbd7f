//! OFF (Geomview's Object File Format), the format of CGAL, libigl and most
//! geometry-processing data sets: `[ST][C][N]OFF`, then `vertices faces
//! edges`, then one vertex per line (`x y z`, then the normal with `N`, the
//! color with `C`, the texture coordinate with `ST`) and one face per line
//! (`k v1 … vk`, then an optional color). `#` starts a comment.
//!
//! Colors are floats in [0, 1] or integers in 0–255 (a color whose values
//! are all integers and one of them above 1 is read as bytes); a single
//! value after a face is a colormap index and is ignored. Faces with fewer
//! than three distinct vertices are skipped and counted, like in OBJ and
//! PLY. The 4D and `nOFF` variants and binary OFF are refused with a clear
//! error.
//!
//! Hostile input: counts are checked against the file size before
//! anything is allocated (a vertex needs at least 6 bytes, a face 8), every
//! index is range-checked, and every error names the line.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Scene, Semantic, ABSENT};

use crate::far::{exact_decimals, trimmed};
use crate::obj::text::{self, parse_f32, parse_i64, show, v_from_file};
use crate::{ErrorKind, OutputFiles};

/// Fewest bytes a vertex line can take (`0 0 0\n`).
const MIN_VERTEX_BYTES: u64 = 6;
/// Fewest bytes a face line can take (`3 0 1 2\n`).
const MIN_FACE_BYTES: u64 = 8;

/// What the header keyword announces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Layout {
    normals: bool,
    colors: bool,
    tex_coords: bool,
}

/// Reads an OFF file.
pub(crate) fn read(
    path: &Path,
    data: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Scene, ErrorKind> {
    let (mut mesh, origin) = read_mesh(data, warnings)?;
    mesh.name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut scene = Scene::from_mesh(mesh);
    if let Some(o) = origin {
        // Positions relative to a far point: the node puts them back.
        scene.nodes[0].matrix[12..15].copy_from_slice(&o);
    }
    Ok(scene)
}

/// Numbered lines of the file (1-based), borrowing from its bytes.
fn lines(data: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    data.split(|&b| b == b'\n')
        .map(|l| l.strip_suffix(b"\r").unwrap_or(l))
        .enumerate()
        .map(|(i, l)| (i + 1, l))
}

/// The next line with content (comments cut, blank lines skipped): its
/// number and tokens.
fn content<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
) -> Option<(usize, Vec<&'a [u8]>)> {
    for (ln, line) in lines {
        let toks: Vec<&[u8]> = text::tokens(text::cut_comment(line)).collect();
        if !toks.is_empty() {
            return Some((ln, toks));
        }
    }
    None
}

fn parse_header(kw: &[u8], ln: usize) -> Result<Layout, ErrorKind> {
    let Some(prefix) = kw.strip_suffix(b"OFF") else {
        return Err(ErrorKind::syntax(
            ln,
            format!(
                "'{}' is not an OFF header ([ST][C][N]OFF expected)",
                show(kw)
            ),
        ));
    };
    let mut rest = prefix;
    let mut layout = Layout::default();
    if let Some(r) = rest.strip_prefix(b"ST") {
        layout.tex_coords = true;
        rest = r;
    }
    if let Some(r) = rest.strip_prefix(b"C") {
        layout.colors = true;
        rest = r;
    }
    if let Some(r) = rest.strip_prefix(b"N") {
        layout.normals = true;
        rest = r;
    }
    if rest.contains(&b'4') || rest.contains(&b'n') {
        return Err(ErrorKind::Unsupported(format!(
            "line {ln}: '{}' is a 4D or n-dimensional OFF; wildlod reads 3D meshes",
            show(kw)
        )));
    }
    if !rest.is_empty() {
        return Err(ErrorKind::syntax(
            ln,
            format!(
                "'{}' is not an OFF header ([ST][C][N]OFF expected)",
                show(kw)
            ),
        ));
    }
    Ok(layout)
}

fn count(tok: &[u8], ln: usize, what: &str) -> Result<u64, ErrorKind> {
    parse_i64(tok)
        .and_then(|v| u64::try_from(v).ok())
        .ok_or_else(|| {
            ErrorKind::syntax(
                ln,
                format!(
                    "the {what} count '{}' is not a non-negative integer",
                    show(tok)
                ),
            )
        })
}

/// A color from its tokens: floats in [0, 1], or bytes when every value is
/// an integer and one exceeds 1.
fn color(toks: &[&[u8]], ln: usize) -> Result<[f32; 4], ErrorKind> {
    let mut c = [1.0f32; 4];
    for (k, t) in toks.iter().enumerate() {
        c[k] = parse_f32(t).map_err(|m| ErrorKind::syntax(ln, m))?;
    }
    let bytes = toks.iter().all(|t| parse_i64(t).is_some()) && c.iter().any(|&x| x > 1.0);
    if bytes {
        for x in &mut c[..toks.len()] {
            *x = (*x / 255.0).clamp(0.0, 1.0);
        }
    }
    Ok(c)
}

/// The mesh of an OFF file, with its positions relative to the point
/// returned beside it when they lie far from the origin
/// ([`crate::far::far_origin`]).
fn read_mesh(
    data: &[u8],
    warnings: &mut Vec<String>,
) -> Result<(Mesh, Option<[f32; 3]>), ErrorKind> {
    let mut lines = lines(data);
    let Some((ln, first)) = content(&mut lines) else {
        return Err(ErrorKind::malformed("OFF", "the file has no header"));
    };
    // The keyword is optional in Geomview's OFF: a file may start with
    // its counts.
    let (layout, mut counts, counts_line) = if parse_i64(first[0]).is_some() {
        (Layout::default(), first, ln)
    } else {
        let layout = parse_header(first[0], ln)?;
        if first[1..].iter().any(|t| t.eq_ignore_ascii_case(b"BINARY")) {
            return Err(ErrorKind::Unsupported(format!(
                "line {ln}: binary OFF is not supported; convert it to text OFF"
            )));
        }
        if first.len() > 1 {
            (layout, first[1..].to_vec(), ln)
        } else {
            let Some((ln, c)) = content(&mut lines) else {
                return Err(ErrorKind::malformed(
                    "OFF header",
                    "no vertex and face counts",
                ));
            };
            (layout, c, ln)
        }
    };
    if counts.len() < 2 {
        return Err(ErrorKind::syntax(
            counts_line,
            "expected the vertex, face and edge counts",
        ));
    }
    counts.truncate(3);
    let nv = count(counts[0], counts_line, "vertex")?;
    let nf = count(counts[1], counts_line, "face")?;
    let size = data.len() as u64;
    for (what, n, per) in [
        ("OFF vertex count", nv, MIN_VERTEX_BYTES),
        ("OFF face count", nf, MIN_FACE_BYTES),
    ] {
        if n > size / per {
            return Err(ErrorKind::ImplausibleCount {
                element: what.into(),
                count: n,
                max: size / per,
            });
        }
    }
    if nv > u32::MAX as u64 - 1 {
        return Err(ErrorKind::malformed(
            "OFF header",
            "more vertices than wildlod holds",
        ));
    }
    let (nv, nf) = (nv as usize, nf as usize);
    let mut positions = Vec::with_capacity(nv);
    let mut exact: Vec<[f64; 3]> = Vec::with_capacity(nv);
    let mut normals: Vec<f32> = Vec::with_capacity(if layout.normals { 3 * nv } else { 0 });
    let mut colors: Vec<f32> = Vec::new();
    let mut color_components = 3u8;
    let mut uvs: Vec<f32> = Vec::with_capacity(if layout.tex_coords { 2 * nv } else { 0 });
    for i in 0..nv {
        let Some((ln, toks)) = content(&mut lines) else {
            return Err(ErrorKind::malformed(
                "OFF",
                format!("the file ends after {i} of {nv} vertices"),
            ));
        };
        let number = |t: &[u8]| parse_f32(t).map_err(|m| ErrorKind::syntax(ln, m));
        let need = 3 + if layout.normals { 3 } else { 0 } + if layout.tex_coords { 2 } else { 0 };
        let with_color = if layout.colors { 3 } else { 0 };
        if toks.len() < need + with_color {
            return Err(ErrorKind::syntax(
                ln,
                format!(
                    "vertex {i} has {} values, the header asks for at least {}",
                    toks.len(),
                    need + with_color
                ),
            ));
        }
        positions.push([number(toks[0])?, number(toks[1])?, number(toks[2])?]);
        // The digits in f64 too, for coordinates far from the origin.
        let wide = |t: &[u8]| text::parse_f64(t).map_err(|m| ErrorKind::syntax(ln, m));
        exact.push([wide(toks[0])?, wide(toks[1])?, wide(toks[2])?]);
        let mut at = 3;
        if layout.normals {
            for t in &toks[3..6] {
                normals.push(number(t)?);
            }
            at = 6;
        }
        if layout.colors {
            // RGB or RGBA: what is left once the texture coordinate is
            // set aside.
            let left = toks.len() - at - if layout.tex_coords { 2 } else { 0 };
            let k = if left >= 4 { 4 } else { 3 };
            if k == 4 && color_components == 3 {
                // The first RGBA vertex turns the stream RGBA.
                let mut wider = Vec::with_capacity(colors.len() / 3 * 4);
                for c in colors.chunks_exact(3) {
                    wider.extend_from_slice(&[c[0], c[1], c[2], 1.0]);
                }
                colors = wider;
                color_components = 4;
            }
            let c = color(&toks[at..at + k], ln)?;
            colors.extend_from_slice(&c[..color_components as usize]);
            at += k;
        }
        if layout.tex_coords {
            let (s, t) = (number(toks[at])?, number(toks[at + 1])?);
            uvs.extend_from_slice(&[s, v_from_file(t as f64)]);
        }
    }
    let mut faces = Faces::with_capacity(nf, 3 * nf);
    let mut face_colors: Vec<Option<[f32; 4]>> = Vec::new();
    let mut skipped = 0usize;
    for f in 0..nf {
        let Some((ln, toks)) = content(&mut lines) else {
            return Err(ErrorKind::malformed(
                "OFF",
                format!("the file ends after {f} of {nf} faces"),
            ));
        };
        let k = parse_i64(toks[0])
            .and_then(|k| usize::try_from(k).ok())
            .ok_or_else(|| {
                ErrorKind::syntax(
                    ln,
                    format!("face {f}: '{}' is not a corner count", show(toks[0])),
                )
            })?;
        if toks.len() < 1 + k {
            return Err(ErrorKind::syntax(
                ln,
                format!(
                    "face {f} announces {k} corners but lists {}",
                    toks.len() - 1
                ),
            ));
        }
        let start = faces.indices.len();
        for t in &toks[1..1 + k] {
            let v = parse_i64(t)
                .and_then(|v| u32::try_from(v).ok())
                .filter(|&v| (v as usize) < nv)
                .ok_or_else(|| {
                    ErrorKind::syntax(
                        ln,
                        format!(
                            "face {f}: vertex index '{}' is out of range ({nv} vertices)",
                            show(t)
                        ),
                    )
                })?;
            faces.indices.push(v);
        }
        if !crate::has_three_distinct(&faces.indices[start..]) {
            faces.indices.truncate(start);
            skipped += 1;
            continue;
        }
        let end = u32::try_from(faces.indices.len())
            .map_err(|_| ErrorKind::syntax(ln, "more face corners than wildlod holds (2³² − 1)"))?;
        faces.offsets.push(end);
        let rest = &toks[1 + k..];
        face_colors.push(match rest.len() {
            3 | 4 => Some(color(rest, ln)?),
            // A colormap index (1), nothing (0), or something we cannot
            // read as a color: no color.
            _ => None,
        });
    }
    if skipped > 0 {
        warnings.push(crate::skipped_faces_warning(skipped));
    }
    if faces.is_empty() {
        return Err(ErrorKind::malformed("OFF", "the file has no faces"));
    }
    let (positions, origin) = crate::far::relative(&exact, positions);
    let mut mesh = Mesh::from_polygons(positions, faces);
    let per_vertex = |values: Vec<f32>, components: u8, semantic: Semantic| Attribute {
        semantic,
        components,
        values,
        indices: mesh.faces.indices.clone(),
        format: ComponentFormat::F32,
    };
    let mut attributes = Vec::new();
    if layout.normals {
        attributes.push(per_vertex(normals, 3, Semantic::Normal));
    }
    if layout.tex_coords {
        attributes.push(per_vertex(uvs, 2, Semantic::TexCoord(0)));
    }
    if layout.colors {
        attributes.push(per_vertex(colors, color_components, Semantic::Color(0)));
        if face_colors.iter().any(Option::is_some) {
            warnings.push(
                "OFF faces carry colors as well as vertices: the vertex colors are kept".into(),
            );
        }
    } else if face_colors.iter().any(Option::is_some) {
        // Face colors become a per-corner stream: one value per face,
        // shared by its corners.
        let k: u8 = if face_colors.iter().flatten().any(|c| c[3] != 1.0) {
            4
        } else {
            3
        };
        let mut values = Vec::new();
        let mut indices = Vec::with_capacity(mesh.faces.corner_count());
        for (f, c) in face_colors.iter().enumerate() {
            let index = match c {
                Some(c) => {
                    values.extend_from_slice(&c[..k as usize]);
                    (values.len() / k as usize - 1) as u32
                }
                None => ABSENT,
            };
            indices.extend(std::iter::repeat(index).take(mesh.faces.face(f).len()));
        }
        attributes.push(Attribute {
            semantic: Semantic::Color(0),
            components: k,
            values,
            indices,
            format: ComponentFormat::F32,
        });
    }
    mesh.attributes = attributes;
    Ok((mesh, origin))
}

/// How colors are written.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ColorMode {
    None,
    /// Per vertex (`COFF`); vertices are split where corners disagree.
    Vertex,
    /// Per face: every face has one color over its corners and some
    /// position has several (the layout a face-colored OFF reads into).
    Face,
}

/// Writes the scene as one OFF mesh: every instance moved into world space
/// (OFF has no scene graph), polygons kept. Normals, the first UV set and
/// the first color set are written per vertex (a vertex is split where its
/// corners disagree), or colors per face when that is how they are laid
/// out.
pub(crate) fn write(scene: &Scene, path: &Path, files: &mut OutputFiles) -> Result<(), ErrorKind> {
    let (meshes, exact) = crate::far::world_meshes(scene);
    let stream = |m: &Mesh, s: &Semantic| m.attribute(s).filter(|a| a.components > 0).cloned();
    let has = |s: &Semantic| meshes.iter().any(|m| m.attribute(s).is_some());
    let with_normals = has(&Semantic::Normal);
    let with_uvs = has(&Semantic::TexCoord(0));
    let color_mode = if !has(&Semantic::Color(0)) {
        ColorMode::None
    } else if meshes
        .iter()
        .all(|m| match m.attribute(&Semantic::Color(0)) {
            Some(a) => per_face(m, a) && !per_position(m, a),
            None => true,
        })
    {
        ColorMode::Face
    } else {
        ColorMode::Vertex
    };
    let color_k = meshes
        .iter()
        .filter_map(|m| m.attribute(&Semantic::Color(0)))
        .map(|a| a.components.clamp(3, 4))
        .max()
        .unwrap_or(3);
    let mut header = String::new();
    if with_uvs {
        header.push_str("ST");
    }
    if color_mode == ColorMode::Vertex {
        header.push('C');
    }
    if with_normals {
        header.push('N');
    }
    header.push_str("OFF\n");
    let mut vertices = String::new();
    let mut face_lines = String::new();
    let (mut nv, mut nf) = (0u64, 0u64);
    for (m, exact) in meshes.iter().zip(&exact) {
        // Survey coordinates: placed in f64, to the digits f32 offsets
        // hold (`crate::far`).
        let decimals = exact_decimals(m.diagonal());
        let normals = stream(m, &Semantic::Normal);
        let uvs = stream(m, &Semantic::TexCoord(0));
        let colors = stream(m, &Semantic::Color(0));
        let vertex_colors = colors.as_ref().filter(|_| color_mode == ColorMode::Vertex);
        let value =
            |a: &Option<Attribute>, corner: usize| a.as_ref().map_or(ABSENT, |a| a.indices[corner]);
        // (position, normal, uv, color) value indices of every corner; a
        // distinct key is a written vertex.
        let keys: Vec<[u32; 4]> = (0..m.faces.corner_count())
            .map(|c| {
                [
                    m.faces.indices[c],
                    value(&normals, c),
                    value(&uvs, c),
                    vertex_colors.map_or(ABSENT, |a| a.indices[c]),
                ]
            })
            .collect();
        // Vertices in position order (then first use), so that a mesh no
        // stream splits keeps its vertex order.
        let mut order: Vec<usize> = Vec::new();
        let mut first: HashMap<[u32; 4], usize> = HashMap::new();
        for (c, k) in keys.iter().enumerate() {
            first.entry(*k).or_insert_with(|| {
                order.push(c);
                c
            });
        }
        order.sort_by_key(|&c| (keys[c][0], c));
        let mut ids: HashMap<[u32; 4], u64> = HashMap::with_capacity(order.len());
        for &c in &order {
            let key = keys[c];
            ids.insert(key, nv);
            nv += 1;
            let p = m
                .positions
                .get(key[0] as usize)
                .copied()
                .unwrap_or_default();
            match exact.as_ref().and_then(|e| e.get(key[0] as usize)) {
                Some(q) => {
                    let [x, y, z] = q.map(|c| trimmed(c, decimals));
                    let _ = write!(vertices, "{x} {y} {z}");
                }
                None => {
                    let _ = write!(vertices, "{} {} {}", p[0], p[1], p[2]);
                }
            }
            if with_normals {
                let n = get(&normals, key[1], [0.0, 0.0, 1.0, 0.0]);
                let _ = write!(vertices, " {} {} {}", n[0], n[1], n[2]);
            }
            if color_mode == ColorMode::Vertex {
                let c = get(&colors, key[3], [1.0; 4]);
                for x in &c[..color_k as usize] {
                    let _ = write!(vertices, " {x}");
                }
            }
            if with_uvs {
                let t = get(&uvs, key[2], [0.0; 4]);
                // OFF, like OBJ, puts v = 0 at the bottom.
                let _ = write!(vertices, " {} {}", t[0], text::v_to_text(t[1]));
            }
            vertices.push('\n');
        }
        for (f, face) in m.faces.iter().enumerate() {
            let _ = write!(face_lines, "{}", face.len());
            let start = m.faces.offsets[f] as usize;
            for key in &keys[start..start + face.len()] {
                let id = ids.get(key).copied().unwrap_or_default();
                let _ = write!(face_lines, " {id}");
            }
            if color_mode == ColorMode::Face {
                let first = m.faces.offsets[f] as usize;
                let c = colors
                    .as_ref()
                    .map(|a| a.indices[first])
                    .filter(|&i| i != ABSENT)
                    .map_or([1.0; 4], |i| get(&colors, i, [1.0; 4]));
                for x in &c[..color_k as usize] {
                    let _ = write!(face_lines, " {x}");
                }
            }
            face_lines.push('\n');
            nf += 1;
        }
    }
    let mut out = header;
    let _ = writeln!(out, "{nv} {nf} 0");
    out.push_str(&vertices);
    out.push_str(&face_lines);
    files.add(path, out.into_bytes())?;
    warn_dropped(scene, files);
    Ok(())
}

/// Value `i` of a stream, padded to four components with `pad`.
fn get(a: &Option<Attribute>, i: u32, pad: [f32; 4]) -> [f32; 4] {
    let mut out = pad;
    if let Some(a) = a {
        if i != ABSENT && (i as usize) < a.value_count() {
            for (o, x) in out.iter_mut().zip(a.value(i)) {
                *o = *x;
            }
        }
    }
    out
}

/// Whether every face's corners share one value of `a`.
fn per_face(m: &Mesh, a: &Attribute) -> bool {
    (0..m.faces.len()).all(|f| {
        let r = m.faces.corner_range(f);
        let first = a.value_of(r.start);
        r.clone().all(|c| a.value_of(c) == first)
    })
}

/// Whether every position's corners share one value of `a`.
fn per_position(m: &Mesh, a: &Attribute) -> bool {
    let mut seen: HashMap<u32, Option<&[f32]>> = HashMap::new();
    m.faces.indices.iter().enumerate().all(|(c, &v)| {
        let x = a.value_of(c);
        *seen.entry(v).or_insert(x) == x
    })
}

trait ValueOf {
    fn value_of(&self, corner: usize) -> Option<&[f32]>;
}

impl ValueOf for Attribute {
    /// A corner's value (by content, not index: two equal values are one
    /// color).
    fn value_of(&self, corner: usize) -> Option<&[f32]> {
        match self.indices.get(corner).copied() {
            Some(i) if i != ABSENT && (i as usize) < self.value_count() => Some(self.value(i)),
            _ => None,
        }
    }
}

fn warn_dropped(scene: &Scene, files: &mut OutputFiles) {
    let kept = [Semantic::Normal, Semantic::TexCoord(0), Semantic::Color(0)];
    if scene
        .meshes
        .iter()
        .any(|m| m.attributes.iter().any(|a| !kept.contains(&a.semantic)) || m.skinning.is_some())
    {
        files.warn(
            "OFF holds normals, one UV set and one color set; other streams and skin weights are dropped",
        );
    }
    if !scene.materials.is_empty() || scene.meshes.iter().any(|m| m.parts.len() > 1) {
        files.warn("OFF holds no parts or materials; all faces are written as one mesh");
    }
    if !scene.animations.is_empty() || !scene.skins.is_empty() {
        files.warn("OFF holds no skins or animations; dropped");
    }
}
