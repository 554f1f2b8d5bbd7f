//! What `wildlod info --json` prints about a file.
//!
//! JSON keys are a stable contract (documented in docs/cli.md); add keys,
//! never rename or remove them.

use serde::Serialize;
use wildlod_io::Document;
use wildlod_mesh::stats::topology;
use wildlod_mesh::Semantic;

/// Face counts by arity.
#[derive(Serialize, Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct FaceCounts {
    /// Polygons as stored.
    pub faces: usize,
    /// Three-sided faces.
    pub triangles: usize,
    /// Four-sided faces.
    pub quads: usize,
    /// Faces with five or more sides.
    pub ngons: usize,
    /// Triangle count when triangulated: a quad is 2, an n-gon n − 2.
    pub triangulated: usize,
}

impl FaceCounts {
    /// The counts of one mesh.
    pub fn of(mesh: &wildlod_mesh::Mesh) -> Self {
        let (t, q, n) = mesh.faces.arity_counts();
        FaceCounts {
            faces: mesh.faces.len(),
            triangles: t,
            quads: q,
            ngons: n,
            triangulated: mesh.faces.triangulated_count(),
        }
    }

    /// Adds `o`, `times` times.
    pub fn add(&mut self, o: FaceCounts, times: usize) {
        self.faces += o.faces * times;
        self.triangles += o.triangles * times;
        self.quads += o.quads * times;
        self.ngons += o.ngons * times;
        self.triangulated += o.triangulated * times;
    }
}

/// One stored mesh.
#[derive(Serialize, Debug)]
pub struct MeshInfo {
    /// Mesh name.
    pub name: String,
    /// Nodes that show it (at least 1).
    pub instances: usize,
    /// Vertices as stored.
    pub vertices: usize,
    /// Distinct positions used by faces.
    pub welded_vertices: usize,
    /// Face counts.
    #[serde(flatten)]
    pub counts: FaceCounts,
    /// Connected components after welding.
    pub components: usize,
    /// Edges of one face.
    pub boundary_edges: usize,
    /// Edges of three or more faces.
    pub nonmanifold_edges: usize,
    /// Faces with a repeated (welded) vertex.
    pub degenerate_faces: usize,
    /// Faces repeating an earlier face's vertex set.
    pub duplicate_faces: usize,
    /// UV islands of UV set 0, or null without UVs.
    pub uv_islands: Option<usize>,
    /// UV sets.
    pub uv_sets: usize,
    /// Whether the mesh has normals.
    pub normals: bool,
    /// Whether the mesh has vertex colors.
    pub colors: bool,
    /// Morph targets.
    pub morph_targets: usize,
    /// Whether the mesh carries skin influences.
    pub skinned: bool,
    /// Parts (glTF primitives, OBJ groups).
    pub parts: usize,
}

/// The whole file.
#[derive(Serialize, Debug)]
pub struct FileInfo {
    /// The file.
    pub file: String,
    /// Its format.
    pub format: String,
    /// Stored meshes.
    pub meshes: usize,
    /// Vertices as stored, summed.
    pub vertices: usize,
    /// Distinct positions, summed per mesh.
    pub welded_vertices: usize,
    /// Face counts, each stored mesh once.
    #[serde(flatten)]
    pub counts: FaceCounts,
    /// Face counts with every mesh counted once per instance.
    pub instanced: FaceCounts,
    /// Triangles drawn: each mesh triangulated and counted once per node
    /// that shows it. The count `simplify`, `lod` and `batch` report and
    /// budget (`instanced.triangulated`, named for what it is).
    pub drawn_triangles: usize,
    /// Components, summed per mesh.
    pub components: usize,
    /// Boundary edges, summed.
    pub boundary_edges: usize,
    /// Non-manifold edges, summed.
    pub nonmanifold_edges: usize,
    /// Degenerate faces, summed.
    pub degenerate_faces: usize,
    /// Duplicate faces, summed.
    pub duplicate_faces: usize,
    /// UV islands, summed over meshes with UVs; null when none has UVs.
    pub uv_islands: Option<usize>,
    /// Materials.
    pub materials: usize,
    /// Textures.
    pub textures: usize,
    /// Skins.
    pub skins: usize,
    /// Joints, summed over skins.
    pub joints: usize,
    /// Animations.
    pub animations: usize,
    /// Scene nodes.
    pub nodes: usize,
    /// Every stored mesh.
    pub per_mesh: Vec<MeshInfo>,
    /// Problems met while reading.
    pub warnings: Vec<String>,
}

/// Describes a document.
pub fn describe(doc: &Document, file: &str) -> FileInfo {
    let s = &doc.scene;
    let inst = s.instance_counts();
    let per_mesh: Vec<MeshInfo> = s
        .meshes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let t = topology(m);
            MeshInfo {
                name: m.name.clone(),
                instances: inst[i],
                vertices: m.positions.len(),
                welded_vertices: t.welded_vertices,
                counts: FaceCounts::of(m),
                components: t.components,
                boundary_edges: t.boundary_edges,
                nonmanifold_edges: t.nonmanifold_edges,
                degenerate_faces: t.degenerate_faces,
                duplicate_faces: t.duplicate_faces,
                uv_islands: t.uv_islands,
                uv_sets: m
                    .attributes
                    .iter()
                    .filter(|a| matches!(a.semantic, Semantic::TexCoord(_)))
                    .count(),
                normals: m.attribute(&Semantic::Normal).is_some(),
                colors: m
                    .attributes
                    .iter()
                    .any(|a| matches!(a.semantic, Semantic::Color(_))),
                morph_targets: m
                    .attributes
                    .iter()
                    .filter_map(|a| match a.semantic {
                        Semantic::Morph { target, .. } => Some(target + 1),
                        _ => None,
                    })
                    .max()
                    .unwrap_or(0) as usize,
                skinned: m.skinning.is_some(),
                parts: m.parts.len(),
            }
        })
        .collect();
    let mut counts = FaceCounts::default();
    let mut instanced = FaceCounts::default();
    for m in &per_mesh {
        counts.add(m.counts, 1);
        instanced.add(m.counts, m.instances);
    }
    let sum = |f: fn(&MeshInfo) -> usize| per_mesh.iter().map(f).sum::<usize>();
    let uv_islands = per_mesh
        .iter()
        .filter_map(|m| m.uv_islands)
        .reduce(|a, b| a + b);
    FileInfo {
        file: file.to_string(),
        format: doc
            .format
            .or_else(|| wildlod_io::Format::from_path(std::path::Path::new(file)).ok())
            .map(|f| f.extension().to_string())
            .unwrap_or_default(),
        meshes: s.meshes.len(),
        vertices: sum(|m| m.vertices),
        welded_vertices: sum(|m| m.welded_vertices),
        counts,
        instanced,
        drawn_triangles: instanced.triangulated,
        components: sum(|m| m.components),
        boundary_edges: sum(|m| m.boundary_edges),
        nonmanifold_edges: sum(|m| m.nonmanifold_edges),
        degenerate_faces: sum(|m| m.degenerate_faces),
        duplicate_faces: sum(|m| m.duplicate_faces),
        uv_islands,
        materials: s.materials.len(),
        textures: s.textures.len(),
        skins: s.skins.len(),
        joints: s.skins.iter().map(|k| k.joints.len()).sum(),
        animations: s.animations.len(),
        nodes: s.nodes.len(),
        per_mesh,
        warnings: doc.warnings.clone(),
    }
}
