//! The attribute state of one chunk of the parallel first phase (see
//! [`crate::Partition`]): the wedges of the chunk's corners and the skin
//! quadrics of its vertices under local ids, its wedges' quadrics as a
//! range of the run's (which the phase rearranges so that every chunk's
//! wedges follow one another), and the way back.
//!
//! A wedge belongs to one vertex, and a chunk collapses only vertices whose
//! whole star is inside it, onto vertices whose whole star is inside it or
//! that stay put; so the wedges a chunk changes are in no other chunk, and
//! the ones it shares with others (at the vertices on its cuts) it only
//! reads. Putting the chunks back one after another gives the state one
//! run making the same collapses would have.

use std::collections::HashMap;

use super::state::{AttributeState, MorphState, SkinState, StreamState, WedgeValues};
use super::wedges::Wedges;
use crate::input::ABSENT;

/// A chunk's wedges, from [`AttributeState::chunk_wedges`]: per stream,
/// its corners' wedges under local ids and the run's id of each local
/// wedge; the material groups' wedges under local ids.
pub(crate) struct ChunkWedges {
    streams: Vec<(Wedges, Vec<u32>)>,
    groups: Option<Wedges>,
}

impl ChunkWedges {
    /// The run's id of each of the chunk's wedges of fitted stream `k`, in
    /// local order: the chunk's range of the rearranged quadrics.
    pub(crate) fn global(&self, k: usize) -> &[u32] {
        &self.streams[k].1
    }
}

impl<'a> AttributeState<'a> {
    /// Streams whose wedge quadrics the phase rearranges.
    pub(crate) fn fitted_streams(&self) -> usize {
        self.streams.len()
    }

    /// Floats per wedge of fitted stream `k`.
    pub(crate) fn stride(&self, k: usize) -> usize {
        self.streams[k].layout.stride()
    }

    /// Wedges of fitted stream `k`.
    pub(crate) fn wedge_count(&self, k: usize) -> usize {
        self.streams[k].wedges.count()
    }

    /// Takes fitted stream `k`'s wedge quadrics out, for the phase to
    /// rearrange them into the chunks' ranges; [`AttributeState::restore_values`]
    /// puts them back. Only a run's own state has them to give.
    pub(crate) fn take_values(&mut self, k: usize) -> Vec<f64> {
        match std::mem::replace(
            &mut self.streams[k].quadrics,
            WedgeValues::Owned(Vec::new()),
        ) {
            WedgeValues::Owned(v) => v,
            // A chunk's state is never cut again; were it, a copy.
            WedgeValues::Borrowed(s) => s.to_vec(),
        }
    }

    /// Gives fitted stream `k` its wedge quadrics back (see
    /// [`AttributeState::take_values`]).
    pub(crate) fn restore_values(&mut self, k: usize, values: Vec<f64>) {
        self.streams[k].quadrics = WedgeValues::Owned(values);
    }

    /// The wedges of a chunk whose local corner `k` is the run's corner
    /// `corners[k]`.
    pub(crate) fn chunk_wedges(&self, corners: &[u32]) -> ChunkWedges {
        ChunkWedges {
            streams: self
                .streams
                .iter()
                .map(|st| local_wedges(&st.wedges, corners))
                .collect(),
            // No collapse merges material wedges: read only.
            groups: self.groups.as_ref().map(|g| local_wedges(g, corners).0),
        }
    }

    /// The state of a chunk with `wedges` (from
    /// [`AttributeState::chunk_wedges`]), whose local vertex `v` is the
    /// run's vertex `vertices[v]`, and whose wedges' quadrics are `values`
    /// (one range per fitted stream, in the order of
    /// [`ChunkWedges::global`]). Returns the run's wedge ids, for
    /// [`AttributeState::put_back`].
    pub(crate) fn chunk<'b>(
        &self,
        wedges: ChunkWedges,
        values: Vec<&'b mut [f64]>,
        vertices: &[u32],
    ) -> (AttributeState<'b>, Vec<Vec<u32>>) {
        let mut ids = Vec::with_capacity(self.streams.len());
        let streams = self
            .streams
            .iter()
            .zip(wedges.streams)
            .zip(values)
            .map(|((st, (local, global)), values)| {
                debug_assert_eq!(values.len(), global.len() * st.layout.stride());
                let merged = global.iter().map(|&g| st.merged[g as usize]).collect();
                ids.push(global);
                StreamState {
                    input: st.input,
                    layout: st.layout,
                    scale: st.scale,
                    seams: st.seams,
                    kind: st.kind,
                    wedges: local,
                    quadrics: WedgeValues::Borrowed(values),
                    merged,
                    lo: st.lo,
                    hi: st.hi,
                }
            })
            .collect();
        let state = AttributeState {
            streams,
            groups: wedges.groups,
            skin: self.skin.as_ref().map(|sk| SkinState {
                scale: sk.scale,
                influences: sk.influences,
                quadrics: vertices
                    .iter()
                    .map(|&v| sk.quadrics[v as usize].clone())
                    .collect(),
            }),
            morph: self.morph.as_ref().map(|ms| MorphState {
                sums: vertices
                    .iter()
                    .map(|&v| ms.sums[v as usize].clone())
                    .collect(),
                lo: ms.lo.clone(),
                hi: ms.hi.clone(),
            }),
            carried: self.carried.clone(),
            stream_count: self.stream_count,
            strict: self.strict,
            has_seams: self.has_seams,
        };
        (state, ids)
    }

    /// Puts back what a chunk's collapses made of its state (see
    /// [`AttributeState::chunk`], with the same `corners` and `vertices`):
    /// its wedges' merges, its corners' wedges, its vertices' skin
    /// quadrics. Its wedges' quadrics are already in the run's (rearranged)
    /// arrays.
    pub(crate) fn put_back(
        &mut self,
        chunk: AttributeState<'_>,
        ids: &[Vec<u32>],
        corners: &[u32],
        vertices: &[u32],
    ) {
        for ((st, local), global) in self.streams.iter_mut().zip(chunk.streams).zip(ids) {
            for (l, &g) in global.iter().enumerate() {
                st.merged[g as usize] = local.merged[l];
            }
            for (&c, &l) in corners.iter().zip(&local.wedges.corner_wedge) {
                st.wedges.corner_wedge[c as usize] = if l == ABSENT {
                    ABSENT
                } else {
                    global[l as usize]
                };
            }
        }
        if let (Some(sk), Some(local)) = (&mut self.skin, chunk.skin) {
            for (q, &v) in local.quadrics.into_iter().zip(vertices) {
                sk.quadrics[v as usize] = q;
            }
        }
        if let (Some(ms), Some(local)) = (&mut self.morph, chunk.morph) {
            for (q, &v) in local.sums.into_iter().zip(vertices) {
                ms.sums[v as usize] = q;
            }
        }
    }
}

/// The wedges of `corners` (the run's corner of each local corner) under
/// local ids, numbered in order of first use, and the run's id of each.
/// A local wedge's first corner is a local corner (only the run's are read
/// for output).
fn local_wedges(w: &Wedges, corners: &[u32]) -> (Wedges, Vec<u32>) {
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut global = Vec::new();
    let mut first_corner = Vec::new();
    let mut corner_wedge = Vec::with_capacity(corners.len());
    for (k, &c) in corners.iter().enumerate() {
        let g = w.corner_wedge[c as usize];
        if g == ABSENT {
            corner_wedge.push(ABSENT);
            continue;
        }
        let id = *local.entry(g).or_insert_with(|| {
            global.push(g);
            first_corner.push(k as u32);
            (global.len() - 1) as u32
        });
        corner_wedge.push(id);
    }
    (
        Wedges {
            corner_wedge,
            first_corner,
        },
        global,
    )
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::morph::MorphSums;
    use super::*;
    use crate::input::{AttributeInput, MorphStream, SeamPolicy};
    use crate::prepare::complex::Complex;

    #[test]
    fn a_chunk_hands_back_the_morph_sums_its_collapses_made() {
        // Two triangles sharing an edge; one morph delta per vertex.
        let pos = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let indices = [0u32, 1, 2, 0, 2, 3];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &indices);
        let values = [
            0.0f32, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 3.0, 0.0, 0.0, 4.0,
        ];
        let input = AttributeInput {
            morphs: vec![MorphStream {
                values: &values,
                indices: &indices,
            }],
            ..AttributeInput::default()
        };
        let corner_vertex = indices.to_vec();
        let mut state = AttributeState::new(
            &input,
            &corner_vertex,
            &c,
            &[1.0; 4],
            SeamPolicy::Penalize,
            1.0,
        )
        .expect("valid input");
        let before = state.morph.as_ref().expect("morphs").sums.clone();
        // A chunk of the second triangle's vertices (run ids 0, 2, 3),
        // whose collapse merges its local vertex 2 (run 3) into 1 (run 2).
        let vertices = [0u32, 2, 3];
        let corners = [3u32, 4, 5];
        let wedges = state.chunk_wedges(&corners);
        let (mut chunk, ids) = state.chunk(wedges, Vec::new(), &vertices);
        {
            let ms = chunk.morph.as_mut().expect("morphs in the chunk");
            assert_eq!(ms.sums[1], before[2]);
            let other = std::mem::take(&mut ms.sums[2]);
            ms.sums[1].merge(&other);
        }
        state.put_back(chunk, &ids, &corners, &vertices);
        let after = &state.morph.as_ref().expect("morphs").sums;
        let mut want = before[2].clone();
        want.merge(&before[3]);
        assert_eq!(after[2], want);
        assert_eq!(after[3], MorphSums::default());
        // Vertices outside the chunk are untouched.
        assert_eq!(after[1], before[1]);
    }
}
