//! The simplicial 2-complex of W §4.1 and App. C.1: vertices, edges
//! (physical and virtual) and polygon faces, with star lists
//! (vertex → faces, vertex → edges). No half-edges: nothing here assumes a
//! manifold, one component, or consistent orientation.
//!
//! Faces keep their polygon arity (Knodt 2024 §3: output faces are input
//! faces with merged vertices). Each face owns a fixed slot range sized by
//! its input arity; a collapse that merges two of its corners shrinks it in
//! place. Every slot remembers the input corner it came from, so per-corner
//! attributes ride along.

use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;
use std::collections::HashMap;

use crate::prepare::neighbour_moments::NeighbourMoments;
use crate::prepare::star_lists::StarLists;

/// Above this many faces, a vertex's boundary neighbours are found edge by
/// edge rather than by sorting the sides of its star.
const HIGH_VALENCE: usize = 32;

/// The crease neighbours kept for each vertex of high valence.
type CreaseLists = HashMap<u32, CreaseList>;

/// A vertex's kept crease neighbours and their positions' moments.
#[derive(Clone, Debug, Default)]
struct CreaseList {
    sides: SmallVec<[u32; 4]>,
    moments: NeighbourMoments,
}

/// Marks a dead face (`face_len == 0`) or an unused scratch entry.
pub(crate) const NONE: u32 = u32::MAX;

/// The complex being simplified.
#[derive(Clone, Debug)]
pub(crate) struct Complex {
    /// Vertex positions (normalized coordinates).
    pub pos: Vec<DVec3>,
    /// Faces around each vertex (each face listed once per vertex).
    pub vert_faces: StarLists,
    /// Edges around each vertex.
    pub vert_edges: StarLists,
    /// Every edge, physical or virtual.
    pub edges: Vec<Edge>,
    /// Every face's slot range.
    pub faces: Vec<FaceSlots>,
    /// Vertex of each slot.
    pub slot_vertex: Vec<u32>,
    /// Input corner of each slot; empty when every slot's corner is its
    /// own index (see [`Complex::corner`]).
    pub slot_corner: Vec<u32>,
    /// Triangles of the triangulated complex (Σ (arity − 2) · copies over
    /// live faces).
    pub triangles: usize,
    /// How many drawn faces each face stands for (empty: one each): a face
    /// and its twins, the copies of it with the other orientation (see
    /// [`Rider`]), each as many times as it is drawn (`instances`). They
    /// count in `triangles`, since the output draws them.
    pub copies: Vec<u32>,
    /// How many times each face is drawn (empty: once each; see
    /// [`crate::InputData::face_instances`](crate::InputData::face_instances)).
    pub instances: Vec<u32>,
    /// The twins folded into a face, sorted by that face.
    pub riders: Vec<Rider>,
    /// Scratch marks for set operations, compared against `stamp`. 16
    /// bits: the marks are cleared once every 65,535 stamps, a pass over
    /// the vertices that costs nothing beside the collapses between, and
    /// every chunk of a large run holds one mark per vertex.
    vmark: Vec<u16>,
    stamp: u16,
    /// Edges the last collapse killed (collapsed or merged away).
    pub killed: Vec<u32>,
    /// Boundary sides at each vertex: sides used by exactly one live face.
    /// Kept through every collapse, so that asking whether a vertex is on
    /// a border costs nothing and listing its border neighbours never
    /// scans a closed star (a fan's centre has the whole mesh in its star).
    border_sides: Vec<u32>,
    /// The boundary neighbours of every vertex with more than
    /// `high_valence` faces, kept with `border_sides`: such a vertex (a
    /// fan's centre) is in the star of most collapses, and finding them
    /// from its faces each time would make the whole run quadratic.
    border_lists: HashMap<u32, SmallVec<[u32; 4]>>,
    /// The valence above which a vertex gets a list (tests lower it).
    pub high_valence: usize,
    /// With [`Complex::keep_crease_lists`]: the cosine of the crease angle,
    /// and the crease neighbours (see [`Complex::crease_neighbors`]) of
    /// every vertex with more than `high_valence` faces, kept through every
    /// collapse. Such a vertex is in the star of most collapses, and each
    /// evaluation of one of its edges would scan its whole star: on a fan
    /// of n slivers whose rounded corners make creases at its centre, n
    /// edges evaluated again and again at O(n) each.
    crease_lists: Option<(f64, CreaseLists)>,
    /// Scratch of `collapse`: the sides at listed vertices it may change.
    crease_sides: Vec<(u32, u32)>,
    /// Where the collapse's `i` and `j` were, for the crease moments (see
    /// `crease_sides_after`).
    crease_moved: [DVec3; 2],
    /// Scratch of `collapse`.
    touched: Vec<u32>,
    j_corners: Vec<u32>,
    j_star: Vec<u32>,
    sides: Vec<(u32, u32)>,
}

/// Per-edge state, packed in 12 bytes: the collapse loop touches an edge's
/// endpoints, generation and flags together, at random, so they share one
/// cache line instead of an array's worth of misses each. The generation
/// and the four flags share one word (`GEN_MASK` and the bits above it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Edge {
    /// Endpoints.
    pub ends: [u32; 2],
    /// Generation (low 28 bits) and flags.
    state: u32,
}

/// The generation's bits of [`Edge`]'s state word. It only has to differ
/// between a queue entry and its edge once the edge changed: it wraps
/// after 2²⁸ changes of one edge.
pub(crate) const GEN_MASK: u32 = (1 << 28) - 1;
const ALIVE: u32 = 1 << 28;
const QUEUED: u32 = 1 << 29;
const REFUSED: u32 = 1 << 30;
const VIRTUAL: u32 = 1 << 31;

impl Edge {
    /// A live edge of generation 0, in no queue.
    pub fn new(ends: [u32; 2], is_virtual: bool) -> Edge {
        Edge {
            ends,
            state: ALIVE | if is_virtual { VIRTUAL } else { 0 },
        }
    }

    /// Bumped whenever the edge changes; queue entries carry the value
    /// they saw, so stale ones are recognized.
    #[inline]
    pub fn gen(&self) -> u32 {
        self.state & GEN_MASK
    }

    /// The edge changed: a new generation.
    #[inline]
    pub fn bump_gen(&mut self) {
        self.state = (self.state & !GEN_MASK) | (self.state.wrapping_add(1) & GEN_MASK);
    }

    #[inline]
    fn flag(&self, bit: u32) -> bool {
        self.state & bit != 0
    }

    #[inline]
    fn set_flag(&mut self, bit: u32, on: bool) {
        if on {
            self.state |= bit;
        } else {
            self.state &= !bit;
        }
    }

    /// False once the edge was collapsed or merged into another.
    #[inline]
    pub fn alive(&self) -> bool {
        self.flag(ALIVE)
    }

    /// See [`Edge::alive`].
    #[inline]
    pub fn set_alive(&mut self, on: bool) {
        self.set_flag(ALIVE, on);
    }

    /// The collapse loop's mark: the edge has an entry in a queue.
    #[inline]
    pub fn queued(&self) -> bool {
        self.flag(QUEUED)
    }

    /// See [`Edge::queued`].
    #[inline]
    pub fn set_queued(&mut self, on: bool) {
        self.set_flag(QUEUED, on);
    }

    /// The collapse loop's mark: a guard refused the edge.
    #[inline]
    pub fn refused(&self) -> bool {
        self.flag(REFUSED)
    }

    /// See [`Edge::refused`].
    #[inline]
    pub fn set_refused(&mut self, on: bool) {
        self.set_flag(REFUSED, on);
    }

    /// Created as a virtual edge (no face at the start).
    #[inline]
    pub fn is_virtual(&self) -> bool {
        self.flag(VIRTUAL)
    }
}

/// A face's slots: where its corners start and how many are left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FaceSlots {
    /// First slot.
    pub start: u32,
    /// Current arity; 0 when the face is gone.
    pub len: u32,
}

/// What a collapse changed, for the caller's bookkeeping.
#[derive(Clone, Debug, Default)]
pub(crate) struct CollapseOutcome {
    /// Triangles removed (triangulated count).
    pub removed_triangles: usize,
    /// Something beyond the regular case happened: a duplicate face was
    /// removed or a face split at a repeated vertex. Only then can edges
    /// away from the old boundary become boundary edges.
    pub irregular: bool,
}

/// An input face with the same vertex cycle as an earlier face but the
/// opposite orientation: a twin, the usual way wild meshes make a sheet
/// double-sided. It is one surface with the face it rides on, so it is not
/// part of the complex (two faces on every side would hide the sheet's
/// border and double its weight); it follows that face through every
/// collapse and is written back beside it, reversed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Rider {
    /// The twin's input face.
    pub face: u32,
    /// The face it rides on.
    pub of: u32,
    /// For each input corner of `of` (by its offset in that face), the
    /// twin's input corner at the same vertex (`NONE` if it has none).
    pub corners: Vec<u32>,
}

/// Faces cleaned away while building: degenerate and duplicate ones.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Cleaned {
    pub degenerate: usize,
    pub duplicate: usize,
}

impl Complex {
    /// [`Complex::faces_only`] with its adjacency built.
    #[cfg(test)]
    pub fn new(pos: Vec<DVec3>, offsets: &[u32], indices: &[u32]) -> (Complex, Cleaned) {
        let (mut c, cleaned) = Complex::faces_only(pos, offsets, indices);
        c.build_adjacency();
        (c, cleaned)
    }

    /// Builds the complex from welded positions and polygon faces
    /// (`offsets`/`indices` over welded vertex ids; slot `c` of the input is
    /// corner `c`). Removes degenerate faces (fewer than three distinct
    /// vertices after dropping repeats) and exact duplicates (the same
    /// vertex cycle with the same orientation; opposite copies are kept:
    /// they are how wild meshes make a sheet double-sided). Without the
    /// star lists and edges (empty) but with the triangle count: the
    /// partitioned path builds them once at the end, every other path at
    /// once, with [`Complex::build_adjacency`].
    pub fn faces_only(pos: Vec<DVec3>, offsets: &[u32], indices: &[u32]) -> (Complex, Cleaned) {
        let nf = offsets.len().saturating_sub(1);
        let mut c = Complex {
            vert_faces: StarLists::default(),
            vert_edges: StarLists::default(),
            edges: Vec::new(),
            faces: (0..nf)
                .map(|f| FaceSlots {
                    start: offsets[f],
                    len: offsets[f + 1] - offsets[f],
                })
                .collect(),
            slot_vertex: indices.to_vec(),
            slot_corner: if offsets.windows(2).all(|w| w[1] - w[0] == 3) {
                // Triangles: see `corner`.
                Vec::new()
            } else {
                (0..indices.len() as u32).collect()
            },
            triangles: 0,
            copies: Vec::new(),
            instances: Vec::new(),
            riders: Vec::new(),
            // The marks serve the star walks: `build_adjacency` sizes them.
            // The partitioned path keeps this complex without star lists
            // through every pass, beside the chunks: no room to spare.
            vmark: Vec::new(),
            stamp: 0,
            killed: Vec::new(),
            border_sides: Vec::new(),
            border_lists: HashMap::new(),
            high_valence: HIGH_VALENCE,
            crease_lists: None,
            crease_sides: Vec::new(),
            crease_moved: [DVec3::ZERO; 2],
            touched: Vec::new(),
            j_corners: Vec::new(),
            j_star: Vec::new(),
            sides: Vec::new(),
            pos,
        };
        let mut cleaned = Cleaned::default();
        for f in 0..nf {
            c.normalize_face(f as u32, None);
            if c.faces[f].len == 0 {
                cleaned.degenerate += 1;
            }
        }
        // Repeated faces: group faces by a hash of their vertex set, then
        // compare cycles within a group against the faces kept so far (the
        // lowest id stays). The same cycle with the same orientation is an
        // exact duplicate and goes; with the opposite one it is a twin and
        // rides on the kept face.
        let mut keys: Vec<(u64, u32)> = (0..nf as u32)
            .into_par_iter()
            .filter(|&f| c.faces[f as usize].len > 0)
            .map(|f| (c.set_hash(f), f))
            .collect();
        keys.par_sort_unstable();
        let mut g = 0;
        while g < keys.len() {
            let mut h = g + 1;
            while h < keys.len() && keys[h].0 == keys[g].0 {
                h += 1;
            }
            for a in g + 1..h {
                let fa = keys[a].1;
                let kept = |b: usize| c.faces[keys[b].1 as usize].len > 0;
                if (g..a).any(|b| kept(b) && c.same_cycle_any(fa, keys[b].1)) {
                    c.faces[fa as usize].len = 0;
                    cleaned.duplicate += 1;
                } else if let Some(b) = (g..a).find(|&b| kept(b) && c.reversed_cycle(fa, keys[b].1))
                {
                    let of = keys[b].1;
                    let arity = (offsets[of as usize + 1] - offsets[of as usize]) as usize;
                    let mut corners = vec![NONE; arity];
                    let (so, sa) = (c.faces[of as usize].start, c.faces[fa as usize].start);
                    for k in 0..c.faces[of as usize].len {
                        let v = c.slot_vertex[(so + k) as usize];
                        let at = (0..c.faces[fa as usize].len)
                            .find(|&t| c.slot_vertex[(sa + t) as usize] == v)
                            .map_or(NONE, |t| c.corner((sa + t) as usize));
                        corners[(c.corner((so + k) as usize) - offsets[of as usize]) as usize] = at;
                    }
                    c.riders.push(Rider {
                        face: fa,
                        of,
                        corners,
                    });
                    c.faces[fa as usize].len = 0;
                }
            }
            g = h;
        }
        if !c.riders.is_empty() {
            c.riders.sort_by_key(|r| (r.of, r.face));
            c.copies = vec![1; nf];
            for r in &c.riders {
                c.copies[r.of as usize] += 1;
            }
        }
        c.triangles = c.count_triangles();
        (c, cleaned)
    }

    /// How many drawn faces face `f` stands for (itself and its twins,
    /// each times its instances).
    #[inline]
    pub fn copies(&self, f: u32) -> usize {
        self.copies.get(f as usize).map_or(1, |&n| n as usize)
    }

    /// How many times face `f` itself is drawn.
    #[inline]
    pub fn instances(&self, f: u32) -> u32 {
        self.instances.get(f as usize).copied().unwrap_or(1)
    }

    /// Counts each face `instances[f]` times (one count per face; empty:
    /// once each), its twins each by their own count, and recounts the
    /// triangles.
    pub fn set_instances(&mut self, instances: Vec<u32>) {
        if instances.is_empty() || instances.len() != self.faces.len() {
            return;
        }
        let mut copies = instances.clone();
        for r in &self.riders {
            // Saturating: an absurd instance count must not wrap.
            copies[r.of as usize] =
                copies[r.of as usize].saturating_add(instances[r.face as usize]);
        }
        self.copies = copies;
        self.instances = instances;
        self.triangles = self.count_triangles();
    }

    /// Σ (arity − 2) · copies over the live faces.
    pub fn count_triangles(&self) -> usize {
        (0..self.faces.len() as u32)
            .map(|f| (self.faces[f as usize].len as usize).saturating_sub(2) * self.copies(f))
            .sum()
    }

    /// Drops the star lists and edges (they went stale).
    pub fn clear_adjacency(&mut self) {
        self.vert_faces = StarLists::default();
        self.vert_edges = StarLists::default();
        self.border_sides = Vec::new();
        self.border_lists = HashMap::new();
        self.crease_lists = None;
        // Freed, not cleared: callers drop the adjacency to make room.
        self.edges = Vec::new();
    }

    /// Whether the star lists and edges are built.
    pub fn has_adjacency(&self) -> bool {
        self.vert_faces.len() == self.pos.len()
    }

    /// A complex over faces that are already clean (no repeated vertex, no
    /// duplicate): a chunk of the partitioned path. `slot_corner` carries
    /// the input corners along.
    pub fn from_clean_faces(
        pos: Vec<DVec3>,
        faces: Vec<FaceSlots>,
        slot_vertex: Vec<u32>,
        slot_corner: Vec<u32>,
    ) -> Complex {
        let mut c = Complex {
            vert_faces: StarLists::default(),
            vert_edges: StarLists::default(),
            edges: Vec::new(),
            faces,
            slot_vertex,
            slot_corner,
            triangles: 0,
            copies: Vec::new(),
            instances: Vec::new(),
            riders: Vec::new(),
            vmark: Vec::new(),
            stamp: 0,
            killed: Vec::new(),
            border_sides: Vec::new(),
            border_lists: HashMap::new(),
            high_valence: HIGH_VALENCE,
            crease_lists: None,
            crease_sides: Vec::new(),
            crease_moved: [DVec3::ZERO; 2],
            touched: Vec::new(),
            j_corners: Vec::new(),
            j_star: Vec::new(),
            sides: Vec::new(),
            pos,
        };
        c.build_adjacency();
        c
    }

    /// (Re)builds the star lists, the physical edges and the triangle count
    /// from the live faces. Used at construction and after faces were
    /// changed from outside (the partitioned path writes chunk results back).
    pub fn build_adjacency(&mut self) {
        let nv = self.pos.len();
        self.triangles = 0;
        // Counted first, so that every star gets exactly its room.
        let mut count = vec![0u32; nv];
        let mut ek: Vec<u64> = Vec::with_capacity(self.slot_vertex.len());
        for f in 0..self.faces.len() as u32 {
            let len = self.faces[f as usize].len as usize;
            if len == 0 {
                continue;
            }
            self.triangles += (len - 2) * self.copies(f);
            let s = self.faces[f as usize].start as usize;
            for k in 0..len {
                let a = self.slot_vertex[s + k];
                count[a as usize] += 1;
                let b = self.slot_vertex[if k + 1 == len { s } else { s + k + 1 }];
                ek.push(side_key(a, b));
            }
        }
        self.vert_faces = StarLists::with_capacities(count.iter().copied());
        for f in 0..self.faces.len() as u32 {
            let FaceSlots { start, len } = self.faces[f as usize];
            for k in start..start + len {
                self.vert_faces
                    .push(self.slot_vertex[k as usize] as usize, f);
            }
        }
        // Physical edges: consecutive corners, deduplicated. A side that
        // occurs once is a boundary side.
        ek.par_sort_unstable();
        self.border_sides.clear();
        self.border_sides.resize(nv, 0);
        for (a, b) in sides_used_once(&ek) {
            self.border_sides[a as usize] += 1;
            self.border_sides[b as usize] += 1;
        }
        ek.dedup();
        count.iter_mut().for_each(|n| *n = 0);
        for &k in &ek {
            count[(k >> 32) as usize] += 1;
            count[k as u32 as usize] += 1;
        }
        self.vert_edges = StarLists::with_capacities(count.into_iter());
        self.edges.clear();
        self.edges.reserve_exact(ek.len());
        for k in ek {
            let (a, b) = ((k >> 32) as u32, k as u32);
            self.push_edge(a, b, false);
        }
        self.vmark.resize(nv, 0);
        self.border_lists.clear();
        for v in 0..nv as u32 {
            self.list_if_high_valence(v);
        }
    }

    fn push_edge(&mut self, a: u32, b: u32, is_virtual: bool) -> u32 {
        let e = self.edges.len() as u32;
        self.edges.push(Edge::new([a, b], is_virtual));
        self.vert_edges.push(a as usize, e);
        self.vert_edges.push(b as usize, e);
        e
    }

    /// Adds an edge between `a` and `b` unless one exists; returns whether
    /// it was added. Used for virtual edges.
    pub fn add_edge(&mut self, a: u32, b: u32) -> bool {
        if a == b || self.edge_between(a, b).is_some() {
            return false;
        }
        self.push_edge(a, b, true);
        true
    }

    /// The edge joining `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let (s, t) = if self.vert_edges[a as usize].len() <= self.vert_edges[b as usize].len() {
            (a, b)
        } else {
            (b, a)
        };
        self.vert_edges[s as usize]
            .iter()
            .copied()
            .find(|&e| self.other(e, s) == t)
    }

    /// The endpoint of `e` that is not `v`.
    #[inline]
    pub fn other(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edges[e as usize].ends;
        if a == v {
            b
        } else {
            a
        }
    }

    /// The input corner of slot `slot`. A complex built from triangles
    /// keeps no list of them: a triangle never loses a corner but dies
    /// (only a polygon shrinks in place, shifting its corners), so every
    /// slot of such a complex stays at the corner it was made for, its
    /// own index. That saves 12 bytes per triangle in the complex and in
    /// every chunk of the partitioned path.
    #[inline]
    pub fn corner(&self, slot: usize) -> u32 {
        if self.slot_corner.is_empty() {
            slot as u32
        } else {
            self.slot_corner[slot]
        }
    }

    /// Sets the input corner of `slot` (only a polygon shrinking does).
    fn set_corner(&mut self, slot: usize, corner: u32) {
        debug_assert!(!self.slot_corner.is_empty(), "a triangle moved a corner");
        if self.slot_corner.is_empty() {
            self.slot_corner = (0..self.slot_vertex.len() as u32).collect();
        }
        self.slot_corner[slot] = corner;
    }

    /// The current corners of face `f` (vertex ids).
    #[inline]
    pub fn face(&self, f: u32) -> &[u32] {
        let s = self.faces[f as usize].start as usize;
        &self.slot_vertex[s..s + self.faces[f as usize].len as usize]
    }

    /// Connected parts (faces sharing a vertex): the part of every vertex,
    /// numbered densely, and how many there are.
    pub fn part_labels(&self) -> (Vec<u32>, usize) {
        let mut sets = wildlod_mesh::disjoint_sets::DisjointSets::new(self.pos.len());
        for f in 0..self.faces.len() as u32 {
            for w in self.face(f).windows(2) {
                sets.union(w[0], w[1]);
            }
        }
        sets.labels()
    }

    /// Where the face's cycle starts when rotated to its smallest vertex.
    fn canonical_start(&self, f: u32) -> usize {
        let face = self.face(f);
        (0..face.len()).min_by_key(|&k| face[k]).unwrap_or(0)
    }

    /// A hash of the face's vertex set: equal for a face, its rotations and
    /// its reversal.
    fn set_hash(&self, f: u32) -> u64 {
        let mut v: SmallVec<[u32; 8]> = self.face(f).into();
        v.sort_unstable();
        let mut h: u64 = v.len() as u64;
        for x in v {
            h = (h.rotate_left(7) ^ x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
        h
    }

    /// Whether face `f` is face `g` walked the other way round.
    fn reversed_cycle(&self, f: u32, g: u32) -> bool {
        let (a, b) = (self.face(f), self.face(g));
        let n = a.len();
        if n != b.len() || n == 0 {
            return false;
        }
        let Some(k) = b.iter().position(|&x| x == a[0]) else {
            return false;
        };
        (0..n).all(|t| a[t] == b[(k + n - t) % n])
    }

    /// Whether faces `f` and `g` are the same cycle with the same
    /// orientation, whatever their starting corners.
    fn same_cycle_any(&self, f: u32, g: u32) -> bool {
        let (a, b) = (self.face(f), self.face(g));
        if a.len() != b.len() {
            return false;
        }
        let (pa, pb) = (self.canonical_start(f), self.canonical_start(g));
        let (a2, a1) = a.split_at(pa);
        let (b2, b1) = b.split_at(pb);
        a1.iter().chain(a2).eq(b1.iter().chain(b2))
    }

    fn next_stamp(&mut self) -> u16 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.vmark.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }

    /// Whether `v` has a side used by exactly one live face.
    #[inline]
    pub fn on_boundary(&self, v: u32) -> bool {
        self.border_sides[v as usize] > 0
    }

    /// Neighbors of `v` joined by an edge used by exactly one face: the
    /// boundary edges around `v`. Appends to `out`.
    pub fn boundary_neighbors(&self, v: u32, out: &mut Vec<u32>) {
        if self.border_sides[v as usize] == 0 {
            return;
        }
        if let Some(list) = self.border_lists.get(&v) {
            let start = out.len();
            out.extend_from_slice(list);
            out[start..].sort_unstable();
            return;
        }
        self.scan_boundary_neighbors(v, out);
    }

    /// Appends to `out` the face-side neighbours `k` of `v` whose side
    /// `v`–`k` has exactly two faces turning by more than the angle whose
    /// cosine is `cos` (a sharp crease of the current mesh; faces wound
    /// against each other are compared with one normal reversed, as for
    /// the input's crease planes), in the order of `v`'s faces.
    ///
    /// It first rules out the common case: when every face's normal is
    /// within half the angle of the first one's, no two faces turn by more
    /// than the angle.
    ///
    /// A vertex with a kept list (see [`Complex::keep_crease_lists`]) reads
    /// it instead, in the order the list was kept.
    pub fn crease_neighbors(&self, v: u32, cos: f64, out: &mut Vec<u32>) {
        if let Some((kept, lists)) = &self.crease_lists {
            if *kept == cos {
                if let Some(list) = lists.get(&v) {
                    out.extend_from_slice(&list.sides);
                    return;
                }
            }
        }
        self.scan_crease_neighbors(v, cos, out);
    }

    /// The number of `v`'s crease neighbours and their positions' moments,
    /// when `v` keeps a list for the crease angle whose cosine is `cos`
    /// (see [`Complex::keep_crease_lists`]).
    pub fn crease_moments(&self, v: u32, cos: f64) -> Option<(usize, &NeighbourMoments)> {
        let (kept, lists) = self.crease_lists.as_ref()?;
        if *kept != cos {
            return None;
        }
        lists.get(&v).map(|l| (l.sides.len(), &l.moments))
    }

    /// A kept list of `v`'s crease neighbours, found from its faces.
    fn crease_list(&self, v: u32, cos: f64) -> CreaseList {
        let mut out = Vec::new();
        self.scan_crease_neighbors(v, cos, &mut out);
        CreaseList {
            moments: NeighbourMoments::of(out.iter().map(|&k| self.pos[k as usize])),
            sides: out.into_iter().collect(),
        }
    }

    /// [`Complex::crease_neighbors`] found from `v`'s faces.
    fn scan_crease_neighbors(&self, v: u32, cos: f64, out: &mut Vec<u32>) {
        // Each face's neighbours of `v` (after it, before it) and normal.
        let mut corners: SmallVec<[(u32, u32, DVec3); 12]> = SmallVec::new();
        for &f in &self.vert_faces[v as usize] {
            let face = self.face(f);
            let n = face.len();
            let Some(k) = face.iter().position(|&w| w == v) else {
                continue;
            };
            let p = |t: usize| self.pos[face[t % n] as usize];
            let normal = if n == 3 {
                (p(1) - p(0)).cross(p(2) - p(0))
            } else {
                (0..n).map(|t| p(t).cross(p(t + 1))).sum()
            };
            corners.push((face[(k + 1) % n], face[(k + n - 1) % n], normal));
        }
        let Some(&(_, _, m)) = corners.first() else {
            return;
        };
        // cos(θ/2)² = (1 + cos θ) / 2.
        let half2 = 0.5 * (1.0 + cos);
        let mm = m.length_squared();
        let smooth = corners.iter().all(|&(_, _, n)| {
            let d = m.dot(n);
            d > 0.0 && d * d >= half2 * mm * n.length_squared()
        });
        if smooth {
            return;
        }
        // Each side at `v` is reported once, from its first occurrence in
        // face order, and only when exactly one other face has it. Sorted
        // by the neighbour, a side's occurrences are next to each other in
        // face order (then after before before): O(d log d) for a star of
        // d faces, where a scan per corner cost O(d²) at a fan's centre.
        let mut sides: SmallVec<[(u32, u32, u8); 24]> = SmallVec::new();
        for (a, &(after, before, _)) in corners.iter().enumerate() {
            sides.push((after, a as u32, 0));
            sides.push((before, a as u32, 1));
        }
        sides.sort_unstable();
        let mut found: SmallVec<[(u32, u8, u32); 4]> = SmallVec::new();
        for side in sides.chunk_by(|x, y| x.0 == y.0) {
            let &[(k, a, walk_a), (_, b, walk_b)] = side else {
                continue;
            };
            let n0 = corners[a as usize].2;
            let n1 = if walk_a == walk_b {
                -corners[b as usize].2
            } else {
                corners[b as usize].2
            };
            let scale = n0.length() * n1.length();
            if scale > 0.0 && n0.dot(n1) < cos * scale {
                found.push((a, walk_a, k));
            }
        }
        // In the order of their first occurrence.
        found.sort_unstable();
        out.extend(found.iter().map(|&(_, _, k)| k));
    }

    /// Keeps the crease neighbours of every vertex with more than
    /// `high_valence` faces for the crease angle whose cosine is `cos`,
    /// through every collapse from now on (see `crease_lists`).
    pub fn keep_crease_lists(&mut self, cos: f64) {
        let big: Vec<u32> = (0..self.vert_faces.len() as u32)
            .filter(|&v| self.vert_faces[v as usize].len() > self.high_valence)
            .collect();
        let lists = big
            .into_iter()
            .map(|v| (v, self.crease_list(v, cos)))
            .collect();
        self.crease_lists = Some((cos, lists));
    }

    /// Whether side `v`–`w` is a crease (see [`Complex::crease_neighbors`]):
    /// from the faces of the smaller star of the two.
    pub(crate) fn side_is_crease(&self, v: u32, w: u32, cos: f64) -> bool {
        let small = if self.vert_faces[w as usize].len() < self.vert_faces[v as usize].len() {
            w
        } else {
            v
        };
        // The faces walking `v`–`w` (after: `w` follows `v`), with normals.
        let mut found: SmallVec<[(bool, DVec3); 2]> = SmallVec::new();
        for &f in &self.vert_faces[small as usize] {
            let face = self.face(f);
            let n = face.len();
            let Some(k) = face.iter().position(|&x| x == v) else {
                continue;
            };
            let (after, before) = (face[(k + 1) % n], face[(k + n - 1) % n]);
            for (x, walks) in [(after, true), (before, false)] {
                if x != w {
                    continue;
                }
                if found.len() == 2 {
                    return false;
                }
                let p = |t: usize| self.pos[face[t % n] as usize];
                let normal = if n == 3 {
                    (p(1) - p(0)).cross(p(2) - p(0))
                } else {
                    (0..n).map(|t| p(t).cross(p(t + 1))).sum()
                };
                found.push((walks, normal));
            }
        }
        let &[(walk_a, n0), (walk_b, n1)] = found.as_slice() else {
            return false;
        };
        let n1 = if walk_a == walk_b { -n1 } else { n1 };
        let scale = n0.length() * n1.length();
        scale > 0.0 && n0.dot(n1) < cos * scale
    }

    /// The first half of keeping the crease lists through a collapse of
    /// `j` into `i`: the sides at listed vertices (other than `i`, `j`) in
    /// the faces of either, with `j` read as `i`. They are the sides whose
    /// faces change: every face of `i` moves with it.
    fn crease_sides_before(&mut self, i: u32, j: u32, i_was: DVec3) {
        self.crease_sides.clear();
        self.crease_moved = [i_was, self.pos[j as usize]];
        let Some((_, lists)) = &self.crease_lists else {
            return;
        };
        if lists.is_empty() {
            return;
        }
        let mut sides = std::mem::take(&mut self.crease_sides);
        for u in [i, j] {
            for &f in &self.vert_faces[u as usize] {
                let face = self.face(f);
                let n = face.len();
                for (t, &v) in face.iter().enumerate() {
                    if v == i || v == j || !lists.contains_key(&v) {
                        continue;
                    }
                    for w in [face[(t + 1) % n], face[(t + n - 1) % n]] {
                        sides.push((v, if w == j { i } else { w }));
                    }
                    // Marks that `j` leaves `v`'s list.
                    sides.push((v, j));
                }
            }
        }
        sides.sort_unstable();
        sides.dedup();
        self.crease_sides = sides;
    }

    /// The second half (see [`Complex::crease_sides_before`]): the
    /// collected sides judged again, `j`'s list dropped, and `i`'s found
    /// again from its faces if it has (or now needs) one.
    fn crease_sides_after(&mut self, i: u32, j: u32) {
        let Some((cos, mut lists)) = self.crease_lists.take() else {
            return;
        };
        lists.remove(&j);
        let sides = std::mem::take(&mut self.crease_sides);
        // Where `i` and `j` were: a listed neighbour leaves the moments
        // from where it was added.
        let [i_was, j_was] = self.crease_moved;
        let was = |w: u32, pos: &[DVec3]| match w {
            _ if w == i => i_was,
            _ if w == j => j_was,
            _ => pos[w as usize],
        };
        for &(v, w) in &sides {
            let crease = w != j && self.side_is_crease(v, w, cos);
            if let Some(list) = lists.get_mut(&v) {
                let at = list.sides.iter().position(|&x| x == w);
                match (crease, at) {
                    (true, None) => {
                        list.sides.push(w);
                        list.moments.add(self.pos[w as usize]);
                    }
                    (false, Some(p)) => {
                        list.sides.remove(p);
                        list.moments.remove(was(w, &self.pos));
                    }
                    (true, Some(_)) if w == i => {
                        list.moments.remove(i_was);
                        list.moments.add(self.pos[i as usize]);
                    }
                    _ => {}
                }
            }
        }
        self.crease_sides = sides;
        if lists.contains_key(&i) || self.vert_faces[i as usize].len() > self.high_valence {
            lists.insert(i, self.crease_list(i, cos));
        }
        self.crease_lists = Some((cos, lists));
    }

    /// [`Complex::boundary_neighbors`] found from `v`'s faces: the sides
    /// of its star, sorted, those that occur once.
    fn scan_boundary_neighbors(&self, v: u32, out: &mut Vec<u32>) {
        let start = out.len();
        for &f in &self.vert_faces[v as usize] {
            let face = self.face(f);
            let n = face.len();
            for k in 0..n {
                if face[k] == v {
                    out.push(face[if k == 0 { n - 1 } else { k - 1 }]);
                    out.push(face[if k + 1 == n { 0 } else { k + 1 }]);
                }
            }
        }
        let tail = &mut out[start..];
        tail.sort_unstable();
        // Keep the values that occur exactly once.
        let mut w = start;
        let mut i = start;
        while i < out.len() {
            let mut j = i + 1;
            while j < out.len() && out[j] == out[i] {
                j += 1;
            }
            if j - i == 1 && out[i] != v {
                out[w] = out[i];
                w += 1;
            }
            i = j;
        }
        out.truncate(w);
    }

    /// Gives `v` a kept list of boundary neighbours if its star has grown
    /// past `high_valence` (once; the list is kept from then on).
    fn list_if_high_valence(&mut self, v: u32) {
        if self.vert_faces[v as usize].len() > self.high_valence
            && !self.border_lists.contains_key(&v)
        {
            let mut out = Vec::new();
            self.scan_boundary_neighbors(v, &mut out);
            self.border_lists.insert(v, out.into_iter().collect());
        }
    }

    /// Side `a`–`b` stops (`gone`) or starts being a boundary side: the
    /// counts at both ends and their lists follow.
    fn flip_border_side(&mut self, a: u32, b: u32, gone: bool) {
        for (v, w) in [(a, b), (b, a)] {
            if gone {
                self.border_sides[v as usize] -= 1;
            } else {
                self.border_sides[v as usize] += 1;
            }
            if let Some(list) = self.border_lists.get_mut(&v) {
                if gone {
                    if let Some(p) = list.iter().position(|&x| x == w) {
                        list.swap_remove(p);
                    }
                } else {
                    list.push(w);
                }
            }
        }
    }

    /// Number of live faces that use `a`–`b` as a side.
    pub fn edge_face_count(&self, a: u32, b: u32) -> usize {
        let (s, t) = if self.vert_faces[a as usize].len() <= self.vert_faces[b as usize].len() {
            (a, b)
        } else {
            (b, a)
        };
        let mut count = 0;
        for &f in &self.vert_faces[s as usize] {
            let face = self.face(f);
            let n = face.len();
            for k in 0..n {
                if face[k] == s && (face[(k + 1) % n] == t || face[(k + n - 1) % n] == t) {
                    count += 1;
                }
            }
        }
        count
    }

    /// Whether collapsing `a`–`b` would leave a vertex with no face: the
    /// last face of its part there would go (a lone triangle, or the rest
    /// of a lone quad half collapsed). Only triangles on the edge vanish in
    /// a collapse; a vertex whose every face is one of them is left bare.
    pub fn collapse_leaves_a_bare_vertex(&self, a: u32, b: u32) -> bool {
        let on_edge = |f: u32| {
            let face = self.face(f);
            face.len() == 3 && face.contains(&a) && face.contains(&b)
        };
        let bare = |v: u32| self.vert_faces[v as usize].iter().all(|&f| on_edge(f));
        if bare(a) && bare(b) {
            return true;
        }
        self.vert_faces[a as usize]
            .iter()
            .filter(|&&f| on_edge(f))
            .any(|&f| self.face(f).iter().any(|&v| v != a && v != b && bare(v)))
    }

    /// The faces around `i` or `j`, each once, in a deterministic order:
    /// `i`'s, then those of `j`'s that do not hold `i` (a star lists a face
    /// once, and exactly the faces that hold its vertex).
    pub fn star_faces(&self, i: u32, j: u32, out: &mut Vec<u32>) {
        out.clear();
        out.extend(self.star_faces_iter(i, j));
    }

    /// The faces of [`Complex::star_faces`], read in place.
    pub fn star_faces_iter(&self, i: u32, j: u32) -> impl Iterator<Item = u32> + '_ {
        let around_j_only = self.vert_faces[j as usize]
            .iter()
            .filter(move |&&f| !self.face(f).contains(&i));
        self.vert_faces[i as usize]
            .iter()
            .chain(around_j_only)
            .copied()
    }

    /// Removes repeated vertices of face `f` in place. Consecutive repeats
    /// collapse to one corner (the one at a vertex listed in `prefer`, if
    /// given: the slot to keep among a run of equal vertices); a vertex
    /// repeated apart splits the cycle into loops, of which the longest is
    /// kept (a face cannot become two). Fewer than three corners left: the
    /// face is gone (`face_len = 0`). Returns the vertices that left the
    /// face (excluding repeats of kept ones) into `dropped`.
    fn normalize_face(&mut self, f: u32, prefer: Option<&dyn Fn(u32) -> bool>) -> Vec<u32> {
        let s = self.faces[f as usize].start as usize;
        let n = self.faces[f as usize].len as usize;
        let verts = &self.slot_vertex[s..s + n];
        let has_repeat = (0..n).any(|a| verts[a + 1..].contains(&verts[a]));
        if !has_repeat {
            return Vec::new();
        }
        if let Some(d) = self.drop_adjacent_repeat(f, prefer) {
            return d;
        }
        let before: Vec<u32> = self.slot_vertex[s..s + n].to_vec();
        // Collapse cyclic runs of equal vertices to one slot.
        let mut slots: Vec<(u32, u32, bool)> = Vec::with_capacity(n); // (vertex, corner, preferred)
        for k in 0..n {
            let v = self.slot_vertex[s + k];
            let pref = prefer.map(|p| p(self.corner(s + k))).unwrap_or(false);
            slots.push((v, self.corner(s + k), pref));
        }
        let mut runs: Vec<(u32, u32, bool)> = Vec::with_capacity(n);
        for &sl in &slots {
            match runs.last_mut() {
                Some(last) if last.0 == sl.0 => {
                    if sl.2 && !last.2 {
                        *last = sl;
                    }
                }
                _ => runs.push(sl),
            }
        }
        while runs.len() > 1 && runs[0].0 == runs[runs.len() - 1].0 {
            let last = runs.pop().unwrap_or((NONE, NONE, false));
            if last.2 && !runs[0].2 {
                runs[0] = last;
            }
        }
        // Split at vertices that still repeat: keep the longest loop.
        let mut kept = runs.clone();
        'split: loop {
            for a in 0..kept.len() {
                for b in a + 1..kept.len() {
                    if kept[a].0 == kept[b].0 {
                        let inner: Vec<_> = kept[a..b].to_vec();
                        let mut outer: Vec<_> = kept[b..].to_vec();
                        outer.extend_from_slice(&kept[..a]);
                        kept = if inner.len() >= outer.len() {
                            inner
                        } else {
                            outer
                        };
                        continue 'split;
                    }
                }
            }
            break;
        }
        let new_len = if kept.len() >= 3 { kept.len() } else { 0 };
        for (k, sl) in kept.iter().take(new_len).enumerate() {
            self.slot_vertex[s + k] = sl.0;
            self.set_corner(s + k, sl.1);
        }
        self.faces[f as usize].len = new_len as u32;
        let mut dropped: Vec<u32> = before
            .into_iter()
            .filter(|v| new_len == 0 || !kept.iter().any(|k| k.0 == *v))
            .collect();
        dropped.sort_unstable();
        dropped.dedup();
        dropped
    }

    /// The common case of `normalize_face`, without allocating: exactly one
    /// vertex appears twice, on neighbouring corners (a face that held the
    /// collapsed edge). Drops one of the two slots in place. `None` when the
    /// face is not in that case.
    fn drop_adjacent_repeat(
        &mut self,
        f: u32,
        prefer: Option<&dyn Fn(u32) -> bool>,
    ) -> Option<Vec<u32>> {
        let s = self.faces[f as usize].start as usize;
        let n = self.faces[f as usize].len as usize;
        let v = &self.slot_vertex[s..s + n];
        let mut pair = None;
        for k in 0..n {
            let next = if k + 1 == n { 0 } else { k + 1 };
            if v[k] == v[next] {
                if pair.is_some() {
                    return None;
                }
                pair = Some((k, next));
            } else if v[k + 1..].contains(&v[k]) && !(k == 0 && v[n - 1] == v[0]) {
                // A repeat that is not adjacent.
                return None;
            }
        }
        // `first` is the slot the slow path would keep by default: the
        // earlier one, or slot 0 when the pair wraps around.
        let (first, second) = match pair? {
            (a, 0) => (0, a),
            (a, b) => (a, b),
        };
        if n <= 3 {
            self.faces[f as usize].len = 0;
            let mut gone: Vec<u32> = self.slot_vertex[s..s + n].to_vec();
            gone.sort_unstable();
            gone.dedup();
            return Some(gone);
        }
        // Keep the preferred slot of the pair; drop the other.
        let keep_second = prefer
            .map(|p| p(self.corner(s + second)) && !p(self.corner(s + first)))
            .unwrap_or(false);
        let drop = if keep_second { first } else { second };
        for k in drop..n - 1 {
            self.slot_vertex[s + k] = self.slot_vertex[s + k + 1];
            self.set_corner(s + k, self.corner(s + k + 1));
        }
        self.faces[f as usize].len = (n - 1) as u32;
        Some(Vec::new())
    }

    /// Collapses edge `e = (i, j)` into `keep` (= `i`), moving it to `x`
    /// (W §4.1).
    ///
    /// `prefer_removed` picks which corners survive where a face held both
    /// endpoints (the ones that were at `j` when true): the caller keeps the
    /// corners of the endpoint nearer to `x`, so their attributes fit best.
    /// Degenerate faces, duplicate faces and duplicate edges that appear are
    /// removed. `changed` receives every live edge around `i` afterwards.
    pub fn collapse(
        &mut self,
        e: u32,
        keep: u32,
        x: DVec3,
        prefer_removed: bool,
        changed: &mut Vec<u32>,
    ) -> CollapseOutcome {
        let [a, b] = self.edges[e as usize].ends;
        let (i, j) = if keep == a { (a, b) } else { (b, a) };
        let mut out = CollapseOutcome::default();
        self.killed.clear();
        let i_was = std::mem::replace(&mut self.pos[i as usize], x);
        let border_before = self.border_sides_before(i, j);
        self.crease_sides_before(i, j, i_was);

        // Faces: move j's faces to i. Only a face that held both endpoints
        // can now repeat a vertex; the others just change a corner.
        let mut j_faces = std::mem::take(&mut self.j_star);
        self.vert_faces.take(j as usize, &mut j_faces);
        let mut touched = std::mem::take(&mut self.touched);
        let mut j_corners = std::mem::take(&mut self.j_corners);
        touched.clear();
        j_corners.clear();
        let mut shared: SmallVec<[u32; 4]> = SmallVec::new();
        for &f in &j_faces {
            let s = self.faces[f as usize].start as usize;
            let n = self.faces[f as usize].len as usize;
            let mut had_i = false;
            for k in s..s + n {
                if self.slot_vertex[k] == j {
                    self.slot_vertex[k] = i;
                    j_corners.push(self.corner(k));
                } else if self.slot_vertex[k] == i {
                    had_i = true;
                }
            }
            if had_i {
                shared.push(f);
            } else {
                self.vert_faces.push(i as usize, f);
            }
            touched.push(f);
        }
        if shared.len() > 1 || shared.iter().any(|&f| self.faces[f as usize].len > 3) {
            j_corners.sort_unstable();
        }
        for &f in &shared {
            let old = self.faces[f as usize].len as usize;
            if old == 3 {
                // A triangle on the edge: it dies, its third vertex loses it.
                let s = self.faces[f as usize].start as usize;
                for k in s..s + 3 {
                    let v = self.slot_vertex[k];
                    if v != i {
                        self.vert_faces.remove(v as usize, f);
                    }
                }
                self.faces[f as usize].len = 0;
                out.removed_triangles += self.copies(f);
                continue;
            }
            let prefer = |c: u32| j_corners.binary_search(&c).is_ok() == prefer_removed;
            let dropped = self.normalize_face(f, Some(&prefer));
            let new = self.faces[f as usize].len as usize;
            if new == 0 {
                out.removed_triangles += (old - 2) * self.copies(f);
            } else {
                out.removed_triangles += (old - new) * self.copies(f);
            }
            for v in dropped {
                if v == j || (new > 0 && v == i) {
                    continue;
                }
                if v != i {
                    // A vertex other than the merged pair left the face: the
                    // face split at a repeated vertex.
                    out.irregular |= new > 0;
                }
                self.vert_faces.remove(v as usize, f);
            }
        }

        // Duplicate faces: only a face that changed can have become equal to
        // another face around i (same cycle, same orientation). The higher
        // id goes, as when cleaning the input. A vertex-set signature rules
        // out almost every pair before the cycle comparison.
        type Signature = (u32, u32, u32);
        let signature = |c: &Complex, f: u32| -> Signature {
            let face = c.face(f);
            let (mut sum, mut x) = (0u32, 0u32);
            for &v in face {
                sum = sum.wrapping_add(v);
                x ^= v.wrapping_mul(0x9E37_79B9);
            }
            (face.len() as u32, sum, x)
        };
        // Each face around i is read once, not once per changed face.
        let around: SmallVec<[(u32, Signature); 24]> = self.vert_faces[i as usize]
            .iter()
            .filter(|&&g| self.faces[g as usize].len > 0)
            .map(|&g| (g, signature(self, g)))
            .collect();
        for &f in &touched {
            if self.faces[f as usize].len == 0 {
                continue;
            }
            let sf = signature(self, f);
            let mut twin = None;
            for &(g, sg) in &around {
                if g != f && sg == sf && self.faces[g as usize].len > 0 && self.same_cycle(f, g, i)
                {
                    twin = Some(g);
                    break;
                }
            }
            if let Some(g) = twin {
                let dead = f.max(g);
                let len = self.faces[dead as usize].len as usize;
                out.removed_triangles += (len - 2) * self.copies(dead);
                out.irregular = true;
                let s = self.faces[dead as usize].start as usize;
                for k in s..s + len {
                    let v = self.slot_vertex[k];
                    if v != i {
                        self.vert_faces.remove(v as usize, dead);
                    }
                }
                self.faces[dead as usize].len = 0;
            }
        }
        let faces = &self.faces;
        self.vert_faces
            .retain(i as usize, |f| faces[f as usize].len > 0);
        self.triangles -= out.removed_triangles;
        self.border_sides_after(i, j, border_before || out.irregular);
        self.crease_sides_after(i, j);
        self.touched = touched;
        self.j_corners = j_corners;

        // Edges: re-point j's edges to i, merging duplicates.
        let s = self.next_stamp();
        for &ei in &self.vert_edges[i as usize] {
            let k = self.other(ei, i);
            self.vmark[k as usize] = s;
        }
        let mut j_edges = j_faces;
        self.vert_edges.take(j as usize, &mut j_edges);
        for &ej in &j_edges {
            if !self.edges[ej as usize].alive() {
                continue;
            }
            let k = self.other(ej, j);
            if k == i {
                self.kill_edge(ej);
                self.vert_edges.remove(i as usize, ej);
                continue;
            }
            if self.vmark[k as usize] == s {
                // i already joins k: the j–k edge merges into it.
                self.kill_edge(ej);
                self.vert_edges.remove(k as usize, ej);
            } else {
                let ends = &mut self.edges[ej as usize].ends;
                if ends[0] == j {
                    ends[0] = i;
                } else {
                    ends[1] = i;
                }
                self.edges[ej as usize].bump_gen();
                self.vert_edges.push(i as usize, ej);
                self.vmark[k as usize] = s;
            }
        }
        self.j_star = j_edges;
        changed.clear();
        changed.extend_from_slice(&self.vert_edges[i as usize]);
        out
    }

    /// The first half of keeping `border_sides` through a collapse of `j`
    /// into `i`, before anything moves: collects in `sides` every side the
    /// collapse can change (the sides of `j`'s faces, with `j` read as `i`)
    /// and takes the boundary ones out of the counts. Returns whether any
    /// vertex around was on a border.
    ///
    /// When none was, no side had one face, and a regular collapse cannot
    /// make one: a side `k`–`i` afterwards has the faces of `k`–`i` and
    /// `k`–`j` (0 or at least 2 each) less two per face on the edge that
    /// dies, and at most one such face holds `k`. Then the second half is
    /// skipped, unless something irregular happened.
    fn border_sides_before(&mut self, i: u32, j: u32) -> bool {
        let mut sides = std::mem::take(&mut self.sides);
        sides.clear();
        let mut any = self.border_sides[i as usize] > 0;
        let mut on_edge = false;
        for &f in &self.vert_faces[j as usize] {
            let face = self.face(f);
            let n = face.len();
            for k in 0..n {
                let (a, b) = (face[k], face[if k + 1 == n { 0 } else { k + 1 }]);
                any |= self.border_sides[a as usize] > 0;
                let (a, b) = (if a == j { i } else { a }, if b == j { i } else { b });
                if a != b {
                    sides.push((a.min(b), a.max(b)));
                } else {
                    on_edge = true;
                }
            }
        }
        sides.sort_unstable();
        sides.dedup();
        if any {
            // The collapsed edge itself is a side that goes.
            if on_edge && self.edge_face_count(i, j) == 1 {
                self.flip_border_side(i, j, true);
            }
            // The sides as they are now: those at j, and those at i they
            // will merge into.
            for &(a, b) in &sides {
                let mut ends = SmallVec::<[(u32, u32); 2]>::new();
                ends.push((a, b));
                if a == i {
                    ends.push((j, b));
                } else if b == i {
                    ends.push((a, j));
                }
                for (a, b) in ends {
                    if self.edge_face_count(a, b) == 1 {
                        self.flip_border_side(a, b, true);
                    }
                }
            }
        }
        self.sides = sides;
        any
    }

    /// The second half (see [`Complex::border_sides_before`]): counts the
    /// collected sides that are boundary sides now; `j` is gone.
    fn border_sides_after(&mut self, i: u32, j: u32, recount: bool) {
        if recount {
            for t in 0..self.sides.len() {
                let (a, b) = self.sides[t];
                if self.edge_face_count(a, b) == 1 {
                    self.flip_border_side(a, b, false);
                }
            }
        }
        debug_assert_eq!(self.border_sides[j as usize], 0);
        self.border_sides[j as usize] = 0;
        self.border_lists.remove(&j);
        self.list_if_high_valence(i);
    }

    /// Whether live faces `f` and `g`, both holding `v` once, are the same
    /// cycle with the same orientation.
    fn same_cycle(&self, f: u32, g: u32, v: u32) -> bool {
        let (a, b) = (self.face(f), self.face(g));
        if a.len() != b.len() {
            return false;
        }
        let (Some(pa), Some(pb)) = (
            a.iter().position(|&x| x == v),
            b.iter().position(|&x| x == v),
        ) else {
            return false;
        };
        // Compare the cycles starting after v, without modulo (an integer
        // division per step in the hottest duplicate test).
        let (a2, a1) = a.split_at(pa + 1);
        let (b2, b1) = b.split_at(pb + 1);
        a1.iter().chain(a2).eq(b1.iter().chain(b2))
    }

    fn kill_edge(&mut self, e: u32) {
        self.killed.push(e);
        self.edges[e as usize].set_alive(false);
        self.edges[e as usize].bump_gen();
    }

    /// The live faces of every vertex as one flat list in face order
    /// (offsets, faces): the star lists without their cost.
    pub fn vertex_face_index(&self) -> (Vec<u32>, Vec<u32>) {
        let mut start = vec![0u32; self.pos.len() + 1];
        for f in self.live_faces() {
            for &v in self.face(f) {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..self.pos.len() {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[self.pos.len()] as usize];
        for f in self.live_faces() {
            for &v in self.face(f) {
                list[fill[v as usize] as usize] = f;
                fill[v as usize] += 1;
            }
        }
        (start, list)
    }

    /// Live faces, for output.
    pub fn live_faces(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.faces.len() as u32).filter(|&f| self.faces[f as usize].len > 0)
    }

    /// Checks the star lists against the faces and edges (debug and tests).
    #[cfg(test)]
    pub fn check(&self) -> Result<(), String> {
        let mut tris = 0;
        for f in self.live_faces() {
            let face = self.face(f);
            if face.len() < 3 {
                return Err(format!("face {f} has {} corners", face.len()));
            }
            tris += (face.len() - 2) * self.copies(f);
            for (k, &v) in face.iter().enumerate() {
                if face[k + 1..].contains(&v) {
                    return Err(format!("face {f} repeats vertex {v}"));
                }
                if !self.vert_faces[v as usize].contains(&f) {
                    return Err(format!("vertex {v} misses face {f}"));
                }
                let w = face[(k + 1) % face.len()];
                if self.edge_between(v, w).is_none() {
                    return Err(format!("face {f} side {v}-{w} has no edge"));
                }
            }
        }
        if tris != self.triangles {
            return Err(format!("triangle count {} != {}", self.triangles, tris));
        }
        for (v, fs) in self.vert_faces.iter().enumerate() {
            for &f in fs {
                if self.faces[f as usize].len == 0 || !self.face(f).contains(&(v as u32)) {
                    return Err(format!("vertex {v} lists face {f} it is not in"));
                }
            }
            let mut s = fs.to_vec();
            s.sort_unstable();
            s.dedup();
            if s.len() != fs.len() {
                return Err(format!("vertex {v} lists a face twice"));
            }
        }
        for v in 0..self.pos.len() as u32 {
            let mut sides = Vec::new();
            for &f in &self.vert_faces[v as usize] {
                let face = self.face(f);
                let n = face.len();
                for k in 0..n {
                    if face[k] == v {
                        sides.push(face[(k + n - 1) % n]);
                        sides.push(face[(k + 1) % n]);
                    }
                }
            }
            sides.sort_unstable();
            let once = sides
                .iter()
                .filter(|&&w| sides.iter().filter(|&&x| x == w).count() == 1)
                .count();
            if once != self.border_sides[v as usize] as usize {
                return Err(format!(
                    "vertex {v} counts {} boundary sides, has {once}",
                    self.border_sides[v as usize]
                ));
            }
            if let Some(list) = self.border_lists.get(&v) {
                let mut kept = list.to_vec();
                kept.sort_unstable();
                let mut found = Vec::new();
                self.scan_boundary_neighbors(v, &mut found);
                if kept != found {
                    return Err(format!(
                        "vertex {v} keeps {kept:?} as border, has {found:?}"
                    ));
                }
            }
            if let Some((cos, lists)) = &self.crease_lists {
                if let Some(list) = lists.get(&v) {
                    let fresh = self.crease_list(v, *cos).moments;
                    let m = &list.moments;
                    let close =
                        |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()));
                    let same = close(m.count, fresh.count)
                        && (0..3).all(|k| close(m.sum[k], fresh.sum[k]))
                        && (0..6).all(|k| close(m.outer[k], fresh.outer[k]));
                    if !same {
                        return Err(format!(
                            "vertex {v} keeps crease moments {m:?}, has {fresh:?}"
                        ));
                    }
                    let mut kept = list.sides.to_vec();
                    kept.sort_unstable();
                    let mut found = Vec::new();
                    self.scan_crease_neighbors(v, *cos, &mut found);
                    found.sort_unstable();
                    if kept != found {
                        return Err(format!(
                            "vertex {v} keeps {kept:?} as crease sides, has {found:?}"
                        ));
                    }
                }
            }
        }
        for (v, es) in self.vert_edges.iter().enumerate() {
            let mut others = Vec::new();
            for &e in es {
                if !self.edges[e as usize].alive() {
                    return Err(format!("vertex {v} lists dead edge {e}"));
                }
                let [a, b] = self.edges[e as usize].ends;
                if a != v as u32 && b != v as u32 {
                    return Err(format!("vertex {v} lists edge {e} = {a}-{b}"));
                }
                others.push(self.other(e, v as u32));
            }
            others.sort_unstable();
            let n = others.len();
            others.dedup();
            if others.len() != n {
                return Err(format!("vertex {v} has duplicate edges"));
            }
        }
        Ok(())
    }
}

/// The key of side `a`–`b` in a sorted list of sides: both orders alike.
#[inline]
pub(crate) fn side_key(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

/// The sides that occur exactly once in `sorted` (keys of [`side_key`],
/// sorted): the boundary sides, as vertex pairs.
pub(crate) fn sides_used_once(sorted: &[u64]) -> impl Iterator<Item = (u32, u32)> + '_ {
    sorted
        .chunk_by(|a, b| a == b)
        .filter(|run| run.len() == 1)
        .map(|run| ((run[0] >> 32) as u32, run[0] as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Complex {
        // 3×2 vertices, two quads:
        // 3---4---5
        // |   |   |
        // 0---1---2
        let pos = (0..6)
            .map(|i| DVec3::new((i % 3) as f64, (i / 3) as f64, 0.0))
            .collect();
        Complex::new(pos, &[0, 4, 8], &[0, 1, 4, 3, 1, 2, 5, 4]).0
    }

    #[test]
    fn an_edge_packs_its_generation_and_flags_in_one_word() {
        assert_eq!(std::mem::size_of::<Edge>(), 12);
        let mut e = Edge::new([3, 7], true);
        assert!(e.alive() && e.is_virtual() && !e.queued() && !e.refused());
        e.set_queued(true);
        e.set_refused(true);
        e.bump_gen();
        assert_eq!(e.gen(), 1);
        e.set_alive(false);
        assert!(!e.alive() && e.queued() && e.refused() && e.is_virtual());
        e.set_refused(false);
        assert!(e.queued() && !e.refused());
        // The generation wraps inside its bits, leaving the flags be.
        e.state = (e.state & !GEN_MASK) | GEN_MASK;
        e.bump_gen();
        assert_eq!(e.gen(), 0);
        assert!(!e.alive() && e.queued() && !e.refused() && e.is_virtual());
        assert_eq!(e.ends, [3, 7]);
    }

    #[test]
    fn triangles_keep_no_corner_list_and_polygons_shift_theirs() {
        // Quads: merging 4 into 1 shrinks both faces. Face 0 (0 1 4 3,
        // corners 0–3) keeps 1's corner, not the merged one's: 0 1 3.
        // Face 1 (1 2 5 4, corners 4–7) repeats 1 across its wrap and
        // keeps slot 0: corners 4 5 6.
        let mut c = grid();
        assert_eq!(c.slot_corner, (0..8).collect::<Vec<u32>>());
        let e = c.edge_between(1, 4).unwrap();
        c.collapse(e, 1, DVec3::X, false, &mut Vec::new());
        let corners = |c: &Complex, f: u32| {
            let s = c.faces[f as usize].start as usize;
            (s..s + c.faces[f as usize].len as usize)
                .map(|k| c.corner(k))
                .collect::<Vec<u32>>()
        };
        assert_eq!(c.face(0), &[0, 1, 3]);
        assert_eq!(corners(&c, 0), vec![0, 1, 3]);
        assert_eq!(c.face(1), &[1, 2, 5]);
        assert_eq!(corners(&c, 1), vec![4, 5, 6]);
        c.check().unwrap();
        // Triangles: no list, and every slot stays its own corner through
        // collapses (a triangle dies rather than shrink).
        let pos = (0..6)
            .map(|i| DVec3::new((i % 3) as f64, (i / 3) as f64, 0.0))
            .collect();
        let tris = [0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4];
        let mut t = Complex::new(pos, &[0, 3, 6, 9, 12], &tris).0;
        assert!(t.slot_corner.is_empty());
        let e = t.edge_between(1, 4).unwrap();
        t.collapse(e, 1, DVec3::X, false, &mut Vec::new());
        assert!(t.slot_corner.is_empty());
        for f in t.live_faces() {
            let s = t.faces[f as usize].start as usize;
            assert_eq!(
                corners(&t, f),
                (s as u32..s as u32 + 3).collect::<Vec<u32>>()
            );
            for (k, &v) in t.face(f).iter().enumerate() {
                let input = tris[s + k];
                assert!(v == input || (input == 4 && v == 1), "{f} {k}");
            }
        }
        t.check().unwrap();
    }

    #[test]
    fn builds_edges_and_stars_for_two_quads() {
        let c = grid();
        assert_eq!(c.edges.len(), 7);
        assert_eq!(c.triangles, 4);
        assert_eq!(&c.vert_faces[1], &[0, 1]);
        assert_eq!(c.edge_face_count(1, 4), 2);
        assert_eq!(c.edge_face_count(0, 1), 1);
        let mut b = Vec::new();
        c.boundary_neighbors(1, &mut b);
        assert_eq!(b, vec![0, 2]);
        c.check().unwrap();
    }

    #[test]
    fn collapsing_a_quad_edge_turns_the_quad_into_a_triangle() {
        let mut c = grid();
        let e = c.edge_between(0, 1).unwrap();
        let mut changed = Vec::new();
        let out = c.collapse(e, 1, DVec3::new(1.0, 0.0, 0.0), false, &mut changed);
        assert_eq!(out.removed_triangles, 1);
        assert_eq!(c.face(0), &[1, 4, 3]);
        assert_eq!(c.face(1), &[1, 2, 5, 4]);
        assert_eq!(c.triangles, 3);
        // The 0–3 edge now joins 1 and 3.
        assert!(c.edge_between(1, 3).is_some());
        c.check().unwrap();
    }

    #[test]
    fn collapsing_the_shared_edge_leaves_two_triangles() {
        let mut c = grid();
        let e = c.edge_between(1, 4).unwrap();
        let mut changed = Vec::new();
        let out = c.collapse(e, 4, DVec3::new(1.0, 0.5, 0.0), false, &mut changed);
        assert_eq!(out.removed_triangles, 2);
        assert_eq!(c.face(0).len(), 3);
        assert_eq!(c.face(1).len(), 3);
        assert!(!c.vert_edges[1].iter().any(|&e| c.edges[e as usize].alive()));
        c.check().unwrap();
    }

    #[test]
    fn degenerate_and_duplicate_input_faces_are_cleaned_and_twins_ride_along() {
        let pos = (0..4)
            .map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0))
            .collect();
        // f0 ok, f1 = f0 rotated (duplicate), f2 degenerate (0,0,1),
        // f3 = f0 reversed (double-sided twin, kept).
        let (c, cleaned) = Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 1, 2, 1, 2, 0, 0, 0, 1, 2, 1, 0],
        );
        assert_eq!(
            cleaned,
            Cleaned {
                degenerate: 1,
                duplicate: 1
            }
        );
        // The twin rides on f0: one face in the complex, two in the count.
        assert_eq!(c.triangles, 2);
        assert_eq!(c.live_faces().collect::<Vec<_>>(), vec![0]);
        assert_eq!(c.copies(0), 2);
        // f0 = (0, 1, 2) at input corners 0, 1, 2; f3 = (2, 1, 0) at 9, 10,
        // 11: vertex 0 is corner 11 of the twin, vertex 1 corner 10, 2 9.
        assert_eq!(
            c.riders,
            vec![Rider {
                face: 3,
                of: 0,
                corners: vec![11, 10, 9]
            }]
        );
        c.check().unwrap();
        // So every side of f0 is a border side: the sheet has its border.
        let mut b = Vec::new();
        c.boundary_neighbors(0, &mut b);
        assert_eq!(b, vec![1, 2]);
    }

    #[test]
    fn collapse_that_creates_a_duplicate_face_removes_it() {
        // Two triangles (0,2,3) and (1,2,3) with the same orientation become
        // the same face when 1 merges into 0.
        let pos = vec![DVec3::ZERO, DVec3::X * 0.1, DVec3::Y, DVec3::Z];
        let (mut c, _) = Complex::new(pos, &[0, 3, 6], &[0, 2, 3, 1, 2, 3]);
        c.add_edge(0, 1);
        let e = c.edge_between(0, 1).unwrap();
        let mut changed = Vec::new();
        let out = c.collapse(e, 0, DVec3::ZERO, false, &mut changed);
        assert_eq!(out.removed_triangles, 1);
        assert_eq!(c.triangles, 1);
        c.check().unwrap();
    }

    #[test]
    fn pentagon_pinched_at_a_diagonal_keeps_its_larger_loop() {
        // Pentagon 0-1-2-3-4 with a virtual edge between 0 and 3: merging
        // them splits the cycle into (0,1,2) and (0,4); the triangle stays.
        let pos = (0..5)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 5.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let (mut c, _) = Complex::new(pos, &[0, 5], &[0, 1, 2, 3, 4]);
        c.add_edge(0, 3);
        let e = c.edge_between(0, 3).unwrap();
        let mut changed = Vec::new();
        let out = c.collapse(e, 0, DVec3::ZERO, false, &mut changed);
        assert_eq!(out.removed_triangles, 2);
        assert_eq!(c.face(0), &[0, 1, 2]);
        assert!(!c.vert_faces[4].contains(&0));
        c.check().unwrap();
    }

    /// A small generator for the stress test (no dependency for it).
    struct Lcg(u64);
    impl Lcg {
        fn below(&mut self, n: usize) -> usize {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((self.0 >> 33) % n as u64) as usize
        }
    }

    #[test]
    fn border_counts_survive_random_collapses_on_wild_complexes() {
        // Triangles and quads drawn at random from few vertices: edges with
        // one, two and many faces, pinched vertices, faces that become
        // duplicates or split, plus virtual edges. After every collapse the
        // kept border counts must equal a recount from the faces.
        for seed in 0..200u64 {
            let mut rng = Lcg(seed);
            let nv = 8 + rng.below(10);
            let pos = (0..nv)
                .map(|k| DVec3::new(k as f64, (k * k % 7) as f64, (k % 3) as f64))
                .collect();
            let (mut offsets, mut indices) = (vec![0u32], Vec::new());
            for _ in 0..6 + rng.below(20) {
                let arity = 3 + rng.below(2);
                for _ in 0..arity {
                    indices.push(rng.below(nv) as u32);
                }
                offsets.push(indices.len() as u32);
            }
            let (mut c, _) = Complex::new(pos, &offsets, &indices);
            if seed % 2 == 1 {
                // Kept border lists for nearly every vertex.
                c.high_valence = 2;
                c.build_adjacency();
            }
            for _ in 0..3 {
                c.add_edge(rng.below(nv) as u32, rng.below(nv) as u32);
            }
            c.check()
                .unwrap_or_else(|e| panic!("seed {seed}, built: {e}"));
            let mut changed = Vec::new();
            for step in 0.. {
                let live: Vec<u32> = (0..c.edges.len() as u32)
                    .filter(|&e| c.edges[e as usize].alive())
                    .collect();
                if live.is_empty() {
                    break;
                }
                let e = live[rng.below(live.len())];
                let keep = c.edges[e as usize].ends[rng.below(2)];
                c.collapse(e, keep, DVec3::ZERO, rng.below(2) == 0, &mut changed);
                c.check()
                    .unwrap_or_else(|err| panic!("seed {seed}, collapse {step}: {err}"));
            }
        }
    }

    #[test]
    fn kept_crease_lists_survive_random_collapses_on_folded_fans() {
        // A fan of 200 slivers from a rim vertex, its corners jittered out
        // of the plane and across the rim so that many sides are creases,
        // collapsed at random to midpoints: after every collapse each kept
        // list must equal a scan of its vertex's faces (`check`).
        for seed in 0..20u64 {
            let mut rng = Lcg(seed);
            let n = 200u32;
            let pos = (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    let j = |r: &mut Lcg| (r.below(1000) as f64 / 1000.0 - 0.5) * 0.05;
                    DVec3::new(a.cos() + j(&mut rng), a.sin() + j(&mut rng), j(&mut rng))
                })
                .collect();
            let idx: Vec<u32> = (1..n - 1).flat_map(|k| [0, k, k + 1]).collect();
            let offsets: Vec<u32> = (0..n - 1).map(|f| 3 * f).collect();
            let (mut c, _) = Complex::new(pos, &offsets, &idx);
            if seed % 2 == 1 {
                // Lists for nearly every vertex, not only the centre.
                c.high_valence = 2;
            }
            let cos = 60f64.to_radians().cos();
            c.keep_crease_lists(cos);
            let mut first = Vec::new();
            c.crease_neighbors(0, cos, &mut first);
            assert!(!first.is_empty(), "seed {seed}: no crease to keep");
            c.check()
                .unwrap_or_else(|e| panic!("seed {seed}, built: {e}"));
            let mut changed = Vec::new();
            for step in 0..150 {
                let live: Vec<u32> = (0..c.edges.len() as u32)
                    .filter(|&e| c.edges[e as usize].alive())
                    .collect();
                if live.is_empty() {
                    break;
                }
                let e = live[rng.below(live.len())];
                let [a, b] = c.edges[e as usize].ends;
                let keep = if rng.below(2) == 0 { a } else { b };
                let x = 0.5 * (c.pos[a as usize] + c.pos[b as usize]);
                c.collapse(e, keep, x, rng.below(2) == 0, &mut changed);
                c.check()
                    .unwrap_or_else(|err| panic!("seed {seed}, collapse {step}: {err}"));
            }
        }
    }

    #[test]
    fn a_fan_centre_keeps_its_two_border_neighbours() {
        // An open fan of 100 triangles: above `HIGH_VALENCE`, so the centre
        // keeps a list; closing the fan leaves no border there.
        let n = 100u32;
        let pos = (0..=n + 1)
            .map(|k| {
                let a = k as f64 * 0.03;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let mut idx = Vec::new();
        for k in 1..=n {
            idx.extend_from_slice(&[0, k, k + 1]);
        }
        let offsets: Vec<u32> = (0..=n).map(|f| 3 * f).collect();
        let (c, _) = Complex::new(pos, &offsets, &idx);
        let mut b = Vec::new();
        c.boundary_neighbors(0, &mut b);
        assert_eq!(b, vec![1, n + 1]);
        assert!(c.on_boundary(0));
        assert!(c.border_lists.contains_key(&0));
        // Collapsing the first rim side moves the list's end to the kept
        // vertex.
        let mut c = c;
        let e = c.edge_between(1, 2).unwrap();
        c.collapse(e, 2, c.pos[2], false, &mut Vec::new());
        c.check().unwrap();
        b.clear();
        c.boundary_neighbors(0, &mut b);
        assert_eq!(b, vec![2, n + 1]);
        // The same fan closed: rim vertex n + 1 is vertex 1 again.
        let idx: Vec<u32> = idx
            .iter()
            .map(|&v| if v == n + 1 { 1 } else { v })
            .collect();
        let pos = (0..=n).map(|k| DVec3::new(k as f64, 1.0, 0.0)).collect();
        let (c, _) = Complex::new(pos, &offsets, &idx);
        b.clear();
        c.boundary_neighbors(0, &mut b);
        assert!(b.is_empty());
        assert!(!c.on_boundary(0));
        assert!(c.on_boundary(1));
    }
}
