//! Face geometry on the complex: normals, planes, and whether a star is
//! flat (W §4.2 measures every face by its plane and area). Every step
//! after the complex is built reads faces through these.

use glam::DVec3;

use crate::prepare::complex::Complex;

/// Newell normal (length = twice the area) and centroid of a polygon given
/// by its corner positions: exact for planar polygons, a least-squares-like
/// average for warped ones.
pub(crate) fn newell(points: impl Iterator<Item = DVec3> + Clone) -> (DVec3, DVec3) {
    let mut n = DVec3::ZERO;
    let mut sum = DVec3::ZERO;
    let mut count = 0.0;
    let mut it = points.clone().peekable();
    let first = it.peek().copied().unwrap_or(DVec3::ZERO);
    let mut prev: Option<DVec3> = None;
    for p in points {
        if let Some(q) = prev {
            n += q.cross(p);
        }
        sum += p;
        count += 1.0;
        prev = Some(p);
    }
    if let Some(q) = prev {
        n += q.cross(first);
    }
    (n, if count > 0.0 { sum / count } else { sum })
}

/// Normal (length = twice the area) of a polygon from its corners: the
/// cross product for triangles, Newell's sum otherwise.
#[inline]
pub(crate) fn polygon_normal(p: &[DVec3]) -> DVec3 {
    match p.len() {
        3 => (p[1] - p[0]).cross(p[2] - p[0]),
        _ => newell(p.iter().copied()).0,
    }
}

/// Sine of the angle below which two unit face normals count as one plane
/// for the flat-border rule (`flat_stars.rs`; as a sine: a cosine cannot tell angles this small
/// from 0 in double precision): faces within 1e-9 radians, so what stays
/// in the plane stays there to about 1e-9 of the region's size.
pub(crate) const PLANAR_SIN: f64 = 1e-9;

/// Whether two unit normals lie within [`PLANAR_SIN`] of one line.
#[inline]
pub(crate) fn coplanar(a: DVec3, b: DVec3) -> bool {
    a.cross(b).length() <= PLANAR_SIN
}

/// Plane of face `f`: (unit normal, area, centroid), or `None` when it has no
/// area.
pub(crate) fn face_plane(c: &Complex, f: u32) -> Option<(DVec3, f64, DVec3)> {
    let face = c.face(f);
    let (n2, centroid) = newell(face.iter().map(|&v| c.pos[v as usize]));
    let len = n2.length();
    if !len.is_finite() || len <= 0.0 {
        return None;
    }
    Some((n2 / len, 0.5 * len, centroid))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coplanar_normals_are_within_a_nanoradian_either_way_round() {
        let z = DVec3::Z;
        let tilted = |a: f64| DVec3::new(a.sin(), 0.0, a.cos());
        assert!(coplanar(z, tilted(5e-10)));
        assert!(coplanar(z, -tilted(5e-10)));
        assert!(!coplanar(z, tilted(2e-9)));
        // The rounding of a unit normal (0.9999999999999999) is no angle.
        assert!(coplanar(z, DVec3::new(0.0, 0.0, 0.9999999999999999)));
    }

    #[test]
    fn newell_normal_of_unit_square_has_area_two() {
        let sq = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let (n, c) = newell(sq.iter().copied());
        assert_eq!(n, DVec3::new(0.0, 0.0, 2.0));
        assert_eq!(c, DVec3::new(0.5, 0.5, 0.0));
    }
}
