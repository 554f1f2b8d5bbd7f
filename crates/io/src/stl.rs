//! STL, ASCII and binary.
//!
//! STL is a triangle soup: every triangle is read with three private
//! positions (the simplifier welds equal positions; see
//! `wildlod_mesh::weld`). Facet normals are derived data and not kept; the
//! writer recomputes them from the triangles.

use std::collections::HashMap;
use std::path::Path;

use wildlod_mesh::shapes::triangulate;
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{Faces, Mesh, Part, Scene};

use crate::obj::text::{parse_f32, show};
use crate::{ErrorKind, OutputFiles};

/// Bytes before the first triangle of a binary STL: an 80-byte header and
/// the triangle count.
const HEADER: usize = 84;
/// Bytes per binary triangle: normal, three vertices, attribute word.
const TRIANGLE: usize = 50;

/// Reads an STL file, ASCII or binary.
pub(crate) fn read(path: &Path, data: &[u8]) -> Result<Scene, ErrorKind> {
    let mut mesh = read_mesh(data)?;
    mesh.name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Scene::from_mesh(mesh))
}

fn read_mesh(data: &[u8]) -> Result<Mesh, ErrorKind> {
    let declared = data
        .get(80..HEADER)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes);
    // The size test comes first: many binary exporters start the header
    // with "solid" too, and only the size tells them apart.
    if let Some(n) = declared {
        if HEADER as u64 + TRIANGLE as u64 * n as u64 == data.len() as u64 {
            return read_binary(data);
        }
    }
    let start = data
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(data.len());
    let looks_ascii = data[start..]
        .get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"));
    if !looks_ascii {
        return read_binary(data);
    }
    match read_ascii(data) {
        Ok(m) => Ok(m),
        // A binary file with a "solid" header and padding after its
        // triangles: fine as binary, so read it that way.
        Err(e) => match declared {
            Some(n)
                if n > 0
                    && HEADER as u64 + TRIANGLE as u64 * n as u64 <= data.len() as u64
                    && data.contains(&0) =>
            {
                read_binary(data)
            }
            _ => Err(e),
        },
    }
}

fn read_binary(data: &[u8]) -> Result<Mesh, ErrorKind> {
    let Some(count) = data.get(80..HEADER) else {
        return Err(ErrorKind::malformed(
            "STL header",
            format!(
                "{} bytes is too short for a binary STL (84-byte header) and the file does not start with 'solid'",
                data.len()
            ),
        ));
    };
    let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as u64;
    let room = (data.len() - HEADER) as u64 / TRIANGLE as u64;
    if n > room {
        // One triangle short: a cut-off file. More: a count no file of this
        // size can hold, refused before allocating.
        return Err(if n == room + 1 {
            ErrorKind::malformed(
                format!("STL triangle {room}"),
                format!(
                    "the file ends inside this triangle; the header declares {n} (truncated file?)"
                ),
            )
        } else {
            ErrorKind::ImplausibleCount {
                element: "STL header triangle count".into(),
                count: n,
                max: room,
            }
        });
    }
    if n == 0 {
        return Err(ErrorKind::malformed("STL", "the file has no triangles"));
    }
    let n = n as usize;
    let mut positions = Vec::with_capacity(3 * n);
    let body = &data[HEADER..HEADER + n * TRIANGLE];
    for (t, tri) in body.chunks_exact(TRIANGLE).enumerate() {
        // Skip the 12-byte facet normal; the attribute word is ignored.
        for k in 0..3 {
            let mut p = [0f32; 3];
            for (c, v) in p.iter_mut().enumerate() {
                let o = 12 + 12 * k + 4 * c;
                *v = f32::from_le_bytes([tri[o], tri[o + 1], tri[o + 2], tri[o + 3]]);
            }
            if !p.iter().all(|c| c.is_finite()) {
                return Err(ErrorKind::malformed(
                    format!("STL triangle {t}"),
                    format!("vertex {k} has a non-finite coordinate {p:?}"),
                ));
            }
            positions.push(p);
        }
    }
    let indices: Vec<u32> = (0..positions.len() as u32).collect();
    Ok(Mesh::from_triangles(positions, &indices))
}

/// Tokens of an ASCII STL with their line numbers.
struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    /// Line of the last token, where an unexpected end of file is reported.
    last: usize,
}

impl<'a> Cursor<'a> {
    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        while let Some(&b) = self.data.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self
            .data
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        if self.pos == start {
            return None;
        }
        self.last = self.line;
        Some((&self.data[start..self.pos], self.line))
    }

    /// The rest of the current line (a solid's name).
    fn rest_of_line(&mut self) -> &'a [u8] {
        let start = self.pos;
        while self.data.get(self.pos).is_some_and(|&b| b != b'\n') {
            self.pos += 1;
        }
        &self.data[start..self.pos]
    }

    /// The next token, which must be `word` (case-insensitive).
    fn expect(&mut self, word: &str, context: &str) -> Result<(), ErrorKind> {
        match self.next() {
            Some((t, _)) if t.eq_ignore_ascii_case(word.as_bytes()) => Ok(()),
            Some((t, ln)) => Err(ErrorKind::syntax(
                ln,
                format!("expected '{word}' {context}, found '{}'", show(t)),
            )),
            None => Err(ErrorKind::syntax(
                self.last,
                format!("the file ends where '{word}' {context} should be"),
            )),
        }
    }

    fn number(&mut self, what: &str) -> Result<f32, ErrorKind> {
        match self.next() {
            Some((t, ln)) => {
                parse_f32(t).map_err(|e| ErrorKind::syntax(ln, format!("{what}: {e}")))
            }
            None => Err(ErrorKind::syntax(
                self.last,
                format!("the file ends inside a {what}"),
            )),
        }
    }
}

fn read_ascii(data: &[u8]) -> Result<Mesh, ErrorKind> {
    let mut cur = Cursor {
        data,
        pos: 0,
        line: 1,
        last: 1,
    };
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut faces = Faces::new();
    let mut face_parts = Vec::new();
    let mut parts: Vec<Part> = Vec::new();
    let mut part_ids: HashMap<String, u32> = HashMap::new();
    // A `solid` met where a facet could be starts the next solid: some
    // exporters omit `endsolid` between blocks.
    let mut pending_solid = false;
    loop {
        if !pending_solid {
            let Some((tok, ln)) = cur.next() else { break };
            if !tok.eq_ignore_ascii_case(b"solid") {
                return Err(ErrorKind::syntax(
                    ln,
                    format!("expected 'solid', found '{}'", show(tok)),
                ));
            }
        }
        pending_solid = false;
        let name = crate::obj::text::name(cur.rest_of_line());
        let next = parts.len() as u32;
        let part = *part_ids.entry(name.clone()).or_insert(next);
        if part == next {
            parts.push(Part {
                name,
                material: None,
            });
        }
        // A missing `endsolid` at the very end loses nothing.
        while let Some((tok, ln)) = cur.next() {
            if tok.eq_ignore_ascii_case(b"endsolid") {
                cur.rest_of_line();
                break;
            }
            if tok.eq_ignore_ascii_case(b"solid") {
                pending_solid = true;
                break;
            }
            if !tok.eq_ignore_ascii_case(b"facet") {
                return Err(ErrorKind::syntax(
                    ln,
                    format!("expected 'facet' or 'endsolid', found '{}'", show(tok)),
                ));
            }
            let facet_line = ln;
            match cur.next() {
                // The normal is derived data: its three values are skipped
                // unchecked (degenerate facets often carry NaN there).
                Some((t, _)) if t.eq_ignore_ascii_case(b"normal") => {
                    for _ in 0..3 {
                        cur.next();
                    }
                    cur.expect("outer", "after the facet normal")?;
                }
                Some((t, _)) if t.eq_ignore_ascii_case(b"outer") => {}
                Some((t, ln)) => {
                    return Err(ErrorKind::syntax(
                        ln,
                        format!("expected 'normal' or 'outer', found '{}'", show(t)),
                    ))
                }
                None => return Err(ErrorKind::syntax(ln, "the file ends inside a facet")),
            }
            cur.expect("loop", "after 'outer'")?;
            let first = positions.len();
            loop {
                match cur.next() {
                    Some((t, _)) if t.eq_ignore_ascii_case(b"vertex") => {
                        let p = [
                            cur.number("vertex")?,
                            cur.number("vertex")?,
                            cur.number("vertex")?,
                        ];
                        positions.push(p);
                    }
                    Some((t, _)) if t.eq_ignore_ascii_case(b"endloop") => break,
                    Some((t, ln)) => {
                        return Err(ErrorKind::syntax(
                            ln,
                            format!("expected 'vertex' or 'endloop', found '{}'", show(t)),
                        ))
                    }
                    None => {
                        return Err(ErrorKind::syntax(cur.last, "the file ends inside a facet"))
                    }
                }
            }
            cur.expect("endfacet", "after 'endloop'")?;
            let arity = positions.len() - first;
            if arity < 3 {
                return Err(ErrorKind::syntax(
                    facet_line,
                    format!("a facet needs 3 vertices, found {arity}"),
                ));
            }
            let end = u32::try_from(positions.len()).map_err(|_| {
                ErrorKind::syntax(facet_line, "more vertices than wildlod holds (2³² − 1)")
            })?;
            // Loops with more than 3 vertices are polygons: kept as such.
            faces.indices.extend(first as u32..end);
            faces.offsets.push(end);
            face_parts.push(part);
        }
    }
    if faces.is_empty() {
        return Err(ErrorKind::malformed("STL", "the file has no facets"));
    }
    Ok(Mesh {
        name: String::new(),
        positions,
        faces,
        face_parts,
        parts,
        attributes: Vec::new(),
        skinning: None,
    })
}

/// Writes a binary STL: every mesh instance moved by its world matrix,
/// polygons triangulated (`shapes::triangulate`: a fan up to 32 corners
/// where it covers the polygon, inner diagonals otherwise),
/// facet normals computed from the triangles.
pub(crate) fn write(scene: &Scene, path: &Path, files: &mut OutputFiles) -> Result<(), ErrorKind> {
    let instances = scene.instances();
    let meshes: Vec<&Mesh> = instances
        .iter()
        .filter_map(|(m, _)| scene.meshes.get(*m as usize))
        .collect();
    let total: u64 = meshes
        .iter()
        .map(|m| m.faces.triangulated_count() as u64)
        .sum();
    let count = u32::try_from(total).map_err(|_| {
        ErrorKind::Unsupported(format!(
            "{total} triangles do not fit a binary STL (at most 2³² − 1)"
        ))
    })?;
    let mut out = Vec::with_capacity(HEADER + TRIANGLE * count as usize);
    let mut header = [b' '; 80];
    // Not "solid…": readers that sniff the first bytes would take it for ASCII.
    let title = b"binary STL written by wildlod";
    header[..title.len()].copy_from_slice(title);
    out.extend_from_slice(&header);
    out.extend_from_slice(&count.to_le_bytes());
    for (m, matrix) in &instances {
        let Some(mesh) = scene.meshes.get(*m as usize) else {
            continue;
        };
        let mut moved = transformed(mesh, matrix);
        // Only positions survive in STL; triangulating streams is wasted work.
        moved.attributes.clear();
        moved.skinning = None;
        let tri = triangulate(&moved);
        for face in tri.faces.iter() {
            let p = [0, 1, 2].map(|k| {
                face.get(k)
                    .and_then(|&v| tri.positions.get(v as usize))
                    .copied()
                    .unwrap_or_default()
            });
            for c in facet_normal(&p) {
                out.extend_from_slice(&c.to_le_bytes());
            }
            for v in &p {
                for c in v {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            out.extend_from_slice(&0u16.to_le_bytes());
        }
    }
    files.add(path, out)?;
    warn_dropped(scene, &meshes, files);
    // Binary STL holds 32-bit floats only: survey coordinates round.
    let far = instances.iter().find_map(|(m, matrix)| {
        let mesh = scene.meshes.get(*m as usize)?;
        crate::far::far_placement(mesh, matrix)?;
        let reach = matrix[12..15].iter().fold(0.0f32, |a, t| a.max(t.abs()));
        Some((reach, mesh.diagonal()))
    });
    if let Some((reach, size)) = far {
        let step = f64::from(reach) * f64::from(f32::EPSILON) / 2.0;
        files.warn(format!(
            "the model lies {reach:.0} units from the origin, where STL's 32-bit floats round positions by up to {step:.2e} (a mesh is {size:.3e} across); write OBJ, PLY, OFF or glTF to keep them"
        ));
    }
    Ok(())
}

/// Unit normal of a triangle, or zero when it is degenerate.
fn facet_normal(p: &[[f32; 3]; 3]) -> [f32; 3] {
    let d = |a: [f32; 3], b: [f32; 3]| [0, 1, 2].map(|k| b[k] as f64 - a[k] as f64);
    let (u, v) = (d(p[0], p[1]), d(p[0], p[2]));
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|c| (c / len) as f32)
    } else {
        [0.0; 3]
    }
}

fn warn_dropped(scene: &Scene, meshes: &[&Mesh], files: &mut OutputFiles) {
    let parts: usize = meshes.iter().map(|m| m.parts.len()).sum();
    if parts > 1
        || meshes
            .iter()
            .any(|m| m.parts.iter().any(|p| p.material.is_some()))
    {
        files.warn("binary STL holds no parts or materials; all faces are written as one solid");
    }
    if meshes
        .iter()
        .any(|m| !m.attributes.is_empty() || m.skinning.is_some())
    {
        files.warn("STL holds no vertex attributes (UVs, normals, colors, skin weights); dropped");
    }
    if !scene.animations.is_empty() || !scene.skins.is_empty() {
        files.warn("STL holds no skins or animations; dropped");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_triangle_gets_a_zero_normal() {
        assert_eq!(facet_normal(&[[1.0; 3]; 3]), [0.0; 3]);
        let n = facet_normal(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(n, [0.0, 0.0, 1.0]);
    }
}
