//! Twins that cannot be seen: the reversed copies of faces whose other
//! side is enclosed.
//!
//! Exporters make a sheet double-sided by writing every face twice, once
//! each way (SketchUp and many CAD exports do it for whole models). On an
//! open sheet both sides show, and the twins ride along with their faces
//! (see [`crate::prepare::complex::Rider`]). On a closed surface one copy of each
//! face looks into the solid: with an opaque material it is never seen, so
//! a level of detail that keeps it spends half its budget on nothing.
//! Blender drops such copies when it imports a file.
//!
//! Here a copy goes when it provably cannot be seen:
//! - on a closed part (no border side, or only cracks along T-junctions),
//!   the copy that looks into the solid, by the sign of the part's volume;
//! - elsewhere, a copy from whose middle no ray of a fixed hemisphere of
//!   directions escapes the mesh and no line of sight reaches an opening
//!   of its part (points along its border): the inside of an almost closed
//!   shell away from its openings. The lines of sight keep what a fixed
//!   set of directions misses: deep in an open pipe a face sees out only
//!   along the pipe, and through a hole in a sphere every inside face.
//!
//! Faces seen through (a blended material) keep both sides.

use crate::prepare::complex::{side_key, sides_used_once, Complex};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use wildlod_geometry::{Aabb, Bvh};

/// Border sides a closed part may have as cracks (checked pairwise, so the
/// check stays cheap); a part with more is open.
const MAX_CRACK_SIDES: usize = 64;

/// How far (relative to the bounding-box diagonal: positions are
/// normalized) a point of a border side may be from another border side
/// and still count as touching it: float noise of an exporter, not a gap.
const CRACK_TOLERANCE: f64 = 1e-5;

/// Drops the copies of twinned faces that cannot be seen (see the module
/// documentation), keeping of each face the copy that can, except where
/// `see_through` says an input face is seen through. Works on a complex
/// with or without star lists (call before [`Complex::build_adjacency`]).
/// Returns the input faces dropped.
///
/// Cost: sorting the sides, plus on parts that are not closed up to
/// 2 × ([`RAYS`] + [`OPENING_POINTS`]) ray casts per twinned face (a
/// doubled dragon of 1.7 M triangles with a hole: 30 s on two cores; a
/// doubled jagged open grid of 2 M triangles 14 s; flat sheets and foliage
/// cards far less, their first ray escapes).
pub(crate) fn drop_hidden_twins(c: &mut Complex, see_through: &dyn Fn(u32) -> bool) -> usize {
    if c.riders.is_empty() {
        return 0;
    }
    // Boundary vertices: the ends of sides that occur once.
    let mut sides: Vec<u64> = Vec::with_capacity(c.slot_vertex.len());
    for f in c.live_faces() {
        let face = c.face(f);
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            sides.push(side_key(a, b));
        }
    }
    sides.par_sort_unstable();
    let (labels, parts) = c.part_labels();
    let mut closed = vec![true; parts];
    let mut border: Vec<(u32, u32)> = sides_used_once(&sides).collect();
    drop(sides);
    // A border whose every side lies along other border sides of its part
    // is a crack, not an opening: a T-junction (one long side facing a row
    // of short ones), as CAD and SketchUp exports leave them. The part is
    // closed all the same. A part with many border sides is open.
    border.sort_by_key(|&(a, _)| labels[a as usize]);
    let mut g = 0;
    while g < border.len() {
        let part = labels[border[g].0 as usize];
        let mut h = g + 1;
        while h < border.len() && labels[border[h].0 as usize] == part {
            h += 1;
        }
        let group = &border[g..h];
        if group.len() > MAX_CRACK_SIDES || !cracks_only(c, group) {
            closed[part as usize] = false;
        }
        g = h;
    }
    // Six times the enclosed volume of each part, by its faces' fans.
    let mut volume = vec![0.0f64; parts];
    for f in c.live_faces() {
        let face = c.face(f);
        let p0 = c.pos[face[0] as usize];
        let mut v = 0.0;
        for k in 1..face.len() - 1 {
            v += p0.dot(c.pos[face[k] as usize].cross(c.pos[face[k + 1] as usize]));
        }
        volume[labels[face[0] as usize] as usize] += v;
    }
    // What happens to each face's twins: by the part's orientation on a
    // closed part, by casting rays elsewhere.
    let riders = std::mem::take(&mut c.riders);
    let mut faces: Vec<u32> = riders.iter().map(|r| r.of).collect();
    faces.dedup();
    let seen: Vec<bool> = {
        let mut seen = vec![false; faces.len()];
        let mut g = 0;
        for r in &riders {
            while faces[g] != r.of {
                g += 1;
            }
            seen[g] |= see_through(r.face) || see_through(r.of);
        }
        seen
    };
    let part_of = |f: u32| c.face(f).first().map(|&v| labels[v as usize] as usize);
    let mut verdict: Vec<Verdict> = faces
        .iter()
        .zip(&seen)
        .map(|(&f, &seen)| match part_of(f) {
            _ if seen => Verdict::Keep,
            Some(p) if closed[p] && volume[p] < 0.0 => Verdict::Swap,
            Some(p) if closed[p] => Verdict::DropTwins,
            Some(_) => Verdict::Look,
            None => Verdict::Keep,
        })
        .collect();
    if verdict.contains(&Verdict::Look) {
        // The openings of each part with faces to look at: points along
        // its border sides (`border` is sorted by part). Only those parts:
        // a soup has a part per face.
        let mut openings: HashMap<usize, Vec<DVec3>> = HashMap::new();
        for (&f, _) in faces
            .iter()
            .zip(&verdict)
            .filter(|(_, v)| **v == Verdict::Look)
        {
            let Some(p) = part_of(f) else { continue };
            if openings.contains_key(&p) {
                continue;
            }
            let lo = border.partition_point(|&(a, _)| (labels[a as usize] as usize) < p);
            let hi = border.partition_point(|&(a, _)| (labels[a as usize] as usize) <= p);
            let sides = &border[lo..hi];
            let stride = sides.len().div_ceil(OPENING_POINTS).max(1);
            let points = sides
                .iter()
                .step_by(stride)
                .map(|&(a, b)| 0.5 * (c.pos[a as usize] + c.pos[b as usize]))
                .collect();
            openings.insert(p, points);
        }
        let sight = Sight::new(c);
        verdict
            .par_iter_mut()
            .zip(&faces)
            .filter(|(v, _)| **v == Verdict::Look)
            .for_each(|(v, &f)| {
                let open = part_of(f)
                    .and_then(|p| openings.get(&p))
                    .map_or(&[][..], |v| &v[..]);
                *v = sight.verdict(c, f, open);
            });
    }
    let mut dropped = 0;
    let mut kept = Vec::with_capacity(riders.len());
    let mut g = 0;
    for r in riders {
        while faces[g] != r.of {
            g += 1;
        }
        let of = r.of;
        match verdict[g] {
            Verdict::Keep | Verdict::Look => {
                kept.push(r);
                continue;
            }
            Verdict::DropTwins => {}
            Verdict::Swap => {
                // The face kept so far looks into the solid: its first
                // twin, the same cycle the other way round, takes its
                // place (later twins of the same face just go).
                if c.faces[of as usize].len > 0 {
                    c.faces[r.face as usize].len = c.faces[of as usize].len;
                    c.faces[of as usize].len = 0;
                    c.copies[r.face as usize] = c.instances(r.face);
                }
            }
        }
        c.copies[of as usize] = c.instances(of);
        dropped += 1;
    }
    c.riders = kept;
    c.triangles = c.count_triangles();
    dropped
}

/// Whether every side of `group` (the border sides of one part) lies along
/// the others: points along it are within [`CRACK_TOLERANCE`] of another
/// side of the group.
fn cracks_only(c: &Complex, group: &[(u32, u32)]) -> bool {
    let seg = |&(a, b): &(u32, u32)| (c.pos[a as usize], c.pos[b as usize]);
    group.iter().enumerate().all(|(s, side)| {
        let (p, q) = seg(side);
        [0.1, 0.3, 0.5, 0.7, 0.9].iter().all(|&t| {
            let x = p.lerp(q, t);
            group
                .iter()
                .enumerate()
                .any(|(o, other)| o != s && distance_to_segment(x, seg(other)) <= CRACK_TOLERANCE)
        })
    })
}

/// What happens to the twins of one face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    /// Both sides can be seen: every copy stays.
    Keep,
    /// The face's own copy faces out: its twins go.
    DropTwins,
    /// The face's own copy looks in: its first twin replaces it, the rest go.
    Swap,
    /// Not decided yet: rays will tell.
    Look,
}

/// Directions per side in [`Sight::enclosed`]: a copy is hidden when every
/// one of them meets the mesh. Small openings between them may be missed,
/// which lets a little of an inside show through them; 32 keeps that
/// below a few degrees of the hemisphere.
const RAYS: usize = 16;

/// Points sampled along a part's border for lines of sight to its
/// openings (every k-th border side's middle).
const OPENING_POINTS: usize = 64;

/// A line of sight to an opening stops this fraction short of it, clear of
/// the faces on the border side it aims at.
const OPENING_MARGIN: f64 = 1e-3;

/// How far from its face a ray starts and what it must travel before a hit
/// counts (relative to the unit diagonal): clear of the face itself and of
/// rounding, far below any wall's thickness.
const RAY_START: f64 = 1e-7;

/// The faces of the complex as triangles in a tree, for rays.
struct Sight {
    bvh: Bvh,
    /// Corners and face of every triangle.
    tris: Vec<([DVec3; 3], u32)>,
}

impl Sight {
    fn new(c: &Complex) -> Sight {
        let mut tris = Vec::new();
        for f in c.live_faces() {
            let face = c.face(f);
            let p0 = c.pos[face[0] as usize];
            for k in 1..face.len() - 1 {
                tris.push((
                    [p0, c.pos[face[k] as usize], c.pos[face[k + 1] as usize]],
                    f,
                ));
            }
        }
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|(t, _)| Aabb::from_triangle(t[0], t[1], t[2]))
            .collect();
        Sight {
            bvh: Bvh::build(&boxes),
            tris,
        }
    }

    /// Whether the segment from `origin` along `d` (to `max_t`) meets a
    /// face of the mesh other than `f`.
    fn blocked(&self, f: u32, origin: DVec3, d: DVec3, max_t: f64) -> bool {
        self.bvh.any_hit(origin, d, max_t, |i| {
            let (t, g) = &self.tris[i as usize];
            *g != f
                && wildlod_geometry::ray_triangle(origin, d, t[0], t[1], t[2])
                    .is_some_and(|s| s > RAY_START && s <= max_t)
        })
    }

    /// Whether the side `n` of face `f` is enclosed: every ray from its
    /// middle into that half-space meets another face, and so does every
    /// line of sight to the openings of its part (`openings`, points on
    /// its border; a face deep in a pipe sees out only along the pipe,
    /// which a fixed set of directions misses).
    fn enclosed(&self, f: u32, middle: DVec3, n: DVec3, openings: &[DVec3]) -> bool {
        let (t1, t2) = n.any_orthonormal_pair();
        let origin = middle + RAY_START * n;
        // Along the normal first: a visible side usually escapes there,
        // and soonest.
        let rays_blocked = (0..RAYS).rev().all(|k| {
            // Fibonacci points on the hemisphere: even coverage, no
            // randomness.
            let z = (k as f64 + 0.5) / RAYS as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = k as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let d = n * z + (t1 * phi.cos() + t2 * phi.sin()) * r;
            self.blocked(f, origin, d, 2.0)
        });
        // Then the openings, which only a side that looks enclosed needs.
        rays_blocked
            && openings.iter().all(|&p| {
                let d = p - origin;
                // Stop short of the border side itself, which its own
                // faces hold.
                d.dot(n) <= 0.0 || self.blocked(f, origin, d, 1.0 - OPENING_MARGIN)
            })
    }

    /// The verdict for face `f` and its twins: a copy whose side of the
    /// face is enclosed cannot be seen.
    fn verdict(&self, c: &Complex, f: u32, openings: &[DVec3]) -> Verdict {
        let p: Vec<DVec3> = c.face(f).iter().map(|&v| c.pos[v as usize]).collect();
        let middle = p.iter().copied().sum::<DVec3>() / p.len().max(1) as f64;
        let mut n = DVec3::ZERO;
        for k in 0..p.len() {
            n += p[k].cross(p[(k + 1) % p.len()]);
        }
        let Some(n) = n.try_normalize() else {
            return Verdict::Keep;
        };
        // The twins' side first: when it is enclosed the face's own side
        // does not matter, and escaping rays (the visible side's) cost the
        // most, since they cross the whole tree.
        if self.enclosed(f, middle, -n, openings) {
            Verdict::DropTwins
        } else if self.enclosed(f, middle, n, openings) {
            Verdict::Swap
        } else {
            Verdict::Keep
        }
    }
}

/// Distance from `x` to the segment `(a, b)`.
fn distance_to_segment(x: DVec3, (a, b): (DVec3, DVec3)) -> f64 {
    let d = b - a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((x - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    x.distance(a + t * d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_segment_clamps_at_its_ends() {
        let seg = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(distance_to_segment(DVec3::new(1.0, 1.0, 0.0), seg), 1.0);
        assert_eq!(distance_to_segment(DVec3::new(3.0, 0.0, 0.0), seg), 1.0);
        assert_eq!(distance_to_segment(DVec3::new(-3.0, 4.0, 0.0), seg), 5.0);
        let point = (DVec3::ONE, DVec3::ONE);
        assert_eq!(distance_to_segment(DVec3::new(1.0, 1.0, 3.0), point), 2.0);
    }

    /// A unit cube whose top is split in two by vertices 8 and 9 on the
    /// middle of its front and back top edges (a T-junction on each: the
    /// side faces keep their long edge), every face followed by its twin;
    /// `lift` moves vertex 8 out of the front face, opening a gap. With
    /// `inward`, each first copy faces into the cube; with `open`, the top
    /// is left off.
    fn doubled_cube(lift: f64, inward: bool, open: bool) -> Complex {
        let mut pos: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64))
            .collect();
        pos.push(DVec3::new(0.5, -lift, 1.0));
        pos.push(DVec3::new(0.5, 1.0, 1.0));
        let outward: [&[u32]; 7] = [
            &[0, 2, 3, 1],
            &[4, 8, 9, 6],
            &[8, 5, 7, 9],
            &[0, 1, 5, 4],
            &[2, 6, 7, 3],
            &[0, 4, 6, 2],
            &[1, 3, 7, 5],
        ];
        let (mut offsets, mut indices) = (vec![0u32], Vec::new());
        for (k, f) in outward.iter().enumerate() {
            if open && (k == 1 || k == 2) {
                continue;
            }
            let back: Vec<u32> = f.iter().rev().copied().collect();
            let (first, second) = if inward {
                (&back[..], &f[..])
            } else {
                (&f[..], &back[..])
            };
            indices.extend_from_slice(first);
            offsets.push(indices.len() as u32);
            indices.extend_from_slice(second);
            offsets.push(indices.len() as u32);
        }
        Complex::faces_only(pos, &offsets, &indices).0
    }

    #[test]
    fn a_closed_part_with_t_junctions_drops_its_twins_and_faces_out() {
        for inward in [false, true] {
            let mut c = doubled_cube(0.0, inward, false);
            assert_eq!(c.riders.len(), 7);
            assert_eq!(c.triangles, 28);
            assert_eq!(drop_hidden_twins(&mut c, &|_| false), 7);
            assert!(c.riders.is_empty());
            assert_eq!(c.triangles, 14);
            // The copies kept are the outward ones: input faces 0, 2, 4…
            // when they came first, 1, 3, 5… when the inward ones did.
            let live: Vec<u32> = c.live_faces().collect();
            let want: Vec<u32> = (0..7).map(|f| 2 * f + u32::from(inward)).collect();
            assert_eq!(live, want, "inward {inward}");
        }
    }

    #[test]
    fn a_gap_shows_to_what_sees_it_an_open_box_shows_all_a_see_through_face_keeps_twins() {
        // A gap of 1% of the cube along its top front edge: no ray of the
        // fixed hemisphere finds it, but the faces that have a line of
        // sight to it can be seen through it and keep their twins; only
        // those that see it edge-on lose them, and they keep the copy that
        // faces out.
        for inward in [false, true] {
            let mut c = doubled_cube(0.01, inward, false);
            assert_eq!(drop_hidden_twins(&mut c, &|_| false), 2);
            // The bottom and the four sides keep their twins (riders are
            // named by the first copy's input face, 2 × the face).
            let kept: Vec<u32> = c.riders.iter().map(|r| r.of / 2).collect();
            assert_eq!(kept, [0, 3, 4, 5, 6], "inward {inward}");
            // The two top faces keep their outward copy only.
            let live: Vec<u32> = c.live_faces().collect();
            let tops = if inward { [3, 5] } else { [2, 4] };
            assert_eq!(live, [0, tops[0], tops[1], 6, 8, 10, 12], "inward {inward}");
        }
        // Without its top, the box's inside shows: every twin stays.
        let mut c = doubled_cube(0.0, false, true);
        assert_eq!(c.riders.len(), 5);
        assert_eq!(drop_hidden_twins(&mut c, &|_| false), 0);
        assert_eq!(c.riders.len(), 5);
        assert_eq!(c.triangles, 20);
        // Closed, but the top is seen through: its two faces keep their
        // twins, the others do not.
        let mut c = doubled_cube(0.0, false, false);
        assert_eq!(drop_hidden_twins(&mut c, &|f| f == 2 || f == 4), 5);
        assert_eq!(c.riders.len(), 2);
        assert_eq!(c.triangles, 18);
    }

    #[test]
    fn random_soups_with_twins_stay_consistent() {
        // Random triangles and quads on few vertices, some written twice
        // (either way round), some degenerate: whatever goes, the riders
        // ride on live faces, the count matches the faces, and the
        // complex built after it checks out.
        let mut state = 7u64;
        let mut below = |n: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 33) % n as u64) as usize
        };
        let mut total = 0;
        for seed in 0..60 {
            let nv = 6 + below(10);
            let pos: Vec<DVec3> = (0..nv)
                .map(|_| DVec3::new(below(7) as f64, below(7) as f64, below(3) as f64) / 7.0)
                .collect();
            let (mut offsets, mut indices) = (vec![0u32], Vec::new());
            for _ in 0..4 + below(20) {
                let face: Vec<u32> = (0..3 + below(2)).map(|_| below(nv) as u32).collect();
                indices.extend_from_slice(&face);
                offsets.push(indices.len() as u32);
                if below(2) == 0 {
                    let back: Vec<u32> = face.iter().rev().copied().collect();
                    indices.extend_from_slice(&back);
                    offsets.push(indices.len() as u32);
                }
            }
            let (mut c, _) = Complex::faces_only(pos, &offsets, &indices);
            let before = c.triangles;
            let dropped = drop_hidden_twins(&mut c, &|f| f % 5 == 0);
            assert_eq!(c.triangles, c.count_triangles(), "seed {seed}");
            // Each dropped copy took at least one triangle with it, and
            // nothing else went.
            assert!(before - c.triangles >= dropped, "seed {seed}");
            assert_eq!(before == c.triangles, dropped == 0, "seed {seed}");
            total += dropped;
            for r in &c.riders {
                assert!(
                    c.faces[r.of as usize].len > 0,
                    "seed {seed}: rider on a dead face"
                );
                assert_eq!(
                    c.copies(r.of),
                    1 + c.riders.iter().filter(|q| q.of == r.of).count()
                );
            }
            c.build_adjacency();
            c.check().unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        }
        // Some soups close up (or enclose copies): the pass did something.
        assert!(total > 0);
    }
}
