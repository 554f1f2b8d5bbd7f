//! `wildlod demo`: the main job on a mesh generated in code, so a fresh
//! checkout can see wildlod work without any file.
//!
//! The example is "wild" on purpose: a table whose top and legs are separate
//! boxes that touch without sharing vertices, a quad-dominant ball resting on
//! it, and a loose sheet of paper: several components, quads and triangles,
//! open borders.

use anyhow::Context;
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Mesh, Scene};
use wildlod_pipeline::describe;
use wildlod_simplify::{simplify_mesh, Options, Target};

use crate::args::DemoArgs;
use crate::commands::info::text;
use crate::commands::simplify::summary;
use crate::stdout::emit;

/// The demo scene, as one mesh.
pub fn example() -> Mesh {
    let top = shapes::box_grid([-1.0, -0.6, 0.9], [1.0, 0.6, 1.0], 16);
    let legs: Vec<Mesh> = [(-0.9, -0.5), (0.8, -0.5), (-0.9, 0.4), (0.8, 0.4)]
        .iter()
        .map(|&(x, y)| shapes::box_grid([x, y, 0.0], [x + 0.1, y + 0.1, 0.9], 8))
        .collect();
    let mut ball = shapes::quad_sphere(12);
    for p in &mut ball.positions {
        *p = [p[0] * 0.3 + 0.3, p[1] * 0.3, p[2] * 0.3 + 1.3];
    }
    let mut paper = shapes::triangulate(&shapes::quad_grid(10, 14));
    for p in &mut paper.positions {
        *p = [
            p[0] * 0.4 - 0.8,
            p[1] * 0.56 - 0.3,
            1.0 + 0.02 * (p[0] * 9.0).sin(),
        ];
    }
    let mut parts = vec![top];
    parts.extend(legs);
    parts.push(ball);
    parts.push(paper);
    let mut m = shapes::merge(&parts);
    m.name = "table".into();
    m
}

/// Runs `demo`.
pub fn run(a: &DemoArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let input = a.out.join("demo_input.obj");
    let output = a.out.join("demo_lod.obj");
    let mesh = example();
    let options = Options {
        target: Target {
            ratio: Some(a.ratio),
            ..Target::default()
        },
        ..Options::default()
    };
    let t0 = std::time::Instant::now();
    let (lod, report) = simplify_mesh(&mesh, &options)?;
    let secs = t0.elapsed().as_secs_f64();
    let write = |m: Mesh, path: &std::path::Path| -> anyhow::Result<Document> {
        let doc = Document::from_scene(Scene::from_mesh(m));
        wildlod_io::write(&doc, path, &WriteOptions::default())?;
        Ok(doc)
    };
    let din = write(mesh, &input)?;
    let dout = write(lod, &output)?;
    emit(&format!(
        "{}{}{}\nWrote {} and {}; simplify your own: wildlod simplify IN -o OUT --ratio {}\n",
        text(&describe(&din, &input.display().to_string())),
        text(&describe(&dout, &output.display().to_string())),
        summary("table", &report, secs),
        input.display(),
        output.display(),
        a.ratio
    ))
}
