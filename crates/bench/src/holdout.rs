//! Meshes made in code to check defaults on assets outside the corpus.
//!
//! The corpus is what every default was measured on, so a default can fit
//! it and nothing else. These meshes are of the corpus's kinds but none of
//! its files: smooth closed surfaces, machined parts (teeth, knurls, turned
//! profiles, hex prisms), scenes of many parts, a double-sided cloth, leaf
//! cards, an unwelded soup, quad meshes, UV-mapped surfaces with normals
//! (smooth, and hard at a prop's edges), and voxel shapes (every face
//! axis-aligned, every outline a staircase, as voxel editors and grid
//! remeshers export them), and kinds the corpus does not have: CAD parts
//! as exporters tessellate them (a perforated plate, embossed lettering),
//! an architectural interior of touching boxes, and a noisy scan with
//! holes and floating specks. They are written as OBJ under one folder per
//! category (`manifold`, `wild`, `quad`, `textured`, `voxel`, `cad`,
//! `architecture`, `scan`), the layout
//! `../shared/peers` reads, so the peers and
//! wildlod are scored on them exactly as on the corpus
//! (`docs/evaluation.md`, "Meshes made in code").
//!
//! The text is written here, not through `wildlod-io`: a check of the
//! product should not depend on the product's own writer.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;

use glam::DVec3;
use wildlod_testkit::SplitMix64;

/// One generated mesh: positions, polygons (0-based), and optionally one
/// UV per corner.
#[derive(Clone, Debug, Default)]
pub struct Generated {
    /// Category folder (`manifold`, `wild`, `quad`, `textured`, `voxel`,
    /// `cad`, `architecture`, `scan`).
    pub category: &'static str,
    /// File stem.
    pub name: &'static str,
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Polygons as vertex ids.
    pub faces: Vec<Vec<u32>>,
    /// UVs, and per face the UV id of each corner (empty: no UVs).
    pub uvs: Vec<[f64; 2]>,
    /// Per face, the UV ids of its corners.
    pub face_uvs: Vec<Vec<u32>>,
    /// Normals, and per face the normal id of each corner (empty: no
    /// normals).
    pub normals: Vec<DVec3>,
    /// Per face, the normal ids of its corners.
    pub face_normals: Vec<Vec<u32>>,
}

impl Generated {
    /// The mesh as OBJ text.
    pub fn to_obj(&self) -> String {
        let mut s = String::with_capacity(64 * (self.positions.len() + self.faces.len()));
        let _ = writeln!(s, "# wildlod holdout mesh {}/{}", self.category, self.name);
        for p in &self.positions {
            let _ = writeln!(s, "v {:.7} {:.7} {:.7}", p.x, p.y, p.z);
        }
        for t in &self.uvs {
            let _ = writeln!(s, "vt {:.7} {:.7}", t[0], t[1]);
        }
        for n in &self.normals {
            let _ = writeln!(s, "vn {:.6} {:.6} {:.6}", n.x, n.y, n.z);
        }
        for (k, f) in self.faces.iter().enumerate() {
            s.push('f');
            for (c, &v) in f.iter().enumerate() {
                let _ = write!(s, " {}", v + 1);
                match (self.face_uvs.get(k), self.face_normals.get(k)) {
                    (Some(t), Some(n)) => {
                        let _ = write!(s, "/{}/{}", t[c] + 1, n[c] + 1);
                    }
                    (Some(t), None) => {
                        let _ = write!(s, "/{}", t[c] + 1);
                    }
                    (None, Some(n)) => {
                        let _ = write!(s, "//{}", n[c] + 1);
                    }
                    (None, None) => {}
                }
            }
            s.push('\n');
        }
        s
    }

    /// Triangles of the mesh once its polygons are fanned.
    pub fn triangles(&self) -> usize {
        self.faces.iter().map(|f| f.len().saturating_sub(2)).sum()
    }
}

/// Every holdout mesh, in a fixed order (deterministic: same bytes on every
/// machine).
pub fn all() -> Vec<Generated> {
    vec![
        blob(),
        torus_knot(),
        turned_shaft(),
        gear(),
        hex_nut(),
        knurled_knob(),
        sprocket(),
        scatter(),
        cloth_two_sided(),
        tree(),
        blob_soup(),
        bumpy_torus_quads(),
        quad_creature(),
        quad_panel(),
        terrain(),
        atlas_sphere(),
        panel_crate(),
        voxel_torus(),
        voxel_terrain(),
        voxel_blob(),
        grid_cut_plate(),
        perforated_plate(),
        stair_interior(),
        embossed_text(),
        noisy_scan(),
    ]
}

/// Random numbers for placing parts (deterministic: the same meshes on
/// every machine).
struct Rng(SplitMix64);

impl Rng {
    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.0.next_f64()
    }

    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = self.uniform(f64::MIN_POSITIVE, 1.0);
        let v = self.uniform(0.0, 1.0);
        (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
    }

    fn unit(&mut self) -> DVec3 {
        DVec3::new(self.normal(), self.normal(), self.normal()).normalize_or(DVec3::Z)
    }
}

/// A smooth field on space: sines along random directions, octaves halving
/// in amplitude (a stand-in for noise that needs no table).
struct Field(Vec<(DVec3, f64, f64, f64)>);

impl Field {
    fn new(octaves: u32, seed: u64) -> Field {
        let mut r = Rng(SplitMix64(seed));
        let mut waves = Vec::new();
        for o in 0..octaves {
            for _ in 0..4 {
                let d = r.unit();
                let freq = 2f64.powi(o as i32) * r.uniform(1.5, 3.0);
                let phase = r.uniform(0.0, TAU);
                waves.push((d, freq, phase, 0.5f64.powi(o as i32)));
            }
        }
        Field(waves)
    }

    fn at(&self, p: DVec3) -> f64 {
        self.0
            .iter()
            .map(|&(d, f, ph, a)| a * (f * p.dot(d) + ph).sin())
            .sum()
    }
}

/// Quads of an `nu × nv` grid of vertex ids `id(i, j)`, wrapped or not in
/// each direction.
fn grid_quads(
    nu: usize,
    nv: usize,
    wrap_u: bool,
    wrap_v: bool,
    id: impl Fn(usize, usize) -> u32,
) -> Vec<Vec<u32>> {
    let cu = if wrap_u { nu } else { nu - 1 };
    let cv = if wrap_v { nv } else { nv - 1 };
    let mut out = Vec::with_capacity(cu * cv);
    for i in 0..cu {
        for j in 0..cv {
            let (i2, j2) = ((i + 1) % nu, (j + 1) % nv);
            out.push(vec![id(i, j), id(i2, j), id(i2, j2), id(i, j2)]);
        }
    }
    out
}

/// Quads split along their first diagonal.
fn triangulate(faces: Vec<Vec<u32>>) -> Vec<Vec<u32>> {
    faces
        .into_iter()
        .flat_map(|f| (1..f.len() - 1).map(move |k| vec![f[0], f[k], f[k + 1]]))
        .collect()
}

/// Positions, polygons, and the vertex ids of each of the six charts of
/// [`cube_sphere`] (row by row).
type CubeSphere = (Vec<DVec3>, Vec<Vec<u32>>, Vec<Vec<u32>>);

/// A sphere of six `n × n` quad grids (a cube's faces pushed out), welded
/// along the cube's edges; with the grid ids of each chart for UVs.
fn cube_sphere(n: usize) -> CubeSphere {
    let (pos, faces, charts) = cube_grid(n);
    (
        pos.into_iter().map(DVec3::normalize).collect(),
        faces,
        charts,
    )
}

/// The cube `[-1, 1]³` as six `n × n` quad grids facing out, welded along
/// its edges, with the grid ids of each chart.
fn cube_grid(n: usize) -> CubeSphere {
    let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
    let mut pos = Vec::new();
    let mut faces = Vec::new();
    let mut charts = Vec::new();
    for axis in 0..3 {
        for s in [-1.0, 1.0] {
            let mut chart = Vec::with_capacity((n + 1) * (n + 1));
            for i in 0..=n {
                for j in 0..=n {
                    let (u, v) = (
                        -1.0 + 2.0 * i as f64 / n as f64,
                        -1.0 + 2.0 * j as f64 / n as f64,
                    );
                    let mut p = DVec3::ZERO;
                    p[axis] = s;
                    p[(axis + 1) % 3] = u * s;
                    p[(axis + 2) % 3] = v;
                    let key = p.to_array().map(|x| (x * 1e6).round() as i64);
                    let id = *ids.entry(key).or_insert_with(|| {
                        pos.push(p);
                        pos.len() as u32 - 1
                    });
                    chart.push(id);
                }
            }
            faces.extend(grid_quads(n + 1, n + 1, false, false, |i, j| {
                chart[i * (n + 1) + j]
            }));
            charts.push(chart);
        }
    }
    (pos, faces, charts)
}

/// `manifold/blob`: a closed smooth lump, 27,648 triangles.
pub fn blob() -> Generated {
    let (pos, faces, _) = cube_sphere(48);
    let f = Field::new(3, 1);
    Generated {
        category: "manifold",
        name: "blob",
        positions: pos.iter().map(|&p| p * (1.0 + 0.15 * f.at(p))).collect(),
        faces: triangulate(faces),
        ..Default::default()
    }
}

/// A tube of radius `r(s)` around a closed curve sampled at `c`.
fn tube(c: &[DVec3], nv: usize, r: impl Fn(f64) -> f64) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let nu = c.len();
    let mut pos = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let t = (c[(i + 1) % nu] - c[(i + nu - 1) % nu]).normalize();
        let n = t.cross(DVec3::Z).normalize();
        let b = t.cross(n);
        for j in 0..nv {
            let s = TAU * j as f64 / nv as f64;
            let d = n * s.cos() + b * s.sin();
            pos.push(c[i] + d * r(s));
        }
    }
    let faces = grid_quads(nu, nv, true, true, |i, j| (i * nv + j) as u32);
    (pos, faces)
}

/// `manifold/torus_knot`: a (2, 3) knot tube, 9,600 triangles.
pub fn torus_knot() -> Generated {
    let c: Vec<DVec3> = (0..300)
        .map(|i| {
            let t = TAU * i as f64 / 300.0;
            let w = 2.0 + (3.0 * t).cos();
            DVec3::new(w * (2.0 * t).cos(), w * (2.0 * t).sin(), -(3.0 * t).sin())
        })
        .collect();
    let (positions, faces) = tube(&c, 16, |_| 0.35);
    Generated {
        category: "manifold",
        name: "torus_knot",
        positions,
        faces: triangulate(faces),
        ..Default::default()
    }
}

/// A closed surface of revolution of `profile` (radius, height), whose ends
/// have radius 0 (poles), in `n` segments; faces outward.
fn lathe(profile: &[(f64, f64)], n: usize) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let mut pos = Vec::new();
    let mut rings: Vec<Vec<u32>> = Vec::new();
    for &(r, z) in profile {
        if r == 0.0 {
            rings.push(vec![pos.len() as u32]);
            pos.push(DVec3::new(0.0, 0.0, z));
        } else {
            let ring = (0..n)
                .map(|k| {
                    let a = TAU * k as f64 / n as f64;
                    pos.push(DVec3::new(r * a.cos(), r * a.sin(), z));
                    pos.len() as u32 - 1
                })
                .collect();
            rings.push(ring);
        }
    }
    let mut faces = Vec::new();
    for w in rings.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        for k in 0..n {
            let k2 = (k + 1) % n;
            match (a.len(), b.len()) {
                (1, _) => faces.push(vec![a[0], b[k2], b[k]]),
                (_, 1) => faces.push(vec![a[k], a[k2], b[0]]),
                _ => faces.push(vec![a[k], a[k2], b[k2], b[k]]),
            }
        }
    }
    (pos, faces)
}

/// Points of a quarter circle around `(rc, zc)` from angle `a0` to `a1`.
fn arc(rc: f64, zc: f64, radius: f64, a0: f64, a1: f64, m: usize) -> Vec<(f64, f64)> {
    (0..m)
        .map(|k| {
            let a = a0 + (a1 - a0) * k as f64 / (m - 1) as f64;
            (rc + radius * a.cos(), zc + radius * a.sin())
        })
        .collect()
}

/// `manifold/turned_shaft`: a stepped shaft with fillets and a groove,
/// tessellated as CAD exports are (few rings on flats and cylinders, many
/// on fillets), 3,456 triangles.
pub fn turned_shaft() -> Generated {
    let mut p = vec![(0.0, 0.0)];
    p.extend(arc(0.45, 0.05, 0.05, -PI / 2.0, 0.0, 6));
    p.extend([
        (0.5, 0.6),
        (0.3, 0.6),
        (0.3, 0.9),
        (0.26, 0.92),
        (0.26, 1.0),
    ]);
    p.extend([(0.3, 1.02), (0.3, 1.6)]);
    p.extend(arc(0.22, 1.6, 0.08, 0.0, PI / 2.0, 6).into_iter().skip(1));
    p.push((0.0, 1.68));
    let (positions, faces) = lathe(&p, 96);
    Generated {
        category: "manifold",
        name: "turned_shaft",
        positions,
        faces: triangulate(faces),
        ..Default::default()
    }
}

/// A plate of outline radius `outer(θ)` with a round hole of radius
/// `inner`, `height` thick, in `n` angular steps: four rings of vertices
/// (outer bottom, outer top, inner top, inner bottom) joined by quads.
fn ring_plate(n: usize, outer: impl Fn(f64) -> f64, inner: f64, height: f64) -> Generated {
    let mut positions = Vec::with_capacity(4 * n);
    for (outside, z) in [(true, 0.0), (true, height), (false, height), (false, 0.0)] {
        for k in 0..n {
            let a = TAU * k as f64 / n as f64;
            let r = if outside { outer(a) } else { inner };
            positions.push(DVec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let mut faces = Vec::with_capacity(4 * n);
    for ring in 0..4 {
        let next = (ring + 1) % 4;
        for k in 0..n {
            let k2 = (k + 1) % n;
            let id = |r: usize, k: usize| (r * n + k) as u32;
            faces.push(vec![id(ring, k), id(ring, k2), id(next, k2), id(next, k)]);
        }
    }
    Generated {
        positions,
        faces: triangulate(faces),
        ..Default::default()
    }
}

/// `wild/gear`: 20 square teeth and a bore, 1,920 triangles.
pub fn gear() -> Generated {
    let teeth = |a: f64| if (20.0 * a).cos() > 0.2 { 1.12 } else { 1.0 };
    Generated {
        category: "wild",
        name: "gear",
        ..ring_plate(240, teeth, 0.35, 0.25)
    }
}

/// `wild/hex_nut`: a hexagonal prism with a bore, 1,536 triangles.
pub fn hex_nut() -> Generated {
    let hex = |a: f64| {
        let sector = (a + PI / 6.0).rem_euclid(PI / 3.0) - PI / 6.0;
        0.866 / sector.cos()
    };
    Generated {
        category: "wild",
        name: "hex_nut",
        ..ring_plate(192, hex, 0.45, 0.5)
    }
}

/// `wild/sprocket`: a thin plate with 12 rounded teeth, 2,880 triangles.
pub fn sprocket() -> Generated {
    let teeth = |a: f64| 1.0 + 0.1 * (1.5 * (12.0 * a).cos()).clamp(-1.0, 1.0);
    Generated {
        category: "wild",
        name: "sprocket",
        ..ring_plate(360, teeth, 0.3, 0.1)
    }
}

/// `wild/knurled_knob`: a cylinder with 24 ridges, a domed top and a flat
/// bottom, 5,760 triangles.
pub fn knurled_knob() -> Generated {
    let n = 480;
    let ridged = |a: f64| if (24.0 * a).sin() > 0.0 { 0.64 } else { 0.6 };
    let mut positions = vec![DVec3::new(0.0, 0.0, 0.0)];
    let mut rings = Vec::new();
    let mut ring = |positions: &mut Vec<DVec3>, r: &dyn Fn(f64) -> f64, z: f64| {
        let ids: Vec<u32> = (0..n)
            .map(|k| {
                let a = TAU * k as f64 / n as f64;
                positions.push(DVec3::new(r(a) * a.cos(), r(a) * a.sin(), z));
                positions.len() as u32 - 1
            })
            .collect();
        rings.push(ids);
    };
    ring(&mut positions, &ridged, 0.0);
    ring(&mut positions, &ridged, 0.5);
    for (r, z) in [(0.55, 0.55), (0.45, 0.62), (0.3, 0.67), (0.15, 0.69)] {
        ring(&mut positions, &move |_| r, z);
    }
    positions.push(DVec3::new(0.0, 0.0, 0.7));
    let top = positions.len() as u32 - 1;
    let mut faces = Vec::new();
    for k in 0..n {
        faces.push(vec![0, rings[0][(k + 1) % n], rings[0][k]]);
    }
    for w in rings.windows(2) {
        for k in 0..n {
            let k2 = (k + 1) % n;
            faces.push(vec![w[0][k], w[0][k2], w[1][k2], w[1][k]]);
        }
    }
    let last = &rings[rings.len() - 1];
    for k in 0..n {
        faces.push(vec![last[k], last[(k + 1) % n], top]);
    }
    Generated {
        category: "wild",
        name: "knurled_knob",
        positions,
        faces: triangulate(faces),
        ..Default::default()
    }
}

/// Appends `part` (positions, faces) to `into`, offsetting its ids.
fn append(into: &mut Generated, positions: Vec<DVec3>, faces: Vec<Vec<u32>>) {
    let base = into.positions.len() as u32;
    into.positions.extend(positions);
    into.faces.extend(
        faces
            .into_iter()
            .map(|f| f.into_iter().map(|v| v + base).collect()),
    );
}

/// `wild/scatter`: 40 separate, partly intersecting spheres and rounded
/// boxes of different sizes, 27,840 triangles.
pub fn scatter() -> Generated {
    let mut r = Rng(SplitMix64(3));
    let mut g = Generated {
        category: "wild",
        name: "scatter",
        ..Default::default()
    };
    for k in 0..40 {
        let c = DVec3::new(
            r.uniform(-1.0, 1.0),
            r.uniform(-1.0, 1.0),
            r.uniform(-1.0, 1.0),
        );
        let size = r.uniform(0.08, 0.3);
        let (pos, faces, _) = cube_sphere(if k % 2 == 0 { 10 } else { 4 });
        let boxy = k % 2 == 1;
        let pos = pos
            .into_iter()
            .map(|p| {
                // A box with slightly rounded corners: each coordinate
                // pushed toward ±1.
                let q = if boxy {
                    let m = p.abs().max_element();
                    p.map(|x| x.signum() * (x.abs() / m).powf(0.05))
                } else {
                    p
                };
                c + q * size
            })
            .collect();
        append(&mut g, pos, triangulate(faces));
    }
    g
}

/// `wild/cloth_two_sided`: a curved open sheet made double-sided by a
/// reversed copy of every face, 19,044 triangles.
pub fn cloth_two_sided() -> Generated {
    let n = 70;
    let positions: Vec<DVec3> = (0..n * n)
        .map(|k| {
            let (u, v) = (
                (k / n) as f64 / (n - 1) as f64,
                (k % n) as f64 / (n - 1) as f64,
            );
            DVec3::new(2.0 * u, 0.3 * (3.0 * u).sin() * (2.0 * v).cos(), 1.5 * v)
        })
        .collect();
    let front = triangulate(grid_quads(n, n, false, false, |i, j| (i * n + j) as u32));
    let back: Vec<Vec<u32>> = front
        .iter()
        .map(|f| f.iter().rev().copied().collect())
        .collect();
    Generated {
        category: "wild",
        name: "cloth_two_sided",
        positions,
        faces: front.into_iter().chain(back).collect(),
        ..Default::default()
    }
}

/// `wild/tree`: a tapered trunk and 500 separate leaf cards (two triangles
/// each), 1,936 triangles.
pub fn tree() -> Generated {
    let (nu, nv) = (40, 12);
    let mut g = Generated {
        category: "wild",
        name: "tree",
        ..Default::default()
    };
    let trunk: Vec<DVec3> = (0..nu * nv)
        .map(|k| {
            let t = (k / nv) as f64 / (nu - 1) as f64;
            let a = TAU * (k % nv) as f64 / nv as f64;
            let r = 0.12 * (1.0 - 0.6 * t);
            DVec3::new(r * a.cos(), r * a.sin(), 2.0 * t)
        })
        .collect();
    let faces = triangulate(grid_quads(nu, nv, false, true, |i, j| (i * nv + j) as u32));
    append(&mut g, trunk, faces);
    let mut r = Rng(SplitMix64(11));
    for _ in 0..500 {
        let c = DVec3::new(0.5 * r.normal(), 0.5 * r.normal(), 1.4 + 0.35 * r.normal());
        let a = r.unit();
        let b = a.cross(r.unit()).normalize();
        let (l, w) = (0.08, 0.032);
        let corner = |s: f64, t: f64| c + a * (s * l) + b * (t * w);
        let card = vec![
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        append(&mut g, card, vec![vec![0, 1, 2], vec![0, 2, 3]]);
    }
    g
}

/// `wild/blob_soup`: a lump whose triangles share no vertex (as STL and
/// some exporters write them), 10,800 triangles.
pub fn blob_soup() -> Generated {
    let (pos, faces, _) = cube_sphere(30);
    let f = Field::new(2, 3);
    let pos: Vec<DVec3> = pos.iter().map(|&p| p * (1.0 + 0.2 * f.at(p))).collect();
    let tris = triangulate(faces);
    Generated {
        category: "wild",
        name: "blob_soup",
        positions: tris.iter().flatten().map(|&v| pos[v as usize]).collect(),
        faces: (0..tris.len() as u32)
            .map(|k| vec![3 * k, 3 * k + 1, 3 * k + 2])
            .collect(),
        ..Default::default()
    }
}

/// `quad/bumpy_torus_quads`: 4,800 quads on a torus with bumps.
pub fn bumpy_torus_quads() -> Generated {
    let (nu, nv) = (120, 40);
    let positions = (0..nu * nv)
        .map(|k| {
            let (a, b) = (
                TAU * (k / nv) as f64 / nu as f64,
                TAU * (k % nv) as f64 / nv as f64,
            );
            let r = 0.4 * (1.0 + 0.1 * (5.0 * a).sin() * (3.0 * b).cos());
            let w = 1.0 + r * b.cos();
            DVec3::new(w * a.cos(), w * a.sin(), r * b.sin())
        })
        .collect();
    Generated {
        category: "quad",
        name: "bumpy_torus_quads",
        positions,
        faces: grid_quads(nu, nv, true, true, |i, j| (i * nv + j) as u32),
        ..Default::default()
    }
}

/// `quad/quad_creature`: 5,400 quads on a stretched lump.
pub fn quad_creature() -> Generated {
    let (pos, faces, _) = cube_sphere(30);
    let f = Field::new(2, 11);
    Generated {
        category: "quad",
        name: "quad_creature",
        positions: pos
            .iter()
            .map(|&p| {
                let k = 1.0 + 0.1 * f.at(p);
                DVec3::new(0.7, 1.0, 1.6) * p * k
            })
            .collect(),
        faces,
        ..Default::default()
    }
}

/// `quad/quad_panel`: an open flat panel of 7,921 quads with a raised ring.
pub fn quad_panel() -> Generated {
    let n = 90;
    let positions = (0..n * n)
        .map(|k| {
            let (x, y) = (
                -1.0 + 2.0 * (k / n) as f64 / (n - 1) as f64,
                -1.0 + 2.0 * (k % n) as f64 / (n - 1) as f64,
            );
            let d = ((x * x + y * y).sqrt() - 0.5) / 0.06;
            DVec3::new(x, y, 0.08 * (-d * d).exp())
        })
        .collect();
    Generated {
        category: "quad",
        name: "quad_panel",
        positions,
        faces: grid_quads(n, n, false, false, |i, j| (i * n + j) as u32),
        ..Default::default()
    }
}

/// Area-weighted vertex normals of `faces` (smooth shading), one per
/// position, and the faces' corners pointing at them.
fn smooth_normals(positions: &[DVec3], faces: &[Vec<u32>]) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let mut n = vec![DVec3::ZERO; positions.len()];
    for f in faces {
        let p = |k: usize| positions[f[k] as usize];
        for k in 1..f.len() - 1 {
            let w = (p(k) - p(0)).cross(p(k + 1) - p(0));
            for &v in &[f[0], f[k], f[k + 1]] {
                n[v as usize] += w;
            }
        }
    }
    (
        n.into_iter().map(|v| v.normalize_or(DVec3::Z)).collect(),
        faces.to_vec(),
    )
}

/// `textured/panel_crate`: a box whose six sides carry raised panels, each
/// side its own UV island and its own normals (hard edges at the box's
/// edges, smooth within a side), like a game prop; 13,824 triangles.
pub fn panel_crate() -> Generated {
    let n = 24;
    let m = n + 1;
    let mut g = Generated {
        category: "textured",
        name: "panel_crate",
        ..Default::default()
    };
    for (side, (axis, s)) in [0, 1, 2]
        .iter()
        .flat_map(|&a| [(a, -1.0), (a, 1.0)])
        .enumerate()
    {
        let base = g.positions.len() as u32;
        let (ox, oy) = ((side % 3) as f64 / 3.0, (side / 3) as f64 / 2.0);
        let mut grid = Vec::with_capacity(m * m);
        for i in 0..m {
            for j in 0..m {
                // (2i − n) / n is exactly −(2(n − i) − n) / n: the sides' shared
                // edges get bit-identical coordinates.
                let c = |k: usize| (2.0 * k as f64 - n as f64) / n as f64;
                let (u, v) = (c(i), c(j));
                // A raised panel inset from the side's outline, with a
                // steep but smooth step, exactly 0 on the rim so that the
                // sides weld along the box's edges.
                let t = ((0.7 - u.abs().max(v.abs()) + 0.03) / 0.06).clamp(0.0, 1.0);
                let h = 0.04 * t * t * (3.0 - 2.0 * t);
                let mut p = DVec3::ZERO;
                p[axis] = s * (1.0 + h);
                p[(axis + 1) % 3] = u * s;
                p[(axis + 2) % 3] = v;
                grid.push(p);
                g.uvs.push([
                    ox + 0.01 + 0.31 * (i as f64 / n as f64),
                    oy + 0.01 + 0.47 * (j as f64 / n as f64),
                ]);
            }
        }
        // The rim stays on the box's faces so that sides meet at its edges.
        let faces = triangulate(grid_quads(m, m, false, false, |i, j| {
            base + (i * m + j) as u32
        }));
        let local: Vec<Vec<u32>> = faces
            .iter()
            .map(|f| f.iter().map(|&v| v - base).collect())
            .collect();
        let (normals, _) = smooth_normals(&grid, &local);
        let nbase = g.normals.len() as u32;
        g.normals.extend(normals);
        g.positions.extend(grid);
        g.face_uvs.extend(faces.iter().cloned());
        g.face_normals
            .extend(local.iter().map(|f| f.iter().map(|&v| v + nbase).collect()));
        g.faces.extend(faces);
    }
    weld_positions(&mut g);
    g
}

/// Merges bit-identical positions (the sides of `panel_crate` meet along
/// the box's edges; −0 counts as 0), keeping UVs and normals per corner.
fn weld_positions(g: &mut Generated) {
    let mut ids: HashMap<[u64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let remap: Vec<u32> = g
        .positions
        .iter()
        .map(|p| {
            *ids.entry(p.to_array().map(|x| (x + 0.0).to_bits()))
                .or_insert_with(|| {
                    positions.push(*p);
                    positions.len() as u32 - 1
                })
        })
        .collect();
    for f in &mut g.faces {
        for v in f.iter_mut() {
            *v = remap[*v as usize];
        }
    }
    g.positions = positions;
}

/// `textured/terrain`: an open height field with planar UVs, 33,282
/// triangles.
pub fn terrain() -> Generated {
    let n = 130;
    let f = Field::new(4, 5);
    let mut positions = Vec::with_capacity(n * n);
    let mut uvs = Vec::with_capacity(n * n);
    for k in 0..n * n {
        let (u, v) = (
            (k / n) as f64 / (n - 1) as f64,
            (k % n) as f64 / (n - 1) as f64,
        );
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        positions.push(DVec3::new(
            x,
            y,
            0.1 * f.at(DVec3::new(1.3 * x, 1.3 * y, 0.0)),
        ));
        uvs.push([u, v]);
    }
    let faces = triangulate(grid_quads(n, n, false, false, |i, j| (i * n + j) as u32));
    let (normals, face_normals) = smooth_normals(&positions, &faces);
    Generated {
        category: "textured",
        name: "terrain",
        positions,
        face_uvs: faces.clone(),
        faces,
        uvs,
        normals,
        face_normals,
    }
}

/// `textured/atlas_sphere`: a bumpy sphere whose six cube-map charts are
/// separate UV islands (a seam along every cube edge), 15,552 triangles.
pub fn atlas_sphere() -> Generated {
    let n = 36;
    let (pos, _, charts) = cube_sphere(n);
    let f = Field::new(3, 9);
    let positions: Vec<DVec3> = pos.iter().map(|&p| p * (1.0 + 0.08 * f.at(p))).collect();
    let (mut uvs, mut faces, mut face_uvs) = (Vec::new(), Vec::new(), Vec::new());
    let m = n + 1;
    for (c, chart) in charts.iter().enumerate() {
        let base = uvs.len() as u32;
        let (ox, oy) = ((c % 3) as f64 / 3.0, (c / 3) as f64 / 2.0);
        for i in 0..m {
            for j in 0..m {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                uvs.push([ox + 0.01 + 0.31 * s, oy + 0.01 + 0.47 * t]);
            }
        }
        faces.extend(triangulate(grid_quads(m, m, false, false, |i, j| {
            chart[i * m + j]
        })));
        face_uvs.extend(triangulate(grid_quads(m, m, false, false, |i, j| {
            base + (i * m + j) as u32
        })));
    }
    let (normals, face_normals) = smooth_normals(&positions, &faces);
    Generated {
        category: "textured",
        name: "atlas_sphere",
        positions,
        faces,
        uvs,
        face_uvs,
        normals,
        face_normals,
    }
}

/// The faces between filled and empty unit cells of `filled` over the
/// cells `lo..=hi` (each axis), as quads split into two triangles, welded:
/// what a voxel editor exports.
fn voxels(filled: impl Fn(i32, i32, i32) -> bool, lo: [i32; 3], hi: [i32; 3]) -> Generated {
    let mut ids: HashMap<[i32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for (corners, _) in wildlod_testkit::scenes::voxel_sides(filled, lo, hi) {
        let q = corners.map(|p| {
            *ids.entry(p).or_insert_with(|| {
                positions.push(DVec3::new(
                    f64::from(p[0]),
                    f64::from(p[1]),
                    f64::from(p[2]),
                ));
                (positions.len() - 1) as u32
            })
        });
        faces.push(vec![q[0], q[1], q[2]]);
        faces.push(vec![q[0], q[2], q[3]]);
    }
    Generated {
        positions,
        faces,
        ..Default::default()
    }
}

/// `voxel/voxel_torus`: the unit cells within 6 of a circle of radius 16,
/// 10,416 triangles.
pub fn voxel_torus() -> Generated {
    let filled = |x: i32, y: i32, z: i32| {
        (f64::from(x).hypot(f64::from(y)) - 16.0).hypot(f64::from(z)) < 6.0
    };
    Generated {
        category: "voxel",
        name: "voxel_torus",
        ..voxels(filled, [-24, -24, -8], [24, 24, 8])
    }
}

/// `voxel/voxel_terrain`: a 64 × 64 height field of unit columns, as a
/// block game's terrain, 27,320 triangles.
pub fn voxel_terrain() -> Generated {
    let height = |x: i32, y: i32| {
        let (x, y) = (f64::from(x), f64::from(y));
        (6.0 + 4.0 * (0.15 * x).sin() + 3.0 * (0.11 * y).cos() + 2.0 * (0.3 * (x + y)).sin()) as i32
    };
    let filled = move |x: i32, y: i32, z: i32| {
        (0..64).contains(&x) && (0..64).contains(&y) && (0..=height(x, y)).contains(&z)
    };
    Generated {
        category: "voxel",
        name: "voxel_terrain",
        ..voxels(filled, [0, 0, 0], [63, 63, 20])
    }
}

/// `voxel/voxel_blob`: a sphere of radius 20 cells with three-lobed bumps,
/// 16,084 triangles.
pub fn voxel_blob() -> Generated {
    let filled = |x: i32, y: i32, z: i32| {
        let (x, y, z) = (f64::from(x), f64::from(y), f64::from(z));
        let r = (x * x + y * y + z * z).sqrt() + 1e-9;
        let bump = 0.12 * (3.0 * y.atan2(x)).sin() * (2.0 * (z / r).acos()).sin();
        r < 20.0 * (1.0 + bump)
    };
    Generated {
        category: "voxel",
        name: "voxel_blob",
        ..voxels(filled, [-24, -24, -24], [24, 24, 24])
    }
}

/// `voxel/grid_cut_plate`: a 100 × 60 × 0.5 plate of 0.5 cells with 15
/// round holes of radius 4 cut along the cells (staircase walls), as a
/// grid remesher leaves a drilled plate; 86,720 triangles. The peers stay
/// exact to 10%; at 1% the holes' outlines must go.
pub fn grid_cut_plate() -> Generated {
    let hole = |x: i32, y: i32| {
        let (cx, cy) = (0.5 * f64::from(x) + 0.25, 0.5 * f64::from(y) + 0.25);
        (0..15).any(|i| {
            let (hx, hy) = (
                10.0 + 20.0 * f64::from(i % 5),
                10.0 + 20.0 * f64::from(i / 5),
            );
            (cx - hx).hypot(cy - hy) < 4.0
        })
    };
    let filled = move |x: i32, y: i32, z: i32| {
        z == 0 && (0..200).contains(&x) && (0..120).contains(&y) && !hole(x, y)
    };
    let mut g = voxels(filled, [0, 0, 0], [199, 119, 0]);
    for p in &mut g.positions {
        *p *= DVec3::splat(0.5);
    }
    Generated {
        category: "voxel",
        name: "grid_cut_plate",
        ..g
    }
}

/// A box of `half` extents around `center`, each side an `n × n` grid of
/// quads split in two.
fn cuboid(center: DVec3, half: DVec3, n: usize) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let (pos, faces, _) = cube_grid(n);
    (
        pos.into_iter().map(|p| center + p * half).collect(),
        triangulate(faces),
    )
}

/// A closed cylinder along +y of `sections` sides standing on `base`:
/// `4 · sections` triangles (sides as quads split in two, fanned caps).
fn cylinder(base: DVec3, radius: f64, height: f64, sections: usize) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let mut pos = Vec::with_capacity(2 * sections + 2);
    for y in [0.0, height] {
        for k in 0..sections {
            let a = TAU * k as f64 / sections as f64;
            pos.push(base + DVec3::new(radius * a.cos(), y, -radius * a.sin()));
        }
    }
    pos.push(base);
    pos.push(base + DVec3::new(0.0, height, 0.0));
    let (bottom, top) = (2 * sections as u32, 2 * sections as u32 + 1);
    let n = sections as u32;
    let mut faces = Vec::with_capacity(4 * sections);
    for k in 0..n {
        let k2 = (k + 1) % n;
        faces.push(vec![k, k2, n + k2]);
        faces.push(vec![k, n + k2, n + k]);
        faces.push(vec![bottom, k2, k]);
        faces.push(vec![top, n + k, n + k2]);
    }
    (pos, faces)
}

/// Vertex ids by position (to 1e-6), for parts built side by side.
#[derive(Default)]
struct Welder {
    ids: HashMap<[i64; 3], u32>,
    positions: Vec<DVec3>,
}

impl Welder {
    /// The id of the vertex at `p`, made on first use.
    fn id(&mut self, p: DVec3) -> u32 {
        let key = p.to_array().map(|x| (x * 1e6).round() as i64);
        let positions = &mut self.positions;
        *self.ids.entry(key).or_insert_with(|| {
            positions.push(p);
            positions.len() as u32 - 1
        })
    }
}

/// `cad/perforated_plate`: a 108 × 72 × 4 plate with a 9 × 6 grid of
/// round holes of radius 3, tessellated as CAD exporters do (each cell a
/// ring of 32 quads from its square outline to its hole, long thin
/// triangles; the holes' walls one band), closed, 11,340 triangles.
pub fn perforated_plate() -> Generated {
    let (nx, ny, cell, radius, thick, n) = (9, 6, 12.0, 3.0, 4.0, 32usize);
    let mut weld = Welder::default();
    let step = TAU / n as f64;
    let angle = |k: usize| PI / n as f64 + step * k as f64;
    // The ray from a cell's center at angle `a` meets its square here.
    let square = |a: f64| {
        let (c, s) = (a.cos(), a.sin());
        let t = 0.5 * cell / c.abs().max(s.abs());
        (c * t, s * t)
    };
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            let cx = (i as f64 - 0.5 * (nx - 1) as f64) * cell;
            let cy = (j as f64 - 0.5 * (ny - 1) as f64) * cell;
            let mut rims = Vec::new();
            for (z, up) in [(thick, true), (0.0, false)] {
                let outer: Vec<u32> = (0..n)
                    .map(|k| {
                        let (x, y) = square(angle(k));
                        weld.id(DVec3::new(cx + x, cy + y, z))
                    })
                    .collect();
                let rim: Vec<u32> = (0..n)
                    .map(|k| {
                        let a = angle(k);
                        weld.id(DVec3::new(cx + radius * a.cos(), cy + radius * a.sin(), z))
                    })
                    .collect();
                let mut put = |mut f: Vec<u32>| {
                    if !up {
                        f.reverse();
                    }
                    faces.push(f);
                };
                for k in 0..n {
                    let k2 = (k + 1) % n;
                    put(vec![outer[k], outer[k2], rim[k2]]);
                    put(vec![outer[k], rim[k2], rim[k]]);
                }
                // The square's corners lie between two rays.
                for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
                    let a = f64::atan2(sy, sx);
                    let k = ((a - PI / n as f64).rem_euclid(TAU) / step).floor() as usize % n;
                    let corner = weld.id(DVec3::new(cx + sx * 0.5 * cell, cy + sy * 0.5 * cell, z));
                    put(vec![outer[k], corner, outer[(k + 1) % n]]);
                }
                rims.push(rim);
            }
            let (top, bottom) = (&rims[0], &rims[1]);
            for k in 0..n {
                let k2 = (k + 1) % n;
                faces.push(vec![top[k], bottom[k2], bottom[k]]);
                faces.push(vec![top[k], top[k2], bottom[k2]]);
            }
        }
    }
    // The plate's outer wall: below every top edge that only one face uses.
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for f in &faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut walls = Vec::new();
    for f in &faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let on_top =
                weld.positions[a as usize].z == thick && weld.positions[b as usize].z == thick;
            if on_top && count[&(a.min(b), a.max(b))] == 1 {
                walls.push((a, b));
            }
        }
    }
    for (a, b) in walls {
        let below = |v: u32| weld.positions[v as usize] * DVec3::new(1.0, 1.0, 0.0);
        let (pa, pb) = (below(a), below(b));
        let (ia, ib) = (weld.id(pa), weld.id(pb));
        faces.push(vec![b, a, ia]);
        faces.push(vec![b, ia, ib]);
    }
    Generated {
        category: "cad",
        name: "perforated_plate",
        positions: weld.positions,
        faces,
        ..Default::default()
    }
}

/// `architecture/stair_interior`: a room corner as an architectural
/// export writes it, every element a separate closed box resting on or
/// against the others (coincident faces, no shared vertices): a 10 × 6
/// floor slab, two walls 0.2 thick, a door frame of three trims, a flight
/// of 12 steps each resting on the one below, and 24 balusters (8-sided
/// cylinders 3 cm across) along it; 29 parts, 984 triangles.
pub fn stair_interior() -> Generated {
    let mut g = Generated {
        category: "architecture",
        name: "stair_interior",
        ..Default::default()
    };
    let block = |g: &mut Generated, center: [f64; 3], size: [f64; 3]| {
        let (p, f) = cuboid(DVec3::from(center), 0.5 * DVec3::from(size), 1);
        append(g, p, f);
    };
    block(&mut g, [0.0, -0.15, 0.0], [10.0, 0.3, 6.0]);
    for i in 0..12 {
        let i = f64::from(i);
        block(
            &mut g,
            [3.0, 0.09 + 0.18 * i, -2.0 + 0.28 * i],
            [1.2, 0.18, 0.28],
        );
    }
    block(&mut g, [-5.0, 1.5, 0.0], [0.2, 3.0, 6.0]);
    block(&mut g, [0.0, 1.5, -3.0], [10.0, 3.0, 0.2]);
    for x in [-0.45, 0.45] {
        block(&mut g, [x, 1.05, -2.875], [0.08, 2.1, 0.05]);
    }
    block(&mut g, [0.0, 2.14, -2.875], [0.98, 0.08, 0.05]);
    for i in 0..24 {
        // Two balusters a step, standing on its outer end.
        let step = f64::from(i / 2);
        let z = -2.0 + 0.28 * step + if i % 2 == 0 { -0.07 } else { 0.07 };
        let base = DVec3::new(3.55, 0.18 * (step + 1.0), z);
        let (p, f) = cylinder(base, 0.015, 0.9, 8);
        append(&mut g, p, f);
    }
    g
}

/// `cad/embossed_text`: a 40 × 10 × 1 plate with 60 raised bars 0.3 high,
/// as the strokes of engraved lettering, each a separate box whose sides
/// are 2 × 2 grids (as a boolean union tessellates them); 2,892 triangles.
pub fn embossed_text() -> Generated {
    let mut r = Rng(SplitMix64(11));
    let mut g = Generated {
        category: "cad",
        name: "embossed_text",
        ..Default::default()
    };
    let (p, f) = cuboid(DVec3::ZERO, DVec3::new(20.0, 5.0, 0.5), 1);
    append(&mut g, p, f);
    for i in 0..60 {
        let (w, h) = (r.uniform(0.2, 0.5), r.uniform(1.0, 2.5));
        let center = DVec3::new(
            -18.0 + f64::from(i % 20) * 1.8,
            -3.0 + f64::from(i / 20) * 3.0,
            0.65,
        );
        let (p, f) = cuboid(center, 0.5 * DVec3::new(w, h, 0.3), 2);
        append(&mut g, p, f);
    }
    g
}

/// `scan/noisy_scan`: a scanned lump as photogrammetry leaves it: a
/// bumpy sphere of 76,800 triangles with 2e-3 of noise on every vertex,
/// five holes where the scanner saw nothing, and 30 floating specks (small
/// closed blobs, some inside) around it; 77,716 triangles.
pub fn noisy_scan() -> Generated {
    let mut r = Rng(SplitMix64(17));
    let (pos, faces, _) = cube_sphere(80);
    let positions: Vec<DVec3> = pos
        .into_iter()
        .map(|p| {
            let bump = 1.0 + 0.05 * (5.0 * p.x).sin() * (4.0 * p.y).cos();
            p * bump + DVec3::new(r.normal(), r.normal(), r.normal()) * 0.002
        })
        .collect();
    let holes: Vec<DVec3> = (0..5).map(|_| r.unit()).collect();
    let faces: Vec<Vec<u32>> = triangulate(faces)
        .into_iter()
        .filter(|f| {
            let c = f.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / 3.0;
            holes.iter().all(|h| c.distance(*h) > 0.08)
        })
        .collect();
    let mut g = Generated {
        category: "scan",
        name: "noisy_scan",
        ..Default::default()
    };
    append(&mut g, positions, faces);
    // Vertices no face uses any more (inside the holes) are left out.
    let mut used = vec![false; g.positions.len()];
    for f in &g.faces {
        for &v in f {
            used[v as usize] = true;
        }
    }
    let mut remap = vec![0u32; used.len()];
    let mut kept = Vec::new();
    for (v, &u) in used.iter().enumerate() {
        if u {
            remap[v] = kept.len() as u32;
            kept.push(g.positions[v]);
        }
    }
    g.positions = kept;
    for f in &mut g.faces {
        for v in f.iter_mut() {
            *v = remap[*v as usize];
        }
    }
    for _ in 0..30 {
        let center = DVec3::new(r.normal(), r.normal(), r.normal()) * 0.6;
        let (p, f, _) = cube_sphere(2);
        append(
            &mut g,
            p.into_iter().map(|q| center + q * 0.01).collect(),
            triangulate(f),
        );
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Edges used by exactly one face, and by more than two (position
    /// ids, unordered).
    fn border_and_nonmanifold(g: &Generated) -> (usize, usize) {
        let mut count: HashMap<(u32, u32), usize> = HashMap::new();
        for f in &g.faces {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let border = count.values().filter(|&&c| c == 1).count();
        let many = count.values().filter(|&&c| c > 2).count();
        (border, many)
    }

    #[test]
    fn each_mesh_has_the_size_and_topology_its_documentation_gives() {
        let expect: &[(&str, usize, bool)] = &[
            // (name, triangles, closed)
            ("blob", 27_648, true),
            ("torus_knot", 9_600, true),
            ("turned_shaft", 3_456, true),
            ("gear", 1_920, true),
            ("hex_nut", 1_536, true),
            ("knurled_knob", 5_760, true),
            ("sprocket", 2_880, true),
            ("scatter", 27_840, true),
            ("bumpy_torus_quads", 9_600, true),
            ("quad_creature", 10_800, true),
            ("atlas_sphere", 15_552, true),
            ("panel_crate", 6_912, true),
            ("voxel_torus", 10_416, true),
            ("voxel_terrain", 27_320, true),
            ("voxel_blob", 16_084, true),
            ("grid_cut_plate", 86_720, true),
            ("perforated_plate", 11_340, true),
            ("embossed_text", 2_892, true),
        ];
        let all = all();
        for &(name, tris, closed) in expect {
            let g = all.iter().find(|g| g.name == name).expect(name);
            assert_eq!(g.triangles(), tris, "{name}");
            let (border, many) = border_and_nonmanifold(g);
            assert_eq!(
                (border == 0, many),
                (closed, 0),
                "{name}: {border} border edges"
            );
        }
        // Open ones: the panel's and the terrain's borders are their grid's
        // outline; the cloth's twins make every edge doubled, none single.
        let find = |n: &str| all.iter().find(|g| g.name == n).expect(n);
        assert_eq!(border_and_nonmanifold(find("quad_panel")), (4 * 89, 0));
        assert_eq!(border_and_nonmanifold(find("terrain")), (4 * 129, 0));
        assert_eq!(find("cloth_two_sided").triangles(), 19_044);
        assert_eq!(border_and_nonmanifold(find("cloth_two_sided")).0, 0);
        // 500 cards of two triangles each, plus the open-ended trunk.
        assert_eq!(find("tree").triangles(), 2 * 39 * 12 + 1000);
        // The interior's boxes share no vertex (a reader that welds by
        // position finds 13 edges of four faces where boxes meet).
        assert_eq!(find("stair_interior").triangles(), 984);
        assert_eq!(border_and_nonmanifold(find("stair_interior")), (0, 0));
        // The scan's five holes are its only border.
        assert_eq!(find("noisy_scan").triangles(), 77_716);
        assert_eq!(border_and_nonmanifold(find("noisy_scan")), (162, 0));
        // The soup shares no vertex.
        let soup = find("blob_soup");
        assert_eq!(soup.positions.len(), 3 * soup.triangles());
    }

    #[test]
    fn generation_is_deterministic_and_uvs_cover_every_corner() {
        let (a, b) = (all(), all());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.to_obj(), y.to_obj(), "{}", x.name);
            if !x.uvs.is_empty() {
                assert_eq!(x.face_uvs.len(), x.faces.len(), "{}", x.name);
                for (f, t) in x.faces.iter().zip(&x.face_uvs) {
                    assert_eq!(f.len(), t.len());
                }
            }
        }
    }

    #[test]
    fn the_atlas_sphere_has_six_uv_islands_and_one_surface() {
        let g = atlas_sphere();
        // Seams: positions with corners of more than one UV.
        let mut uv_of: HashMap<u32, Vec<u32>> = HashMap::new();
        for (f, t) in g.faces.iter().zip(&g.face_uvs) {
            for (&v, &u) in f.iter().zip(t) {
                let e = uv_of.entry(v).or_default();
                if !e.contains(&u) {
                    e.push(u);
                }
            }
        }
        let seam = uv_of.values().filter(|u| u.len() > 1).count();
        // The twelve cube edges hold 12·35 inner vertices (two UVs each)
        // and the eight corners (three UVs each).
        assert_eq!(seam, 12 * 35 + 8);
        assert_eq!(border_and_nonmanifold(&g), (0, 0));
    }
}
