//! Mesh and point-cache files: `tailor.read_mesh`, `tailor.AnimatedMesh` (glTF skins),
//! `tailor.read_pc2`, `tailor.write_pc2`, `tailor.Pc2Stream` (a cache written frame by frame),
//! `tailor.write_obj`.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::io::{self, gltf::GltfScene, pc2::PointCache};

use crate::convert::points3;
use crate::errors::to_py;

fn points_to_numpy<'py>(py: Python<'py>, p: &[[f32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = p.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([p.len(), 3])?.into_any())
}

fn triangles_to_numpy<'py>(py: Python<'py>, t: &[[u32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<u32> = t.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([t.len(), 3])?.into_any())
}

/// Reads an OBJ, PLY or glTF/GLB triangle mesh: `(vertices (n, 3) float32, triangles (m, 3))`.
/// A glTF is read in its rest pose; use `AnimatedMesh` for its animation.
#[pyfunction]
pub fn read_mesh<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    crate::errors::guard(|| {
        let m = py.detach(|| io::read_mesh(&path)).map_err(to_py)?;
        Ok((points_to_numpy(py, &m.positions)?, triangles_to_numpy(py, &m.triangles)?))
    })
}

/// A glTF/GLB scene with skinned animation, evaluated at any time.
#[pyclass(module = "tailor")]
pub struct AnimatedMesh {
    scene: GltfScene,
}

#[pymethods]
impl AnimatedMesh {
    #[new]
    fn new(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        crate::errors::guard(|| Ok(Self { scene: py.detach(|| GltfScene::load(&path)).map_err(to_py)? }))
    }

    #[getter]
    fn num_vertices(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.scene.num_vertices()))
    }

    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| triangles_to_numpy(py, self.scene.triangles()))
    }

    /// `[(name, duration_seconds)]` of the scene's animations.
    #[getter]
    fn animations(&self) -> PyResult<Vec<(String, f32)>> {
        crate::errors::guard(|| Ok(self.scene.animations().iter().map(|a| (a.name.clone(), a.duration)).collect()))
    }

    /// Skinned vertex positions (n, 3) at `time` seconds of animation `animation` (None = rest).
    #[pyo3(signature = (time, animation=Some(0)))]
    fn positions_at<'py>(&self, py: Python<'py>, time: f32, animation: Option<usize>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let anim = animation.filter(|_| !self.scene.animations().is_empty());
            let mut out = Vec::new();
            self.scene.positions_at(anim, time, &mut out).map_err(to_py)?;
            points_to_numpy(py, &out)
        })
    }
}

/// Reads a PC2 point cache: a dict with `frames` (k, n, 3) float32, `start_frame`, `sample_rate`.
#[pyfunction]
pub fn read_pc2<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let c = py.detach(|| io::pc2::read_pc2(&path)).map_err(to_py)?;
        let d = PyDict::new(py);
        let flat: Vec<f32> = c.frames.iter().flatten().flatten().copied().collect();
        d.set_item("frames", PyArray1::from_vec(py, flat).reshape([c.frames.len(), c.num_points, 3])?)?;
        d.set_item("start_frame", c.start_frame)?;
        d.set_item("sample_rate", c.sample_rate)?;
        Ok(d)
    })
}

/// Writes a PC2 point cache atomically from `frames` (k, n, 3).
#[pyfunction]
#[pyo3(signature = (path, frames, start_frame=0.0, sample_rate=1.0))]
pub fn write_pc2(
    py: Python<'_>,
    path: std::path::PathBuf,
    frames: &Bound<'_, PyAny>,
    start_frame: f32,
    sample_rate: f32,
) -> PyResult<()> {
    crate::errors::guard(|| {
        let arr = frames.py().import("numpy")?.call_method1("asarray", (frames,))?;
        let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
        if shape.len() != 3 || shape[2] != 3 {
            return Err(to_py(tailor_core::TailorError::shape(
                "pc2 frames",
                format!("expected shape (k, n, 3), got {shape:?}"),
            )));
        }
        let flat = points3(&arr.call_method1("reshape", ((shape[0] * shape[1]) as i64, 3))?, "pc2 frames")?;
        let cache = PointCache {
            start_frame,
            sample_rate,
            num_points: shape[1],
            frames: flat.chunks(shape[1].max(1)).map(|c| c.to_vec()).take(shape[0]).collect(),
        };
        py.detach(|| io::pc2::write_pc2(&path, &cache)).map_err(to_py)
    })
}

/// A PC2 cache written frame by frame into its own path, a valid cache after every frame
/// (`tailor simulate -o` writes this way: a crash or a kill keeps every frame finished).
#[pyclass(module = "tailor")]
pub struct Pc2Stream {
    inner: io::pc2_stream::Pc2Stream,
}

#[pymethods]
impl Pc2Stream {
    /// A new cache of `num_points` points at `path` (replacing any file there).
    #[new]
    #[pyo3(signature = (path, num_points, start_frame=0.0, sample_rate=1.0))]
    fn new(path: std::path::PathBuf, num_points: usize, start_frame: f32, sample_rate: f32) -> PyResult<Self> {
        crate::errors::guard(|| {
            let inner =
                io::pc2_stream::Pc2Stream::create(&path, num_points, start_frame, sample_rate).map_err(to_py)?;
            Ok(Self { inner })
        })
    }

    /// Goes on with the cache at `path` (it must hold `num_points` points), keeping its first
    /// `keep` whole frames (all when None) and cutting off anything after them.
    #[staticmethod]
    #[pyo3(signature = (path, num_points, keep=None))]
    fn resume(path: std::path::PathBuf, num_points: usize, keep: Option<usize>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let inner = io::pc2_stream::Pc2Stream::resume(&path, num_points, keep).map_err(to_py)?;
            Ok(Self { inner })
        })
    }

    /// Appends one frame ((num_points, 3)), then counts it in the header.
    fn push(&mut self, py: Python<'_>, points: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let p = points3(points, "pc2 frame")?;
            let inner = &mut self.inner;
            py.detach(|| inner.push_frame(&p)).map_err(to_py)
        })
    }

    /// Frames in the cache.
    #[getter]
    fn num_samples(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.num_samples()))
    }

    /// The header's (start frame, sample rate).
    #[getter]
    fn timing(&self) -> PyResult<(f32, f32)> {
        crate::errors::guard(|| Ok(self.inner.timing()))
    }
}

/// Writes a triangle mesh as Wavefront OBJ, atomically: `positions` (n, 3), `triangles` (m, 3)
/// and, optionally, `uv` (3m, 2): texture coordinates per triangle corner.
#[pyfunction]
#[pyo3(signature = (path, positions, triangles, uv=None))]
pub fn write_obj(
    py: Python<'_>,
    path: std::path::PathBuf,
    positions: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    uv: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    crate::errors::guard(|| {
        let p = points3(positions, "positions")?;
        let t = crate::convert::triangles(triangles, "triangles")?;
        let uv = uv.map(|u| crate::convert::points2(u, "uv")).transpose()?;
        py.detach(|| io::obj_write::write_obj(&path, &p, &t, uv.as_deref())).map_err(to_py)
    })
}
