//! Parts no one can see: a part wholly inside another part that is closed,
//! faces outward and is drawn opaque.
//!
//! Models carry parts inside others: the shaft and bearings of a closed CAD
//! housing, the engine block under a sealed body, a tongue inside a closed
//! head. Behind an opaque enclosure they never show, yet a level of detail
//! that keeps them spends its budget on them and takes it from what shows.
//! Here a part (a set of faces joined by shared vertices) goes before
//! simplifying when
//!
//! - another part encloses it: that part is closed (every side is used by
//!   exactly two of its faces, once in each direction), faces outward (a
//!   point of the enclosed part has winding number +1 in it, counted as
//!   the signed crossings of rays from the point, on three rays that must
//!   agree; a room modelled from the inside, facing in, encloses nothing)
//!   and is drawn opaque and one-sided (none of its faces is seen through,
//!   none has a twin: from inside either of those shows what it holds);
//! - and the two never touch: no face of the part comes within [`CONTACT`]
//!   of a face of the enclosure. The part being connected, one point of it
//!   inside then puts all of it inside.
//!
//! The contact test is exact up to [`CONTACT`], and a ray that rounding
//! fools (one through an edge) miscounts alone: the three must agree, so
//! it keeps the part. A part that shows through an opening, pokes out or
//! rests on the enclosure's inner wall stays. A part costs three rays and
//! a contact query in the enclosure's tree, whatever the enclosure's size.
//! What no mesh can tell, an animation that opens or moves the enclosure,
//! the caller rules out ([`crate::Guards::drop_enclosed_parts`]). Not in
//! either paper: the reverse copies of faces that cannot be seen go for the
//! same reason (`twins.rs`).

use std::collections::HashSet;

use glam::DVec3;
use wildlod_geometry::{ray_triangle, triangle_triangle_distance, Aabb, Bvh};

use crate::prepare::complex::Complex;

/// Closer than this (normalized coordinates: a share of the bounding-box
/// diagonal) a part touches its enclosure, and stays: far below any gap a
/// renderer shows, far above rounding.
const CONTACT: f64 = 1e-7;

/// Directions of the rays a point's winding number is counted on: no two
/// alike and none along an axis, so that a ray grazing an edge of a
/// modelled (axis-aligned, gridded) surface on one is unlikely on the
/// others.
const RAYS: [DVec3; 3] = [
    DVec3::new(0.267_261_2, 0.534_522_5, 0.801_783_7),
    DVec3::new(-0.717_137_2, 0.358_568_6, 0.597_614_3),
    DVec3::new(0.424_264_1, -0.848_528_1, 0.316_227_8),
];

/// How far a ray runs (normalized coordinates: the input spans a unit
/// diagonal).
const RAY_LENGTH: f64 = 4.0;

/// Drops the parts of `c` that another part encloses (see the module
/// documentation), where `see_through` names the faces seen through (an
/// enclosure with one of them shows what it holds). Call before the
/// twins are folded away (`twins.rs`): a face with a twin is two-sided.
/// Returns how many parts went.
pub(crate) fn drop_enclosed_parts(c: &mut Complex, see_through: &dyn Fn(u32) -> bool) -> usize {
    let (labels, count) = c.part_labels();
    if count < 2 {
        return 0;
    }
    // Each part's faces, `order[start[p]..start[p + 1]]`.
    let mut start = vec![0usize; count + 1];
    for f in c.live_faces() {
        start[labels[c.face(f)[0] as usize] as usize + 1] += 1;
    }
    for p in 0..count {
        start[p + 1] += start[p];
    }
    let mut order = vec![0u32; start[count]];
    let mut fill = start.clone();
    for f in c.live_faces() {
        let p = labels[c.face(f)[0] as usize] as usize;
        order[fill[p]] = f;
        fill[p] += 1;
    }
    let faces = |p: usize| &order[start[p]..start[p + 1]];
    let two_sided: HashSet<u32> = c.riders.iter().map(|r| r.of).collect();
    // A closed surface has at least four faces.
    let encloser: Vec<bool> = (0..count)
        .map(|p| {
            let fs = faces(p);
            fs.len() >= 4
                && fs
                    .iter()
                    .all(|&f| !see_through(f) && !two_sided.contains(&f))
                && closed_and_consistent(c, fs)
        })
        .collect();
    if !encloser.contains(&true) {
        return 0;
    }
    let boxes: Vec<Aabb> = (0..count)
        .map(|p| {
            Aabb::from_points(
                faces(p)
                    .iter()
                    .flat_map(|&f| c.face(f).iter().map(|&v| c.pos[v as usize])),
            )
        })
        .collect();
    // Parts with faces only: a welded vertex no face uses is a part with
    // an empty box, which has no place in a tree.
    let with_faces: Vec<usize> = (0..count).filter(|&p| !faces(p).is_empty()).collect();
    let parts = Bvh::build(&with_faces.iter().map(|&p| boxes[p]).collect::<Vec<_>>());
    let mut dropped = vec![false; count];
    for q in (0..count).filter(|&q| encloser[q]) {
        let mut inner = Vec::new();
        parts.query_within(&boxes[q], 0.0, |k| {
            let p = with_faces[k as usize];
            if p != q && !dropped[p] && strictly_inside(&boxes[p], &boxes[q]) {
                inner.push(p);
            }
        });
        if inner.is_empty() {
            continue;
        }
        let shell = Shell::new(c, faces(q));
        for p in inner {
            let point = c.pos[c.face(faces(p)[0])[0] as usize];
            if shell.holds(point) && !shell.touches(c, faces(p)) {
                dropped[p] = true;
            }
        }
    }
    let mut n = 0;
    for p in (0..count).filter(|&p| dropped[p]) {
        for &f in faces(p) {
            c.faces[f as usize].len = 0;
        }
        n += 1;
    }
    if n > 0 {
        c.riders.retain(|r| c.faces[r.of as usize].len > 0);
        c.triangles = c.count_triangles();
    }
    n
}

/// Whether `inner` lies strictly inside `outer` on every axis.
fn strictly_inside(inner: &Aabb, outer: &Aabb) -> bool {
    inner.min.cmpgt(outer.min).all() && inner.max.cmplt(outer.max).all()
}

/// Whether the faces `fs` close up: every side is used exactly once in each
/// direction (which also makes the orientation consistent).
fn closed_and_consistent(c: &Complex, fs: &[u32]) -> bool {
    let mut sides: Vec<u64> = Vec::new();
    for &f in fs {
        let face = c.face(f);
        let n = face.len();
        for k in 0..n {
            sides.push(((face[k] as u64) << 32) | face[(k + 1) % n] as u64);
        }
    }
    sides.sort_unstable();
    if sides.windows(2).any(|w| w[0] == w[1]) {
        return false;
    }
    sides
        .iter()
        .all(|&s| sides.binary_search(&s.rotate_right(32)).is_ok())
}

/// An enclosure's faces as triangles, with a tree for contacts.
struct Shell {
    triangles: Vec<[DVec3; 3]>,
    tree: Bvh,
}

impl Shell {
    fn new(c: &Complex, fs: &[u32]) -> Shell {
        Shell::of(fan(c, fs))
    }

    fn of(triangles: Vec<[DVec3; 3]>) -> Shell {
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| Aabb::from_triangle(t[0], t[1], t[2]))
            .collect();
        Shell {
            tree: Bvh::build(&boxes),
            triangles,
        }
    }

    /// Whether `p` has winding number 1 in the shell on every ray of
    /// [`RAYS`]: inside it, the shell facing outward.
    fn holds(&self, p: DVec3) -> bool {
        RAYS.iter().all(|&d| self.crossings(p, d) == 1)
    }

    /// The signed count of the shell's triangles the ray from `p` along `d`
    /// crosses: +1 leaving through a triangle's front, -1 entering. For a
    /// closed shell, the winding number of `p` (unless the ray meets an
    /// edge, which can count a crossing twice or not at all).
    fn crossings(&self, p: DVec3, d: DVec3) -> i64 {
        let mut n = 0i64;
        self.tree.any_hit(p, d, RAY_LENGTH, |i| {
            let [a, b, c] = self.triangles[i as usize];
            if ray_triangle(p, d, a, b, c).is_some_and(|t| t > 0.0) {
                n += if (b - a).cross(c - a).dot(d) > 0.0 {
                    1
                } else {
                    -1
                };
            }
            false
        });
        n
    }

    /// Whether a face of `fs` comes within [`CONTACT`] of the shell.
    fn touches(&self, c: &Complex, fs: &[u32]) -> bool {
        fan(c, fs).iter().any(|t| {
            let mut hit = false;
            self.tree
                .query_within(&Aabb::from_triangle(t[0], t[1], t[2]), CONTACT, |i| {
                    hit = hit
                        || triangle_triangle_distance(t, &self.triangles[i as usize]) <= CONTACT;
                });
            hit
        })
    }
}

/// The faces `fs` fanned into triangles.
fn fan(c: &Complex, fs: &[u32]) -> Vec<[DVec3; 3]> {
    let mut out = Vec::new();
    for &f in fs {
        let face = c.face(f);
        let p0 = c.pos[face[0] as usize];
        for k in 1..face.len().saturating_sub(1) {
            out.push([p0, c.pos[face[k] as usize], c.pos[face[k + 1] as usize]]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's six faces as twelve triangles, facing out.
    fn cube() -> Vec<[DVec3; 3]> {
        let m = wildlod_mesh::shapes::cube();
        let at = |v: u32| DVec3::from(m.positions[v as usize].map(f64::from));
        m.faces
            .iter()
            .flat_map(|q| {
                [
                    [at(q[0]), at(q[1]), at(q[2])],
                    [at(q[0]), at(q[2]), at(q[3])],
                ]
            })
            .collect()
    }

    #[test]
    fn a_cube_holds_its_inside_only_when_it_faces_out() {
        let out = cube();
        // Facing out: each face's normal points away from the centre.
        let centre = DVec3::splat(0.5);
        for t in &out {
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            assert!(n.dot((t[0] + t[1] + t[2]) / 3.0 - centre) > 0.0);
        }
        let shell = Shell::of(out.clone());
        for p in [centre, DVec3::new(0.1, 0.9, 0.2), DVec3::splat(0.999)] {
            assert!(RAYS.iter().all(|&d| shell.crossings(p, d) == 1), "{p}");
            assert!(shell.holds(p), "{p}");
        }
        for p in [
            DVec3::splat(1.5),
            DVec3::new(0.5, 0.5, -0.01),
            DVec3::new(-0.5, 0.2, 0.2),
        ] {
            assert!(RAYS.iter().all(|&d| shell.crossings(p, d) == 0), "{p}");
            assert!(!shell.holds(p), "{p}");
        }
        // Facing in: -1 inside, held nowhere.
        let inward = Shell::of(out.iter().map(|t| [t[0], t[2], t[1]]).collect());
        assert_eq!(inward.crossings(centre, RAYS[0]), -1);
        assert!(!inward.holds(centre));
        // The rays are unit length and apart.
        for (i, a) in RAYS.iter().enumerate() {
            assert!((a.length() - 1.0).abs() < 1e-6);
            for b in &RAYS[i + 1..] {
                assert!(a.dot(*b).abs() < 0.9);
            }
        }
    }

    #[test]
    fn a_box_strictly_inside_another_is_inside_on_every_axis() {
        let outer = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let inner = Aabb::new(DVec3::splat(0.2), DVec3::splat(0.8));
        assert!(strictly_inside(&inner, &outer));
        assert!(!strictly_inside(&outer, &inner));
        // Resting on the floor is not strictly inside.
        let resting = Aabb::new(DVec3::new(0.2, 0.0, 0.2), DVec3::splat(0.8));
        assert!(!strictly_inside(&resting, &outer));
    }
}
