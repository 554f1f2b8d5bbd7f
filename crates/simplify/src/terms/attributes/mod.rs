//! Attributes through every collapse (Hoppe 1999; Knodt 2024 §3, Eq. 6–7):
//! UVs, normals, colors, morph deltas and skin weights are fitted, not
//! copied. Each stream's corners are grouped into wedges (`wedges.rs`);
//! every face adds its attributes' linear functionals to the quadrics of
//! its wedges (`linear_fit.rs`, `quadric.rs`); a collapse adds the
//! attribute error to its position quadric, so the optimal position
//! accounts for it, and merges the wedges it joins under the seam rules of
//! `seams.rs`; at the end each wedge takes the value its quadric fits at
//! its vertex's final position. Skin weights are sparse per-vertex
//! quadrics (`skin.rs`), morph deltas sparse per-vertex functional sums
//! (`morph.rs`). `state.rs` holds a run's state and the hooks the
//! collapse loop calls; `chunk.rs` cuts it for the chunks of the parallel
//! first phase and puts their results back.

mod chunk;
mod linear_fit;
mod morph;
mod quadric;
mod seams;
mod skin;
mod state;
mod wedges;

pub(crate) use chunk::ChunkWedges;
pub(crate) use state::{AttrScratch, AttributeState};
