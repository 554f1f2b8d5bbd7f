//! `evaluate-appearance`: wildlod against gltfpack and Blender's Decimate on
//! the corpus's textured and skinned files (texture and normal Chamfer,
//! distances at rest and posed at animation frames), as markdown.
//!
//! ```text
//! cargo build --release -p wildlod-cli
//! (cd tools/gltfpack && npm install)          # gltfpack 1.3
//! ../shared/peers/setup.sh                    # Blender as a Python module
//! cargo run --release -p wildlod-bench --bin evaluate-appearance -- ../shared/corpus \
//!     --out /tmp/appearance.md
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use wildlod_bench::appearance::{evaluate, markdown, Config, Peer};
use wildlod_testkit::{mesh_files, short};

/// Appearance evaluation of wildlod against its peers.
#[derive(Parser, Debug)]
struct Args {
    /// Corpus folder.
    #[arg(default_value = "../shared/corpus")]
    corpus: PathBuf,
    /// Where to write the markdown tables.
    #[arg(long, default_value = "appearance.md")]
    out: PathBuf,
    /// Ratios, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "0.5,0.1,0.01")]
    ratios: Vec<f64>,
    /// The wildlod binary.
    #[arg(long, default_value = "target/release/wildlod")]
    wildlod: String,
    /// Extra arguments for wildlod, space separated (a second wildlod row).
    #[arg(long)]
    wildlod_variant: Option<String>,
    /// The gltfpack binary (empty: leave it out).
    #[arg(long, default_value = "tools/gltfpack/node_modules/.bin/gltfpack")]
    gltfpack: String,
    /// Python with Blender's bpy module (empty: leave Blender out).
    #[arg(long, default_value = "../shared/peers/bpy")]
    blender_python: String,
    /// Frames (30 fps) of the first animation for skinned files.
    #[arg(long, default_value_t = 50)]
    frames: usize,
    /// Surface samples for distances.
    #[arg(long, default_value_t = 50_000)]
    samples: usize,
    /// Samples for texture and normal Chamfer.
    #[arg(long, default_value_t = 40_000)]
    texture_samples: usize,
}

fn main() -> ExitCode {
    let a = Args::parse();
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let mut peers = vec![Peer {
        name: "wildlod".into(),
        command: [
            vec![a.wildlod.clone()],
            s(&[
                "simplify", "{input}", "-o", "{output}", "--ratio", "{ratio}", "-q",
            ]),
        ]
        .concat(),
    }];
    if let Some(v) = &a.wildlod_variant {
        peers.push(Peer {
            name: format!("wildlod {v}"),
            command: [
                vec![a.wildlod.clone()],
                s(&[
                    "simplify", "{input}", "-o", "{output}", "--ratio", "{ratio}", "-q",
                ]),
                v.split_whitespace().map(String::from).collect(),
            ]
            .concat(),
        });
    }
    if !a.gltfpack.is_empty() {
        let base = s(&[
            "-i", "{input}", "-o", "{output}", "-si", "{ratio}", "-se", "1", "-noq", "-kn", "-km",
        ]);
        peers.push(Peer {
            name: "gltfpack".into(),
            command: [vec![a.gltfpack.clone()], base.clone()].concat(),
        });
        peers.push(Peer {
            name: "gltfpack -sv".into(),
            command: [vec![a.gltfpack.clone()], base, s(&["-sv"])].concat(),
        });
    }
    if !a.blender_python.is_empty() {
        peers.push(Peer {
            name: "Blender".into(),
            command: [
                vec![a.blender_python.clone()],
                s(&[
                    "tools/blender/decimate_gltf.py",
                    "{input}",
                    "{output}",
                    "{ratio}",
                ]),
            ]
            .concat(),
        });
    }
    let files: Vec<(String, PathBuf)> = ["textured", "skinned"]
        .iter()
        .flat_map(|c| mesh_files(&a.corpus, c))
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("gltf" | "glb" | "obj")
            )
        })
        .map(|p| (short(&a.corpus, &p), p))
        .collect();
    let work = std::env::temp_dir().join(format!("wildlod-appearance-{}", std::process::id()));
    if let Err(e) = std::fs::create_dir_all(&work) {
        eprintln!("error: {}: {e}", work.display());
        return ExitCode::FAILURE;
    }
    let cfg = Config {
        files,
        ratios: a.ratios.clone(),
        peers,
        samples: a.samples,
        texture_samples: a.texture_samples,
        frames: a.frames,
        work: work.clone(),
    };
    let rows = evaluate(&cfg, |r| match &r.result {
        Ok(m) => eprintln!(
            "{} {} {}: {} tris, texture {:?}, H {:.4}",
            r.file, r.ratio, r.peer, m.triangles, m.texture_chamfer, m.hausdorff
        ),
        Err(e) => eprintln!("{} {} {}: {e}", r.file, r.ratio, r.peer),
    });
    let _ = std::fs::remove_dir_all(&work);
    if let Err(e) = std::fs::write(&a.out, markdown(&rows, &cfg)) {
        eprintln!("error: {}: {e}", a.out.display());
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
