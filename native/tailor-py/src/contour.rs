//! Contour helpers of the seam tool (`tailor.shortest_path`, `candidate_paths`,
//! `nearer_candidate`, `nearest_contour_position`, `find_corners`, `nearest_corner_segment`)
//! and the `ContourPath` they return: thin wrappers over `tailor_core::seam::paths`/`corners`.

use pyo3::prelude::*;
use tailor_core::seam::{self as core, Direction};
use tailor_core::TailorError;

use crate::errors::to_py;
use crate::patterns::PieceMesh;

pub fn direction_name(d: Direction) -> &'static str {
    match d {
        Direction::Ccw => "ccw",
        Direction::Cw => "cw",
    }
}

pub fn parse_direction(s: &str) -> PyResult<Direction> {
    match s.to_ascii_lowercase().as_str() {
        "ccw" => Ok(Direction::Ccw),
        "cw" => Ok(Direction::Cw),
        _ => Err(to_py(TailorError::setting("direction", s, "must be \"ccw\" or \"cw\""))),
    }
}

/// A run of contour positions walked in one direction ("ccw" or "cw").
#[pyclass(module = "tailor", frozen, from_py_object)]
#[derive(Clone)]
pub struct ContourPath {
    pub inner: core::ContourPath,
}

#[pymethods]
impl ContourPath {
    #[new]
    #[pyo3(signature = (positions, direction="ccw"))]
    fn new(positions: Vec<usize>, direction: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            Ok(Self { inner: core::ContourPath { positions, direction: parse_direction(direction)? } })
        })
    }
    #[getter]
    fn positions(&self) -> PyResult<Vec<usize>> {
        crate::errors::guard(|| Ok(self.inner.positions.clone()))
    }
    #[getter]
    fn direction(&self) -> PyResult<&'static str> {
        crate::errors::guard(|| Ok(direction_name(self.inner.direction)))
    }
    /// The mesh vertices of the path, in order (positions must be on `mesh`'s contour).
    fn vertices(&self, mesh: &PieceMesh) -> PyResult<Vec<u32>> {
        crate::errors::guard(|| {
            let n = mesh.inner.contour.len();
            if let Some(&p) = self.inner.positions.iter().find(|&&p| p >= n) {
                return Err(to_py(TailorError::index("contour path", p as i64, n, "contour vertices")));
            }
            Ok(self.inner.vertices(&mesh.inner))
        })
    }
    /// Rest arc length, metres.
    fn length(&self, mesh: &PieceMesh) -> PyResult<f64> {
        crate::errors::guard(|| {
            self.vertices(mesh)?;
            Ok(self.inner.length(&mesh.inner))
        })
    }
    fn __len__(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.len()))
    }
    fn __eq__(&self, other: &Self) -> PyResult<bool> {
        crate::errors::guard(|| Ok(self.inner == other.inner))
    }
    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok(format!("ContourPath({:?}, {:?})", self.inner.positions, direction_name(self.inner.direction)))
        })
    }
}

fn wrap(r: tailor_core::Result<core::ContourPath>) -> PyResult<ContourPath> {
    r.map(|inner| ContourPath { inner }).map_err(to_py)
}

/// The contour position nearest `point` (rest frame, metres): steps 1 and 4 of the seam tool.
#[pyfunction]
pub fn nearest_contour_position(mesh: &PieceMesh, point: (f32, f32)) -> PyResult<usize> {
    crate::errors::guard(|| Ok(core::nearest_contour_position(&mesh.inner, [point.0, point.1])))
}

/// The shorter contour path from position `start` to position `end` (steps 2-3).
#[pyfunction]
pub fn shortest_path(mesh: &PieceMesh, start: usize, end: usize) -> PyResult<ContourPath> {
    crate::errors::guard(|| wrap(core::shortest_path(&mesh.inner, start, end)))
}

/// The two `n`-vertex paths from position `b1`: (counter-clockwise, clockwise) (step 5).
#[pyfunction]
pub fn candidate_paths(mesh: &PieceMesh, b1: usize, n: usize) -> PyResult<(ContourPath, ContourPath)> {
    crate::errors::guard(|| {
        let [a, b] = core::candidate_paths(&mesh.inner, b1, n).map_err(to_py)?;
        Ok((ContourPath { inner: a }, ContourPath { inner: b }))
    })
}

/// Of the two `n`-vertex paths from `b1`, the one ending nearer `point` (step 5).
#[pyfunction]
pub fn nearer_candidate(mesh: &PieceMesh, b1: usize, n: usize, point: (f32, f32)) -> PyResult<ContourPath> {
    crate::errors::guard(|| wrap(core::nearer_candidate(&mesh.inner, b1, n, [point.0, point.1])))
}

/// Contour positions whose contour angle is under `max_angle_deg` (180° = straight).
#[pyfunction]
#[pyo3(signature = (mesh, max_angle_deg=150.0))]
pub fn find_corners(mesh: &PieceMesh, max_angle_deg: f64) -> PyResult<Vec<usize>> {
    crate::errors::guard(|| Ok(core::find_corners(&mesh.inner, max_angle_deg)))
}

/// The counter-clockwise run between the two `corners` around the contour edge nearest `point`.
#[pyfunction]
pub fn nearest_corner_segment(mesh: &PieceMesh, corners: Vec<usize>, point: (f32, f32)) -> PyResult<ContourPath> {
    crate::errors::guard(|| wrap(core::nearest_corner_segment(&mesh.inner, &corners, [point.0, point.1])))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<ContourPath>()?;
    m.add_function(wrap_pyfunction!(nearest_contour_position, m)?)?;
    m.add_function(wrap_pyfunction!(shortest_path, m)?)?;
    m.add_function(wrap_pyfunction!(candidate_paths, m)?)?;
    m.add_function(wrap_pyfunction!(nearer_candidate, m)?)?;
    m.add_function(wrap_pyfunction!(find_corners, m)?)?;
    m.add_function(wrap_pyfunction!(nearest_corner_segment, m)?)
}
