//! The backend facade: one interface over the CPU solver ([`crate::solver`]) and the GPU
//! backend (`crate::gpu`, feature `gpu`). [`Solver`] owns a [`Simulation`] and steps it on the
//! backend [`Backend`] asks for, falling back to the CPU (never failing) when the GPU cannot run
//! the scene, with the reason in [`StepStats::warning`].
//!
//! It sits above both backends, so that neither imports it and the CPU solver never imports
//! the GPU one (`tests/layers.rs`): `engine` → `gpu` → `solver`.

use crate::error::{Result, TailorError};
use crate::quality::QualityMetrics;
use crate::solver::{ActiveBackend, ColliderId, Simulation, StepStats, Vec3Soa};

/// Which backend steps the simulation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Backend {
    /// The GPU where it was measured faster: a discrete adapter and a scene of at least
    /// [`AUTO_GPU_MIN_PARTICLES`]; else the CPU (see [`auto_uses_gpu`]).
    #[default]
    Auto,
    Cpu,
    /// The GPU when there is one and it supports the scene; otherwise the CPU, with a warning.
    Gpu,
}

/// Below this many particles `Auto` stays on the CPU: the smallest size measured on a real GPU
/// (docs/gpu.md: an NVIDIA H100 against the 16 cores of its host, a cloth with body and self
/// collision, 10,000 particles: 39 ms a frame against 214 ms). Smaller scenes were not
/// measured there, and a frame's fixed cost on the GPU (its 1,600-1,900 dispatches: 6-9 ms on
/// the H100) is what a small cloth costs the CPU in all.
pub const AUTO_GPU_MIN_PARTICLES: usize = 10_000;

/// `Auto`'s rule, from what was measured: the GPU on a discrete adapter from
/// [`AUTO_GPU_MIN_PARTICLES`] up. Integrated, virtual and software adapters stay on the CPU:
/// on lavapipe (software Vulkan) the GPU path was 3-12 times slower at every size, and no
/// integrated GPU has been measured.
pub fn auto_uses_gpu(discrete: bool, particles: usize) -> bool {
    discrete && particles >= AUTO_GPU_MIN_PARTICLES
}

/// How a [`Solver`] is built.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolverOptions {
    pub backend: Backend,
    /// Behave as if no GPU adapter existed (tests of the fallback; the environment variable
    /// `TAILOR_GPU_FORCE_NO_ADAPTER=1` does the same).
    pub force_no_adapter: bool,
}

/// A simulation and the backend that steps it.
pub struct Solver {
    sim: Simulation,
    #[cfg(feature = "gpu")]
    gpu: Option<crate::gpu::GpuSolver>,
    warning: Option<String>,
    /// A thread pool of its own for the CPU's work (`set_threads`); `None`: rayon's global pool
    /// (a thread per core, or `RAYON_NUM_THREADS`), shared with every other solver.
    pool: Option<(usize, std::sync::Arc<rayon::ThreadPool>)>,
}

impl Solver {
    pub fn new(sim: Simulation, backend: Backend) -> Self {
        Self::with_options(sim, SolverOptions { backend, ..Default::default() })
    }

    pub fn with_options(sim: Simulation, options: SolverOptions) -> Self {
        let mut s = Self {
            sim,
            #[cfg(feature = "gpu")]
            gpu: None,
            warning: None,
            pool: None,
        };
        s.choose(options);
        s
    }

    /// Runs this solver's CPU work on `threads` threads of its own (`None`: the process's
    /// global pool). A batch of simulations side by side gives each a share of the machine
    /// this way, where the global pool is sized once per process; results do not depend on
    /// the thread count (the solver's parallel loops split work in fixed chunks).
    pub fn set_threads(&mut self, threads: Option<usize>) -> Result<()> {
        self.pool = match threads {
            None => None,
            Some(0) => {
                return Err(TailorError::setting("threads", 0, "must be at least 1 (None: one per core)"));
            }
            Some(n) => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .thread_name(|i| format!("tailor-{i}"))
                    .build()
                    .map_err(|e| TailorError::setting("threads", n, format!("could not start the threads: {e}")))?;
                Some((n, std::sync::Arc::new(pool)))
            }
        };
        Ok(())
    }

    /// The threads the CPU's work runs on.
    pub fn threads(&self) -> usize {
        match &self.pool {
            Some((n, _)) => *n,
            None => rayon::current_num_threads(),
        }
    }

    /// `f` on this solver's threads: inside its pool, or inside the global pool (`scope` runs
    /// `f` on one of its workers). Called from a thread outside the pool, every parallel loop of
    /// a step would otherwise be sent to the pool and waited for, the caller asleep meanwhile:
    /// the T-shirt sample's walking frame took 57 ms that way and 42 ms on a worker (2 cores).
    fn on_threads<R: Send>(&mut self, f: impl FnOnce(&mut Self) -> R + Send) -> R {
        match self.pool.as_ref().map(|(_, p)| p.clone()) {
            Some(pool) => pool.install(|| f(self)),
            None => rayon::scope(|_| f(self)),
        }
    }

    #[cfg(not(feature = "gpu"))]
    fn choose(&mut self, options: SolverOptions) {
        if options.backend == Backend::Gpu {
            self.warning = Some("GPU requested, but Tailor was built without the `gpu` feature; using the CPU".into());
        }
    }

    #[cfg(feature = "gpu")]
    fn choose(&mut self, options: SolverOptions) {
        use crate::gpu::{GpuOptions, GpuSolver};
        if options.backend == Backend::Cpu {
            return;
        }
        // Not even a discrete adapter would be used: no adapter is asked for.
        if options.backend == Backend::Auto && !auto_uses_gpu(true, self.sim.num_particles()) {
            return;
        }
        match GpuSolver::new(GpuOptions { force_no_adapter: options.force_no_adapter }) {
            Ok(g) if options.backend == Backend::Auto && !auto_uses_gpu(g.is_discrete(), self.sim.num_particles()) => {}
            Ok(g) => self.gpu = Some(g),
            Err(why) if options.backend == Backend::Gpu => self.warning = Some(format!("{why}; using the CPU")),
            Err(_) => {}
        }
    }

    /// Chooses the backend again (the simulation's state is kept: GPU velocities are brought
    /// back first). A previous warning is dropped; a new one says why the GPU is not used.
    pub fn set_backend(&mut self, options: SolverOptions) {
        self.sync_from_gpu();
        #[cfg(feature = "gpu")]
        {
            self.gpu = None;
        }
        self.warning = None;
        self.choose(options);
    }

    /// Quality metrics of the current state (see [`Simulation::metrics`]), with the
    /// velocities brought back from the GPU first.
    pub fn metrics(&mut self, collider: Option<ColliderId>) -> Result<QualityMetrics> {
        self.sync_from_gpu();
        self.on_threads(|s| s.sim.metrics(collider))
    }

    /// The fit maps of the current state ([`crate::quality::fit_maps`]).
    pub fn fit_maps(&mut self, collider: Option<ColliderId>) -> Result<crate::quality::fit_maps::FitMaps> {
        self.sync_from_gpu();
        self.on_threads(|s| s.sim.fit_maps(collider))
    }

    /// The backend the next step will use.
    pub fn active_backend(&self) -> ActiveBackend {
        #[cfg(feature = "gpu")]
        if self.gpu.is_some() {
            return ActiveBackend::Gpu;
        }
        ActiveBackend::Cpu
    }

    /// How the GPU backend's creation went (whether it made the process's shared GPU context,
    /// and the seconds it took), when the GPU is in use.
    pub fn gpu_setup(&self) -> Option<(bool, f64)> {
        #[cfg(feature = "gpu")]
        if let Some(g) = &self.gpu {
            let s = g.setup();
            return Some((s.context_made, s.seconds));
        }
        None
    }

    /// Why the GPU is not in use although it was asked for, if so.
    pub fn warning(&self) -> Option<&str> {
        self.warning.as_deref()
    }

    /// Description of the GPU adapter in use, if any.
    pub fn adapter(&self) -> Option<String> {
        #[cfg(feature = "gpu")]
        if let Some(g) = &self.gpu {
            let i = g.adapter_info();
            return Some(format!(
                "{} ({:?}, {:?}, driver {} {})",
                i.name, i.backend, i.device_type, i.driver, i.driver_info
            ));
        }
        None
    }

    /// Advances by `dt` seconds on the active backend (the CPU's work on this solver's
    /// threads, `set_threads`).
    pub fn step(&mut self, dt: f32) -> Result<StepStats> {
        self.on_threads(|s| {
            let mut st = s.step_here(dt)?;
            st.threads = rayon::current_num_threads();
            Ok(st)
        })
    }

    fn step_here(&mut self, dt: f32) -> Result<StepStats> {
        #[cfg(feature = "gpu")]
        if self.gpu.is_some() && self.sim.backend_asleep() {
            // Asleep (`sleep.rs`, tested on the GPU's speeds as on the CPU's): nothing to solve,
            // the CPU step only advances the clock; the GPU takes the next frame that wakes it.
            // A collider that starts moving wakes it within this CPU step (the motion is known
            // once the frame begins), which then solves the frame; the GPU, marked stale when
            // the cloth fell asleep, restarts from that state.
            let mut st = self.sim.step(dt)?;
            st.warning = self.warning.clone();
            return Ok(st);
        }
        #[cfg(feature = "gpu")]
        if let Some(g) = &mut self.gpu {
            use crate::gpu::GpuFailure;
            match g.step(&mut self.sim, dt) {
                Ok(mut st) => {
                    st.warning = self.warning.clone();
                    return Ok(st);
                }
                Err(GpuFailure::Step(e)) => return Err(e),
                Err(GpuFailure::Unsupported(why)) => {
                    // This frame only: the scene holds something the GPU does not run (the
                    // Jacobi method, more mesh colliders than it binds). The CPU's state is current
                    // (the GPU refuses before the frame's work, or hands the begun frame over),
                    // and the GPU, marked stale, tries again next frame from it.
                    let mut st = self.sim.step(dt)?;
                    st.warning = Some(self.frame_on_cpu(&format!("not supported on the GPU yet: {why}")));
                    return Ok(st);
                }
                Err(other) => {
                    // Keep the velocities if the device still answers; positions are current.
                    let kept = g.sync_velocities(&mut self.sim).is_ok();
                    let lost = if kept { "" } else { " (velocities of the last GPU frame were lost)" };
                    self.warning = Some(format!("{other}; using the CPU{lost}"));
                    self.gpu = None;
                }
            }
        }
        let mut st = self.sim.step(dt)?;
        st.warning = self.warning.clone();
        Ok(st)
    }

    /// The warning of a frame the CPU ran although the GPU is in use, and why.
    #[cfg(feature = "gpu")]
    fn frame_on_cpu(&self, why: &str) -> String {
        let before = self.warning.as_deref().map(|w| format!("{w}; ")).unwrap_or_default();
        format!("{before}this frame ran on the CPU: {why}")
    }

    /// The simulation, read-only. Positions are always current; velocities are current on the
    /// CPU backend (use [`Solver::velocities`] otherwise).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    pub fn positions(&self) -> &Vec3Soa {
        self.sim.positions()
    }

    /// Current velocities (downloaded from the GPU when it runs the simulation).
    pub fn velocities(&mut self) -> &Vec3Soa {
        self.sync_from_gpu();
        self.sim.velocities()
    }

    /// Edits the simulation (pins, seams, settings, positions…); the GPU re-uploads afterwards.
    pub fn edit<R>(&mut self, f: impl FnOnce(&mut Simulation) -> R) -> R {
        self.sync_from_gpu();
        let r = f(&mut self.sim);
        #[cfg(feature = "gpu")]
        if let Some(g) = &mut self.gpu {
            g.mark_dirty();
        }
        r
    }

    /// The positions of a mesh collider at the end of the next step (the per-frame input of
    /// an animated character): on the GPU only these go up, once per frame, with no
    /// re-upload of the model (unlike [`Solver::edit`]).
    pub fn set_collider_positions(&mut self, id: ColliderId, positions: &[[f32; 3]]) -> Result<()> {
        self.sim.set_collider_positions(id, positions)
    }

    /// Gives the simulation back (with current velocities).
    pub fn into_simulation(mut self) -> Simulation {
        self.sync_from_gpu();
        self.sim
    }

    fn sync_from_gpu(&mut self) {
        #[cfg(feature = "gpu")]
        if let Some(g) = &mut self.gpu {
            if let Err(e) = g.sync_velocities(&mut self.sim) {
                self.warning = Some(format!("{e}; using the CPU"));
                self.gpu = None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_picks_the_gpu_only_where_it_was_measured_faster() {
        assert!(auto_uses_gpu(true, AUTO_GPU_MIN_PARTICLES));
        assert!(auto_uses_gpu(true, 1_000_000));
        assert!(!auto_uses_gpu(true, AUTO_GPU_MIN_PARTICLES - 1));
        // Integrated, virtual and software adapters: never (not measured, or slower).
        assert!(!auto_uses_gpu(false, 1_000_000));
    }
}
