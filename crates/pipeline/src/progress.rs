//! Progress of one mesh's simplification, shown however the caller likes.

/// Receives the progress of one mesh: fractions done, then `finish`.
pub trait MeshProgress {
    /// The fraction of the work done, 0 to 1.
    fn set(&self, fraction: f64);
    /// The mesh is done.
    fn finish(&self);
}

/// Shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl MeshProgress for NoProgress {
    fn set(&self, _fraction: f64) {}
    fn finish(&self) {}
}
