//! Axis-aligned bounding boxes in `f64`.

use glam::DVec3;

/// An axis-aligned box `[min, max]`.
///
/// The empty box has `min = +∞` and `max = −∞` on every axis, so that
/// growing it by any point gives that point's box, and distances to it are
/// `+∞`. Coordinates that are NaN are skipped when growing, so a stray NaN
/// vertex cannot poison the bounds of its neighbours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::empty()
    }
}

/// `a.min(b)` per axis that keeps `a` when `b` is NaN.
#[inline]
fn min_skip_nan(a: DVec3, b: DVec3) -> DVec3 {
    // glam's `min` is `if self < rhs { self } else { rhs }`: with `b` as
    // `self`, a NaN in `b` compares false and `a` is kept.
    b.min(a)
}

/// `a.max(b)` per axis that keeps `a` when `b` is NaN.
#[inline]
fn max_skip_nan(a: DVec3, b: DVec3) -> DVec3 {
    b.max(a)
}

impl Aabb {
    /// The empty box: contains nothing, `+∞` away from everything.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The empty box (see [`Aabb::EMPTY`]).
    #[inline]
    pub const fn empty() -> Self {
        Self::EMPTY
    }

    /// The box with the given corners (not reordered).
    #[inline]
    pub const fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }

    /// The box of one point (empty when the point is entirely NaN).
    #[inline]
    pub fn from_point(p: DVec3) -> Self {
        let mut b = Self::EMPTY;
        b.grow(p);
        b
    }

    /// The smallest box containing all `points` (empty for none).
    pub fn from_points<I: IntoIterator<Item = DVec3>>(points: I) -> Self {
        let mut b = Self::EMPTY;
        for p in points {
            b.grow(p);
        }
        b
    }

    /// The box of a triangle.
    #[inline]
    pub fn from_triangle(a: DVec3, b: DVec3, c: DVec3) -> Self {
        let mut bb = Self::from_point(a);
        bb.grow(b);
        bb.grow(c);
        bb
    }

    /// True when the box contains no point (some `min > max`, or NaN).
    #[inline]
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// Grows the box to contain `p`; NaN coordinates are ignored.
    #[inline]
    pub fn grow(&mut self, p: DVec3) {
        self.min = min_skip_nan(self.min, p);
        self.max = max_skip_nan(self.max, p);
    }

    /// The smallest box containing both boxes.
    #[inline]
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: min_skip_nan(self.min, other.min),
            max: max_skip_nan(self.max, other.max),
        }
    }

    /// The box grown by `margin` on every side (an empty box stays empty).
    #[inline]
    pub fn expand(&self, margin: f64) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        Aabb {
            min: self.min - DVec3::splat(margin),
            max: self.max + DVec3::splat(margin),
        }
    }

    /// Center of the box (NaN for the empty box).
    #[inline]
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths `max − min` (zero for the empty box).
    #[inline]
    pub fn extent(&self) -> DVec3 {
        if self.is_empty() {
            DVec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Length of the diagonal (0 for the empty box).
    #[inline]
    pub fn diagonal(&self) -> f64 {
        self.extent().length()
    }

    /// Half the surface area, the SAH's measure of how likely a random ray
    /// or query hits the box (0 for the empty box).
    #[inline]
    pub fn half_area(&self) -> f64 {
        let e = self.extent();
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// Index (0, 1, 2) of the longest axis; the first one on ties.
    #[inline]
    pub fn longest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// True when `p` lies in the closed box.
    #[inline]
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when the closed boxes share a point.
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.distance2(other) == 0.0
    }

    /// Squared distance from `p` to the closed box: 0 inside, `+∞` for the
    /// empty box.
    #[inline]
    pub fn distance2_to_point(&self, p: DVec3) -> f64 {
        // Per axis the gap is max(min − p, p − max, 0); on the empty box
        // `min − p` is +∞.
        let d = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        d.length_squared()
    }

    /// Squared distance between two closed boxes: 0 when they overlap or
    /// touch, `+∞` when either is empty.
    #[inline]
    pub fn distance2(&self, other: &Aabb) -> f64 {
        let d = (self.min - other.max)
            .max(other.min - self.max)
            .max(DVec3::ZERO);
        d.length_squared()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb::new(DVec3::from(min), DVec3::from(max))
    }

    #[test]
    fn empty_box_grows_to_the_first_point_and_is_infinitely_far() {
        let mut e = Aabb::empty();
        assert!(e.is_empty());
        assert_eq!(e.diagonal(), 0.0);
        assert_eq!(e.distance2_to_point(DVec3::ZERO), f64::INFINITY);
        assert_eq!(e.distance2(&b([0.0; 3], [1.0; 3])), f64::INFINITY);
        e.grow(DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(e, b([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]));
        assert!(!e.is_empty());
    }

    #[test]
    fn nan_coordinates_are_skipped_when_growing() {
        let mut e = Aabb::from_points([DVec3::ZERO, DVec3::ONE]);
        e.grow(DVec3::new(f64::NAN, 5.0, f64::NAN));
        assert_eq!(e, b([0.0; 3], [1.0, 5.0, 1.0]));
        assert!(Aabb::from_point(DVec3::NAN).is_empty());
    }

    #[test]
    fn point_distance_is_zero_inside_and_euclidean_to_a_corner() {
        let u = b([0.0; 3], [1.0; 3]);
        assert_eq!(u.distance2_to_point(DVec3::splat(0.5)), 0.0);
        assert_eq!(u.distance2_to_point(DVec3::new(0.5, 3.0, 0.5)), 4.0);
        // Corner (1, 1, 1) to (2, 3, 4): 1 + 4 + 9.
        assert_eq!(u.distance2_to_point(DVec3::new(2.0, 3.0, 4.0)), 14.0);
    }

    #[test]
    fn box_distance_is_zero_when_touching_and_gap_otherwise() {
        let u = b([0.0; 3], [1.0; 3]);
        assert_eq!(u.distance2(&b([1.0, 0.0, 0.0], [2.0, 1.0, 1.0])), 0.0);
        assert!(u.overlaps(&b([0.5; 3], [3.0; 3])));
        // Gaps 2 on x and 1 on y.
        assert_eq!(u.distance2(&b([3.0, -3.0, 0.0], [4.0, -1.0, 1.0])), 5.0);
        assert_eq!(
            u.distance2(&b([3.0, -3.0, 0.0], [4.0, -1.0, 1.0])),
            b([3.0, -3.0, 0.0], [4.0, -1.0, 1.0]).distance2(&u)
        );
    }

    #[test]
    fn union_expand_center_and_diagonal_of_unit_boxes() {
        let u = b([0.0; 3], [1.0; 3]).union(&b([2.0; 3], [3.0; 3]));
        assert_eq!(u, b([0.0; 3], [3.0; 3]));
        assert_eq!(u.center(), DVec3::splat(1.5));
        assert!((u.diagonal() - 27f64.sqrt()).abs() < 1e-15);
        assert_eq!(u.expand(0.5), b([-0.5; 3], [3.5; 3]));
        assert!(Aabb::empty().expand(1.0).is_empty());
        assert_eq!(u.union(&Aabb::empty()), u);
        assert_eq!(b([0.0; 3], [1.0, 2.0, 3.0]).half_area(), 2.0 + 6.0 + 3.0);
        assert_eq!(b([0.0; 3], [1.0, 3.0, 2.0]).longest_axis(), 1);
    }
}
