//! `tailor.fabric_library()` and `tailor.Fabric.named`: the core's measured fabrics
//! (`tailor_core::fabrics`), their source's properties and the solver fabric each becomes.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::fabrics::{self as core, MeasuredFabric};

use crate::errors::{guard, to_py};
use crate::settings::Fabric;

impl From<tailor_core::solver::Fabric> for Fabric {
    fn from(f: tailor_core::solver::Fabric) -> Self {
        Fabric {
            density: f.density,
            stretch: f.stretch,
            shear: f.shear,
            bend: f.bend,
            stretch_v: f.stretch_v,
            bend_bias: f.bend_bias,
            bend_v: f.bend_v,
        }
    }
}

/// The solver fabric of the library's fabric `name` (InvalidParameterError naming the library's
/// fabrics for another name); `Fabric.named` calls it inside its guard.
pub fn named(name: &str) -> PyResult<Fabric> {
    core::named(name).map(|m| Fabric::from(m.fabric())).map_err(to_py)
}

fn entry<'py>(py: Python<'py>, m: &MeasuredFabric) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", m.name)?;
    d.set_item("description", m.description)?;
    d.set_item("density", m.density)?;
    d.set_item("stretch_u", m.stretch_u())?;
    d.set_item("stretch_v", m.stretch_v())?;
    d.set_item("shear", m.shear())?;
    let [u, b, v] = m.rigidities();
    d.set_item("rigidity_u", u)?;
    d.set_item("rigidity_bias", b)?;
    d.set_item("rigidity_v", v)?;
    d.set_item("rigidity", m.rigidity())?;
    d.set_item("fabric", Py::new(py, Fabric::from(m.fabric()))?)?;
    Ok(d)
}

/// Every fabric of the library, lightest first: `name`, `description`, `density` (kg/m²),
/// `stretch_u`, `stretch_v` and `shear` at 5 % strain (N/m), the flexural rigidities
/// `rigidity_u`, `rigidity_bias`, `rigidity_v` and their geometric mean `rigidity` (N·m), and
/// `fabric`, the solver's `Fabric` for it (anisotropic as measured: `stretch` along u,
/// `stretch_v`, and bending by the hinge's direction). Source and rules: `tailor_core::fabrics`
/// (docs/python-api.md, "Fabric library").
#[pyfunction]
pub fn fabric_library(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    guard(|| core::LIBRARY.iter().map(|m| entry(py, m)).collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fabric_library, m)?)?;
    m.add("HINGE_ENERGY_PER_RIGIDITY", core::HINGE_ENERGY_PER_RIGIDITY)?;
    Ok(())
}
