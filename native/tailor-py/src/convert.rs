//! numpy ⇄ Rust conversions at the boundary.
//!
//! Inputs accept any array-like; C-contiguous arrays of the right dtype are read in place
//! (no intermediate copy), anything else goes through `numpy.ascontiguousarray` once. Shapes
//! and index ranges are checked here so that errors name the argument and the element.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use tailor_core::solver::Vec3Soa;
use tailor_core::TailorError;

use crate::errors::to_py;

/// `obj` as a C-contiguous numpy array of `dtype`. numpy's own error for something that is not
/// an array of numbers (a string, a ragged list, a value out of the dtype's range) becomes a
/// `TailorError` naming the argument, as the docs promise for every error.
fn contiguous<'py>(obj: &Bound<'py, PyAny>, dtype: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    np.call_method1("ascontiguousarray", (obj, np.getattr(dtype)?))
        .map_err(|e| shape_err(name, format!("expected an array of numbers ({dtype}): {e}")))
}

/// `obj` (any array-like) flattened to one dimension, for arguments given as `(k, 2)` rows.
pub fn flattened<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    np.call_method1("ravel", (obj,)).map_err(|e| shape_err(name, format!("expected an array: {e}")))
}

fn shape_err(name: &str, reason: String) -> PyErr {
    to_py(TailorError::shape(name, reason))
}

/// Reads an `(n, K)` float32 array into rows.
fn rows_f32<const K: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f32; K]>> {
    let arr = match obj.extract::<PyReadonlyArray2<f32>>() {
        Ok(a) if a.is_c_contiguous() => a,
        _ => contiguous(obj, "float32", name)?
            .extract::<PyReadonlyArray2<f32>>()
            .map_err(|_| shape_err(name, format!("expected a 2D array of shape (n, {K})")))?,
    };
    let shape = arr.shape();
    if shape[1] != K {
        return Err(shape_err(name, format!("expected shape (n, {K}), got ({}, {})", shape[0], shape[1])));
    }
    let flat = arr.as_slice().map_err(|e| shape_err(name, e.to_string()))?;
    Ok(flat.chunks_exact(K).map(|c| std::array::from_fn(|k| c[k])).collect())
}

pub fn points3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f32; 3]>> {
    rows_f32::<3>(obj, name)
}

pub fn points2(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f32; 2]>> {
    rows_f32::<2>(obj, name)
}

/// A 1D float32 array.
pub fn floats(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f32>> {
    let arr = match obj.extract::<PyReadonlyArray1<f32>>() {
        Ok(a) => a,
        Err(_) => contiguous(obj, "float32", name)?
            .extract::<PyReadonlyArray1<f32>>()
            .map_err(|_| shape_err(name, "expected a 1D array of numbers".into()))?,
    };
    Ok(arr.as_array().iter().copied().collect())
}

/// Integer indices (any integer dtype), checked to be non-negative and below `len` when given.
pub fn ints(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<i64>, Vec<usize>)> {
    let arr = contiguous(obj, "int64", name)?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let flat = arr.call_method1("reshape", (-1,))?;
    let flat = flat.extract::<PyReadonlyArray1<i64>>().map_err(|_| shape_err(name, "expected integers".into()))?;
    Ok((flat.as_array().to_vec(), shape))
}

fn check_index(v: i64, len: Option<usize>, name: &str, pos: String) -> PyResult<u32> {
    match len {
        Some(n) if v < 0 || v as usize >= n => {
            Err(to_py(TailorError::index(format!("{name} {pos}"), v, n, "vertices")))
        }
        None if v < 0 || v > u32::MAX as i64 => {
            Err(to_py(TailorError::index(format!("{name} {pos}"), v, u32::MAX as usize, "allowed")))
        }
        _ => Ok(v as u32),
    }
}

/// A 1D array of indices below `len`.
pub fn indices(obj: &Bound<'_, PyAny>, name: &str, len: usize) -> PyResult<Vec<u32>> {
    let (v, shape) = ints(obj, name)?;
    if shape.len() != 1 {
        return Err(shape_err(name, format!("expected a 1D array of indices, got shape {shape:?}")));
    }
    v.iter().enumerate().map(|(k, &i)| check_index(i, Some(len), name, format!("entry {k}"))).collect()
}

/// An `(m, 3)` triangle array (range-checked later by the mesh, which names the triangle).
pub fn triangles(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[u32; 3]>> {
    let (v, shape) = ints(obj, name)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(shape_err(name, format!("expected shape (m, 3), got {shape:?}")));
    }
    v.chunks_exact(3)
        .enumerate()
        .map(|(t, c)| {
            let mut out = [0u32; 3];
            for k in 0..3 {
                out[k] = check_index(c[k], None, name, format!("triangle {t}"))?;
            }
            Ok(out)
        })
        .collect()
}

/// A new `(n, 3)` float32 array from structure-of-arrays storage (one copy).
pub fn soa_to_numpy<'py>(py: Python<'py>, v: &Vec3Soa) -> PyResult<Bound<'py, PyAny>> {
    let mut flat = vec![0.0f32; 3 * v.len()];
    v.write_interleaved(&mut flat);
    Ok(PyArray1::from_vec(py, flat).reshape([v.len(), 3])?.into_any())
}

/// A new 1D float32 array.
pub fn vec_to_numpy<'py>(py: Python<'py>, v: Vec<f32>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

/// A new 1D float64 array.
pub fn vec64_to_numpy<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}
