//! `scenes`: writes the generated scenes of [`wildlod_testkit::scenes`]
//! (a house, a filleted CAD part, a flat tiling, a city block, a bent
//! skinned tube, a terrain with outliers, a many-island textured ball, a
//! double-sided sheet, a sky dome over 40 small parts, a sphere with 52
//! blend shapes, a tree of 1,500 leaf cards, an alpha-tested fence) as
//! glTF, and the quad-dominant ones also as OBJ (glTF stores triangles
//! only), for the CLI, `../shared/peers` and the renders to run on assets
//! unlike the corpus.
//!
//! ```text
//! cargo run --release -p wildlod-bench --bin scenes -- /tmp/scenes
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Parser;
use wildlod_testkit::scenes;

/// Writes the generated scenes.
#[derive(Parser, Debug)]
struct Args {
    /// Folder to write into (created; existing files of the same names are
    /// replaced).
    out: PathBuf,
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scenes: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let all = [
        ("house", scenes::house(false), false),
        ("house_textured", scenes::house(true), false),
        ("filleted_block", scenes::filleted_block(), false),
        ("flat_tiling", scenes::flat_tiling(1), true),
        ("city_block", scenes::city_block(), true),
        ("bent_tube", scenes::bent_tube(), false),
        ("outlier_terrain", scenes::outlier_terrain(200, 3), false),
        ("uv_fold_mesh", scenes::uv_fold_mesh(), false),
        ("double_sided_sheet", scenes::double_sided_sheet(), false),
        ("domed_scene", scenes::domed_scene(40), false),
        ("morph_sphere", scenes::morph_sphere(115, 52), false),
        ("foliage_tree", scenes::foliage_tree(1500), false),
        ("chain_link_fence", scenes::chain_link_fence(), false),
        ("decal_wall", scenes::decal_wall(), false),
    ];
    for (name, scene, quads) in all {
        let mut exts = vec!["glb"];
        if quads {
            exts.push("obj");
        }
        for ext in exts {
            let path = args.out.join(format!("{name}.{ext}"));
            let doc = wildlod_io::Document::from_scene(scene.clone());
            wildlod_io::write(&doc, &path, &wildlod_io::WriteOptions::default())
                .with_context(|| format!("writing {}", path.display()))?;
            println!("{}", path.display());
        }
    }
    Ok(())
}
