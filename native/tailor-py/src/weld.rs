//! `tailor.weld` and `tailor.WeldedMesh`: the sewn pieces as one mesh for export. The weld
//! itself is `tailor_core::weld`; this file converts.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::solver::{Seam, SeamPoint};
use tailor_core::weld as core;
use tailor_core::TailorError;

use crate::convert::{floats, indices, points3, triangles};
use crate::errors::to_py;
use crate::patterns::rows;

/// A garment welded into one mesh (`tailor.weld`, `Garment.welded`).
#[pyclass(module = "tailor", frozen)]
pub struct WeldedMesh {
    pub inner: core::WeldedMesh,
}

#[pymethods]
impl WeldedMesh {
    /// (k, 3) float32 welded vertex positions.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.positions))
    }

    /// (m, 3) uint32 triangles over the welded vertices.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.triangles))
    }

    /// (n,) uint32: the welded vertex of each input vertex.
    #[getter]
    fn vertex_map<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| Ok(PyArray1::from_vec(py, self.inner.vertex_map.clone()).into_any()))
    }

    /// (m,) uint32: the input triangle each welded triangle was cut from.
    #[getter]
    fn triangle_source<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| Ok(PyArray1::from_vec(py, self.inner.triangle_source.clone()).into_any()))
    }

    /// (m, 3, 3) float32: each welded corner's barycentric coordinates in its source triangle.
    #[getter]
    fn corner_weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let flat: Vec<f32> = self.inner.corner_weights.iter().flatten().flatten().copied().collect();
            Ok(PyArray1::from_vec(py, flat).reshape([self.inner.corner_weights.len(), 3, 3])?.into_any())
        })
    }

    #[getter]
    fn num_vertices(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.num_vertices()))
    }

    /// What the weld did: merged vertices, inserted seam points, split and collapsed
    /// triangles, flipped pieces, and the result's boundary, non-manifold and misoriented edges.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let s = &self.inner.stats;
            let d = PyDict::new(py);
            for (k, v) in [
                ("input_vertices", s.input_vertices),
                ("input_triangles", s.input_triangles),
                ("merged", s.merged),
                ("inserted_points", s.inserted_points),
                ("centroids", s.centroids),
                ("split_triangles", s.split_triangles),
                ("collapsed_triangles", s.collapsed_triangles),
                ("flipped_pieces", s.flipped_pieces),
                ("boundary_edges", s.boundary_edges),
                ("non_manifold_edges", s.non_manifold_edges),
                ("misoriented_edges", s.misoriented_edges),
            ] {
                d.set_item(k, v)?;
            }
            Ok(d)
        })
    }

    /// Welds one frame of the input vertices ((n, 3), e.g. a baked or PC2 frame) into (k, 3).
    fn apply<'py>(&self, py: Python<'py>, frame: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let f = points3(frame, "frame")?;
            let out = py.detach(|| self.inner.apply(&f)).map_err(to_py)?;
            rows(py, &out)
        })
    }

    /// Carries a per-corner attribute over: `values` is (3 × input triangles, d) float32, one
    /// row per input corner in triangle order (Blender's loops of triangles, e.g. UVs); returns
    /// (3 × welded triangles, d).
    fn apply_corners<'py>(&self, py: Python<'py>, values: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let np = py.import("numpy")?;
            let arr = np.call_method1("ascontiguousarray", (values, np.getattr("float32")?))?;
            let arr = arr
                .extract::<PyReadonlyArray2<f32>>()
                .map_err(|_| to_py(TailorError::shape("values", "expected a 2D array of shape (3 × triangles, d)")))?;
            let width = arr.shape()[1];
            let flat = arr.as_slice().map_err(|e| to_py(TailorError::shape("values", e.to_string())))?;
            let out = self.inner.apply_corners(flat, width).map_err(to_py)?;
            let rows_out = out.len() / width.max(1);
            Ok(PyArray1::from_vec(py, out).reshape([rows_out, width])?.into_any())
        })
    }

    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                let s = &self.inner.stats;
                format!(
                    "WeldedMesh({} vertices, {} triangles; {} merged, {} inserted, {} boundary edges)",
                    self.inner.num_vertices(),
                    self.inner.triangles.len(),
                    s.merged,
                    s.inserted_points,
                    s.boundary_edges
                )
            })
        })
    }
}

fn seam_from(d: &Bound<'_, PyAny>, index: usize, n: usize) -> PyResult<Seam> {
    let d = d.cast::<PyDict>().map_err(|_| {
        to_py(TailorError::shape(format!("seams[{index}]"), "expected a dict (as Simulation.seam_pairs() gives)"))
    })?;
    let name = match d.get_item("name")? {
        Some(v) => v.extract::<String>()?,
        None => format!("seam {index}"),
    };
    let get = |key: &str| {
        d.get_item(key)?
            .ok_or_else(|| to_py(TailorError::shape(format!("seam '{name}'"), format!("'{key}' is missing"))))
    };
    let side = |key: char| -> PyResult<Vec<SeamPoint>> {
        let label = format!("seam '{name}' side {}", key.to_ascii_uppercase());
        let np = d.py().import("numpy")?;
        let verts = indices(&np.call_method1("ravel", (get(&format!("{key}_vertices"))?,))?, &label, n)?;
        let weights = floats(&np.call_method1("ravel", (get(&format!("{key}_weights"))?,))?, &label)?;
        if verts.len() != weights.len() || verts.len() % 2 != 0 {
            return Err(to_py(TailorError::shape(label, "vertices and weights must both have shape (k, 2)")));
        }
        Ok(verts
            .chunks_exact(2)
            .zip(weights.chunks_exact(2))
            .map(|(v, w)| SeamPoint { verts: [v[0], v[1]], weights: [w[0], w[1]] })
            .collect())
    };
    let (a, b) = (side('a')?, side('b')?);
    if a.len() != b.len() {
        return Err(to_py(TailorError::InvalidSeam {
            seam: name,
            reason: format!("{} points on side A and {} on side B: pairs go row by row", a.len(), b.len()),
        }));
    }
    Ok(Seam { name, pairs: a.into_iter().zip(b).collect(), stiffness: 0.0, bend_stiffness: 0.0 })
}

/// Welds sewn pieces into one mesh: `positions` (n, 3) and `triangles` (m, 3) of all pieces
/// together, `seams` as `Simulation.seam_pairs()` returns them (dicts with `a_vertices`,
/// `a_weights`, `b_vertices`, `b_weights`, each (k, 2), and an optional `name`).
#[pyfunction]
pub fn weld(
    py: Python<'_>,
    positions: &Bound<'_, PyAny>,
    triangles_: &Bound<'_, PyAny>,
    seams: Vec<Bound<'_, PyAny>>,
) -> PyResult<WeldedMesh> {
    crate::errors::guard(|| {
        let p = points3(positions, "positions")?;
        let t = triangles(triangles_, "triangles")?;
        let s = seams.iter().enumerate().map(|(i, d)| seam_from(d, i, p.len())).collect::<PyResult<Vec<_>>>()?;
        let inner = py.detach(|| core::weld(&p, &t, &s)).map_err(to_py)?;
        Ok(WeldedMesh { inner })
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<WeldedMesh>()?;
    m.add_function(wrap_pyfunction!(weld, m)?)
}
