//! Every OBJ and STL of the shared corpus: read, validate, face counts by
//! arity as the corpus README states them, and round trips through the same
//! format (and OBJ → PLY → PLY) with bit-equal data per corner.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use wildlod_io::{read, write, Document, WriteOptions};
use wildlod_mesh::{ImageSource, Mesh, Scene};
use wildlod_testkit::{corpus, mesh_files, short};

/// Face counts by arity (tri, quad, n-gon) for every file of the README
/// tables, keyed by path relative to the corpus root.
fn readme_counts(root: &Path) -> HashMap<PathBuf, (usize, usize, usize)> {
    let text = std::fs::read_to_string(root.join("README.md")).expect("corpus README");
    let mut category = String::new();
    let mut out = HashMap::new();
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            category = h.trim().trim_end_matches('/').to_string();
            continue;
        }
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        // Only the per-category tables; the attribution table also lists files.
        if category.contains(' ') || cols.len() < 3 || !cols[1].starts_with('`') {
            continue;
        }
        let file = cols[1].split('`').nth(1).expect("file in backticks");
        let mut counts = (0, 0, 0);
        for term in cols[2].split('+') {
            let mut words = term.split_whitespace();
            let n: usize = words.next().unwrap().replace(',', "").parse().unwrap();
            match words.next().unwrap() {
                "tri" | "tris" => counts.0 = n,
                "quad" => counts.1 = n,
                "n-gon" => counts.2 = n,
                other => panic!("unknown face kind {other} in README row {line}"),
            }
        }
        out.insert(Path::new(&category).join(file), counts);
    }
    out
}

fn obj_and_stl(root: &Path) -> Vec<PathBuf> {
    mesh_files(root, "")
        .into_iter()
        .filter(|p| matches!(ext(p).as_str(), "obj" | "stl"))
        .collect()
}

fn ext(p: &Path) -> String {
    p.extension()
        .unwrap()
        .to_string_lossy()
        .to_ascii_lowercase()
}

#[test]
fn every_corpus_obj_and_stl_reads_with_the_readme_face_counts() {
    let Some(root) = corpus("every_corpus_obj_and_stl_reads_with_the_readme_face_counts") else {
        return;
    };
    let table = readme_counts(&root);
    let files = obj_and_stl(&root);
    assert!(
        files.len() >= 25,
        "found only {} OBJ/STL files",
        files.len()
    );
    for f in files {
        let name = short(&root, &f);
        let doc = read(&f).unwrap_or_else(|e| panic!("{e}"));
        doc.scene.validate().unwrap();
        assert_eq!(doc.scene.meshes.len(), 1, "{name}");
        let counts = doc.scene.meshes[0].faces.arity_counts();
        let expected = table
            .get(&PathBuf::from(&name))
            .unwrap_or_else(|| panic!("{name} is not in the README table"));
        assert_eq!(counts, *expected, "{name}: faces by arity");
    }
}
