//! A whole scene under one budget (W §1, Fig. 1).
//!
//! W's first figure is a street: simplified as one mesh, the streetlamps
//! give their triangles to the buildings because the error is measured on
//! the scene, not on each object. A file's stored meshes are the objects
//! here. Simplifying each alone to the same ratio spends the budget where
//! the error is largest and cannot remove a part that does not matter.
//!
//! Pipeline: place every mesh in world space through its largest instance
//! → group the meshes that can share one complex → merge each group into one
//! mesh (each face keeps its mesh and part, hence its material) → simplify
//! → split back, inverse-transform into each mesh's own space.
//!
//! One group is the common case: one complex, one greedy queue, virtual
//! edges and welds across meshes (W §4.1.1), so touching parts close their
//! gaps and the queue alone decides which part loses triangles. Meshes that
//! cannot share a space or a layout form their own groups:
//!
//! - skinned meshes, in their bind space (glTF ignores their node's
//!   transform), one group per skin and influence count;
//! - meshes with morph targets (their deltas live in mesh space);
//! - meshes placed by a singular transform;
//! - meshes whose streams disagree with a group's (the same semantic with a
//!   different component count).
//!
//! Across groups the budget is allocated so that every group stops at the
//! same world-space error: a first pass records each group's
//! error-vs-triangles curve ([`crate::Record::error_curve`]) down to as
//! few triangles as it can go; the smallest threshold whose triangle sum
//! fits the budget is chosen; a second pass reruns each group to its count
//! at that threshold (the greedy order is deterministic, so it stops at the
//! recorded state).
//!
//! A mesh instanced several times is simplified once (the file stores it
//! once), placed by its largest instance: its error counts at that size,
//! and its triangles count in the budget once per instance, since the
//! renderer draws them that often (a budget is of drawn triangles, as
//! gltfpack's per-mesh ratio and `wildlod info`'s instanced counts are).

use std::collections::HashMap;

use glam::DMat4;
use wildlod_mesh::transform::{apply_point, transformed};
use wildlod_mesh::{Attribute, ComponentFormat, Mesh, Scene, Semantic, Skinning, ABSENT, IDENTITY};

use crate::error::Error;
use crate::mesh::simplify_mesh_with_progress;
use crate::options::{Guards, InputData, Options, Partition, Record, Target};
use crate::report::{Report, StopReason};

/// Why a group was not merged with the world-space meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupSpace {
    /// Meshes placed in world space by their largest instance.
    World,
    /// Skinned meshes in the bind space of one skin (`None`: no node names
    /// the skin).
    Skinned {
        /// The skin of the nodes showing these meshes.
        skin: Option<u32>,
    },
    /// A mesh with morph targets, in its own space.
    Morph,
    /// A mesh whose largest instance has a singular (or non-finite)
    /// transform, in its own space.
    Singular,
}

/// One group of meshes simplified together.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupReport {
    /// The scene's mesh indices in the group.
    pub meshes: Vec<u32>,
    /// The space the group was simplified in.
    pub space: GroupSpace,
    /// The run's report (its error is relative to the group's diagonal in
    /// that space).
    pub report: Report,
    /// The run's largest collapse error as a world-space distance (scene
    /// units), its own-space error scaled by the largest instance.
    pub world_error: f64,
}

/// What became of one stored mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshOutcome {
    /// Triangles of the stored mesh before (once, however many nodes show
    /// it).
    pub input_triangles: usize,
    /// Triangles of the stored mesh after.
    pub output_triangles: usize,
    /// Every triangle went: the mesh is empty (writers drop it, and the
    /// nodes that showed it no longer refer to it).
    pub removed: bool,
}

/// What [`simplify_scene`] reached.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneReport {
    /// Triangles the scene draws: each stored mesh's as many times as nodes
    /// show it (a mesh no node shows counts once).
    pub input_triangles: usize,
    /// Triangles the run aimed for over the whole scene, counted the same
    /// way.
    pub target_triangles: usize,
    /// Triangles the scene draws after.
    pub output_triangles: usize,
    /// Largest collapse error in the scene, as a world-space distance.
    pub world_error: f64,
    /// The same, relative to the scene's world bounding-box diagonal.
    pub error: f64,
    /// The scene's world bounding-box diagonal.
    pub diagonal: f64,
    /// The groups, in order of their first mesh.
    pub groups: Vec<GroupReport>,
    /// Per stored mesh.
    pub meshes: Vec<MeshOutcome>,
    /// Whether the budget was shared across groups by a common error
    /// threshold (two passes), rather than reached by one run.
    pub common_threshold: bool,
}

impl SceneReport {
    /// Why the scene's run stopped: the target when every group reached its
    /// share, otherwise the first group's other reason.
    pub fn stop(&self) -> Option<StopReason> {
        let reasons = self.groups.iter().filter_map(|g| g.report.stop);
        let mut first_other = None;
        for r in reasons {
            if !matches!(r, StopReason::TargetReached | StopReason::NothingToDo) {
                first_other.get_or_insert(r);
            }
        }
        first_other.or(self.groups.first().and_then(|g| g.report.stop))
    }

    /// Indices of the meshes whose every triangle went.
    pub fn removed(&self) -> Vec<u32> {
        (0..self.meshes.len() as u32)
            .filter(|&m| self.meshes[m as usize].removed)
            .collect()
    }
}

/// Simplifies every stored mesh of `scene` under one budget, in world
/// space (W §1, Fig. 1): see the module documentation.
///
/// `options.target` refers to the whole scene: `ratio` and `triangles` to
/// the triangles the scene draws (each mesh once per node that shows it),
/// `error` to the scene's world
/// bounding-box diagonal. A mesh may lose every triangle (it is then empty;
/// [`MeshOutcome::removed`]). Per-vertex options ([`crate::InputData::vertex_weights`],
/// [`crate::InputData::vertex_joints`]) and the history do not apply to a scene and
/// are ignored. Materials, nodes, skins and animations are unchanged.
///
/// ```
/// use wildlod_mesh::{shapes, Node, Scene};
/// use wildlod_simplify::{simplify_scene, Options, Target};
/// let mut scene = Scene::from_mesh(shapes::torus(24, 12, 1.0, 0.3));
/// scene.meshes.push(shapes::torus(24, 12, 0.01, 0.003));
/// scene.nodes.push(Node { mesh: Some(1), matrix: {
///     let mut m = wildlod_mesh::IDENTITY; m[12] = 5.0; m }, ..Node::default() });
/// scene.roots.push(1);
/// let options = Options { target: Target { ratio: Some(0.25), ..Target::default() }, ..Options::default() };
/// let (lod, report) = simplify_scene(&scene, &options)?;
/// assert!(report.output_triangles <= report.target_triangles + 1);
/// // The tiny torus gives its triangles to the big one.
/// assert!(lod.meshes[1].triangle_count() < lod.meshes[0].triangle_count() / 10);
/// # Ok::<(), wildlod_simplify::Error>(())
/// ```
pub fn simplify_scene(scene: &Scene, options: &Options) -> Result<(Scene, SceneReport), Error> {
    simplify_scene_with_progress(scene, options, &|_| {})
}

/// [`simplify_scene`] with a progress callback (fraction done, 0 to 1).
pub fn simplify_scene_with_progress(
    scene: &Scene,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<(Scene, SceneReport), Error> {
    let base = Options {
        record: Record {
            history: false,
            ..options.record
        },
        data: InputData {
            vertex_weights: Vec::new(),
            vertex_joints: Vec::new(),
            see_through_materials: if options.data.see_through_materials.is_empty() {
                see_through_materials(scene)
            } else {
                options.data.see_through_materials.clone()
            },
            see_through_faces: Vec::new(),
            material_uv_sets: Some(
                options
                    .data
                    .material_uv_sets
                    .clone()
                    .unwrap_or_else(|| material_uv_sets(scene)),
            ),
            ..options.data.clone()
        },
        guards: Guards {
            drop_enclosed_parts: options.guards.drop_enclosed_parts && enclosures_hide(scene),
            ..options.guards
        },
        ..options.clone()
    };
    let placements = placements(scene);
    let groups = group_meshes(scene, &placements);
    let merged: Vec<Merged> = groups
        .iter()
        .map(|g| merge(scene, g, &placements))
        .collect();
    let diagonal = world_diagonal(scene);
    // The budget is of drawn triangles: a mesh counts once per node that
    // shows it, and each group's faces say so (`InputData::face_instances`).
    let instances = scene.instance_counts();
    let drawn = |meshes: &[Mesh]| -> usize {
        meshes
            .iter()
            .zip(&instances)
            .map(|(m, &k)| m.triangle_count() * k)
            .sum()
    };
    let face_instances: Vec<Vec<u32>> = merged
        .iter()
        .map(|m| {
            if m.members.iter().all(|b| instances[b.mesh as usize] == 1) {
                return Vec::new();
            }
            m.members
                .iter()
                .flat_map(|b| {
                    let k = u32::try_from(instances[b.mesh as usize]).unwrap_or(u32::MAX);
                    std::iter::repeat(k).take(scene.meshes[b.mesh as usize].faces.len())
                })
                .collect()
        })
        .collect();
    let input_triangles = drawn(&scene.meshes);
    let counted = options.target.ratio.is_some() || options.target.triangles.is_some();
    let budget = options.target.triangles_for(input_triangles);
    // The user's error limit in each group's own units.
    let limit = |g: usize| {
        options.target.error.map(|e| {
            let d = merged[g].world_size();
            if d > 0.0 && diagonal > 0.0 {
                e * diagonal / d
            } else {
                e
            }
        })
    };
    let common_threshold = counted && merged.len() > 1;
    let passes = if common_threshold { 2 } else { 1 };
    let total_work: usize = merged.iter().map(|m| m.mesh.triangle_count()).sum();
    let mut done = 0usize;
    // Skinned groups are measured in the poses they are drawn in.
    let poses: Vec<Vec<Vec<[f32; 16]>>> = groups
        .iter()
        .map(|g| match g.space {
            GroupSpace::Skinned { skin: Some(skin) } => skin_poses(scene, skin),
            _ => Vec::new(),
        })
        .collect();
    let mut step = |g: usize, options: &Options| -> Result<(Mesh, Report), Error> {
        let work = merged[g].mesh.triangle_count();
        let start = done;
        let options = &Options {
            data: InputData {
                face_instances: face_instances[g].clone(),
                skin_poses: if options.data.skin_poses.is_empty() {
                    poses[g].clone()
                } else {
                    options.data.skin_poses.clone()
                },
                ..options.data.clone()
            },
            ..options.clone()
        };
        let r = simplify_mesh_with_progress(&merged[g].mesh, options, &|f| {
            progress((start as f64 + f * work as f64) / (passes * total_work.max(1)) as f64)
        });
        done += work;
        r
    };
    let mut results: Vec<(Mesh, Report)> = Vec::with_capacity(merged.len());
    if common_threshold {
        // Pass 1: every group as far as it goes, recording its curve. The
        // parallel phase records none and changes the order with the
        // target, so it stays off in both passes.
        let sequential = Partition::OFF;
        let mut floors = Vec::with_capacity(merged.len());
        for g in 0..merged.len() {
            let o = Options {
                target: Target {
                    ratio: None,
                    triangles: Some(0),
                    error: limit(g),
                },
                record: Record {
                    error_curve: true,
                    ..base.record
                },
                partition: sequential,
                ..base.clone()
            };
            floors.push(step(g, &o)?);
        }
        let curves: Vec<Curve> = floors
            .iter()
            .enumerate()
            .map(|(g, (_, r))| Curve::new(r, merged[g].world_size()))
            .collect();
        let shares = common_shares(&curves, budget);
        for (g, (floor, share)) in floors.into_iter().zip(shares).enumerate() {
            if share <= floor.1.output_triangles {
                results.push(floor);
                continue;
            }
            let o = Options {
                target: Target {
                    ratio: None,
                    triangles: Some(share),
                    error: limit(g),
                },
                partition: sequential,
                ..base.clone()
            };
            results.push(step(g, &o)?);
        }
    } else {
        for g in 0..merged.len() {
            let o = Options {
                target: Target {
                    ratio: None,
                    triangles: counted.then_some(budget),
                    error: limit(g),
                },
                ..base.clone()
            };
            results.push(step(g, &o)?);
        }
    }
    progress(1.0);
    let mut out = scene.clone();
    let mut report = SceneReport {
        input_triangles,
        target_triangles: if counted { budget } else { 0 },
        diagonal,
        common_threshold,
        ..SceneReport::default()
    };
    for ((group, m), (lod, r)) in groups.iter().zip(&merged).zip(results) {
        for (member, faces) in m.members.iter().zip(member_faces(&lod, &m.members)) {
            let i = member.mesh as usize;
            out.meshes[i] = split(&lod, member, &scene.meshes[i], &faces);
        }
        let world_error = r.error * m.world_size();
        report.world_error = report.world_error.max(world_error);
        report.groups.push(GroupReport {
            meshes: group.meshes.clone(),
            space: group.space,
            report: r,
            world_error,
        });
    }
    report.error = if diagonal > 0.0 {
        report.world_error / diagonal
    } else {
        report.world_error
    };
    report.meshes = scene
        .meshes
        .iter()
        .zip(&out.meshes)
        .map(|(a, b)| MeshOutcome {
            input_triangles: a.triangle_count(),
            output_triangles: b.triangle_count(),
            removed: !a.faces.is_empty() && b.faces.is_empty(),
        })
        .collect();
    report.output_triangles = drawn(&out.meshes);
    Ok((out, report))
}

/// Where a mesh goes: the world matrix of its largest instance and that
/// instance's scale (the length of the longest column of its linear part,
/// the largest factor by which it can stretch a coordinate axis).
#[derive(Clone, Copy, Debug)]
struct Placement {
    matrix: [f32; 16],
    scale: f64,
}

fn linear_scale(m: &[f32; 16]) -> f64 {
    (0..3)
        .map(|c| {
            (0..3)
                .map(|r| (m[4 * c + r] as f64).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

fn placements(scene: &Scene) -> Vec<Placement> {
    let mut out = vec![
        Placement {
            matrix: IDENTITY,
            scale: f64::NEG_INFINITY,
        };
        scene.meshes.len()
    ];
    for (m, world) in scene.instances() {
        let s = linear_scale(&world);
        let p = &mut out[m as usize];
        // NaN scales never win: a broken instance does not place the mesh.
        if s > p.scale {
            *p = Placement {
                matrix: world,
                scale: s,
            };
        }
    }
    for p in &mut out {
        if !(p.scale.is_finite() && p.scale > 0.0) {
            *p = Placement {
                matrix: p.matrix,
                scale: 1.0,
            };
        }
    }
    out
}

/// The meshes of one group and the space they are simplified in.
#[derive(Clone, Debug)]
struct Group {
    meshes: Vec<u32>,
    space: GroupSpace,
    /// (semantic, components) of the streams seen so far.
    streams: Vec<(Semantic, u8)>,
}

fn streams_of(mesh: &Mesh) -> Vec<(Semantic, u8)> {
    mesh.attributes
        .iter()
        .map(|a| (a.semantic.clone(), a.components))
        .collect()
}

/// Streams agree when no semantic has two component counts.
fn compatible(a: &[(Semantic, u8)], b: &[(Semantic, u8)]) -> bool {
    b.iter()
        .all(|(s, c)| a.iter().all(|(t, d)| t != s || d == c))
}

/// Whether a world matrix can be inverted without losing the mesh: its
/// linear part's determinant is finite and not tiny against its scale.
fn invertible(m: &[f32; 16]) -> bool {
    let d = DMat4::from_cols_array(&m.map(f64::from));
    let det = d.determinant();
    let s = linear_scale(m);
    m.iter().all(|x| x.is_finite()) && det.is_finite() && det.abs() > 1e-9 * s.powi(3)
}

fn group_meshes(scene: &Scene, placements: &[Placement]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for (m, mesh) in scene.meshes.iter().enumerate() {
        if mesh.faces.is_empty() {
            continue;
        }
        let morph = mesh
            .attributes
            .iter()
            .any(|a| matches!(a.semantic, Semantic::Morph { .. }));
        let space = if morph {
            GroupSpace::Morph
        } else if mesh.skinning.is_some() {
            GroupSpace::Skinned {
                skin: scene
                    .nodes
                    .iter()
                    .find(|n| n.mesh == Some(m as u32) && n.skin.is_some())
                    .and_then(|n| n.skin),
            }
        } else if !invertible(&placements[m].matrix) {
            GroupSpace::Singular
        } else {
            GroupSpace::World
        };
        let streams = streams_of(mesh);
        let influences = mesh.skinning.as_ref().map(|s| s.influences);
        let joinable = matches!(space, GroupSpace::World | GroupSpace::Skinned { .. });
        let found = groups.iter_mut().find(|g| {
            joinable
                && g.space == space
                && compatible(&g.streams, &streams)
                && scene.meshes[g.meshes[0] as usize]
                    .skinning
                    .as_ref()
                    .map(|s| s.influences)
                    == influences
        });
        match found {
            Some(g) => {
                for s in streams {
                    if !g.streams.contains(&s) {
                        g.streams.push(s);
                    }
                }
                g.meshes.push(m as u32);
            }
            None => groups.push(Group {
                meshes: vec![m as u32],
                space,
                streams,
            }),
        }
    }
    groups
}

/// One mesh's place in a merged mesh.
struct Member {
    mesh: u32,
    /// Its parts are `part_base..part_base + parts` of the merged mesh.
    part_base: u32,
    parts: u32,
    /// Mesh space → group space.
    matrix: [f32; 16],
    /// Group-space position bits → the mesh's own position, so that a
    /// vertex no collapse moved comes back bit for bit (an inverse
    /// transform would round it).
    exact: HashMap<[u32; 3], [f32; 3]>,
}

/// A group as one mesh: the scene's own mesh when the group is one mesh in
/// place (no copy: on a large single-mesh file a copy is a fifth of the
/// peak memory).
struct Merged<'s> {
    mesh: std::borrow::Cow<'s, Mesh>,
    members: Vec<Member>,
    /// Group-space units → world units (1 for world-space groups).
    scale: f64,
}

impl Merged<'_> {
    /// The group's diagonal in world units: errors relative to the run's
    /// diagonal times this are world distances.
    fn world_size(&self) -> f64 {
        self.mesh.diagonal() * self.scale
    }
}

fn merge<'s>(scene: &'s Scene, group: &Group, placements: &[Placement]) -> Merged<'s> {
    let world = group.space == GroupSpace::World;
    let scale = if world {
        1.0
    } else {
        group
            .meshes
            .iter()
            .map(|&m| placements[m as usize].scale)
            .fold(0.0, f64::max)
    };
    // A world-space group is placed about a point of its own, its first
    // member's position, not about the world origin: a georeferenced file
    // puts its meshes millions of units away, where f32 coordinates step by
    // a quarter of a unit (a 20-unit sphere at y = 4e6 came out with 10×
    // the Hausdorff distance of the same sphere at the origin). Distances do
    // not depend on the point, and the split inverts the same placements.
    let origin = match group.meshes.first() {
        Some(&m) if world => translation(&placements[m as usize].matrix),
        _ => [0.0; 3],
    };
    let mut placed: Vec<(u32, [f32; 16], std::borrow::Cow<'_, Mesh>)> = group
        .meshes
        .iter()
        .map(|&m| {
            let mesh = &scene.meshes[m as usize];
            let matrix = if world {
                shifted(&placements[m as usize].matrix, origin)
            } else {
                IDENTITY
            };
            let cow = if matrix == IDENTITY {
                std::borrow::Cow::Borrowed(mesh)
            } else {
                std::borrow::Cow::Owned(transformed(mesh, &matrix))
            };
            (m, matrix, cow)
        })
        .collect();
    if placed.len() == 1 {
        if let Some((m, matrix, mesh)) = placed.pop() {
            // One mesh: no concatenation to do.
            let members = vec![Member {
                mesh: m,
                part_base: 0,
                parts: mesh.parts.len() as u32,
                matrix,
                exact: exact_map(&scene.meshes[m as usize], &mesh, &matrix),
            }];
            return Merged {
                mesh,
                members,
                scale,
            };
        }
    }
    let mut out = Mesh::default();
    let mut members = Vec::with_capacity(placed.len());
    // Streams in order of first appearance.
    let mut semantics: Vec<(Semantic, u8, ComponentFormat)> = Vec::new();
    for (_, _, mesh) in &placed {
        for a in &mesh.attributes {
            if !semantics.iter().any(|(s, _, _)| *s == a.semantic) {
                semantics.push((a.semantic.clone(), a.components, a.format));
            }
        }
    }
    let mut streams: Vec<Attribute> = semantics
        .iter()
        .map(|(s, c, f)| Attribute {
            semantic: s.clone(),
            components: *c,
            values: Vec::new(),
            indices: Vec::new(),
            format: *f,
        })
        .collect();
    let mut skin: Option<Skinning> = None;
    for (m, matrix, mesh) in &placed {
        let base = out.positions.len() as u32;
        let part_base = out.parts.len() as u32;
        members.push(Member {
            mesh: *m,
            part_base,
            parts: mesh.parts.len() as u32,
            matrix: *matrix,
            exact: exact_map(&scene.meshes[*m as usize], mesh, matrix),
        });
        out.positions.extend_from_slice(&mesh.positions);
        for f in mesh.faces.iter() {
            out.faces.indices.extend(f.iter().map(|&v| v + base));
            out.faces.offsets.push(out.faces.indices.len() as u32);
        }
        out.face_parts
            .extend(mesh.face_parts.iter().map(|&p| p + part_base));
        out.parts.extend(mesh.parts.iter().cloned());
        let corners = mesh.faces.corner_count();
        for s in &mut streams {
            match mesh.attribute(&s.semantic) {
                Some(a) => {
                    let vb = s.value_count() as u32;
                    s.values.extend_from_slice(&a.values);
                    s.indices.extend(a.indices.iter().map(|&i| {
                        if i == ABSENT {
                            ABSENT
                        } else {
                            i + vb
                        }
                    }));
                }
                None => s.indices.extend(std::iter::repeat(ABSENT).take(corners)),
            }
        }
        if let Some(src) = &mesh.skinning {
            let dst = skin.get_or_insert_with(|| Skinning {
                influences: src.influences,
                joints: Vec::new(),
                weights: Vec::new(),
                indices: Vec::new(),
                weight_format: src.weight_format,
                joint_format: src.joint_format,
            });
            let eb = dst.entry_count() as u32;
            dst.joints.extend_from_slice(&src.joints);
            dst.weights.extend_from_slice(&src.weights);
            dst.indices.extend(
                src.indices
                    .iter()
                    .map(|&i| if i == ABSENT { ABSENT } else { i + eb }),
            );
        }
    }
    out.attributes = streams;
    out.skinning = skin;
    Merged {
        mesh: std::borrow::Cow::Owned(out),
        members,
        scale,
    }
}

/// The translation of a world matrix (column-major), in f64.
fn translation(m: &[f32; 16]) -> [f64; 3] {
    [m[12], m[13], m[14]].map(f64::from)
}

/// `m` followed by a translation by `-origin`, computed in f64: the
/// placement relative to `origin`.
fn shifted(m: &[f32; 16], origin: [f64; 3]) -> [f32; 16] {
    let mut out = *m;
    for c in 0..4 {
        let w = f64::from(m[4 * c + 3]);
        for k in 0..3 {
            out[4 * c + k] = (f64::from(m[4 * c + k]) - origin[k] * w) as f32;
        }
    }
    out
}

fn exact_map(original: &Mesh, placed: &Mesh, matrix: &[f32; 16]) -> HashMap<[u32; 3], [f32; 3]> {
    if *matrix == IDENTITY {
        return HashMap::new();
    }
    let mut map = HashMap::with_capacity(placed.positions.len());
    for (p, q) in placed.positions.iter().zip(&original.positions) {
        map.entry(p.map(f32::to_bits)).or_insert(*q);
    }
    map
}

/// The faces of the simplified group each member's parts hold, in the
/// group's order: one pass over the faces for all members.
fn member_faces(lod: &Mesh, members: &[Member]) -> Vec<Vec<u32>> {
    let parts = members
        .iter()
        .map(|m| m.part_base + m.parts)
        .max()
        .unwrap_or(0);
    let mut member_of = vec![u32::MAX; parts as usize];
    for (k, m) in members.iter().enumerate() {
        for p in m.part_base..m.part_base + m.parts {
            member_of[p as usize] = k as u32;
        }
    }
    let mut out = vec![Vec::new(); members.len()];
    for (f, &part) in lod.face_parts.iter().enumerate() {
        if let Some(&k) = member_of.get(part as usize).filter(|&&k| k != u32::MAX) {
            out[k as usize].push(f as u32);
        }
    }
    out
}

/// Mesh `member`'s faces of the simplified group (`faces`, see
/// [`member_faces`]), in the mesh's own space, with the streams and parts
/// of `original`.
fn split(lod: &Mesh, member: &Member, original: &Mesh, faces: &[u32]) -> Mesh {
    let mut corners: Vec<usize> = Vec::new();
    let mut out = Mesh {
        name: original.name.clone(),
        parts: original.parts.clone(),
        ..Mesh::default()
    };
    for &f in faces {
        let f = f as usize;
        let part = lod.face_parts[f];
        let face = lod.faces.face(f);
        let start = lod.faces.offsets[f] as usize;
        corners.extend(start..start + face.len());
        out.faces.indices.extend_from_slice(face);
        out.faces.offsets.push(out.faces.indices.len() as u32);
        out.face_parts.push(part - member.part_base);
    }
    // Only what this mesh's faces use, in the group's order: copying the
    // group's pools for every member and compacting them made a scene of
    // many meshes quadratic (20,000 boxes: 72 s).
    out.positions = used_of(&lod.positions, 1, &mut out.faces.indices);
    for a in &original.attributes {
        let Some(src) = lod.attribute(&a.semantic) else {
            continue;
        };
        let mut indices: Vec<u32> = corners.iter().map(|&c| src.indices[c]).collect();
        let values = used_of(&src.values, a.components as usize, &mut indices);
        out.attributes.push(Attribute {
            semantic: a.semantic.clone(),
            components: a.components,
            values,
            indices,
            format: a.format,
        });
    }
    if let (Some(src), Some(orig)) = (&lod.skinning, &original.skinning) {
        let mut indices: Vec<u32> = corners.iter().map(|&c| src.indices[c]).collect();
        let k = src.influences as usize;
        let mut again = indices.clone();
        let joints = used_of(&src.joints, k, &mut indices);
        let weights = used_of(&src.weights, k, &mut again);
        out.skinning = Some(Skinning {
            influences: src.influences,
            joints,
            weights,
            indices,
            weight_format: orig.weight_format,
            joint_format: orig.joint_format,
        });
    }
    if member.matrix != IDENTITY {
        let placed = out.positions.clone();
        let inverse = DMat4::from_cols_array(&member.matrix.map(f64::from))
            .inverse()
            .to_cols_array()
            .map(|x| x as f32);
        out = transformed(&out, &inverse);
        for (p, q) in out.positions.iter_mut().zip(&placed) {
            if let Some(x) = member.exact.get(&q.map(f32::to_bits)) {
                *p = *x;
            }
        }
    }
    out
}

/// The items of `pool` (of `stride` elements each) that `indices` name,
/// in ascending pool order, with `indices` renumbered into them (as
/// [`Mesh::compact`] leaves a pool; indices past the pool, such as
/// `ABSENT`, stay as they are). Work in the number of indices, not the
/// pool's size.
fn used_of<T: Copy>(pool: &[T], stride: usize, indices: &mut [u32]) -> Vec<T> {
    let n = pool.len().checked_div(stride).unwrap_or(0);
    let mut used: Vec<u32> = indices
        .iter()
        .copied()
        .filter(|&i| (i as usize) < n)
        .collect();
    used.sort_unstable();
    used.dedup();
    for i in indices.iter_mut() {
        if let Ok(k) = used.binary_search(i) {
            *i = k as u32;
        }
    }
    let mut out = Vec::with_capacity(used.len() * stride);
    for &u in &used {
        let u = u as usize;
        out.extend_from_slice(&pool[u * stride..(u + 1) * stride]);
    }
    out
}

/// A group's recorded run: (triangles, world error) after every collapse.
struct Curve {
    input: usize,
    points: Vec<(usize, f64)>,
}

impl Curve {
    fn new(r: &Report, world_size: f64) -> Curve {
        Curve {
            input: r.input_triangles,
            points: r
                .error_curve
                .iter()
                .map(|&(t, e)| (t, e * world_size))
                .collect(),
        }
    }

    /// Triangles left once every collapse of error at most `tau` is made
    /// (errors are a running maximum, so these are a prefix).
    fn triangles_at(&self, tau: f64) -> usize {
        let k = self.points.partition_point(|&(_, e)| e <= tau);
        match k {
            0 => self.input,
            k => self.points[k - 1].0,
        }
    }
}

/// Triangles per group such that every group stops at the same world error
/// and the sum is the budget (or as close above it as the groups can go).
fn common_shares(curves: &[Curve], budget: usize) -> Vec<usize> {
    let mut taus: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.points.iter().map(|&(_, e)| e))
        .collect();
    taus.sort_by(f64::total_cmp);
    taus.dedup();
    let sum = |tau: f64| -> usize { curves.iter().map(|c| c.triangles_at(tau)).sum() };
    let inputs: Vec<usize> = curves.iter().map(|c| c.input).collect();
    if inputs.iter().sum::<usize>() <= budget || taus.is_empty() {
        return inputs;
    }
    // The smallest threshold that fits; the sum only falls as it grows.
    let k = taus.partition_point(|&t| sum(t) > budget);
    let Some(&tau) = taus.get(k) else {
        // Even the last collapse leaves too many: every group goes as far
        // as it can.
        return curves
            .iter()
            .map(|c| c.points.last().map_or(c.input, |p| p.0))
            .collect();
    };
    let mut shares: Vec<usize> = curves.iter().map(|c| c.triangles_at(tau)).collect();
    // The collapses at exactly `tau` may remove more than needed: hand the
    // difference back to the groups that made them, in order.
    let before: Vec<usize> = match k {
        0 => inputs,
        _ => curves.iter().map(|c| c.triangles_at(taus[k - 1])).collect(),
    };
    let mut slack = budget.saturating_sub(shares.iter().sum());
    for (s, b) in shares.iter_mut().zip(before) {
        let add = slack.min(b.saturating_sub(*s));
        *s += add;
        slack -= add;
    }
    shares
}

/// Whether a part of `scene` inside a closed part of it is surely hidden
/// there, as [`crate::Guards::drop_enclosed_parts`] asks the caller to
/// rule out otherwise: no animation moves a node, no skin or morph target
/// poses a mesh (either could open an enclosure or move a part out), and
/// every material is opaque and one-sided (an enclosure drawn two-sided,
/// alpha-tested or blended shows what it holds).
pub fn enclosures_hide(scene: &Scene) -> bool {
    let posed = |m: &Mesh| {
        m.skinning.is_some()
            || m.attributes
                .iter()
                .any(|a| matches!(a.semantic, Semantic::Morph { .. }))
    };
    scene.animations.is_empty()
        && scene.skins.is_empty()
        && !scene.meshes.iter().any(posed)
        && scene
            .materials
            .iter()
            .all(|m| !m.double_sided && m.alpha_mode == wildlod_mesh::AlphaMode::Opaque)
}

/// Bounding-box diagonal of everything the scene shows, in world space.
/// The scene's materials that are seen through (alpha blended): their
/// twins stay (see [`crate::InputData::see_through_materials`]).
pub fn see_through_materials(scene: &Scene) -> Vec<u32> {
    scene
        .materials
        .iter()
        .enumerate()
        .filter(|(_, m)| m.alpha_mode == wildlod_mesh::AlphaMode::Blend)
        .map(|(i, _)| i as u32)
        .collect()
}

/// Poses sampled per animation when a file has them: enough to see each
/// motion's extremes (a walk cycle's swing, a bend's end) at a cost of one
/// pass over the faces per pose.
const FRAMES_PER_ANIMATION: usize = 8;

/// At most this many poses in all, however many animations a file has.
const MAX_POSES: usize = 32;

/// How far every joint turns in the poses of a skin no animation moves:
/// half a right angle, about two axes of its frame, each way, a range a
/// rigged limb is built to bend through.
const BEND_DEGREES: f32 = 45.0;

/// The poses `skin` is drawn in (see [`crate::InputData::skin_poses`]): frames
/// spread evenly over each animation of the file (both ends included), or,
/// when it has none, every joint turned by `BEND_DEGREES` about its
/// frame's x and z axes, each way (four poses).
pub fn skin_poses(scene: &Scene, skin: u32) -> Vec<Vec<[f32; 16]>> {
    use wildlod_mesh::pose::{bent_world_matrices, skin_matrices, world_matrices};
    let Some(joints) = scene.skins.get(skin as usize).map(|s| &s.joints) else {
        return Vec::new();
    };
    let matrices = |world: Vec<glam::Mat4>| -> Vec<[f32; 16]> {
        skin_matrices(scene, skin, &world)
            .iter()
            .map(|m| m.to_cols_array())
            .collect()
    };
    if let Some(per) = MAX_POSES.checked_div(scene.animations.len()) {
        let frames = per.clamp(2, FRAMES_PER_ANIMATION);
        let mut out = Vec::new();
        for (a, anim) in scene.animations.iter().enumerate() {
            for k in 0..frames {
                let t = anim.duration * k as f32 / (frames - 1) as f32;
                out.push(matrices(world_matrices(scene, Some(a), t)));
            }
            if out.len() >= MAX_POSES {
                break;
            }
        }
        out.truncate(MAX_POSES);
        return out;
    }
    let angle = BEND_DEGREES.to_radians();
    [glam::Vec3::X, glam::Vec3::Z]
        .into_iter()
        .flat_map(|axis| [angle, -angle].map(|a| (axis, a)))
        .map(|(axis, a)| matrices(bent_world_matrices(scene, joints, axis, a)))
        .collect()
}

/// Per material, the UV sets its textures sample, as a bitmask (see
/// [`crate::InputData::material_uv_sets`]).
pub fn material_uv_sets(scene: &Scene) -> Vec<u32> {
    scene
        .materials
        .iter()
        .map(|m| {
            m.texture_refs()
                .filter(|t| t.tex_coord < 32)
                .fold(0u32, |bits, t| bits | 1 << t.tex_coord)
        })
        .collect()
}

/// The diagonal of the world-space box of the bulk of the scene's drawn
/// vertices (far outliers left out, see [`wildlod_mesh::bounds`]), 0 when
/// there is none.
pub(crate) fn world_diagonal(scene: &Scene) -> f64 {
    let mut points: Vec<[f64; 3]> = Vec::new();
    for (m, world) in scene.instances() {
        let mesh = &scene.meshes[m as usize];
        let mut used = vec![false; mesh.positions.len()];
        for &v in &mesh.faces.indices {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        for (v, _) in used.iter().enumerate().filter(|(_, &u)| u) {
            let q = apply_point(&world, mesh.positions[v]);
            points.push(q.map(f64::from));
        }
    }
    wildlod_mesh::bounds::robust_bounds(points, &Default::default()).diagonal()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(input: usize, points: &[(usize, f64)]) -> Curve {
        Curve {
            input,
            points: points.to_vec(),
        }
    }

    #[test]
    fn common_threshold_takes_the_cheap_group_first() {
        // Group 0 is cheap to reduce, group 1 expensive: a budget of 12
        // (from 20) is met by group 0 alone.
        let a = curve(10, &[(8, 0.1), (6, 0.2), (4, 0.3), (2, 0.4)]);
        let b = curve(10, &[(8, 5.0), (6, 6.0)]);
        assert_eq!(common_shares(&[a, b], 12), vec![2, 10]);
    }

    #[test]
    fn ties_at_the_threshold_give_back_the_slack() {
        // Both groups drop from 10 to 4 at the same error: the budget 15
        // takes 6 + 4 + the slack given back in order.
        let a = curve(10, &[(4, 1.0)]);
        let b = curve(10, &[(4, 1.0)]);
        let s = common_shares(&[a, b], 15);
        assert_eq!(s.iter().sum::<usize>(), 15);
        assert_eq!(s, vec![10, 5]);
    }

    #[test]
    fn unreachable_budget_takes_every_group_to_its_floor() {
        let a = curve(10, &[(5, 1.0)]);
        let b = curve(10, &[(7, 2.0)]);
        assert_eq!(common_shares(&[a, b], 3), vec![5, 7]);
        let c = curve(10, &[(5, 1.0)]);
        assert_eq!(common_shares(&[c], 20), vec![10]);
    }
}
