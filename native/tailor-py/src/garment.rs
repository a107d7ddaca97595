//! `tailor.Garment` (a pattern assembled into pieces and seams, saved as a garment file, built
//! into a `tailor.Simulation`) and `tailor.bend`. Logic lives in `tailor_core::garment`,
//! `garment_file` and `bend`; this file converts.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::bend::{bend_piece, BendMode, BendParams, SymmetryLine};
use tailor_core::garment::{self as core, BuildOptions, Layout};
use tailor_core::garment_file::setup::maps;
use tailor_core::garment_file::{self, GarmentPiece, ParticleParam};
use tailor_core::pattern::Placement;
use tailor_core::triangulate::{PieceMesh as CoreMesh, TriangulateOptions, MESHER_VERSION};
use tailor_core::TailorError;

use crate::convert::{points2, points3};
use crate::errors::to_py;
use crate::patterns::{placement_dict, read_options, rows, Piece, PieceMesh};
use crate::seams::Seam;
use crate::settings::{Fabric, Settings};
use crate::weld::WeldedMesh;

/// A garment: pattern pieces with their resolution, placement and bend, and the seams between
/// them. Meshes are rebuilt from the pieces (triangulation is deterministic) and cached.
#[pyclass(module = "tailor")]
pub struct Garment {
    inner: garment_file::Garment,
    meshes: Option<Vec<CoreMesh>>,
    /// What the last `build_simulation` left out or changed, for the user.
    build_warnings: Vec<String>,
}

impl Garment {
    /// Runs one part of the setup on `sim`; returns its warnings.
    fn apply_part(
        &mut self,
        py: Python<'_>,
        sim: &Bound<'_, crate::simulation::Simulation>,
        f: impl FnOnce(
            &mut tailor_core::solver::Simulation,
            &garment_file::Garment,
            &Layout,
            &mut Vec<String>,
        ) -> tailor_core::Result<()>,
    ) -> PyResult<Vec<String>> {
        {
            let layout = Layout::of_meshes(self.meshes_ref(py)?);
            if layout.particles() != sim.borrow_mut().edit(|s| s.num_particles())? {
                return Err(to_py(TailorError::shape(
                    "Garment.apply",
                    "the simulation was not built from this garment",
                )));
            }
            self.inner.setup.validate(layout.vertices.len()).map_err(to_py)?;
            let mut warnings = Vec::new();
            let g = &self.inner;
            sim.borrow_mut().edit(|s| f(s, g, &layout, &mut warnings))?.map_err(to_py)?;
            Ok(warnings)
        }
    }

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
    #[pyo3(signature = (path, edge=0.01, size=None, units=None, tolerance=0.0005, unfold=true, quantities=true))]
    #[allow(clippy::too_many_arguments)]
    fn from_pattern(
        py: Python<'_>,
        path: PathBuf,
        edge: f64,
        size: Option<String>,
        units: Option<&str>,
        tolerance: f64,
        unfold: bool,
        quantities: bool,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let read = read_options(size, units, tolerance, unfold, quantities)?;
            let (_, inner, meshes) =
                py.detach(|| core::read_garment(&path, &read, &TriangulateOptions::new(edge))).map_err(to_py)?;
            Ok(Self { inner, meshes: Some(meshes), build_warnings: Vec::new() })
        })
    }

    /// A garment from its parts, e.g. as a host application (the Blender add-on) keeps them:
    /// `pieces` with their target edge lengths, `seams` over piece indices, and per piece an
    /// optional placement (`{"translation", "rotation_deg", "flipped"}`, as `Piece.placement`;
    /// it overrides the piece's own) and bend (`{"axis_point", "axis_direction", "angle_deg",
    /// "symmetry", "threshold", "radius", "mode"}`, as `set_bend` takes them) and the mesher that made its mesh
    /// (`meshers`, default `MESHER_VERSION` for every piece; see `triangulate`). Every seam is
    /// checked against the meshes. `positions` (per piece an (n, 3) array or None): the piece
    /// as placed, used instead of placing and bending it (kept in the file as the painted map
    /// `position`), so a garment placed by hand simulates exactly as it stands.
    #[staticmethod]
    #[pyo3(signature = (pieces, edge_lengths, seams, placements=None, bends=None, meshers=None, positions=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_parts(
        py: Python<'_>,
        pieces: Vec<Piece>,
        edge_lengths: Vec<f64>,
        seams: Vec<Seam>,
        placements: Option<Vec<Option<Bound<'_, PyDict>>>>,
        bends: Option<Vec<Option<Bound<'_, PyDict>>>>,
        meshers: Option<Vec<u32>>,
        positions: Option<Vec<Option<Bound<'_, PyAny>>>>,
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
            let positions = positions.unwrap_or_else(|| vec![None; n]);
            count("positions", positions.len())?;
            for (piece, p) in positions.iter().enumerate() {
                if let Some(p) = p {
                    let v = crate::setup::values(maps::POSITION, p, None, meshes[piece].rest.len(), &inner.setup)?;
                    inner.particle_params.push(ParticleParam { name: maps::POSITION.into(), piece, values: v });
                }
            }
            Ok(Self { inner, meshes: Some(meshes), build_warnings: Vec::new() })
        })
    }

    /// Reads a garment file (`NAME.json` with its `NAME.bin` sidecar).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        crate::errors::guard(|| {
            Ok(Self { inner: garment_file::load(&path).map_err(to_py)?, meshes: None, build_warnings: Vec::new() })
        })
    }

    /// Writes the garment file (`path`, plus its `.bin` sidecar next to it).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        crate::errors::guard(|| garment_file::save(&self.inner, &path).map_err(to_py))
    }

    /// The file's free-form named settings (its manifest's `settings` object) as JSON text:
    /// other tools' data, kept as read (the garment's own setup is `setup`).
    #[getter]
    fn settings_json(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            serde_json::to_string(&self.inner.settings)
                .map_err(|e| to_py(TailorError::shape("garment settings", e.to_string())))
        })
    }

    /// The painted per-particle parameters as `(name, piece, values)`: float32, int32 or bool
    /// arrays, one value per vertex of that piece's mesh ((n, 3) float32 for `position`), as
    /// the sidecar holds them.
    #[getter]
    fn particle_params<'py>(&self, py: Python<'py>) -> PyResult<Vec<(String, usize, Bound<'py, PyAny>)>> {
        crate::errors::guard(|| {
            self.inner
                .particle_params
                .iter()
                .map(|p| Ok((p.name.clone(), p.piece, crate::setup::to_numpy(py, &p.values)?)))
                .collect()
        })
    }

    /// The source pattern pieces, in garment order.
    #[getter]
    fn pieces(&self) -> PyResult<Vec<Piece>> {
        crate::errors::guard(|| Ok(self.inner.pieces.iter().map(|p| Piece { inner: p.source.clone() }).collect()))
    }

    /// Each piece's placement in effect (its own, else its pattern piece's) as `from_parts`
    /// takes it (`{"translation", "rotation_deg", "flipped"}`), or None.
    #[getter]
    fn placements<'py>(&self, py: Python<'py>) -> PyResult<Vec<Option<Bound<'py, PyDict>>>> {
        crate::errors::guard(|| {
            self.inner.pieces.iter().map(|p| placement_dict(py, &p.placement_in_effect().cloned())).collect()
        })
    }

    /// Each piece's bend as `from_parts` and `set_bend` take it (`{"axis_point",
    /// "axis_direction", "angle_deg", "symmetry", "threshold", "radius", "mode"}`, `symmetry` =
    /// ((x, y), (dx, dy)) or None), or None for an unbent piece.
    #[getter]
    fn bends<'py>(&self, py: Python<'py>) -> PyResult<Vec<Option<Bound<'py, PyDict>>>> {
        crate::errors::guard(|| {
            self.inner.pieces.iter().map(|p| p.bend.as_ref().map(|b| bend_dict(py, b)).transpose()).collect()
        })
    }

    /// The mesher version of each piece's mesh (see `triangulate`).
    #[getter]
    fn meshers(&self) -> PyResult<Vec<u32>> {
        crate::errors::guard(|| Ok(self.inner.pieces.iter().map(|p| p.options.mesher).collect()))
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

    /// Bends piece `piece` after placement (see `tailor.bend`); `angle_deg = 0` without a
    /// `radius` removes it.
    #[pyo3(signature = (piece, axis_point, axis_direction, angle_deg, symmetry=None, threshold=0.0, radius=None, mode="roll", taper_deg=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn set_bend(
        &mut self,
        piece: usize,
        axis_point: [f64; 3],
        axis_direction: [f64; 3],
        angle_deg: f64,
        symmetry: Option<([f64; 2], [f64; 2])>,
        threshold: f64,
        radius: Option<f64>,
        mode: &str,
        taper_deg: f64,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let n = self.inner.pieces.len();
            let p = self.inner.pieces.get_mut(piece).ok_or_else(|| {
                to_py(TailorError::setting("piece", piece, format!("must be a piece index below {n}")))
            })?;
            let params = bend_params(
                axis_point,
                axis_direction,
                angle_deg,
                symmetry,
                threshold,
                radius,
                BendMode::parse(mode).map_err(to_py)?,
                taper_deg,
            );
            p.bend = if angle_deg == 0.0 && radius.is_none() { None } else { Some(params) };
            Ok(())
        })
    }

    /// Warnings recorded at import (for example internal lines that had to be dropped).
    #[getter]
    fn warnings(&self) -> PyResult<Vec<String>> {
        crate::errors::guard(|| Ok(core::import_warnings(&self.inner)))
    }

    /// The garment's setup as a dict (the garment file's `setup`): `name`, `fabrics` (one
    /// `{"density", "stretch", "shear", "bend"}` per piece, with `stretch_v`, `bend_bias` and
    /// `bend_v` where the fabric is anisotropic, or empty for the default fabric),
    /// `thickness`, `friction` (`{"static", "kinetic"}`: the cloth's, against itself and, where
    /// painted, against colliders), `self_collision`, `self_collision_radius` (0: automatic),
    /// `pin_mode` ("attach": ride on the collider once the seams have met; "fixed": held in
    /// place), `pin_stiffness` (N/m at weight 1), `seam_stiffness`, `seam_bend_stiffness`,
    /// `collider_levels` (`{"vertices", "runs": [[start, length, level], ...]}` or None).
    /// Assign a dict to change it: missing keys take their defaults, unknown keys and bad values
    /// are refused (nothing changes then).
    #[getter]
    fn setup<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| crate::setup::to_dict(py, &self.inner.setup))
    }

    #[setter(setup)]
    fn set_setup(&mut self, py: Python<'_>, setup: Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let s = crate::setup::from_dict(py, &setup)?;
            s.validate(self.inner.pieces.len()).map_err(to_py)?;
            self.inner.setup = s;
            Ok(())
        })
    }

    /// Paints map `name` (one of `PAINTED_MAPS`: pin, collision_level, friction_static,
    /// friction_kinetic, mass_scale, bend_scale, position) on piece `piece`: one value per
    /// vertex of its mesh ((n, 3) for `position`); `painted` (bools, optional) marks the painted
    /// vertices, the others taking the unpainted value (pin 0, level 0, scales 1, friction the
    /// setup's). Replaces what the piece had for that map.
    #[pyo3(signature = (name, piece, values, painted=None))]
    fn set_painted(
        &mut self,
        py: Python<'_>,
        name: &str,
        piece: usize,
        values: Bound<'_, PyAny>,
        painted: Option<Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let count = self
                .meshes_ref(py)?
                .get(piece)
                .map(|m| m.rest.len())
                .ok_or_else(|| to_py(TailorError::setting("piece", piece, "no such piece")))?;
            let v = crate::setup::values(name, &values, painted.as_ref(), count, &self.inner.setup)?;
            self.inner.particle_params.retain(|p| !(p.name == name && p.piece == piece));
            self.inner.particle_params.push(ParticleParam { name: name.into(), piece, values: v });
            Ok(())
        })
    }

    /// Records the collision levels painted on the collider (one per vertex) in the setup
    /// (`collider_levels`, run-length encoded); None or all zero: none.
    #[pyo3(signature = (levels=None))]
    fn set_collider_levels(&mut self, levels: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        crate::errors::guard(|| {
            let levels = levels.map(|l| crate::colliders::levels(&l, "collider levels")).transpose()?;
            self.inner.setup.collider_levels = levels
                .filter(|l| l.iter().any(|&x| x != 0))
                .map(|l| tailor_core::garment_file::setup::ColliderLevels::encode(&l));
            Ok(())
        })
    }

    /// Removes painted map `name` (every map when None) from every piece.
    #[pyo3(signature = (name=None))]
    fn clear_painted(&mut self, name: Option<&str>) -> PyResult<()> {
        crate::errors::guard(|| {
            self.inner.particle_params.retain(|p| name.is_some_and(|n| p.name != n));
            Ok(())
        })
    }

    /// Builds the sewn cloth and its `tailor.Simulation`, configured by the garment's setup in
    /// the core (`tailor_core::garment::apply_setup`): every seam (its spring constant is the
    /// setup's `seam_stiffness` N/m times its own factor, unless `seam_stiffness` is given),
    /// fabric per piece (`fabric`, when given, stands for every piece), the painted maps,
    /// thickness, self-collision, and pins: held in place when the setup's `pin_mode` is
    /// "fixed" or `ride` is false (no collider to ride on), else left for `attach_groups`.
    /// Pieces without a placement are laid side by side `gap` metres apart. Returns
    /// `(simulation, offsets)`: `offsets[i]` is the index of piece `i`'s first particle. What
    /// the build left out (a painted map for another mesh) is in `build_warnings`.
    #[pyo3(signature = (fabric=None, settings=None, seam_stiffness=None, seam_bend_stiffness=None, gap=0.05,
                        backend="auto", ride=true))]
    #[allow(clippy::too_many_arguments)]
    fn build_simulation<'py>(
        &mut self,
        py: Python<'py>,
        fabric: Option<Fabric>,
        settings: Option<Settings>,
        seam_stiffness: Option<f32>,
        seam_bend_stiffness: Option<f32>,
        gap: f64,
        backend: &str,
        ride: bool,
    ) -> PyResult<(Bound<'py, PyAny>, Vec<u32>)> {
        crate::errors::guard(|| {
            let mut options = BuildOptions { gap, ..BuildOptions::of(&self.inner) };
            options.seam_stiffness = seam_stiffness.unwrap_or(options.seam_stiffness);
            options.seam_bend_stiffness = seam_bend_stiffness.unwrap_or(options.seam_bend_stiffness);
            let fabric = fabric.as_ref().map(tailor_core::solver::Fabric::from);
            let settings = settings.map(|s| s.to_core()).transpose()?.unwrap_or_default();
            let backend = crate::simulation::parse_backend(backend)?;
            self.meshes_ref(py)?;
            let g = &self.inner;
            let (sim, input, applied) =
                py.detach(|| core::build_configured(g, fabric, settings, &options, ride)).map_err(to_py)?;
            self.build_warnings = applied.warnings;
            let sim = crate::simulation::Simulation::wrap(sim, backend);
            Ok((Bound::new(py, sim)?.into_any(), input.sewn.offsets.clone()))
        })
    }

    /// The seams' sewn points in the sewn cloth's particle indices, as `build_simulation` adds
    /// them (a dart's tip, sewn to itself, left out), in `Simulation.seam_pairs()`'s form,
    /// without building a simulation.
    fn seam_pairs<'py>(&mut self, py: Python<'py>) -> PyResult<Vec<Bound<'py, pyo3::types::PyDict>>> {
        crate::errors::guard(|| {
            let meshes = self.meshes_ref(py)?.clone();
            let options = BuildOptions::of(&self.inner);
            let g = &self.inner;
            let input = py.detach(|| core::solver_input(g, meshes, &options)).map_err(to_py)?;
            crate::simulation::seam_dicts(py, &input.seams)
        })
    }

    /// What the last `build_simulation` left out or changed (a painted map that no longer fits
    /// its piece, pins held in place for want of a collider), one line each.
    #[getter]
    fn build_warnings(&self) -> PyResult<Vec<String>> {
        crate::errors::guard(|| Ok(self.build_warnings.clone()))
    }

    /// Applies the setup's fabric per piece and the painted mass and bend scales to `sim` (a
    /// simulation this garment built), as `build_simulation` does: a live edit.
    fn apply_fabric(
        &mut self,
        py: Python<'_>,
        sim: &Bound<'_, crate::simulation::Simulation>,
    ) -> PyResult<Vec<String>> {
        crate::errors::guard(|| self.apply_part(py, sim, core::apply_fabric))
    }

    /// Applies the painted friction (or none) to `sim`, as `build_simulation` does.
    fn apply_friction(
        &mut self,
        py: Python<'_>,
        sim: &Bound<'_, crate::simulation::Simulation>,
    ) -> PyResult<Vec<String>> {
        crate::errors::guard(|| self.apply_part(py, sim, core::apply_friction))
    }

    /// Applies the setup's thickness and self-collision to `sim`, as `build_simulation` does.
    fn apply_collision(
        &mut self,
        py: Python<'_>,
        sim: &Bound<'_, crate::simulation::Simulation>,
    ) -> PyResult<Vec<String>> {
        crate::errors::guard(|| self.apply_part(py, sim, |s, g, _, _| core::apply_collision(s, g)))
    }

    /// The painted pins by weight: `[(weight, particles)]`, weight 1 first (weights at or above
    /// 0.999), then lighter ones rounded to 1/20, lightest first.
    fn pin_weights<'py>(&mut self, py: Python<'py>) -> PyResult<Vec<(f32, Bound<'py, PyAny>)>> {
        crate::errors::guard(|| {
            let layout = Layout::of_meshes(self.meshes_ref(py)?);
            let groups = core::setup::painted_pins(&self.inner, &layout).map_err(to_py)?;
            Ok(groups
                .into_iter()
                .map(|(w, p)| (w, numpy::PyArray1::from_vec(py, p.into_iter().map(i64::from).collect()).into_any()))
                .collect())
        })
    }

    /// The pins to attach to the collider once every seam has met (`tailor.bake.ColliderPins`):
    /// `[(particles, stiffness N/m)]`, the setup's `pin_stiffness` times each painted weight
    /// (weights at or above 0.999 count as 1; lighter ones are rounded to 1/20). Empty when
    /// the setup's `pin_mode` is "fixed" or nothing is pinned.
    fn attach_groups<'py>(&mut self, py: Python<'py>) -> PyResult<Vec<(Bound<'py, PyAny>, f32)>> {
        crate::errors::guard(|| {
            let layout = Layout::of_meshes(self.meshes_ref(py)?);
            let groups = core::pin_groups(&self.inner, &layout).map_err(to_py)?;
            Ok(crate::setup::groups(py, &groups))
        })
    }

    /// The collision levels the setup records for a collider of `num_vertices` vertices:
    /// `(levels or None, warnings)`; None with a warning when they were painted on a mesh of
    /// another vertex count.
    fn collider_levels<'py>(
        &self,
        py: Python<'py>,
        num_vertices: usize,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, Vec<String>)> {
        crate::errors::guard(|| {
            match &self.inner.setup.collider_levels {
            None => Ok((None, Vec::new())),
            Some(l) if l.vertices != num_vertices => Ok((
                None,
                vec![format!(
                    "the garment's collider levels are for a mesh of {} vertices, the collider has {num_vertices}: left out",
                    l.vertices
                )],
            )),
            Some(l) => Ok((Some(numpy::PyArray1::from_vec(py, l.decode().map_err(to_py)?).into_any()), Vec::new())),
        }
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

/// A bend as `bend_from` reads it back.
pub(crate) fn bend_dict<'py>(py: Python<'py>, b: &BendParams) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("axis_point", b.axis_point.to_vec())?;
    d.set_item("axis_direction", b.axis_direction.to_vec())?;
    d.set_item("angle_deg", b.angle_deg)?;
    let pair = |v: [f64; 2]| (v[0], v[1]);
    d.set_item("symmetry", b.symmetry.as_ref().map(|s| (pair(s.point), pair(s.direction))))?;
    d.set_item("threshold", b.threshold)?;
    d.set_item("radius", b.radius)?;
    d.set_item("mode", b.mode.name())?;
    d.set_item("taper_deg", b.taper_deg)?;
    Ok(d)
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
    let radius: Option<f64> = match d.get_item("radius")? {
        Some(v) if !v.is_none() => Some(v.extract()?),
        _ => None,
    };
    let mode = match d.get_item("mode")? {
        Some(v) if !v.is_none() => BendMode::parse(&v.extract::<String>()?).map_err(to_py)?,
        _ => BendMode::Roll,
    };
    let taper_deg = match d.get_item("taper_deg")? {
        Some(v) if !v.is_none() => v.extract()?,
        _ => 0.0,
    };
    Ok(bend_params(
        item(d, "axis_point", "bend")?.extract()?,
        item(d, "axis_direction", "bend")?.extract()?,
        item(d, "angle_deg", "bend")?.extract()?,
        symmetry,
        threshold,
        radius,
        mode,
        taper_deg,
    ))
}

#[allow(clippy::too_many_arguments)]
fn bend_params(
    axis_point: [f64; 3],
    axis_direction: [f64; 3],
    angle_deg: f64,
    symmetry: Option<([f64; 2], [f64; 2])>,
    threshold: f64,
    radius: Option<f64>,
    mode: BendMode,
    taper_deg: f64,
) -> BendParams {
    BendParams {
        axis_point,
        axis_direction,
        angle_deg,
        symmetry: symmetry.map(|(point, direction)| SymmetryLine { point, direction }),
        threshold,
        radius,
        mode,
        taper_deg,
    }
}

/// Rolls a flat placed piece onto a cylinder round an axis, keeping lengths along it (paper
/// Fig. 4, made isometric: `tailor_core::bend`); returns the new (n, 3) positions.
/// `symmetry` = ((x, y), (dx, dy)), a rest-frame line whose sides roll in opposite senses;
/// `radius` sets the cylinder instead of `angle_deg`, whose sign then only says which way it rolls;
/// `taper_deg` rolls it onto a cone instead (for a tapered limb), whose radius is the cylinder's
/// level with `axis_point` and grows by `sin(taper_deg)` per metre along `axis_direction`.
#[pyfunction]
#[pyo3(signature = (positions, rest, axis_point, axis_direction, angle_deg, symmetry=None, threshold=0.0, radius=None, mode="roll", taper_deg=0.0))]
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
    radius: Option<f64>,
    mode: &str,
    taper_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    crate::errors::guard(|| {
        let mut p = points3(positions, "positions")?;
        let r = points2(rest, "rest")?;
        let mode = BendMode::parse(mode).map_err(to_py)?;
        let params = bend_params(axis_point, axis_direction, angle_deg, symmetry, threshold, radius, mode, taper_deg);
        bend_piece(&mut p, &r, &params).map_err(to_py)?;
        rows(py, &p)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Garment>()?;
    m.add_function(wrap_pyfunction!(bend, m)?)
}
