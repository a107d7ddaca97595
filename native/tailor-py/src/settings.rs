//! `tailor.Fabric` and `tailor.Settings`: plain value objects mirroring the core's settings.
//! Validation happens in the core when they are applied, so errors are the core's.

use pyo3::prelude::*;
use tailor_core::solver::{self as core, Method};
use tailor_core::TailorError;

use crate::errors::to_py;

/// Material of a garment piece (SI units). `u` is the pattern's x axis, `v` its y axis;
/// `stretch_v`, `bend_bias` and `bend_v` make it anisotropic (None: isotropic; the core's
/// `Fabric` documents the directions).
#[pyclass(module = "tailor", get_all, set_all, from_py_object)]
#[derive(Clone)]
pub struct Fabric {
    /// Area density, kg/m².
    pub density: f32,
    /// Stretch stiffness along u (and v unless `stretch_v`), N/m.
    pub stretch: f32,
    /// Shear stiffness, N/m.
    pub shear: f32,
    /// Bending stiffness of the quadratic hinge model (hinges along u, and all unless
    /// `bend_bias`/`bend_v`): a flexural rigidity of 3 × bend N·m (`HINGE_ENERGY_PER_RIGIDITY`;
    /// the fabric library's fabrics convert so).
    pub bend: f32,
    /// Stretch stiffness along v, N/m (None: `stretch`).
    pub stretch_v: Option<f32>,
    /// Bending stiffness of hinges on the bias (None: the mean of u's and v's).
    pub bend_bias: Option<f32>,
    /// Bending stiffness of hinges along v (None: `bend`).
    pub bend_v: Option<f32>,
}

#[pymethods]
impl Fabric {
    #[new]
    #[pyo3(signature = (density=None, stretch=None, shear=None, bend=None, *, stretch_v=None, bend_bias=None, bend_v=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        density: Option<f32>,
        stretch: Option<f32>,
        shear: Option<f32>,
        bend: Option<f32>,
        stretch_v: Option<f32>,
        bend_bias: Option<f32>,
        bend_v: Option<f32>,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            Ok({
                let d = core::Fabric::default();
                Self {
                    density: density.unwrap_or(d.density),
                    stretch: stretch.unwrap_or(d.stretch),
                    shear: shear.unwrap_or(d.shear),
                    bend: bend.unwrap_or(d.bend),
                    stretch_v,
                    bend_bias,
                    bend_v,
                }
            })
        })
    }

    /// The stiffness in each direction as the solver takes it (the core's rule for the `None`
    /// directions): `{"stretch_u", "stretch_v", "bend_u", "bend_bias", "bend_v"}`.
    fn directions(&self) -> PyResult<std::collections::HashMap<&'static str, f32>> {
        crate::errors::guard(|| {
            let f = core::Fabric::from(self);
            let ([su, sv], [bu, bb, bv]) = (f.stretch_uv(), f.bend_directions());
            Ok([("stretch_u", su), ("stretch_v", sv), ("bend_u", bu), ("bend_bias", bb), ("bend_v", bv)].into())
        })
    }

    /// The fabric library's fabric `name` as the solver's fabric (`tailor.fabric_library()`
    /// lists them with their measured properties).
    #[staticmethod]
    fn named(name: &str) -> PyResult<Self> {
        crate::errors::guard(|| crate::fabrics::named(name))
    }

    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                let mut s = format!(
                    "Fabric(density={}, stretch={}, shear={}, bend={}",
                    self.density, self.stretch, self.shear, self.bend
                );
                for (name, v) in [("stretch_v", self.stretch_v), ("bend_bias", self.bend_bias), ("bend_v", self.bend_v)]
                {
                    if let Some(v) = v {
                        s += &format!(", {name}={v}");
                    }
                }
                s + ")"
            })
        })
    }
}

impl From<&Fabric> for core::Fabric {
    fn from(f: &Fabric) -> Self {
        core::Fabric {
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

/// Solver settings. `method` is "chebyshev", "gauss_seidel" or "jacobi".
#[pyclass(module = "tailor", get_all, set_all, from_py_object)]
#[derive(Clone)]
pub struct Settings {
    pub substeps: u32,
    pub iterations: u32,
    /// Stop a substep when the force the last sweep corrected is under this fraction of the
    /// larger of its first value and the cloth's weight (0 = always run `iterations`).
    pub tolerance: f32,
    pub method: String,
    pub gravity: [f32; 3],
    /// Base air damping, 1/s.
    pub air_damping: f32,
    pub ramp_enabled: bool,
    pub ramp_closing_damping: f32,
    pub ramp_gap_threshold: f32,
    pub ramp_closed_fraction: f32,
    /// The widest seam pair must be within this (m) for the release, too.
    pub ramp_release_gap: f32,
    pub ramp_release_time: f32,
    /// Speed at which sewn points are drawn together, m/s (0 = at once).
    pub ramp_closing_speed: f32,
    /// Factor on gravity while seams close (0 = the pieces stay where placed until sewn).
    pub ramp_closing_gravity: f32,
    /// Stiffness (N/m) with which the body holds the cloth near it while seams close (0 = none).
    pub ramp_closing_hold: f32,
    /// Cloth within this distance (m) of a mesh collider is held while seams close.
    pub ramp_closing_hold_distance: f32,
    /// Fixed Chebyshev spectral radius; None = measured automatically.
    pub chebyshev_rho: Option<f32>,
    pub colouring_seed: u64,
    /// The two-level global step: a coarse-grid correction after every sweep, so that bending
    /// and large-scale stretch converge (on the CPU and the GPU).
    pub two_level: bool,
}

/// The settings' field names, as the errors of `Settings(**kwargs)` name them.
const SETTINGS_FIELDS: &[&str] = &[
    "substeps",
    "iterations",
    "tolerance",
    "method",
    "gravity",
    "air_damping",
    "ramp_enabled",
    "ramp_closing_damping",
    "ramp_gap_threshold",
    "ramp_closed_fraction",
    "ramp_release_gap",
    "ramp_release_time",
    "ramp_closing_speed",
    "ramp_closing_gravity",
    "ramp_closing_hold",
    "ramp_closing_hold_distance",
    "chebyshev_rho",
    "colouring_seed",
    "two_level",
];

#[pymethods]
impl Settings {
    #[new]
    #[pyo3(signature = (**kwargs))]
    fn new(py: Python<'_>, kwargs: Option<&Bound<'_, pyo3::types::PyDict>>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let obj = Bound::new(py, Self::from(&core::SolverSettings::default()))?;
            if let Some(kw) = kwargs {
                for (k, v) in kw.iter() {
                    let name: String = k.extract()?;
                    if !obj.hasattr(name.as_str())? {
                        return Err(pyo3::exceptions::PyTypeError::new_err(format!("Settings has no field {name:?}")));
                    }
                    // pyo3's own conversion error (OverflowError for substeps=-1, TypeError for a
                    // string) becomes InvalidParameterError naming the setting.
                    if let Err(e) = obj.setattr(name.as_str(), &v) {
                        let field = SETTINGS_FIELDS.iter().find(|f| **f == name).copied().unwrap_or("Settings");
                        let value = v.repr().map(|r| r.to_string()).unwrap_or_default();
                        return Err(to_py(TailorError::setting(field, value, format!("not accepted: {e}"))));
                    }
                }
            }
            let out = obj.borrow().clone();
            Ok(out)
        })
    }

    /// A quality preset of the core ("preview" or "final"): substeps, iterations and
    /// tolerance chosen from the run-time-against-error benchmark (docs/accuracy.md).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        crate::errors::guard(|| Ok(Self::from(&core::SolverSettings::preset(name).map_err(to_py)?)))
    }

    /// The preset names, fastest first.
    #[staticmethod]
    fn presets() -> PyResult<Vec<&'static str>> {
        crate::errors::guard(|| Ok(core::PRESETS.to_vec()))
    }

    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                format!(
                    "Settings(substeps={}, iterations={}, tolerance={}, method={:?}, gravity={:?}, air_damping={})",
                    self.substeps, self.iterations, self.tolerance, self.method, self.gravity, self.air_damping
                )
            })
        })
    }
}

impl From<&core::SolverSettings> for Settings {
    fn from(s: &core::SolverSettings) -> Self {
        Self {
            substeps: s.substeps,
            iterations: s.iterations,
            tolerance: s.tolerance,
            method: method_name(s.method).into(),
            gravity: s.gravity,
            air_damping: s.air_damping,
            ramp_enabled: s.ramp.enabled,
            ramp_closing_damping: s.ramp.closing_damping,
            ramp_gap_threshold: s.ramp.gap_threshold,
            ramp_closed_fraction: s.ramp.closed_fraction,
            ramp_release_gap: s.ramp.release_gap,
            ramp_release_time: s.ramp.release_time,
            ramp_closing_speed: s.ramp.closing_speed,
            ramp_closing_gravity: s.ramp.closing_gravity,
            ramp_closing_hold: s.ramp.closing_hold,
            ramp_closing_hold_distance: s.ramp.closing_hold_distance,
            chebyshev_rho: s.chebyshev.rho,
            colouring_seed: s.colouring_seed,
            two_level: s.two_level,
        }
    }
}

impl Settings {
    pub fn to_core(&self) -> PyResult<core::SolverSettings> {
        let d = core::SolverSettings::default();
        Ok(core::SolverSettings {
            substeps: self.substeps,
            iterations: self.iterations,
            tolerance: self.tolerance,
            method: parse_method(&self.method)?,
            gravity: self.gravity,
            air_damping: self.air_damping,
            ramp: core::SeamRamp {
                enabled: self.ramp_enabled,
                closing_damping: self.ramp_closing_damping,
                gap_threshold: self.ramp_gap_threshold,
                closed_fraction: self.ramp_closed_fraction,
                release_gap: self.ramp_release_gap,
                release_time: self.ramp_release_time,
                closing_speed: self.ramp_closing_speed,
                closing_gravity: self.ramp_closing_gravity,
                closing_hold: self.ramp_closing_hold,
                closing_hold_distance: self.ramp_closing_hold_distance,
            },
            chebyshev: core::ChebyshevSettings { rho: self.chebyshev_rho, ..d.chebyshev },
            colouring_seed: self.colouring_seed,
            two_level: self.two_level,
            ..d
        })
    }
}

pub fn parse_method(name: &str) -> PyResult<Method> {
    match name {
        "chebyshev" => Ok(Method::Chebyshev),
        "gauss_seidel" => Ok(Method::GaussSeidel),
        "jacobi" => Ok(Method::Jacobi),
        other => {
            Err(to_py(TailorError::setting("method", other, "expected \"chebyshev\", \"gauss_seidel\" or \"jacobi\"")))
        }
    }
}

pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::Chebyshev => "chebyshev",
        Method::GaussSeidel => "gauss_seidel",
        Method::Jacobi => "jacobi",
    }
}
