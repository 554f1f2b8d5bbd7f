//! Geometric primitives for wildlod, in `f64`:
//!
//! - [`Aabb`]: axis-aligned boxes;
//! - [`closest_point_on_triangle`], [`segment_segment_closest`]: exact
//!   closest points, robust for degenerate input;
//! - [`triangle_triangle_distance`]: the exact triangle–triangle distance
//!   that W §4.1.1 uses to find virtual edges between touching components;
//! - [`Bvh`]: a flat bounding volume hierarchy with nearest-primitive and
//!   pairs-within-a-margin queries;
//! - [`TriangleSet`]: the closest point on a whole triangle set;
//! - [`ray_triangle`] and [`Bvh::any_hit`]: ray casts, for visibility.
//!
//! ```
//! use glam::DVec3;
//! use wildlod_geometry::{triangle_triangle_distance, TriangleSet};
//!
//! // A unit square in the plane z = 0, as two triangles.
//! let positions = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
//! let set = TriangleSet::new(&positions, &[[0, 1, 2], [0, 2, 3]]);
//! let hit = set.closest(DVec3::new(0.25, 0.75, 2.0)).unwrap();
//! assert_eq!(hit.triangle, 1);
//! assert!((hit.point - DVec3::new(0.25, 0.75, 0.0)).length() < 1e-15);
//! assert!((hit.distance2 - 4.0).abs() < 1e-12);
//!
//! // The same square's first triangle lifted by 0.5 is 0.5 away from it.
//! let t = [positions[0], positions[1], positions[2]];
//! let lifted = t.map(|p| p + DVec3::Z * 0.5);
//! assert!((triangle_triangle_distance(&t, &lifted) - 0.5).abs() < 1e-15);
//! ```
//!
//! W = Liu, Zhang, Yuksel 2025, *Simplifying Textured Triangle Meshes in the
//! Wild*.

mod aabb;
mod bvh;
mod closest;
mod ray;
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
pub use ray::ray_triangle;
pub use triangle_distance::{
    triangle_triangle_closest, triangle_triangle_distance, triangles_intersect, ClosestPair,
};
pub use triangle_set::{Hit, TriangleSet};
