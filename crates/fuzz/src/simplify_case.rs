//! `simplify_mesh` on arbitrary small meshes with arbitrary options.

use arbitrary::{Arbitrary, Unstructured};
use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Part, Semantic, ABSENT};
use wildlod_simplify::{
    simplify_mesh, Error, Guards, Options, Partition, QuadMode, Report, StopReason, Target,
};

/// A mesh and options for one simplifier run, built by `arbitrary`.
///
/// Meshes are small (at most 48 vertices, 40 faces of 3 to 12 corners) so
/// that a run takes milliseconds; positions come either from a coarse grid
/// (coincident vertices, collinear and coplanar faces, zero areas: the
/// degenerate cases) or from arbitrary floats (huge, tiny and subnormal
/// coordinates). Faces may repeat vertices, duplicate each other and, now
/// and then, point past the last vertex, which must be refused.
#[derive(Clone, Debug)]
pub struct SimplifyCase {
    /// The input mesh.
    pub mesh: Mesh,
    /// The options.
    pub options: Options,
}

impl<'a> Arbitrary<'a> for SimplifyCase {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        let nv = u.int_in_range(0..=48usize)?;
        let grid = u.ratio(3u8, 4u8)?;
        let mut positions = Vec::with_capacity(nv);
        for _ in 0..nv {
            let p = if grid {
                [0; 3].map(|_| u.int_in_range(-2i8..=2).map(|c| f32::from(c) * 0.5))
            } else {
                [0; 3].map(|_| u.arbitrary::<f32>())
            };
            positions.push([p[0]?, p[1]?, p[2]?]);
        }
        let nf = if nv == 0 {
            0
        } else {
            u.int_in_range(0..=40usize)?
        };
        let mut faces = Faces::with_capacity(nf, 4 * nf);
        let mut corners = Vec::new();
        for _ in 0..nf {
            let arity = match u.int_in_range(0..=19u8)? {
                0..=11 => 3,
                12..=16 => 4,
                _ => u.int_in_range(5..=12usize)?,
            };
            corners.clear();
            for _ in 0..arity {
                let max = if u.ratio(1u8, 200u8)? { nv } else { nv - 1 };
                corners.push(u.int_in_range(0..=max)? as u32);
            }
            faces.push(&corners);
        }
        let mut mesh = Mesh::from_polygons(positions, faces);
        let parts = u.int_in_range(1..=3usize)?;
        mesh.parts = (0..parts)
            .map(|p| Part {
                name: format!("part{p}"),
                material: None,
            })
            .collect();
        for fp in &mut mesh.face_parts {
            *fp = u.int_in_range(0..=parts as u32 - 1)?;
        }
        if u.arbitrary()? {
            // A UV stream with seams: corners index a small pool, some none.
            let count = u.int_in_range(1..=16usize)?;
            let mut values = Vec::with_capacity(2 * count);
            for _ in 0..2 * count {
                values.push(f32::from(u.int_in_range(0u8..=8)?) / 8.0);
            }
            let mut indices = Vec::with_capacity(mesh.faces.corner_count());
            for _ in 0..mesh.faces.corner_count() {
                indices.push(if u.ratio(1u8, 16u8)? {
                    ABSENT
                } else {
                    u.int_in_range(0..=count as u32 - 1)?
                });
            }
            mesh.attributes.push(Attribute {
                semantic: Semantic::TexCoord(0),
                components: 2,
                values,
                indices,
                format: ComponentFormat::F32,
            });
        }
        Ok(SimplifyCase {
            options: arbitrary_options(u, nv)?,
            mesh,
        })
    }
}

fn arbitrary_options(u: &mut Unstructured<'_>, nv: usize) -> arbitrary::Result<Options> {
    let mut o = if u.ratio(1u8, 6u8)? {
        Options::classic_qem()
    } else {
        Options::default()
    };
    let ratio = match u.int_in_range(0..=7u8)? {
        0 => None,
        1 => Some(0.0),
        2 => Some(1.0),
        3 => Some(0.01),
        4 => Some(0.1),
        _ => Some(f64::from(u.int_in_range(0..=1000u16)?) / 1000.0),
    };
    o.target = Target {
        ratio,
        triangles: if u.ratio(1u8, 3u8)? {
            Some(u.int_in_range(0..=80usize)?)
        } else {
            None
        },
        error: if u.ratio(1u8, 4u8)? {
            Some(f64::from(u.int_in_range(0..=100u8)?) / 1000.0)
        } else {
            None
        },
    };
    o.guards.virtual_edge_radius = [0.0, 0.0025, 0.05, 0.5][u.int_in_range(0..=3usize)?];
    o.guards = Guards {
        max_normal_turn_degrees: [None, Some(90.0), Some(10.0)][u.int_in_range(0..=2usize)?],
        keep_topology: u.ratio(1u8, 4u8)?,
        lock_borders: u.ratio(1u8, 6u8)?,
        ..o.guards
    };
    o.quad.mode =
        [QuadMode::Auto, QuadMode::Never, QuadMode::Always][u.int_in_range(0..=2usize)?];
    if u.ratio(1u8, 4u8)? {
        o.quad.tangent_weight = 1.0 / 3.0;
        o.metric.tangent_weight = 1.0 / 3.0;
    }
    if u.ratio(1u8, 6u8)? {
        o.quad.symmetry = 1.0;
    }
    o.metric.introduced_error = u.ratio(1u8, 6u8)?;
    if u.ratio(1u8, 4u8)? {
        // The parallel first phase runs on meshes this small only when told.
        o.partition = Partition {
            min_triangles: 4,
            chunk_faces: u.int_in_range(2..=16usize)?,
            ..Partition::default()
        };
    }
    if u.ratio(1u8, 8u8)? {
        o.data.vertex_weights = (0..nv)
            .map(|_| u.int_in_range(0..=4u8).map(f32::from))
            .collect::<arbitrary::Result<_>>()?;
    }
    o.record.history = u.ratio(1u8, 8u8)?;
    Ok(o)
}

/// Runs one case and panics on a broken property: a panic inside, an
/// error on valid input, an invalid output, a dishonest report, or two runs
/// that differ.
pub fn check_simplify(case: &SimplifyCase) {
    let valid = case.mesh.validate().is_ok();
    match simplify_mesh(&case.mesh, &case.options) {
        Err(Error::InvalidMesh(_)) if !valid => {}
        Err(e) => panic!("simplify_mesh refused a valid mesh: {e}"),
        Ok(_) if !valid => panic!("simplify_mesh accepted an invalid mesh"),
        Ok((lod, report)) => {
            check_outcome(&case.mesh, &case.options, &lod, &report);
            let again = simplify_mesh(&case.mesh, &case.options);
            assert!(
                matches!(&again, Ok((l, r)) if *l == lod && same_report(r, &report)),
                "two runs on the same input differ"
            );
        }
    }
}

/// Reports are compared through their debug text, which prints every
/// float exactly (shortest round-trip) and a NaN as `NaN`: a NaN field (the
/// steering check's distances on a mesh without area) would otherwise
/// never equal itself and hide as a nondeterminism.
fn same_report(a: &Report, b: &Report) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

/// The properties of one successful simplification.
pub(crate) fn check_outcome(input: &Mesh, options: &Options, lod: &Mesh, report: &Report) {
    if let Err(e) = lod.validate() {
        panic!("simplify_mesh returned an invalid mesh: {e}");
    }
    assert_eq!(
        lod.triangle_count(),
        report.output_triangles,
        "the report's output triangles are not the output's"
    );
    assert_eq!(report.input_triangles, input.triangle_count());
    assert!(
        report.output_triangles <= report.input_triangles,
        "simplification added triangles"
    );
    if report.stop == Some(StopReason::TargetReached) {
        assert!(
            report.output_triangles <= report.target_triangles,
            "the report says reached, but {} > target {}",
            report.output_triangles,
            report.target_triangles
        );
    }
    // A ratio is of the surface's triangles: degenerate faces, exact
    // repeats and repeated corners of a polygon are cleaned away before the
    // target is taken, so it is never more than the input's.
    let target = options.target.triangles_for(report.input_triangles);
    assert!(
        report.target_triangles <= target,
        "the report's target {} exceeds the input's {target}",
        report.target_triangles
    );
    assert!(
        report.error.is_finite() && report.error >= 0.0,
        "the report's error is {}",
        report.error
    );
}
