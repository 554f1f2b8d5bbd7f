//! The simplifiers being compared, on the same input: wildlod (default and
//! classic-QEM settings) and meshoptimizer (`simplify`, which keeps vertex
//! positions, and `simplify_with_update`, which moves them).

use std::time::Instant;

use wildlod_mesh::{shapes, transform, Faces, Mesh, Scene};
use wildlod_simplify::{simplify_mesh, Options, Partition, QuadMode, Target};

/// A simplifier under test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// wildlod with default options.
    Wildlod,
    /// wildlod with default options but one global greedy loop
    /// (`Partition::OFF`): what the parallel first phase costs in quality.
    WildlodGlobal,
    /// wildlod with default options but the quad-preserving ordering off
    /// (`QuadMode::Never`): what keeping quads costs. On inputs without
    /// quads it is the default run again; it runs on them anyway so that
    /// every method's means cover the same meshes.
    WildlodNoQuads,
    /// wildlod's engine with `Options::classic_qem()` (Garland & Heckbert
    /// 1997: no virtual edges, no area term).
    ClassicQem,
    /// meshoptimizer `simplify`, no error limit.
    Meshopt,
    /// meshoptimizer `simplify_with_update`, no error limit.
    MeshoptUpdate,
    /// wildlod with default options, asked for exactly the triangle count
    /// meshoptimizer `simplify` reached: the comparison at equal budget when
    /// meshoptimizer stops short of the target.
    WildlodAtMeshoptCount,
}

impl Method {
    /// Every method, in report order.
    pub const ALL: [Method; 7] = [
        Method::Wildlod,
        Method::WildlodGlobal,
        Method::WildlodNoQuads,
        Method::ClassicQem,
        Method::Meshopt,
        Method::MeshoptUpdate,
        Method::WildlodAtMeshoptCount,
    ];

    /// Name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Wildlod => "wildlod",
            Method::WildlodGlobal => "wildlod, one global loop",
            Method::WildlodNoQuads => "wildlod, quads off",
            Method::ClassicQem => "wildlod classic QEM",
            Method::Meshopt => "meshopt simplify",
            Method::MeshoptUpdate => "meshopt simplify_with_update",
            Method::WildlodAtMeshoptCount => "wildlod at meshopt's count",
        }
    }

    /// Short name for command lines.
    pub fn key(self) -> &'static str {
        match self {
            Method::Wildlod => "wildlod",
            Method::WildlodGlobal => "global",
            Method::WildlodNoQuads => "no-quads",
            Method::ClassicQem => "classic",
            Method::Meshopt => "meshopt",
            Method::MeshoptUpdate => "meshopt-update",
            Method::WildlodAtMeshoptCount => "at-meshopt-count",
        }
    }

    /// The method whose [`Method::key`] is `key`.
    pub fn from_key(key: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.key() == key)
    }
}

/// The result of one run: the simplified scene (or flattened mesh) and the
/// time the simplifier took, excluding I/O.
pub struct Run {
    /// The result, in the input's scene structure (wildlod) or flattened to
    /// world space (meshoptimizer, which takes one index buffer).
    pub scene: Scene,
    /// Seconds spent simplifying.
    pub seconds: f64,
    /// Triangles of the result, counted per instance like the input.
    pub triangles: usize,
}

/// All instances of a scene as one world-space triangle mesh: the input
/// meshoptimizer sees.
pub fn flatten(scene: &Scene) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (m, world) in scene.instances() {
        let mesh = shapes::triangulate(&transform::transformed(&scene.meshes[m as usize], &world));
        let base = positions.len() as u32;
        positions.extend_from_slice(&mesh.positions);
        indices.extend(mesh.faces.indices.iter().map(|&v| v + base));
    }
    (positions, indices)
}

/// Triangles of a scene counted per instance.
pub fn instanced_triangles(scene: &Scene) -> usize {
    scene
        .instances()
        .iter()
        .map(|(m, _)| scene.meshes[*m as usize].triangle_count())
        .sum()
}

/// Runs `method` on `scene` at `ratio` of its (instanced) triangles.
/// [`Method::WildlodAtMeshoptCount`] needs meshoptimizer's result count,
/// `meshopt_count`.
pub fn run(
    method: Method,
    scene: &Scene,
    ratio: f64,
    meshopt_count: Option<usize>,
) -> Result<Run, wildlod_simplify::Error> {
    match method {
        Method::Wildlod
        | Method::WildlodGlobal
        | Method::WildlodNoQuads
        | Method::ClassicQem
        | Method::WildlodAtMeshoptCount => {
            let base = match method {
                Method::ClassicQem => Options::classic_qem(),
                Method::WildlodGlobal => Options {
                    partition: Partition::OFF,
                    ..Options::default()
                },
                // The ordering alone switched off: the metric stays the one
                // quad mode uses, attribute weights scaled the same way, so
                // that the comparison prices the ordering and nothing else.
                Method::WildlodNoQuads => {
                    let d = Options::default();
                    let k = d.quad.attribute_weight;
                    let a = d.attributes;
                    Options {
                        quad: wildlod_simplify::QuadSettings {
                            mode: QuadMode::Never,
                            ..d.quad
                        },
                        attributes: wildlod_simplify::AttributeOptions {
                            tex_coord_weight: k * a.tex_coord_weight,
                            normal_weight: k * a.normal_weight,
                            color_weight: k * a.color_weight,
                            skin_weight: k * a.skin_weight,
                            ..a
                        },
                        ..d
                    }
                }
                _ => Options::default(),
            };
            // At meshoptimizer's count: the same ratio of every mesh, so
            // that the instanced total matches.
            let total = instanced_triangles(scene).max(1);
            let ratio = match (method, meshopt_count) {
                (Method::WildlodAtMeshoptCount, Some(n)) => (n as f64 / total as f64).min(1.0),
                _ => ratio,
            };
            let options = Options {
                target: Target {
                    ratio: Some(ratio),
                    ..Target::default()
                },
                ..base
            };
            let mut out = scene.clone();
            let t = Instant::now();
            for mesh in &mut out.meshes {
                if mesh.faces.is_empty() {
                    continue;
                }
                *mesh = simplify_mesh(mesh, &options)?.0;
            }
            let seconds = t.elapsed().as_secs_f64();
            let triangles = instanced_triangles(&out);
            Ok(Run {
                scene: out,
                seconds,
                triangles,
            })
        }
        Method::Meshopt | Method::MeshoptUpdate => {
            let _ = meshopt_count;
            let (mut positions, indices) = flatten(scene);
            let target = ((indices.len() / 3) as f64 * ratio).round().max(1.0) as usize;
            let t = Instant::now();
            let out = if method == Method::Meshopt {
                meshopt_simplify(&positions, &indices, target)
            } else {
                meshopt_simplify_with_update(&mut positions, &indices, target)
            };
            let seconds = t.elapsed().as_secs_f64();
            let triangles = out.len() / 3;
            let mesh = Mesh::from_polygons(positions, Faces::from_triangles(&out));
            Ok(Run {
                scene: Scene::from_mesh(mesh),
                seconds,
                triangles,
            })
        }
    }
}

/// meshoptimizer `simplify` to `target` triangles with no error limit.
pub fn meshopt_simplify(positions: &[[f32; 3]], indices: &[u32], target: usize) -> Vec<u32> {
    let bytes: &[u8] = meshopt::typed_to_bytes(positions);
    match meshopt::VertexDataAdapter::new(bytes, 12, 0) {
        Ok(adapter) => meshopt::simplify(
            indices,
            &adapter,
            target * 3,
            f32::MAX,
            meshopt::SimplifyOptions::None,
            None,
        ),
        Err(_) => indices.to_vec(),
    }
}

/// meshoptimizer `simplify_with_update` (moves vertices to better
/// positions) to `target` triangles with no error limit; updates `positions`.
pub fn meshopt_simplify_with_update(
    positions: &mut [[f32; 3]],
    indices: &[u32],
    target: usize,
) -> Vec<u32> {
    let mut out = indices.to_vec();
    let n = meshopt::simplify_with_update(
        &mut out,
        positions,
        &mut [],
        &[],
        0,
        None,
        target * 3,
        f32::MAX,
        meshopt::SimplifyOptions::None,
        None,
    );
    out.truncate(n);
    out
}
