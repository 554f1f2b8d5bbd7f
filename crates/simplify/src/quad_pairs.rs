//! Triangle pairs joined into quads where the quad draws the same surface.
//!
//! A quad-dominant simplification (Knodt 2024) keeps the input's quads
//! where it can, but collapses also leave pairs of triangles that together
//! form a good quad: two triangles across one edge, in one part, with the
//! same attribute values on both sides of that edge. Joined, with the
//! shared edge as the diagonal the quad is drawn with (writers and
//! renderers draw a polygon as the fan from its first corner, and
//! [`wildlod_mesh::polygon::triangulate`] does wherever that fan covers it), the
//! surface, its attributes and its triangle count are exactly those of the
//! pair: only the face count changes. Blender's "Tris to Quads" and
//! MeshLab's quad-dominant conversion offer the same step as a tool.
//!
//! A quad is joined only where it is convex in its plane (both diagonals
//! inside: no fold whichever one a renderer picks), where the two
//! triangles turn by at most a crease angle (a box's corner stays two
//! faces), and where it is no more warped than allowed ([`JoinLimits`]):
//! readers and renderers pick their own diagonal, and the distance between
//! the two diagonals is how far that moves the surface. Pairs are joined
//! flattest first, each triangle once.

use std::collections::HashMap;

use glam::DVec3;
use wildlod_geometry::segment_segment_closest;
use wildlod_mesh::polygon::fan_covers;
use wildlod_mesh::{Faces, Mesh};

/// The uses of one edge: (face, corner `k` of its directed edge `k → k + 1`).
type Uses = Vec<(u32, u8)>;

/// How far a joined quad may depart from a flat one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JoinLimits {
    /// The distance between the quad's two diagonals may always reach this
    /// (what no screen shows, in the mesh's units).
    pub(crate) max_warp: f64,
    /// ... and this share of the quad's longer diagonal ([`relative_warp`]):
    /// a quad as warped as the input's own quads is drawn as theirs are.
    pub(crate) max_relative_warp: f64,
    /// The most the two triangles' normals may turn (a crease: a box's
    /// corner stays two faces), in degrees.
    pub(crate) max_fold_degrees: f64,
}

/// The distance between a quad's two diagonals over the longer one: 0
/// for a flat quad, how far a reader that draws it by the other diagonal
/// moves its surface, relative to its size.
pub(crate) fn relative_warp(quad: &[[f32; 3]; 4]) -> f64 {
    let len = |a: [f32; 3], b: [f32; 3]| {
        (0..3)
            .map(|k| (f64::from(a[k]) - f64::from(b[k])).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let longer = len(quad[0], quad[2]).max(len(quad[1], quad[3]));
    if longer > 0.0 {
        segment_distance(quad[0], quad[2], quad[1], quad[3]) / longer
    } else {
        0.0
    }
}

/// Joins triangle pairs of `mesh` into quads (see the module
/// documentation) within `limits`; returns how many quads were made.
/// Positions, attribute values and the triangles drawn are unchanged;
/// faces, their parts and their corners' indices are rebuilt.
pub(crate) fn join_triangle_pairs(mesh: &mut Mesh, limits: JoinLimits) -> usize {
    let min_cos = limits.max_fold_degrees.to_radians().cos();
    let nf = mesh.faces.len();
    // Every undirected edge's uses: (face, corner k of the directed edge
    // k → k + 1).
    let mut uses: HashMap<(u32, u32), Uses> = HashMap::new();
    for f in 0..nf {
        let face = mesh.faces.face(f);
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            uses.entry((a.min(b), a.max(b)))
                .or_default()
                .push((f as u32, k as u8));
        }
    }
    // A sheet written twice, once reversed, is joined on both sides
    // alike: the pair of its front and the pair of its back.
    let twin = reversed_twins(mesh);
    let secondary = |f: u32| twin[f as usize] < f;
    let mut pairs: Vec<(f64, Pair, Option<Pair>)> = Vec::new();
    for u in uses.values() {
        let (back, front): (Uses, Uses) = u.iter().partition(|&&(f, _)| secondary(f));
        let &[a, b] = front.as_slice() else {
            continue;
        };
        let Some((warp, p)) = pair(mesh, a, b, &limits, min_cos) else {
            continue;
        };
        let twins = match back.as_slice() {
            [] => None,
            &[c, d] => {
                let mut want = [twin[a.0 as usize], twin[b.0 as usize]];
                let mut got = [c.0, d.0];
                want.sort_unstable();
                got.sort_unstable();
                if want != got {
                    continue;
                }
                // The back's pair, its first the twin of the front's first.
                let (c, d) = if c.0 == twin[a.0 as usize] {
                    (c, d)
                } else {
                    (d, c)
                };
                let any = JoinLimits {
                    max_warp: f64::INFINITY,
                    ..limits
                };
                let Some((_, q)) = pair(mesh, c, d, &any, min_cos) else {
                    continue;
                };
                Some(q)
            }
            _ => continue,
        };
        pairs.push((warp, p, twins));
    }
    // Flattest first; ties in face order, so the result does not depend
    // on the map's order.
    pairs.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then((a.1.first, a.1.second, a.1.corners).cmp(&(b.1.first, b.1.second, b.1.corners)))
    });
    // Per face: `None` as it is, else the quad's corners (input corner
    // indices) for its first triangle; its second is `taken` and dropped.
    let mut joined: Vec<Option<[usize; 4]>> = vec![None; nf];
    let mut taken = vec![false; nf];
    let mut count = 0;
    for (_, p, twins) in &pairs {
        let all = [Some(p), twins.as_ref()];
        let faces = all
            .iter()
            .flatten()
            .flat_map(|p| [p.first as usize, p.second as usize]);
        if faces.clone().any(|f| taken[f]) {
            continue;
        }
        for f in faces {
            taken[f] = true;
        }
        for p in all.iter().flatten() {
            joined[p.first as usize] = Some(p.corners);
            count += 1;
        }
    }
    if count == 0 {
        return 0;
    }
    let mut faces = Faces::with_capacity(nf - count, mesh.faces.indices.len() - 2 * count);
    let mut corner_src: Vec<usize> = Vec::with_capacity(mesh.faces.indices.len() - 2 * count);
    let mut face_parts = Vec::with_capacity(nf - count);
    for f in 0..nf {
        let corners: Vec<usize> = match joined[f] {
            Some(q) => q.to_vec(),
            None if taken[f] => continue,
            None => mesh.faces.corner_range(f).collect(),
        };
        faces.push(
            &corners
                .iter()
                .map(|&c| mesh.faces.indices[c])
                .collect::<Vec<u32>>(),
        );
        corner_src.extend_from_slice(&corners);
        face_parts.push(mesh.face_parts.get(f).copied().unwrap_or(0));
    }
    for a in &mut mesh.attributes {
        a.indices = corner_src.iter().map(|&c| a.indices[c]).collect();
    }
    if let Some(s) = &mut mesh.skinning {
        s.indices = corner_src.iter().map(|&c| s.indices[c]).collect();
    }
    mesh.faces = faces;
    mesh.face_parts = face_parts;
    count
}

/// For every face, the triangle that is its exact reverse (the same three
/// vertices the other way round), or `u32::MAX`: only where a vertex set
/// holds exactly those two faces.
fn reversed_twins(mesh: &Mesh) -> Vec<u32> {
    let nf = mesh.faces.len();
    let mut by_set: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
    for f in 0..nf {
        let face = mesh.faces.face(f);
        if face.len() == 3 {
            let mut key = [face[0], face[1], face[2]];
            key.sort_unstable();
            by_set.entry(key).or_default().push(f as u32);
        }
    }
    // A triangle's orientation: whether its corners are an even rotation
    // of their sorted order.
    let even = |f: u32| {
        let t = mesh.faces.face(f as usize);
        (t[0] < t[1]) as u8 + (t[1] < t[2]) as u8 + (t[2] < t[0]) as u8 == 2
    };
    let mut twin = vec![u32::MAX; nf];
    for faces in by_set.values() {
        if let &[a, b] = faces.as_slice() {
            if even(a) != even(b) {
                twin[a as usize] = b;
                twin[b as usize] = a;
            }
        }
    }
    twin
}

/// Two triangles that may be joined, and the quad's corners: the shared
/// edge `u → v` of the first, the second's third corner `x`, the first's
/// `w`, as `[u, x, v, w]` (the fan from `u` draws the second triangle,
/// then the first).
struct Pair {
    first: u32,
    second: u32,
    corners: [usize; 4],
}

/// The pair across one edge (used by `(f1, k1)` and `(f2, k2)` only), and
/// its warp, if the two can be joined.
fn pair(
    mesh: &Mesh,
    (f1, k1): (u32, u8),
    (f2, k2): (u32, u8),
    limits: &JoinLimits,
    min_cos: f64,
) -> Option<(f64, Pair)> {
    let (r1, r2) = (
        mesh.faces.corner_range(f1 as usize),
        mesh.faces.corner_range(f2 as usize),
    );
    if r1.len() != 3 || r2.len() != 3 || f1 == f2 {
        return None;
    }
    let part = |f: u32| mesh.face_parts.get(f as usize).copied();
    if part(f1) != part(f2) {
        return None;
    }
    let c1 = |i: u8| r1.start + ((k1 + i) % 3) as usize;
    let c2 = |i: u8| r2.start + ((k2 + i) % 3) as usize;
    let v = |c: usize| mesh.faces.indices[c];
    // First: u → v → w; second (opposite way along the edge): v → u → x.
    let (u, vv, w) = (c1(0), c1(1), c1(2));
    let (v2, u2, x) = (c2(0), c2(1), c2(2));
    if v(u) != v(u2) || v(vv) != v(v2) || v(w) == v(x) {
        return None;
    }
    // The same values on both sides of the shared edge.
    let same = |idx: &[u32]| idx[u] == idx[u2] && idx[vv] == idx[v2];
    if !mesh.attributes.iter().all(|a| same(&a.indices)) {
        return None;
    }
    if mesh.skinning.as_ref().is_some_and(|s| !same(&s.indices)) {
        return None;
    }
    let p = |c: usize| mesh.positions.get(v(c) as usize).copied();
    let quad = [p(u)?, p(x)?, p(vv)?, p(w)?];
    if !(fan_covers(&quad) && fan_covers(&[quad[1], quad[2], quad[3], quad[0]])) {
        return None;
    }
    // The fold across the shared edge: the two triangles' normals.
    let n = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
        let (a, b, c) = (a.map(f64::from), b.map(f64::from), c.map(f64::from));
        let (e, g) = (
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        );
        [
            e[1] * g[2] - e[2] * g[1],
            e[2] * g[0] - e[0] * g[2],
            e[0] * g[1] - e[1] * g[0],
        ]
    };
    let (n1, n2) = (n(quad[0], quad[2], quad[3]), n(quad[2], quad[0], quad[1]));
    let dot = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
    let len =
        (n1.iter().map(|x| x * x).sum::<f64>() * n2.iter().map(|x| x * x).sum::<f64>()).sqrt();
    // (A NaN turn, from a degenerate triangle, is no quad either.)
    if !matches!(
        dot.partial_cmp(&(min_cos * len)),
        Some(std::cmp::Ordering::Greater | std::cmp::Ordering::Equal)
    ) {
        return None;
    }
    let warp = segment_distance(quad[0], quad[2], quad[1], quad[3]);
    let relative = relative_warp(&quad);
    (warp <= limits.max_warp || relative <= limits.max_relative_warp).then_some((
        warp,
        Pair {
            first: f1,
            second: f2,
            corners: [u, x, vv, w],
        },
    ))
}

/// Distance between segments `ab` and `cd`, in double precision.
fn segment_distance(a: [f32; 3], b: [f32; 3], c: [f32; 3], d: [f32; 3]) -> f64 {
    let v = |p: [f32; 3]| DVec3::from(p.map(f64::from));
    let (p, q) = segment_segment_closest(v(a), v(b), v(c), v(d));
    p.distance(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::polygon::triangulate;
    use wildlod_mesh::{Attribute, ComponentFormat, Semantic};

    /// Limits of `max_warp` alone (no relative allowance, folds to 90°).
    fn limits(max_warp: f64) -> JoinLimits {
        JoinLimits {
            max_warp,
            max_relative_warp: 0.0,
            max_fold_degrees: 90.0,
        }
    }

    /// A 2 × 1 strip of unit squares, each split into two triangles along
    /// its diagonal, z from `lift` per vertex, UVs per corner.
    fn strip(lift: [f32; 6]) -> Mesh {
        let positions: Vec<[f32; 3]> = (0..6)
            .map(|i| [(i % 3) as f32, (i / 3) as f32, lift[i]])
            .collect();
        // Vertices 0 1 2 along y = 0, 3 4 5 along y = 1.
        let tris = [0u32, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4];
        let mut m = Mesh::from_polygons(positions.clone(), Faces::from_triangles(&tris));
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: positions.iter().flat_map(|p| [p[0] / 2.0, p[1]]).collect(),
            indices: tris.to_vec(),
            format: ComponentFormat::F32,
        });
        m
    }

    #[test]
    fn two_flat_squares_of_triangles_become_two_quads_drawing_the_same_triangles() {
        let mut m = strip([0.0; 6]);
        let before = triangulate(&m);
        assert_eq!(join_triangle_pairs(&mut m, limits(0.0)), 2);
        assert_eq!(m.faces.len(), 2);
        assert!((0..2).all(|f| m.faces.arity(f) == 4));
        m.validate().expect("valid");
        // Drawn as fans, the quads give back the input's triangles, with
        // the same UVs on every corner.
        let after = triangulate(&m);
        let tri = |t: &Mesh, f: usize| {
            let mut k: Vec<(u32, [u32; 2])> = t
                .faces
                .corner_range(f)
                .map(|c| {
                    let uv = t.attributes[0].corner_value(c).unwrap();
                    (t.faces.indices[c], [uv[0].to_bits(), uv[1].to_bits()])
                })
                .collect();
            k.sort();
            k
        };
        let mut a: Vec<_> = (0..4).map(|f| tri(&before, f)).collect();
        let mut b: Vec<_> = (0..4).map(|f| tri(&after, f)).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
    }

    #[test]
    fn a_sheet_written_twice_is_joined_alike_on_both_sides() {
        // The strip, then every triangle again the other way round (UVs
        // per corner copied): each square becomes a quad on the front and
        // its reverse on the back.
        let mut m = strip([0.0; 6]);
        let n = m.faces.len();
        let mut indices = m.faces.indices.clone();
        let mut uv = m.attributes[0].indices.clone();
        for f in 0..n {
            let r = m.faces.corner_range(f);
            for c in r.rev() {
                indices.push(m.faces.indices[c]);
                uv.push(m.attributes[0].indices[c]);
            }
        }
        m.faces = Faces::from_triangles(&indices);
        m.face_parts = vec![0; 2 * n];
        m.attributes[0].indices = uv;
        m.validate().expect("valid");
        assert_eq!(join_triangle_pairs(&mut m, limits(0.0)), 4);
        let sets: Vec<Vec<u32>> = (0..4)
            .map(|f| {
                let mut q = m.faces.face(f).to_vec();
                q.sort();
                q
            })
            .collect();
        assert_eq!(sets.iter().filter(|q| **q == [0, 1, 3, 4]).count(), 2);
        assert_eq!(sets.iter().filter(|q| **q == [1, 2, 4, 5]).count(), 2);
        // Front and back of one square wind opposite ways.
        let normal = |f: usize| {
            let q = m.faces.face(f);
            let p = |k: usize| m.positions[q[k] as usize];
            let (a, b, c) = (p(0), p(1), p(2));
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        };
        let ups = (0..4).filter(|&f| normal(f) > 0.0).count();
        assert_eq!(ups, 2);
    }

    #[test]
    fn a_seam_a_fold_or_another_part_keeps_the_triangles() {
        // A UV seam along the first square's diagonal (corner 4 is vertex
        // 4 in the second triangle): that square stays two triangles; the
        // triangle pair across the squares' shared side is joined instead.
        let mut m = strip([0.0; 6]);
        let uv = &mut m.attributes[0];
        uv.values.extend_from_slice(&[0.9, 0.9]);
        uv.indices[4] = 6;
        assert_eq!(join_triangle_pairs(&mut m, limits(0.0)), 1);
        let kept: Vec<u32> = {
            let f =
                (0..m.faces.len()).find(|&f| m.faces.arity(f) == 3 && m.faces.face(f).contains(&3));
            let mut t = m
                .faces
                .face(f.expect("the triangle 0, 4, 3 stays"))
                .to_vec();
            t.sort();
            t
        };
        assert_eq!(kept, vec![0, 3, 4]);
        // Another part for that triangle: the same.
        let mut m = strip([0.0; 6]);
        m.parts.push(m.parts[0].clone());
        m.face_parts[1] = 1;
        assert_eq!(join_triangle_pairs(&mut m, limits(0.0)), 1);
        assert!((0..m.faces.len()).any(|f| m.face_parts[f] == 1 && m.faces.arity(f) == 3));
        // A dart: the second square's corner 2 pulled in past its diagonal
        // 1–5, so the quad 5, 4, 1, 2 is not convex; the first square joins.
        let mut m = strip([0.0; 6]);
        m.positions[2] = [1.2, 0.9, 0.0];
        assert_eq!(join_triangle_pairs(&mut m, limits(0.0)), 1);
        assert_eq!(m.faces.arity(0), 4);
        assert_eq!(m.faces.face(0).iter().filter(|&&v| v == 2).count(), 0);
    }

    #[test]
    fn a_warped_square_is_joined_only_within_the_allowed_warp() {
        // One unit square of two triangles along the diagonal 0–2, corner
        // 3 lifted by 1: the other diagonal (1–3) passes 1/√6 from it.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
        ];
        let m0 = Mesh::from_polygons(positions, Faces::from_triangles(&[0, 1, 2, 0, 2, 3]));
        let warp = segment_distance(
            m0.positions[0],
            m0.positions[2],
            m0.positions[1],
            m0.positions[3],
        );
        assert!((warp - 1.0 / 6f64.sqrt()).abs() < 1e-9, "{warp}");
        // Relative to its longer diagonal (1–3, √3): 1/√18.
        let quad = [0, 1, 2, 3].map(|k| m0.positions[k]);
        assert!((relative_warp(&quad) - 1.0 / 18f64.sqrt()).abs() < 1e-9);
        for (rel, joined) in [(0.23, 0), (0.24, 1)] {
            let mut m = m0.clone();
            let l = JoinLimits {
                max_relative_warp: rel,
                ..limits(0.0)
            };
            assert_eq!(join_triangle_pairs(&mut m, l), joined, "{rel}");
        }
        let mut m = m0.clone();
        assert_eq!(join_triangle_pairs(&mut m, limits(0.4)), 0);
        let mut m = m0;
        assert_eq!(join_triangle_pairs(&mut m, limits(0.41)), 1);
        // Drawn from its first corner, the quad's fan is the shared
        // diagonal: the two input triangles.
        let q = m.faces.face(0).to_vec();
        let mut fan = [[q[0], q[1], q[2]], [q[0], q[2], q[3]]].map(|mut t| {
            t.sort();
            t
        });
        fan.sort();
        assert_eq!(fan, [[0, 1, 2], [0, 2, 3]]);
    }
}
