//! A triangle set with a BVH: the closest point on a whole surface.

use glam::DVec3;

use crate::aabb::Aabb;
use crate::bvh::Bvh;
use crate::closest::{closest_point_on_triangle, point_triangle_distance2};

/// Box of a triangle, empty unless all corners are finite: a NaN corner
/// must not leave a partial box that makes the triangle look reachable.
fn corner_box(c: &[DVec3; 3]) -> Aabb {
    if c.iter().all(|p| p.is_finite()) {
        Aabb::from_triangle(c[0], c[1], c[2])
    } else {
        Aabb::EMPTY
    }
}

/// The closest point of a [`TriangleSet`] to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index of the triangle (in the order given to [`TriangleSet::new`]).
    pub triangle: u32,
    /// The closest point.
    pub point: DVec3,
    /// Barycentric coordinates of `point` on the triangle's corners.
    pub barycentric: [f64; 3],
    /// Squared distance from the query to `point`.
    pub distance2: f64,
}

/// Triangles (as corner positions) with a BVH, for closest-point queries.
///
/// Triangles whose corners are not all finite, or that refer to a missing
/// position, are kept (indices stay those of the input) but never hit.
#[derive(Clone, Debug, Default)]
pub struct TriangleSet {
    bvh: Bvh,
    /// Corners of every triangle in the BVH's leaf order.
    slot_corners: Vec<[DVec3; 3]>,
    /// Leaf slot of every triangle.
    slot_of: Vec<u32>,
}

impl TriangleSet {
    /// A set from shared positions and index triples.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let corners =
            |t: &[u32; 3]| t.map(|v| positions.get(v as usize).copied().unwrap_or(DVec3::NAN));
        let boxes: Vec<Aabb> = triangles.iter().map(|t| corner_box(&corners(t))).collect();
        Self::assemble(Bvh::build(&boxes), |t| corners(&triangles[t as usize]))
    }

    /// A set from the three corners of every triangle.
    pub fn from_corners(corners: &[[DVec3; 3]]) -> Self {
        let boxes: Vec<Aabb> = corners.iter().map(corner_box).collect();
        Self::assemble(Bvh::build(&boxes), |t| corners[t as usize])
    }

    fn assemble(bvh: Bvh, corners: impl Fn(u32) -> [DVec3; 3]) -> Self {
        let order = bvh.slot_order();
        let mut slot_of = vec![0u32; order.len()];
        for (k, &t) in order.iter().enumerate() {
            slot_of[t as usize] = k as u32;
        }
        let slot_corners = order.iter().map(|&t| corners(t)).collect();
        TriangleSet {
            bvh,
            slot_corners,
            slot_of,
        }
    }

    /// Number of triangles.
    #[inline]
    pub fn len(&self) -> usize {
        self.slot_corners.len()
    }

    /// True when there is no triangle.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.slot_corners.is_empty()
    }

    /// Corners of triangle `t` (NaN corners for a triangle that referred to
    /// a missing position).
    #[inline]
    pub fn triangle(&self, t: u32) -> [DVec3; 3] {
        self.slot_corners[self.slot_of[t as usize] as usize]
    }

    /// The BVH over the triangles' boxes.
    #[inline]
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Bounds of the triangles with finite corners.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The closest point of the set to `p`, or `None` when the set has no
    /// triangle with finite corners (or `p` is NaN).
    #[inline]
    pub fn closest(&self, p: DVec3) -> Option<Hit> {
        self.closest_within(p, f64::INFINITY)
    }

    /// Squared distance from `p` to the set, or `None` as for
    /// [`TriangleSet::closest`]; skips computing the point itself.
    #[inline]
    pub fn distance2(&self, p: DVec3) -> Option<f64> {
        self.bvh
            .nearest_by_slot(p, f64::INFINITY, |k| {
                let c = &self.slot_corners[k];
                point_triangle_distance2(p, c[0], c[1], c[2])
            })
            .map(|(_, d2)| d2)
    }

    /// [`TriangleSet::distance2`] if it is at most `max_dist2`, else
    /// `None`: the search never opens a node farther than that, so telling
    /// that a point is within a known distance costs less than measuring
    /// how far it is.
    #[inline]
    pub fn distance2_within(&self, p: DVec3, max_dist2: f64) -> Option<f64> {
        self.bvh
            .nearest_by_slot(p, max_dist2, |k| {
                let c = &self.slot_corners[k];
                point_triangle_distance2(p, c[0], c[1], c[2])
            })
            .map(|(_, d2)| d2)
    }

    /// The closest point of the set to `p` if its squared distance is at
    /// most `max_dist2`. Among triangles at the same distance (a point on a
    /// shared edge) the lowest index wins.
    pub fn closest_within(&self, p: DVec3, max_dist2: f64) -> Option<Hit> {
        let (t, d2) = self.bvh.nearest_by_slot(p, max_dist2, |k| {
            let c = &self.slot_corners[k];
            point_triangle_distance2(p, c[0], c[1], c[2])
        })?;
        let c = self.triangle(t);
        let (point, barycentric) = closest_point_on_triangle(p, c[0], c[1], c[2]);
        Some(Hit {
            triangle: t,
            point,
            barycentric,
            distance2: d2,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;
    use wildlod_mesh::shapes;

    fn set_of(mesh: &wildlod_mesh::Mesh) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let t = shapes::triangulate(mesh);
        let pos = t
            .positions
            .iter()
            .map(|p| DVec3::from(p.map(f64::from)))
            .collect();
        let tris = t.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
        (pos, tris)
    }

    #[test]
    fn closest_point_on_a_cube_from_outside_a_face_is_its_projection() {
        let (pos, tris) = set_of(&shapes::cube());
        let s = TriangleSet::new(&pos, &tris);
        let h = s.closest(DVec3::new(0.25, 0.5, 3.0)).expect("a hit");
        assert!((h.point - DVec3::new(0.25, 0.5, 1.0)).length() < 1e-15);
        assert!((h.distance2 - 4.0).abs() < 1e-12);
        let c = s.triangle(h.triangle);
        let back = c[0] * h.barycentric[0] + c[1] * h.barycentric[1] + c[2] * h.barycentric[2];
        assert!((back - h.point).length() < 1e-12);
    }

    #[test]
    fn empty_and_invalid_sets_give_no_hit() {
        assert!(TriangleSet::new(&[], &[]).closest(DVec3::ZERO).is_none());
        let s = TriangleSet::new(&[DVec3::ZERO, DVec3::X], &[[0, 1, 7]]);
        assert!(s.closest(DVec3::ZERO).is_none());
        let (pos, tris) = set_of(&shapes::cube());
        let s = TriangleSet::new(&pos, &tris);
        assert!(s.closest(DVec3::NAN).is_none());
        assert!(s.closest_within(DVec3::new(0.5, 0.5, 3.0), 3.9).is_none());
        assert!(s.closest_within(DVec3::new(0.5, 0.5, 3.0), 4.0).is_some());
    }

    #[test]
    fn distance_within_a_bound_is_the_distance_or_none_beyond_it() {
        // (0.25, 0.5, 3) is 2 above the cube's top face: squared 4.
        let (pos, tris) = set_of(&shapes::cube());
        let s = TriangleSet::new(&pos, &tris);
        let p = DVec3::new(0.25, 0.5, 3.0);
        assert_eq!(s.distance2_within(p, 4.0), s.distance2(p));
        assert!((s.distance2_within(p, 100.0).unwrap() - 4.0).abs() < 1e-12);
        assert_eq!(s.distance2_within(p, 3.9), None);
        assert_eq!(s.distance2_within(p, 0.0), None);
    }

    #[test]
    fn closest_equals_brute_force_on_a_torus_and_random_soup() {
        let mut rng = Rng::new(21);
        let (pos, tris) = set_of(&shapes::torus(24, 12, 2.0, 0.5));
        let mut soup: Vec<[DVec3; 3]> = tris.iter().map(|t| t.map(|v| pos[v as usize])).collect();
        for _ in 0..300 {
            let c = DVec3::new(
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                rng.range(-1.0, 1.0),
            );
            let mut t = [c; 3];
            for p in &mut t {
                *p += DVec3::new(
                    rng.range(-0.3, 0.3),
                    rng.range(-0.3, 0.3),
                    rng.range(-0.3, 0.3),
                );
            }
            soup.push(t);
        }
        let s = TriangleSet::from_corners(&soup);
        for _ in 0..2000 {
            let p = DVec3::new(
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
                rng.range(-2.0, 2.0),
            );
            let h = s.closest(p).expect("a hit");
            let (bt, bd) = soup
                .iter()
                .enumerate()
                .map(|(i, c)| (i as u32, point_triangle_distance2(p, c[0], c[1], c[2])))
                .fold(
                    (u32::MAX, f64::INFINITY),
                    |a, b| if b.1 < a.1 { b } else { a },
                );
            assert_eq!(h.distance2, bd);
            assert_eq!(h.triangle, bt);
            assert_eq!(s.distance2(p), Some(bd));
        }
    }
}
