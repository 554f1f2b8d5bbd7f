//! Whether a level of detail that kept its input's UVs can still show the
//! input's textures: the share of its textured surface whose UV triangles
//! fold over or stretch far from the input's texel density.
//!
//! Keeping UVs (Hoppe 1999's attribute quadrics with seams kept) works
//! while the collapses can stay inside UV charts. Past that, a collapse
//! across a seam gives one corner a UV between two charts, and the faces
//! around it show whatever texture lies between the islands (a smear, a
//! black wedge); a collapse that flattens a chart's fold turns a UV
//! triangle over (the texture mirrored). Re-baking (W §4.3) has neither
//! problem, at the price of a new atlas. This measure is what decides
//! between the two (`--textures auto`): it is read off the output, per
//! face, against the input face it came from, so it needs no rendering.

use glam::{DVec2, DVec3};
use wildlod_mesh::{Faces, Mesh, Semantic, ABSENT};

/// An output face whose UV area per surface area differs from its input
/// face's by more than this factor either way is stretched: its texels are
/// 2× larger or smaller along a side than the artist laid them out, far
/// beyond the variation within a chart (a UV unwrap keeps texel density
/// within about 1.5× inside an island), and what a face spanning two
/// charts shows (the gap between islands: its UV area grows by the area
/// between them).
const STRETCH: f64 = 4.0;

/// Signed area of a polygon's UVs (fan from its first corner), positive
/// when counter-clockwise in UV space.
fn uv_area(uv: &[DVec2]) -> f64 {
    let mut twice = 0.0;
    for k in 1..uv.len().saturating_sub(1) {
        let (a, b) = (uv[k] - uv[0], uv[k + 1] - uv[0]);
        twice += a.perp_dot(b);
    }
    0.5 * twice
}

/// Area of a polygon (its Newell normal's half length).
fn surface_area(p: &[DVec3]) -> f64 {
    let mut n = DVec3::ZERO;
    for k in 0..p.len() {
        n += p[k].cross(p[(k + 1) % p.len()]);
    }
    0.5 * n.length()
}

/// One face's UVs and positions, or `None` when a corner has no UV.
fn face_uv(
    mesh_positions: &[[f32; 3]],
    faces: &Faces,
    uv: &wildlod_mesh::Attribute,
    f: usize,
) -> Option<(Vec<DVec2>, Vec<DVec3>)> {
    let (start, end) = (faces.offsets[f] as usize, faces.offsets[f + 1] as usize);
    let mut uvs = Vec::with_capacity(end - start);
    let mut ps = Vec::with_capacity(end - start);
    for corner in start..end {
        let i = uv.indices[corner];
        if i == ABSENT {
            return None;
        }
        let v = uv.value(i);
        uvs.push(DVec2::new(v[0] as f64, v[1] as f64));
        ps.push(DVec3::from(
            mesh_positions[faces.indices[corner] as usize].map(f64::from),
        ));
    }
    Some((uvs, ps))
}

/// The share (0 to 1) of `output`'s surface, over the faces `textured`
/// marks (per input face; `None`: every face), whose UVs in attribute
/// `k` (a UV set) fold over or stretch beyond [`STRETCH`] relative to the
/// input face each came from (`face_origin`). `None` when no textured face
/// has UV area in the input (nothing to show).
pub(crate) fn uv_damage(
    input: &Mesh,
    output: &Mesh,
    face_origin: &[u32],
    k: usize,
    textured: Option<&[bool]>,
) -> Option<f64> {
    let (uv_in, uv_out) = (&input.attributes[k], &output.attributes[k]);
    if !matches!(uv_in.semantic, Semantic::TexCoord(_)) || uv_in.components < 2 {
        return None;
    }
    let (mut damaged, mut total) = (0.0f64, 0.0f64);
    for (f, &origin) in face_origin.iter().enumerate() {
        let origin = origin as usize;
        if textured.is_some_and(|t| !t.get(origin).copied().unwrap_or(false)) {
            continue;
        }
        let Some((uvs_in, ps_in)) = face_uv(&input.positions, &input.faces, uv_in, origin) else {
            continue;
        };
        let (a_in, s_in) = (uv_area(&uvs_in), surface_area(&ps_in));
        // An input face without UV area (or surface) shows no texture
        // layout to keep.
        if !(a_in.abs() > 0.0 && s_in > 0.0) {
            continue;
        }
        let Some((uvs_out, ps_out)) = face_uv(&output.positions, &output.faces, uv_out, f) else {
            continue;
        };
        let (a_out, s_out) = (uv_area(&uvs_out), surface_area(&ps_out));
        if s_out.is_nan() || s_out <= 0.0 {
            continue;
        }
        total += s_out;
        let folded = a_out * a_in <= 0.0;
        let density = (a_out.abs() / s_out) / (a_in.abs() / s_in);
        // NaN is outside the range too.
        let stretched = !(1.0 / STRETCH..=STRETCH).contains(&density);
        if folded || stretched {
            damaged += s_out;
        }
    }
    (total > 0.0).then(|| damaged / total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::{Attribute, ComponentFormat};

    /// A unit square of two triangles with UVs `uv` per corner (corners of
    /// faces (0,1,2) and (0,2,3)).
    fn square(uv: [[f32; 2]; 4]) -> Mesh {
        let mut m = Mesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            faces: Faces::from_triangles(&[0, 1, 2, 0, 2, 3]),
            ..Mesh::default()
        };
        m.face_parts = vec![0, 0];
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: uv.iter().flatten().copied().collect(),
            indices: vec![0, 1, 2, 0, 2, 3],
            format: ComponentFormat::F32,
        });
        m
    }

    #[test]
    fn the_same_layout_is_undamaged() {
        let m = square([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(uv_damage(&m, &m, &[0, 1], 0, None), Some(0.0));
    }

    #[test]
    fn a_folded_triangle_is_damaged_by_its_share_of_the_area() {
        let input = square([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        // Corner 3's UV moved across the diagonal: face (0,2,3) turns over.
        let out = square([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.9, 0.1]]);
        assert_eq!(uv_damage(&input, &out, &[0, 1], 0, None), Some(0.5));
        // Only textured faces count: the first face alone is whole.
        assert_eq!(
            uv_damage(&input, &out, &[0, 1], 0, Some(&[true, false])),
            Some(0.0)
        );
    }

    #[test]
    fn stretch_beyond_four_times_the_density_is_damage_and_within_is_not() {
        let input = square([[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1]]);
        // UV area ×4 exactly: within the bound.
        let four = square([[0.0, 0.0], [0.2, 0.0], [0.2, 0.2], [0.0, 0.2]]);
        assert_eq!(uv_damage(&input, &four, &[0, 1], 0, None), Some(0.0));
        // ×9: a face spanning the gap between two islands.
        let nine = square([[0.0, 0.0], [0.3, 0.0], [0.3, 0.3], [0.0, 0.3]]);
        assert_eq!(uv_damage(&input, &nine, &[0, 1], 0, None), Some(1.0));
        // Collapsed to a line in UV: a streak.
        let line = square([[0.0, 0.0], [0.1, 0.0], [0.1, 0.0], [0.0, 0.0]]);
        assert_eq!(uv_damage(&input, &line, &[0, 1], 0, None), Some(1.0));
    }

    #[test]
    fn faces_without_uv_area_in_the_input_do_not_count() {
        let flat = square([[0.5, 0.5]; 4]);
        assert_eq!(uv_damage(&flat, &flat, &[0, 1], 0, None), None);
    }
}
