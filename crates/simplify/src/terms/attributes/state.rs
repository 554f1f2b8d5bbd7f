//! The attribute state of a run: wedges and their quadrics per stream, the
//! skin quadrics per vertex, and the three hooks the collapse loop calls —
//! [`AttributeState::terms`] when it evaluates a collapse (the attribute
//! error as a position quadric, and where seams forbid or pin it),
//! [`AttributeState::plan`] / [`AttributeState::commit`] around a collapse
//! (merge the wedges it joins), and [`AttributeState::output`] at the end
//! (the fitted values at the final positions).

use glam::DVec3;
use smallvec::SmallVec;

use super::linear_fit::FaceFrame;
use super::morph::{MorphSums, MorphTerm};
use super::quadric::{accumulate, Layout};
use super::seams::{plan_stream, StreamPlan};
use super::skin::SkinQuadric;
use super::wedges::{build_wedges, stream_key, value_tolerance, within, Wedges};
use crate::error::Error;
use crate::input::{
    AttributeInput, FittedSkin, FittedStream, MorphStream, SeamPolicy, SkinStream, StreamKind,
    ABSENT,
};
use crate::prepare::complex::Complex;
use crate::prepare::geometry::newell;
use crate::terms::quadric::Quadric;
use crate::terms::tangent::tangent_plane;

/// Above this share of split edges a stream's values are per face, not
/// charts with seams: half of the edges is far beyond any UV layout or
/// hard-edge set an artist makes, and below what flat shading gives (every
/// edge between faces of different planes).
const MAX_SEAM_SHARE: f64 = 0.5;

/// One fitted stream's state.
/// A stream's wedge quadrics (`layout.stride()` floats per wedge): the
/// run's own, or a chunk's range of the run's, which the partitioned phase
/// rearranges so that each chunk's wedges follow one another (see
/// `collapse::partition`): the phase then needs no second copy.
pub(crate) enum WedgeValues<'a> {
    Owned(Vec<f64>),
    Borrowed(&'a mut [f64]),
}

impl std::ops::Deref for WedgeValues<'_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        match self {
            WedgeValues::Owned(v) => v,
            WedgeValues::Borrowed(s) => s,
        }
    }
}

impl std::ops::DerefMut for WedgeValues<'_> {
    fn deref_mut(&mut self) -> &mut [f64] {
        match self {
            WedgeValues::Owned(v) => v,
            WedgeValues::Borrowed(s) => s,
        }
    }
}

pub(super) struct StreamState<'a> {
    /// Index in the caller's `AttributeInput::streams`.
    pub(super) input: usize,
    pub(super) layout: Layout,
    /// (weight / range)²: the factor of its reduced quadrics in the cost.
    pub(super) scale: f64,
    pub(super) seams: bool,
    pub(super) kind: StreamKind,
    pub(super) wedges: Wedges,
    /// Per wedge, `layout.stride()` floats.
    pub(super) quadrics: WedgeValues<'a>,
    /// Per wedge: merged with another wedge (its value must be refitted).
    pub(super) merged: Vec<bool>,
    /// The input range of each component, for clamping fitted values.
    pub(super) lo: [f32; 4],
    pub(super) hi: [f32; 4],
}

/// The per-vertex skin quadrics.
pub(super) struct SkinState {
    pub(super) scale: f64,
    pub(super) influences: usize,
    pub(super) quadrics: Vec<SkinQuadric>,
}

/// The per-vertex morph sums (see `morph.rs`) and each morph stream's
/// input range per component, for clamping fitted deltas.
pub(super) struct MorphState {
    pub(super) sums: Vec<MorphSums>,
    pub(super) lo: Vec<[f32; 3]>,
    pub(super) hi: Vec<[f32; 3]>,
}

/// What attributes add to the evaluation of a collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Terms {
    /// The attribute error as a position quadric (already weighted).
    pub quadric: Quadric,
    /// The first endpoint must stay where it is (a seam would move).
    pub fixed_i: bool,
    /// The second endpoint must stay where it is.
    pub fixed_j: bool,
}

/// The merges a collapse makes, planned before it changes the faces.
pub(crate) struct Plan {
    streams: Vec<StreamPlan>,
}

/// Reusable buffers of one evaluating thread.
#[derive(Default)]
pub(crate) struct AttrScratch {
    corners_i: Vec<u32>,
    corners_j: Vec<u32>,
    pairs: Vec<(u32, u32)>,
    wi: Vec<u32>,
    wj: Vec<u32>,
    wpairs: Vec<(u32, u32)>,
    sum: Vec<f64>,
}

/// Attribute state of one run.
pub(crate) struct AttributeState<'a> {
    pub(super) streams: Vec<StreamState<'a>>,
    /// Material borders as a stream without values: wedges only.
    pub(super) groups: Option<Wedges>,
    pub(super) skin: Option<SkinState>,
    pub(super) morph: Option<MorphState>,
    /// Streams given to [`AttributeState::new`], carried ones included.
    pub(super) carried: Vec<usize>,
    pub(super) stream_count: usize,
    /// Seams are kept strictly ([`SeamPolicy::Keep`]).
    pub(super) strict: bool,
    /// Any seam exists at all (otherwise relaxing changes nothing).
    pub(super) has_seams: bool,
}

/// Per-corner checks of a stream against the face corners.
fn check_stream(
    k: usize,
    components: usize,
    values: &[f32],
    indices: &[u32],
    corners: usize,
) -> Result<(), Error> {
    if !(1..=4).contains(&components) || values.len() % components != 0 {
        return Err(Error::BadAttribute {
            stream: k,
            problem: format!("{components} components and {} values", values.len()),
        });
    }
    if indices.len() != corners {
        return Err(Error::BadAttribute {
            stream: k,
            problem: format!("{} indices for {corners} corners", indices.len()),
        });
    }
    let count = values.len() / components;
    if let Some(c) = indices
        .iter()
        .position(|&i| i != ABSENT && i as usize >= count)
    {
        return Err(Error::BadAttribute {
            stream: k,
            problem: format!(
                "corner {c} refers to value {}, but there are {count}",
                indices[c]
            ),
        });
    }
    if let Some(x) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::BadAttribute {
            stream: k,
            problem: format!("value {} is not finite", x / components),
        });
    }
    Ok(())
}

impl AttributeState<'_> {
    /// Builds wedges and quadrics from the input. `corner_vertex[c]` is the
    /// welded vertex of input corner `c`; the complex is the run's, built
    /// over the same corners (its slots still are the input corners).
    /// `vertex_weight` scales a vertex's quadrics (empty: all 1);
    /// `weight_factor` every stream's weight (see
    /// [`crate::QuadSettings::attribute_weight`]).
    pub fn new(
        input: &AttributeInput<'_>,
        corner_vertex: &[u32],
        c: &Complex,
        vertex_weight: &[f64],
        policy: SeamPolicy,
        weight_factor: f64,
    ) -> Result<AttributeState<'static>, Error> {
        let corners = corner_vertex.len();
        let edge_length = mean_edge_length(c);
        let mut streams = Vec::new();
        let mut carried = Vec::new();
        for (k, s) in input.streams.iter().enumerate() {
            check_stream(k, s.components, s.values, s.indices, corners)?;
            if !(s.weight >= 0.0 && s.weight.is_finite()) {
                return Err(Error::BadOption {
                    name: "attribute weight",
                    value: s.weight,
                });
            }
            if s.kind == StreamKind::Carried {
                carried.push(k);
                continue;
            }
            let m = s.components;
            let (mut lo, mut hi) = ([f32::INFINITY; 4], [f32::NEG_INFINITY; 4]);
            for v in s.values.chunks_exact(m) {
                for (x, &y) in v.iter().enumerate() {
                    lo[x] = lo[x].min(y);
                    hi[x] = hi[x].max(y);
                }
            }
            let value_range = (0..m)
                .map(|x| (hi[x] - lo[x]) as f64)
                .fold(0.0f64, f64::max);
            let wedges = build_wedges(
                corner_vertex,
                |c| stream_key(s.values, s.indices, m, c),
                within(value_tolerance(s.kind, value_range)),
            );
            // The factor that brings the stream to the diagonal's scale
            // (see `StreamKind`); texture coordinates get theirs once the
            // face loop has measured surface and UV areas.
            let unit = match s.kind {
                StreamKind::Generic if value_range > 0.0 => 1.0 / value_range,
                // Normals and colors change by their gradient times the
                // distance a collapse spans: an error in them is worth the
                // surface displacement one edge away, not a diagonal, or
                // they would outweigh geometry more the finer the mesh.
                StreamKind::Direction | StreamKind::Color => edge_length,
                _ => 1.0,
            };
            let layout = Layout { m };
            streams.push(StreamState {
                input: k,
                layout,
                scale: (s.weight * weight_factor * unit).powi(2),
                seams: s.seams && policy != SeamPolicy::Ignore,
                kind: s.kind,
                quadrics: WedgeValues::Owned(vec![0.0; wedges.count() * layout.stride()]),
                merged: vec![false; wedges.count()],
                wedges,
                lo,
                hi,
            });
        }
        let groups = if input.face_groups.is_empty() || policy == SeamPolicy::Ignore {
            None
        } else {
            if input.face_groups.len() != c.faces.len() {
                return Err(Error::BadAttribute {
                    stream: usize::MAX,
                    problem: format!(
                        "{} face groups for {} faces",
                        input.face_groups.len(),
                        c.faces.len()
                    ),
                });
            }
            // The face of every input corner.
            let mut corner_face = vec![0u32; corners];
            let offsets = face_offsets(c, corners);
            for f in 0..offsets.len() - 1 {
                for x in offsets[f]..offsets[f + 1] {
                    corner_face[x as usize] = f as u32;
                }
            }
            let g = input.face_groups;
            Some(build_wedges(
                corner_vertex,
                |x| Some([g[corner_face[x] as usize], 0, 0, 0]),
                |a, b| a == b,
            ))
        };
        let mut state = AttributeState {
            streams,
            groups,
            skin: None,
            morph: morph_state(&input.morphs, corners, c)?,
            carried,
            stream_count: input.streams.len(),
            strict: policy == SeamPolicy::Keep,
            has_seams: false,
        };
        if let Some(skin) = &input.skin {
            let mut sk = skin_state(skin, corners, c, vertex_weight)?;
            sk.scale *= weight_factor * weight_factor;
            state.skin = Some(sk);
        }
        state.fill_quadrics(input, c, vertex_weight);
        for st in &mut state.streams {
            // A stream that steers nothing has no seams worth a collapse
            // (UVs without area map no texture); one that splits most edges
            // holds per-face values (flat shading, degenerate UVs), whose
            // "seams" are the whole mesh, not curves to keep.
            if st.seams && (st.scale == 0.0 || seam_share(c, &st.wedges) > MAX_SEAM_SHARE) {
                st.seams = false;
            }
        }
        state.has_seams = state.find_any_seam(corner_vertex, c.pos.len());
        Ok(state)
    }

    /// Whether any attribute steers collapses: a stream of nonzero weight,
    /// or skin weights of nonzero weight.
    pub fn steers(&self) -> bool {
        self.streams.iter().any(|s| s.scale > 0.0)
            || self.skin.as_ref().is_some_and(|k| k.scale > 0.0)
    }

    /// Adds every live face's linear functionals to the wedges of its
    /// corners (area share = area / arity).
    fn fill_quadrics(&mut self, input: &AttributeInput<'_>, c: &Complex, weight: &[f64]) {
        // Per stream: surface and UV area of the faces it covers.
        let mut areas = vec![(0.0f64, 0.0f64); self.streams.len()];
        let mut pos: Vec<DVec3> = Vec::new();
        let mut corners: Vec<u32> = Vec::new();
        let mut g: Vec<DVec3> = Vec::new();
        let mut d: Vec<f64> = Vec::new();
        for f in c.live_faces() {
            let fs = c.faces[f as usize];
            let (s, n) = (fs.start as usize, fs.len as usize);
            pos.clear();
            pos.extend(c.slot_vertex[s..s + n].iter().map(|&v| c.pos[v as usize]));
            let (n2, _) = newell(pos.iter().copied());
            let len = n2.length();
            if (len.is_nan() || len <= 0.0) || !len.is_finite() {
                continue;
            }
            let Some(frame) = FaceFrame::new(&pos, n2 / len) else {
                continue;
            };
            let share = 0.5 * len / n as f64;
            corners.clear();
            corners.extend((s..s + n).map(|k| c.corner(k)));
            let verts = &c.slot_vertex[s..s + n];
            for (st, area) in self.streams.iter_mut().zip(&mut areas) {
                let src = &input.streams[st.input];
                let m = st.layout.m;
                if corners.iter().any(|&x| src.indices[x as usize] == ABSENT) {
                    continue;
                }
                if st.kind == StreamKind::TexCoord && m >= 2 {
                    let uv = |x: u32| {
                        let i = src.indices[x as usize] as usize * m;
                        (src.values[i] as f64, src.values[i + 1] as f64)
                    };
                    let mut twice = 0.0;
                    for k in 0..n {
                        let (a, b) = (uv(corners[k]), uv(corners[(k + 1) % n]));
                        twice += a.0 * b.1 - a.1 * b.0;
                    }
                    area.0 += 0.5 * len;
                    area.1 += 0.5 * twice.abs();
                }
                g.clear();
                d.clear();
                for k in 0..m {
                    let (gk, dk) = frame.fit(
                        &pos,
                        corners
                            .iter()
                            .map(|&x| src.values[src.indices[x as usize] as usize * m + k] as f64),
                    );
                    g.push(gk);
                    d.push(dk);
                }
                let stride = st.layout.stride();
                for (&x, &v) in corners.iter().zip(verts) {
                    let w = st.wedges.corner_wedge[x as usize] as usize;
                    let a = share * weight.get(v as usize).copied().unwrap_or(1.0);
                    st.layout
                        .add_face(&mut st.quadrics[w * stride..(w + 1) * stride], a, &g, &d);
                }
            }
            let face = FaceShare {
                frame: &frame,
                pos: &pos,
                corners: &corners,
                verts,
                share,
                weight,
            };
            if let (Some(sk), Some(src)) = (&mut self.skin, &input.skin) {
                add_skin_face(sk, src, &face);
            }
            if let Some(ms) = &mut self.morph {
                add_morph_face(ms, &input.morphs, &face);
            }
        }
        for (st, (surface, uv)) in self.streams.iter_mut().zip(areas) {
            if st.kind == StreamKind::TexCoord {
                // A UV error of d slides the texture by d·sqrt(surface/uv)
                // on the surface; without UV area the UVs say nothing.
                st.scale *= if uv > 0.0 { surface / uv } else { 0.0 };
            }
        }
    }

    /// Whether any stream that keeps seams (or the material) has a vertex
    /// with two wedges.
    fn find_any_seam(&self, corner_vertex: &[u32], vertices: usize) -> bool {
        let mut first = vec![ABSENT; vertices];
        let seam_wedges = self
            .streams
            .iter()
            .filter(|s| s.seams)
            .map(|s| &s.wedges)
            .chain(self.groups.iter());
        for w in seam_wedges {
            first.fill(ABSENT);
            for (x, &wedge) in w.corner_wedge.iter().enumerate() {
                if wedge == ABSENT {
                    continue;
                }
                let f = &mut first[corner_vertex[x] as usize];
                if *f == ABSENT {
                    *f = wedge;
                } else if *f != wedge {
                    return true;
                }
            }
        }
        false
    }

    /// The corners at `i` and at `j`, and the (corner at `i`, corner at `j`)
    /// of every face holding both, into the scratch.
    fn gather(&self, c: &Complex, i: u32, j: u32, s: &mut AttrScratch) {
        s.corners_i.clear();
        s.corners_j.clear();
        s.pairs.clear();
        for &f in &c.vert_faces[i as usize] {
            let fs = c.faces[f as usize];
            let (st, n) = (fs.start as usize, fs.len as usize);
            let (mut ci, mut cj) = (ABSENT, ABSENT);
            for k in st..st + n {
                let v = c.slot_vertex[k];
                if v == i {
                    ci = c.corner(k);
                } else if v == j {
                    cj = c.corner(k);
                }
            }
            if ci != ABSENT {
                s.corners_i.push(ci);
                if cj != ABSENT {
                    s.pairs.push((ci, cj));
                }
            }
        }
        for &f in &c.vert_faces[j as usize] {
            let fs = c.faces[f as usize];
            let (st, n) = (fs.start as usize, fs.len as usize);
            for k in st..st + n {
                if c.slot_vertex[k] == j {
                    s.corners_j.push(c.corner(k));
                }
            }
        }
    }

    /// The distinct wedges of `corners` in `w`, and the wedge pairs.
    fn wedge_sets(w: &Wedges, s: &mut AttrScratch) {
        let cw = &w.corner_wedge;
        let distinct = |corners: &[u32], out: &mut Vec<u32>| {
            out.clear();
            for &x in corners {
                let id = cw[x as usize];
                if id != ABSENT && !out.contains(&id) {
                    out.push(id);
                }
            }
        };
        distinct(&s.corners_i, &mut s.wi);
        distinct(&s.corners_j, &mut s.wj);
        s.wpairs.clear();
        for &(a, b) in &s.pairs {
            let (wa, wb) = (cw[a as usize], cw[b as usize]);
            if wa != ABSENT && wb != ABSENT {
                s.wpairs.push((wa, wb));
            }
        }
    }

    /// The attribute terms of collapsing `(i, j)`, or `None` when keeping
    /// seams forbids it.
    pub fn terms(&self, c: &Complex, i: u32, j: u32, s: &mut AttrScratch) -> Option<Terms> {
        self.gather(c, i, j, s);
        let mut t = Terms {
            quadric: Quadric::ZERO,
            fixed_i: false,
            fixed_j: false,
        };
        if let Some(g) = &self.groups {
            Self::wedge_sets(g, s);
            let p = plan_stream(&s.wi, &s.wj, &s.wpairs, self.strict).ok()?;
            t.fixed_i |= p.fixed_i;
            t.fixed_j |= p.fixed_j;
        }
        for st in &self.streams {
            if st.scale == 0.0 && !st.seams {
                continue;
            }
            Self::wedge_sets(&st.wedges, s);
            let p = plan_stream(&s.wi, &s.wj, &s.wpairs, self.strict && st.seams).ok()?;
            t.fixed_i |= p.fixed_i;
            t.fixed_j |= p.fixed_j;
            if st.scale == 0.0 {
                continue;
            }
            let stride = st.layout.stride();
            for group in &p.groups {
                let q = |w: u32| &st.quadrics[w as usize * stride..(w as usize + 1) * stride];
                if group.len() == 1 {
                    t.quadric += st.layout.reduce(q(group[0]), st.scale);
                } else {
                    s.sum.clear();
                    s.sum.extend_from_slice(q(group[0]));
                    for &w in &group[1..] {
                        accumulate(&mut s.sum, q(w));
                    }
                    t.quadric += st.layout.reduce(&s.sum, st.scale);
                }
            }
        }
        if let Some(sk) = &self.skin {
            if sk.scale > 0.0 {
                let mut merged = sk.quadrics[i as usize].clone();
                merged.merge(
                    &sk.quadrics[j as usize],
                    c.pos[i as usize],
                    c.pos[j as usize],
                );
                t.quadric += merged.reduce(sk.scale);
            }
        }
        if t.fixed_i && t.fixed_j {
            return None;
        }
        Some(t)
    }

    /// The merges of collapsing `(i, j)`, planned on the faces before the
    /// collapse changes them.
    pub fn plan(&self, c: &Complex, i: u32, j: u32, s: &mut AttrScratch) -> Plan {
        self.gather(c, i, j, s);
        let streams = self
            .streams
            .iter()
            .map(|st| {
                Self::wedge_sets(&st.wedges, s);
                // Made collapses were allowed: plan without refusing.
                plan_stream(&s.wi, &s.wj, &s.wpairs, false).unwrap_or_default()
            })
            .collect();
        Plan { streams }
    }

    /// Carries out `plan` after `j` was merged into `i` (which now holds
    /// every surviving corner of both): merged wedges sum their quadrics and
    /// the corners of the absorbed ones take the survivor's id; `i`'s skin
    /// quadric absorbs `j`'s. `pi`, `pj` are the endpoints' positions
    /// before the collapse.
    pub fn commit(&mut self, c: &Complex, i: u32, j: u32, plan: Plan, pi: DVec3, pj: DVec3) {
        for (st, p) in self.streams.iter_mut().zip(plan.streams) {
            let stride = st.layout.stride();
            for group in p.groups.iter().filter(|g| g.len() > 1) {
                let lead = group[0] as usize;
                st.merged[lead] = true;
                for &w in &group[1..] {
                    let w = w as usize;
                    let (head, tail) = st.quadrics.split_at_mut(w.max(lead) * stride);
                    if w > lead {
                        accumulate(
                            &mut head[lead * stride..(lead + 1) * stride],
                            &tail[..stride],
                        );
                    } else {
                        let src: Vec<f64> = head[w * stride..(w + 1) * stride].to_vec();
                        accumulate(&mut tail[..stride], &src);
                    }
                }
                for &f in &c.vert_faces[i as usize] {
                    let fs = c.faces[f as usize];
                    for k in fs.start as usize..(fs.start + fs.len) as usize {
                        if c.slot_vertex[k] != i {
                            continue;
                        }
                        let x = c.corner(k) as usize;
                        if group[1..].contains(&st.wedges.corner_wedge[x]) {
                            st.wedges.corner_wedge[x] = lead as u32;
                        }
                    }
                }
            }
        }
        if let Some(sk) = &mut self.skin {
            let other = std::mem::take(&mut sk.quadrics[j as usize]);
            sk.quadrics[i as usize].merge(&other, pi, pj);
        }
        if let Some(ms) = &mut self.morph {
            let other = std::mem::take(&mut ms.sums[j as usize]);
            ms.sums[i as usize].merge(&other);
        }
    }

    /// The output streams, in the caller's order: for every output corner
    /// (`corner_origin`, its input corner; `corner_vertex_out`, the run's
    /// vertex it is at), the value of its wedge fitted at the vertex's final
    /// position (normalized coordinates in `pos`) — or the input value of
    /// the wedge's first corner, bit for bit, for a wedge that was never
    /// merged at a vertex that never moved. Carried streams keep every corner's input value.
    pub fn output(
        &self,
        input: &AttributeInput<'_>,
        corner_origin: &[u32],
        corner_vertex: &[u32],
        pos: &[DVec3],
        moved: &[bool],
    ) -> Vec<FittedStream> {
        let mut out: Vec<FittedStream> = (0..self.stream_count)
            .map(|k| FittedStream {
                components: input.streams[k].components,
                ..FittedStream::default()
            })
            .collect();
        for &k in &self.carried {
            let src = &input.streams[k];
            out[k].values = src.values.to_vec();
            out[k].indices = corner_origin
                .iter()
                .map(|&x| src.indices[x as usize])
                .collect();
        }
        let mut buf = [0.0f64; 4];
        for st in &self.streams {
            let src = &input.streams[st.input];
            let m = st.layout.m;
            let stride = st.layout.stride();
            let mut value_of = vec![ABSENT; st.wedges.count()];
            let o = &mut out[st.input];
            o.indices.reserve(corner_origin.len());
            for (&x, &v) in corner_origin.iter().zip(corner_vertex) {
                let w = st.wedges.corner_wedge[x as usize];
                if w == ABSENT {
                    o.indices.push(ABSENT);
                    continue;
                }
                if value_of[w as usize] == ABSENT {
                    value_of[w as usize] = (o.values.len() / m) as u32;
                    let q = &st.quadrics[w as usize * stride..(w as usize + 1) * stride];
                    let refit = st.merged[w as usize] || moved[v as usize];
                    let fitted = refit
                        && st
                            .layout
                            .values(q, pos[v as usize], &mut buf[..m])
                            .is_some();
                    if fitted {
                        finish(st, &mut buf[..m]);
                        o.values.extend(buf[..m].iter().map(|&y| y as f32));
                    } else {
                        // The value of the wedge's first input corner.
                        let first = st.wedges.first_corner[w as usize] as usize;
                        let i = src.indices[first] as usize;
                        o.values.extend_from_slice(&src.values[i * m..i * m + m]);
                    }
                }
                o.indices.push(value_of[w as usize]);
            }
        }
        out
    }

    /// Per morph stream, one delta per output vertex (`vertices[k]` is the
    /// run's vertex of output vertex `k`): fitted at its final position
    /// (normalized coordinates in `pos`) and clamped to the stream's input
    /// range, or, at a vertex that never moved and never merged, the
    /// input delta of its first corner, bit for bit.
    pub fn output_morphs(
        &self,
        input: &AttributeInput<'_>,
        vertices: &[u32],
        pos: &[DVec3],
        moved: &[bool],
    ) -> Vec<Vec<[f32; 3]>> {
        let Some(ms) = &self.morph else {
            return Vec::new();
        };
        input
            .morphs
            .iter()
            .enumerate()
            .map(|(k, src)| {
                vertices
                    .iter()
                    .map(|&v| {
                        let sums = &ms.sums[v as usize];
                        let still = !sums.merged && !moved.get(v as usize).copied().unwrap_or(true);
                        if still && sums.first_corner != u32::MAX {
                            return morph_value(src, sums.first_corner);
                        }
                        let d = sums.value(k as u32, pos[v as usize]);
                        std::array::from_fn(|c| {
                            let x = d[c] as f32;
                            if x.is_finite() {
                                x.clamp(ms.lo[k][c], ms.hi[k][c])
                            } else {
                                0.0
                            }
                        })
                    })
                    .collect()
            })
            .collect()
    }

    /// One influence set per output vertex (`vertices[k]` is the run's
    /// vertex of output vertex `k`), fitted at its final position.
    pub fn output_skin(&self, vertices: &[u32], pos: &[DVec3]) -> Option<FittedSkin> {
        let sk = self.skin.as_ref()?;
        let k = sk.influences;
        let mut joints = vec![0u16; vertices.len() * k];
        let mut weights = vec![0f32; vertices.len() * k];
        for (o, &v) in vertices.iter().enumerate() {
            let inf = sk.quadrics[v as usize].influences(pos[v as usize], k);
            let mut w: Vec<f32> = inf.iter().map(|x| x.1 as f32).collect();
            // Rounding to f32 may leave the sum off by an ulp or two; the
            // largest weight takes up the difference.
            let sum: f32 = w.iter().sum();
            if let Some(first) = w.first_mut() {
                *first += 1.0 - sum;
            }
            for (slot, (x, wx)) in inf.iter().zip(w).enumerate() {
                joints[o * k + slot] = x.0;
                weights[o * k + slot] = wx;
            }
        }
        Some(FittedSkin {
            influences: k,
            joints,
            weights,
        })
    }

    /// Constraint planes along seam edges (edges whose faces disagree on a
    /// wedge at either end, in any stream that keeps seams, or on the
    /// material): for each face on such an edge, the plane through the edge
    /// orthogonal to the face, weighted by `weight · |edge|²`, added to both
    /// endpoints. They keep a seam's vertices on the seam's curve when a
    /// collapse along it moves them, as boundary planes keep a border
    /// (Garland & Heckbert 1997 §6; meshoptimizer does the same for seams).
    pub fn seam_planes(&self, c: &Complex, weight: f64) -> Vec<Quadric> {
        let mut out = vec![Quadric::ZERO; c.pos.len()];
        if weight <= 0.0 || !self.has_seams {
            return out;
        }
        let seam_streams: Vec<&Wedges> = self
            .streams
            .iter()
            .filter(|s| s.seams)
            .map(|s| &s.wedges)
            .chain(self.groups.iter())
            .collect();
        let mut sides: Vec<(u32, u32, u32)> = Vec::new();
        for e in &c.edges {
            if !e.alive() {
                continue;
            }
            let [a, b] = e.ends;
            edge_sides(c, a, b, &mut sides);
            if sides.len() < 2 {
                continue;
            }
            if !seam_streams.iter().any(|w| splits(w, &sides)) {
                continue;
            }
            let (pa, pb) = (c.pos[a as usize], c.pos[b as usize]);
            let len2 = pa.distance_squared(pb);
            for &(f, _, _) in &sides {
                let fs = c.faces[f as usize];
                let (s, n) = (fs.start as usize, fs.len as usize);
                let (n2, _) = newell(c.slot_vertex[s..s + n].iter().map(|&v| c.pos[v as usize]));
                let l = n2.length();
                if l.is_nan() || l <= 0.0 {
                    continue;
                }
                if let Some(q) = tangent_plane(pa, pb, n2 / l) {
                    let q = q.scaled(weight * len2);
                    let q = Quadric { weight: 0.0, ..q };
                    out[a as usize] += q;
                    out[b as usize] += q;
                }
            }
        }
        out
    }
}

/// The faces that use `a`–`b` as a side, as (face, corner at `a`, corner at
/// `b`), into `out` (cleared first).
fn edge_sides(c: &Complex, a: u32, b: u32, out: &mut Vec<(u32, u32, u32)>) {
    out.clear();
    for &f in &c.vert_faces[a as usize] {
        let fs = c.faces[f as usize];
        let (s, n) = (fs.start as usize, fs.len as usize);
        for k in 0..n {
            if c.slot_vertex[s + k] != a {
                continue;
            }
            let next = if k + 1 == n { 0 } else { k + 1 };
            let prev = if k == 0 { n - 1 } else { k - 1 };
            for other in [next, prev] {
                if c.slot_vertex[s + other] == b {
                    out.push((f, c.corner(s + k), c.corner(s + other)));
                }
            }
        }
    }
}

/// Whether the faces on an edge (`sides`, see [`edge_sides`]) disagree on
/// a wedge at either end: the edge is on a seam of `w`.
fn splits(w: &Wedges, sides: &[(u32, u32, u32)]) -> bool {
    let cw = &w.corner_wedge;
    let Some(first) = sides.first() else {
        return false;
    };
    let (fa, fb) = (cw[first.1 as usize], cw[first.2 as usize]);
    sides[1..]
        .iter()
        .any(|x| cw[x.1 as usize] != fa || cw[x.2 as usize] != fb)
}

/// The share of the complex's edges between two or more faces that lie on
/// a seam of `w`.
fn seam_share(c: &Complex, w: &Wedges) -> f64 {
    let (mut seams, mut inner) = (0usize, 0usize);
    let mut sides = Vec::new();
    for e in c.edges.iter().filter(|e| e.alive()) {
        edge_sides(c, e.ends[0], e.ends[1], &mut sides);
        if sides.len() >= 2 {
            inner += 1;
            seams += usize::from(splits(w, &sides));
        }
    }
    if inner == 0 {
        0.0
    } else {
        seams as f64 / inner as f64
    }
}

/// The finishing of a fitted value: clamped to the stream's input range
/// per component (colors stay in [0, 1], UVs in the used part of the
/// texture); directions normalized.
fn finish(st: &StreamState, v: &mut [f64]) {
    for (x, y) in v.iter_mut().enumerate() {
        *y = y.clamp(st.lo[x] as f64, st.hi[x] as f64);
    }
    if st.kind == StreamKind::Direction {
        let n = v.len().min(3);
        let len = v[..n].iter().map(|x| x * x).sum::<f64>().sqrt();
        if len > 0.0 {
            for y in v[..n].iter_mut() {
                *y /= len;
            }
        }
    }
}

/// Mean length of the complex's physical edges (normalized coordinates);
/// 1 when it has none.
fn mean_edge_length(c: &Complex) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for e in c.edges.iter().filter(|e| e.alive() && !e.is_virtual()) {
        sum += c.pos[e.ends[0] as usize].distance(c.pos[e.ends[1] as usize]);
        n += 1;
    }
    if n > 0 && sum > 0.0 {
        sum / n as f64
    } else {
        1.0
    }
}

/// The start of every face's corners in input order (`offsets` rebuilt
/// from the complex's slot ranges, which are the input's at the start).
fn face_offsets(c: &Complex, corners: usize) -> Vec<u32> {
    let mut o: Vec<u32> = c.faces.iter().map(|f| f.start).collect();
    o.push(corners as u32);
    o
}

/// The delta of corner `x` in morph stream `src` (zero without one).
fn morph_value(src: &MorphStream<'_>, x: u32) -> [f32; 3] {
    match src.indices.get(x as usize) {
        Some(&i) if i != ABSENT => {
            let at = i as usize * 3;
            [src.values[at], src.values[at + 1], src.values[at + 2]]
        }
        _ => [0.0; 3],
    }
}

/// The morph sums, one per welded vertex (filled by the face loop), after
/// checking every stream against the corners; `None` without morphs.
fn morph_state(
    morphs: &[MorphStream<'_>],
    corners: usize,
    c: &Complex,
) -> Result<Option<MorphState>, Error> {
    if morphs.is_empty() {
        return Ok(None);
    }
    let mut lo = Vec::with_capacity(morphs.len());
    let mut hi = Vec::with_capacity(morphs.len());
    for (k, m) in morphs.iter().enumerate() {
        let problem = if m.values.len() % 3 != 0 {
            Some(format!(
                "{} morph values, not three per delta",
                m.values.len()
            ))
        } else if m.indices.len() != corners {
            Some(format!(
                "{} morph indices for {corners} corners",
                m.indices.len()
            ))
        } else if m
            .indices
            .iter()
            .any(|&i| i != ABSENT && i as usize >= m.values.len() / 3)
        {
            Some("a morph index is out of range".into())
        } else if m.values.iter().any(|x| !x.is_finite()) {
            Some("a morph delta is not finite".into())
        } else {
            None
        };
        if let Some(problem) = problem {
            return Err(Error::BadAttribute {
                stream: usize::MAX - 1 - k,
                problem,
            });
        }
        // Zero is in range: a vertex no delta reached gets zero.
        let (mut l, mut h) = ([0.0f32; 3], [0.0f32; 3]);
        for d in m.values.chunks_exact(3) {
            for x in 0..3 {
                l[x] = l[x].min(d[x]);
                h[x] = h[x].max(d[x]);
            }
        }
        lo.push(l);
        hi.push(h);
    }
    Ok(Some(MorphState {
        sums: vec![MorphSums::default(); c.pos.len()],
        lo,
        hi,
    }))
}

/// One live face as the face loop hands it to the per-vertex terms: its
/// plane frame, its corners' positions, input corners and vertices, and
/// its area share per corner; `weight` the vertex importance.
struct FaceShare<'f> {
    frame: &'f FaceFrame,
    pos: &'f [DVec3],
    corners: &'f [u32],
    verts: &'f [u32],
    share: f64,
    weight: &'f [f64],
}

impl FaceShare<'_> {
    /// The area share of vertex `v` (times its importance).
    fn area(&self, v: u32) -> f64 {
        self.share * self.weight.get(v as usize).copied().unwrap_or(1.0)
    }
}

/// Adds one face to the morph sums of its corners' vertices: its area to
/// every one, and the functional of every delta set nonzero on one of its
/// corners.
fn add_morph_face(ms: &mut MorphState, morphs: &[MorphStream<'_>], face: &FaceShare<'_>) {
    let FaceShare {
        frame,
        pos,
        corners,
        verts,
        ..
    } = *face;
    // Each set's functional, unweighted.
    let mut fits: SmallVec<[MorphTerm; 2]> = SmallVec::new();
    for (k, src) in morphs.iter().enumerate() {
        let values: SmallVec<[[f32; 3]; 8]> =
            corners.iter().map(|&x| morph_value(src, x)).collect();
        if values.iter().all(|d| *d == [0.0; 3]) {
            continue;
        }
        let mut grad = [DVec3::ZERO; 3];
        let mut offset = [0.0; 3];
        for c in 0..3 {
            (grad[c], offset[c]) = frame.fit(pos, values.iter().map(|d| f64::from(d[c])));
        }
        fits.push(MorphTerm {
            set: k as u32,
            grad,
            offset,
        });
    }
    for (&v, &x) in verts.iter().zip(corners) {
        let a = face.area(v);
        let sums = &mut ms.sums[v as usize];
        sums.alpha += a;
        if sums.first_corner == u32::MAX {
            sums.first_corner = x;
        }
        for t in &fits {
            sums.add(t.set, a, t.grad, t.offset);
        }
    }
}

/// The skin quadrics, one per welded vertex (filled by the face loop).
fn skin_state(
    skin: &SkinStream<'_>,
    corners: usize,
    c: &Complex,
    _weight: &[f64],
) -> Result<SkinState, Error> {
    let k = skin.influences;
    if k == 0 || skin.joints.len() != skin.weights.len() || skin.weights.len() % k != 0 {
        return Err(Error::BadAttribute {
            stream: usize::MAX,
            problem: format!(
                "skin with {k} influences, {} joints and {} weights",
                skin.joints.len(),
                skin.weights.len()
            ),
        });
    }
    if skin.indices.len() != corners {
        return Err(Error::BadAttribute {
            stream: usize::MAX,
            problem: format!("{} skin indices for {corners} corners", skin.indices.len()),
        });
    }
    let entries = skin.weights.len() / k;
    if skin
        .indices
        .iter()
        .any(|&i| i != ABSENT && i as usize >= entries)
        || skin.weights.iter().any(|w| !w.is_finite() || *w < 0.0)
    {
        return Err(Error::BadAttribute {
            stream: usize::MAX,
            problem: "a skin index or weight is out of range".into(),
        });
    }
    Ok(SkinState {
        scale: skin.weight * skin.weight,
        influences: k,
        quadrics: vec![SkinQuadric::default(); c.pos.len()],
    })
}

/// Adds one face's joint functionals to the skin quadrics of its corners'
/// vertices.
fn add_skin_face(sk: &mut SkinState, src: &SkinStream<'_>, face: &FaceShare<'_>) {
    let FaceShare {
        frame,
        pos,
        corners,
        verts,
        ..
    } = *face;
    let k = src.influences;
    if corners.iter().any(|&x| src.indices[x as usize] == ABSENT) {
        return;
    }
    let mut joints: SmallVec<[u16; 16]> = SmallVec::new();
    for &x in corners {
        let e = src.indices[x as usize] as usize;
        for s in e * k..e * k + k {
            if src.weights[s] > 0.0 && !joints.contains(&src.joints[s]) {
                joints.push(src.joints[s]);
            }
        }
    }
    joints.sort_unstable();
    let weight_of = |x: u32, j: u16| -> f64 {
        let e = src.indices[x as usize] as usize;
        (e * k..e * k + k)
            .filter(|&s| src.joints[s] == j)
            .map(|s| src.weights[s] as f64)
            .sum()
    };
    let fits: SmallVec<[(u16, DVec3, f64); 16]> = joints
        .iter()
        .map(|&j| {
            let (g, d) = frame.fit(pos, corners.iter().map(|&x| weight_of(x, j)));
            (j, g, d)
        })
        .collect();
    for &v in verts {
        let a = face.area(v);
        let q = &mut sk.quadrics[v as usize];
        q.alpha += a;
        for &(j, g, d) in &fits {
            q.add_joint(j, a, g, d);
        }
    }
}
