//! Every mesh of a scene simplified to its target.

use std::path::Path;
use std::time::Instant;

use wildlod_mesh::Scene;
use wildlod_simplify::{
    simplify_mesh_with_progress, simplify_scene_with_progress, InputData, Options, QuadTies,
    Rejections, Report, SceneReport, SteeringOutcome, Target,
};

use crate::{Error, FileTargets, MeshProgress, MIN_TRIANGLES};

/// One simplified mesh of a file: what the per-mesh line and the JSON
/// report say.
#[derive(Clone, Debug)]
pub struct MeshRun {
    /// Index of the mesh in the scene.
    pub mesh: usize,
    /// Its name for messages (the file stem for a lone unnamed mesh).
    pub name: String,
    /// What the simplifier reached.
    pub report: Report,
    /// Wall time of this mesh.
    pub seconds: f64,
}

/// Names joint 0 in every influence slot of `mesh`'s skin that has no
/// weight. A fitted skin's unused slots keep a joint from a neighbour's
/// influences at weight 0; that does not move the vertex, but the Khronos
/// validator flags every such slot (ACCESSOR_JOINTS_USED_ZERO_WEIGHT), so
/// simplified levels would carry warnings their input did not. Meshes
/// written unchanged keep their slots as read. Returns the slots changed.
pub fn clear_unused_joint_slots(mesh: &mut wildlod_mesh::Mesh) -> usize {
    let Some(skin) = mesh.skinning.as_mut() else {
        return 0;
    };
    let mut changed = 0;
    for (j, &w) in skin.joints.iter_mut().zip(&skin.weights) {
        if w == 0.0 && *j != 0 {
            *j = 0;
            changed += 1;
        }
    }
    changed
}

/// How a mesh is named in messages: its own name, the file's stem when it
/// is the file's only mesh, else `mesh N`.
pub fn mesh_name(scene: &Scene, m: usize, stem: &str) -> String {
    match (
        scene.meshes.get(m).map_or("", |x| x.name.as_str()),
        scene.meshes.len(),
    ) {
        ("", 1) => stem.to_string(),
        ("", _) => format!("mesh {m}"),
        (n, _) => n.to_string(),
    }
}

/// The stem of a file name, for messages and output names.
pub fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Simplifies every mesh of `scene` in place to its target (keep-UV mode:
/// every stream fitted, textures shared), one after the other; targets and
/// reports count the triangles a mesh draws (its own times the nodes that
/// show it, see `InputData::face_instances`); `progress`
/// makes the display for a mesh's name. Meshes without faces and meshes
/// without a target are left as they are. Errors name `input` and the
/// mesh.
pub fn simplify_scene<P: MeshProgress>(
    scene: &mut Scene,
    input: &Path,
    options: &Options,
    targets: &[Target],
    stem: &str,
    progress: &dyn Fn(&str) -> P,
) -> Result<Vec<MeshRun>, Error> {
    let mut runs = Vec::new();
    let see_through = if options.data.see_through_materials.is_empty() {
        wildlod_simplify::see_through_materials(scene)
    } else {
        options.data.see_through_materials.clone()
    };
    let uv_sets = options
        .data
        .material_uv_sets
        .clone()
        .unwrap_or_else(|| wildlod_simplify::material_uv_sets(scene));
    let instances = scene.instance_counts();
    let guards = wildlod_simplify::Guards {
        drop_enclosed_parts: options.guards.drop_enclosed_parts
            && wildlod_simplify::enclosures_hide(scene),
        ..options.guards
    };
    for (m, target) in targets.iter().enumerate() {
        let Some(mesh) = scene.meshes.get(m) else {
            continue;
        };
        if mesh.faces.is_empty() {
            continue;
        }
        let name = mesh_name(scene, m, stem);
        // Targets and reports count drawn triangles, as the scene budget's.
        let k = instances.get(m).copied().unwrap_or(1);
        let options = Options {
            target: *target,
            data: InputData {
                see_through_materials: see_through.clone(),
                material_uv_sets: Some(uv_sets.clone()),
                face_instances: if k > 1 {
                    vec![u32::try_from(k).unwrap_or(u32::MAX); mesh.faces.len()]
                } else {
                    Vec::new()
                },
                ..options.data.clone()
            },
            guards,
            ..options.clone()
        };
        let bar = progress(&name);
        let t0 = Instant::now();
        let (lod, report) =
            simplify_mesh_with_progress(mesh, &options, &|f| bar.set(f)).map_err(|source| {
                Error::Simplify {
                    file: input.to_path_buf(),
                    mesh: name.clone(),
                    source,
                }
            })?;
        bar.finish();
        runs.push(MeshRun {
            mesh: m,
            name,
            report,
            seconds: t0.elapsed().as_secs_f64(),
        });
        scene.meshes[m] = lod;
        clear_unused_joint_slots(&mut scene.meshes[m]);
    }
    Ok(runs)
}

/// Simplifies the whole of `scene` under one budget in world space (W §1,
/// Fig. 1; see [`wildlod_simplify::simplify_scene`]): the triangles go where
/// the error is smallest, and a part too small to matter may disappear.
/// `targets` are the file's (checked); the file keeps at least
/// [`MIN_TRIANGLES`]. Returns one run for the whole file (named `stem`:
/// its budget and error, relative to the file's diagonal, are the file's)
/// and the scene's own report. Errors name `input`.
pub fn simplify_whole_scene<P: MeshProgress>(
    scene: &mut Scene,
    input: &Path,
    options: &Options,
    targets: &FileTargets,
    stem: &str,
    progress: &dyn Fn(&str) -> P,
) -> Result<(MeshRun, SceneReport), Error> {
    let options = Options {
        target: Target {
            ratio: targets.ratio,
            // `ratio 0` means "as small as possible", not an empty file.
            triangles: Some(targets.faces.unwrap_or(MIN_TRIANGLES).max(MIN_TRIANGLES)),
            error: targets.error,
        },
        ..options.clone()
    };
    let bar = progress(stem);
    let t0 = Instant::now();
    let (lod, report) =
        simplify_scene_with_progress(scene, &options, &|f| bar.set(f)).map_err(|source| {
            Error::Simplify {
                file: input.to_path_buf(),
                mesh: "the scene".into(),
                source,
            }
        })?;
    bar.finish();
    *scene = lod;
    for mesh in &mut scene.meshes {
        clear_unused_joint_slots(mesh);
    }
    let run = MeshRun {
        mesh: 0,
        name: stem.to_string(),
        report: whole_report(&report),
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((run, report))
}

/// A scene run as one [`Report`]: the file's triangles, target and error
/// (relative to the file's diagonal), the guards' refusals summed.
pub fn whole_report(r: &SceneReport) -> Report {
    let mut rejected = Rejections::default();
    for g in &r.groups {
        let j = &g.report.rejected;
        rejected.normal_flip += j.normal_flip;
        rejected.topology += j.topology;
        rejected.flat_border += j.flat_border;
        rejected.locked_border += j.locked_border;
        rejected.overshoot += j.overshoot;
        rejected.error_limit += j.error_limit;
    }
    Report {
        input_triangles: r.input_triangles,
        target_triangles: r.target_triangles,
        output_triangles: r.output_triangles,
        error: r.error,
        stop: r.stop(),
        twin_slack: r.groups.iter().any(|g| g.report.twin_slack),
        rejected,
        split_polygons: r.groups.iter().map(|g| g.report.split_polygons).sum(),
        joined_quads: r.groups.iter().map(|g| g.report.joined_quads).sum(),
        hidden_twins: r.groups.iter().map(|g| g.report.hidden_twins).sum(),
        enclosed_parts: r.groups.iter().map(|g| g.report.enclosed_parts).sum(),
        collapses: r.groups.iter().map(|g| g.report.collapses).sum(),
        evaluations: r.groups.iter().map(|g| g.report.evaluations).sum(),
        faces_tested: r.groups.iter().map(|g| g.report.faces_tested).sum(),
        stray_normals: r.groups.iter().map(|g| g.report.stray_normals).sum(),
        layer_vertices: r.groups.iter().map(|g| g.report.layer_vertices).sum(),
        outliers: r
            .groups
            .iter()
            .flat_map(|g| g.report.outliers.iter().copied())
            .collect(),
        uv_damage: r
            .groups
            .iter()
            .filter_map(|g| g.report.uv_damage)
            .reduce(f64::max),
        virtual_radius_reduced: r
            .groups
            .iter()
            .filter_map(|g| g.report.virtual_radius_reduced)
            .reduce(f64::min),
        held_by_constraints: r
            .groups
            .iter()
            .filter_map(|g| g.report.held_by_constraints)
            .reduce(f64::max),
        // The file's quad ties: the narrowest any group was held to.
        quad_ties: r
            .groups
            .iter()
            .filter_map(|g| g.report.quad_ties)
            .reduce(|a, b| QuadTies {
                scale: a.scale.min(b.scale),
                chamfer: a.chamfer.max(b.chamfer),
                plain_chamfer: a.plain_chamfer.max(b.plain_chamfer),
            }),
        // The file's steering: kept where every group kept its own.
        steering: r
            .groups
            .iter()
            .filter_map(|g| g.report.steering)
            .reduce(|a, b| SteeringOutcome {
                kept: a.kept && b.kept,
                hausdorff: a.hausdorff.max(b.hausdorff),
                chamfer: a.chamfer.max(b.chamfer),
                geometry_hausdorff: a.geometry_hausdorff.max(b.geometry_hausdorff),
                geometry_chamfer: a.geometry_chamfer.max(b.geometry_chamfer),
            }),
        ..Report::default()
    }
}
