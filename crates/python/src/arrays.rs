//! `simplify` on numpy arrays: a mesh of per-vertex arrays in, the same
//! arrays out, split at seams where a vertex ends up with two values.

use std::collections::HashMap;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Semantic, Skinning, ABSENT};
use wildlod_pipeline::{FileTargets, MeshJson, MeshRun, Tuning};
use wildlod_simplify::{simplify_mesh, Options, Target};

use crate::convert::{report_dict, simplify_error, to_pyerr, wildlod_error};

/// Per-vertex streams, as plain rows (copied out of numpy, so the work can
/// run without the GIL).
#[derive(Default)]
pub struct Streams {
    /// (semantic name, semantic, components, values).
    pub attributes: Vec<(&'static str, Semantic, usize, Vec<f32>)>,
    /// Skin: influences per vertex, joints, weights.
    pub skin: Option<(usize, Vec<u16>, Vec<f32>)>,
}

/// Rows of a 2-D array, checked against the vertex count.
fn rows<T: numpy::Element + Copy>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, T>,
    vertices: usize,
    widths: &[usize],
) -> PyResult<(usize, Vec<T>)> {
    let view = a.as_array();
    let (n, w) = view.dim();
    if n != vertices || !widths.contains(&w) {
        let want = widths
            .iter()
            .map(|k| format!("({vertices}, {k})"))
            .collect::<Vec<_>>()
            .join(" or ");
        return Err(wildlod_error(
            py,
            format!("{name} has shape ({n}, {w}), expected {want}: one row per vertex"),
            false,
        ));
    }
    Ok((w, view.iter().copied().collect()))
}

/// The arrays of one call.
pub struct ArrayMesh {
    positions: Vec<[f32; 3]>,
    faces: Faces,
    streams: Streams,
    vertex_weights: Vec<f32>,
}

impl ArrayMesh {
    /// Copies and checks the arrays (shapes here; indices and values are
    /// the simplifier's to check, which names the face or vertex).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        py: Python<'_>,
        positions: PyReadonlyArray2<'_, f32>,
        indices: PyReadonlyArray1<'_, u32>,
        sizes: PyReadonlyArray1<'_, u32>,
        uvs: Option<PyReadonlyArray2<'_, f32>>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        colors: Option<PyReadonlyArray2<'_, f32>>,
        skin: (
            Option<PyReadonlyArray2<'_, u16>>,
            Option<PyReadonlyArray2<'_, f32>>,
        ),
        vertex_weights: Option<PyReadonlyArray1<'_, f32>>,
    ) -> PyResult<ArrayMesh> {
        let p = positions.as_array();
        if p.ncols() != 3 {
            return Err(wildlod_error(
                py,
                format!("positions has shape {:?}, expected (n, 3)", p.dim()),
                false,
            ));
        }
        let positions: Vec<[f32; 3]> = p.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
        let n = positions.len();
        let indices: Vec<u32> = indices.as_array().iter().copied().collect();
        let mut faces = Faces::with_capacity(sizes.len()?, indices.len());
        let mut at = 0usize;
        for (f, &k) in sizes.as_array().iter().enumerate() {
            let k = k as usize;
            if k < 3 {
                return Err(wildlod_error(
                    py,
                    format!("face {f} has {k} corners; a face needs at least 3"),
                    false,
                ));
            }
            let Some(corners) = indices.get(at..at + k) else {
                return Err(wildlod_error(
                    py,
                    format!(
                        "the face sizes add up to more than the {} indices given (at face {f})",
                        indices.len()
                    ),
                    false,
                ));
            };
            faces.push(corners);
            at += k;
        }
        if at != indices.len() {
            return Err(wildlod_error(
                py,
                format!(
                    "the face sizes add up to {at}, but {} indices were given",
                    indices.len()
                ),
                false,
            ));
        }
        let mut streams = Streams::default();
        if let Some(a) = uvs {
            let (w, v) = rows(py, "uvs", &a, n, &[2])?;
            streams
                .attributes
                .push(("uvs", Semantic::TexCoord(0), w, v));
        }
        if let Some(a) = normals {
            let (w, v) = rows(py, "normals", &a, n, &[3])?;
            streams.attributes.push(("normals", Semantic::Normal, w, v));
        }
        if let Some(a) = colors {
            let (w, v) = rows(py, "colors", &a, n, &[3, 4])?;
            streams
                .attributes
                .push(("colors", Semantic::Color(0), w, v));
        }
        match skin {
            (None, None) => {}
            (Some(j), Some(w)) => {
                let k = j.as_array().ncols();
                if !(1..=255).contains(&k) {
                    return Err(wildlod_error(
                        py,
                        format!("joints has {k} columns, expected 1 to 255 influences"),
                        false,
                    ));
                }
                let (_, joints) = rows(py, "joints", &j, n, &[k])?;
                let (_, weights) = rows(py, "weights", &w, n, &[k])?;
                streams.skin = Some((k, joints, weights));
            }
            _ => {
                return Err(wildlod_error(
                    py,
                    "joints and weights go together: give both or neither".into(),
                    false,
                ))
            }
        }
        let vertex_weights = match vertex_weights {
            Some(w) => {
                let w: Vec<f32> = w.as_array().iter().copied().collect();
                if w.len() != n {
                    return Err(wildlod_error(
                        py,
                        format!("vertex_weights has {} entries for {n} vertices", w.len()),
                        false,
                    ));
                }
                w
            }
            None => Vec::new(),
        };
        Ok(ArrayMesh {
            positions,
            faces,
            streams,
            vertex_weights,
        })
    }

    /// The mesh model: every stream per vertex, so corners index values by
    /// their vertex.
    fn mesh(&self) -> Mesh {
        let mut mesh = Mesh::from_polygons(self.positions.clone(), self.faces.clone());
        for (_, semantic, components, values) in &self.streams.attributes {
            mesh.attributes.push(Attribute {
                semantic: semantic.clone(),
                components: *components as u8,
                values: values.clone(),
                indices: self.faces.indices.clone(),
                format: ComponentFormat::F32,
            });
        }
        if let Some((k, joints, weights)) = &self.streams.skin {
            mesh.skinning = Some(Skinning {
                influences: *k as u8,
                joints: joints.clone(),
                weights: weights.clone(),
                indices: self.faces.indices.clone(),
                weight_format: ComponentFormat::F32,
                joint_format: ComponentFormat::U16,
            });
        }
        mesh
    }
}

/// The simplified mesh as per-vertex arrays: a vertex per distinct
/// combination of position and stream values of a corner (a seam splits a
/// position into several vertices, as glTF does).
pub struct Unwelded {
    positions: Vec<f32>,
    indices: Vec<u32>,
    sizes: Vec<u32>,
    attributes: Vec<(&'static str, usize, Vec<f32>)>,
    skin: Option<(usize, Vec<u16>, Vec<f32>)>,
}

fn unweld(mesh: &Mesh, names: &[&'static str]) -> Unwelded {
    let streams: Vec<&Attribute> = mesh.attributes.iter().collect();
    let mut map: HashMap<Vec<u32>, u32> = HashMap::new();
    let mut out = Unwelded {
        positions: Vec::new(),
        indices: Vec::with_capacity(mesh.faces.indices.len()),
        sizes: mesh.faces.iter().map(|f| f.len() as u32).collect(),
        attributes: streams
            .iter()
            .zip(names)
            .map(|(a, n)| (*n, a.components as usize, Vec::new()))
            .collect(),
        skin: mesh
            .skinning
            .as_ref()
            .map(|s| (s.influences as usize, Vec::new(), Vec::new())),
    };
    for (corner, &v) in mesh.faces.indices.iter().enumerate() {
        let mut key = vec![v];
        key.extend(streams.iter().map(|a| a.indices[corner]));
        if let Some(s) = &mesh.skinning {
            key.push(s.indices[corner]);
        }
        let next = map.len() as u32;
        let id = *map.entry(key).or_insert_with(|| {
            out.positions.extend_from_slice(&mesh.positions[v as usize]);
            for (a, (_, c, values)) in streams.iter().zip(out.attributes.iter_mut()) {
                match a.indices[corner] {
                    // A corner without a value (not made by this package's
                    // input, which gives every vertex one) reads as zeros.
                    ABSENT => values.extend(std::iter::repeat(0.0).take(*c)),
                    i => values.extend_from_slice(a.value(i)),
                }
            }
            if let (Some(s), Some((k, joints, weights))) = (&mesh.skinning, out.skin.as_mut()) {
                match s.indices[corner] {
                    ABSENT => {
                        joints.extend(std::iter::repeat(0).take(*k));
                        weights.extend(std::iter::repeat(0.0).take(*k));
                    }
                    i => {
                        let (j, w) = s.entry(i);
                        joints.extend_from_slice(j);
                        weights.extend_from_slice(w);
                    }
                }
            }
            next
        });
        out.indices.push(id);
    }
    out
}

/// Simplifies the arrays without the GIL; what to return is built after.
pub fn run(
    mesh: &ArrayMesh,
    targets: FileTargets,
    tuning: &Tuning,
) -> Result<(Unwelded, MeshRun), RunError> {
    let targets = targets.checked().map_err(RunError::Pipeline)?;
    let mut options = Options {
        target: Target {
            ratio: targets.ratio,
            triangles: targets.faces,
            error: targets.error,
        },
        ..tuning.options().map_err(RunError::Pipeline)?
    };
    options.data.vertex_weights = mesh.vertex_weights.clone();
    let t0 = std::time::Instant::now();
    let (lod, report) = simplify_mesh(&mesh.mesh(), &options).map_err(RunError::Simplify)?;
    let names: Vec<&'static str> = mesh.streams.attributes.iter().map(|a| a.0).collect();
    Ok((
        unweld(&lod, &names),
        MeshRun {
            mesh: 0,
            name: "mesh".into(),
            report,
            seconds: t0.elapsed().as_secs_f64(),
        },
    ))
}

/// Why [`run`] failed.
pub enum RunError {
    /// Settings refused.
    Pipeline(wildlod_pipeline::Error),
    /// Arrays refused.
    Simplify(wildlod_simplify::Error),
}

impl RunError {
    /// As a Python exception.
    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            RunError::Pipeline(e) => to_pyerr(py, e),
            RunError::Simplify(e) => simplify_error(py, e),
        }
    }
}

/// The result dict: `positions`, `indices`, `face_sizes`, the streams
/// given, and `report` (the keys of a mesh in `simplify --json`).
pub fn result_dict<'py>(
    py: Python<'py>,
    u: Unwelded,
    run: &MeshRun,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = u.positions.len() / 3;
    let shaped = |v: Vec<f32>, w: usize| {
        Array2::from_shape_vec((v.len() / w.max(1), w), v)
            .map_err(|e| wildlod_error(py, format!("internal error: {e}"), false))
    };
    d.set_item("positions", shaped(u.positions, 3)?.into_pyarray(py))?;
    d.set_item("indices", u.indices.into_pyarray(py))?;
    d.set_item("face_sizes", u.sizes.into_pyarray(py))?;
    for (name, w, values) in u.attributes {
        d.set_item(name, shaped(values, w)?.into_pyarray(py))?;
    }
    if let Some((k, joints, weights)) = u.skin {
        let j = Array2::from_shape_vec((n, k), joints)
            .map_err(|e| wildlod_error(py, format!("internal error: {e}"), false))?;
        d.set_item("joints", j.into_pyarray(py))?;
        d.set_item("weights", shaped(weights, k)?.into_pyarray(py))?;
    }
    d.set_item("report", report_dict(py, &MeshJson::new(run))?)?;
    Ok(d)
}
