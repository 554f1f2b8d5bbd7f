//! Geometric primitives for wildlod, in `f64`:
//!
//! - [`Aabb`]: axis-aligned boxes;
//! - [`closest_point_on_triangle`], [`segment_segment_closest`]: exact
//!   closest points, robust for degenerate input;
//! - [`triangle_triangle_distance`]: the exact triangle–triangle distance
//!   that W §4.1.1 uses to find virtual edges between touching components;
//! - [`Bvh`]: a flat bounding volume hierarchy with nearest-primitive and
//!   pairs-within-a-margin queries;
//! - [`TriangleSet`]: the closest point on a whole triangle set.
//!
//! W = Liu, Zhang, Yuksel 2025, *Simplifying Textured Triangle Meshes in the
//! Wild*.

mod aabb;
mod bvh;
mod closest;
#[cfg(test)]
mod testing;
mod triangle_distance;
mod triangle_set;

pub use aabb::Aabb;
pub use bvh::Bvh;
pub use closest::{
    closest_point_on_segment, closest_point_on_triangle, point_triangle_distance2,
    segment_segment_closest,
};
pub use triangle_distance::{
    triangle_triangle_closest, triangle_triangle_distance, triangles_intersect, ClosestPair,
};
pub use triangle_set::{Hit, TriangleSet};
