//! Errors: input the simplifier refuses, naming the element.

/// Why a simplification could not start. Running out of collapses is not an
/// error: the report says how far the run got.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// The face offsets are not `[0, …, indices.len()]` increasing.
    #[error("face offsets are malformed")]
    MalformedFaces,
    /// A triangle index list whose length is not a multiple of 3.
    #[error("{0} triangle indices is not a multiple of 3")]
    IndexCount(usize),
    /// A face with fewer than three corners.
    #[error("face {face} has fewer than 3 corners")]
    FaceTooSmall {
        /// Face index.
        face: usize,
    },
    /// A corner refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but there are {vertices} vertices")]
    IndexOutOfRange {
        /// Face index.
        face: usize,
        /// The bad index.
        index: u32,
        /// Vertex count.
        vertices: usize,
    },
    /// A face uses a position with a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinitePosition {
        /// Vertex index.
        vertex: usize,
    },
    /// An option out of its range.
    #[error("option {name} = {value} is out of range")]
    BadOption {
        /// Option name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// Vertex weights given, but not one per vertex.
    #[error("{weights} vertex weights for {vertices} vertices")]
    WeightCount {
        /// Weights given.
        weights: usize,
        /// Vertices.
        vertices: usize,
    },
    /// See-through flags given, but not one per input face.
    #[error("{flags} see-through flags for {faces} faces")]
    SeeThroughCount {
        /// Flags given.
        flags: usize,
        /// Input faces.
        faces: usize,
    },
    /// Instance counts given, but not one per input face.
    #[error("{counts} instance counts for {faces} faces")]
    InstanceCount {
        /// Counts given.
        counts: usize,
        /// Input faces.
        faces: usize,
    },
    /// A negative or non-finite vertex weight.
    #[error("vertex {vertex} has weight {weight}; weights must be finite and non-negative")]
    BadWeight {
        /// Vertex index.
        vertex: usize,
        /// The weight.
        weight: f32,
    },
    /// An attribute stream (or the skin, `stream == usize::MAX`) does not
    /// fit the faces it was given with.
    #[error("attribute stream {stream}: {problem}")]
    BadAttribute {
        /// Index of the stream in [`crate::AttributeInput::streams`].
        stream: usize,
        /// What is wrong.
        problem: String,
    },
    /// The mesh handed to [`crate::simplify_mesh`] is invalid.
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
}
