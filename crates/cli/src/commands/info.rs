//! `wildlod info`: what a mesh file holds.
//!
//! JSON keys are a stable contract (documented in docs/cli.md); add keys,
//! never rename or remove them. They are `wildlod_pipeline::FileInfo`'s,
//! which the Python package's `info` returns too.

use wildlod_pipeline::{describe, FileInfo};

use crate::args::InfoArgs;
use crate::stdout::emit;

/// Runs `info`.
pub fn run(a: &InfoArgs) -> anyhow::Result<()> {
    let doc = wildlod_io::read(&a.file)?;
    let info = describe(&doc, &a.file.display().to_string());
    if a.json {
        emit(&(serde_json::to_string_pretty(&info)? + "\n"))
    } else {
        emit(&text(&info))
    }
}

/// The human-readable form.
pub fn text(i: &FileInfo) -> String {
    let opt = |o: Option<usize>| o.map_or("-".to_string(), |v| v.to_string());
    let mut s = format!(
        "{} ({}): {} mesh{}, {} vertices ({} welded)\n",
        i.file,
        i.format,
        i.meshes,
        if i.meshes == 1 { "" } else { "es" },
        i.vertices,
        i.welded_vertices
    );
    s += &format!(
        "  faces       {} ({} triangles, {} quads, {} n-gons) = {} triangles triangulated\n",
        i.counts.faces, i.counts.triangles, i.counts.quads, i.counts.ngons, i.counts.triangulated
    );
    if i.instanced != i.counts {
        s += &format!(
            "  drawn       {} faces = {} triangles triangulated (each mesh once per instance: the count simplify, lod and batch use)\n",
            i.instanced.faces, i.drawn_triangles
        );
    }
    s += &format!(
        "  topology    {} components, {} boundary edges, {} non-manifold edges, {} degenerate and {} duplicate faces\n",
        i.components, i.boundary_edges, i.nonmanifold_edges, i.degenerate_faces, i.duplicate_faces
    );
    s += &format!(
        "  appearance  {} UV islands, {} materials, {} textures\n",
        opt(i.uv_islands),
        i.materials,
        i.textures
    );
    if i.skins + i.animations > 0 {
        s += &format!(
            "  animation   {} skins, {} joints, {} animations\n",
            i.skins, i.joints, i.animations
        );
    }
    for w in &i.warnings {
        s += &format!("  warning     {w}\n");
    }
    s
}
