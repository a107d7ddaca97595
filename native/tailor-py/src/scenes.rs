//! Procedural scenes for the demo and tests (`tailor.sewn_tube`).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::scenes;

use numpy::PyArrayMethods;

use crate::convert::soa_to_numpy;
use crate::errors::to_py;

/// Two rectangular panels facing each other `gap` metres apart, to be sewn along both sides
/// into a tube. Returns positions, rest, triangles and the seams as (name, a, b) index arrays.
#[pyfunction]
#[pyo3(signature = (width=0.5, height=0.6, edge=0.02, gap=0.1, bottom=0.0, seam_stiffness=1000.0))]
pub fn sewn_tube<'py>(
    py: Python<'py>,
    width: f32,
    height: f32,
    edge: f32,
    gap: f32,
    bottom: f32,
    seam_stiffness: f32,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let tube = scenes::sewn_tube(width, height, edge, gap, bottom, seam_stiffness).map_err(to_py)?;
        let d = PyDict::new(py);
        let m = &tube.mesh;
        d.set_item("positions", soa_to_numpy(py, &tailor_core::solver::Vec3Soa::from_aos(m.positions()))?)?;
        let rest: Vec<f32> = m.rest().iter().flatten().copied().collect();
        d.set_item("rest", numpy::PyArray1::from_vec(py, rest).reshape([m.num_vertices(), 2])?)?;
        let tris: Vec<u32> = m.triangles().iter().flatten().copied().collect();
        d.set_item("triangles", numpy::PyArray1::from_vec(py, tris).reshape([m.num_triangles(), 3])?)?;
        let seams: Vec<(String, Vec<u32>, Vec<u32>)> = tube
            .seams
            .iter()
            .map(|s| {
                (
                    s.name.clone(),
                    s.pairs.iter().map(|p| p.0.verts[0]).collect(),
                    s.pairs.iter().map(|p| p.1.verts[0]).collect(),
                )
            })
            .collect();
        d.set_item("seams", seams)?;
        Ok(d)
    })
}
