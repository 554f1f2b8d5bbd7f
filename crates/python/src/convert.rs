//! Between Python and the library: errors as exceptions, keyword options
//! as [`Tuning`], reports as dicts.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use wildlod_pipeline::{NormalSetting, SeamSetting, Tuning};

/// The names `**options` accepts: the fields of [`Tuning`], and
/// `normal_mode` for `normals` (in `simplify`, `normals` is the stream).
pub const OPTION_NAMES: [&str; 32] = [
    "virtual_radius",
    "keep_topology",
    "lock_borders",
    "max_normal_turn",
    "no_quads",
    "quad_epsilon",
    "quad_tie_factor",
    "quad_tolerance",
    "tangent_weight",
    "symmetry",
    "area_floor",
    "pinch_cost",
    "pinch_distance",
    "area_exponent",
    "face_weight_floor",
    "crease_weight",
    "crease_angle",
    "crease_area_weight",
    "current_faces",
    "refit_sweeps",
    "keep_hidden_twins",
    "keep_enclosed_parts",
    "no_layers",
    "classic",
    "uv_weight",
    "normal_weight",
    "color_weight",
    "skin_weight",
    "seams",
    "seam_weight",
    "normals",
    "normal_mode",
];

/// The message of an error and of every error below it, joined by ": "
/// (what the CLI prints).
fn chain_message(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut next = e.source();
    while let Some(inner) = next {
        s.push_str(": ");
        s.push_str(&inner.to_string());
        next = inner.source();
    }
    s
}

/// A `wildlod.WildlodError` (a `ValueError`) with `message`, or a
/// `wildlod.WildlodOSError` (also an `OSError`) when `os` is set. The
/// classes live in `wildlod/_errors.py`, so the package's pure Python
/// parts raise the same ones.
pub fn wildlod_error(py: Python<'_>, message: String, os: bool) -> PyErr {
    let class = py
        .import("wildlod._errors")
        .and_then(|m| m.getattr(if os { "WildlodOSError" } else { "WildlodError" }));
    match class {
        Ok(class) => match class.call1((message.clone(),)) {
            Ok(instance) => PyErr::from_value(instance),
            Err(e) => e,
        },
        // Only when the package is broken: say so rather than hide it.
        Err(e) => e,
    }
}

/// A library error as a Python exception.
pub fn to_pyerr(py: Python<'_>, e: wildlod_pipeline::Error) -> PyErr {
    wildlod_error(py, chain_message(&e), e.is_os_error())
}

/// A simplifier error (arrays refused) as a Python exception.
pub fn simplify_error(py: Python<'_>, e: wildlod_simplify::Error) -> PyErr {
    wildlod_error(py, chain_message(&e), false)
}

/// [`Tuning`] from `**options`: unknown names are a `TypeError` (as for
/// any unexpected keyword argument), wrong types too; ranges are checked
/// later by the library.
pub fn tuning(py: Python<'_>, options: Option<&Bound<'_, PyDict>>) -> PyResult<Tuning> {
    let mut t = Tuning::default();
    let Some(options) = options else {
        return Ok(t);
    };
    for (key, value) in options.iter() {
        let name: String = key.extract()?;
        match name.as_str() {
            "virtual_radius" => t.virtual_radius = value.extract()?,
            "keep_topology" => t.keep_topology = value.extract()?,
            "lock_borders" => t.lock_borders = value.extract()?,
            "max_normal_turn" => t.max_normal_turn = value.extract()?,
            "no_quads" => t.no_quads = value.extract()?,
            "quad_epsilon" => t.quad_epsilon = value.extract()?,
            "quad_tie_factor" => t.quad_tie_factor = value.extract()?,
            "quad_tolerance" => t.quad_tolerance = value.extract()?,
            "tangent_weight" => t.tangent_weight = value.extract()?,
            "symmetry" => t.symmetry = value.extract()?,
            "area_floor" => t.area_floor = value.extract()?,
            "pinch_cost" => t.pinch_cost = value.extract()?,
            "pinch_distance" => t.pinch_distance = value.extract()?,
            "area_exponent" => t.area_exponent = value.extract()?,
            "face_weight_floor" => t.face_weight_floor = value.extract()?,
            "crease_weight" => t.crease_weight = value.extract()?,
            "crease_angle" => t.crease_angle = value.extract()?,
            "crease_area_weight" => t.crease_area_weight = value.extract()?,
            "current_faces" => t.current_faces = value.extract()?,
            "refit_sweeps" => t.refit_sweeps = value.extract()?,
            "keep_hidden_twins" => t.keep_hidden_twins = value.extract()?,
            "keep_enclosed_parts" => t.keep_enclosed_parts = value.extract()?,
            "no_layers" => t.no_layers = value.extract()?,
            "classic" => t.classic = value.extract()?,
            "uv_weight" => t.uv_weight = value.extract()?,
            "normal_weight" => t.normal_weight = value.extract()?,
            "color_weight" => t.color_weight = value.extract()?,
            "skin_weight" => t.skin_weight = value.extract()?,
            "seam_weight" => t.seam_weight = value.extract()?,
            "seams" => {
                let s: String = value.extract()?;
                t.seams = match s.as_str() {
                    "penalize" => SeamSetting::Penalize,
                    "keep" => SeamSetting::Keep,
                    "ignore" => SeamSetting::Ignore,
                    _ => {
                        return Err(wildlod_error(
                            py,
                            format!("seams must be 'penalize', 'keep' or 'ignore', got {s:?}"),
                            false,
                        ))
                    }
                }
            }
            "normals" | "normal_mode" => {
                let s: String = value.extract()?;
                t.normals = match s.as_str() {
                    "fit" => NormalSetting::Fit,
                    "recompute" => NormalSetting::Recompute,
                    _ => {
                        return Err(wildlod_error(
                            py,
                            format!("{name} must be 'fit' or 'recompute', got {s:?}"),
                            false,
                        ))
                    }
                }
            }
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "unexpected option {name:?}; the options are {}",
                    OPTION_NAMES.join(", ")
                )))
            }
        }
    }
    Ok(t)
}

/// A JSON value as Python objects (dicts, lists, numbers, strings, None).
pub fn to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_u64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(to_py(py, x)?)?;
            }
            list.into_any()
        }
        Value::Object(o) => {
            let dict = PyDict::new(py);
            for (k, x) in o {
                dict.set_item(k, to_py(py, x)?)?;
            }
            dict.into_any()
        }
    })
}

/// A report (any serializable value) as a dict.
pub fn report_dict<'py, T: serde::Serialize>(
    py: Python<'py>,
    report: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let v =
        serde_json::to_value(report).map_err(|e| to_pyerr(py, wildlod_pipeline::Error::Json(e)))?;
    to_py(py, &v)
}
