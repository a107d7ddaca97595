//! `tailor.Simulation`: the core solver behind a Python object. Every solve releases the GIL.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::engine::{Backend, Solver, SolverOptions};
use tailor_core::garment::DEFAULT_SEAM_STIFFNESS;
use tailor_core::mesh::ClothMesh;
use tailor_core::solver::{
    self as core, Attachment, ColliderId, ImplicitCollider, RampPhase, ReferenceOptions, Seam, SeamPoint, Shape,
    StepStats,
};

use crate::colliders;
use crate::convert::{floats, indices, points2, points3, soa_to_numpy, triangles, vec64_to_numpy, vec_to_numpy};
use crate::errors::to_py;
use crate::settings::{parse_method, Fabric, Settings};

/// A cloth simulation: positions (n, 3), triangles (m, 3) and the flat 2D rest shape (n, 2),
/// all in metres.
#[pyclass(module = "tailor")]
pub struct Simulation {
    /// `None` while a call that releases the GIL (`step`, `measure_step`, `metrics`,
    /// `attach_to_collider`) or an unfinished `step_async` / `metrics_async` (`background.rs`)
    /// has it: another call then gets a `SimulationError`
    /// saying so, where it got pyo3's `RuntimeError: Already borrowed` (see [`Self::detached`]).
    inner: Option<Solver>,
}

fn busy() -> PyErr {
    to_py(tailor_core::TailorError::Busy {
        what: "this Simulation is in use by a call in another thread (step, measure_step, metrics or \
               attach_to_collider) or by an unfinished step_async / metrics_async; wait for it to \
               return, or finish it"
            .into(),
    })
}

impl Simulation {
    fn solver(&self) -> PyResult<&Solver> {
        self.inner.as_ref().ok_or_else(busy)
    }

    fn solver_mut(&mut self) -> PyResult<&mut Solver> {
        self.inner.as_mut().ok_or_else(busy)
    }

    /// Takes the solver out (the simulation says busy until [`Self::put_back`]): a step on a
    /// native thread owns it meanwhile (`background.rs`).
    pub(crate) fn take_solver(slf: &Bound<'_, Self>) -> PyResult<Solver> {
        slf.try_borrow_mut().map_err(|_| busy())?.inner.take().ok_or_else(busy)
    }

    /// A mesh collider's id from Python's (None stays None).
    fn collider_of(slf: &Bound<'_, Self>, collider: Option<i64>) -> PyResult<Option<ColliderId>> {
        let meshes = slf.borrow().solver()?.simulation().num_mesh_colliders();
        collider.map(|c| colliders::collider_id(c, meshes)).transpose()
    }

    pub(crate) fn put_back(slf: &Bound<'_, Self>, solver: Solver) -> PyResult<()> {
        slf.try_borrow_mut().map_err(|_| busy())?.inner = Some(solver);
        Ok(())
    }

    /// Runs `f` on the solver with the GIL released and no borrow of `slf` held, so that other
    /// threads may call in meanwhile (and are told the simulation is busy, by a TailorError).
    /// A panic in `f` loses the solver: later calls say busy (the panic was an InternalError).
    fn detached<T: Send>(slf: &Bound<'_, Self>, f: impl FnOnce(&mut Solver) -> T + Send) -> PyResult<T> {
        let mut solver = slf.try_borrow_mut().map_err(|_| busy())?.inner.take().ok_or_else(busy)?;
        let out = slf.py().detach(|| f(&mut solver));
        slf.try_borrow_mut().map_err(|_| busy())?.inner = Some(solver);
        Ok(out)
    }
}

impl Simulation {
    /// A simulation of a core one built elsewhere (`Garment.build_simulation`).
    pub fn wrap(sim: core::Simulation, backend: Backend) -> Self {
        Self { inner: Some(Solver::new(sim, backend)) }
    }

    /// Runs a core edit on the simulation (the GPU copy is marked stale).
    pub fn edit<R>(&mut self, f: impl FnOnce(&mut core::Simulation) -> R) -> PyResult<R> {
        Ok(self.solver_mut()?.edit(f))
    }
}

/// The dict of `Simulation.fit_maps`: `strain`, `distance` and `pressure` arrays (the last two
/// None without a collider).
pub fn fit_maps_dict(py: Python<'_>, m: tailor_core::quality::fit_maps::FitMaps) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("strain", PyArray1::from_vec(py, m.strain))?;
    d.set_item("distance", m.distance.map(|v| PyArray1::from_vec(py, v)))?;
    d.set_item("pressure", m.pressure.map(|v| PyArray1::from_vec(py, v)))?;
    Ok(d)
}

/// Seams as `seam_pairs` gives them: name, stiffness, bend_stiffness, and per side the sewn
/// points as (k, 2) vertex and weight arrays (a vertex has weights (1, 0)).
pub fn seam_dicts<'py>(py: Python<'py>, seams: &[Seam]) -> PyResult<Vec<Bound<'py, PyDict>>> {
    seams
        .iter()
        .map(|s| {
            let d = PyDict::new(py);
            d.set_item("name", s.name.as_str())?;
            d.set_item("stiffness", s.stiffness)?;
            d.set_item("bend_stiffness", s.bend_stiffness)?;
            let side = |f: fn(&(SeamPoint, SeamPoint)) -> SeamPoint| s.pairs.iter().map(f).collect::<Vec<_>>();
            for (key, pts) in [("a", side(|p| p.0)), ("b", side(|p| p.1))] {
                let v: Vec<[u32; 2]> = pts.iter().map(|p| p.verts).collect();
                let w: Vec<[f32; 2]> = pts.iter().map(|p| p.weights).collect();
                d.set_item(format!("{key}_vertices"), crate::patterns::rows(py, &v)?)?;
                d.set_item(format!("{key}_weights"), crate::patterns::rows(py, &w)?)?;
            }
            Ok(d)
        })
        .collect()
}

pub fn parse_backend(name: &str) -> PyResult<Backend> {
    match name {
        "auto" => Ok(Backend::Auto),
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        other => {
            Err(to_py(tailor_core::TailorError::setting("backend", other, "expected \"auto\", \"cpu\" or \"gpu\"")))
        }
    }
}

fn backend_name(b: core::ActiveBackend) -> &'static str {
    match b {
        core::ActiveBackend::Cpu => "cpu",
        core::ActiveBackend::Gpu => "gpu",
    }
}

pub(crate) fn stats_dict<'py>(py: Python<'py>, s: &StepStats, adapter: Option<String>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("backend", backend_name(s.backend))?;
    d.set_item("adapter", adapter)?;
    d.set_item("warning", s.warning.clone())?;
    d.set_item("substeps", s.substeps)?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("residual", s.residual)?;
    d.set_item("colours", s.colours)?;
    d.set_item("rho", s.rho)?;
    let t = PyDict::new(py);
    for (stage, seconds) in s.timings.iter() {
        t.set_item(stage.name(), seconds)?;
    }
    t.set_item("total", s.timings.total())?;
    d.set_item("timings", t)?;
    d.set_item("damping", s.damping)?;
    let phase = match s.ramp_phase {
        RampPhase::Closing => "closing",
        RampPhase::Releasing { .. } => "releasing",
        RampPhase::Done => "done",
    };
    d.set_item("ramp_phase", phase)?;
    d.set_item("seam_gap_max", s.seam_gap_max)?;
    d.set_item("seam_closed_fraction", s.seam_closed_fraction)?;
    d.set_item("contacts", s.contacts)?;
    d.set_item("contact_motion_m", s.contact_motion)?;
    d.set_item("threads", s.threads)?;
    d.set_item("dispatches", s.dispatches)?;
    d.set_item("collision", crate::colliders::collision_stats_dict(py, &s.collision)?)?;
    Ok(d)
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (positions, triangles_, rest, fabric=None, settings=None, backend="auto"))]
    fn new(
        positions: &Bound<'_, PyAny>,
        triangles_: &Bound<'_, PyAny>,
        rest: &Bound<'_, PyAny>,
        fabric: Option<Fabric>,
        settings: Option<Settings>,
        backend: &str,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let backend = parse_backend(backend)?;
            let mesh = ClothMesh::new(
                points3(positions, "positions")?,
                points2(rest, "rest")?,
                triangles(triangles_, "triangles")?,
            )
            .map_err(to_py)?;
            let fabric = fabric.as_ref().map(core::Fabric::from).unwrap_or_default();
            let settings = match settings {
                Some(s) => s.to_core()?,
                None => core::SolverSettings::default(),
            };
            let sim = core::Simulation::new(mesh, fabric, settings).map_err(to_py)?;
            Ok(Self { inner: Some(Solver::new(sim, backend)) })
        })
    }

    /// Chooses the backend: "auto" (the GPU for large scenes on a hardware adapter), "cpu" or
    /// "gpu" (the CPU, with a warning in `backend_warning` and the step stats, when no
    /// adapter exists or the scene is not supported there). The state is kept.
    fn set_backend(&mut self, backend: &str) -> PyResult<()> {
        crate::errors::guard(|| {
            let backend = parse_backend(backend)?;
            self.solver_mut()?.set_backend(SolverOptions { backend, ..Default::default() });
            Ok(())
        })
    }

    /// Runs the CPU's work of this simulation (its steps and metrics) on `threads` threads of
    /// its own; None: the process's pool, one thread per core (or `RAYON_NUM_THREADS`). Results
    /// do not depend on it.
    #[pyo3(signature = (threads=None))]
    fn set_threads(&mut self, threads: Option<i64>) -> PyResult<()> {
        crate::errors::guard(|| {
            let n = match threads {
                Some(n) if n < 1 => {
                    return Err(to_py(tailor_core::TailorError::setting(
                        "threads",
                        n,
                        "must be at least 1 (None: one per core)",
                    )))
                }
                other => other.map(|n| n as usize),
            };
            self.solver_mut()?.set_threads(n).map_err(to_py)
        })
    }

    /// The CPU threads this simulation's work runs on.
    #[getter]
    fn threads(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.solver()?.threads()))
    }

    /// The backend the next step will use: "cpu" or "gpu".
    #[getter]
    fn backend(&self) -> PyResult<&'static str> {
        crate::errors::guard(|| Ok(backend_name(self.solver()?.active_backend())))
    }

    /// The GPU adapter in use (name, API, type, driver), or None on the CPU.
    #[getter]
    fn adapter(&self) -> PyResult<Option<String>> {
        crate::errors::guard(|| Ok(self.solver()?.adapter()))
    }

    /// How the GPU backend was set up, or None on the CPU: `{"context_made": bool,
    /// "seconds": float}`. The first GPU simulation of the process makes the shared context
    /// (adapter, device, every shader compiled); later ones reuse it.
    #[getter]
    fn gpu_setup<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        crate::errors::guard(|| {
            let Some((made, seconds)) = self.solver()?.gpu_setup() else { return Ok(None) };
            let d = PyDict::new(py);
            d.set_item("context_made", made)?;
            d.set_item("seconds", seconds)?;
            Ok(Some(d))
        })
    }

    /// Why the GPU asked for is not in use, or None.
    #[getter]
    fn backend_warning(&self) -> PyResult<Option<String>> {
        crate::errors::guard(|| Ok(self.solver()?.warning().map(str::to_owned)))
    }

    #[getter]
    fn num_particles(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.solver()?.simulation().num_particles()))
    }

    #[getter]
    fn num_triangles(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.solver()?.simulation().model().mesh.num_triangles()))
    }

    /// Positions, a new (n, 3) float32 array.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| soa_to_numpy(py, self.solver()?.positions()))
    }

    #[setter(positions)]
    fn set_positions(&mut self, p: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let positions = points3(p, "positions")?;
            self.solver_mut()?.edit(|sim| sim.set_positions(&positions)).map_err(to_py)
        })
    }

    /// Velocities (brought back from the GPU when it runs the simulation).
    #[getter]
    fn velocities<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| soa_to_numpy(py, self.solver_mut()?.velocities()))
    }

    #[setter(velocities)]
    fn set_velocities(&mut self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let velocities = points3(v, "velocities")?;
            self.solver_mut()?.edit(|sim| sim.set_velocities(&velocities)).map_err(to_py)
        })
    }

    /// Triangles, a new (m, 3) uint32 array (what other solvers need to run the same cloth).
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| crate::patterns::rows(py, self.solver()?.simulation().model().mesh.triangles()))
    }

    /// The flat 2D rest shape, a new (n, 2) float32 array, metres.
    #[getter]
    fn rest<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| crate::patterns::rows(py, self.solver()?.simulation().model().mesh.rest()))
    }

    /// Unique mesh edges, a new (k, 2) uint32 array (the edges the strain metric measures).
    #[getter]
    fn edges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| crate::patterns::rows(py, &self.solver()?.simulation().model().mesh.topology().edges))
    }

    /// The seams as added: one dict per seam with its name, stiffness, bend_stiffness and the
    /// sewn pairs as (k, 2) vertex and weight arrays per side (a vertex has weights (1, 0)).
    fn seam_pairs<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        crate::errors::guard(|| seam_dicts(py, &self.solver()?.simulation().model().seams))
    }

    /// Particle masses, kg (density × a third of adjacent rest areas × mass scale).
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| Ok(vec_to_numpy(py, self.solver()?.simulation().masses().to_vec())))
    }

    #[getter]
    fn settings(&self) -> PyResult<Settings> {
        crate::errors::guard(|| Ok(Settings::from(self.solver()?.simulation().settings())))
    }

    #[setter(settings)]
    fn set_settings(&mut self, s: Settings) -> PyResult<()> {
        crate::errors::guard(|| {
            let settings = s.to_core()?;
            self.solver_mut()?.edit(|sim| sim.set_settings(settings)).map_err(to_py)
        })
    }

    /// Collision thickness, metres.
    #[setter(thickness)]
    fn set_thickness(&mut self, t: f32) -> PyResult<()> {
        crate::errors::guard(|| self.solver_mut()?.edit(|sim| sim.set_thickness(t)).map_err(to_py))
    }

    fn set_mass_scale(&mut self, scale: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let scale = floats(scale, "mass scale")?;
            self.solver_mut()?.edit(|sim| sim.set_mass_scale(&scale)).map_err(to_py)
        })
    }

    /// Stretch and shear stiffness (N/m) per triangle; `stretch` along u (the pattern's x axis)
    /// and, unless `stretch_v` is given, along v too.
    #[pyo3(signature = (stretch, shear, stretch_v=None))]
    fn set_triangle_stiffness(
        &mut self,
        stretch: &Bound<'_, PyAny>,
        shear: &Bound<'_, PyAny>,
        stretch_v: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let (stretch, shear) = (floats(stretch, "stretch")?, floats(shear, "shear")?);
            let stretch_v = match stretch_v {
                Some(v) => floats(v, "stretch_v")?,
                None => stretch.clone(),
            };
            self.solver_mut()?.edit(|sim| sim.set_triangle_stiffness_uv(&stretch, &stretch_v, &shear)).map_err(to_py)
        })
    }

    /// The fabric's orientation per triangle: the angle of its u axis from the pattern's x axis,
    /// radians (a garment turns an anisotropic piece's fabric so that v lies along its grain
    /// line). Call before setting directional bending; 0 everywhere is the pattern's axes.
    fn set_triangle_grain(&mut self, angle: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let angle = floats(angle, "grain angle")?;
            self.solver_mut()?.edit(|sim| sim.set_triangle_grain(&angle)).map_err(to_py)
        })
    }

    /// Bending stiffness (N·m) per triangle; each interior edge's hinge takes the mean of its two.
    fn set_triangle_bending(&mut self, bend: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let bend = floats(bend, "bend")?;
            self.solver_mut()?.edit(|sim| sim.set_triangle_bending(&bend)).map_err(to_py)
        })
    }

    /// Bending rest shape from a pose (n, 3), keeping its creases; None = flat.
    #[pyo3(signature = (pose=None))]
    fn set_bending_rest_pose(&mut self, pose: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        crate::errors::guard(|| {
            let p = pose.map(|p| points3(p, "pose")).transpose()?;
            self.solver_mut()?.edit(|sim| sim.set_bending_rest_pose(p.as_deref())).map_err(to_py)
        })
    }

    /// Sews vertex path `a` to vertex path `b` one-to-one (equal counts). Returns the number
    /// of hinges created across the sewn edges.
    #[pyo3(signature = (a, b, stiffness=DEFAULT_SEAM_STIFFNESS, bend_stiffness=1e-5, name="seam"))]
    fn add_seam(
        &mut self,
        a: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
        stiffness: f32,
        bend_stiffness: f32,
        name: &str,
    ) -> PyResult<usize> {
        crate::errors::guard(|| {
            let n = self.solver_mut()?.simulation().num_particles();
            let (a, b) = (indices(a, "seam side A", n)?, indices(b, "seam side B", n)?);
            let seam = Seam::one_to_one(name, &a, &b, stiffness, bend_stiffness).map_err(to_py)?;
            self.solver_mut()?.edit(|sim| sim.add_seam(seam)).map_err(to_py)
        })
    }

    /// Sews weighted points: each side is (k, 2) vertex indices and (k, 2) weights summing to
    /// one per row (an edge point; a single vertex has weights (1, 0)). Seams of unequal
    /// vertex counts use this.
    #[pyo3(signature = (a_vertices, a_weights, b_vertices, b_weights, stiffness=DEFAULT_SEAM_STIFFNESS, bend_stiffness=1e-5, name="seam"))]
    #[allow(clippy::too_many_arguments)]
    fn add_weighted_seam(
        &mut self,
        a_vertices: &Bound<'_, PyAny>,
        a_weights: &Bound<'_, PyAny>,
        b_vertices: &Bound<'_, PyAny>,
        b_weights: &Bound<'_, PyAny>,
        stiffness: f32,
        bend_stiffness: f32,
        name: &str,
    ) -> PyResult<usize> {
        crate::errors::guard(|| {
            let n = self.solver_mut()?.simulation().num_particles();
            let side = |v: &Bound<'_, PyAny>, w: &Bound<'_, PyAny>, label: &str| -> PyResult<Vec<SeamPoint>> {
                let verts = indices(&crate::convert::flattened(v, label)?, label, n)?;
                let weights = floats(&crate::convert::flattened(w, label)?, label)?;
                if verts.len() != weights.len() || verts.len() % 2 != 0 {
                    return Err(to_py(tailor_core::TailorError::shape(
                        label,
                        "vertices and weights must both have shape (k, 2)",
                    )));
                }
                Ok(verts
                    .chunks_exact(2)
                    .zip(weights.chunks_exact(2))
                    .map(|(v, w)| SeamPoint { verts: [v[0], v[1]], weights: [w[0], w[1]] })
                    .collect())
            };
            let (a, b) = (side(a_vertices, a_weights, "seam side A")?, side(b_vertices, b_weights, "seam side B")?);
            if a.len() != b.len() {
                return Err(to_py(tailor_core::TailorError::InvalidSeam {
                    seam: name.into(),
                    reason: format!(
                        "{} points on side A and {} on side B: weighted seams pair row by row",
                        a.len(),
                        b.len()
                    ),
                }));
            }
            let seam = Seam { name: name.into(), pairs: a.into_iter().zip(b).collect(), stiffness, bend_stiffness };
            self.solver_mut()?.edit(|sim| sim.add_seam(seam)).map_err(to_py)
        })
    }

    /// Pins particles hard, at `targets` (k, 3) or where they are.
    #[pyo3(signature = (particles, targets=None))]
    fn pin(&mut self, particles: &Bound<'_, PyAny>, targets: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        crate::errors::guard(|| {
            let p = indices(particles, "pin", self.solver_mut()?.simulation().num_particles())?;
            let t = targets.map(|t| points3(t, "pin targets")).transpose()?;
            self.solver_mut()?.edit(|sim| sim.pin(&p, t.as_deref())).map_err(to_py)
        })
    }

    fn unpin(&mut self, particles: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let p = indices(particles, "unpin", self.solver_mut()?.simulation().num_particles())?;
            self.solver_mut()?.edit(|sim| sim.unpin(&p)).map_err(to_py)
        })
    }

    /// Soft attachments of particles to targets (k, 3) with a weight (N/m).
    fn add_attachments(
        &mut self,
        particles: &Bound<'_, PyAny>,
        targets: &Bound<'_, PyAny>,
        weight: f32,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let p = indices(particles, "attachments", self.solver_mut()?.simulation().num_particles())?;
            let t = points3(targets, "attachment targets")?;
            if t.len() != p.len() {
                return Err(to_py(tailor_core::TailorError::shape(
                    "attachments",
                    format!("{} targets for {} particles", t.len(), p.len()),
                )));
            }
            for (&particle, &target) in p.iter().zip(&t) {
                self.solver_mut()?
                    .edit(|sim| sim.add_attachment(Attachment { particle, target, weight }))
                    .map_err(to_py)?;
            }
            Ok(())
        })
    }

    fn set_attachment_targets(&mut self, targets: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let targets = points3(targets, "attachment targets")?;
            self.solver_mut()?.edit(|sim| sim.set_attachment_targets(&targets)).map_err(to_py)
        })
    }

    #[pyo3(signature = (center, radius, static_friction=0.5, kinetic_friction=0.3))]
    fn add_sphere_collider(
        &mut self,
        center: [f32; 3],
        radius: f32,
        static_friction: f32,
        kinetic_friction: f32,
    ) -> PyResult<()> {
        crate::errors::guard(|| self.add_collider(Shape::Sphere { center, radius }, static_friction, kinetic_friction))
    }

    #[pyo3(signature = (point, normal, static_friction=0.5, kinetic_friction=0.3))]
    fn add_plane_collider(
        &mut self,
        point: [f32; 3],
        normal: [f32; 3],
        static_friction: f32,
        kinetic_friction: f32,
    ) -> PyResult<()> {
        crate::errors::guard(|| self.add_collider(Shape::Plane { point, normal }, static_friction, kinetic_friction))
    }

    #[pyo3(signature = (a, b, radius, static_friction=0.5, kinetic_friction=0.3))]
    fn add_capsule_collider(
        &mut self,
        a: [f32; 3],
        b: [f32; 3],
        radius: f32,
        static_friction: f32,
        kinetic_friction: f32,
    ) -> PyResult<()> {
        crate::errors::guard(|| self.add_collider(Shape::Capsule { a, b, radius }, static_friction, kinetic_friction))
    }

    /// Advances `frames` frames of `dt` seconds each (the GIL is released while solving).
    /// Returns the statistics of the last frame.
    #[pyo3(signature = (dt, frames=1))]
    fn step<'py>(slf: &Bound<'py, Self>, py: Python<'py>, dt: f32, frames: u32) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let t0 = std::time::Instant::now();
            let stats = Self::detached(slf, |inner| {
                let mut last = StepStats::default();
                for _ in 0..frames.max(1) {
                    last = inner.step(dt)?;
                }
                Ok::<_, tailor_core::TailorError>(last)
            })?;
            let wall_s = t0.elapsed().as_secs_f64();
            let stats = stats.map_err(to_py)?;
            let adapter =
                if stats.backend == core::ActiveBackend::Gpu { slf.borrow().solver()?.adapter() } else { None };
            let d = stats_dict(py, &stats, adapter)?;
            d.set_item("wall_s", wall_s)?;
            Ok(d)
        })
    }

    /// `step` on a native thread: returns at once with a `Pending` (`done`, `wait`, `finish`);
    /// the simulation says busy until it is finished. With `measure`, the statistics also hold
    /// `metrics`: `metrics(collider)` of the state reached, computed on the same thread. For
    /// hosts whose other threads must never run Python meanwhile (Blender: see `background.rs`).
    #[pyo3(signature = (dt, frames=1, *, measure=false, collider=None))]
    fn step_async(
        slf: &Bound<'_, Self>,
        dt: f32,
        frames: u32,
        measure: bool,
        collider: Option<i64>,
    ) -> PyResult<crate::background::Pending> {
        crate::errors::guard(|| {
            let id = Self::collider_of(slf, collider)?;
            crate::background::start(slf, crate::background::Work::Step { dt, frames, measure: measure.then_some(id) })
        })
    }

    /// `metrics` on a native thread, as `step_async`.
    #[pyo3(signature = (collider=None))]
    fn metrics_async(slf: &Bound<'_, Self>, collider: Option<i64>) -> PyResult<crate::background::Pending> {
        crate::errors::guard(|| {
            let id = Self::collider_of(slf, collider)?;
            crate::background::start(slf, crate::background::Work::Metrics(id))
        })
    }

    /// (largest sewn-pair gap in metres, fraction of pairs under the ramp threshold).
    fn seam_gaps(&self) -> PyResult<(f32, f32)> {
        crate::errors::guard(|| Ok(self.solver()?.simulation().seam_gaps()))
    }

    fn colour_count(&mut self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.solver_mut()?.edit(|sim| sim.colour_count())))
    }

    fn state_hash(&self) -> PyResult<u64> {
        crate::errors::guard(|| Ok(self.solver()?.simulation().state_hash()))
    }

    /// Measures `iterations` iterations of `method` on the next substep against the reference
    /// solution; the simulation is unchanged. Returns per-iteration arrays.
    #[pyo3(signature = (dt, method="chebyshev", iterations=100, reference_iterations=5000, reference_tolerance=1e-7))]
    fn measure_step<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
        dt: f32,
        method: &str,
        iterations: u32,
        reference_iterations: u32,
        reference_tolerance: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let method = parse_method(method)?;
            let opts = ReferenceOptions { max_iterations: reference_iterations, tolerance_m: reference_tolerance };
            let m = Self::detached(slf, |inner| inner.edit(|s| s.measure_step(dt, method, iterations, opts)))?
                .map_err(to_py)?;
            let d = PyDict::new(py);
            let r = PyDict::new(py);
            r.set_item("iterations", m.reference.iterations)?;
            r.set_item("last_change", m.reference.last_change)?;
            r.set_item("gradient_rel", m.reference.gradient_rel)?;
            r.set_item("seconds", m.reference.seconds)?;
            d.set_item("reference", r)?;
            let col = |f: &dyn Fn(&core::IterationRecord) -> f64| m.records.iter().map(f).collect::<Vec<f64>>();
            d.set_item(
                "iteration",
                PyArray1::from_vec(py, m.records.iter().map(|r| r.iteration).collect::<Vec<u32>>()),
            )?;
            d.set_item("seconds", vec64_to_numpy(py, col(&|r| r.seconds)))?;
            d.set_item("objective_rel", vec64_to_numpy(py, col(&|r| r.measures.objective_rel)))?;
            d.set_item("residual_rel", vec64_to_numpy(py, col(&|r| r.measures.residual_rel)))?;
            d.set_item("distance_rel", vec64_to_numpy(py, col(&|r| r.measures.distance_rel)))?;
            d.set_item("distance_max", vec64_to_numpy(py, col(&|r| r.measures.distance_max)))?;
            Ok(d)
        })
    }

    // ----- mesh colliders, levels, friction, self-collision, metrics (see colliders.rs) -----

    /// Adds an animated mesh collider (outward-facing triangles); returns its id. Give its
    /// positions once per frame with `set_collider_positions`.
    #[pyo3(signature = (vertices, triangles_, static_friction=0.5, kinetic_friction=0.3, cell_size=None, insertion="paper_or_plane"))]
    fn add_mesh_collider(
        &mut self,
        vertices: &Bound<'_, PyAny>,
        triangles_: &Bound<'_, PyAny>,
        static_friction: f32,
        kinetic_friction: f32,
        cell_size: Option<f32>,
        insertion: &str,
    ) -> PyResult<u32> {
        crate::errors::guard(|| {
            let opts = core::MeshColliderOptions {
                static_friction,
                kinetic_friction,
                cell_size,
                rule: colliders::insertion_rule(insertion)?,
            };
            let (v, t) = (points3(vertices, "collider vertices")?, triangles(triangles_, "collider triangles")?);
            Ok(self.solver_mut()?.edit(|sim| sim.add_mesh_collider(&v, &t, opts)).map_err(to_py)?.0)
        })
    }

    #[getter]
    fn num_mesh_colliders(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.solver()?.simulation().num_mesh_colliders()))
    }

    /// The collider's vertex positions (n, 3) at the end of the next step.
    fn set_collider_positions(&mut self, collider: i64, positions: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let id = colliders::collider_id(collider, self.solver_mut()?.simulation().num_mesh_colliders())?;
            self.solver_mut()?.set_collider_positions(id, &points3(positions, "collider positions")?).map_err(to_py)
        })
    }

    /// The collider's positions at the last substep run.
    fn collider_positions<'py>(&self, py: Python<'py>, collider: i64) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let id = colliders::collider_id(collider, self.solver()?.simulation().num_mesh_colliders())?;
            colliders::rows_to_numpy(py, self.solver()?.simulation().collider_positions(id).map_err(to_py)?)
        })
    }

    /// Collision levels of a collider, one per vertex or one per triangle.
    fn set_collider_levels(&mut self, collider: i64, levels: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let id = colliders::collider_id(collider, self.solver_mut()?.simulation().num_mesh_colliders())?;
            let levels = colliders::levels(levels, "collider levels")?;
            self.solver_mut()?.edit(|sim| sim.set_collider_levels(id, &levels)).map_err(to_py)
        })
    }

    fn set_collider_friction(&mut self, collider: i64, static_friction: f32, kinetic_friction: f32) -> PyResult<()> {
        crate::errors::guard(|| {
            let id = colliders::collider_id(collider, self.solver_mut()?.simulation().num_mesh_colliders())?;
            self.solver_mut()?
                .edit(|sim| sim.set_collider_friction(id, static_friction, kinetic_friction))
                .map_err(to_py)
        })
    }

    /// Attaches `particles` softly (`stiffness` N/m each) to mesh collider `collider`, so they
    /// ride on it: each is bound where it is now to the nearest collider triangle (barycentric
    /// point plus its offset in the triangle's frame) and from then on pulled, every substep,
    /// towards that point as the collider moves and deforms. Attaching an attached particle
    /// rebinds it. The GPU backend runs them too.
    /// Raises InvalidMeshError for an unknown collider or a particle out of range,
    /// InvalidParameterError for a stiffness not positive and finite; nothing changes then.
    fn attach_to_collider(
        slf: &Bound<'_, Self>,
        particles: &Bound<'_, PyAny>,
        collider: i64,
        stiffness: f32,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let (meshes, n) = {
                let me = slf.borrow();
                (me.solver()?.simulation().num_mesh_colliders(), me.solver()?.simulation().num_particles())
            };
            let id = colliders::collider_id(collider, meshes)?;
            let p = indices(particles, "attach_to_collider particles", n)?;
            Self::detached(slf, |inner| inner.edit(|sim| sim.attach_to_collider(&p, id, stiffness)))?.map_err(to_py)
        })
    }

    /// Removes the collider attachments of `particles` (every one with None); particles not
    /// attached are ignored.
    #[pyo3(signature = (particles=None))]
    fn detach_from_collider(&mut self, particles: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        crate::errors::guard(|| {
            let n = self.solver_mut()?.simulation().num_particles();
            let p = particles.map(|p| indices(p, "detach_from_collider particles", n)).transpose()?;
            self.solver_mut()?.edit(|sim| sim.detach_from_collider(p.as_deref())).map_err(to_py)
        })
    }

    /// The particles attached to a mesh collider by `attach_to_collider`, a new uint32 array
    /// (in attachment order; the holds while seams close are `closing_holds`).
    #[getter]
    fn collider_attached<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            Ok({
                let p: Vec<u32> =
                    self.solver()?.simulation().asked_attachments().into_iter().map(|a| a.particle).collect();
                PyArray1::from_vec(py, p).into_any()
            })
        })
    }

    /// The particles the body holds while the seams close (`Settings.ramp_closing_hold`), a
    /// new uint32 array; empty once the ramp has released.
    #[getter]
    fn closing_holds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            Ok(PyArray1::from_vec(py, self.solver()?.simulation().closing_holds().to_vec()).into_any())
        })
    }

    /// The targets of the collider attachments at the last substep run, a new (k, 3) float32
    /// array in the order of `collider_attached`.
    #[getter]
    fn collider_attachment_targets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            let t: Vec<[f32; 3]> =
                self.solver()?.simulation().asked_attachments().into_iter().map(|a| a.target).collect();
            colliders::rows_to_numpy(py, &t)
        })
    }

    /// Collision level per cloth particle: a particle of level a and a primitive of level b
    /// collide unless a != 0, b != 0 and a != b.
    fn set_particle_levels(&mut self, levels: &Bound<'_, PyAny>) -> PyResult<()> {
        crate::errors::guard(|| {
            let levels = colliders::levels(levels, "particle levels")?;
            self.solver_mut()?.edit(|sim| sim.set_particle_levels(&levels)).map_err(to_py)
        })
    }

    #[getter]
    fn particle_levels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| {
            Ok(PyArray1::from_vec(py, self.solver()?.simulation().particle_levels().to_vec()).into_any())
        })
    }

    /// Per-particle static and kinetic friction (overriding the colliders' and the
    /// self-collision defaults); call without arguments to restore the defaults.
    #[pyo3(signature = (static_friction=None, kinetic_friction=None))]
    fn set_particle_friction(
        &mut self,
        static_friction: Option<&Bound<'_, PyAny>>,
        kinetic_friction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        crate::errors::guard(|| match (static_friction, kinetic_friction) {
            (Some(s), Some(k)) => {
                let (s, k) = (floats(s, "static_friction")?, floats(k, "kinetic_friction")?);
                self.solver_mut()?.edit(|sim| sim.set_particle_friction(Some((&s, &k)))).map_err(to_py)
            }
            (None, None) => self.solver_mut()?.edit(|sim| sim.set_particle_friction(None)).map_err(to_py),
            _ => Err(to_py(tailor_core::TailorError::shape(
                "particle friction",
                "give both static and kinetic coefficients, or neither",
            ))),
        })
    }

    /// Self-collision: on/off, the radius (spheres: the sphere radius, None = half the mean
    /// rest edge; triangles: the distance kept from a triangle, None = 4 mm), friction, and
    /// the contact model, "spheres" or "triangles".
    #[pyo3(signature = (enabled=true, radius=None, static_friction=0.3, kinetic_friction=0.2, contacts="spheres"))]
    fn set_self_collision(
        &mut self,
        enabled: bool,
        radius: Option<f32>,
        static_friction: f32,
        kinetic_friction: f32,
        contacts: &str,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let contacts = core::SelfContacts::named(contacts).map_err(to_py)?;
            let s = core::SelfCollisionSettings { enabled, radius, contacts, static_friction, kinetic_friction };
            self.solver_mut()?.edit(|sim| sim.set_self_collision(s)).map_err(to_py)
        })
    }

    /// Self-collision settings in effect (radius resolved).
    #[getter]
    fn self_collision<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            colliders::self_collision_dict(
                py,
                &self.solver()?.simulation().self_collision(),
                self.solver()?.simulation().self_collision_radius(),
            )
        })
    }

    /// Quality of the current state: penetration into mesh collider `collider` (if given),
    /// self-intersections, seam gap, edge strain, kinetic energy.
    #[pyo3(signature = (collider=None))]
    fn metrics<'py>(slf: &Bound<'py, Self>, py: Python<'py>, collider: Option<i64>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let id = Self::collider_of(slf, collider)?;
            let m = Self::detached(slf, |inner| inner.metrics(id))?.map_err(to_py)?;
            colliders::metrics_dict(py, &m)
        })
    }

    /// Per-particle fit maps of the current state (see the stub): `strain` always; with a mesh
    /// collider, `distance` (signed, metres) and `pressure` (pascals).
    #[pyo3(signature = (collider=None))]
    fn fit_maps<'py>(slf: &Bound<'py, Self>, py: Python<'py>, collider: Option<i64>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let id = Self::collider_of(slf, collider)?;
            let m = Self::detached(slf, |inner| inner.fit_maps(id))?.map_err(to_py)?;
            fit_maps_dict(py, m)
        })
    }

    /// `fit_maps` on a native thread, as `step_async`.
    #[pyo3(signature = (collider=None))]
    fn fit_maps_async(slf: &Bound<'_, Self>, collider: Option<i64>) -> PyResult<crate::background::Pending> {
        crate::errors::guard(|| {
            let id = Self::collider_of(slf, collider)?;
            crate::background::start(slf, crate::background::Work::FitMaps(id))
        })
    }

    fn __repr__(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                format!(
                    "Simulation({} particles, {} triangles, backend {})",
                    self.solver()?.simulation().num_particles(),
                    self.solver()?.simulation().model().mesh.num_triangles(),
                    backend_name(self.solver()?.active_backend())
                )
            })
        })
    }
}

impl Simulation {
    fn add_collider(&mut self, shape: Shape, static_friction: f32, kinetic_friction: f32) -> PyResult<()> {
        self.solver_mut()?
            .edit(|sim| sim.add_collider(ImplicitCollider { shape, static_friction, kinetic_friction }))
            .map_err(to_py)
    }
}
