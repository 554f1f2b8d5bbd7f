//! `bake-inputs DIR`: writes the generated re-baking benchmark inputs
//! (`wildlod_bench::bake_inputs`) as GLB with embedded PNG images:
//! `textured20k.glb` (20,000 triangles, 2048² base colour) and
//! `scan10k.glb` (10,092 triangles, 4096² base colour, one UV island per
//! quad) and `terrain1m.glb` (998,002 triangles of a noisy height field,
//! 1024² base colour) and `boxes8k.glb` (8,000 meshes of 12 triangles
//! sharing a 512² base colour) and `torus1m.glb` (1,000,000 triangles,
//! smooth UVs over a 1024² base colour: a large textured mesh for the
//! parallel phase with attributes). Time them with
//! `/usr/bin/time -v target/release/wildlod simplify DIR/textured20k.glb -o OUT.glb --ratio 0.1 --bake --texture-size 2048`
//! and `... DIR/scan10k.glb -o OUT.glb --ratio 0.01 --bake`.

use std::path::PathBuf;

use anyhow::Context;
use wildlod_bench::bake_inputs::{many_boxes, noisy_terrain, scan_like, textured_torus, BakeInput};
use wildlod_io::{encode_image, Document, ImageEncoding, WriteOptions};
use wildlod_mesh::ImageSource;

fn main() -> anyhow::Result<()> {
    let dir: PathBuf = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .context("usage: bake-inputs DIR")?;
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    for (name, input) in [
        ("textured20k.glb", textured_torus(100, 100, 2048)),
        ("scan10k.glb", scan_like(29, 4096)),
        ("terrain1m.glb", noisy_terrain(708, 1024)),
        ("boxes8k.glb", many_boxes(8000, 512)),
        ("torus1m.glb", textured_torus(1000, 500, 1024)),
    ] {
        let BakeInput { mut scene, image } = input;
        let bytes = encode_image(&image, ImageEncoding::Png, name)?;
        scene.textures[0].source = ImageSource::Embedded {
            bytes,
            mime_type: "image/png".into(),
        };
        let path = dir.join(name);
        let triangles: usize = scene.meshes.iter().map(|m| m.triangle_count()).sum();
        wildlod_io::write(
            &Document::from_scene(scene),
            &path,
            &WriteOptions::default(),
        )
        .with_context(|| format!("writing {}", path.display()))?;
        println!("{}: {triangles} triangles", path.display());
    }
    Ok(())
}
