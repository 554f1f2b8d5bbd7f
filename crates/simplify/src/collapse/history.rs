//! The collapse history for successive mapping (W §4.3, App. C.2): for every
//! collapse, the edge one-ring before it (faces with their corners' vertex
//! ids and positions at that moment) and the vertex one-ring after it (the
//! ids of the faces around the new vertex).
//!
//! Face ids are stable: a face keeps its id (its input face index) while
//! collapses merge its vertices, so "the point lies on face f" means the same
//! face at every level of the history.

use glam::DVec3;

use crate::prepare::complex::Complex;

/// A face of an edge one-ring given to [`History::push`]: its id, its
/// corners' vertex ids and their positions (input units).
pub type RingInput<'a> = (u32, &'a [u32], &'a [[f32; 3]]);

/// One collapse, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CollapseRecord {
    /// The vertex that stayed (welded id).
    pub kept: u32,
    /// The vertex merged into it.
    pub removed: u32,
    before: (u32, u32),
    after: (u32, u32),
}

/// A face of a recorded one-ring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RingFace {
    /// Face id (input face index).
    pub face: u32,
    start: u32,
    len: u32,
}

/// Every collapse of a run, stored flat.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// The collapses, first to last.
    pub records: Vec<CollapseRecord>,
    ring_faces: Vec<RingFace>,
    corner_vertices: Vec<u32>,
    corner_positions: Vec<[f32; 3]>,
    after_faces: Vec<u32>,
}

impl History {
    /// Number of collapses recorded.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// True when nothing was collapsed.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Renames every recorded face id through `f` (faces split before
    /// simplifying are recorded by piece; this points them at the input
    /// face).
    pub(crate) fn map_faces(&mut self, f: impl Fn(u32) -> u32) {
        for r in &mut self.ring_faces {
            r.face = f(r.face);
        }
        for a in &mut self.after_faces {
            *a = f(*a);
        }
    }

    /// The faces of the edge one-ring before collapse `k`.
    pub fn before(&self, k: usize) -> &[RingFace] {
        let (a, b) = self.records[k].before;
        &self.ring_faces[a as usize..b as usize]
    }

    /// The faces around the new vertex after collapse `k`.
    pub fn after(&self, k: usize) -> &[u32] {
        let (a, b) = self.records[k].after;
        &self.after_faces[a as usize..b as usize]
    }

    /// Vertex ids of a recorded face's corners, at the time of recording.
    pub fn vertices(&self, f: &RingFace) -> &[u32] {
        &self.corner_vertices[f.start as usize..(f.start + f.len) as usize]
    }

    /// Positions (input units) of a recorded face's corners.
    pub fn positions(&self, f: &RingFace) -> &[[f32; 3]] {
        &self.corner_positions[f.start as usize..(f.start + f.len) as usize]
    }

    /// Appends a collapse recorded elsewhere: `kept` and `removed`
    /// vertices, the edge one-ring before it as `(face id, corner vertex
    /// ids, corner positions)` and the face ids around the kept vertex
    /// after it. For engines with their own collapse loop that want the
    /// successive mapping (W §4.3), and for hand-built tests.
    ///
    /// # Panics
    /// When a ring face's vertex and position lists differ in length.
    pub fn push(&mut self, kept: u32, removed: u32, before: &[RingInput<'_>], after: &[u32]) {
        let start = self.ring_faces.len() as u32;
        for &(face, vertices, positions) in before {
            assert_eq!(
                vertices.len(),
                positions.len(),
                "face {face}: one position per corner"
            );
            let s = self.corner_vertices.len() as u32;
            self.corner_vertices.extend_from_slice(vertices);
            self.corner_positions.extend_from_slice(positions);
            self.ring_faces.push(RingFace {
                face,
                start: s,
                len: vertices.len() as u32,
            });
        }
        let a = self.after_faces.len() as u32;
        self.after_faces.extend_from_slice(after);
        self.records.push(CollapseRecord {
            kept,
            removed,
            before: (start, self.ring_faces.len() as u32),
            after: (a, self.after_faces.len() as u32),
        });
    }
}

/// Records collapses as the loop makes them (a visitor: the loop calls
/// `before` and `after` around every collapse).
#[derive(Debug)]
pub(crate) struct HistoryRecorder {
    h: History,
    center: DVec3,
    scale: f64,
    pending: Option<(u32, u32, u32)>,
}

impl HistoryRecorder {
    pub fn new(center: DVec3, scale: f64) -> Self {
        HistoryRecorder {
            h: History::default(),
            center,
            scale,
            pending: None,
        }
    }

    /// Before collapsing `i`–`j`: the faces of their star.
    pub fn before(&mut self, c: &Complex, star: &[u32], i: u32, j: u32) {
        let start = self.h.ring_faces.len() as u32;
        for &f in star {
            let face = c.face(f);
            let s = self.h.corner_vertices.len() as u32;
            for &v in face {
                let p = c.pos[v as usize] * self.scale + self.center;
                self.h.corner_vertices.push(v);
                self.h
                    .corner_positions
                    .push([p.x as f32, p.y as f32, p.z as f32]);
            }
            self.h.ring_faces.push(RingFace {
                face: f,
                start: s,
                len: face.len() as u32,
            });
        }
        self.pending = Some((i, j, start));
    }

    /// After the collapse: the faces around the kept vertex.
    pub fn after(&mut self, c: &Complex, i: u32, j: u32) {
        let Some((pi, pj, start)) = self.pending.take() else {
            return;
        };
        debug_assert_eq!((pi, pj), (i, j));
        let a = self.h.after_faces.len() as u32;
        self.h
            .after_faces
            .extend_from_slice(&c.vert_faces[i as usize]);
        let end = self.h.ring_faces.len() as u32;
        self.h.records.push(CollapseRecord {
            kept: i,
            removed: j,
            before: (start, end),
            after: (a, self.h.after_faces.len() as u32),
        });
    }

    pub fn finish(self) -> History {
        self.h
    }
}
