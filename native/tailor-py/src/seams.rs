//! `tailor.Seam`: the resolution-independent seam of `tailor_core::seam::model`, created from
//! picked contour paths and resolved against the current piece meshes.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::seam::{self as core, SeamMode};
use tailor_core::TailorError;

use crate::contour::{direction_name, ContourPath};
use crate::errors::to_py;
use crate::patterns::{rows, PieceMesh};

pub fn mode_name(m: SeamMode) -> &'static str {
    match m {
        SeamMode::Equal => "equal",
        SeamMode::Unequal => "unequal",
    }
}

fn parse_mode(s: &str) -> PyResult<SeamMode> {
    match s {
        "equal" => Ok(SeamMode::Equal),
        "unequal" => Ok(SeamMode::Unequal),
        _ => Err(to_py(TailorError::setting("mode", s, "must be \"equal\" or \"unequal\""))),
    }
}

fn meshes_of(meshes: &[PieceMesh]) -> Vec<tailor_core::triangulate::PieceMesh> {
    meshes.iter().map(|m| m.inner.clone()).collect()
}

/// A seam between two contour runs, stored by endpoint rest positions (it survives a change
/// of resolution). `mode`: "equal" (one-to-one) or "unequal" (arc-length pairing).
#[pyclass(module = "tailor", frozen, from_py_object)]
#[derive(Clone)]
pub struct Seam {
    pub inner: core::Seam,
}

fn side_dict<'py>(py: Python<'py>, s: &core::SeamSide) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("piece", s.piece)?;
    d.set_item("start", s.start.to_vec())?;
    d.set_item("end", s.end.to_vec())?;
    d.set_item("direction", direction_name(s.direction))?;
    Ok(d)
}

fn side_from_dict(d: &Bound<'_, PyDict>, label: &str) -> PyResult<core::SeamSide> {
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(key)?
            .ok_or_else(|| to_py(TailorError::setting("seam side", label, format!("needs the key \"{key}\""))))
    };
    let direction: String = get("direction")?.extract()?;
    Ok(core::SeamSide {
        piece: get("piece")?.extract()?,
        start: get("start")?.extract()?,
        end: get("end")?.extract()?,
        direction: crate::contour::parse_direction(&direction)?,
    })
}

#[pymethods]
impl Seam {
    /// A seam from its stored sides (dicts as `Seam.a` returns them: `piece`, `start`, `end`,
    /// `direction`), e.g. kept by a host application between sessions. It is checked against
    /// the meshes when resolved. `stiffness` and `bend_stiffness` are factors on the solver's
    /// seam stiffnesses.
    #[new]
    #[pyo3(signature = (name, a, b, mode="equal", stiffness=1.0, bend_stiffness=1.0))]
    fn new(
        name: &str,
        a: &Bound<'_, PyDict>,
        b: &Bound<'_, PyDict>,
        mode: &str,
        stiffness: f32,
        bend_stiffness: f32,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            for (v, n) in [(stiffness, "stiffness"), (bend_stiffness, "bend_stiffness")] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(to_py(TailorError::setting(
                        if n == "stiffness" { "stiffness" } else { "bend_stiffness" },
                        v,
                        "must be a finite factor of 0 or more",
                    )));
                }
            }
            let inner = core::Seam {
                name: name.to_string(),
                a: side_from_dict(a, "a")?,
                b: side_from_dict(b, "b")?,
                mode: parse_mode(mode)?,
                stiffness,
                bend_stiffness,
            };
            Ok(Self { inner })
        })
    }
    /// A validated seam from two picked paths (`piece_a`, `piece_b`: indices of the pieces in
    /// the list later passed to `resolve`).
    #[staticmethod]
    #[pyo3(signature = (name, piece_a, mesh_a, path_a, piece_b, mesh_b, path_b, mode="equal"))]
    #[allow(clippy::too_many_arguments)]
    fn from_paths(
        name: &str,
        piece_a: usize,
        mesh_a: &PieceMesh,
        path_a: &ContourPath,
        piece_b: usize,
        mesh_b: &PieceMesh,
        path_b: &ContourPath,
        mode: &str,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let mode = parse_mode(mode)?;
            let inner = core::Seam::from_paths(
                name,
                piece_a,
                &mesh_a.inner,
                &path_a.inner,
                piece_b,
                &mesh_b.inner,
                &path_b.inner,
                mode,
            )
            .map_err(to_py)?;
            Ok(Self { inner })
        })
    }
    #[getter]
    fn name(&self) -> PyResult<&str> {
        crate::errors::guard(|| Ok(self.inner.name.as_str()))
    }
    #[getter]
    fn mode(&self) -> PyResult<&'static str> {
        crate::errors::guard(|| Ok(mode_name(self.inner.mode)))
    }
    /// Side A: {"piece", "start", "end", "direction"} (rest positions, metres).
    #[getter]
    fn a<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| side_dict(py, &self.inner.a))
    }
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| side_dict(py, &self.inner.b))
    }
    /// Factors on the solver's seam stiffness and seam bending stiffness.
    #[getter]
    fn stiffness(&self) -> PyResult<f32> {
        crate::errors::guard(|| Ok(self.inner.stiffness))
    }
    #[getter]
    fn bend_stiffness(&self) -> PyResult<f32> {
        crate::errors::guard(|| Ok(self.inner.bend_stiffness))
    }
    /// Resolves (or remaps) the seam on `meshes` (indexed by piece). Returns a dict: `a`, `b`
    /// (ContourPath), `a_vertices`, `b_vertices` (piece-local indices), `mode`,
    /// `length_ratio`, and the sewn pairs as (p, 2) arrays `pair_a_vertices`,
    /// `pair_a_weights`, `pair_b_vertices`, `pair_b_weights` (piece-local; each row a point
    /// as two weighted vertices, as `Simulation.add_weighted_seam` takes them).
    fn resolve<'py>(&self, py: Python<'py>, meshes: Vec<PieceMesh>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let meshes = meshes_of(&meshes);
            let r = self.inner.resolve(&meshes).map_err(to_py)?;
            let (ma, mb) = (&meshes[r.piece_a], &meshes[r.piece_b]);
            let pairs = r.pairs(ma, mb).map_err(to_py)?;
            let d = PyDict::new(py);
            d.set_item("a_vertices", r.a.vertices(ma))?;
            d.set_item("b_vertices", r.b.vertices(mb))?;
            d.set_item("mode", mode_name(r.mode))?;
            d.set_item("length_ratio", r.length_ratio)?;
            let v = |p: &core::WeightedPoint| [p[0].0, p[1].0];
            let w = |p: &core::WeightedPoint| [p[0].1, p[1].1];
            d.set_item("pair_a_vertices", rows(py, &pairs.iter().map(|p| v(&p.a)).collect::<Vec<_>>())?)?;
            d.set_item("pair_a_weights", rows(py, &pairs.iter().map(|p| w(&p.a)).collect::<Vec<_>>())?)?;
            d.set_item("pair_b_vertices", rows(py, &pairs.iter().map(|p| v(&p.b)).collect::<Vec<_>>())?)?;
            d.set_item("pair_b_weights", rows(py, &pairs.iter().map(|p| w(&p.b)).collect::<Vec<_>>())?)?;
            d.set_item("a", ContourPath { inner: r.a })?;
            d.set_item("b", ContourPath { inner: r.b })?;
            Ok(d)
        })
    }
    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| Ok(format!("Seam({:?}, mode={:?})", self.inner.name, mode_name(self.inner.mode))))
    }
}
