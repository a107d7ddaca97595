//! `tailor.Garment` (a pattern assembled into pieces and seams, saved as a garment file, built
//! into a `tailor.Simulation`) and `tailor.bend`. Logic lives in `tailor_core::garment`,
//! `garment_file` and `bend`; this file converts.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::bend::{bend_piece, BendParams, SymmetryLine};
use tailor_core::garment::{self as core, BuildOptions};
use tailor_core::garment_file::{self, GarmentPiece};
use tailor_core::pattern::Placement;
use tailor_core::triangulate::{PieceMesh as CoreMesh, TriangulateOptions, MESHER_VERSION};
use tailor_core::TailorError;

use crate::convert::{points2, points3};
use crate::errors::to_py;
use crate::patterns::{read_options, rows, Piece, PieceMesh};
use crate::seams::Seam;
use crate::weld::WeldedMesh;

/// A garment: pattern pieces with their resolution, placement and bend, and the seams between
/// them. Meshes are rebuilt from the pieces (triangulation is deterministic) and cached.
#[pyclass(module = "tailor")]
pub struct Garment {
    inner: garment_file::Garment,
    meshes: Option<Vec<CoreMesh>>,
}

impl Garment {
    fn meshes_ref(&mut self, py: Python<'_>) -> PyResult<&Vec<CoreMesh>> {
        if self.meshes.is_none() {
            let g = &self.inner;
            self.meshes = Some(py.detach(|| core::triangulate_all(g)).map_err(to_py)?);
        }
        Ok(self.meshes.as_ref().expect("just set"))
    }
}

#[pymethods]
impl Garment {
    /// Reads a pattern file and triangulates every piece at `edge` metres; GarmentCode
    /// placements are kept and stitches become seams.
    #[staticmethod]
    #[pyo3(signature = (path, edge=0.01, size=None, units=None, tolerance=0.0005))]
    fn from_pattern(
        py: Python<'_>,
        path: PathBuf,
        edge: f64,
        size: Option<String>,
        units: Option<&str>,
        tolerance: f64,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let read = read_options(size, units, tolerance)?;
            let (_, inner, meshes) =
                py.detach(|| core::read_garment(&path, &read, &TriangulateOptions::new(edge))).map_err(to_py)?;
            Ok(Self { inner, meshes: Some(meshes) })
        })
    }

    /// A garment from its parts, e.g. as a host application (the Blender add-on) keeps them:
    /// `pieces` with their target edge lengths, `seams` over piece indices, and per piece an
    /// optional placement (`{"translation", "rotation_deg", "flipped"}`, as `Piece.placement`;
    /// it overrides the piece's own) and bend (`{"axis_point", "axis_direction", "angle_deg",
    /// "symmetry", "threshold"}`, as `set_bend` takes them) and the mesher that made its mesh
    /// (`meshers`, default `MESHER_VERSION` for every piece; see `triangulate`). Every seam is
    /// checked against the meshes.
    #[staticmethod]
    #[pyo3(signature = (pieces, edge_lengths, seams, placements=None, bends=None, meshers=None))]
    fn from_parts(
        py: Python<'_>,
        pieces: Vec<Piece>,
        edge_lengths: Vec<f64>,
        seams: Vec<Seam>,
        placements: Option<Vec<Option<Bound<'_, PyDict>>>>,
        bends: Option<Vec<Option<Bound<'_, PyDict>>>>,
        meshers: Option<Vec<u32>>,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let n = pieces.len();
            let count = |what: &'static str, len: usize| {
                if len == n {
                    Ok(())
                } else {
                    Err(to_py(TailorError::shape("Garment.from_parts", format!("{n} pieces but {len} {what}"))))
                }
            };
            count("edge lengths", edge_lengths.len())?;
            let placements = placements.unwrap_or_else(|| vec![None; n]);
            let bends = bends.unwrap_or_else(|| vec![None; n]);
            count("placements", placements.len())?;
            count("bends", bends.len())?;
            let meshers = meshers.unwrap_or_else(|| vec![MESHER_VERSION; n]);
            count("meshers", meshers.len())?;
            let mut inner = garment_file::Garment::default();
            let parts = pieces.into_iter().zip(edge_lengths).zip(placements).zip(bends).zip(meshers);
            for ((((piece, edge), placement), bend), mesher) in parts {
                inner.pieces.push(GarmentPiece {
                    source: piece.inner,
                    options: TriangulateOptions { mesher, ..TriangulateOptions::new(edge) },
                    placement: placement.map(|d| placement_from(&d)).transpose()?,
                    bend: bend.map(|d| bend_from(&d)).transpose()?,
                });
            }
            inner.seams = seams.into_iter().map(|s| s.inner).collect();
            let g = &inner;
            let meshes = py.detach(|| core::triangulate_all(g)).map_err(to_py)?;
            for seam in &inner.seams {
                seam.resolve(&meshes).map_err(to_py)?;
            }
            Ok(Self { inner, meshes: Some(meshes) })
        })
    }

    /// Reads a garment file (`NAME.json` with its `NAME.bin` sidecar).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        crate::errors::guard(|| Ok(Self { inner: garment_file::load(&path).map_err(to_py)?, meshes: None }))
    }

    /// Writes the garment file (`path`, plus its `.bin` sidecar next to it).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        crate::errors::guard(|| garment_file::save(&self.inner, &path).map_err(to_py))
    }

    /// The file's named settings (its manifest's `settings` object) as JSON text; the add-on
    /// and `tailor.commands.garment_extras` keep per-piece fabric, levels and choices there.
    #[getter]
    fn settings_json(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            serde_json::to_string(&self.inner.settings)
                .map_err(|e| to_py(TailorError::shape("garment settings", e.to_string())))
        })
    }

    /// The painted per-particle parameters as `(name, piece, values)`: float32, int32 or bool
    /// arrays, one value per vertex of that piece's mesh, as the sidecar holds them.
    #[getter]
    fn particle_params<'py>(&self, py: Python<'py>) -> PyResult<Vec<(String, usize, Bound<'py, PyAny>)>> {
        crate::errors::guard(|| {
            use garment_file::ParticleValues as V;
            use numpy::PyArray1;
            Ok(self
                .inner
                .particle_params
                .iter()
                .map(|p| {
                    let values = match &p.values {
                        V::F32(v) => PyArray1::from_slice(py, v).into_any(),
                        V::I32(v) => PyArray1::from_slice(py, v).into_any(),
                        V::Bool(v) => PyArray1::from_slice(py, v).into_any(),
                    };
                    (p.name.clone(), p.piece, values)
                })
                .collect())
        })
    }

    /// The source pattern pieces, in garment order.
    #[getter]
    fn pieces(&self) -> PyResult<Vec<Piece>> {
        crate::errors::guard(|| Ok(self.inner.pieces.iter().map(|p| Piece { inner: p.source.clone() }).collect()))
    }

    /// Target edge length of each piece, metres.
    #[getter]
    fn edge_lengths(&self) -> PyResult<Vec<f64>> {
        crate::errors::guard(|| Ok(self.inner.pieces.iter().map(|p| p.options.edge_length).collect()))
    }

    #[getter]
    fn seams(&self) -> PyResult<Vec<Seam>> {
        crate::errors::guard(|| Ok(self.inner.seams.iter().map(|s| Seam { inner: s.clone() }).collect()))
    }

    /// The piece meshes at the current resolutions.
    fn meshes(&mut self, py: Python<'_>) -> PyResult<Vec<PieceMesh>> {
        crate::errors::guard(|| Ok(self.meshes_ref(py)?.iter().map(|m| PieceMesh { inner: m.clone() }).collect()))
    }

    /// Adds a seam (checked against the current meshes first). Returns its index.
    fn add_seam(&mut self, py: Python<'_>, seam: Seam) -> PyResult<usize> {
        crate::errors::guard(|| {
            seam.inner.resolve(self.meshes_ref(py)?).map_err(to_py)?;
            self.inner.seams.push(seam.inner);
            Ok(self.inner.seams.len() - 1)
        })
    }

    /// Re-triangulates piece `piece` at `edge` metres and remaps the seams (an equal-count
    /// seam whose counts no longer match becomes unequal). Returns the piece's new mesh.
    fn set_resolution(&mut self, py: Python<'_>, piece: usize, edge: f64) -> PyResult<PieceMesh> {
        crate::errors::guard(|| {
            let g = &mut self.inner;
            let meshes = py.detach(|| core::set_resolution(g, piece, edge)).map_err(to_py)?;
            let out = PieceMesh { inner: meshes[piece].clone() };
            self.meshes = Some(meshes);
            Ok(out)
        })
    }

    /// Bends piece `piece` after placement (see `tailor.bend`); `angle_deg = 0` removes it.
    #[pyo3(signature = (piece, axis_point, axis_direction, angle_deg, symmetry=None, threshold=0.0))]
    fn set_bend(
        &mut self,
        piece: usize,
        axis_point: [f64; 3],
        axis_direction: [f64; 3],
        angle_deg: f64,
        symmetry: Option<([f64; 2], [f64; 2])>,
        threshold: f64,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let n = self.inner.pieces.len();
            let p = self.inner.pieces.get_mut(piece).ok_or_else(|| {
                to_py(TailorError::setting("piece", piece, format!("must be a piece index below {n}")))
            })?;
            let params = bend_params(axis_point, axis_direction, angle_deg, symmetry, threshold);
            p.bend = if angle_deg == 0.0 { None } else { Some(params) };
            Ok(())
        })
    }

    /// Warnings recorded at import (for example internal lines that had to be dropped).
    #[getter]
    fn warnings(&self) -> PyResult<Vec<String>> {
        crate::errors::guard(|| Ok(core::import_warnings(&self.inner)))
    }

    /// Builds the sewn cloth and a `tailor.Simulation` with every seam added. Returns
    /// `(simulation, offsets)`: `offsets[i]` is the index of piece `i`'s first particle.
    /// Each seam's spring constant is `seam_stiffness` (N/m) times its own stiffness factor;
    /// pieces without a placement are laid side by side `gap` metres apart.
    #[pyo3(signature = (fabric=None, settings=None, seam_stiffness=1.0e4, seam_bend_stiffness=1e-5, gap=0.05))]
    fn build_simulation<'py>(
        &mut self,
        py: Python<'py>,
        fabric: Option<Bound<'py, PyAny>>,
        settings: Option<Bound<'py, PyAny>>,
        seam_stiffness: f32,
        seam_bend_stiffness: f32,
        gap: f64,
    ) -> PyResult<(Bound<'py, PyAny>, Vec<u32>)> {
        crate::errors::guard(|| {
            let meshes = self.meshes_ref(py)?.clone();
            let g = &self.inner;
            let options = BuildOptions { gap, seam_stiffness, seam_bend_stiffness };
            let input = py.detach(|| core::solver_input(g, meshes, &options)).map_err(to_py)?;
            let m = &input.sewn.mesh;
            let sim = py.get_type::<crate::simulation::Simulation>().call1((
                rows(py, m.positions())?,
                rows(py, m.triangles())?,
                rows(py, m.rest())?,
                fabric,
                settings,
            ))?;
            for s in &input.seams {
                let v: Vec<[[u32; 2]; 2]> = s.pairs.iter().map(|p| [p.0.verts, p.1.verts]).collect();
                let w: Vec<[[f32; 2]; 2]> = s.pairs.iter().map(|p| [p.0.weights, p.1.weights]).collect();
                sim.call_method1(
                    "add_weighted_seam",
                    (
                        rows(py, &v.iter().map(|x| x[0]).collect::<Vec<_>>())?,
                        rows(py, &w.iter().map(|x| x[0]).collect::<Vec<_>>())?,
                        rows(py, &v.iter().map(|x| x[1]).collect::<Vec<_>>())?,
                        rows(py, &w.iter().map(|x| x[1]).collect::<Vec<_>>())?,
                        s.stiffness,
                        s.bend_stiffness,
                        s.name.as_str(),
                    ),
                )?;
            }
            Ok((sim, input.sewn.offsets.clone()))
        })
    }

    /// The garment as one mesh (`tailor.WeldedMesh`): the pieces sewn as `build_simulation`
    /// sews them, merged along every seam, at `positions` (one per particle, e.g. a simulation's
    /// `positions`) or as placed when `None`.
    #[pyo3(signature = (positions=None, gap=0.05))]
    fn welded(&mut self, py: Python<'_>, positions: Option<Bound<'_, PyAny>>, gap: f64) -> PyResult<WeldedMesh> {
        crate::errors::guard(|| {
            let positions = positions.map(|p| points3(&p, "positions")).transpose()?;
            let meshes = self.meshes_ref(py)?.clone();
            let g = &self.inner;
            let options = BuildOptions { gap, ..BuildOptions::default() };
            let inner = py
                .detach(|| {
                    let input = core::solver_input(g, meshes, &options)?;
                    tailor_core::weld::weld_garment(&input, positions.as_deref())
                })
                .map_err(to_py)?;
            Ok(WeldedMesh { inner })
        })
    }

    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok(format!("Garment({} pieces, {} seams)", self.inner.pieces.len(), self.inner.seams.len()))
        })
    }
}

fn item<'py>(d: &Bound<'py, PyDict>, key: &'static str, what: &str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(key)?.ok_or_else(|| to_py(TailorError::setting(key, what, "is missing")))
}

fn placement_from(d: &Bound<'_, PyDict>) -> PyResult<Placement> {
    let flipped = match d.get_item("flipped")? {
        Some(v) => v.extract()?,
        None => false,
    };
    Ok(Placement {
        translation: item(d, "translation", "placement")?.extract()?,
        rotation_deg: item(d, "rotation_deg", "placement")?.extract()?,
        flipped,
    })
}

fn bend_from(d: &Bound<'_, PyDict>) -> PyResult<BendParams> {
    let symmetry: Option<([f64; 2], [f64; 2])> = match d.get_item("symmetry")? {
        Some(v) if !v.is_none() => Some(v.extract()?),
        _ => None,
    };
    let threshold = match d.get_item("threshold")? {
        Some(v) => v.extract()?,
        None => 0.0,
    };
    Ok(bend_params(
        item(d, "axis_point", "bend")?.extract()?,
        item(d, "axis_direction", "bend")?.extract()?,
        item(d, "angle_deg", "bend")?.extract()?,
        symmetry,
        threshold,
    ))
}

fn bend_params(
    axis_point: [f64; 3],
    axis_direction: [f64; 3],
    angle_deg: f64,
    symmetry: Option<([f64; 2], [f64; 2])>,
    threshold: f64,
) -> BendParams {
    BendParams {
        axis_point,
        axis_direction,
        angle_deg,
        symmetry: symmetry.map(|(point, direction)| SymmetryLine { point, direction }),
        threshold,
    }
}

/// Bends a placed piece around an axis (paper Fig. 4); returns the new (n, 3) positions.
/// `symmetry` = ((x, y), (dx, dy)), a rest-frame line whose sides bend in opposite senses.
#[pyfunction]
#[pyo3(signature = (positions, rest, axis_point, axis_direction, angle_deg, symmetry=None, threshold=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn bend<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    rest: &Bound<'py, PyAny>,
    axis_point: [f64; 3],
    axis_direction: [f64; 3],
    angle_deg: f64,
    symmetry: Option<([f64; 2], [f64; 2])>,
    threshold: f64,
) -> PyResult<Bound<'py, PyAny>> {
    crate::errors::guard(|| {
        let mut p = points3(positions, "positions")?;
        let r = points2(rest, "rest")?;
        let params = bend_params(axis_point, axis_direction, angle_deg, symmetry, threshold);
        bend_piece(&mut p, &r, &params).map_err(to_py)?;
        rows(py, &p)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Garment>()?;
    m.add_function(wrap_pyfunction!(bend, m)?)
}
