//! Conversions for `tailor.Garment`'s setup: the typed `GarmentSetup` as a Python dict (through
//! JSON, so the dict has exactly the manifest's keys and every unknown key is refused by the
//! core's serde), painted maps as numpy arrays, pin groups as (particles, stiffness).

use numpy::PyArray1;
use pyo3::prelude::*;
use tailor_core::garment::PinGroup;
use tailor_core::garment_file::setup::maps;
use tailor_core::garment_file::{GarmentSetup, ParticleValues};
use tailor_core::TailorError;

use crate::convert::{floats, ints, points3};
use crate::errors::to_py;

/// The setup as a dict (the manifest's `setup` object).
pub fn to_dict<'py>(py: Python<'py>, setup: &GarmentSetup) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(setup).map_err(|e| to_py(TailorError::shape("garment setup", e.to_string())))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A setup from a dict: keys as `to_dict` gives them; missing keys take their defaults.
pub fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<GarmentSetup> {
    // JSON has no NaN: name the value here rather than let serde say "line 1 column 304".
    if let Some((path, v)) = non_finite(d, "setup")? {
        return Err(to_py(TailorError::setting("setup", v, format!("{path} must be finite"))));
    }
    let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
    serde_json::from_str(&text).map_err(|e| to_py(TailorError::setting("setup", "dict", e.to_string())))
}

/// The first float that is not finite in a dict or list (its key path and value).
fn non_finite(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Option<(String, f64)>> {
    use pyo3::types::{PyDict, PyFloat, PyList, PyTuple};
    if let Ok(d) = obj.cast::<PyDict>() {
        for (k, v) in d.iter() {
            if let Some(found) = non_finite(&v, &format!("{path}.{k}"))? {
                return Ok(Some(found));
            }
        }
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        for (i, v) in obj.try_iter()?.enumerate() {
            if let Some(found) = non_finite(&v?, &format!("{path}[{i}]"))? {
                return Ok(Some(found));
            }
        }
    } else if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract()?;
        if !x.is_finite() {
            return Ok(Some((path.to_string(), x)));
        }
    }
    Ok(None)
}

/// The values of painted map `name` for a piece of `count` vertices: floats (pin, friction,
/// scales), integers (collision levels) or (count, 3) floats (positions). `painted` (bools,
/// optional) marks where the map is painted; elsewhere the setup's unpainted value.
pub fn values(
    name: &str,
    obj: &Bound<'_, PyAny>,
    painted: Option<&Bound<'_, PyAny>>,
    count: usize,
    setup: &GarmentSetup,
) -> PyResult<ParticleValues> {
    if !maps::ALL.contains(&name) {
        return Err(to_py(TailorError::setting("painted map", name, format!("expected one of {:?}", maps::ALL))));
    }
    let wrong =
        |n: usize| to_py(TailorError::shape(format!("painted '{name}'"), format!("{n} values for {count} vertices")));
    if name == maps::POSITION {
        let v = points3(obj, "positions")?;
        if v.len() != count {
            return Err(wrong(v.len()));
        }
        return Ok(ParticleValues::Vec3(v));
    }
    let mask = painted.map(|m| ints(m, "painted")).transpose()?.map(|(v, _)| v);
    if let Some(m) = &mask {
        if m.len() != count {
            return Err(wrong(m.len()));
        }
    }
    let keep = |k: usize| mask.as_ref().is_none_or(|m| m[k] != 0);
    if name == maps::COLLISION_LEVEL {
        let v = crate::colliders::levels(obj, "collision levels")?;
        if v.len() != count {
            return Err(wrong(v.len()));
        }
        return Ok(ParticleValues::I32(v.iter().enumerate().map(|(k, &l)| if keep(k) { l } else { 0 }).collect()));
    }
    let v = floats(obj, name)?;
    if v.len() != count {
        return Err(wrong(v.len()));
    }
    let unpainted = setup.unpainted(name);
    Ok(ParticleValues::F32(v.iter().enumerate().map(|(k, &x)| if keep(k) { x } else { unpainted }).collect()))
}

/// A painted map's values as a numpy array ((n, 3) for positions).
pub fn to_numpy<'py>(py: Python<'py>, values: &ParticleValues) -> PyResult<Bound<'py, PyAny>> {
    Ok(match values {
        ParticleValues::F32(v) => PyArray1::from_slice(py, v).into_any(),
        ParticleValues::I32(v) => PyArray1::from_slice(py, v).into_any(),
        ParticleValues::Bool(v) => PyArray1::from_slice(py, v).into_any(),
        ParticleValues::Vec3(v) => crate::patterns::rows(py, v)?,
    })
}

/// Pin groups as `[(particles int64 array, stiffness N/m)]`.
pub fn groups<'py>(py: Python<'py>, groups: &[PinGroup]) -> Vec<(Bound<'py, PyAny>, f32)> {
    groups
        .iter()
        .map(|g| {
            let p: Vec<i64> = g.particles.iter().map(|&i| i as i64).collect();
            (PyArray1::from_vec(py, p).into_any(), g.stiffness)
        })
        .collect()
}
