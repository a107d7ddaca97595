//! Collisions and quality metrics at the Python boundary: argument conversion for the
//! `Simulation` methods on mesh colliders, levels, friction and self-collision, the dicts
//! they return, and the module-level metric functions over plain arrays.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::collision::InsertionRule;
use tailor_core::quality::metrics;
use tailor_core::quality::verdict;
use tailor_core::solver::{ColliderId, CollisionStats, QualityMetrics, SelfCollisionSettings};
use tailor_core::TailorError;

use crate::convert::{floats, points3, triangles};
use crate::errors::to_py;

/// Integers of any dtype as a flat int64 vector with the array's shape.
fn ints(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<i64>, Vec<usize>)> {
    let np = obj.py().import("numpy")?;
    let arr = np
        .call_method1("ascontiguousarray", (obj, np.getattr("int64")?))
        .map_err(|e| to_py(TailorError::shape(name, format!("expected an array of integers: {e}"))))?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let flat = arr.call_method1("reshape", (-1,))?;
    let flat =
        flat.extract::<PyReadonlyArray1<i64>>().map_err(|_| to_py(TailorError::shape(name, "expected integers")))?;
    Ok((flat.as_array().to_vec(), shape))
}

/// A 1D array of collision levels (int32 range).
pub fn levels(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<i32>> {
    let (v, shape) = ints(obj, name)?;
    if shape.len() != 1 {
        return Err(to_py(TailorError::shape(name, format!("expected a 1D array, got shape {shape:?}"))));
    }
    v.iter()
        .enumerate()
        .map(|(k, &l)| {
            i32::try_from(l)
                .map_err(|_| to_py(TailorError::shape(name, format!("entry {k} ({l}) is not a 32-bit integer"))))
        })
        .collect()
}

/// A `(k, 2)` array of vertex pairs below `len`.
pub fn pairs(obj: &Bound<'_, PyAny>, name: &str, len: usize) -> PyResult<Vec<[u32; 2]>> {
    let (v, shape) = ints(obj, name)?;
    if shape.len() != 2 || shape[1] != 2 {
        return Err(to_py(TailorError::shape(name, format!("expected shape (k, 2), got {shape:?}"))));
    }
    v.chunks_exact(2)
        .enumerate()
        .map(|(k, c)| {
            let mut out = [0u32; 2];
            for j in 0..2 {
                if c[j] < 0 || c[j] as usize >= len {
                    return Err(to_py(TailorError::index(format!("{name} row {k}"), c[j], len, "vertices")));
                }
                out[j] = c[j] as u32;
            }
            Ok(out)
        })
        .collect()
}

pub fn collider_id(id: i64, count: usize) -> PyResult<ColliderId> {
    u32::try_from(id).map(ColliderId).map_err(|_| to_py(TailorError::index("collider id", id, count, "mesh colliders")))
}

pub fn insertion_rule(name: &str) -> PyResult<InsertionRule> {
    match name {
        "paper" => Ok(InsertionRule::Paper),
        "paper_or_plane" => Ok(InsertionRule::PaperOrPlane),
        "aabb" => Ok(InsertionRule::Aabb),
        _ => Err(to_py(TailorError::setting("insertion", name, "expected 'paper', 'paper_or_plane' or 'aabb'"))),
    }
}

pub fn collision_stats_dict<'py>(py: Python<'py>, c: &CollisionStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("hash_seconds", c.hash_seconds)?;
    d.set_item("contact_seconds", c.contact_seconds)?;
    d.set_item("self_seconds", c.self_seconds)?;
    d.set_item("resolve_seconds", c.resolve_seconds)?;
    d.set_item("rebuilds", c.rebuilds)?;
    d.set_item("reuses", c.reuses)?;
    d.set_item("triangles_kept", c.triangles_kept)?;
    d.set_item("triangles_culled", c.triangles_culled)?;
    d.set_item("mesh_contacts", c.mesh_contacts)?;
    d.set_item("self_pairs", c.self_pairs)?;
    d.set_item("self_searches", c.self_searches)?;
    d.set_item("self_partial_searches", c.self_partial_searches)?;
    d.set_item("contact_tests", c.contact_tests)?;
    d.set_item("contact_skips", c.contact_skips)?;
    d.set_item("contact_nearest", c.contact_nearest)?;
    Ok(d)
}

pub fn metrics_dict<'py>(py: Python<'py>, m: &QualityMetrics) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("penetration_count", m.penetration_count)?;
    d.set_item("penetration_max_depth", m.penetration_max_depth)?;
    d.set_item("self_intersections", m.self_intersections)?;
    d.set_item("seam_gap", m.seam_gap)?;
    d.set_item("strain_max", m.strain_max)?;
    d.set_item("strain_mean", m.strain_mean)?;
    d.set_item("kinetic_energy", m.kinetic_energy)?;
    d.set_item("particles", m.particles)?;
    d.set_item("centroid", m.centroid.to_vec())?;
    d.set_item("top", m.top.to_vec())?;
    d.set_item("on_body_fraction", m.on_body_fraction)?;
    d.set_item("collider_centroid", m.collider_centroid.map(|c| c.to_vec()))?;
    d.set_item("seams_closing", m.seams_closing)?;
    Ok(d)
}

/// The fields of a metrics dict (as [`metrics_dict`] writes it) that the verdict reads; a
/// missing or mistyped one is an `InvalidParameterError` naming it.
fn metrics_from_dict(d: &Bound<'_, PyDict>, name: &str) -> PyResult<QualityMetrics> {
    let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(key)?
            .ok_or_else(|| to_py(TailorError::shape(name, format!("no '{key}' (a dict of Simulation.metrics)"))))
    };
    let bad = |key: &str, e: PyErr| to_py(TailorError::shape(name, format!("'{key}': {e}")));
    macro_rules! field {
        ($key:literal, $t:ty) => {
            item($key)?.extract::<$t>().map_err(|e| bad($key, e.into()))?
        };
    }
    let centroid = field!("centroid", [f32; 3]);
    // Dicts written before the top was measured: the centroid stands for it.
    let top = match d.get_item("top")? {
        Some(t) => t.extract::<[f32; 3]>().map_err(|e| bad("top", e))?,
        None => centroid,
    };
    Ok(QualityMetrics {
        penetration_count: field!("penetration_count", usize),
        penetration_max_depth: field!("penetration_max_depth", f32),
        seam_gap: field!("seam_gap", f32),
        particles: field!("particles", usize),
        centroid,
        top,
        on_body_fraction: field!("on_body_fraction", Option<f32>),
        collider_centroid: field!("collider_centroid", Option<[f32; 3]>),
        seams_closing: field!("seams_closing", bool),
        ..Default::default()
    })
}

/// The checks a frame fails (see the stub's docstring and `tailor_core::quality::verdict`).
#[pyfunction]
#[pyo3(signature = (metrics, start=None, nan=false))]
pub fn judge<'py>(
    py: Python<'py>,
    metrics: &Bound<'py, PyDict>,
    start: Option<&Bound<'py, PyDict>>,
    nan: bool,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let now = metrics_from_dict(metrics, "metrics")?;
        let start = match start {
            Some(s) => metrics_from_dict(s, "start")?,
            None => now,
        };
        let d = PyDict::new(py);
        d.set_item("centroid_shift_m", verdict::centroid_shift(&start, &now))?;
        d.set_item("top_shift_m", verdict::top_shift(&start, &now))?;
        let failed = pyo3::types::PyList::empty(py);
        for f in verdict::judge(&now, &start, nan) {
            let e = PyDict::new(py);
            e.set_item("check", f.check.name())?;
            e.set_item("reason", f.reason)?;
            failed.append(e)?;
        }
        d.set_item("failed", failed)?;
        Ok(d)
    })
}

/// `tailor.judge_unfinished`: the "open" failure of a run whose last frame still had seams
/// closing (`verdict::judge_unfinished`), or None.
#[pyfunction]
pub fn judge_unfinished<'py>(
    py: Python<'py>,
    seams_closing: bool,
    seam_gap: f32,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    crate::errors::guard(|| {
        verdict::judge_unfinished(seams_closing, seam_gap)
            .map(|f| {
                let e = PyDict::new(py);
                e.set_item("check", f.check.name())?;
                e.set_item("reason", f.reason)?;
                Ok(e)
            })
            .transpose()
    })
}

/// The verdict's thresholds by name (`tailor.VERDICT_THRESHOLDS`), as the shortest decimals
/// that round to them (0.1, not 0.10000000149).
pub fn verdict_thresholds<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let tidy = |x: f32| x.to_string().parse::<f64>().unwrap_or(x as f64);
    d.set_item("on_body_distance_m", tidy(metrics::ON_BODY_DISTANCE))?;
    d.set_item("on_body_min", tidy(verdict::ON_BODY_MIN))?;
    d.set_item("fell_shift_m", tidy(verdict::FELL_SHIFT))?;
    d.set_item("fell_top_shift_m", tidy(verdict::FELL_TOP_SHIFT))?;
    d.set_item("open_gap_m", tidy(verdict::OPEN_GAP))?;
    d.set_item("inside_depth_m", tidy(verdict::INSIDE_DEPTH))?;
    d.set_item("inside_share", tidy(verdict::INSIDE_SHARE))?;
    d.set_item("checks", verdict::Check::ALL.map(verdict::Check::name).to_vec())?;
    Ok(d)
}

pub fn self_collision_dict<'py>(
    py: Python<'py>,
    s: &SelfCollisionSettings,
    radius: f32,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("enabled", s.enabled)?;
    d.set_item("radius", radius)?;
    d.set_item("radius_setting", s.radius)?;
    d.set_item("contacts", s.contacts.name())?;
    d.set_item("static_friction", s.static_friction)?;
    d.set_item("kinetic_friction", s.kinetic_friction)?;
    Ok(d)
}

/// Penetration of `points` (n, 3) into the closed mesh (vertices, triangles):
/// {"count": int, "max_depth": float}.
#[pyfunction]
pub fn penetration<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    vertices: &Bound<'py, PyAny>,
    triangles_: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let (p, v, t) =
            (points3(points, "points")?, points3(vertices, "vertices")?, triangles(triangles_, "triangles")?);
        let pen = py.detach(|| metrics::penetration(&p, &v, &t)).map_err(to_py)?;
        let d = PyDict::new(py);
        d.set_item("count", pen.count)?;
        d.set_item("max_depth", pen.max_depth)?;
        Ok(d)
    })
}

/// Number of intersecting pairs of triangles that share no vertex.
#[pyfunction]
pub fn count_self_intersections(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    triangles_: &Bound<'_, PyAny>,
) -> PyResult<usize> {
    crate::errors::guard(|| {
        let (v, t) = (points3(vertices, "vertices")?, triangles(triangles_, "triangles")?);
        py.detach(|| metrics::count_self_intersections(&v, &t)).map_err(to_py)
    })
}

/// The intersecting pairs of triangles that share no vertex, (k, 2) uint32, `i < j`, sorted;
/// vertices `joined` in pairs (k, 2) (sewn together) count as one.
#[pyfunction]
#[pyo3(signature = (vertices, triangles_, joined=None))]
pub fn self_intersecting_pairs<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    triangles_: &Bound<'py, PyAny>,
    joined: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    crate::errors::guard(|| {
        let (v, t) = (points3(vertices, "vertices")?, triangles(triangles_, "triangles")?);
        let joined: Vec<[u32; 2]> = match joined {
            Some(j) => pairs(j, "joined", v.len())?,
            None => Vec::new(),
        };
        let pairs = py.detach(|| metrics::self_intersecting_pairs(&v, &t, &joined)).map_err(to_py)?;
        let flat: Vec<u32> = pairs.into_iter().flatten().collect();
        let n = flat.len() / 2;
        Ok(numpy::PyArray1::from_vec(py, flat).reshape([n, 2])?.into_any())
    })
}

/// Edge strain |l/l0 - 1| of `edges` (k, 2): {"max": float, "mean": float}.
#[pyfunction]
pub fn edge_strain<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    edges: &Bound<'py, PyAny>,
    rest_lengths: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let p = points3(positions, "positions")?;
        let e = pairs(edges, "edges", p.len())?;
        let s = metrics::edge_strain(&p, &e, &floats(rest_lengths, "rest_lengths")?).map_err(to_py)?;
        let d = PyDict::new(py);
        d.set_item("max", s.max)?;
        d.set_item("mean", s.mean)?;
        Ok(d)
    })
}

/// Kinetic energy 1/2 sum m v^2, joules.
#[pyfunction]
pub fn kinetic_energy(velocities: &Bound<'_, PyAny>, masses: &Bound<'_, PyAny>) -> PyResult<f64> {
    crate::errors::guard(|| {
        metrics::kinetic_energy(&points3(velocities, "velocities")?, &floats(masses, "masses")?).map_err(to_py)
    })
}

/// Largest distance between the two points of any pair (k, 2).
#[pyfunction]
pub fn max_seam_gap(positions: &Bound<'_, PyAny>, pairs_: &Bound<'_, PyAny>) -> PyResult<f32> {
    crate::errors::guard(|| {
        let p = points3(positions, "positions")?;
        let pr = pairs(pairs_, "pairs", p.len())?;
        metrics::max_seam_gap(&p, &pr).map_err(to_py)
    })
}

/// A new (n, 3) float32 array from rows.
pub fn rows_to_numpy<'py>(py: Python<'py>, rows: &[[f32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([rows.len(), 3])?.into_any())
}
