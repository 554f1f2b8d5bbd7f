//! PLY body → [`Mesh`]. Per-vertex properties become per-corner streams
//! indexed like the positions; every other element is skipped. Texture
//! v is flipped to the model's top-left origin (see `v_from_file`).

use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Scene, Semantic};

use super::header::{self, Element, Encoding, Kind, Scalar};
use crate::obj::text::{is_space, parse_f32, parse_i64, show, v_from_file};
use crate::ErrorKind;

/// What went wrong inside one element instance; the caller adds the
/// element name and index.
enum Fault {
    End,
    Bad(String),
}

impl Fault {
    fn at(self, element: &Element, index: u64) -> ErrorKind {
        let msg = match self {
            Fault::End => "the file ends here (truncated body)".to_string(),
            Fault::Bad(m) => m,
        };
        ErrorKind::malformed(element.at(index), msg)
    }
}

/// The body, read value by value in any of the three encodings.
struct Body<'a> {
    data: &'a [u8],
    pos: usize,
    encoding: Encoding,
}

impl Body<'_> {
    #[inline]
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], Fault> {
        let b: [u8; N] = self
            .data
            .get(self.pos..self.pos + N)
            .and_then(|s| s.try_into().ok())
            .ok_or(Fault::End)?;
        self.pos += N;
        Ok(match self.encoding {
            Encoding::BinaryBigEndian => {
                let mut r = b;
                r.reverse();
                r
            }
            _ => b,
        })
    }

    #[inline]
    fn token(&mut self) -> Result<&[u8], Fault> {
        while self.data.get(self.pos).is_some_and(|&b| is_space(b)) {
            self.pos += 1;
        }
        let start = self.pos;
        while self.data.get(self.pos).is_some_and(|&b| !is_space(b)) {
            self.pos += 1;
        }
        if self.pos == start {
            return Err(Fault::End);
        }
        Ok(&self.data[start..self.pos])
    }

    /// One value as `f64` (every PLY type fits exactly). ASCII `float`s
    /// are parsed as `f32` directly so that they are not rounded twice.
    #[inline]
    fn value(&mut self, ty: Scalar) -> Result<f64, Fault> {
        if self.encoding == Encoding::Ascii {
            let tok = self.token()?;
            return if ty.is_integer() {
                // Some writers print integers as "255.000000": accepted when
                // the value is integral.
                let v = parse_i64(tok)
                    .map(|i| i as f64)
                    .or_else(|| {
                        crate::obj::text::parse_f64(tok)
                            .ok()
                            .filter(|x| x.fract() == 0.0)
                    })
                    .ok_or_else(|| Fault::Bad(format!("'{}' is not an integer", show(tok))))?;
                let (lo, hi) = ty.range();
                if v < lo || v > hi {
                    return Err(Fault::Bad(format!("{v} does not fit the type {ty:?}")));
                }
                Ok(v)
            } else if ty == Scalar::F32 {
                parse_f32(tok).map(f64::from).map_err(Fault::Bad)
            } else {
                crate::obj::text::parse_f64(tok).map_err(Fault::Bad)
            };
        }
        // Little-endian bytes after `bytes` (big-endian input is reversed).
        Ok(match ty {
            Scalar::I8 => i8::from_le_bytes(self.bytes()?) as f64,
            Scalar::U8 => u8::from_le_bytes(self.bytes()?) as f64,
            Scalar::I16 => i16::from_le_bytes(self.bytes()?) as f64,
            Scalar::U16 => u16::from_le_bytes(self.bytes()?) as f64,
            Scalar::I32 => i32::from_le_bytes(self.bytes()?) as f64,
            Scalar::U32 => u32::from_le_bytes(self.bytes()?) as f64,
            Scalar::F32 => f32::from_le_bytes(self.bytes()?) as f64,
            Scalar::F64 => f64::from_le_bytes(self.bytes()?),
        })
    }

    /// A position coordinate: its value as [`Body::value`] reads it, and
    /// in f64 as the file writes it (for an ASCII `float`, its digits
    /// parsed in f64), for positions far from the origin.
    #[inline]
    fn value_and_digits(&mut self, ty: Scalar) -> Result<(f64, f64), Fault> {
        if self.encoding == Encoding::Ascii && matches!(ty, Scalar::F32) {
            let tok = self.token()?;
            let v = parse_f32(tok).map_err(Fault::Bad)?;
            let wide = crate::obj::text::parse_f64(tok).map_err(Fault::Bad)?;
            return Ok((f64::from(v), wide));
        }
        self.value(ty).map(|v| (v, v))
    }

    /// A list length, checked against what is left of the file before the
    /// caller loops over it.
    fn list_len(&mut self, count: Scalar, item: Scalar) -> Result<usize, Fault> {
        let n = self.value(count)?;
        if n < 0.0 {
            return Err(Fault::Bad(format!("negative list length {n}")));
        }
        let n = n as u64;
        let left = self.data.len().saturating_sub(self.pos) as u64;
        let min = match self.encoding {
            Encoding::Ascii => 2,
            _ => item.size() as u64,
        };
        if n.saturating_mul(min) > left + 1 {
            return Err(Fault::End);
        }
        Ok(n as usize)
    }

    fn skip_property(&mut self, kind: Kind) -> Result<(), Fault> {
        match kind {
            Kind::Scalar(ty) => self.skip(ty, 1),
            Kind::List { count, item } => {
                let n = self.list_len(count, item)?;
                self.skip(item, n)
            }
        }
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Fault> {
        if self.encoding == Encoding::Ascii {
            for _ in 0..n {
                self.token()?;
            }
            return Ok(());
        }
        let end = self.pos.saturating_add(n.saturating_mul(ty.size()));
        if end > self.data.len() {
            return Err(Fault::End);
        }
        self.pos = end;
        Ok(())
    }
}

/// What a vertex property means to us.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Position(usize),
    Normal(usize),
    Color(usize),
    Uv(usize),
    Other,
}

fn role(name: &str) -> Role {
    match name {
        "x" => Role::Position(0),
        "y" => Role::Position(1),
        "z" => Role::Position(2),
        "nx" => Role::Normal(0),
        "ny" => Role::Normal(1),
        "nz" => Role::Normal(2),
        "red" | "r" | "diffuse_red" => Role::Color(0),
        "green" | "g" | "diffuse_green" => Role::Color(1),
        "blue" | "b" | "diffuse_blue" => Role::Color(2),
        "alpha" | "a" | "diffuse_alpha" => Role::Color(3),
        "s" | "u" | "texture_u" | "texture_s" => Role::Uv(0),
        "t" | "v" | "texture_v" | "texture_t" => Role::Uv(1),
        _ => Role::Other,
    }
}

/// Reads a PLY file (ASCII or binary, format 1.0).
pub(crate) fn read(data: &[u8], warnings: &mut Vec<String>) -> Result<Scene, ErrorKind> {
    let h = header::parse(data)?;
    let vertex = h
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| ErrorKind::malformed("PLY header", "no 'vertex' element"))?;
    let face = h.elements.iter().position(|e| e.name == "face");
    let mut body = Body {
        data,
        pos: h.body,
        encoding: h.encoding,
    };
    let vertex_count = h.elements[vertex].count;
    let mut verts = None;
    let mut faces = None;
    for (i, e) in h.elements.iter().enumerate() {
        if i == vertex && verts.is_none() {
            verts = Some(read_vertices(&mut body, e)?);
        } else if Some(i) == face && faces.is_none() {
            faces = Some(read_faces(&mut body, e, vertex_count)?);
        } else {
            skip_element(&mut body, e)?;
        }
    }
    let v = verts.unwrap_or_default();
    if let Some(f) = faces.as_ref().filter(|f| f.skipped > 0) {
        warnings.push(crate::skipped_faces_warning(f.skipped));
    }
    let f = match faces {
        Some(f) if !f.faces.is_empty() => f,
        _ => return Err(ErrorKind::malformed("PLY", "the file has no faces")),
    };
    let origin = v.origin;
    let mut scene = Scene::from_mesh(build(v, f));
    if let Some(o) = origin {
        // Positions relative to a far point: the node puts them back.
        scene.nodes[0].matrix[12..15].copy_from_slice(&o);
    }
    Ok(scene)
}

#[derive(Default)]
struct Vertices {
    positions: Vec<[f32; 3]>,
    /// Where `positions` are relative to, when the file's coordinates lie
    /// so far from the origin that f32 would round them visibly
    /// ([`crate::far::far_origin`]).
    origin: Option<[f32; 3]>,
    normals: Option<Vec<f32>>,
    colors: Option<(Vec<f32>, u8, ComponentFormat)>,
    uvs: Option<Vec<f32>>,
}

fn read_vertices(body: &mut Body, e: &Element) -> Result<Vertices, ErrorKind> {
    let roles: Vec<Role> = e.properties.iter().map(|p| role(&p.name)).collect();
    let has = |r: Role| {
        e.properties
            .iter()
            .zip(&roles)
            .any(|(p, &q)| q == r && matches!(p.kind, Kind::Scalar(_)))
    };
    if !(0..3).all(|k| has(Role::Position(k))) {
        return Err(ErrorKind::malformed(
            "PLY element 'vertex'",
            "no x, y and z properties",
        ));
    }
    let with_normals = (0..3).all(|k| has(Role::Normal(k)));
    let with_colors = (0..3).all(|k| has(Role::Color(k)));
    let with_alpha = with_colors && has(Role::Color(3));
    let with_uvs = has(Role::Uv(0)) && has(Role::Uv(1));
    // Integer colors are normalized by their type's maximum (uchar → /255).
    let color_type = e
        .properties
        .iter()
        .zip(&roles)
        .find_map(|(p, r)| match (r, p.kind) {
            (Role::Color(0), Kind::Scalar(t)) => Some(t),
            _ => None,
        });
    let scale = |t: Scalar| match t {
        Scalar::F32 | Scalar::F64 => 1.0,
        t => t.range().1,
    };
    let n = e.count as usize;
    let comps = if with_alpha { 4 } else { 3 };
    let mut out = Vertices {
        positions: Vec::with_capacity(n),
        normals: with_normals.then(|| Vec::with_capacity(3 * n)),
        colors: with_colors.then(|| {
            let format = match color_type {
                Some(Scalar::U8) => ComponentFormat::U8Norm,
                Some(Scalar::U16) => ComponentFormat::U16Norm,
                _ => ComponentFormat::F32,
            };
            (Vec::with_capacity(comps as usize * n), comps, format)
        }),
        uvs: with_uvs.then(|| Vec::with_capacity(2 * n)),
        origin: None,
    };
    // Positions as the file writes them, before f32 rounds them: `double`
    // properties, or the digits of an ASCII `float`.
    let mut exact: Vec<[f64; 3]> = Vec::with_capacity(n);
    for i in 0..e.count {
        let mut p = [0f64; 3];
        let mut p_exact = [0f64; 3];
        let mut nrm = [0f64; 3];
        let mut col = [0f64, 0.0, 0.0, 1.0];
        let mut uv = [0f64; 2];
        for (prop, &r) in e.properties.iter().zip(&roles) {
            let Kind::Scalar(ty) = prop.kind else {
                body.skip_property(prop.kind).map_err(|f| f.at(e, i))?;
                continue;
            };
            let (v, v_exact) = match r {
                Role::Position(_) => body.value_and_digits(ty),
                _ => body.value(ty).map(|v| (v, v)),
            }
            .map_err(|f| f.at(e, i))?;
            if !(v.is_finite() && v_exact.is_finite()) {
                return Err(ErrorKind::malformed(
                    e.at(i),
                    format!("property '{}' is not finite ({v})", prop.name),
                ));
            }
            match r {
                Role::Position(k) => {
                    p[k] = v;
                    p_exact[k] = v_exact;
                }
                Role::Normal(k) => nrm[k] = v,
                Role::Color(k) => col[k] = v / scale(ty),
                Role::Uv(k) => uv[k] = v,
                Role::Other => {}
            }
        }
        let p32 = p.map(|c| c as f32);
        if !p32.iter().all(|c| c.is_finite()) {
            return Err(ErrorKind::malformed(
                e.at(i),
                format!("position {p:?} does not fit a 32-bit float"),
            ));
        }
        out.positions.push(p32);
        exact.push(p_exact);
        if let Some(ns) = &mut out.normals {
            ns.extend(nrm.map(|c| c as f32));
        }
        if let Some((cs, k, _)) = &mut out.colors {
            cs.extend(col[..*k as usize].iter().map(|&c| c as f32));
        }
        if let Some(us) = &mut out.uvs {
            let t = v_from_file(uv[1]);
            if !t.is_finite() {
                return Err(ErrorKind::malformed(
                    e.at(i),
                    "texture coordinate v is not finite",
                ));
            }
            us.extend([uv[0] as f32, t]);
        }
    }
    let positions = std::mem::take(&mut out.positions);
    (out.positions, out.origin) = crate::far::relative(&exact, positions);
    Ok(out)
}

struct FaceData {
    faces: Faces,
    /// Per-corner UVs from a face `texcoord` list (MeshLab's wedge UVs).
    corner_uvs: Option<Vec<f32>>,
    /// Faces skipped for having fewer than three distinct vertices.
    skipped: usize,
}

fn read_faces(body: &mut Body, e: &Element, vertex_count: u64) -> Result<FaceData, ErrorKind> {
    let list = e.properties.iter().position(|p| {
        matches!(p.kind, Kind::List { .. })
            && (p.name == "vertex_indices" || p.name == "vertex_index")
    });
    let Some(list) = list else {
        return Err(ErrorKind::malformed(
            "PLY element 'face'",
            "no 'vertex_indices' list property",
        ));
    };
    let texcoord = e
        .properties
        .iter()
        .position(|p| matches!(p.kind, Kind::List { .. }) && p.name == "texcoord");
    // Room for triangles, but never more than the rest of the file can
    // encode: the header check allows one byte per face, which would
    // otherwise reserve twelve per byte of file for corners.
    let left = body.data.len().saturating_sub(body.pos);
    let (count_size, item_size) = match (body.encoding, e.properties[list].kind) {
        (Encoding::Ascii, _) => (2, 2),
        (_, Kind::List { count, item }) => (count.size(), item.size()),
        (_, Kind::Scalar(_)) => (1, 1),
    };
    let n = (e.count as usize).min(left / (count_size + 3 * item_size));
    let mut faces = Faces::with_capacity(n, (3 * n).min(left / item_size));
    let mut corner_uvs: Option<Vec<f32>> = texcoord.map(|_| Vec::new());
    let mut uv_scratch = Vec::new();
    let mut skipped = 0usize;
    for i in 0..e.count {
        let start = faces.indices.len();
        let mut arity = None;
        let mut uv_len = None;
        for (j, prop) in e.properties.iter().enumerate() {
            match prop.kind {
                Kind::List { count, item } if j == list => {
                    let k = body.list_len(count, item).map_err(|f| f.at(e, i))?;
                    for _ in 0..k {
                        let v = body.value(item).map_err(|f| f.at(e, i))?;
                        if v.fract() != 0.0 || v < 0.0 || v >= vertex_count as f64 {
                            return Err(ErrorKind::malformed(
                                e.at(i),
                                format!(
                                    "vertex index {v} is out of range ({vertex_count} vertices)"
                                ),
                            ));
                        }
                        faces.indices.push(v as u32);
                    }
                    arity = Some(k);
                }
                Kind::List { count, item } if Some(j) == texcoord => {
                    let k = body.list_len(count, item).map_err(|f| f.at(e, i))?;
                    uv_scratch.clear();
                    for j in 0..k {
                        let x = body.value(item).map_err(|f| f.at(e, i))?;
                        uv_scratch.push(if j % 2 == 1 { v_from_file(x) } else { x as f32 });
                    }
                    uv_len = Some(k);
                }
                kind => body.skip_property(kind).map_err(|f| f.at(e, i))?,
            }
        }
        let arity = arity.unwrap_or(0);
        if !crate::has_three_distinct(&faces.indices[start..]) {
            // No area: skipped and counted (see `has_three_distinct`).
            faces.indices.truncate(start);
            skipped += 1;
            continue;
        }
        let end = u32::try_from(faces.indices.len()).map_err(|_| {
            ErrorKind::malformed(e.at(i), "more corners than wildlod holds (2³² − 1)")
        })?;
        faces.offsets.push(end);
        if let Some(uvs) = &mut corner_uvs {
            if uv_len == Some(2 * arity) && uv_scratch.iter().all(|c| c.is_finite()) {
                uvs.extend_from_slice(&uv_scratch);
            } else {
                // Wedge UVs that do not match the face are unusable for the
                // whole mesh; vertex UVs (if any) still apply.
                corner_uvs = None;
            }
        }
    }
    Ok(FaceData {
        faces,
        corner_uvs,
        skipped,
    })
}

fn skip_element(body: &mut Body, e: &Element) -> Result<(), ErrorKind> {
    if e.properties.is_empty() {
        return Ok(());
    }
    let fixed: Option<usize> = e.properties.iter().try_fold(0usize, |s, p| match p.kind {
        Kind::Scalar(t) => Some(s + t.size()),
        Kind::List { .. } => None,
    });
    if let (Some(size), true) = (fixed, body.encoding != Encoding::Ascii) {
        // Fixed-size instances are skipped at once; a short body is
        // reported at the first instance that does not fit.
        let fits = (body.data.len().saturating_sub(body.pos) / size.max(1)) as u64;
        let bytes = (e.count as usize).saturating_mul(size);
        return body.skip(Scalar::U8, bytes).map_err(|f| f.at(e, fits));
    }
    for i in 0..e.count {
        for p in &e.properties {
            body.skip_property(p.kind).map_err(|f| f.at(e, i))?;
        }
    }
    Ok(())
}

fn build(v: Vertices, f: FaceData) -> Mesh {
    let mut mesh = Mesh::from_polygons(v.positions, f.faces);
    let per_vertex = |semantic, components, values, format| Attribute {
        semantic,
        components,
        values,
        indices: mesh.faces.indices.clone(),
        format,
    };
    let mut attributes = Vec::new();
    match (v.uvs, f.corner_uvs) {
        (Some(uvs), _) => attributes.push(per_vertex(
            Semantic::TexCoord(0),
            2,
            uvs,
            ComponentFormat::F32,
        )),
        (None, Some(uvs)) => attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            indices: (0..mesh.faces.indices.len() as u32).collect(),
            values: uvs,
            format: ComponentFormat::F32,
        }),
        (None, None) => {}
    }
    if let Some(n) = v.normals {
        attributes.push(per_vertex(Semantic::Normal, 3, n, ComponentFormat::F32));
    }
    if let Some((c, k, format)) = v.colors {
        attributes.push(per_vertex(Semantic::Color(0), k, c, format));
    }
    mesh.attributes = attributes;
    mesh
}
