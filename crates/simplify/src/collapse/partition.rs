//! The partitioned first phase for large inputs (see
//! [`crate::Partition`]): chunks along a Morton curve, simplified in
//! parallel rounds of a rising cost cap with the vertices near the cuts
//! locked, then written back into the global complex for the global loop.

use std::sync::atomic::AtomicBool;
use std::sync::atomic::AtomicU32;
use std::sync::atomic::Ordering::Relaxed;

use glam::DVec3;
use rayon::prelude::*;

use super::refused_around::RefusedAround;
use super::slots::{first_slots, split_ranges, Slots};
use super::{PerVertex, Run};
use crate::prepare::complex::{Complex, FaceSlots, NONE};
use crate::prepare::Prepared;
use crate::report::Report;
use crate::terms::attributes::ChunkWedges;
use crate::terms::stored::{Isotropic, StoredQuadric};

/// A chunk stops at this many times the triangles around its locked
/// vertices. Measured on the dragon at 1%: with no such floor the chunks
/// collapse their interiors onto the cuts (Hausdorff 0.039 against 0.018 for
/// one global loop); with 1.5, 2 or 3 the result is within 1% of the global
/// loop's Chamfer distance, in 2, 3 or 4 passes.
const RING_FLOOR: usize = 2;

/// Marks a vertex used by faces of more than one chunk.
const SHARED: u32 = u32::MAX - 1;

/// One chunk: its run over a local complex, and the way back to global ids.
struct Chunk<'o> {
    run: Run<'o>,
    /// Global id of each local vertex.
    vertex: Vec<u32>,
    /// Global id of each local face.
    face: Vec<u32>,
    /// The chunk paused under the current cap with work left, or stopped
    /// at its round's share of the removals.
    active: bool,
    /// Where it stops whatever the rounds allow: twice the faces around
    /// its locked vertices (see [`RING_FLOOR`]).
    floor: usize,
    /// It stopped at its round's share, with collapses under the cap left.
    limited: bool,
    /// With attributes: the run's corner of each local corner, and the
    /// run's id of each of the chunk's wedges, per fitted stream.
    corners: Vec<u32>,
    wedges: Option<Vec<Vec<u32>>>,
}

/// Whether the phase applies to this run.
pub(super) fn applies(run: &Run) -> bool {
    let o = run.options;
    let p = &o.partition;
    !o.record.history
        && !run.quads_active
        && run.p.complex.triangles >= p.min_triangles
        && p.chunk_faces > 0
        && chunk_count(run) >= 2
        && (run.p.complex.triangles > run.target || o.target.error.is_some())
}

/// How many chunks a pass over `run`'s complex would make.
fn chunk_count(run: &Run) -> usize {
    let faces = run.p.complex.faces.iter().filter(|f| f.len > 0).count();
    faces / run.options.partition.chunk_faces.max(1)
}

/// Spreads the low 10 bits of `x` to every third bit.
fn spread(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// 30-bit Morton code of a point in the normalized box ([-½, ½]³ at most),
/// with the grid shifted by `shift` (in box units, wrapping around).
fn morton(p: DVec3, shift: DVec3) -> u32 {
    let q = |t: f64, s: f64| {
        let u = (t + 0.5).clamp(0.0, 1.0) + s;
        (((u - u.floor()) * 1024.0) as u32).min(1023)
    };
    (spread(q(p.x, shift.x)) << 2) | (spread(q(p.y, shift.y)) << 1) | spread(q(p.z, shift.z))
}

/// The live faces cut into chunks of about `size` faces, consecutive along
/// the Morton curve of their centroids (ties by face id: deterministic).
fn cut(c: &Complex, size: usize, shift: DVec3) -> Vec<Vec<u32>> {
    let mut keyed: Vec<(u32, u32)> = (0..c.faces.len() as u32)
        .into_par_iter()
        .filter(|&f| c.faces[f as usize].len > 0)
        .map(|f| {
            let face = c.face(f);
            let sum: DVec3 = face.iter().map(|&v| c.pos[v as usize]).sum();
            (morton(sum / face.len() as f64, shift), f)
        })
        .collect();
    keyed.par_sort_unstable();
    let n = keyed.len();
    let count = n.div_ceil(size.max(1)).max(1);
    (0..count)
        .map(|k| {
            keyed[k * n / count..(k + 1) * n / count]
                .iter()
                .map(|&(_, f)| f)
                .collect()
        })
        .collect()
}

/// Which vertices the chunks must leave alone: those on faces of more than
/// one chunk (the cuts) and their face neighbours, and the ends of virtual
/// edges between chunks. With the ring locked too,
/// every collapse a chunk makes removes a vertex whose whole star is in the
/// chunk, onto a vertex whose whole star is in the chunk or that stays put;
/// so guards, duplicates and the link condition see all they would see
/// globally. Also returns each vertex's chunk (`SHARED` on a cut, `NONE`
/// when unused).
///
/// The chunks are swept in parallel (a sequential sweep of random vertex
/// accesses was a tenth of the phase's wall time): every result is the same
/// in any order, a vertex's owner being its one chunk or `SHARED`.
fn locked_vertices(
    c: &Complex,
    chunks: &[Vec<u32>],
    virtual_pairs: &[(u32, u32)],
) -> (Vec<bool>, Vec<u32>) {
    let owner: Vec<AtomicU32> = (0..c.pos.len()).map(|_| AtomicU32::new(NONE)).collect();
    chunks.par_iter().enumerate().for_each(|(k, faces)| {
        let k = k as u32;
        for &f in faces {
            for &v in c.face(f) {
                let o = &owner[v as usize];
                let now = o.load(Relaxed);
                if now == k || now == SHARED {
                    continue;
                }
                // Ignoring the result: `None` means nothing to change.
                let _ = o.fetch_update(Relaxed, Relaxed, |x| match x {
                    NONE => Some(k),
                    x if x == k || x == SHARED => None,
                    _ => Some(SHARED),
                });
            }
        }
    });
    let owner: Vec<u32> = owner.into_iter().map(AtomicU32::into_inner).collect();
    let locked: Vec<AtomicBool> = owner
        .par_iter()
        .map(|&o| AtomicBool::new(o == SHARED))
        .collect();
    // A virtual edge between chunks is a cut too: the global order glues
    // such parts early (the gluing term is cheap for close parts), so their
    // ends must still be there when the global loop gets to them. Where
    // parts touch everywhere, everything locks and the phase steps aside.
    for &(a, b) in virtual_pairs {
        if owner[a as usize] != owner[b as usize] || owner[a as usize] == SHARED {
            locked[a as usize].store(true, Relaxed);
            locked[b as usize].store(true, Relaxed);
        }
    }
    chunks.par_iter().for_each(|faces| {
        for &f in faces {
            let face = c.face(f);
            if face.iter().any(|&v| owner[v as usize] == SHARED) {
                for &v in face {
                    locked[v as usize].store(true, Relaxed);
                }
            }
        }
    });
    let locked = locked.into_iter().map(AtomicBool::into_inner).collect();
    (locked, owner)
}

/// A chunk's faces over local vertex ids, before its complex is built.
#[derive(Default)]
struct Layout {
    /// Global id of each local vertex, in order of first use.
    vertex: Vec<u32>,
    /// Global id of each face.
    face: Vec<u32>,
    slots: Vec<FaceSlots>,
    slot_vertex: Vec<u32>,
    slot_corner: Vec<u32>,
    /// Position of each local vertex: taken here, so that the global
    /// positions are freed before the chunks' adjacency is built (the
    /// pass's peak).
    pos: Vec<DVec3>,
    /// Virtual edges with both ends inside the chunk (local ids).
    pairs: Vec<(u32, u32)>,
    /// Triangles of the faces touching a locked vertex.
    ring: usize,
    /// With attributes, the run's corner of each local corner (a local
    /// corner is the slot it starts at): the chunk's attribute state is
    /// indexed by local corners.
    corners: Vec<u32>,
}

/// Every chunk's layout, in one sequential sweep with a shared global →
/// local map (a chunk's entries are only read while it is laid out; a
/// vertex inside one chunk keeps its entry).
fn layouts(
    c: &Complex,
    chunks: Vec<Vec<u32>>,
    locked: &[bool],
    owner: &[u32],
    virtual_pairs: &[(u32, u32)],
    attributes: bool,
) -> Vec<Layout> {
    let mut local = vec![NONE; c.pos.len()];
    let mut seen = vec![NONE; c.pos.len()];
    let mut out: Vec<Layout> = Vec::with_capacity(chunks.len());
    for (k, faces) in chunks.into_iter().enumerate() {
        // Exact capacities: the chunks' arrays live through every round, and
        // grown by doubling they would hold up to twice their size.
        let corners: usize = faces
            .iter()
            .map(|&f| c.faces[f as usize].len as usize)
            .sum();
        let mut l = Layout {
            slots: Vec::with_capacity(faces.len()),
            slot_vertex: Vec::with_capacity(corners),
            slot_corner: Vec::with_capacity(if c.slot_corner.is_empty() { 0 } else { corners }),
            ..Layout::default()
        };
        for &f in &faces {
            let g = c.faces[f as usize];
            l.slots.push(FaceSlots {
                start: l.slot_vertex.len() as u32,
                len: g.len,
            });
            let (s, n) = (g.start as usize, g.len as usize);
            let mut touches_lock = false;
            for &v in &c.slot_vertex[s..s + n] {
                if seen[v as usize] != k as u32 {
                    seen[v as usize] = k as u32;
                    local[v as usize] = l.vertex.len() as u32;
                    l.vertex.push(v);
                }
                l.slot_vertex.push(local[v as usize]);
                touches_lock |= locked[v as usize];
            }
            if attributes {
                // The chunk's attribute state is local: so are the corners
                // it reads (for triangles, the slots themselves).
                let local = l.corners.len() as u32;
                l.corners.extend((s..s + n).map(|k| c.corner(k)));
                if !c.slot_corner.is_empty() {
                    l.slot_corner.extend(local..local + n as u32);
                }
            } else if !c.slot_corner.is_empty() {
                // Empty for triangles (see `Complex::corner`): the global
                // corners stay valid through the pass.
                l.slot_corner.extend_from_slice(&c.slot_corner[s..s + n]);
            }
            if touches_lock {
                l.ring += n - 2;
            }
        }
        l.vertex.shrink_to_fit();
        l.pos = l.vertex.iter().map(|&v| c.pos[v as usize]).collect();
        l.face = faces;
        out.push(l);
    }
    for &(a, b) in virtual_pairs {
        let k = owner[a as usize];
        if k == owner[b as usize] && k != SHARED && k != NONE {
            out[k as usize]
                .pairs
                .push((local[a as usize], local[b as usize]));
        }
    }
    out
}

/// A live vertex in no chunk (unused by the live faces), its quadrics and
/// its position, set aside while the global arrays hold the chunks' values
/// (and the global positions are freed).
type Aside = (u32, StoredQuadric, Isotropic, DVec3);
/// Builds a chunk's run from its layout: its vertices' quadrics (its
/// ranges of the pass's arrays, see [`Slots`]) and locks, its virtual
/// edges, and a floor (see below) as its target.
fn build_chunk<'a>(
    run: &Run<'a>,
    layout: Layout,
    (quadrics, reg): (&'a mut [StoredQuadric], &'a mut [Isotropic]),
    (wedges, values): (Option<ChunkWedges>, Vec<&'a mut [f64]>),
    locked: &[bool],
) -> Chunk<'a> {
    let Layout {
        vertex,
        face,
        slots,
        slot_vertex,
        slot_corner,
        pos,
        pairs,
        ring,
        corners,
    } = layout;
    let mut complex = Complex::from_clean_faces(pos, slots, slot_vertex, slot_corner);
    for (a, b) in pairs {
        complex.add_edge(a, b);
    }
    let chunk_locked = vertex.iter().map(|&v| locked[v as usize]).collect();
    let triangles = complex.triangles;
    // Never below twice the faces around its locked vertices, where the
    // rest of the chunk would be collapsed onto them at ever higher cost
    // (the next pass, cut elsewhere, does better). Not held at its share
    // of the target: the rounds bound what the chunks remove together.
    let floor = RING_FLOOR * ring;
    let prepared = Prepared {
        complex,
        appearance_budget: f64::INFINITY,
        outliers: Vec::new(),
        outlier_inputs: Vec::new(),
        cleaned: 0,
        hidden_twins: 0,
        enclosed_parts: 0,
        ratio_base: triangles,
        weld: Vec::new(),
        center: run.p.center,
        scale: run.p.scale,
        input_triangles: triangles,
        weights: Vec::new(),
        rep: Vec::new(),
    };
    let (attrs, wedges) = match (&run.attrs, wedges) {
        (Some(a), Some(w)) => {
            let (state, ids) = a.chunk(w, values, &vertex);
            (Some(state), Some(ids))
        }
        _ => (None, None),
    };
    let mut chunk_run = Run::chunk(run, prepared, (quadrics, reg), attrs, chunk_locked, floor);
    chunk_run.inherit_pinch_prices(run, &vertex);
    Chunk {
        run: chunk_run,
        vertex,
        face,
        active: true,
        floor,
        limited: false,
        corners,
        wedges,
    }
}

/// Runs the phase on `run`'s complex, leaving it simplified to about the
/// handoff point with its adjacency and virtual edges rebuilt; the caller
/// then builds the queue and runs the global loop.
///
/// In passes: a pass leaves the faces around its locked vertices as they
/// are and stops where its interiors have been reduced as far as the whole
/// should be (see [`pass_goal`]); the next pass cuts the smaller mesh
/// again, its chunks spanning more surface and its cuts elsewhere (the grid
/// is shifted), until the mesh is small enough or the handoff point is
/// reached.
pub(super) fn presimplify(run: &mut Run, progress: &dyn Fn(f64)) {
    let settings = run.options.partition;
    let start = run.progress_start;
    let remove = start.saturating_sub(run.target);
    let handoff = run.target + (settings.handoff.clamp(0.0, 1.0) * remove as f64) as usize;
    // Golden-ratio steps: every pass's grid is shifted far from the last.
    const STEP: DVec3 = DVec3::new(0.618_034, 0.414_214, 0.732_051);
    let mut pass = 0.0;
    while run.p.complex.triangles > handoff && chunk_count(run) >= 2 {
        let before = run.p.complex.triangles;
        one_pass(run, STEP * pass, handoff, progress);
        run.report.parallel_passes += 1;
        pass += 1.0;
        // A pass that achieved little means the chunks are all at their
        // floors: the global loop does the rest better.
        if run.p.complex.triangles as f64 > 0.9 * before as f64 {
            break;
        }
    }
}

/// Where a pass over `triangles`, `ring` of them around its locked
/// vertices, stops for the phase to end at `handoff`: with its interiors
/// reduced, as a whole, by the ratio the phase has left to make
/// (`handoff / triangles`), and not further. The ring cannot be reduced
/// until a later pass cuts elsewhere; a pass that went all the way to the
/// handoff would leave it at full density and take its triangles out of
/// the interiors instead. On the dragon (871k triangles, a fifth of them
/// in the first pass's ring) at 50%, one pass to the handoff left the
/// interiors at 39% and the ring at 100%: Hausdorff 6.6e-5 and Chamfer
/// 5.1e-6 where one global loop gets 5.7e-5 and 4.2e-6; stopping each
/// pass here gets 5.7e-5 and 4.2e-6 in three passes.
fn pass_goal(triangles: usize, ring: usize, handoff: usize) -> usize {
    let ring = ring.min(triangles) as u128;
    let (n, h) = (triangles.max(1) as u128, handoff as u128);
    let goal = h + (ring * n.saturating_sub(h)) / n;
    goal.min(triangles as u128) as usize
}

/// One pass: cut, build the chunks, run the rounds, write back.
fn one_pass(run: &mut Run, shift: DVec3, handoff: usize, progress: &dyn Fn(f64)) {
    let settings = run.options.partition;
    let chunks = cut(&run.p.complex, settings.chunk_faces, shift);
    let (locked, owner) = locked_vertices(&run.p.complex, &chunks, &run.virtual_pairs);
    let start = run.progress_start;
    let remove = start.saturating_sub(run.target);
    let layouts = layouts(
        &run.p.complex,
        chunks,
        &locked,
        &owner,
        &run.virtual_pairs,
        run.attrs.is_some(),
    );
    let ring: usize = layouts.iter().map(|l| l.ring).sum();
    let goal = pass_goal(run.p.complex.triangles, ring, handoff);
    drop(owner);
    // The layouts hold every live face now, and `write_back` rewrites the
    // global corners from the chunks: freed before the chunks are built.
    let corners = run.p.complex.slot_vertex.len();
    // A complex of triangles keeps no corner list (see `Complex::corner`).
    let listed = !run.p.complex.slot_corner.is_empty();
    run.p.complex.slot_vertex = Vec::new();
    run.p.complex.slot_corner = Vec::new();
    // Faces laid out three slots each, in order (a complex built from
    // triangles): `write_back` can rebuild their slot ranges, so they are
    // freed too.
    let face_count = run.p.complex.faces.len();
    let regular = run
        .p
        .complex
        .faces
        .iter()
        .enumerate()
        .all(|(f, s)| s.start as usize == 3 * f);
    if regular {
        run.p.complex.faces = Vec::new();
    }
    let slots = Slots::new(
        layouts.iter().map(|l| &l.vertex[..]),
        run.p.complex.pos.len(),
    );
    // Live vertices in no chunk keep their quadrics; a removed vertex's
    // are never read again.
    let aside: Vec<Aside> = (0..slots.slot.len() as u32)
        .filter(|&v| slots.slot[v as usize] == NONE && run.merged_into[v as usize] == v)
        .map(|v| {
            let v_ = v as usize;
            (v, run.quadrics[v_], run.reg[v_], run.p.complex.pos[v_])
        })
        .collect();
    // Every chunk has its vertices' positions, and `write_back` puts them
    // back.
    run.p.complex.pos = Vec::new();
    let mut quadrics = std::mem::take(&mut run.quadrics).into_vec();
    let mut reg = std::mem::take(&mut run.reg).into_vec();
    let vertex_lists = || layouts.iter().map(|l| &l.vertex[..]);
    slots.move_to_chunks(&mut quadrics, 1, vertex_lists());
    slots.move_to_chunks(&mut reg, 1, vertex_lists());
    let ranges: Vec<_> = split_ranges(&mut quadrics, &slots.start, 1)
        .into_iter()
        .zip(split_ranges(&mut reg, &slots.start, 1))
        .collect();
    // Attributes: each chunk's wedges, and every fitted stream's wedge
    // quadrics rearranged into the chunks' ranges the same way.
    let wedges: Vec<Option<ChunkWedges>> = match &run.attrs {
        Some(a) => layouts
            .par_iter()
            .map(|l| Some(a.chunk_wedges(&l.corners)))
            .collect(),
        None => layouts.iter().map(|_| None).collect(),
    };
    let mut wedge_values: Vec<(Slots, Vec<f64>, usize)> = Vec::new();
    if let Some(a) = &mut run.attrs {
        for k in 0..a.fitted_streams() {
            let lists = || wedges.iter().flatten().map(|w| w.global(k));
            let ws = Slots::new(lists(), a.wedge_count(k));
            let stride = a.stride(k);
            let mut values = a.take_values(k);
            ws.move_to_chunks(&mut values, stride, lists());
            wedge_values.push((ws, values, stride));
        }
    }
    let mut chunk_values: Vec<Vec<&mut [f64]>> = layouts.iter().map(|_| Vec::new()).collect();
    for (ws, values, stride) in &mut wedge_values {
        for (to, range) in chunk_values
            .iter_mut()
            .zip(split_ranges(values, &ws.start, *stride))
        {
            to.push(range);
        }
    }
    let mut parts: Vec<Chunk> = {
        let this = &*run;
        layouts
            .into_par_iter()
            .zip(ranges)
            .zip(wedges.into_par_iter().zip(chunk_values))
            .map(|((layout, q), w)| build_chunk(this, layout, q, w, &locked))
            .collect()
    };
    // Not needed in the rounds: `write_back` finds the first slots again
    // from the chunks' vertex lists, and the global loop, which has not
    // run yet, refuses nothing before it does.
    drop(locked);
    let nv = slots.slot.len();
    let mut slots = slots;
    slots.slot = Vec::new();
    debug_assert!(run.refused_around.is_clear());
    debug_assert!(run.witness_waits.is_empty());
    run.refused_around = RefusedAround::default();
    // Rounds: every chunk makes its collapses up to the cap, which then
    // doubles (or jumps to the cheapest collapse left). Within a round the
    // order is each chunk's greedy order; across rounds, the global one.
    // The triangles go where the collapses are cheapest, as in the global
    // loop: a chunk is not held at its share of the target (a flat chunk
    // goes far below it, a detailed one stays above). What bounds the
    // chunks together is each round's removals: a chunk removes at most
    // its share (by its triangles) of those left before the pass's goal,
    // so that the chunks, running in parallel, cannot together go past it.
    // A chunk stopped by that share keeps the cap for another round.
    let mut cap = 0.0f64;
    loop {
        let left: usize = parts.iter().map(|p| p.run.p.complex.triangles).sum();
        progress(start.saturating_sub(left) as f64 / remove.max(1) as f64);
        // Within a triangle per chunk of the goal: the shares would round
        // to nothing, and the global loop finishes anyway.
        if left <= goal + parts.len() {
            break;
        }
        let budget = (left - goal) as u128;
        if !parts.iter().any(|p| p.active && p.limited) {
            let cheapest = parts
                .par_iter_mut()
                .filter(|p| p.active)
                .filter_map(|p| p.run.next_cost())
                .min_by(f64::total_cmp);
            let Some(cheapest) = cheapest else {
                break;
            };
            cap = (2.0 * cap).max(cheapest);
        }
        parts.par_iter_mut().filter(|p| p.active).for_each(|p| {
            let triangles = p.run.p.complex.triangles;
            let share = (budget * triangles as u128 / left as u128) as usize;
            p.run.target = p.floor.max(triangles.saturating_sub(share));
            let paused = p.run.collapse_until(cap, &|_| {});
            p.limited =
                !paused && p.run.target > p.floor && p.run.p.complex.triangles <= p.run.target;
            p.active = paused || p.limited;
        });
        // A round may remove nothing (the cheapest collapse refused): the
        // cap grows. But while a chunk waits at its share, the cap stays,
        // and shares rounded down to nothing would wait forever.
        let after: usize = parts.iter().map(|p| p.run.p.complex.triangles).sum();
        if after == left && parts.iter().any(|p| p.active && p.limited) {
            break;
        }
    }
    slots.slot = write_back(run, parts, corners, listed, regular.then_some(face_count));
    run.refused_around = RefusedAround::new(nv);
    slots.move_back(&mut quadrics, 1);
    slots.move_back(&mut reg, 1);
    if let Some(a) = &mut run.attrs {
        for (k, (ws, mut values, stride)) in wedge_values.into_iter().enumerate() {
            ws.move_back(&mut values, stride);
            a.restore_values(k, values);
        }
    }
    for (v, q, r, p) in aside {
        quadrics[v as usize] = q;
        reg[v as usize] = r;
        run.p.complex.pos[v as usize] = p;
    }
    run.quadrics = PerVertex::Owned(quadrics);
    run.reg = PerVertex::Owned(reg);
}

/// Copies every chunk's faces, moved positions and merges back to the
/// global complex (chunks in order: deterministic), whose corner arrays
/// (`corners` slots, freed during the rounds; the corner list only if it
/// was `listed`) are rebuilt here, and with them the faces' slot ranges
/// when those were freed too (`regular`: that many faces, three slots
/// each); the slots of faces in no chunk (dead ones) are never read
/// again. Each chunk's quadrics stay where they are, in its ranges of the
/// pass's arrays, summed by its own collapses. Returns each vertex's first
/// slot in those arrays (see [`Slots`]), freed during the rounds.
fn write_back(
    run: &mut Run,
    mut parts: Vec<Chunk>,
    corners: usize,
    listed: bool,
    regular: Option<usize>,
) -> Vec<u32> {
    // The chunks' adjacency and queues first, or the global corners would
    // be allocated on top of everything (the pass's peak).
    for part in &mut parts {
        part.run.release_adjacency();
    }
    let slot = first_slots(parts.iter().map(|p| &p.vertex[..]), run.merged_into.len());
    if let Some(n) = regular {
        // Every face that is in no chunk is dead.
        run.p.complex.faces = (0..n as u32)
            .map(|f| FaceSlots {
                start: 3 * f,
                len: 0,
            })
            .collect();
    }
    run.p.complex.slot_vertex = vec![NONE; corners];
    if listed {
        run.p.complex.slot_corner = vec![NONE; corners];
    }
    // Every vertex a chunk has gets its chunk's position (a vertex on a cut
    // is locked, so all its copies agree); the caller restores the others.
    run.p.complex.pos = vec![DVec3::ZERO; run.merged_into.len()];
    for part in parts {
        let Chunk {
            run: mut local,
            vertex,
            face,
            corners: corner_of,
            wedges,
            ..
        } = part;
        let lc = &local.p.complex;
        let gc = &mut run.p.complex;
        for (lf, &gf) in face.iter().enumerate() {
            let l = lc.faces[lf];
            let g = &mut gc.faces[gf as usize];
            g.len = l.len;
            let (ls, gs) = (l.start as usize, g.start as usize);
            for k in 0..l.len as usize {
                gc.slot_vertex[gs + k] = vertex[lc.slot_vertex[ls + k] as usize];
            }
            if listed && wedges.is_some() {
                for k in 0..l.len as usize {
                    gc.slot_corner[gs + k] = corner_of[lc.slot_corner[ls + k] as usize];
                }
            } else if listed {
                gc.slot_corner[gs..gs + l.len as usize]
                    .copy_from_slice(&lc.slot_corner[ls..ls + l.len as usize]);
            }
        }
        for (lv, &gv) in vertex.iter().enumerate() {
            gc.pos[gv as usize] = lc.pos[lv];
            if local.moved[lv] {
                run.moved[gv as usize] = true;
            }
            let into = local.merged_into[lv];
            if into != lv as u32 {
                run.merged_into[gv as usize] = vertex[into as usize];
            }
        }
        if let (Some(a), Some(chunk), Some(ids)) = (&mut run.attrs, local.attrs.take(), &wedges) {
            a.put_back(chunk, ids, &corner_of, &vertex);
        }
        add_report(&mut run.report, &local.report);
        run.error_limited |= local.error_limited;
    }
    // The global star lists are stale now: `Run::start` rebuilds them
    // (with the virtual edges) once the last pass is done.
    let c = &mut run.p.complex;
    c.clear_adjacency();
    c.triangles = c.count_triangles();
    slot
}

/// Adds a chunk's counts to the run's report.
fn add_report(to: &mut Report, from: &Report) {
    to.collapses += from.collapses;
    to.parallel_collapses += from.collapses;
    to.evaluations += from.evaluations;
    to.faces_tested += from.faces_tested;
    to.error = to.error.max(from.error);
    let (t, f) = (&mut to.rejected, &from.rejected);
    t.normal_flip += f.normal_flip;
    t.flat_border += f.flat_border;
    t.topology += f.topology;
    t.locked_border += f.locked_border;
    t.overshoot += f.overshoot;
    t.error_limit += f.error_limit;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_interleaves_axes() {
        // x = 1 step in the last cell column: bit 2; y: bit 1; z: bit 0.
        assert_eq!(spread(1), 1);
        assert_eq!(spread(0b11), 0b1001);
        assert_eq!(spread(0x3ff), 0x0924_9249);
        assert_eq!(morton(DVec3::splat(-0.5), DVec3::ZERO), 0);
        assert_eq!(morton(DVec3::splat(0.4999), DVec3::ZERO), (1 << 30) - 1);
        // Clamped outside the box.
        assert_eq!(morton(DVec3::splat(-3.0), DVec3::ZERO), 0);
        // Shifted by half the box: the low corner lands mid-grid (cell 512
        // on every axis), the middle wraps to the start.
        assert_eq!(
            morton(DVec3::splat(-0.5), DVec3::splat(0.5)),
            spread(512) * 7
        );
        assert_eq!(morton(DVec3::ZERO, DVec3::splat(0.5)), 0);
    }

    /// A strip of 8 quads (16 triangles) along x: vertex `k` at (k, 0),
    /// `9 + k` at (k, 1); quad `q` is triangles `2q` and `2q + 1`.
    fn strip() -> Complex {
        let pos = (0..18)
            .map(|v| DVec3::new((v % 9) as f64, (v / 9) as f64, 0.0))
            .collect();
        let mut idx = Vec::new();
        for k in 0..8u32 {
            idx.extend_from_slice(&[k, k + 1, k + 10, k, k + 10, k + 9]);
        }
        let offsets: Vec<u32> = (0..=16).map(|f| 3 * f).collect();
        Complex::new(pos, &offsets, &idx).0
    }

    #[test]
    fn a_pass_reduces_its_interiors_by_the_phases_ratio_and_leaves_the_ring() {
        // 1000 triangles, 200 in the ring, the phase to end at 400: the
        // 800 inside go to 800 · 0.4 = 320, the ring stays: 520.
        assert_eq!(pass_goal(1000, 200, 400), 520);
        // No ring: straight to the handoff.
        assert_eq!(pass_goal(1000, 0, 400), 400);
        // All ring: nothing to do this pass.
        assert_eq!(pass_goal(1000, 1000, 400), 1000);
        assert_eq!(pass_goal(1000, 5000, 400), 1000);
        // Already at the handoff.
        assert_eq!(pass_goal(300, 100, 400), 300);
    }

    #[test]
    fn the_cut_and_its_ring_are_locked() {
        let c = strip();
        // Quads 0-3 in one chunk, 4-7 in the other: they share column 4.
        let chunks = vec![(0..8).collect::<Vec<u32>>(), (8..16).collect()];
        let (locked, owner) = locked_vertices(&c, &chunks, &[]);
        let column = |v: usize| v % 9;
        for (v, &l) in locked.iter().enumerate() {
            assert_eq!(l, (3..=5).contains(&column(v)), "vertex {v}");
        }
        assert_eq!(owner[4], SHARED);
        assert_eq!(owner[13], SHARED);
        assert_eq!(owner[0], 0);
        assert_eq!(owner[8], 1);
        // A virtual edge across the chunks locks its ends; one inside a
        // chunk does not.
        let (locked, _) = locked_vertices(&c, &chunks, &[(0, 8), (1, 10)]);
        assert!(locked[0] && locked[8]);
        assert!(!locked[1] && !locked[10]);
    }

    #[test]
    fn slots_move_values_to_the_chunks_and_back() {
        let c = strip();
        let chunks = vec![(0..8).collect::<Vec<u32>>(), (8..16).collect()];
        let (locked, owner) = locked_vertices(&c, &chunks, &[]);
        let l = layouts(&c, chunks, &locked, &owner, &[], false);
        // Two more vertices than the faces use: they are in no chunk.
        let nv = c.pos.len() + 2;
        let slots = Slots::new(l.iter().map(|p| &p.vertex[..]), nv);
        let values: Vec<u64> = (0..nv as u64).map(|v| 100 + v).collect();
        let mut g = values.clone();
        slots.move_to_chunks(&mut g, 1, l.iter().map(|p| &p.vertex[..]));
        for (part, &start) in l.iter().zip(&slots.start) {
            for (k, &v) in part.vertex.iter().enumerate() {
                assert_eq!(g[start + k], values[v as usize], "vertex {v}");
            }
        }
        // The cut's column is in both chunks.
        assert_eq!(slots.start[2], c.pos.len() + 2);
        slots.move_back(&mut g, 1);
        let mut expected = values;
        expected[nv - 2..].fill(0);
        assert_eq!(g, expected);
    }

    #[test]
    fn layouts_map_faces_to_local_ids_and_back() {
        let c = strip();
        let chunks = vec![(0..8).collect::<Vec<u32>>(), (8..16).collect()];
        let (locked, owner) = locked_vertices(&c, &chunks, &[]);
        let l = layouts(&c, chunks, &locked, &owner, &[(0, 10)], false);
        for part in &l {
            for (lf, &gf) in part.face.iter().enumerate() {
                let s = part.slots[lf];
                let local = &part.slot_vertex[s.start as usize..(s.start + s.len) as usize];
                let global: Vec<u32> = local.iter().map(|&v| part.vertex[v as usize]).collect();
                assert_eq!(global, c.face(gf));
            }
        }
        // Locked columns 3-5 touch quads 2-3 and 4-5: 4 triangles a chunk.
        assert_eq!(l[0].ring, 4);
        assert_eq!(l[1].ring, 4);
        // The virtual edge 0-10 lies inside chunk 0.
        let (a, b) = l[0].pairs[0];
        assert_eq!((l[0].vertex[a as usize], l[0].vertex[b as usize]), (0, 10));
        assert!(l[1].pairs.is_empty());
    }
}
