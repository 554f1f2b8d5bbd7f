//! Twins that cannot be seen: the reversed copies of the faces of a closed
//! surface.
//!
//! Exporters make a sheet double-sided by writing every face twice, once
//! each way (SketchUp and many CAD exports do it for whole models). On an
//! open sheet both sides show, and the twins ride along with their faces
//! (see [`crate::complex::Rider`]). On a closed surface one copy of each
//! face looks into the solid: with an opaque material it is never seen, so
//! a level of detail that keeps it spends half its budget on nothing.
//! Blender drops such copies when it imports a file; this does it for
//! closed components only, keeps the copy that faces out, and leaves faces
//! seen through (a blended material) alone.

use crate::complex::Complex;
use glam::DVec3;
use rayon::prelude::*;

/// Border sides a closed part may have as cracks (checked pairwise, so the
/// check stays cheap); a part with more is open.
const MAX_CRACK_SIDES: usize = 64;

/// How far (relative to the bounding-box diagonal: positions are
/// normalized) a point of a border side may be from another border side
/// and still count as touching it: float noise of an exporter, not a gap.
const CRACK_TOLERANCE: f64 = 1e-5;

/// Drops the twins of the faces of closed components (no side used by one
/// face only), keeping of each face the copy that faces out (the sign of
/// the component's enclosed volume), except where `see_through` says an
/// input face is seen through. Works on a complex with or without star
/// lists (call before [`Complex::build_adjacency`]). Returns the input
/// faces dropped.
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
            sides.push(((a.min(b) as u64) << 32) | a.max(b) as u64);
        }
    }
    sides.par_sort_unstable();
    let (labels, parts) = c.part_labels();
    let mut closed = vec![true; parts];
    let mut border: Vec<(u32, u32)> = Vec::new();
    let mut r = 0;
    while r < sides.len() {
        let mut t = r + 1;
        while t < sides.len() && sides[t] == sides[r] {
            t += 1;
        }
        if t - r == 1 {
            border.push(((sides[r] >> 32) as u32, sides[r] as u32));
        }
        r = t;
    }
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
    let mut dropped = 0;
    let riders = std::mem::take(&mut c.riders);
    let mut kept = Vec::with_capacity(riders.len());
    // Riders are sorted by the face they ride on: one group per face.
    let mut it = riders.into_iter().peekable();
    while let Some(first) = it.next() {
        let of = first.of;
        let mut group = vec![first];
        while let Some(r) = it.next_if(|r| r.of == of) {
            group.push(r);
        }
        let part = c.face(of).first().map(|&v| labels[v as usize] as usize);
        let hidden = part.is_some_and(|p| closed[p])
            && !see_through(of)
            && group.iter().all(|r| !see_through(r.face));
        let Some(part) = part.filter(|_| hidden) else {
            kept.extend(group);
            continue;
        };
        dropped += group.len();
        if volume[part] < 0.0 {
            // The face kept so far looks into the solid: its first twin,
            // the same cycle the other way round, takes its place.
            let twin = group[0].face;
            c.faces[twin as usize].len = c.faces[of as usize].len;
            c.faces[of as usize].len = 0;
            c.copies[twin as usize] = 1;
        }
        c.copies[of as usize] = 1;
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
    /// `inward`, each first copy faces into the cube.
    fn doubled_cube(lift: f64, inward: bool) -> Complex {
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
        for f in outward {
            let back: Vec<u32> = f.iter().rev().copied().collect();
            let (first, second) = if inward {
                (&back[..], f)
            } else {
                (f, &back[..])
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
            let mut c = doubled_cube(0.0, inward);
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
    fn an_open_gap_or_a_see_through_face_keeps_the_twins() {
        let mut c = doubled_cube(0.01, false);
        assert_eq!(drop_hidden_twins(&mut c, &|_| false), 0);
        assert_eq!(c.riders.len(), 7);
        assert_eq!(c.triangles, 28);
        // Closed, but the top is seen through: its two faces keep their
        // twins, the others do not.
        let mut c = doubled_cube(0.0, false);
        assert_eq!(drop_hidden_twins(&mut c, &|f| f == 2 || f == 4), 5);
        assert_eq!(c.riders.len(), 2);
        assert_eq!(c.triangles, 18);
    }
}
