//! Scenes generated in code that are *unlike* the corpus: an architectural
//! export, a filleted CAD part, a flat mixed-arity tiling, a city block, a
//! skinned and animated tube, a terrain with far outliers, a texture atlas
//! of many small islands, a double-sided sheet, a sky dome over small
//! parts, a blend-shape rig, a tree of leaf cards, a chain-link fence and
//! a wall with decals.
//!
//! Each generator is deterministic (the same scene, and the same bytes
//! when written, on every run and machine), returns a [`Scene`] that
//! passes [`Scene::validate`], and says in its documentation what it is,
//! how large it is and what it stresses. Conventions are glTF's: y up
//! (except the tiling, which lies in z = 0), metres, UV `v = 0` at the top
//! of the image.
//!
//! Equal positions are stored once, and so are equal attribute values
//! (normals only within one B-rep face for the CAD part): the way exporters index
//! their vertices.

use std::collections::HashMap;
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, PI, TAU};

use glam::{DVec2, DVec3};
use wildlod_mesh::{
    AlphaMode, Animation, Attribute, ComponentFormat, Faces, ImageSource, Interpolation, Material,
    Mesh, Node, Part, Scene, Semantic, Skin, Skinning, Texture, TextureRef, Track, TrackPath,
    ABSENT, IDENTITY,
};

use crate::SplitMix64;

// ---------------------------------------------------------------------------
// Building blocks

/// `-0.0` as `0.0`: keys on bits must not tell the two apart.
fn canonical(x: f32) -> f32 {
    if x == 0.0 {
        0.0
    } else {
        x
    }
}

/// A per-corner stream being built: values stored once per (group, bits).
#[derive(Default)]
struct Stream<const N: usize> {
    values: Vec<f32>,
    ids: HashMap<(u32, [u32; N]), u32>,
    indices: Vec<u32>,
    used: bool,
}

impl<const N: usize> Stream<N> {
    fn push(&mut self, group: u32, v: Option<[f32; N]>) {
        let i = match v {
            None => ABSENT,
            Some(v) => {
                self.used = true;
                let v = v.map(canonical);
                let Stream { values, ids, .. } = self;
                *ids.entry((group, v.map(f32::to_bits))).or_insert_with(|| {
                    values.extend_from_slice(&v);
                    (values.len() / N - 1) as u32
                })
            }
        };
        self.indices.push(i);
    }

    fn attribute(self, semantic: Semantic) -> Option<Attribute> {
        self.used.then_some(Attribute {
            semantic,
            components: N as u8,
            values: self.values,
            indices: self.indices,
            format: ComponentFormat::F32,
        })
    }
}

/// One corner of a face being built.
#[derive(Clone, Copy)]
struct Corner {
    p: DVec3,
    uv: Option<[f64; 2]>,
    n: Option<DVec3>,
}

/// Collects faces part by part, with per-corner UVs and normals.
///
/// Normals are shared between corners only within one `group`: a CAD
/// exporter splits vertices between B-rep faces even where the normals
/// agree (a fillet meets its flat tangentially), so [`filleted_block`]
/// gives every B-rep face its own group.
#[derive(Default)]
struct Builder {
    positions: Vec<[f32; 3]>,
    position_ids: HashMap<[u32; 3], u32>,
    faces: Faces,
    face_parts: Vec<u32>,
    parts: Vec<Part>,
    uv: Stream<2>,
    normal: Stream<3>,
    group: u32,
    /// Polygons made by [`Builder::poly`] get box-mapped UVs in world
    /// units, as architectural exporters write them.
    box_uv: bool,
    /// Polygons made by [`Builder::poly`] get their plane's normal at
    /// every corner.
    flat_normals: bool,
}

impl Builder {
    fn new(box_uv: bool, flat_normals: bool) -> Self {
        Builder {
            box_uv,
            flat_normals,
            ..Builder::default()
        }
    }

    /// Starts a new part; the faces that follow belong to it.
    fn part(&mut self, name: &str, material: u32) {
        self.parts.push(Part {
            name: name.into(),
            material: Some(material),
        });
    }

    fn vertex(&mut self, p: DVec3) -> u32 {
        let p = p.as_vec3().to_array().map(canonical);
        let Builder {
            positions,
            position_ids,
            ..
        } = self;
        *position_ids.entry(p.map(f32::to_bits)).or_insert_with(|| {
            positions.push(p);
            (positions.len() - 1) as u32
        })
    }

    fn face(&mut self, corners: &[Corner]) {
        let ids: Vec<u32> = corners.iter().map(|c| self.vertex(c.p)).collect();
        self.faces.push(&ids);
        self.face_parts.push(self.parts.len() as u32 - 1);
        for c in corners {
            self.uv.push(0, c.uv.map(|u| u.map(|x| x as f32)));
            self.normal
                .push(self.group, c.n.map(|n| n.as_vec3().to_array()));
        }
    }

    /// A planar polygon wound so that its normal points along `facing`,
    /// with the builder's box-mapped UVs and flat normals.
    fn poly(&mut self, ps: &[DVec3], facing: DVec3) {
        let mut ps = ps.to_vec();
        let mut n = plane_normal(&ps);
        if n.dot(facing) < 0.0 {
            ps.reverse();
            n = -n;
        }
        let corners: Vec<Corner> = ps
            .iter()
            .map(|&p| Corner {
                p,
                uv: self.box_uv.then(|| box_uv(p, n)),
                n: self.flat_normals.then_some(n),
            })
            .collect();
        self.face(&corners);
    }

    /// A triangle with a normal per corner, wound to agree with them.
    fn smooth_tri(&mut self, c: [(DVec3, DVec3); 3]) {
        let [a, b, d] = c;
        let cross = (b.0 - a.0).cross(d.0 - a.0);
        let order = if cross.dot(a.1 + b.1 + d.1) < 0.0 {
            [a, d, b]
        } else {
            [a, b, d]
        };
        let corners = order.map(|(p, n)| Corner {
            p,
            uv: None,
            n: Some(n),
        });
        self.face(&corners);
    }

    fn mesh(self, name: &str) -> Mesh {
        let mut m = Mesh {
            name: name.into(),
            positions: self.positions,
            faces: self.faces,
            face_parts: self.face_parts,
            parts: self.parts,
            attributes: Vec::new(),
            skinning: None,
        };
        m.attributes
            .extend(self.uv.attribute(Semantic::TexCoord(0)));
        m.attributes.extend(self.normal.attribute(Semantic::Normal));
        m
    }
}

/// The unit normal of a planar polygon (Newell's method), with float noise
/// in components that should be zero snapped to zero, so that an
/// axis-aligned face gets an exact axis.
fn plane_normal(ps: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, &p) in ps.iter().enumerate() {
        let q = ps[(i + 1) % ps.len()];
        n += (p - q).cross(p + q) * 0.5;
    }
    let n = n.normalize_or_zero();
    n.map(|x| if x.abs() < 1e-9 { 0.0 } else { x })
        .normalize_or_zero()
}

/// Box-mapped texture coordinates in world units, as architectural
/// exporters write them: the face is projected along its dominant axis,
/// u to the right and v down when the face is seen from outside.
fn box_uv(p: DVec3, n: DVec3) -> [f64; 2] {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        [-p.z * n.x.signum(), 1.0 - p.y]
    } else if a.z >= a.y {
        [p.x * n.z.signum(), 1.0 - p.y]
    } else {
        [p.x, 1.0 + p.z * n.y.signum()]
    }
}

/// `a` at `t = 0`, `b` at `t = 1`, both exactly.
fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a * (1.0 - t) + b * t
}

/// [`lerp`] for points.
fn lerp3(a: DVec3, b: DVec3, t: f64) -> DVec3 {
    a * (1.0 - t) + b * t
}

/// The unit vector `s` times axis `a`.
fn axis(a: usize, s: f64) -> DVec3 {
    let mut v = DVec3::ZERO;
    v[a] = s;
    v
}

/// A hexahedron of corners `c` (bit 0 of the index selects u, bit 1 v,
/// bit 2 w) with planar sides, each side a grid of `div` cells along its
/// two directions, wound outward. Sides sharing an edge share its points
/// bit for bit (the same trilinear parameters give the same point).
fn hexa(b: &mut Builder, c: [DVec3; 8], div: [usize; 3]) {
    let at = |t: [f64; 3]| {
        let lo = lerp3(lerp3(c[0], c[1], t[0]), lerp3(c[2], c[3], t[0]), t[1]);
        let hi = lerp3(lerp3(c[4], c[5], t[0]), lerp3(c[6], c[7], t[0]), t[1]);
        lerp3(lo, hi, t[2])
    };
    let center = at([0.5; 3]);
    for ax in 0..3 {
        for side in [0.0, 1.0] {
            let (u, v) = ((ax + 1) % 3, (ax + 2) % 3);
            let mut mid = [0.5; 3];
            mid[ax] = side;
            let facing = at(mid) - center;
            for i in 0..div[u] {
                for j in 0..div[v] {
                    let p = |di: usize, dj: usize| {
                        let mut t = [0.0; 3];
                        t[ax] = side;
                        t[u] = (i + di) as f64 / div[u] as f64;
                        t[v] = (j + dj) as f64 / div[v] as f64;
                        at(t)
                    };
                    b.poly(&[p(0, 0), p(1, 0), p(1, 1), p(0, 1)], facing);
                }
            }
        }
    }
}

/// An axis-aligned box from `lo` to `hi`, `div` cells along x, y, z.
fn cuboid(b: &mut Builder, lo: [f64; 3], hi: [f64; 3], div: [usize; 3]) {
    let c = std::array::from_fn(|k| {
        DVec3::new(
            if k & 1 == 0 { lo[0] } else { hi[0] },
            if k & 2 == 0 { lo[1] } else { hi[1] },
            if k & 4 == 0 { lo[2] } else { hi[2] },
        )
    });
    hexa(b, c, div);
}

/// A wall's (or facade's) frame: `s` runs along it, `t` up, `d` into it
/// from its outer face, which faces `along × up`.
#[derive(Clone, Copy)]
struct Frame {
    origin: DVec3,
    along: DVec3,
    up: DVec3,
}

impl Frame {
    fn out(&self) -> DVec3 {
        self.along.cross(self.up)
    }

    fn at(&self, s: f64, t: f64, d: f64) -> DVec3 {
        self.origin + self.along * s + self.up * t - self.out() * d
    }

    /// A box aligned with the frame.
    fn cuboid(&self, b: &mut Builder, s: [f64; 2], t: [f64; 2], d: [f64; 2], div: [usize; 3]) {
        let c = std::array::from_fn(|k| self.at(s[k & 1], t[(k >> 1) & 1], d[k >> 2]));
        hexa(b, c, div);
    }
}

/// Rectangular openings `[s0, t0, s1, t1]` in a face of `size`, and the
/// grid of cells that tessellates it: lines every `spacing` at most and at
/// every opening's edges.
struct Grid {
    s: Vec<f64>,
    t: Vec<f64>,
    opening: Vec<bool>,
}

impl Grid {
    fn new(size: [f64; 2], spacing: f64, openings: &[[f64; 4]]) -> Grid {
        let lines = |len: f64, cuts: Vec<f64>| {
            let n = if spacing.is_finite() {
                (len / spacing).ceil().max(1.0) as usize
            } else {
                1
            };
            let mut v: Vec<f64> = (0..=n).map(|k| len * k as f64 / n as f64).collect();
            v.extend(cuts);
            v.sort_by(f64::total_cmp);
            v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            v
        };
        let s = lines(
            size[0],
            openings.iter().flat_map(|o| [o[0], o[2]]).collect(),
        );
        let t = lines(
            size[1],
            openings.iter().flat_map(|o| [o[1], o[3]]).collect(),
        );
        let mut opening = Vec::with_capacity((s.len() - 1) * (t.len() - 1));
        for j in 0..t.len() - 1 {
            for i in 0..s.len() - 1 {
                let (sc, tc) = (0.5 * (s[i] + s[i + 1]), 0.5 * (t[j] + t[j + 1]));
                opening.push(
                    openings
                        .iter()
                        .any(|o| o[0] < sc && sc < o[2] && o[1] < tc && tc < o[3]),
                );
            }
        }
        Grid { s, t, opening }
    }

    fn cols(&self) -> usize {
        self.s.len() - 1
    }

    fn rows(&self) -> usize {
        self.t.len() - 1
    }

    fn is_opening(&self, i: usize, j: usize) -> bool {
        self.opening[j * self.cols() + i]
    }

    /// The cells at depth `d` facing `facing`: the opening cells when
    /// `openings`, the wall cells otherwise.
    fn cells(&self, b: &mut Builder, f: &Frame, d: f64, openings: bool, facing: DVec3) {
        for j in 0..self.rows() {
            for i in 0..self.cols() {
                if self.is_opening(i, j) == openings {
                    let (s, t) = (&self.s, &self.t);
                    b.poly(
                        &[
                            f.at(s[i], t[j], d),
                            f.at(s[i + 1], t[j], d),
                            f.at(s[i + 1], t[j + 1], d),
                            f.at(s[i], t[j + 1], d),
                        ],
                        facing,
                    );
                }
            }
        }
    }

    /// The reveals of every opening from the face to `depth`, facing into
    /// the opening; sides on the face's outline have none.
    fn reveals(&self, b: &mut Builder, f: &Frame, depth: f64) {
        let (s, t) = (&self.s, &self.t);
        for j in 0..self.rows() {
            for i in 0..self.cols() {
                if !self.is_opening(i, j) {
                    continue;
                }
                let strip = |b: &mut Builder, p: DVec3, q: DVec3, facing: DVec3| {
                    let back = -f.out() * depth;
                    b.poly(&[p, q, q + back, p + back], facing);
                };
                if j > 0 && !self.is_opening(i, j - 1) {
                    strip(b, f.at(s[i], t[j], 0.0), f.at(s[i + 1], t[j], 0.0), f.up);
                }
                if j + 1 < self.rows() && !self.is_opening(i, j + 1) {
                    let (p, q) = (f.at(s[i], t[j + 1], 0.0), f.at(s[i + 1], t[j + 1], 0.0));
                    strip(b, p, q, -f.up);
                }
                if i > 0 && !self.is_opening(i - 1, j) {
                    strip(b, f.at(s[i], t[j], 0.0), f.at(s[i], t[j + 1], 0.0), f.along);
                }
                if i + 1 < self.cols() && !self.is_opening(i + 1, j) {
                    let (p, q) = (f.at(s[i + 1], t[j], 0.0), f.at(s[i + 1], t[j + 1], 0.0));
                    strip(b, p, q, -f.along);
                }
            }
        }
    }
}

/// A solid wall of `thickness` behind the frame's face of `size`, pierced
/// by `openings` through its whole thickness: outer and inner faces as
/// grids, reveals, and top, bottom and end strips (a closed solid).
fn wall(b: &mut Builder, f: &Frame, size: [f64; 2], thickness: f64, openings: &[[f64; 4]]) {
    let g = Grid::new(size, 0.5, openings);
    g.cells(b, f, 0.0, false, f.out());
    g.cells(b, f, thickness, false, -f.out());
    g.reveals(b, f, thickness);
    let (s, t) = (&g.s, &g.t);
    let strip = |b: &mut Builder, p: DVec3, q: DVec3, facing: DVec3| {
        let back = -f.out() * thickness;
        b.poly(&[p, q, q + back, p + back], facing);
    };
    for i in 0..g.cols() {
        if !g.is_opening(i, 0) {
            strip(b, f.at(s[i], 0.0, 0.0), f.at(s[i + 1], 0.0, 0.0), -f.up);
        }
        if !g.is_opening(i, g.rows() - 1) {
            strip(
                b,
                f.at(s[i], size[1], 0.0),
                f.at(s[i + 1], size[1], 0.0),
                f.up,
            );
        }
    }
    for j in 0..g.rows() {
        if !g.is_opening(0, j) {
            strip(b, f.at(0.0, t[j], 0.0), f.at(0.0, t[j + 1], 0.0), -f.along);
        }
        if !g.is_opening(g.cols() - 1, j) {
            strip(
                b,
                f.at(size[0], t[j], 0.0),
                f.at(size[0], t[j + 1], 0.0),
                f.along,
            );
        }
    }
}

/// A non-metallic material of one color.
fn material(name: &str, rgb: [f32; 3]) -> Material {
    Material {
        name: name.into(),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        metallic: 0.0,
        roughness: 0.8,
        ..Material::default()
    }
}

/// A texture whose image is a PNG of `width × height` pixels (opaque RGB,
/// first row at the top), embedded in the scene; repeat sampling.
fn png_texture(
    name: &str,
    width: u32,
    height: u32,
    pixel: impl Fn(u32, u32) -> [u8; 3],
) -> Texture {
    let img = image::RgbImage::from_fn(width, height, |x, y| image::Rgb(pixel(x, y)));
    embedded_png(name, image::DynamicImage::ImageRgb8(img))
}

/// A texture whose image is `img`, PNG-encoded and embedded in the
/// scene; repeat sampling.
fn embedded_png(name: &str, img: image::DynamicImage) -> Texture {
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .expect("PNG encoding into memory");
    Texture {
        name: name.into(),
        source: ImageSource::Embedded {
            bytes: bytes.into_inner(),
            mime_type: "image/png".into(),
        },
        sampler: Default::default(),
    }
}

/// A scene of one mesh instanced by one root node, with its materials and
/// textures.
fn scene(mesh: Mesh, materials: Vec<Material>, textures: Vec<Texture>) -> Scene {
    let mut s = Scene::from_mesh(mesh);
    s.materials = materials;
    s.textures = textures;
    s
}

/// A game prop of flat panels: a cube of side 2 whose six sides are `n × n`
/// grids of triangles, each with a square panel raised by 0.04 over its
/// middle (a one-cell ramp around it), and smooth normals shared across
/// the whole box (no seam, not even at the cube's edges). Every face is
/// planar and the ramps' strips are flat too, so an exact simplifier can
/// stay on the input's planes to rounding; the normals, which turn across
/// every ramp and edge, are what would pull a vertex off them.
pub fn panel_box(n: usize) -> Scene {
    let mut b = Builder::new(false, false);
    b.part("crate", 0);
    let height = |u: f64, v: f64| {
        if u.abs().max(v.abs()) < 0.45 {
            0.04
        } else {
            0.0
        }
    };
    for a in 0..3 {
        for s in [-1.0, 1.0] {
            let at = |i: usize, j: usize| {
                let c = |k: usize| (2 * k) as f64 / n as f64 - 1.0;
                let (u, v) = (c(i), c(j));
                let mut p = DVec3::ZERO;
                p[a] = s * (1.0 + height(u, v));
                p[(a + 1) % 3] = u;
                p[(a + 2) % 3] = v;
                p
            };
            let out = axis(a, s);
            for i in 0..n {
                for j in 0..n {
                    let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                    b.poly(&[q[0], q[1], q[2]], out);
                    b.poly(&[q[0], q[2], q[3]], out);
                }
            }
        }
    }
    let mut m = b.mesh("panel_box");
    smooth_normals(&mut m);
    scene(m, vec![material("paint", [0.6, 0.5, 0.3])], Vec::new())
}

/// A scan-like closed surface: [`wildlod_mesh::shapes::bumpy_quad_sphere`]
/// of `n × n` cells a side, every quad split into two triangles, with
/// smooth normals shared by every corner of a position (no seam). The
/// normals only follow the surface: whatever they steer, a geometry-only
/// run must give the surface it gives without them.
pub fn smooth_bumpy_sphere(n: usize) -> Scene {
    let mut m = wildlod_mesh::polygon::triangulate(&wildlod_mesh::shapes::bumpy_quad_sphere(n));
    m.name = "bumpy_sphere".into();
    smooth_normals(&mut m);
    Scene::from_mesh(m)
}

/// Area-weighted smooth normals: one per position, shared by all its
/// corners (no seam), replacing any normal stream.
fn smooth_normals(m: &mut Mesh) {
    let mut acc = vec![DVec3::ZERO; m.positions.len()];
    let p = |v: u32| DVec3::from(m.positions[v as usize].map(f64::from));
    for f in m.faces.iter() {
        for k in 1..f.len() - 1 {
            let n = (p(f[k]) - p(f[0])).cross(p(f[k + 1]) - p(f[0]));
            for &v in [f[0], f[k], f[k + 1]].iter() {
                acc[v as usize] += n;
            }
        }
    }
    m.attributes.retain(|a| a.semantic != Semantic::Normal);
    m.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: acc
            .iter()
            .flat_map(|n| n.normalize_or(DVec3::Y).as_vec3().to_array())
            .collect(),
        indices: m.faces.indices.clone(),
        format: ComponentFormat::F32,
    });
}

// ---------------------------------------------------------------------------
// 1. An architectural export

/// A small house as an architectural OBJ export brings it: 31 parts and 12
/// materials, every face with box-mapped UVs in world units (large values,
/// 57 UV islands where the projection changes) and flat normals, and
/// under it a ground plane of exactly 2 triangles, 60 m square: the
/// largest part by far (3,600 m², seven times the 514 m² of all the other
/// parts' faces together).
///
/// The house (8 × 6 m, ridge at 4.6 m): a foundation slab; four walls
/// 0.2 m thick, tessellated in cells of at most 0.5 m, with a door and six
/// windows cut through them (reveals on all sides); two gables; a pitched
/// roof of two 0.15 m slabs; a chimney through the roof; frames, sills and
/// panes in every window; a door with its frame; a porch with two posts, a
/// sloped roof and two steps. 2,708 faces (2,702 quads, as OBJ exports
/// write them, and 6 triangles), 5,410 triangles.
///
/// With `textured_walls` false no material has a texture: the UVs steer
/// nothing a renderer shows, yet they are everywhere. With it true the
/// wall material (`plaster`, used by the walls and gables) samples a
/// 64 × 64 brick texture through UV set 0, one brick pattern per metre.
///
/// Stresses: attributes steering collapses where nothing shows them;
/// a large, two-triangle part that must not vanish; thin trims (frames,
/// sills, posts) beside large flat walls.
pub fn house(textured_walls: bool) -> Scene {
    let mut b = Builder::new(true, true);
    let plaster = 1;
    let mut materials = vec![
        material("ground", [0.25, 0.45, 0.15]),
        material("plaster", [0.85, 0.82, 0.75]),
        material("roof_tiles", [0.55, 0.18, 0.12]),
        material("chimney_brick", [0.5, 0.25, 0.2]),
        material("window_frame", [0.95, 0.95, 0.95]),
        Material {
            alpha_mode: AlphaMode::Blend,
            ..material("glass", [0.6, 0.75, 0.85])
        },
        material("door_wood", [0.4, 0.25, 0.12]),
        material("sill_stone", [0.55, 0.55, 0.52]),
        material("porch_wood", [0.55, 0.4, 0.25]),
        material("post_paint", [0.95, 0.95, 0.9]),
        material("concrete", [0.6, 0.6, 0.58]),
        Material {
            metallic: 0.8,
            roughness: 0.4,
            ..material("porch_roof_metal", [0.3, 0.32, 0.35])
        },
    ];
    materials[5].base_color[3] = 0.35;
    let mut textures = Vec::new();
    if textured_walls {
        textures.push(brick_texture());
        materials[plaster as usize].base_color = [1.0; 4];
        materials[plaster as usize].base_color_texture = Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        });
    }

    b.part("ground", 0);
    let g = |x: f64, z: f64| DVec3::new(x, 0.0, z);
    b.poly(&[g(-30.0, -30.0), g(30.0, -30.0), g(30.0, 30.0)], DVec3::Y);
    b.poly(&[g(-30.0, -30.0), g(30.0, 30.0), g(-30.0, 30.0)], DVec3::Y);

    b.part("foundation", 10);
    cuboid(&mut b, [-4.1, -0.2, -3.1], [4.1, 0.3, 3.1], [8, 1, 6]);

    // Walls stand on the slab (y = 0.3) and are 2.7 m high; the front and
    // back walls span the whole width, the side walls fit between them.
    let (base, height, thick) = (0.3, 2.7, 0.2);
    let door = [3.5, 0.0, 4.5, 2.1];
    let window = |s: f64| [s, 0.9, s + 1.2, 2.1];
    let walls = [
        (
            "wall_front",
            Frame {
                origin: DVec3::new(-4.0, base, 3.0),
                along: DVec3::X,
                up: DVec3::Y,
            },
            8.0,
            vec![window(1.0), door, window(5.8)],
        ),
        (
            "wall_back",
            Frame {
                origin: DVec3::new(4.0, base, -3.0),
                along: DVec3::NEG_X,
                up: DVec3::Y,
            },
            8.0,
            vec![window(1.0), window(5.8)],
        ),
        (
            "wall_east",
            Frame {
                origin: DVec3::new(4.0, base, 2.8),
                along: DVec3::NEG_Z,
                up: DVec3::Y,
            },
            5.6,
            vec![window(2.2)],
        ),
        (
            "wall_west",
            Frame {
                origin: DVec3::new(-4.0, base, -2.8),
                along: DVec3::Z,
                up: DVec3::Y,
            },
            5.6,
            vec![window(2.2)],
        ),
    ];
    for (name, f, len, openings) in &walls {
        b.part(name, plaster);
        wall(&mut b, f, [*len, height], thick, openings);
    }

    // Gables: triangular prisms on the side walls up to the ridge.
    let (eave_y, ridge_y) = (base + height, 4.5);
    for (name, x, inward) in [("gable_east", 4.0, -1.0), ("gable_west", -4.0, 1.0)] {
        b.part(name, plaster);
        let tri = |x: f64| {
            [
                DVec3::new(x, eave_y, -3.0),
                DVec3::new(x, eave_y, 3.0),
                DVec3::new(x, ridge_y, 0.0),
            ]
        };
        let (o, i) = (tri(x), tri(x + inward * thick));
        let out = DVec3::new(-inward, 0.0, 0.0);
        b.poly(&o, out);
        b.poly(&i, -out);
        b.poly(&[o[0], o[1], i[1], i[0]], DVec3::NEG_Y);
        b.poly(&[o[1], o[2], i[2], i[1]], DVec3::new(0.0, 1.0, 1.0));
        b.poly(&[o[2], o[0], i[0], i[2]], DVec3::new(0.0, 1.0, -1.0));
    }

    // Roof: two slabs resting on the gables' slopes (y = 4.5 − |z| / 2),
    // overhanging 0.4 m at the gables and 0.5 m at the eaves.
    for (name, side) in [("roof_south", 1.0), ("roof_north", -1.0)] {
        b.part(name, 2);
        let n = DVec3::new(0.0, 1.0, 0.5 * side).normalize() * 0.15;
        let c: [DVec3; 8] = std::array::from_fn(|k| {
            let x = if k & 1 == 0 { -4.4 } else { 4.4 };
            let bottom = if k & 2 == 0 {
                DVec3::new(x, ridge_y, 0.0)
            } else {
                DVec3::new(x, ridge_y - 1.75, 3.5 * side)
            };
            if k & 4 == 0 {
                bottom
            } else {
                bottom + n
            }
        });
        hexa(&mut b, c, [16, 8, 1]);
    }

    b.part("chimney", 3);
    cuboid(&mut b, [2.2, 3.2, -1.8], [2.8, 5.4, -1.2], [2, 6, 2]);

    // Windows: a frame of four members and a sill per window, all panes in
    // one part.
    let mut panes = Vec::new();
    let mut k = 0;
    for (_, f, _, openings) in &walls {
        for o in openings.iter().filter(|o| o[1] > 0.0) {
            k += 1;
            let [s0, t0, s1, t1] = *o;
            let (w, d) = (0.06, [0.06, 0.14]);
            b.part(&format!("window_frame_{k}"), 4);
            f.cuboid(&mut b, [s0, s0 + w], [t0, t1], d, [1, 4, 1]);
            f.cuboid(&mut b, [s1 - w, s1], [t0, t1], d, [1, 4, 1]);
            f.cuboid(&mut b, [s0 + w, s1 - w], [t0, t0 + w], d, [4, 1, 1]);
            f.cuboid(&mut b, [s0 + w, s1 - w], [t1 - w, t1], d, [4, 1, 1]);
            b.part(&format!("sill_{k}"), 7);
            f.cuboid(
                &mut b,
                [s0 - 0.05, s1 + 0.05],
                [t0 - 0.05, t0],
                [-0.06, 0.1],
                [4, 1, 1],
            );
            panes.push((*f, [s0 + w, s1 - w], [t0 + w, t1 - w]));
        }
    }
    b.part("glass", 5);
    for (f, s, t) in &panes {
        f.cuboid(&mut b, *s, *t, [0.095, 0.105], [1, 1, 1]);
    }

    let front = walls[0].1;
    let [s0, _, s1, t1] = door;
    b.part("door", 6);
    front.cuboid(
        &mut b,
        [s0 + 0.05, s1 - 0.05],
        [0.0, t1 - 0.05],
        [0.08, 0.12],
        [2, 4, 1],
    );
    b.part("door_frame", 4);
    let d = [0.04, 0.16];
    front.cuboid(&mut b, [s0, s0 + 0.05], [0.0, t1], d, [1, 4, 1]);
    front.cuboid(&mut b, [s1 - 0.05, s1], [0.0, t1], d, [1, 4, 1]);
    front.cuboid(
        &mut b,
        [s0 + 0.05, s1 - 0.05],
        [t1 - 0.05, t1],
        d,
        [2, 1, 1],
    );

    b.part("porch", 8);
    cuboid(&mut b, [-2.0, -0.1, 3.1], [2.0, 0.3, 5.0], [8, 1, 4]);
    for (name, x) in [("porch_post_west", -1.85), ("porch_post_east", 1.85)] {
        b.part(name, 9);
        cuboid(
            &mut b,
            [x - 0.06, 0.3, 4.79],
            [x + 0.06, 2.76, 4.91],
            [1, 4, 1],
        );
    }
    b.part("porch_roof", 11);
    let c: [DVec3; 8] = std::array::from_fn(|k| {
        let x = if k & 1 == 0 { -2.1 } else { 2.1 };
        let (z, y) = if k & 2 == 0 { (3.0, 2.9) } else { (5.1, 2.75) };
        DVec3::new(x, if k & 4 == 0 { y } else { y + 0.08 }, z)
    });
    hexa(&mut b, c, [8, 4, 1]);
    b.part("steps", 10);
    cuboid(&mut b, [-0.8, -0.1, 5.0], [0.8, 0.2, 5.3], [2, 1, 1]);
    cuboid(&mut b, [-0.8, -0.1, 5.3], [0.8, 0.1, 5.6], [2, 1, 1]);

    scene(b.mesh("house"), materials, textures)
}

/// A 64 × 64 brick pattern: 16 × 8 px bricks, rows offset by half a brick,
/// 1 px mortar, a deterministic shade per brick.
fn brick_texture() -> Texture {
    png_texture("bricks", 64, 64, |x, y| {
        let row = y / 8;
        let shifted = x + if row % 2 == 1 { 8 } else { 0 };
        if y % 8 == 7 || shifted % 16 == 15 {
            return [200, 196, 188];
        }
        let brick = u64::from(row) * 8 + u64::from((shifted / 16) % 4);
        let shade = (SplitMix64(brick).next_u64() % 40) as u8;
        [150 + shade, 60 + shade / 2, 45 + shade / 3]
    })
}

// ---------------------------------------------------------------------------
// 2. A CAD part

/// Half extents of [`filleted_block`].
const BLOCK_HALF: [f64; 3] = [2.0, 1.0, 1.5];
/// Fillet radius of [`filleted_block`]; every coordinate of its inner box
/// (`BLOCK_HALF − r`) is a short binary fraction, so that points computed
/// from different B-rep faces agree bit for bit.
const BLOCK_FILLET: f64 = 0.375;
/// Radius of [`filleted_block`]'s through-hole.
const BLOCK_HOLE: f64 = 0.5;

/// cos and sin of `i / k` of a quarter turn, exact at both ends and
/// symmetric (`quarter(k − i, k)` is `quarter(i, k)` swapped, bit for bit),
/// so that arcs sampled from either end meet exactly.
fn quarter(i: usize, k: usize) -> (f64, f64) {
    if 2 * i > k {
        let (c, s) = quarter(k - i, k);
        return (s, c);
    }
    if i == 0 {
        return (1.0, 0.0);
    }
    if 2 * i == k {
        // cos and sin of 45° differ in their last bit.
        return (FRAC_1_SQRT_2, FRAC_1_SQRT_2);
    }
    let a = FRAC_PI_2 * i as f64 / k as f64;
    (a.cos(), a.sin())
}

/// A closed CAD part as a STEP-to-mesh export brings it: a 4 × 2 × 3 block
/// with every edge and corner rounded (radius 0.375) and a round
/// through-hole (radius 0.5) along y with sharp 90° rims. 7,864 triangles,
/// one part, one material.
///
/// Tessellated as CAD exporters do, one B-rep face at a time: the six
/// flats in few large triangles (fans; the two pierced by the hole filled
/// between their outline and the hole by long triangles), the twelve edge
/// fillets in strips of long thin triangles (24 across the quarter
/// circle), the eight corner patches in rows of triangles (576 each), the
/// hole's wall in 64 full-length strips. Positions are shared across B-rep
/// faces (watertight), but every B-rep face has its own normals: exact
/// plane normals on flats, smooth radial normals on fillets, corners and
/// hole, so every B-rep edge is a normal seam, even where a fillet meets
/// its flat tangentially. The hole's rims are real creases.
///
/// Stresses: normal seams that are not creases; small triangles carrying
/// features (fillets) beside huge ones (flats); sharp rims.
pub fn filleted_block() -> Scene {
    const K: usize = 24;
    const HOLE_N: usize = 64;
    let r = BLOCK_FILLET;
    let inner = BLOCK_HALF.map(|h| h - r);
    // Segments along an edge of the inner box, at most 0.5 long.
    let segs = |a: usize| (2.0 * inner[a] / 0.5).ceil() as usize;
    let along = |a: usize, j: usize| lerp(-inner[a], inner[a], j as f64 / segs(a) as f64);
    let surface = |q: DVec3, n: DVec3| (q + n * r, n);
    let mut b = Builder::new(false, false);
    b.part("block", 0);

    // Edge fillets: axes a < c of the two flats they join, running along
    // the third axis e.
    for (a, c, e) in [(0, 1, 2), (0, 2, 1), (1, 2, 0)] {
        for sa in [-1.0, 1.0] {
            for sc in [-1.0, 1.0] {
                b.group += 1;
                let pt = |i: usize, j: usize| {
                    let (co, si) = quarter(i, K);
                    let mut q = DVec3::ZERO;
                    q[a] = sa * inner[a];
                    q[c] = sc * inner[c];
                    q[e] = along(e, j);
                    surface(q, axis(a, sa * co) + axis(c, sc * si))
                };
                for i in 0..K {
                    for j in 0..segs(e) {
                        let (p00, p10, p11, p01) =
                            (pt(i, j), pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1));
                        b.smooth_tri([p00, p10, p11]);
                        b.smooth_tri([p00, p11, p01]);
                    }
                }
            }
        }
    }

    // Corner patches: rows of constant angle from the x axis, row i with
    // i + 1 points; the rows' ends and the last row meet the fillets.
    for k in 0..8 {
        b.group += 1;
        let s = [0, 1, 2].map(|bit| if k >> bit & 1 == 0 { -1.0 } else { 1.0 });
        let q = DVec3::new(s[0] * inner[0], s[1] * inner[1], s[2] * inner[2]);
        let pt = |i: usize, j: usize| {
            let (ct, st) = quarter(i, K);
            let (cp, sp) = quarter(j, i);
            surface(
                q,
                axis(0, s[0] * ct) + axis(1, s[1] * st * cp) + axis(2, s[2] * st * sp),
            )
        };
        for i in 0..K {
            for j in 0..=i {
                b.smooth_tri([pt(i, j), pt(i + 1, j), pt(i + 1, j + 1)]);
                if j < i {
                    b.smooth_tri([pt(i, j), pt(i + 1, j + 1), pt(i, j + 1)]);
                }
            }
        }
    }

    // The hole's rim, shared by the hole's wall and the flats it pierces.
    let rim = |y: f64| -> Vec<DVec3> {
        (0..HOLE_N)
            .map(|k| {
                let a = TAU * k as f64 / HOLE_N as f64;
                DVec3::new(BLOCK_HOLE * a.cos(), y, BLOCK_HOLE * a.sin())
            })
            .collect()
    };

    // Flats: the inner box's faces pushed out by r, outlined by the
    // fillets' tangent lines.
    for a in 0..3 {
        for sa in [-1.0, 1.0] {
            b.group += 1;
            let n = axis(a, sa);
            let (u, v) = ((a + 1) % 3, (a + 2) % 3);
            let pt = |cu: f64, cv: f64| {
                let mut q = DVec3::ZERO;
                q[a] = sa * inner[a];
                q[u] = cu;
                q[v] = cv;
                surface(q, n).0
            };
            let mut outline = Vec::new();
            let (mu, mv) = (segs(u), segs(v));
            outline.extend((0..mu).map(|j| pt(along(u, j), -inner[v])));
            outline.extend((0..mv).map(|j| pt(inner[u], along(v, j))));
            outline.extend((0..mu).map(|j| pt(along(u, mu - j), inner[v])));
            outline.extend((0..mv).map(|j| pt(-inner[u], along(v, mv - j))));
            let tris = if a == 1 {
                zip_loops(&outline, &rim(sa * BLOCK_HALF[1]))
            } else {
                let center = pt(0.0, 0.0);
                (0..outline.len())
                    .map(|k| [center, outline[k], outline[(k + 1) % outline.len()]])
                    .collect()
            };
            for t in tris {
                b.smooth_tri(t.map(|p| (p, n)));
            }
        }
    }

    // The hole's wall: full-length strips, normals towards the axis.
    b.group += 1;
    let (top, bottom) = (rim(BLOCK_HALF[1]), rim(-BLOCK_HALF[1]));
    for k in 0..HOLE_N {
        let l = (k + 1) % HOLE_N;
        let n = |p: DVec3| DVec3::new(-p.x, 0.0, -p.z).normalize();
        let c = |p: DVec3| (p, n(p));
        b.smooth_tri([c(top[k]), c(bottom[k]), c(bottom[l])]);
        b.smooth_tri([c(top[k]), c(bottom[l]), c(top[l])]);
    }

    let metal = Material {
        metallic: 1.0,
        roughness: 0.35,
        ..material("machined_steel", [0.7, 0.7, 0.72])
    };
    scene(b.mesh("filleted_block"), vec![metal], Vec::new())
}

/// Triangles filling the ring between two loops around the y axis (both
/// star-shaped about it), merged by angle in the x-z plane: how CAD
/// tessellators fill a pierced flat in few long triangles.
fn zip_loops(outer: &[DVec3], inner: &[DVec3]) -> Vec<[DVec3; 3]> {
    let sorted = |l: &[DVec3]| {
        let mut v: Vec<(f64, DVec3)> = l.iter().map(|p| (p.z.atan2(p.x), *p)).collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let first = v[0];
        v.push((first.0 + TAU, first.1));
        v
    };
    let (o, q) = (sorted(outer), sorted(inner));
    let (no, nq) = (o.len() - 1, q.len() - 1);
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::with_capacity(no + nq);
    while i < no || j < nq {
        if j == nq || (i < no && o[i + 1].0 <= q[j + 1].0) {
            out.push([o[i].1, o[i + 1].1, q[j].1]);
            i += 1;
        } else {
            out.push([o[i].1, q[j + 1].1, q[j].1]);
            j += 1;
        }
    }
    out
}

// ---------------------------------------------------------------------------
// 3. A flat tiling

/// Cells along each side of [`flat_tiling`]'s grid.
const TILING_CELLS: usize = 72;

/// An open, flat tiling of triangles and quads in the plane z = 0 exactly,
/// with a ragged border and a hole: a 72 × 72 grid of 0.125 cells (9 × 9
/// units) where each cell is a quad or two triangles (split along either
/// diagonal, at random), cells removed in runs of depth 0 to 3 along every
/// side and in a disk of radius 5 cells near the middle; interior vertices
/// jittered in the plane (border vertices stay on the grid, so the border
/// is axis-aligned runs and steps). About 4,600 cells, about 9,300
/// triangles when triangulated; one part, one material; no attributes.
/// Every vertex is manifold (no two cells meet at a corner only).
///
/// [`border_segments`] gives its border as segments, to check that a
/// simplified tiling's border vertices stay on it. glTF stores triangles
/// only: write it to OBJ (or simplify the scene in memory) to keep the
/// quads, and so to exercise quad mode.
///
/// Stresses: flatness and borders that must stay exact whatever the arity
/// mix (quad mode), straight border runs where sliding along is allowed
/// and corners where it is not.
pub fn flat_tiling(seed: u64) -> Scene {
    const N: usize = TILING_CELLS;
    const CELL: f64 = 0.125;
    let mut rng = SplitMix64(seed);
    let mut present = vec![true; N * N];
    let id = |i: usize, j: usize| j * N + i;
    // Ragged sides: depth profiles in runs of 3 to 8 cells.
    for side in 0..4 {
        let mut k = 0;
        while k < N {
            let run = 3 + (rng.next_u64() % 6) as usize;
            let depth = (rng.next_u64() % 4) as usize;
            for along in k..(k + run).min(N) {
                for d in 0..depth {
                    let (i, j) = match side {
                        0 => (along, d),
                        1 => (N - 1 - d, along),
                        2 => (along, N - 1 - d),
                        _ => (d, along),
                    };
                    present[id(i, j)] = false;
                }
            }
            k += run;
        }
    }
    let (hx, hy) = (
        N as f64 / 2.0 + rng.next_f64() * 6.0 - 3.0,
        N as f64 / 2.0 + rng.next_f64() * 6.0 - 3.0,
    );
    for j in 0..N {
        for i in 0..N {
            if (i as f64 + 0.5 - hx).hypot(j as f64 + 0.5 - hy) < 5.0 {
                present[id(i, j)] = false;
            }
        }
    }
    // Where two removed cells meet at a corner only, the vertex between
    // them would be non-manifold: remove one of the other two as well.
    loop {
        let mut changed = false;
        for j in 0..N - 1 {
            for i in 0..N - 1 {
                let c =
                    [id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)].map(|c| present[c]);
                if c == [true, false, false, true] || c == [false, true, true, false] {
                    let victim = if c[0] { id(i, j) } else { id(i + 1, j) };
                    present[victim] = false;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    // Grid vertices of present cells; those not on the border are jittered.
    let cell = |i: isize, j: isize| {
        i >= 0
            && j >= 0
            && (i as usize) < N
            && (j as usize) < N
            && present[id(i as usize, j as usize)]
    };
    let mut pos = vec![DVec3::ZERO; (N + 1) * (N + 1)];
    for j in 0..=N {
        for i in 0..=N {
            let (ii, jj) = (i as isize, j as isize);
            let around = [
                cell(ii - 1, jj - 1),
                cell(ii, jj - 1),
                cell(ii - 1, jj),
                cell(ii, jj),
            ];
            let (dx, dy) = (rng.next_f64() - 0.5, rng.next_f64() - 0.5);
            let interior = around.iter().all(|&c| c);
            let jitter = if interior { 0.4 * CELL } else { 0.0 };
            pos[j * (N + 1) + i] = DVec3::new(
                i as f64 * CELL + dx * jitter,
                j as f64 * CELL + dy * jitter,
                0.0,
            );
        }
    }
    let mut b = Builder::new(false, false);
    b.part("tiles", 0);
    for j in 0..N {
        for i in 0..N {
            let kind = rng.next_u64() % 4;
            if !present[id(i, j)] {
                continue;
            }
            let v = |di: usize, dj: usize| pos[(j + dj) * (N + 1) + i + di];
            let [a, bb, c, d] = [v(0, 0), v(1, 0), v(1, 1), v(0, 1)];
            match kind {
                0 | 1 => b.poly(&[a, bb, c, d], DVec3::Z),
                2 => {
                    b.poly(&[a, bb, c], DVec3::Z);
                    b.poly(&[a, c, d], DVec3::Z);
                }
                _ => {
                    b.poly(&[a, bb, d], DVec3::Z);
                    b.poly(&[bb, c, d], DVec3::Z);
                }
            }
        }
    }
    scene(
        b.mesh("flat_tiling"),
        vec![material("tile", [0.7, 0.68, 0.62])],
        Vec::new(),
    )
}

/// The border of a mesh as segments: every edge that exactly one face
/// uses, positions compared bit for bit (so seams in attribute streams do
/// not count), in face order. For [`flat_tiling`], the outline and the
/// hole's rim.
pub fn border_segments(mesh: &Mesh) -> Vec<[[f32; 3]; 2]> {
    let key = |v: u32| mesh.positions[v as usize].map(|x| canonical(x).to_bits());
    let mut count: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    let edges = || {
        mesh.faces
            .iter()
            .flat_map(|f| (0..f.len()).map(move |k| (f[k], f[(k + 1) % f.len()])))
    };
    let undirected = |(a, b): (u32, u32)| {
        let (ka, kb) = (key(a), key(b));
        if ka <= kb {
            (ka, kb)
        } else {
            (kb, ka)
        }
    };
    for e in edges() {
        *count.entry(undirected(e)).or_default() += 1;
    }
    edges()
        .filter(|&e| count[&undirected(e)] == 1)
        .map(|(a, b)| [mesh.positions[a as usize], mesh.positions[b as usize]])
        .collect()
}

/// Distance from `p` to the nearest of `segments` (infinite when there is
/// none), in double precision.
pub fn distance_to_segments(p: [f64; 3], segments: &[[[f32; 3]; 2]]) -> f64 {
    let p = DVec3::from(p);
    segments
        .iter()
        .map(|s| {
            let (a, b) = (
                DVec3::from(s[0].map(f64::from)),
                DVec3::from(s[1].map(f64::from)),
            );
            let ab = b - a;
            let t = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

// ---------------------------------------------------------------------------
// 4. A city block

/// A city block as a procedural city generator exports it: 12 boxy
/// buildings (14–22 m wide, 6 to 19 floors: 20–62 m high) on lots 36 m
/// apart, their
/// facades pierced by a window per 2.5 m bay and 3.2 m floor, each window
/// recessed 8 cm into the facade (four reveal quads and a back pane), flat
/// roofs; 150 lamp posts (8-sided poles 5 m high with a box head); a
/// street plane of 2 triangles under it all. 41,404 faces (mostly quads),
/// 80,338 triangles, 27 parts
/// (a facade part and a window-pane part per building, posts, heads,
/// street), 7 materials.
///
/// Normals are per face, as exporters write boxy models: every planar
/// face carries its own plane normal, so every reveal edge is a normal
/// seam (the poles' sides have smooth normals). Facades are grids of
/// cells between the windows, so each window adds many small faces.
///
/// Stresses: normals that flattened facades must not inherit from their
/// recesses; many small features on large planes; many tiny separate
/// parts (the posts).
pub fn city_block() -> Scene {
    let mut rng = SplitMix64(0x5eed_c17e);
    let mut b = Builder::new(false, true);
    let materials = vec![
        material("facade_sandstone", [0.76, 0.68, 0.52]),
        material("facade_brick", [0.55, 0.3, 0.24]),
        material("facade_concrete", [0.62, 0.63, 0.62]),
        Material {
            metallic: 0.2,
            roughness: 0.1,
            ..material("window_glass", [0.2, 0.3, 0.38])
        },
        Material {
            metallic: 0.9,
            roughness: 0.5,
            ..material("lamp_metal", [0.2, 0.22, 0.22])
        },
        Material {
            emissive: [1.0, 0.9, 0.7],
            ..material("lamp_light", [1.0, 0.95, 0.85])
        },
        material("asphalt", [0.18, 0.18, 0.19]),
    ];
    // Lots 24 m square, 36 m apart (12 m streets); coordinates in half
    // metres so that facades meet at their corners bit for bit.
    let half = |x: f64| (x * 2.0).round() / 2.0;
    for k in 0..12 {
        let (col, row) = ((k % 4) as f64, (k / 4) as f64);
        let (w, d) = (
            half(14.0 + 8.0 * rng.next_f64()),
            half(14.0 + 8.0 * rng.next_f64()),
        );
        let floors = 6 + (rng.next_u64() % 14) as usize;
        let h = floors as f64 * 3.2 + 0.6;
        let (x0, z0) = (
            col * 36.0 + half((24.0 - w) / 2.0),
            row * 36.0 + half((24.0 - d) / 2.0),
        );
        let (x1, z1) = (x0 + w, z0 + d);
        let facades = [
            (DVec3::new(x0, 0.0, z1), DVec3::X, w),
            (DVec3::new(x1, 0.0, z1), DVec3::NEG_Z, d),
            (DVec3::new(x1, 0.0, z0), DVec3::NEG_X, w),
            (DVec3::new(x0, 0.0, z0), DVec3::Z, d),
        ];
        let windows = |len: f64| -> Vec<[f64; 4]> {
            let bays = ((len - 1.0) / 2.5).floor() as usize;
            let margin = (len - bays as f64 * 2.5) / 2.0;
            let mut out = Vec::new();
            for f in 0..floors {
                for bay in 0..bays {
                    let s = margin + bay as f64 * 2.5 + 0.65;
                    let t = f as f64 * 3.2 + 0.9;
                    out.push([s, t, s + 1.2, t + 1.6]);
                }
            }
            out
        };
        b.part(&format!("building_{k}"), (k % 3) as u32);
        let mut grids = Vec::new();
        let mut roof_outline = Vec::new();
        for &(origin, along, len) in &facades {
            let f = Frame {
                origin,
                along,
                up: DVec3::Y,
            };
            let g = Grid::new([len, h], f64::INFINITY, &windows(len));
            g.cells(&mut b, &f, 0.0, false, f.out());
            g.reveals(&mut b, &f, 0.08);
            roof_outline.extend(g.s[..g.s.len() - 1].iter().map(|&s| f.at(s, h, 0.0)));
            grids.push((f, g));
        }
        // The roof: a fan over the facades' top edges, so that it meets
        // every facade vertex there (no T-junctions).
        let center = DVec3::new(0.5 * (x0 + x1), h, 0.5 * (z0 + z1));
        for i in 0..roof_outline.len() {
            let next = roof_outline[(i + 1) % roof_outline.len()];
            b.poly(&[center, roof_outline[i], next], DVec3::Y);
        }
        b.part(&format!("windows_{k}"), 3);
        for (f, g) in &grids {
            g.cells(&mut b, f, 0.08, true, f.out());
        }
    }

    // Lamp posts along both sides of every street, 10 m apart, 150 of
    // them spread over the candidates.
    let mut spots = Vec::new();
    for line in 0..5 {
        let c = line as f64 * 36.0 - 6.0;
        for side in [-4.5, 4.5] {
            for k in 0..11 {
                spots.push(DVec2::new(c + side, k as f64 * 10.0 - 2.0));
            }
        }
    }
    for line in 0..4 {
        let c = line as f64 * 36.0 - 6.0;
        for side in [-4.5, 4.5] {
            for k in 0..15 {
                spots.push(DVec2::new(k as f64 * 10.0 - 3.0, c + side));
            }
        }
    }
    let mut posts: Vec<DVec2> = Vec::new();
    for s in spots {
        if posts.iter().all(|p| p.distance(s) > 2.0) {
            posts.push(s);
        }
    }
    let chosen: Vec<DVec2> = (0..150).map(|k| posts[k * posts.len() / 150]).collect();
    b.part("lamp_posts", 4);
    for p in &chosen {
        pole(&mut b, DVec3::new(p.x, 0.0, p.y), 0.08, 5.0, 8);
    }
    b.part("lamp_heads", 5);
    for p in &chosen {
        cuboid(
            &mut b,
            [p.x - 0.12, 4.95, p.y - 0.25],
            [p.x + 0.12, 5.1, p.y + 0.25],
            [1, 1, 1],
        );
    }

    b.part("street", 6);
    let g = |x: f64, z: f64| DVec3::new(x, 0.0, z);
    b.poly(
        &[g(-12.0, -12.0), g(144.0, -12.0), g(144.0, 108.0)],
        DVec3::Y,
    );
    b.poly(
        &[g(-12.0, -12.0), g(144.0, 108.0), g(-12.0, 108.0)],
        DVec3::Y,
    );
    scene(b.mesh("city_block"), materials, Vec::new())
}

/// An open-bottomed pole of `sides` sides standing at `base`: side
/// triangles with smooth radial normals, a polygon cap (with the builder's
/// flat normals).
fn pole(b: &mut Builder, base: DVec3, radius: f64, height: f64, sides: usize) {
    let dir = |k: usize| {
        let a = TAU * k as f64 / sides as f64;
        DVec3::new(a.cos(), 0.0, a.sin())
    };
    let up = DVec3::Y * height;
    for k in 0..sides {
        let (d0, d1) = (dir(k), dir((k + 1) % sides));
        let (p0, p1) = (base + d0 * radius, base + d1 * radius);
        b.smooth_tri([(p0, d0), (p0 + up, d0), (p1 + up, d1)]);
        b.smooth_tri([(p0, d0), (p1 + up, d1), (p1, d1)]);
    }
    let cap: Vec<DVec3> = (0..sides).map(|k| base + up + dir(k) * radius).collect();
    b.poly(&cap, DVec3::Y);
}

// ---------------------------------------------------------------------------
// 5. A skinned, animated tube

/// Length of [`bent_tube`] along y; its elbow joint is at half of it.
pub const TUBE_LENGTH: f32 = 6.0;

/// A skinned tube bending 90° at its elbow, like a character's arm: a
/// capped cylinder of radius 0.5 along y from 0 to 6, 24 sides × 60
/// segments (2,928 triangles, smooth normals, flat caps), skinned to three
/// joints `root` (y = 0), `elbow` (y = 3) and `end` (y = 6, a leaf), with
/// linear-blend weights between root and elbow over 20% of the length
/// around the elbow (a smoothstep from y = 2.4 to 3.6) and inverse bind
/// matrices. Nodes: 0 `tube` (mesh and skin), 1 `root` → 2 `elbow` → 3
/// `end`; roots 0 and 1. One animation, `bend`: the elbow's rotation about
/// z from 0° to 90° in 31 linear keys at 30 fps (1 s), so that at its end
/// the tube's tip is at (−3, 3, 0).
///
/// Stresses: a level of detail judged posed (the elbow's outer side), not
/// only at rest.
pub fn bent_tube() -> Scene {
    const SIDES: usize = 24;
    const SEGMENTS: usize = 60;
    let (len, radius) = (f64::from(TUBE_LENGTH), 0.5);
    let mut b = Builder::new(false, false);
    b.part("tube", 0);
    let ring = |j: usize, k: usize| {
        let a = TAU * (k % SIDES) as f64 / SIDES as f64;
        let n = DVec3::new(a.cos(), 0.0, -a.sin());
        (
            n * radius + DVec3::Y * (len * j as f64 / SEGMENTS as f64),
            n,
        )
    };
    for j in 0..SEGMENTS {
        for k in 0..SIDES {
            let (a, bb, c, d) = (
                ring(j, k),
                ring(j, k + 1),
                ring(j + 1, k + 1),
                ring(j + 1, k),
            );
            b.smooth_tri([a, bb, c]);
            b.smooth_tri([a, c, d]);
        }
    }
    for (j, n) in [(0, DVec3::NEG_Y), (SEGMENTS, DVec3::Y)] {
        let center = DVec3::Y * (len * j as f64 / SEGMENTS as f64);
        for k in 0..SIDES {
            b.smooth_tri([(center, n), (ring(j, k).0, n), (ring(j, k + 1).0, n)]);
        }
    }
    let mut mesh = b.mesh("tube");
    // One skin entry per position: root and elbow blended by height.
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for p in &mesh.positions {
        let t = ((p[1] - 0.4 * TUBE_LENGTH) / (0.2 * TUBE_LENGTH)).clamp(0.0, 1.0);
        let w = t * t * (3.0 - 2.0 * t);
        // Unused slots name joint 0 (the validator warns about a joint
        // named with weight 0).
        let (j, wt) = match w {
            0.0 => ([0, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            1.0 => ([1, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            _ => ([0, 1, 0, 0], [1.0 - w, w, 0.0, 0.0]),
        };
        joints.extend_from_slice(&j);
        weights.extend_from_slice(&wt);
    }
    mesh.skinning = Some(Skinning {
        influences: 4,
        joints,
        weights,
        indices: mesh.faces.indices.clone(),
        weight_format: ComponentFormat::F32,
        joint_format: ComponentFormat::U8,
    });
    let translate = |y: f32| {
        let mut m = IDENTITY;
        m[13] = y;
        m
    };
    let half = 0.5 * TUBE_LENGTH;
    let nodes = vec![
        Node {
            name: "tube".into(),
            mesh: Some(0),
            skin: Some(0),
            ..Node::default()
        },
        Node {
            name: "root".into(),
            children: vec![2],
            ..Node::default()
        },
        Node {
            name: "elbow".into(),
            matrix: translate(half),
            children: vec![3],
            ..Node::default()
        },
        Node {
            name: "end".into(),
            matrix: translate(half),
            ..Node::default()
        },
    ];
    let keys = 31;
    let times: Vec<f32> = (0..keys).map(|k| k as f32 / 30.0).collect();
    let values: Vec<f32> = (0..keys)
        .flat_map(|k| {
            let half_angle = 0.25 * PI * k as f64 / (keys - 1) as f64;
            [0.0, 0.0, half_angle.sin() as f32, half_angle.cos() as f32]
        })
        .collect();
    let mut s = scene(mesh, vec![material("skin", [0.8, 0.6, 0.5])], Vec::new());
    s.nodes = nodes;
    s.roots = vec![0, 1];
    s.skins = vec![Skin {
        name: "arm".into(),
        joints: vec![1, 2, 3],
        inverse_bind_matrices: vec![IDENTITY, translate(-half), translate(-TUBE_LENGTH)],
        skeleton: Some(1),
    }];
    s.animations = vec![Animation {
        name: "bend".into(),
        channels: 1,
        duration: times[keys - 1],
        tracks: vec![Track {
            node: 2,
            path: TrackPath::Rotation,
            interpolation: Interpolation::Linear,
            times,
            values,
        }],
    }];
    s
}

// ---------------------------------------------------------------------------
// 6. A terrain with far outliers

/// The height [`outlier_terrain`] gives its outliers: far away, as broken
/// exporters write uninitialized or sentinel coordinates.
pub const OUTLIER_HEIGHT: f32 = -1e30;

/// An open height field of `n × n` vertices (at least 2; 100 × 100 m, y
/// up, smooth hills up to about ±7 m), `2 (n − 1)²` triangles, one part,
/// no attributes; with `outliers` of its interior vertices (chosen at
/// random, the same ones for the same `n`, see [`terrain_outliers`])
/// moved to height [`OUTLIER_HEIGHT`]. `outlier_terrain(n, 0)` is the same
/// terrain without outliers, vertex for vertex.
///
/// Stresses: normalization and error reports that one far vertex must not
/// dominate.
pub fn outlier_terrain(n: usize, outliers: usize) -> Scene {
    let n = n.max(2);
    let mut positions: Vec<[f32; 3]> = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (x, z) = (
                100.0 * i as f64 / (n - 1) as f64,
                100.0 * j as f64 / (n - 1) as f64,
            );
            let y = 4.0 * (0.07 * x).sin() * (0.05 * z + 0.3).cos()
                + 2.0 * (0.13 * x + 0.11 * z).sin()
                + 0.8 * (0.31 * z - 0.17 * x).cos();
            positions.push([x as f32, y as f32, z as f32]);
        }
    }
    for v in terrain_outliers(n, outliers) {
        positions[v as usize][1] = OUTLIER_HEIGHT;
    }
    let mut mesh = Mesh::from_triangles(positions, &height_field_triangles(n));
    mesh.name = "terrain".into();
    mesh.parts[0] = Part {
        name: "terrain".into(),
        material: Some(0),
    };
    scene(
        mesh,
        vec![material("ground", [0.35, 0.42, 0.25])],
        Vec::new(),
    )
}

/// The triangles of a height field of `n × n` vertices in rows of `n`
/// (vertex `j · n + i` at column `i`, row `j`; x along columns, z along
/// rows): two a cell, `2 (n − 1)²` in all, wound to face +y.
pub fn height_field_triangles(n: usize) -> Vec<u32> {
    let id = |i: usize, j: usize| (j * n + i) as u32;
    let mut indices = Vec::with_capacity(6 * n.saturating_sub(1).pow(2));
    for j in 0..n.saturating_sub(1) {
        for i in 0..n - 1 {
            indices.extend_from_slice(&[id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
            indices.extend_from_slice(&[id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
        }
    }
    indices
}

/// The vertices [`outlier_terrain`] moves far away: `outliers` distinct
/// interior vertices (at most all of them), in the order chosen.
pub fn terrain_outliers(n: usize, outliers: usize) -> Vec<u32> {
    let n = n.max(2);
    let interior = (n - 2) * (n - 2);
    let mut rng = SplitMix64(0x0071_1e55);
    let mut out: Vec<u32> = Vec::new();
    while out.len() < outliers.min(interior) {
        let k = (rng.next_u64() % interior as u64) as usize;
        let v = ((k / (n - 2) + 1) * n + k % (n - 2) + 1) as u32;
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

// ---------------------------------------------------------------------------
// 7. A texture atlas of many small islands

/// Cells along each cube face of [`uv_fold_mesh`].
const FOLD_CELLS: usize = 48;
/// Cells along each side of one of [`uv_fold_mesh`]'s charts.
const FOLD_CHART: usize = 8;
/// Atlas slots along each side of [`uv_fold_mesh`]'s texture.
const FOLD_SLOTS: usize = 15;
/// Gutter around each island, as a fraction of its slot.
const FOLD_GUTTER: f64 = 0.12;

/// A textured bumpy ball whose texture is an atlas of 216 small islands:
/// a cube sphere of six 48 × 48 grids (27,648 triangles, closed, smooth
/// normals without seams), each cube face cut into 6 × 6 charts of 8 × 8
/// cells, every chart its own UV island in a 15 × 15 grid of atlas slots
/// with gutters (12% of a slot on each side) between them (the islands
/// of three cube faces are mirrored, as atlases often have them; none is
/// folded). The 512 × 512
/// base-color texture gives each island its own color and pattern
/// (checks, stripes either way, diagonals) and paints the gutters black.
/// One part, one material.
///
/// Stresses: keeping the input's UVs. Each island is bounded by UV seams,
/// so at 1% (276 triangles for 216 islands) a simplifier that keeps the
/// UVs must tear the seams or fold UV triangles across the gutters (black
/// shows), while at 50% it can keep every island whole: the case for
/// re-baking chosen per file.
pub fn uv_fold_mesh() -> Scene {
    const N: usize = FOLD_CELLS;
    let charts = N / FOLD_CHART;
    let point = |q: [usize; 3]| {
        let c = DVec3::from(q.map(|x| 2.0 * x as f64 / N as f64 - 1.0));
        let d = c.normalize();
        let bump = (4.0 * d.x + 1.0).sin() * (5.0 * d.y).sin() * (3.0 * d.z + 0.5).sin()
            + 0.5 * (9.0 * d.x - 7.0 * d.z).sin() * (8.0 * d.y + 0.3).cos();
        d * (1.0 + 0.06 * bump)
    };
    let slot = 1.0 / FOLD_SLOTS as f64;
    let island_uv = |chart: usize, lu: usize, lv: usize| {
        let (sx, sy) = ((chart % FOLD_SLOTS) as f64, (chart / FOLD_SLOTS) as f64);
        let span = 1.0 - 2.0 * FOLD_GUTTER;
        let f = |x: usize| x as f64 / FOLD_CHART as f64;
        [
            (sx + FOLD_GUTTER + f(lu) * span) * slot,
            (sy + FOLD_GUTTER + f(lv) * span) * slot,
        ]
    };
    let mut b = Builder::new(false, false);
    b.part("ball", 0);
    let mut cube_face = 0;
    for ax in 0..3 {
        for side in [0, N] {
            let (u, v) = ((ax + 1) % 3, (ax + 2) % 3);
            for i in 0..N {
                for j in 0..N {
                    let chart =
                        cube_face * charts * charts + (i / FOLD_CHART) * charts + j / FOLD_CHART;
                    let corner = |di: usize, dj: usize| {
                        let mut q = [0; 3];
                        q[ax] = side;
                        q[u] = i + di;
                        q[v] = j + dj;
                        let uv = island_uv(chart, i % FOLD_CHART + di, j % FOLD_CHART + dj);
                        Corner {
                            p: point(q),
                            uv: Some(uv),
                            n: None,
                        }
                    };
                    let [c00, c10, c11, c01] =
                        [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    for tri in [[c00, c10, c11], [c00, c11, c01]] {
                        let outward = (tri[1].p - tri[0].p)
                            .cross(tri[2].p - tri[0].p)
                            .dot(tri[0].p)
                            > 0.0;
                        b.face(&if outward {
                            tri
                        } else {
                            [tri[0], tri[2], tri[1]]
                        });
                    }
                }
            }
            cube_face += 1;
        }
    }
    let mut mesh = b.mesh("uv_fold_ball");
    smooth_normals(&mut mesh);
    let islands = 6 * charts * charts;
    let texture = png_texture("island_atlas", 512, 512, |x, y| {
        let (u, v) = ((x as f64 + 0.5) / 512.0, (y as f64 + 0.5) / 512.0);
        let (sx, sy) = ((u / slot) as usize, (v / slot) as usize);
        let chart = sy * FOLD_SLOTS + sx;
        let (lu, lv) = (u / slot - sx as f64, v / slot - sy as f64);
        let inside = |l: f64| (FOLD_GUTTER..=1.0 - FOLD_GUTTER).contains(&l);
        if chart >= islands || !inside(lu) || !inside(lv) {
            return [0, 0, 0];
        }
        let hue = (chart as f64 * 0.618_033_988_75).fract();
        let rgb = [0.0, 1.0 / 3.0, 2.0 / 3.0].map(|o| 0.55 + 0.45 * (TAU * (hue + o)).cos());
        let (a, c) = ((lu * 6.0) as usize, (lv * 6.0) as usize);
        let dark = match chart % 4 {
            0 => (a + c) % 2 == 0,
            1 => a % 2 == 0,
            2 => c % 2 == 0,
            _ => ((lu + lv) * 4.0) as usize % 2 == 0,
        };
        let k = if dark { 0.45 } else { 1.0 };
        rgb.map(|x| (255.0 * x * k).round() as u8)
    });
    let mat = Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        base_color: [1.0; 4],
        ..material("atlas", [1.0; 3])
    };
    scene(mesh, vec![mat], vec![texture])
}

// ---------------------------------------------------------------------------
// 8. A double-sided sheet

/// A waving flag as SketchUp exports an open sheet: a 3 × 2 m curved
/// surface of 60 × 40 cells (4,800 triangles) written twice, every face
/// once more reversed (9,600 triangles), all in one part with one
/// single-sided material carrying a 128 × 64 flag texture. The first 4,800
/// faces are the front; face `f + 4800` is face `f` reversed (same
/// positions, corners in opposite order from the same first corner), its
/// normals negated and its UVs mirrored (`u → 1 − u`), so that the back
/// shows the flag the right way round. Smooth normals, UV `v = 0` at the
/// top edge.
///
/// Stresses: twin faces (each edge has four faces), which must be
/// simplified once and drawn from both sides.
pub fn double_sided_sheet() -> Scene {
    const NX: usize = 60;
    const NY: usize = 40;
    // z = f(x, y): a wave growing away from the pole at x = 0.
    let f =
        |x: f64, y: f64| 0.2 * (x / 3.0) * (PI * x / 1.5 + 0.5 * y).sin() + 0.05 * (2.3 * y).sin();
    let grad = |x: f64, y: f64| {
        let a = PI * x / 1.5 + 0.5 * y;
        DVec2::new(
            0.2 / 3.0 * a.sin() + 0.2 * (x / 3.0) * (PI / 1.5) * a.cos(),
            0.2 * (x / 3.0) * 0.5 * a.cos() + 0.05 * 2.3 * (2.3 * y).cos(),
        )
    };
    let corner = |i: usize, j: usize, back: bool| {
        let (x, y) = (3.0 * i as f64 / NX as f64, 2.0 * j as f64 / NY as f64);
        let g = grad(x, y);
        let n = DVec3::new(-g.x, -g.y, 1.0).normalize();
        let u = x / 3.0;
        Corner {
            p: DVec3::new(x, y, f(x, y)),
            uv: Some([if back { 1.0 - u } else { u }, 1.0 - y / 2.0]),
            n: Some(if back { -n } else { n }),
        }
    };
    let mut b = Builder::new(false, false);
    b.part("flag", 0);
    for back in [false, true] {
        for j in 0..NY {
            for i in 0..NX {
                let c = |di, dj| corner(i + di, j + dj, back);
                for [p, q, r] in [[c(0, 0), c(1, 0), c(1, 1)], [c(0, 0), c(1, 1), c(0, 1)]] {
                    b.face(&if back { [p, r, q] } else { [p, q, r] });
                }
            }
        }
    }
    let texture = png_texture("flag", 128, 64, |x, y| {
        let (dx, dy) = (x as f64 - 30.0, y as f64 - 32.0);
        if dx.hypot(dy) < 16.0 {
            [250, 205, 40]
        } else if x < 12 {
            [20, 60, 150]
        } else {
            [[200, 30, 40], [245, 245, 245], [30, 120, 60]][(y / 22) as usize]
        }
    });
    let mat = Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        base_color: [1.0; 4],
        ..material("flag_cloth", [1.0; 3])
    };
    scene(b.mesh("double_sided_sheet"), vec![mat], vec![texture])
}

/// A latitude-longitude patch of a sphere of `radius` at `center`, from
/// latitude `lat0` to `lat1` (radians, 0 at the equator), `around` ×
/// `up` quads as triangles, UVs mapping the patch onto `[u0, u1] × [0, 1]`
/// of the texture, wound outward, or inward with `inward`.
#[allow(clippy::too_many_arguments)]
fn sphere_patch(
    center: DVec3,
    radius: f64,
    (lat0, lat1): (f64, f64),
    around: usize,
    up: usize,
    (u0, u1): (f64, f64),
    inward: bool,
    material: u32,
) -> Mesh {
    let mut positions = Vec::new();
    let mut uv = Vec::new();
    let mut faces = Faces::new();
    let mut uv_idx = Vec::new();
    for j in 0..=up {
        let lat = lerp(lat0, lat1, j as f64 / up as f64);
        for i in 0..=around {
            let lon = TAU * i as f64 / around as f64;
            let d = DVec3::new(lat.cos() * lon.cos(), lat.sin(), lat.cos() * lon.sin());
            positions.push((center + radius * d).as_vec3().to_array());
            uv.extend_from_slice(&[
                lerp(u0, u1, i as f64 / around as f64) as f32,
                (j as f64 / up as f64) as f32,
            ]);
        }
    }
    let id = |i: usize, j: usize| (j * (around + 1) + i) as u32;
    for j in 0..up {
        for i in 0..around {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            for t in [[a, c, b], [a, d, c]] {
                let t = if inward { [t[0], t[2], t[1]] } else { t };
                faces.push(&t);
                uv_idx.extend_from_slice(&t);
            }
        }
    }
    // Seam and pole vertices are welded by position; the UVs keep their
    // own values per corner.
    let mut m = Mesh::from_polygons(positions, faces);
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices: uv_idx,
        format: ComponentFormat::F32,
    });
    m.parts[0].material = Some(material);
    m
}

/// A sky dome over small parts: an inward-facing textured hemisphere of
/// radius 10 (3,072 triangles) enclosing `parts` small textured spheres
/// (radius 0.3 to 0.6, 144 triangles each), every one its own mesh and
/// node, all sampling one 256 × 128 texture of smooth gradients (the dome
/// its left half, the spheres its right half).
///
/// Stresses: one budget over a whole file. Budgets per mesh cut the dome,
/// most of what is seen, as hard as each small part; a budget over the
/// file spends triangles where the surface needs them.
pub fn domed_scene(parts: usize) -> Scene {
    let mut meshes = vec![sphere_patch(
        DVec3::ZERO,
        10.0,
        (0.0, FRAC_PI_2 * 0.98),
        48,
        32,
        (0.0, 0.5),
        true,
        0,
    )];
    meshes[0].name = "dome".into();
    let mut rng = SplitMix64(0xd0e5);
    for k in 0..parts {
        let (x, z) = (rng.next_f64() * 12.0 - 6.0, rng.next_f64() * 12.0 - 6.0);
        let r = 0.3 + 0.3 * rng.next_f64();
        let mut m = sphere_patch(
            DVec3::new(x, r, z),
            r,
            (-FRAC_PI_2, FRAC_PI_2),
            12,
            6,
            (0.5, 1.0),
            false,
            1,
        );
        m.name = format!("part{k}");
        meshes.push(m);
    }
    // Smooth gradients, so that the texture Chamfer distance's sampling
    // floor stays well below what a LOD changes.
    let texture = png_texture("sky_and_parts", 256, 128, |x, y| {
        if x < 128 {
            // Sky: a hue that turns around the dome, lighter upwards.
            [(x * 2) as u8, (60 + y) as u8, (250 - y) as u8]
        } else {
            let u = x - 128;
            [(250 - u) as u8, (y * 2) as u8, (40 + u) as u8]
        }
    });
    let mut scene = Scene {
        meshes,
        materials: vec![textured("sky"), textured("paint")],
        textures: vec![texture],
        ..Scene::default()
    };
    for m in 0..scene.meshes.len() {
        scene.nodes.push(Node {
            name: scene.meshes[m].name.clone(),
            mesh: Some(m as u32),
            ..Node::default()
        });
        scene.roots.push(m as u32);
    }
    scene
}

/// [`textured`], alpha-tested at 0.5 and double-sided, as cards and cut-out
/// sheets are.
fn alpha_tested(name: &str) -> Material {
    Material {
        alpha_mode: AlphaMode::Mask,
        alpha_cutoff: 0.5,
        double_sided: true,
        ..textured(name)
    }
}

/// A white material sampling texture 0 through UV set 0.
fn textured(name: &str) -> Material {
    Material {
        base_color: [1.0; 4],
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..material(name, [1.0, 1.0, 1.0])
    }
}

// ---------------------------------------------------------------------------
// A blend-shape rig

/// A sphere of radius 1 (`quad_sphere(n)` triangulated: `12·n²`
/// triangles) with `targets` position morph targets, each a smooth bump of
/// height 0.2 over 15° around its own direction (spread evenly by a
/// golden-angle spiral), zero elsewhere, the way a face rig's blend
/// shapes each move one small region; and an animation (`"targets"`) that
/// shows each target at full weight in turn: target `k` peaks at
/// `k + 1` seconds, all weights are 0 at 0 s. Stresses fitting many sparse
/// delta sets and keeping what only a target shows
/// (`wildlod compare --animation 0 --fps 1`).
pub fn morph_sphere(n: usize, targets: usize) -> Scene {
    let mut m = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::quad_sphere(n));
    m.name = "morph_sphere".into();
    m.attributes.retain(|a| a.semantic != Semantic::TexCoord(0));
    let golden = PI * (3.0 - 5f64.sqrt());
    for k in 0..targets {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / targets as f64;
        let r = (1.0 - z * z).sqrt();
        let dir = DVec3::new(
            r * (golden * k as f64).cos(),
            r * (golden * k as f64).sin(),
            z,
        );
        let values: Vec<f32> = m
            .positions
            .iter()
            .flat_map(|p| {
                let p = DVec3::from(p.map(f64::from));
                let len = p.length();
                let angle = (p.dot(dir) / len).clamp(-1.0, 1.0).acos().to_degrees();
                let h = if angle < 15.0 {
                    0.2 * (1.0 - angle / 15.0).powi(2)
                } else {
                    0.0
                };
                (p / len * h).to_array().map(|c| canonical(c as f32))
            })
            .collect();
        m.attributes.push(Attribute {
            semantic: Semantic::Morph {
                target: k as u32,
                channel: wildlod_mesh::MorphChannel::Position,
            },
            components: 3,
            values,
            indices: m.faces.indices.clone(),
            format: ComponentFormat::F32,
        });
    }
    let mut scene = Scene::from_mesh(m);
    let keys = targets + 1;
    let mut values = vec![0.0f32; keys * targets];
    for k in 0..targets {
        values[(k + 1) * targets + k] = 1.0;
    }
    scene.animations.push(Animation {
        name: "targets".into(),
        channels: 1,
        duration: targets as f32,
        tracks: vec![Track {
            node: 0,
            path: TrackPath::Weights,
            interpolation: Interpolation::Linear,
            times: (0..keys).map(|t| t as f32).collect(),
            values,
        }],
    });
    scene
}

// ---------------------------------------------------------------------------
// Foliage

/// A tree as game assets draw one: a tapered trunk with four branches
/// (untextured bark, 16-sided cylinders) and a crown of `cards` leaf cards,
/// each a 0.35 m square of two triangles at a random place in an ellipsoid
/// and a random orientation, all showing one 128 × 128 leaf texture whose
/// alpha cuts the leaf shape out (`MASK`, cutoff 0.5, double-sided, one
/// part).
///
/// Stresses: hundreds of tiny disconnected parts whose whole look is their
/// texture's alpha. A card stretched across the crown (merged by a virtual
/// edge) or its UVs moved draws leaves where none were; a LOD draws fewer
/// cards, each whole.
pub fn foliage_tree(cards: usize) -> Scene {
    let mut b = Builder::new(false, false);
    b.part("bark", 0);
    let limb = |b: &mut Builder, from: DVec3, to: DVec3, r0: f64, r1: f64, rings: usize| {
        let axis_dir = (to - from).normalize();
        let side = if axis_dir.y.abs() < 0.9 {
            DVec3::Y
        } else {
            DVec3::X
        };
        let e1 = axis_dir.cross(side).normalize();
        let e2 = axis_dir.cross(e1);
        let at = |i: usize, j: usize| {
            let t = j as f64 / rings as f64;
            let a = TAU * (i % 16) as f64 / 16.0;
            let r = lerp(r0, r1, t);
            lerp3(from, to, t) + (e1 * a.cos() + e2 * a.sin()) * r
        };
        for j in 0..rings {
            for i in 0..16 {
                let n = |i: usize| {
                    let a = TAU * (i % 16) as f64 / 16.0;
                    e1 * a.cos() + e2 * a.sin()
                };
                b.smooth_tri([
                    (at(i, j), n(i)),
                    (at(i + 1, j), n(i + 1)),
                    (at(i + 1, j + 1), n(i + 1)),
                ]);
                b.smooth_tri([
                    (at(i, j), n(i)),
                    (at(i + 1, j + 1), n(i + 1)),
                    (at(i, j + 1), n(i)),
                ]);
            }
        }
    };
    limb(
        &mut b,
        DVec3::ZERO,
        DVec3::new(0.0, 3.0, 0.0),
        0.25,
        0.15,
        12,
    );
    for k in 0..4 {
        let a = TAU * (k as f64 + 0.3) / 4.0;
        let from = DVec3::new(0.0, 2.2 + 0.2 * k as f64, 0.0);
        let to = DVec3::new(1.6 * a.cos(), 3.4 + 0.3 * k as f64, 1.6 * a.sin());
        limb(&mut b, from, to, 0.08, 0.03, 6);
    }
    b.part("leaves", 1);
    let mut rng = SplitMix64(0x1eaf);
    for _ in 0..cards {
        // A point in the crown's ellipsoid (rejection sampling).
        let c = loop {
            let q = DVec3::new(
                rng.next_f64() * 2.0 - 1.0,
                rng.next_f64() * 2.0 - 1.0,
                rng.next_f64() * 2.0 - 1.0,
            );
            if q.length_squared() <= 1.0 {
                break DVec3::new(2.0 * q.x, 3.8 + 1.4 * q.y, 2.0 * q.z);
            }
        };
        let n = loop {
            let q = DVec3::new(
                rng.next_f64() * 2.0 - 1.0,
                rng.next_f64() * 2.0 - 1.0,
                rng.next_f64() * 2.0 - 1.0,
            );
            let l = q.length();
            if l > 0.1 && l <= 1.0 {
                break q / l;
            }
        };
        let side = if n.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
        let u = n.cross(side).normalize() * 0.175;
        let v = n.cross(u);
        let corner = |su: f64, sv: f64, uv: [f64; 2]| Corner {
            p: c + u * su + v * sv,
            uv: Some(uv),
            n: Some(n),
        };
        let q = [
            corner(-1.0, -1.0, [0.0, 1.0]),
            corner(1.0, -1.0, [1.0, 1.0]),
            corner(1.0, 1.0, [1.0, 0.0]),
            corner(-1.0, 1.0, [0.0, 0.0]),
        ];
        b.face(&[q[0], q[1], q[2]]);
        b.face(&[q[0], q[2], q[3]]);
    }
    // A leaf along the diagonal: an ellipse, a darker midrib, transparent
    // around it.
    let leaf = png_texture_rgba("leaf", 128, 128, |x, y| {
        let (s, t) = ((x as f64 + 0.5) / 64.0 - 1.0, (y as f64 + 0.5) / 64.0 - 1.0);
        let (a, b) = ((s + t) * FRAC_1_SQRT_2, (s - t) * FRAC_1_SQRT_2);
        let inside = (a / 0.95).powi(2) + (b / 0.42).powi(2) <= 1.0;
        let rib = b.abs() < 0.03;
        let shade = (40.0 * (1.0 - a)) as u8;
        match (inside, rib) {
            (false, _) => [30, 90, 30, 0],
            (true, true) => [120, 160, 60, 255],
            (true, false) => [40 + shade, 120 + shade / 2, 35, 255],
        }
    });
    let leaves = alpha_tested("leaves");
    scene(
        b.mesh("tree"),
        vec![material("bark", [0.35, 0.25, 0.15]), leaves],
        vec![leaf],
    )
}

/// A chain-link fence: a 120° arc of radius 5 and height 2 with a gentle
/// wave, 96 × 16 quads as triangles, its UVs one unique chart over a
/// 1024 × 256 image of diagonal wires 3 texels wide every 24 texels, opaque
/// on the wires and transparent between them (`MASK`, cutoff 0.5,
/// double-sided), the same grey everywhere as painters dilate colour under
/// transparent texels.
///
/// Stresses: what an alpha test shows. Averaged to a smaller atlas, thin
/// wires' alpha falls under the cutoff and the fence vanishes, while its
/// colour, and every colour metric, say nothing changed.
pub fn chain_link_fence() -> Scene {
    const NX: usize = 96;
    const NY: usize = 16;
    let mut b = Builder::new(false, false);
    b.part("fence", 0);
    let corner = |i: usize, j: usize| {
        let (u, v) = (i as f64 / NX as f64, j as f64 / NY as f64);
        let a = (u - 0.5) * TAU / 3.0;
        let r = 5.0 + 0.15 * (3.0 * TAU * u).sin();
        let p = DVec3::new(r * a.sin(), 2.0 * v, r * a.cos());
        let n = DVec3::new(a.sin(), 0.0, a.cos());
        Corner {
            p,
            uv: Some([u, 1.0 - v]),
            n: Some(n),
        }
    };
    for j in 0..NY {
        for i in 0..NX {
            let c = |di, dj| corner(i + di, j + dj);
            b.face(&[c(0, 0), c(1, 0), c(1, 1)]);
            b.face(&[c(0, 0), c(1, 1), c(0, 1)]);
        }
    }
    let wires = png_texture_rgba("chain_link", 1024, 256, |x, y| {
        let on = |t: u32| t % 24 < 3;
        let alpha = if on(x + y) || on(x + 1024 - y) {
            255
        } else {
            0
        };
        [150, 152, 158, alpha]
    });
    let mat = alpha_tested("chain_link");
    scene(b.mesh("fence"), vec![mat], vec![wires])
}

// ---------------------------------------------------------------------------
// A wall with decals

/// The gap between [`decal_wall`]'s decals and its wall, in metres.
pub const DECAL_GAP: f64 = 0.002;

/// The height of [`decal_wall`]'s wall in front of the plane z = 0.
pub fn decal_wall_height(x: f64, y: f64) -> f64 {
    0.05 * (TAU * x / 4.0 + 0.5).sin() * (TAU * y / 3.0).sin()
        + 0.006 * (TAU * x / 1.1).sin() * (TAU * y / 0.9).cos()
}

/// A plastered wall with 24 decals, as environment art places them: a
/// 10 × 6 m wall (x right, y up, facing +z) of 100 × 60 quads whose surface
/// waves by up to 5.6 cm ([`decal_wall_height`]), and 24 mesh decals
/// (posters, stains, signs) 0.3 to 0.8 m wide, each its own grid of cells
/// at most 0.1 m wide conforming to the wall [`DECAL_GAP`] (2 mm) in front
/// of it along z, facing the same way. Parts "wall" (material 0, grey) and
/// "decals" (material 1, red, opaque). About 12,000 + 1,900 triangles.
///
/// Stresses: sheets lying on another part. Nothing ties a decal to the
/// wall under it, and at 10% the wall moves by more than the gap: the
/// decals must move with it rather than sink behind it.
pub fn decal_wall() -> Scene {
    const NX: usize = 100;
    const NY: usize = 60;
    let mut b = Builder::new(false, false);
    let at = |x: f64, y: f64, lift: f64| Corner {
        p: DVec3::new(x, y, decal_wall_height(x, y) + lift),
        uv: None,
        n: None,
    };
    b.part("wall", 0);
    for j in 0..NY {
        for i in 0..NX {
            let (x0, y0) = (i as f64 * 0.1, j as f64 * 0.1);
            let (x1, y1) = (x0 + 0.1, y0 + 0.1);
            b.face(&[
                at(x0, y0, 0.0),
                at(x1, y0, 0.0),
                at(x1, y1, 0.0),
                at(x0, y1, 0.0),
            ]);
        }
    }
    b.part("decals", 1);
    let mut rng = SplitMix64(0xdeca1);
    for _ in 0..24 {
        let w = 0.3 + 0.5 * rng.next_f64();
        let h = 0.3 + 0.5 * rng.next_f64();
        let x0 = 0.2 + (9.6 - w) * rng.next_f64();
        let y0 = 0.2 + (5.6 - h) * rng.next_f64();
        let (nx, ny) = ((w / 0.1).ceil() as usize, (h / 0.1).ceil() as usize);
        let c = |i: usize, j: usize| {
            at(
                x0 + w * i as f64 / nx as f64,
                y0 + h * j as f64 / ny as f64,
                DECAL_GAP,
            )
        };
        for j in 0..ny {
            for i in 0..nx {
                b.face(&[c(i, j), c(i + 1, j), c(i + 1, j + 1), c(i, j + 1)]);
            }
        }
    }
    scene(
        b.mesh("decal_wall"),
        vec![
            material("wall", [0.7, 0.7, 0.68]),
            material("decal", [0.8, 0.1, 0.1]),
        ],
        Vec::new(),
    )
}

/// [`png_texture`] with an alpha channel.
fn png_texture_rgba(
    name: &str,
    width: u32,
    height: u32,
    pixel: impl Fn(u32, u32) -> [u8; 4],
) -> Texture {
    let img = image::RgbaImage::from_fn(width, height, |x, y| image::Rgba(pixel(x, y)));
    embedded_png(name, image::DynamicImage::ImageRgba8(img))
}

/// The sides between a filled and an empty unit cell of `filled`, over the
/// cells `lo..=hi` on each axis, in cell order: each side's four corners
/// (counter-clockwise seen from outside) and the axis direction it faces.
/// What a voxel editor exports, before welding.
pub fn voxel_sides(
    filled: impl Fn(i32, i32, i32) -> bool,
    lo: [i32; 3],
    hi: [i32; 3],
) -> Vec<([[i32; 3]; 4], [i32; 3])> {
    const SIDES: [([i32; 3], [[i32; 3]; 4]); 6] = [
        ([1, 0, 0], [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]]),
        ([-1, 0, 0], [[0, 0, 0], [0, 0, 1], [0, 1, 1], [0, 1, 0]]),
        ([0, 1, 0], [[0, 1, 0], [0, 1, 1], [1, 1, 1], [1, 1, 0]]),
        ([0, -1, 0], [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]]),
        ([0, 0, 1], [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]),
        ([0, 0, -1], [[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]]),
    ];
    let mut out = Vec::new();
    for x in lo[0]..=hi[0] {
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                if !filled(x, y, z) {
                    continue;
                }
                for (d, corners) in SIDES {
                    if !filled(x + d[0], y + d[1], z + d[2]) {
                        out.push((corners.map(|c| [x + c[0], y + c[1], z + c[2]]), d));
                    }
                }
            }
        }
    }
    out
}

/// A voxel torus, as voxel editors and grid remeshers export one: the unit
/// cubes whose corner nearest the origin lies within 6 of a circle of
/// radius 16, written as
/// the quads between a filled and an empty cell, each split into two
/// triangles, welded, in an order shuffled by `seed` (as an exporter's
/// hash order would): which of the many equal-cost collapses comes first
/// follows the order, and so does which one meets a degenerate face.
/// 10,416 triangles; every face is axis-aligned and the outline of every
/// flat region is a staircase.
///
/// Stresses: exactness on piecewise-flat surfaces. Half its triangles go
/// by merging coplanar faces alone (meshoptimizer, Blender and MeshLab are
/// exact at 50%); every edge of a staircase is a crease, and a straight
/// run collapsed onto a line leaves faces without area, which a later
/// collapse can give area again across a step's corner.
pub fn voxel_torus(seed: u64) -> Scene {
    let filled = |x: i32, y: i32, z: i32| {
        (f64::from(x).hypot(f64::from(y)) - 16.0).hypot(f64::from(z)) < 6.0
    };
    let mut quads = voxel_sides(filled, [-24, -24, -8], [24, 24, 8]);
    // Fisher–Yates.
    let mut rng = SplitMix64(seed);
    for k in (1..quads.len()).rev() {
        quads.swap(k, (rng.next_u64() % (k as u64 + 1)) as usize);
    }
    voxel_scene("voxel_torus", "voxels", quads)
}

/// One part of voxel sides (from [`voxel_sides`]), each cut into two
/// triangles wound along its facing, with one grey material.
fn voxel_scene(name: &str, part: &str, quads: Vec<([[i32; 3]; 4], [i32; 3])>) -> Scene {
    let mut b = Builder::new(false, false);
    b.part(part, 0);
    for (corners, facing) in quads {
        let p = corners.map(|c| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])));
        let facing = DVec3::new(
            f64::from(facing[0]),
            f64::from(facing[1]),
            f64::from(facing[2]),
        );
        b.poly(&[p[0], p[1], p[2]], facing);
        b.poly(&[p[0], p[2], p[3]], facing);
    }
    scene(
        b.mesh(name),
        vec![material(part, [0.6, 0.6, 0.65])],
        Vec::new(),
    )
}

/// A plate one voxel thick, `80 × 48` voxels, with 12 round holes of
/// radius 5 on a 4 × 3 grid cut as voxels: flat top and bottom, staircase
/// hole walls, every vertex at height 0 or 1; about 17,000 triangles.
///
/// Stresses: the rims between the flat faces and the walls. A vertex no
/// collapse has touched holds the top or bottom plane only by its few
/// input faces while the triangles it anchors grow large around it, so
/// memory quadrics alone let a wall's top and bottom rims merge at
/// mid-height, tilting the plate around them into streaks.
pub fn holed_voxel_plate() -> Scene {
    let filled = |x: i32, y: i32, z: i32| {
        if z != 0 || !(0..80).contains(&x) || !(0..48).contains(&y) {
            return false;
        }
        let (cx, cy) = (10 + 20 * (x / 20), 8 + 16 * (y / 16));
        let (dx, dy) = (f64::from(x - cx) + 0.5, f64::from(y - cy) + 0.5);
        dx.hypot(dy) > 5.0
    };
    let quads = voxel_sides(filled, [-1, -1, -1], [81, 49, 1]);
    voxel_scene("holed_voxel_plate", "plate", quads)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_arcs_are_exact_at_their_ends_and_symmetric() {
        assert_eq!(quarter(0, 24), (1.0, 0.0));
        assert_eq!(quarter(24, 24), (0.0, 1.0));
        for i in 0..=24 {
            let (c, s) = quarter(i, 24);
            let (c2, s2) = quarter(24 - i, 24);
            assert_eq!(
                (c.to_bits(), s.to_bits()),
                (s2.to_bits(), c2.to_bits()),
                "i = {i}"
            );
            let a = FRAC_PI_2 * i as f64 / 24.0;
            assert!((c - a.cos()).abs() < 1e-15 && (s - a.sin()).abs() < 1e-15);
        }
    }

    #[test]
    fn plane_normal_of_an_axis_aligned_quad_is_the_exact_axis() {
        // Coordinates whose differences round: the snap must remove the noise.
        let q = [
            DVec3::new(0.1, 0.7, 3.3),
            DVec3::new(0.1 + 0.2, 0.7, 3.3),
            DVec3::new(0.1 + 0.2, 0.7 + 0.3, 3.3),
            DVec3::new(0.1, 0.7 + 0.3, 3.3),
        ];
        assert_eq!(plane_normal(&q), DVec3::Z);
        let mut r = q;
        r.reverse();
        assert_eq!(plane_normal(&r), DVec3::NEG_Z);
    }

    #[test]
    fn box_uv_maps_in_world_units_with_v_down() {
        // A +z face: u = x, v = 1 − y; a −x face: u = z.
        assert_eq!(box_uv(DVec3::new(2.0, 3.0, 5.0), DVec3::Z), [2.0, -2.0]);
        assert_eq!(box_uv(DVec3::new(2.0, 3.0, 5.0), DVec3::NEG_X), [5.0, -2.0]);
        assert_eq!(box_uv(DVec3::new(2.0, 0.0, 5.0), DVec3::Y), [2.0, 6.0]);
    }

    #[test]
    fn grid_cells_tile_the_face_around_openings() {
        // A 2 × 1 face, one opening [0.5, 0.25]–[1.5, 0.75], lines every 0.5.
        let g = Grid::new([2.0, 1.0], 0.5, &[[0.5, 0.25, 1.5, 0.75]]);
        assert_eq!(g.s, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(g.t, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let openings = (0..g.rows())
            .flat_map(|j| (0..g.cols()).map(move |i| (i, j)))
            .filter(|&(i, j)| g.is_opening(i, j))
            .count();
        assert_eq!(openings, 4);
        // Wall cells cover 2 − 0.5 = 1.5; reveals: 4 sides of 2 cells each.
        let mut b = Builder::new(false, false);
        b.part("w", 0);
        let f = Frame {
            origin: DVec3::ZERO,
            along: DVec3::X,
            up: DVec3::Y,
        };
        g.cells(&mut b, &f, 0.0, false, f.out());
        let walls = b.faces.len();
        assert_eq!(walls, 16 - 4);
        g.reveals(&mut b, &f, 0.1);
        assert_eq!(b.faces.len() - walls, 8);
        let m = b.mesh("w");
        let area: f64 = (0..walls)
            .map(|k| {
                let f = m.faces.face(k);
                let p = |c: usize| DVec3::from(m.positions[f[c] as usize].map(f64::from));
                plane_normal(&[p(0), p(1), p(2), p(3)]).z
                    * 0.5
                    * (p(2) - p(0)).cross(p(3) - p(1)).length()
            })
            .sum();
        assert!((area - 1.5).abs() < 1e-6, "{area}");
    }

    #[test]
    fn zip_loops_fills_a_square_ring_without_overlap() {
        // Outer square of side 4, inner square of side 2 (rotated 45°, so
        // the angles interleave): the ring's area is 16 − 2.
        let outer = [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)];
        let inner = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
        let to3 = |l: &[(f64, f64)]| {
            l.iter()
                .map(|&(x, z)| DVec3::new(x, 0.0, z))
                .collect::<Vec<_>>()
        };
        let tris = zip_loops(&to3(&outer), &to3(&inner));
        assert_eq!(tris.len(), 8);
        let signed: Vec<f64> = tris
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).y)
            .collect();
        // All wound the same way, and they sum to the ring's area.
        assert!(signed.iter().all(|&a| a < 0.0) || signed.iter().all(|&a| a > 0.0));
        let total: f64 = signed.iter().map(|a| a.abs()).sum();
        assert!((total - 14.0).abs() < 1e-12, "{total}");
    }

    #[test]
    fn builder_shares_equal_positions_and_values_and_splits_normal_groups() {
        let mut b = Builder::new(false, false);
        b.part("p", 0);
        let c = |x: f64, n: DVec3| Corner {
            p: DVec3::new(x, 0.0, if x == 2.0 { 1.0 } else { 0.0 }),
            uv: Some([x, -0.0]),
            n: Some(n),
        };
        b.face(&[c(0.0, DVec3::Z), c(1.0, DVec3::Z), c(2.0, DVec3::Z)]);
        b.group += 1;
        b.face(&[c(0.0, DVec3::Z), c(2.0, DVec3::Z), c(1.0, DVec3::Z)]);
        let m = b.mesh("m");
        assert_eq!(m.positions.len(), 3);
        let uv = m.attribute(&Semantic::TexCoord(0)).expect("uv");
        assert_eq!(uv.value_count(), 3);
        assert_eq!(uv.values[1], 0.0, "−0 stored as 0");
        let n = m.attribute(&Semantic::Normal).expect("normals");
        assert_eq!(n.value_count(), 2, "one normal per group");
        assert_eq!(n.indices, vec![0, 0, 0, 1, 1, 1]);
    }
}
