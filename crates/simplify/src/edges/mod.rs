//! Step 2 of the simplifier: the edges a collapse may take (W §4.1). The
//! physical edges are the complex's own (its star lists, built in
//! `prepare`); `virtual_edges.rs` adds the virtual ones W §4.1.1 joins
//! nearby parts with, so that separate components can merge.

pub(crate) mod virtual_edges;
