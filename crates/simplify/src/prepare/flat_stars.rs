//! Whether each vertex's faces lie in one plane, kept current through the
//! collapses (issue 31, decision 3: flat stays flat).
//!
//! The flat-border rule asks, for every border edge it evaluates, whether
//! the faces around both ends are coplanar. Scanning them each time costs
//! the ends' stars; at the centre of a flat fan that is every face of the
//! mesh, asked again for each of the centre's edges after every collapse
//! near it (a 100k-triangle flat fan took 56 minutes). The faces around two
//! vertices are coplanar exactly when each vertex's faces are and their
//! planes agree, so one answer per vertex serves every edge there. Each
//! vertex counts its faces with area and those off a reference plane; a
//! collapse takes its star's faces out of their corners' counts before it
//! and puts the survivors back after, so what a collapse costs here is what
//! it changes, not the size of its neighbours' stars.

use glam::DVec3;

use crate::prepare::complex::Complex;
use crate::prepare::geometry::{coplanar, face_plane};

/// The faces around one vertex, as the flat-border rule sees them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum StarPlane {
    /// No face around the vertex has area: no plane to keep.
    NoArea,
    /// Faces with area in more than one plane.
    Curved,
    /// Every face with area lies in the plane of this unit normal
    /// (orientation aside).
    Flat(DVec3),
}

impl StarPlane {
    /// Measures the faces around `v` (every one, in star order: the first
    /// with area sets the plane).
    pub(crate) fn of(c: &Complex, v: u32) -> StarPlane {
        match count(c, v) {
            Counts { area: 0, .. } => StarPlane::NoArea,
            Counts {
                reference, off: 0, ..
            } => StarPlane::Flat(reference),
            _ => StarPlane::Curved,
        }
    }

    /// Whether the faces around two vertices, measured as `self` and
    /// `other`, lie in one plane together.
    pub(crate) fn flat_with(self, other: StarPlane) -> bool {
        match (self, other) {
            (StarPlane::Curved, _) | (_, StarPlane::Curved) => false,
            (StarPlane::Flat(a), StarPlane::Flat(b)) => coplanar(a, b),
            _ => true,
        }
    }
}

/// Per vertex: faces with area around it, and how many of them lie off
/// the plane of a reference normal. None off: flat in that plane; some
/// off and some on: curved (faces on the plane and off it cannot share
/// one); all off: the reference is stale (its faces changed), and the
/// vertex is measured again.
///
/// The rule asks only about edges with an end on a border, so only border
/// vertices and their neighbours are counted: from the start, from the
/// collapse that puts a vertex on a border, and from the first time an
/// edge to a border is taken from the queue. Counting every
/// vertex through every collapse cost a closed scan (the dragon) a fifth
/// of its run.
///
/// A counted vertex has a slot in dense arrays: a closed mesh keeps none,
/// and a scan with a few holes a slot index a vertex, where the counts of
/// every vertex cost the dragon 18 MB. Collapses skip every face with no
/// counted corner without computing its plane.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlatStars {
    /// Whether the run keeps counts (else every question is measured on
    /// the spot).
    kept: bool,
    /// Per vertex, its slot or [`UNCOUNTED`]; empty until the first vertex
    /// is counted.
    slot: Vec<u32>,
    /// Per slot: the reference normal, faces with area, faces off its
    /// plane.
    counts: Vec<Counts>,
}

/// The counts of one vertex.
#[derive(Clone, Copy, Debug)]
struct Counts {
    reference: DVec3,
    area: u32,
    off: u32,
}

impl FlatStars {
    /// Every border vertex and its neighbours measured (in parallel: each
    /// reads only its own faces); the others not.
    pub(crate) fn measure(c: &Complex) -> FlatStars {
        use rayon::prelude::*;
        let counted: Vec<(u32, Counts)> = (0..c.pos.len() as u32)
            .into_par_iter()
            .filter(|&v| near_border(c, v))
            .map(|v| (v, count(c, v)))
            .collect();
        let mut stars = FlatStars {
            kept: true,
            ..FlatStars::default()
        };
        for (v, counts) in counted {
            stars.set(c, v, counts);
        }
        stars
    }

    /// The slot of `v`, if it is counted.
    #[inline]
    fn slot(&self, v: u32) -> Option<usize> {
        match self.slot.get(v as usize) {
            Some(&k) if k != UNCOUNTED => Some(k as usize),
            _ => None,
        }
    }

    /// Starts or renews `v`'s counts.
    fn set(&mut self, c: &Complex, v: u32, counts: Counts) {
        if let Some(k) = self.slot(v) {
            self.counts[k] = counts;
            return;
        }
        if self.slot.is_empty() {
            self.slot = vec![UNCOUNTED; c.pos.len()];
        }
        self.slot[v as usize] = self.counts.len() as u32;
        self.counts.push(counts);
    }

    /// Whether no corner of face `f` is counted (its plane is then not
    /// needed).
    #[inline]
    fn uncounted(&self, c: &Complex, f: u32) -> bool {
        c.face(f).iter().all(|&v| self.slot(v).is_none())
    }

    /// What the counts say about `v`: `None` when its reference is stale
    /// or it is not counted (or nothing was measured).
    #[inline]
    fn known(&self, v: u32) -> Option<StarPlane> {
        let Counts {
            reference,
            area,
            off,
        } = self.counts[self.slot(v)?];
        match () {
            _ if area == 0 => Some(StarPlane::NoArea),
            _ if off == 0 => Some(StarPlane::Flat(reference)),
            _ if off < area => Some(StarPlane::Curved),
            _ => None,
        }
    }

    /// The faces around `v`, from the counts when they are current, else
    /// measured on the spot.
    pub(crate) fn get(&self, c: &Complex, v: u32) -> StarPlane {
        self.known(v).unwrap_or_else(|| StarPlane::of(c, v))
    }

    /// Whether every face with area around `i` or `j` lies in one plane
    /// (orientation aside: a flipped face of a flat sheet is still flat).
    pub(crate) fn flat_pair(&self, c: &Complex, i: u32, j: u32) -> bool {
        let a = self.get(c, i);
        a != StarPlane::Curved && a.flat_with(self.get(c, j))
    }

    /// Takes `faces` out of their corners' counts: call before a collapse
    /// changes them (the faces around its two ends), with the positions
    /// they were counted at.
    pub(crate) fn before_collapse(&mut self, c: &Complex, faces: &[u32]) {
        self.each_counted_corner(c, faces, |x, n| {
            x.area -= 1;
            x.off -= u32::from(!coplanar(x.reference, n));
        });
    }

    /// Calls `f(counts, face normal)` for every counted corner of every
    /// face of `faces` with area; a face with no counted corner is skipped
    /// before its plane is computed.
    fn each_counted_corner(
        &mut self,
        c: &Complex,
        faces: &[u32],
        mut f: impl FnMut(&mut Counts, DVec3),
    ) {
        if self.counts.is_empty() {
            return;
        }
        for &face in faces {
            if self.uncounted(c, face) {
                continue;
            }
            let Some((n, _, _)) = face_plane(c, face) else {
                continue;
            };
            for &v in c.face(face) {
                if let Some(k) = self.slot(v) {
                    f(&mut self.counts[k], n);
                }
            }
        }
    }

    /// Puts what is left of `faces` back into their corners' counts after
    /// the collapse (a dead face has no corners left), and starts counting
    /// the vertices it put on a border.
    pub(crate) fn after_collapse(&mut self, c: &Complex, faces: &[u32]) {
        if !self.kept {
            return;
        }
        self.each_counted_corner(c, faces, |x, n| {
            if x.area == 0 {
                x.reference = n;
                x.off = 0;
            }
            x.area += 1;
            x.off += u32::from(!coplanar(x.reference, n));
        });
        // Then counted from scratch (after the faces went back, which
        // skipped them): the vertices the collapse put on a border, which
        // changes only at the corners of its faces. Their neighbours are
        // counted when an edge to them is next taken from the queue
        // (`refresh`); counting them here would read a fan centre's every
        // neighbour at each collapse along its border.
        for &f in faces {
            for &v in c.face(f) {
                if self.slot(v).is_none() && c.on_boundary(v) {
                    self.set(c, v, count(c, v));
                }
            }
        }
    }

    /// Measures `v` again if its reference went stale (or counts it from
    /// now on if it was not counted), so that every edge evaluated there
    /// until the next change reads the counts.
    pub(crate) fn refresh(&mut self, c: &Complex, v: u32) {
        if !self.kept || self.known(v).is_some() {
            return;
        }
        self.set(c, v, count(c, v));
    }
}

/// The slot of a vertex not counted (yet).
const UNCOUNTED: u32 = u32::MAX;

/// Whether `v` is on a border or next to a vertex that is.
fn near_border(c: &Complex, v: u32) -> bool {
    c.on_boundary(v)
        || c.vert_edges[v as usize]
            .iter()
            .any(|&e| c.on_boundary(c.other(e, v)))
}

/// Reference normal (the first face with area's), faces with area, and
/// faces off the reference's plane around `v`.
fn count(c: &Complex, v: u32) -> Counts {
    let (mut reference, mut area, mut off) = (DVec3::ZERO, 0, 0);
    for &f in c.vert_faces[v as usize].iter() {
        let Some((n, _, _)) = face_plane(c, f) else {
            continue;
        };
        if area == 0 {
            reference = n;
        }
        area += 1;
        off += u32::from(!coplanar(reference, n));
    }
    Counts {
        reference,
        area,
        off,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square of four triangles around a centre vertex 4, lifted by
    /// `lift` at corner 2.
    fn square(lift: f64) -> Complex {
        let pos = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 2.0, lift),
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        ];
        let idx = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];
        let offsets: Vec<u32> = (0..=4).map(|f| 3 * f).collect();
        Complex::new(pos, &offsets, &idx).0
    }

    #[test]
    fn a_star_is_flat_curved_or_without_area() {
        let c = square(0.0);
        assert_eq!(StarPlane::of(&c, 4), StarPlane::Flat(DVec3::Z));
        let bent = square(0.5);
        assert_eq!(StarPlane::of(&bent, 4), StarPlane::Curved);
        // Corner 0 touches only flat faces of the bent square.
        assert_eq!(StarPlane::of(&bent, 0), StarPlane::Flat(DVec3::Z));
        let line = Complex::new(
            vec![DVec3::ZERO, DVec3::X, 2.0 * DVec3::X],
            &[0, 3],
            &[0, 1, 2],
        )
        .0;
        assert_eq!(StarPlane::of(&line, 0), StarPlane::NoArea);
    }

    #[test]
    fn two_stars_are_flat_together_only_in_one_plane() {
        let z = StarPlane::Flat(DVec3::Z);
        assert!(z.flat_with(StarPlane::Flat(-DVec3::Z)));
        assert!(z.flat_with(StarPlane::NoArea));
        assert!(StarPlane::NoArea.flat_with(StarPlane::NoArea));
        assert!(!z.flat_with(StarPlane::Flat(DVec3::X)));
        assert!(!z.flat_with(StarPlane::Curved));
        assert!(!StarPlane::NoArea.flat_with(StarPlane::Curved));
    }

    /// The faces around `i` or `j` scanned together against the first
    /// with area: what the per-vertex answers must agree with.
    fn scanned(c: &Complex, i: u32, j: u32) -> bool {
        let normals: Vec<DVec3> = c
            .star_faces_iter(i, j)
            .filter_map(|f| face_plane(c, f).map(|p| p.0))
            .collect();
        normals.iter().all(|&n| coplanar(normals[0], n))
    }

    #[test]
    fn the_pair_rule_agrees_with_a_scan_of_both_stars() {
        // Every edge of a flat, a bent and a barely bent square (a lift
        // far below the tolerance counts as flat), known or measured on
        // the spot.
        for c in [square(0.0), square(0.5), square(1e-12)] {
            let stars = FlatStars::measure(&c);
            let unknown = FlatStars::default();
            for e in &c.edges {
                let [i, j] = e.ends;
                let want = scanned(&c, i, j);
                assert_eq!(stars.flat_pair(&c, i, j), want, "edge {i}-{j}");
                assert_eq!(unknown.flat_pair(&c, i, j), want, "edge {i}-{j}");
            }
        }
        assert!(scanned(&square(1e-12), 4, 2) && !scanned(&square(0.5), 4, 2));
    }

    /// Same classification; flat planes within the tolerance.
    fn same(a: StarPlane, b: StarPlane) -> bool {
        match (a, b) {
            (StarPlane::Flat(x), StarPlane::Flat(y)) => coplanar(x, y),
            _ => a == b,
        }
    }

    #[test]
    fn counts_follow_collapses_as_a_fresh_measurement_would() {
        // A 9×9 grid of quads split into triangles: flat on the left half,
        // a ridge on the right, some faces turned over. Random collapses
        // (to an end, to the middle, or lifted off the plane) keep every
        // vertex's counted answer equal to measuring it again.
        let n = 10usize;
        let mut pos = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let z = if x > n / 2 {
                    0.3 * ((x + y) % 2) as f64
                } else {
                    0.0
                };
                pos.push(DVec3::new(x as f64, y as f64, z));
            }
        }
        let mut idx = Vec::new();
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let v = (y * n + x) as u32;
                let (a, b, c, d) = (v, v + 1, v + 1 + n as u32, v + n as u32);
                if (x * 7 + y * 3) % 5 == 0 {
                    idx.extend_from_slice(&[a, c, b, a, d, c]);
                } else {
                    idx.extend_from_slice(&[a, b, c, a, c, d]);
                }
            }
        }
        let offsets: Vec<u32> = (0..=idx.len() as u32 / 3).map(|f| 3 * f).collect();
        let mut c = Complex::new(pos, &offsets, &idx).0;
        let mut stars = FlatStars::measure(&c);
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut star, mut changed) = (Vec::new(), Vec::new());
        let mut collapses = 0;
        let mut stale = 0;
        let mut untracked = 0;
        while collapses < 60 {
            let e = (next() % c.edges.len() as u64) as u32;
            if !c.edges[e as usize].alive() {
                continue;
            }
            let [i, j] = c.edges[e as usize].ends;
            let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
            let x = match next() % 4 {
                0 => pi,
                1 => pj,
                2 => 0.5 * (pi + pj),
                _ => 0.5 * (pi + pj) + DVec3::new(0.0, 0.0, 0.2),
            };
            c.star_faces(i, j, &mut star);
            stars.before_collapse(&c, &star);
            c.collapse(e, i, x, false, &mut changed);
            stars.after_collapse(&c, &star);
            collapses += 1;
            for v in 0..c.pos.len() as u32 {
                let fresh = StarPlane::of(&c, v);
                stale += usize::from(stars.known(v).is_none());
                untracked += usize::from(stars.slot(v).is_none());
                // Counted where the rule asks: every border vertex.
                if c.on_boundary(v) {
                    assert!(stars.slot(v).is_some(), "border vertex {v}");
                }
                assert!(
                    same(stars.get(&c, v), fresh),
                    "vertex {v} after {collapses}"
                );
                // The loop refreshes the ends of the edges it takes; here
                // some of the inner vertices, the others stay uncounted.
                if c.on_boundary(v) || v % 3 == 0 {
                    stars.refresh(&c, v);
                    assert!(stars.known(v).is_some_and(|k| same(k, fresh)), "vertex {v}");
                }
            }
        }
        // The lifted collapses left references stale somewhere: the
        // re-measuring path was taken, not only the counts; and inner
        // vertices went uncounted.
        assert!(stale > 0);
        assert!(untracked > 0);
    }
}
