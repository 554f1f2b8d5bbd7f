//! The corpus evaluation (issue "Measure like the papers"): every mesh of a
//! corpus folder, at several ratios, simplified by every [`Method`],
//! measured against its input with `wildlod-eval` (Hausdorff, Chamfer as
//! mean and mean squared distance, normalized to the input's bounding-box
//! diagonal), and written as markdown.

use std::path::{Path, PathBuf};

use wildlod_eval::{compare, CompareOptions, EvalMesh};

use crate::methods::{instanced_triangles, run, Method};

/// Whether a row's target is meshoptimizer's reached count rather than the
/// ratio (its `target` is then that count).
fn target_of(method: Method, ratio_target: usize, meshopt_count: Option<usize>) -> usize {
    match (method, meshopt_count) {
        (Method::WildlodAtMeshoptCount, Some(n)) => n,
        _ => ratio_target,
    }
}

/// What to evaluate.
#[derive(Clone, Debug)]
pub struct Config {
    /// The corpus root; categories are its subfolders.
    pub corpus: PathBuf,
    /// Categories (subfolders) to include; empty means all.
    pub categories: Vec<String>,
    /// Ratios of the input triangles to simplify to.
    pub ratios: Vec<f64>,
    /// Sample points per surface for the distances.
    pub samples: usize,
    /// Methods to compare.
    pub methods: Vec<Method>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            corpus: PathBuf::from("../shared/corpus"),
            categories: Vec::new(),
            ratios: vec![0.5, 0.1, 0.01, 0.001],
            samples: 50_000,
            methods: Method::ALL.to_vec(),
        }
    }
}

/// One measurement.
#[derive(Clone, Debug)]
pub struct Row {
    /// File, relative to the corpus root.
    pub file: String,
    /// Its category (first folder).
    pub category: String,
    /// Stored meshes in the file.
    pub meshes: usize,
    /// Triangles of the input, per instance.
    pub input_triangles: usize,
    /// Ratio asked for.
    pub ratio: f64,
    /// The simplifier.
    pub method: Method,
    /// Triangles asked for.
    pub target: usize,
    /// Triangles reached.
    pub triangles: usize,
    /// Symmetric Hausdorff distance (relative to the input's diagonal).
    pub hausdorff: f64,
    /// Chamfer distance as mean distance, both directions averaged.
    pub chamfer_mean: f64,
    /// Chamfer distance as mean squared distance (W Table 1).
    pub chamfer_squared: f64,
    /// Seconds spent simplifying.
    pub seconds: f64,
    /// Quad ratio as in Knodt 2024, (outQuads/outTris)/(inQuads/inTris);
    /// `None` when the input has no quads.
    pub quad_ratio: Option<f64>,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

impl Row {
    /// Whether the run reached its target, allowing one triangle per mesh
    /// (each mesh's own target is rounded).
    pub fn reached(&self) -> bool {
        self.failure.is_none()
            && self.triangles <= self.target + self.meshes
            && self.triangles + self.meshes >= self.target
    }
}

/// Mesh files of the chosen categories, sorted.
pub fn files(cfg: &Config) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![cfg.corpus.clone()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if is_mesh(&p) && in_categories(cfg, &p) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn is_mesh(p: &Path) -> bool {
    wildlod_io::Format::from_path(p).is_ok()
}

fn category(cfg: &Config, p: &Path) -> String {
    p.strip_prefix(&cfg.corpus)
        .ok()
        .and_then(|r| r.components().next())
        .filter(|_| p.parent() != Some(cfg.corpus.as_path()))
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn in_categories(cfg: &Config, p: &Path) -> bool {
    cfg.categories.is_empty() || cfg.categories.contains(&category(cfg, p))
}

/// Evaluates every file; `each` sees every row as soon as it is measured.
pub fn evaluate(cfg: &Config, mut each: impl FnMut(&Row)) -> anyhow::Result<Vec<Row>> {
    let mut rows = Vec::new();
    let options = CompareOptions {
        samples: cfg.samples,
        ..CompareOptions::default()
    };
    for path in files(cfg) {
        let file = path
            .strip_prefix(&cfg.corpus)
            .unwrap_or(&path)
            .display()
            .to_string();
        let doc = wildlod_io::read(&path)?;
        let input_triangles = instanced_triangles(&doc.scene);
        if input_triangles == 0 {
            continue;
        }
        let reference = EvalMesh::from_scene(&doc.scene, &[]);
        for &ratio in &cfg.ratios {
            let target = ((input_triangles as f64 * ratio).round() as usize).max(1);
            let mut meshopt_count = None;
            for &method in &cfg.methods {
                let mut row = Row {
                    file: file.clone(),
                    category: category(cfg, &path),
                    meshes: doc.scene.meshes.len(),
                    input_triangles,
                    ratio,
                    method,
                    target: target_of(method, target, meshopt_count),
                    triangles: 0,
                    hausdorff: f64::NAN,
                    chamfer_mean: f64::NAN,
                    chamfer_squared: f64::NAN,
                    seconds: 0.0,
                    quad_ratio: None,
                    failure: None,
                };
                // Nothing to compare at an empty budget.
                if method == Method::WildlodAtMeshoptCount && meshopt_count.unwrap_or(0) == 0 {
                    continue;
                }
                match run(method, &doc.scene, ratio, meshopt_count) {
                    Ok(r) => {
                        if method == Method::Meshopt {
                            meshopt_count = Some(r.triangles);
                        }
                        let cand = EvalMesh::from_scene(&r.scene, &[]);
                        let c = compare(&reference, &cand, &options);
                        row.triangles = r.triangles;
                        row.seconds = r.seconds;
                        row.hausdorff = c.hausdorff;
                        row.chamfer_mean = c.chamfer_mean;
                        row.chamfer_squared = c.chamfer_squared;
                        row.quad_ratio = c.quad_ratio;
                    }
                    Err(e) => row.failure = Some(e.to_string()),
                }
                each(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        s / n as f64
    }
}

/// Median (the mean of the middle two for an even count), or `None` for
/// no values: how the summary reduces quad ratios per category.
pub fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(v[n / 2]),
        _ => Some(0.5 * (v[n / 2 - 1] + v[n / 2])),
    }
}

fn quad_cell(q: Option<f64>) -> String {
    q.map_or_else(|| "–".to_string(), |q| format!("{q:.3}"))
}

fn pct(r: f64) -> String {
    let p = r * 100.0;
    if p >= 1.0 {
        format!("{p:.0}%")
    } else {
        format!("{p}%")
    }
}

/// The markdown report: how it was made, a summary per category, ratio and
/// method, and a table per mesh.
pub fn markdown(cfg: &Config, rows: &[Row], command: &str) -> String {
    let mut s = String::new();
    s += "# wildlod evaluation\n\n";
    s += &format!("Generated by `{command}`.\n\n");
    s += "Every mesh is simplified to each ratio of its triangles (a quad counts as two; \
          instanced meshes count once per instance) by each method, then compared with its \
          input by `wildlod-eval`: distances are normalized by the input's bounding-box \
          diagonal; **Hausdorff** is the larger of the two directed distances (maximum over \
          area samples and all vertices); **Chamfer** is the mean distance and **Chamfer²** the \
          mean squared distance (W Table 1's), each averaged over both directions; \
          **quad ratio** is Knodt 2024's (outQuads/outTris)/(inQuads/inTris), on inputs with \
          quads. ";
    s += &format!(
        "{} area samples per surface. Times are simplification only (no I/O), on this machine, \
         one run each: compare ratios, not absolute values.\n\n",
        cfg.samples
    );
    s += "wildlod simplifies each stored mesh of a file to the ratio; meshoptimizer gets the \
          whole scene flattened into one index buffer (it has no notion of meshes). A method \
          that stops short of its target keeps more triangles, so its errors are not \
          comparable with those that reached it: see the *reached* column.\n\n";
    s += "## Summary\n\nMeans over the meshes of each category. *reached*: results within one \
          triangle per mesh of the target; *empty*: results with no triangle left (their \
          distances are infinite and left out of the means); *quad ratio*: the median over \
          the meshes that have quads.\n\n";
    s += "| category | ratio | method | reached | empty | triangles / target | Hausdorff | Chamfer | Chamfer² | quad ratio | time (ms) |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|---|\n";
    let mut cats: Vec<String> = rows.iter().map(|r| r.category.clone()).collect();
    cats.sort();
    cats.dedup();
    for cat in &cats {
        for &ratio in &cfg.ratios {
            for &m in &cfg.methods {
                let sel: Vec<&Row> = rows
                    .iter()
                    .filter(|r| &r.category == cat && r.ratio == ratio && r.method == m)
                    .collect();
                if sel.is_empty() {
                    continue;
                }
                let ok: Vec<&&Row> = sel
                    .iter()
                    .filter(|r| r.failure.is_none() && r.triangles > 0)
                    .collect();
                let empty = sel
                    .iter()
                    .filter(|r| r.failure.is_none() && r.triangles == 0)
                    .count();
                s += &format!(
                    "| {cat} | {} | {} | {}/{} | {} | {:.3} | {:.5} | {:.6} | {:.3e} | {} | {:.1} |\n",
                    pct(ratio),
                    m.name(),
                    sel.iter().filter(|r| r.reached()).count(),
                    sel.len(),
                    empty,
                    mean(ok.iter().map(|r| r.triangles as f64 / r.target as f64)),
                    mean(ok.iter().map(|r| r.hausdorff)),
                    mean(ok.iter().map(|r| r.chamfer_mean)),
                    mean(ok.iter().map(|r| r.chamfer_squared)),
                    quad_cell(median(ok.iter().filter_map(|r| r.quad_ratio).collect())),
                    mean(ok.iter().map(|r| r.seconds * 1000.0)),
                );
            }
        }
    }
    s += "\n## Per mesh\n";
    let mut files: Vec<(String, usize)> = rows
        .iter()
        .map(|r| (r.file.clone(), r.input_triangles))
        .collect();
    files.dedup();
    for (file, tris) in files {
        s += &format!("\n### {file} ({tris} triangles)\n\n");
        s += "| ratio | method | triangles (target) | Hausdorff | Chamfer | Chamfer² | quad ratio | time (ms) |\n";
        s += "|---|---|---|---|---|---|---|---|\n";
        for r in rows.iter().filter(|r| r.file == file) {
            match &r.failure {
                Some(f) => {
                    s += &format!(
                        "| {} | {} | failed: {f} | | | | | |\n",
                        pct(r.ratio),
                        r.method.name()
                    )
                }
                None => {
                    s += &format!(
                        "| {} | {} | {} ({}) | {:.5} | {:.6} | {:.3e} | {} | {:.1} |\n",
                        pct(r.ratio),
                        r.method.name(),
                        r.triangles,
                        r.target,
                        r.hausdorff,
                        r.chamfer_mean,
                        r.chamfer_squared,
                        quad_cell(r.quad_ratio),
                        r.seconds * 1000.0
                    )
                }
            }
        }
    }
    s
}
