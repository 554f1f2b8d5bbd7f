//! Per-edge tangent quadrics (Knodt 2024 §3.1, Eq. 2, Alg. 1 lines 5–11).
//!
//! Face planes leave a vertex free to slide within a flat region or along a
//! tube's axis: the quadric is degenerate there, so collapses place vertices
//! anywhere in the tangent plane, edge flow is lost, and thin parts shrink
//! (a tube's planes all contain its axis). Knodt adds, for every edge
//! `(e0, e1)` and every face `f` on it, a plane through the edge that is
//! orthogonal to `f`: normal `normalize(e0 − e1) × n(f)`, weighted by
//! `w · |e0 − e1|²` with
//!
//! `w = max(dihedral / π (edges of two faces) or 1 (others), λ_sym·s, λ_joint·d, 0.01)`,
//!
//! added to both endpoints with memory. Sharp edges (a tube's rim, a crease)
//! get weight near 1/2 and hold their place; flat edges keep a small weight
//! that regularizes the tangent plane and spaces vertices evenly.
//!
//! Eq. 2 weighs by `|e0 − e1|`, but the face planes it is balanced against
//! are weighted by area (Knodt Alg. 1 line 4), so the balance depends on the
//! mesh's scale: on our unit-diagonal meshes, where edges are about 1e-3
//! long, the tangent planes outweighed the face planes by the inverse edge
//! length, and turning them on at 1/3 raised the Chamfer distance of
//! `manifold/armadillo` at 50% elevenfold (0.000101 → 0.001125). With the
//! squared length both terms scale like an area: the balance is Eq. 2's
//! where edges have unit length, at every scale (armadillo: 0.000150).

use glam::DVec3;
use rayon::prelude::*;

use crate::prepare::complex::Complex;
use crate::terms::quadric::Quadric;

/// Floor of `w` in Eq. 2 ("to prevent degenerate quadrics", Knodt §3.1).
const MIN_WEIGHT: f64 = 1e-2;

/// Optional per-edge importance inputs of Eq. 2.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct EdgeImportance<'a> {
    /// λ_sym · s per edge (Knodt's soft symmetry), or empty.
    pub symmetry: &'a [f64],
    /// λ_joint · d per edge (joint-influence difference), or empty.
    pub joints: &'a [f64],
}

/// Knodt Eq. 3: half the ℓ1 distance between two joint-influence
/// distributions given as sparse (joint, weight) lists; 0 for identical
/// influences, 1 for disjoint ones (when each sums to 1).
pub(crate) fn joint_difference(a: &[(u32, f32)], b: &[(u32, f32)]) -> f64 {
    let weight = |list: &[(u32, f32)], j: u32| -> f64 {
        list.iter()
            .filter(|(k, _)| *k == j)
            .map(|(_, w)| *w as f64)
            .sum()
    };
    let mut sum = 0.0;
    for &(j, w) in a {
        sum += (w as f64 - weight(b, j)).abs();
    }
    for &(j, w) in b {
        if !a.iter().any(|(k, _)| *k == j) {
            sum += (w as f64).abs();
        }
    }
    0.5 * sum
}

/// `w` of Eq. 2 for an edge whose faces have the given unit normals.
pub(crate) fn edge_weight(normals: &[DVec3], extra: f64) -> f64 {
    let base = if normals.len() == 2 {
        normals[0].dot(normals[1]).clamp(-1.0, 1.0).acos() / std::f64::consts::PI
    } else {
        1.0
    };
    base.max(extra).max(MIN_WEIGHT)
}

/// The tangent quadric of one (edge, face) pair, unweighted: the plane
/// through `e0` with normal `normalize(e0 − e1) × n`.
pub(crate) fn tangent_plane(e0: DVec3, e1: DVec3, n: DVec3) -> Option<Quadric> {
    let d = e0 - e1;
    let len = d.length();
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let t = (d / len).cross(n);
    let tl = t.length();
    // An edge parallel to the face normal (a degenerate face) has no tangent.
    if tl.is_nan() || tl <= 1e-12 {
        return None;
    }
    Some(Quadric::plane(t / tl, e0, 1.0))
}

/// The unit normals of the faces that use `v`–`k` as a side (faces without
/// area are left out), into `out` (cleared first).
pub(crate) fn side_normals(
    c: &Complex,
    normals: &[Option<DVec3>],
    v: u32,
    k: u32,
    out: &mut Vec<DVec3>,
) {
    out.clear();
    for &f in &c.vert_faces[v as usize] {
        let face = c.face(f);
        let n = face.len();
        let at = face.iter().position(|&x| x == v);
        let side = at.is_some_and(|p| {
            face[if p + 1 == n { 0 } else { p + 1 }] == k
                || face[if p == 0 { n - 1 } else { p - 1 }] == k
        });
        if side {
            if let Some(nf) = normals[f as usize] {
                out.push(nf);
            }
        }
    }
}

/// Sum over the edges of each vertex of its tangent quadrics, times
/// `scale`: the per-vertex addition of this term. `normals[f]` is the unit
/// normal of face `f` (None for faces without area). Summed per vertex in
/// star order, so independent of thread count.
pub(crate) fn tangent_quadrics(
    c: &Complex,
    normals: &[Option<DVec3>],
    importance: EdgeImportance<'_>,
    scale: f64,
) -> Vec<Quadric> {
    (0..c.pos.len() as u32)
        .into_par_iter()
        .map_init(Vec::new, |faces: &mut Vec<DVec3>, v| {
            let mut q = Quadric::ZERO;
            for &e in &c.vert_edges[v as usize] {
                let k = c.other(e, v);
                side_normals(c, normals, v, k, faces);
                if faces.is_empty() {
                    continue;
                }
                let extra = importance
                    .symmetry
                    .get(e as usize)
                    .copied()
                    .unwrap_or(0.0)
                    .max(importance.joints.get(e as usize).copied().unwrap_or(0.0));
                let w = edge_weight(faces, extra);
                let [a, b] = c.edges[e as usize].ends;
                let (e0, e1) = (c.pos[a as usize], c.pos[b as usize]);
                let len = (e0 - e1).length();
                for &nf in faces.iter() {
                    if let Some(t) = tangent_plane(e0, e1, nf) {
                        q += t.scaled(scale * w * len * len);
                    }
                }
            }
            q
        })
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The two-quad hinge of issue 5: quads (0,1,2,3) in the plane z = 0 and
    /// (1,0,4,5) folded up to the plane x… sharing the edge 0–1 on the x axis.
    ///
    /// ```text
    ///   3 (0,1,0)   2 (1,1,0)        5 (0,0,1)   4 (1,0,1)
    ///   0 (0,0,0)   1 (1,0,0)        (vertical quad above the same edge)
    /// ```
    pub(crate) fn hinge() -> Complex {
        let pos = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        Complex::new(pos, &[0, 4, 8], &[0, 1, 2, 3, 1, 0, 5, 4]).0
    }

    #[test]
    fn dihedral_weight_of_a_right_angle_is_one_half() {
        // Normals +z and +y meet at 90°: w = (π/2)/π = 1/2.
        assert!((edge_weight(&[DVec3::Z, DVec3::Y], 0.0) - 0.5).abs() < 1e-15);
        // Coplanar faces: w is the floor 0.01.
        assert_eq!(edge_weight(&[DVec3::Z, DVec3::Z], 0.0), MIN_WEIGHT);
        // A border edge (one face): w = 1; importance can only raise it.
        assert_eq!(edge_weight(&[DVec3::Z], 0.0), 1.0);
        assert_eq!(edge_weight(&[DVec3::Z, DVec3::Z], 0.7), 0.7);
    }

    #[test]
    fn joint_difference_follows_eq3() {
        // Knodt Eq. 3: j0 = {a: α, b: 1−α}, j1 = {b: β, c: 1−β} gives
        // ½(α + |(1−α) − β| + (1−β)). With α = 0.25, β = 0.5:
        // ½(0.25 + 0.25 + 0.5) = 0.5.
        let (a, b, c) = (0, 1, 2);
        let d = joint_difference(&[(a, 0.25), (b, 0.75)], &[(b, 0.5), (c, 0.5)]);
        assert!((d - 0.5).abs() < 1e-7);
        assert_eq!(joint_difference(&[(3, 1.0)], &[(3, 1.0)]), 0.0);
        assert_eq!(joint_difference(&[(3, 1.0)], &[(4, 1.0)]), 1.0);
        assert_eq!(joint_difference(&[], &[]), 0.0);
    }

    #[test]
    fn joint_importance_raises_the_weight_of_an_edge_between_bones() {
        let c = hinge();
        let normals: Vec<Option<DVec3>> = (0..2)
            .map(|f| crate::prepare::geometry::face_plane(&c, f).map(|p| p.0))
            .collect();
        let plain = tangent_quadrics(&c, &normals, EdgeImportance::default(), 1.0);
        // Hinge edge 0–1 is edge 0 (edges are sorted by endpoints): give it
        // λ_joint·d = 0.9, above its dihedral weight 1/2.
        let e = c.edge_between(0, 1).unwrap() as usize;
        let mut joints = vec![0.0; c.edges.len()];
        joints[e] = 0.9;
        let heavy = tangent_quadrics(
            &c,
            &normals,
            EdgeImportance {
                symmetry: &[],
                joints: &joints,
            },
            1.0,
        );
        // At vertex 0 the hinge planes y = 0 and z = 0 now weigh 0.9 each.
        let p = DVec3::new(0.3, 0.5, -0.7);
        let expected = 0.9 * 0.25 + 0.9 * 0.49 + 2.0 * 0.09;
        assert!((heavy[0].eval(p) - expected).abs() < 1e-12);
        assert!(heavy[0].eval(p) > plain[0].eval(p));
    }

    #[test]
    fn tangent_plane_is_orthogonal_to_face_and_contains_edge() {
        // Edge along x in the face z = 0 (normal +z): tangent normal is
        // x × z = -y, plane through the edge: E = y².
        let q = tangent_plane(DVec3::ZERO, DVec3::X, DVec3::Z).unwrap();
        assert!((q.eval(DVec3::new(5.0, 2.0, 7.0)) - 4.0).abs() < 1e-12);
        assert!(q.eval(DVec3::new(3.0, 0.0, -1.0)).abs() < 1e-12);
        assert!(tangent_plane(DVec3::ZERO, DVec3::ZERO, DVec3::Z).is_none());
    }

    #[test]
    fn tangent_planes_scale_like_areas() {
        // One triangle (0,0,0), (2,0,0), (0,2,0) in z = 0: at vertex 0 the
        // edges 0–1 (length 2, plane y = 0) and 0–2 (length 2, plane x = 0)
        // have one face each, so w = 1 and the weight is 1 · 2² = 4:
        // E0(p) = 4y² + 4x². Scaling the mesh by 2 scales the face's area
        // quadric by 2⁴ (area 4×, squared distances 4×), and so this.
        let pos = vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ];
        let c = Complex::new(pos, &[0, 3], &[0, 1, 2]).0;
        let normals = vec![Some(DVec3::Z)];
        let q = tangent_quadrics(&c, &normals, EdgeImportance::default(), 1.0);
        let p = DVec3::new(0.3, -0.5, 0.7);
        let expected = 4.0 * 0.25 + 4.0 * 0.09;
        assert!((q[0].eval(p) - expected).abs() < 1e-12, "{}", q[0].eval(p));
    }

    #[test]
    fn hinge_edge_gets_two_tangent_planes_at_weight_one_half_times_length() {
        let c = hinge();
        // Face normals: quad 0 is +z, quad 1 (1,0,5,4) faces -y… compute.
        let normals: Vec<Option<DVec3>> = (0..2)
            .map(|f| crate::prepare::geometry::face_plane(&c, f).map(|p| p.0))
            .collect();
        let n0 = normals[0].unwrap();
        let n1 = normals[1].unwrap();
        assert!((n0.dot(n1)).abs() < 1e-12, "the hinge is a right angle");
        let q = tangent_quadrics(&c, &normals, EdgeImportance::default(), 1.0);
        // At vertex 0 the hinge edge 0–1 (length 1, w = 1/2) contributes
        // planes y = 0 (from the flat quad) and z = 0 (from the upright one),
        // each weighted 1/2. The border edges 0–3 (in quad 0) and 0–5 (in
        // quad 1) have one face each, w = 1, length 1: planes x = 0 twice.
        // So E0(p) = ½y² + ½z² + x² + x² at p = (x, y, z).
        let p = DVec3::new(0.3, 0.5, -0.7);
        let expected = 0.5 * 0.25 + 0.5 * 0.49 + 2.0 * 0.09;
        assert!(
            (q[0].eval(p) - expected).abs() < 1e-12,
            "{} vs {expected}",
            q[0].eval(p)
        );
    }
}
