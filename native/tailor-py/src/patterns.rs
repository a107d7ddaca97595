//! `tailor.read_pattern`, `tailor.list_sizes`, `tailor.triangulate` and the read-only
//! `Pattern`, `Piece` and `PieceMesh` objects: conversions only (see `tailor_core::pattern`
//! and `tailor_core::triangulate` for what they mean).

use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::pattern::{self as core, ReadOptions, Units};
use tailor_core::triangulate::{self as tri, TriangulateOptions};
use tailor_core::TailorError;

use crate::errors::to_py;

/// A new `(k, K)` array from rows.
pub fn rows<'py, T: numpy::Element + Copy, const K: usize>(
    py: Python<'py>,
    v: &[[T; K]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<T> = v.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([v.len(), K])?.into_any())
}

pub fn read_options(
    size: Option<String>,
    units: Option<&str>,
    tolerance: f64,
    unfold: bool,
    quantities: bool,
) -> PyResult<ReadOptions> {
    let units_override = match units {
        None => None,
        Some(u) => Some(
            Units::parse(u)
                .ok_or_else(|| to_py(TailorError::setting("units", u, "must be one of mm, cm, m, inch, ft, px, pt")))?,
        ),
    };
    Ok(ReadOptions { size, units_override, tolerance_m: tolerance, unfold, quantities })
}

pub fn placement_dict<'py>(py: Python<'py>, p: &Option<core::Placement>) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(p) = p else { return Ok(None) };
    let d = PyDict::new(py);
    d.set_item("translation", p.translation.to_vec())?;
    d.set_item("rotation_deg", p.rotation_deg.to_vec())?;
    d.set_item("flipped", p.flipped)?;
    Ok(Some(d))
}

/// One pattern piece (outline in metres, counter-clockwise; holes clockwise).
#[pyclass(module = "tailor", frozen, from_py_object)]
#[derive(Clone)]
pub struct Piece {
    pub inner: core::Piece,
}

#[pymethods]
impl Piece {
    /// The piece as JSON text (outline, holes, lines, notches, placement, edges), so that a host
    /// application can store it (the Blender add-on keeps it on the piece object) and rebuild
    /// the exact same mesh later with `triangulate(Piece.from_json(text), edge)`.
    fn to_json(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            serde_json::to_string(&self.inner)
                .map_err(|e| to_py(TailorError::shape(format!("piece {}", self.inner.name), e.to_string())))
        })
    }
    /// The piece stored by `to_json`.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            let inner: core::Piece = serde_json::from_str(text)
                .map_err(|e| to_py(TailorError::parse("piece JSON", "piece", e.to_string())))?;
            if inner.outline.len() < 3 || inner.outline.iter().flatten().any(|c| !c.is_finite()) {
                return Err(to_py(TailorError::parse(
                    "piece JSON",
                    inner.name.clone(),
                    "the outline needs at least 3 finite points",
                )));
            }
            Ok(Self { inner })
        })
    }
    #[getter]
    fn name(&self) -> PyResult<&str> {
        crate::errors::guard(|| Ok(self.inner.name.as_str()))
    }
    /// Outline, an (k, 2) float64 array in metres.
    #[getter]
    fn outline<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.outline))
    }
    #[getter]
    fn holes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        crate::errors::guard(|| self.inner.holes.iter().map(|h| rows(py, h)).collect())
    }
    #[getter]
    fn internal_lines<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        crate::errors::guard(|| self.inner.internal_lines.iter().map(|h| rows(py, h)).collect())
    }
    #[getter]
    fn notches<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.notches))
    }
    #[getter]
    fn fixed_vertices(&self) -> PyResult<Vec<usize>> {
        crate::errors::guard(|| Ok(self.inner.fixed_vertices.clone()))
    }
    /// The grain line's two ends, `((x, y), (x, y))` in metres, or None when the file has none.
    #[getter]
    fn grain(&self) -> PyResult<Option<([f64; 2], [f64; 2])>> {
        crate::errors::guard(|| Ok(self.inner.grain.map(|[a, b]| (a, b))))
    }
    /// `{"translation": [x, y, z], "rotation_deg": [a, b, c], "flipped": bool}` or None.
    #[getter]
    fn placement<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        crate::errors::guard(|| placement_dict(py, &self.inner.placement))
    }
    /// Named edges as (start, end) outline indices, walked counter-clockwise.
    #[getter]
    fn edges(&self) -> PyResult<Vec<(usize, usize)>> {
        crate::errors::guard(|| Ok(self.inner.edges.iter().map(|e| (e.start, e.end)).collect()))
    }
    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                format!(
                    "Piece({:?}, {} outline points, {} holes)",
                    self.inner.name,
                    self.inner.outline.len(),
                    self.inner.holes.len()
                )
            })
        })
    }
}

/// A pattern as read from one file (one size of a graded nest).
#[pyclass(module = "tailor", frozen)]
pub struct Pattern {
    pub inner: core::Pattern,
}

#[pymethods]
impl Pattern {
    #[getter]
    fn source(&self) -> PyResult<&str> {
        crate::errors::guard(|| Ok(self.inner.source.as_str()))
    }
    #[getter]
    fn pieces(&self) -> PyResult<Vec<Piece>> {
        crate::errors::guard(|| Ok(self.inner.pieces.iter().map(|p| Piece { inner: p.clone() }).collect()))
    }
    /// Stitches as ((piece, edge), (piece, edge)).
    #[getter]
    fn stitches(&self) -> PyResult<Vec<((usize, usize), (usize, usize))>> {
        crate::errors::guard(|| {
            Ok(self.inner.stitches.iter().map(|s| ((s.a.piece, s.a.edge), (s.b.piece, s.b.edge))).collect())
        })
    }
    #[getter]
    fn sizes(&self) -> PyResult<Vec<String>> {
        crate::errors::guard(|| Ok(self.inner.sizes.clone()))
    }
    #[getter]
    fn size(&self) -> PyResult<Option<String>> {
        crate::errors::guard(|| Ok(self.inner.size.clone()))
    }
    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                format!(
                    "Pattern({:?}, {} pieces, {} stitches)",
                    self.inner.source,
                    self.inner.pieces.len(),
                    self.inner.stitches.len()
                )
            })
        })
    }
}

/// A triangulated piece: flat rest mesh plus its counter-clockwise outer contour.
#[pyclass(module = "tailor", frozen, from_py_object)]
#[derive(Clone)]
pub struct PieceMesh {
    pub inner: tri::PieceMesh,
}

#[pymethods]
impl PieceMesh {
    #[getter]
    fn name(&self) -> PyResult<&str> {
        crate::errors::guard(|| Ok(self.inner.name.as_str()))
    }
    #[getter]
    fn edge_length(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.inner.edge_length))
    }
    /// Rest coordinates, (n, 2) float32, metres.
    #[getter]
    fn rest<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.rest))
    }
    /// Triangles, (m, 3) uint32.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| rows(py, &self.inner.triangles))
    }
    /// Outer contour, counter-clockwise vertex indices (uint32).
    #[getter]
    fn contour<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| Ok(PyArray1::from_vec(py, self.inner.contour.clone()).into_any()))
    }
    /// Arc length from the first contour vertex to each contour vertex (float64, metres).
    #[getter]
    fn contour_param<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| Ok(PyArray1::from_vec(py, self.inner.contour_param.clone()).into_any()))
    }
    #[getter]
    fn contour_length(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.inner.contour_length))
    }
    /// Contour positions of the corners (pins and sharp turns), ascending.
    #[getter]
    fn corners(&self) -> PyResult<Vec<usize>> {
        crate::errors::guard(|| Ok(self.inner.corners.clone()))
    }
    /// Contour positions (start, end) of each named edge of the piece.
    #[getter]
    fn span_map(&self) -> PyResult<Vec<(usize, usize)>> {
        crate::errors::guard(|| Ok(self.inner.span_map.iter().map(|s| (s[0], s[1])).collect()))
    }
    /// Quality figures: vertices, triangles, min/max angle (deg), edge lengths (m), area (m²)…
    #[getter]
    fn quality<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let q = &self.inner.quality;
            let d = PyDict::new(py);
            d.set_item("vertices", q.vertices)?;
            d.set_item("triangles", q.triangles)?;
            d.set_item("min_angle_deg", q.min_angle_deg)?;
            d.set_item("max_angle_deg", q.max_angle_deg)?;
            d.set_item("min_edge", q.min_edge)?;
            d.set_item("mean_edge", q.mean_edge)?;
            d.set_item("max_edge", q.max_edge)?;
            d.set_item("edges_within_35pct", q.edges_within_35pct)?;
            d.set_item("contour_min_edge", q.contour_min_edge)?;
            d.set_item("contour_max_edge", q.contour_max_edge)?;
            d.set_item("area", q.area)?;
            d.set_item("refinement_complete", q.refinement_complete)?;
            Ok(d)
        })
    }
    /// Rest position of contour position `i` (wrapping).
    fn contour_point(&self, i: usize) -> PyResult<(f32, f32)> {
        crate::errors::guard(|| {
            Ok({
                let p = self.inner.contour_point(i);
                (p[0], p[1])
            })
        })
    }
    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                format!(
                    "PieceMesh({:?}, {} vertices, {} triangles)",
                    self.inner.name,
                    self.inner.rest.len(),
                    self.inner.triangles.len()
                )
            })
        })
    }
}

/// Reads a DXF, SVG or GarmentCode JSON pattern (coordinates in metres). `unfold`: a DXF piece
/// drawn as a half with a mirror line (cut on the fold) becomes the whole piece. `quantities`: a
/// DXF piece is read as many times as its `Quantity:` says (a pair as the piece and its mirror
/// image named `R` and `L`, a piece cut 0 times left out).
#[pyfunction]
#[pyo3(signature = (path, size=None, units=None, tolerance=0.0005, unfold=true, quantities=true))]
pub fn read_pattern(
    py: Python<'_>,
    path: PathBuf,
    size: Option<String>,
    units: Option<&str>,
    tolerance: f64,
    unfold: bool,
    quantities: bool,
) -> PyResult<Pattern> {
    crate::errors::guard(|| {
        let options = read_options(size, units, tolerance, unfold, quantities)?;
        let inner = py.detach(|| core::read_pattern(&path, &options)).map_err(to_py)?;
        Ok(Pattern { inner })
    })
}

/// The sizes a graded pattern file offers (empty when it is not graded).
#[pyfunction]
pub fn list_sizes(path: PathBuf) -> PyResult<Vec<String>> {
    crate::errors::guard(|| core::list_sizes(&path).map_err(to_py))
}

/// Triangulates `piece` at target edge length `edge` (metres) with mesher `mesher` (default
/// `MESHER_VERSION`; a host that stored a mesh made by an older mesher passes its number to get
/// the same mesh back).
#[pyfunction]
#[pyo3(signature = (piece, edge=0.01, mesher=None))]
pub fn triangulate(py: Python<'_>, piece: Piece, edge: f64, mesher: Option<u32>) -> PyResult<PieceMesh> {
    crate::errors::guard(|| {
        let mut options = TriangulateOptions::new(edge);
        options.mesher = mesher.unwrap_or(tri::MESHER_VERSION);
        let inner = py.detach(|| tri::triangulate_piece(&piece.inner, &options)).map_err(to_py)?;
        Ok(PieceMesh { inner })
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Pattern>()?;
    m.add_class::<Piece>()?;
    m.add_class::<PieceMesh>()?;
    m.add_function(wrap_pyfunction!(read_pattern, m)?)?;
    m.add_function(wrap_pyfunction!(list_sizes, m)?)?;
    m.add_function(wrap_pyfunction!(triangulate, m)?)
}
