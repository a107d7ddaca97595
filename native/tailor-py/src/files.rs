//! `tailor.check_outputs`, `tailor.sidecar_path` and `tailor.check_playback`: the checks a
//! command runs before it starts (`tailor_core::files`, `garment_file`, `playback`).

use std::path::PathBuf;

use pyo3::prelude::*;
use tailor_core::{files, garment_file, playback};

use crate::errors::{guard, to_py};

/// Refuses, before a run, outputs that are (the same file as) an input or another output, a
/// folder, or in a folder that cannot be written. `inputs` and `outputs` are `(name, path)`
/// pairs, the name being what the user called the file (`"GARMENT_FILE"`, `"--report"`).
#[pyfunction]
pub fn check_outputs(inputs: Vec<(String, PathBuf)>, outputs: Vec<(String, PathBuf)>) -> PyResult<()> {
    guard(|| {
        let i: Vec<(&str, &std::path::Path)> = inputs.iter().map(|(n, p)| (n.as_str(), p.as_path())).collect();
        let o: Vec<(&str, &std::path::Path)> = outputs.iter().map(|(n, p)| (n.as_str(), p.as_path())).collect();
        files::check_outputs(&i, &o).map_err(to_py)
    })
}

/// The sidecar path `Garment.save(path)` writes beside `path` (`x.json` -> `x.bin`).
#[pyfunction]
pub fn sidecar_path(path: PathBuf) -> PyResult<PathBuf> {
    guard(|| Ok(garment_file::sidecar_path(&path)))
}

/// Checks a frame rate (positive, finite) and, when given, a frame count (at least 1),
/// raising `InvalidParameterError` naming `fps` or `frames`.
#[pyfunction]
#[pyo3(signature = (fps, frames=None))]
pub fn check_playback(fps: f64, frames: Option<i64>) -> PyResult<()> {
    guard(|| playback::check_playback(fps, frames).map_err(to_py))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_outputs, m)?)?;
    m.add_function(wrap_pyfunction!(sidecar_path, m)?)?;
    m.add_function(wrap_pyfunction!(check_playback, m)?)?;
    Ok(())
}
