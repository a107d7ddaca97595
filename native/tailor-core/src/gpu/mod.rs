//! The per-frame solve on the GPU (feature `gpu`): wgpu compute shaders in WGSL running the
//! same substeps as [`Simulation::step`](crate::solver::Simulation::step).
//!
//! Each stage is one WGSL file with its host side beside it (`close_seams`, `predict`, `mesh_hash`, `hash`,
//! `contacts`, `project_triangles`, `project_stencils`, `gauss_seidel`, `chebyshev`,
//! `self_collide`, `resolve_mesh`, `finish`, `ramp`; `common` and `collide_common` hold the
//! shared structs, `mesh_query` the mesh-collider query). Every WGSL
//! struct has a `#[repr(C)]` [`bytemuck::Pod`] mirror whose size is checked against naga's
//! layout in the unit tests, which validate every shader without a GPU.
//!
//! **What lives where.** The model (matrix, colouring, slot layout, triangles, seam pairs) and
//! the whole moving state (positions, velocities, prediction, right-hand side, slots,
//! Chebyshev history, the iteration state and the seam-closing ramp) stay on the GPU across
//! substeps and frames. The CPU prepares derived data exactly as the CPU step would
//! ([`Simulation::gpu_view`](crate::solver::Simulation::gpu_view): colouring, diagonal, the
//! measured Chebyshev ρ), uploads it once (again only after an edit, reusing the buffers when
//! they are large enough), then each frame records every substep's dispatches into one
//! command buffer, submits it, and reads back positions plus a 104-byte state (residual, seam
//! gap, ramp phase) once, with the seam pairs' closing schedule while it runs. Velocities are
//! read back only on request.
//!
//! **Same physics.** Prediction with pins; stretch and shear projections (ported line for line
//! from `constraints/triangle.rs`) and curved (creased-rest) bending and seam-hinge stencils;
//! contacts with analytic colliders (plane, sphere, capsule) and mesh colliders (detection
//! every iteration, the penalty term in the row solve, penetration resolution and Coulomb
//! friction after the iterations); Gauss-Seidel one dispatch per colour (a colour's rows are
//! independent, so the order inside a dispatch does not matter and the only differences from
//! the CPU are f32 rounding, e.g. fused multiply-adds); Chebyshev with the CPU's measured ρ and
//! its growth restart, driven by an on-GPU reduction of the update norm; self-collision after
//! each iteration; velocities and air damping with the seam-closing ramp advanced on the GPU
//! from an on-GPU seam-gap reduction. Seams close there too: the closing schedule shrinks each
//! pair's rest length every substep (`close_seams`), gravity is held while the ramp closes,
//! and the body's holds of the closing phase are placed and released by the host around the
//! frame in which they come or go, as the CPU step does at its start and end.
//!
//! **Collisions** (`collide_common`, `mesh_hash`, `hash`, `mesh_query`, `contacts`,
//! `resolve_mesh`, `self_collide`). The spatial hash of Eq. 1-3 is built on the GPU by a
//! counting sort (count per bucket with atomics, one-workgroup prefix sum, scatter at atomic
//! cursors, per-bucket sort by (cell, primitive) so the table does not depend on the
//! schedule): for the mesh colliders every substep while one moves (their positions go up
//! once per frame and are interpolated per substep on the GPU, as on the CPU) and once after
//! an upload otherwise; for the cloth particles after every iteration with self-collision on.
//! Buckets use the CPU's Eq. 1 bit for bit (`collide_common::gpu_bucket_of`, tested); entries
//! carry the whole cell, so cells sharing a bucket are never confused. Collision levels filter
//! both, per-collider and per-particle Coulomb friction apply as on the CPU. Self-collision is
//! a per-particle gather (each particle sums its own share of its pairs' corrections), so it is
//! deterministic; it differs from the CPU's scatter only in the order of that sum.
//! The collision stages compose their source as `common.wgsl + collide_common.wgsl (+
//! mesh_query.wgsl) + stage.wgsl`; the unit tests validate exactly those composed sources.
//!
//! Attachments to a mesh collider (`Simulation::attach_to_collider`, painted pins riding on
//! the character) move their targets with the collider every substep (`attach.wgsl`).
//!
//! **Not yet on the GPU** (a [`Solver`](crate::engine::Solver) asked for the GPU runs such a
//! frame on the CPU, that frame only, with the reason in its stats): the Jacobi method and more
//! than [`collide_common::MAX_MESHES`] mesh colliders. The
//! early stop on `tolerance` runs on the GPU: `reduce_omega` sets a flag that every iteration
//! stage, self-collision's passes included, reads first (no readback).
//! Flat bending and seams are linear, so they are fully in the matrix and need no GPU kernel.

pub mod attach;
mod buffers;
pub mod chebyshev;
pub mod close_seams;
pub mod coarse;
pub mod collide_common;
pub mod common;
pub mod contacts;
mod context;
pub mod finish;
mod frame;
pub mod gauss_seidel;
pub mod hash;
pub mod mesh_hash;
pub mod mesh_query;
mod pipelines;
mod plan;
pub mod predict;
pub mod project_stencils;
pub mod project_triangles;
pub mod ramp;
pub mod resolve_mesh;
pub mod row;
pub mod self_collide;
mod timing;
mod upload;
pub use timing::STAGE_TIMES_ENV;

use std::sync::Arc;
use std::time::Instant;

use crate::error::TailorError;
use crate::solver::model::settings::Method;
use crate::solver::stages::damping::RampPhase;
use crate::solver::Simulation;
use collide_common::Meshes;
use common::{PHASE_CLOSING, PHASE_DONE, PHASE_RELEASING};
use gauss_seidel::ColourRange;
use predict::Particle;

pub use buffers::Buffers;
use buffers::VEC4;
use context::GpuContext;
use pipelines::{BindGroups, Pipelines};

/// Set to `1` to make adapter discovery fail (tests of the CPU fallback).
pub const FORCE_NO_ADAPTER_ENV: &str = "TAILOR_GPU_FORCE_NO_ADAPTER";

/// How the GPU solver is created.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GpuOptions {
    /// Behave as if no adapter existed (also enabled by [`FORCE_NO_ADAPTER_ENV`]).
    pub force_no_adapter: bool,
}

/// Why a GPU step did not happen.
#[derive(Debug, Clone, PartialEq)]
pub enum GpuFailure {
    /// The step itself failed as it would on the CPU (it diverged); the state was rolled back.
    Step(TailorError),
    /// The scene uses something the GPU path does not implement yet.
    Unsupported(String),
    /// No adapter, a device error or a lost device.
    Device(String),
}

impl std::fmt::Display for GpuFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GpuFailure::Step(e) => write!(f, "{e}"),
            GpuFailure::Unsupported(s) => write!(f, "not supported on the GPU yet: {s}"),
            GpuFailure::Device(s) => write!(f, "GPU device: {s}"),
        }
    }
}

/// What the current upload was made for.
struct Uploaded {
    n: usize,
    n_tris: usize,
    n_curved: usize,
    n_colliders: usize,
    n_meshes: usize,
    n_mesh_verts: usize,
    n_mesh_tris: usize,
    mesh_buckets: usize,
    /// Per mesh collider: first vertex in the `mverts` sections.
    mesh_vert_off: Vec<u32>,
    /// The per-frame uniform as uploaded (moving flags and 1/dt are rewritten per frame).
    meshes: Meshes,
    self_enabled: bool,
    self_buckets: usize,
    n_attach: usize,
    /// The early stop is on (`tolerance` > 0): each iteration starts with `gate`.
    early_stop: bool,
    /// Seam pairs were on their closing schedule at upload: each substep starts with
    /// `close_seams`, and each frame reads their state back.
    closing_scheduled: bool,
    n_seam_pairs: usize,
    colours: Vec<ColourRange>,
    h: f32,
    rho: f32,
    method: Method,
    /// Aggregates of the two-level step's coarse grid (0: the step is one-level).
    n_coarse: usize,
}

/// The GPU backend of one simulation: the shared context (device and compiled stages), and
/// this simulation's buffers, bind groups and uploaded model and state.
pub struct GpuSolver {
    ctx: Arc<GpuContext>,
    setup: GpuSetup,
    buffers: Option<Buffers>,
    binds: Option<BindGroups>,
    uploaded: Option<Uploaded>,
    dirty: bool,
    /// The collider hash on the GPU is built for the current collider positions.
    mesh_hash_valid: bool,
    /// Per-stage timestamps are written (`set_stage_timing`), and their query set once made.
    stage_timing: bool,
    /// A timestamp after every dispatch instead (`set_kernel_timing`: a profile).
    kernel_timing: bool,
    /// The last timed frame's seconds per kernel, in the order each first ran.
    kernel_times: Vec<(&'static str, f64)>,
    timing: Option<timing::Timing>,
}

/// How a [`GpuSolver`]'s creation went.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpuSetup {
    /// It made the process's shared context (the first GPU simulation, or the first after a
    /// lost device); otherwise it reused it.
    pub context_made: bool,
    /// Seconds its creation took (the context's creation included when it made it).
    pub seconds: f64,
}

fn groups(count: usize, size: u32) -> u32 {
    (count as u32).div_ceil(size).max(1)
}

fn phase_to_gpu(p: RampPhase) -> (u32, f32) {
    match p {
        RampPhase::Closing => (PHASE_CLOSING, 0.0),
        RampPhase::Releasing { elapsed } => (PHASE_RELEASING, elapsed),
        RampPhase::Done => (PHASE_DONE, 0.0),
    }
}

fn phase_from_gpu(phase: u32, elapsed: f32) -> RampPhase {
    match phase {
        PHASE_CLOSING => RampPhase::Closing,
        PHASE_RELEASING => RampPhase::Releasing { elapsed },
        _ => RampPhase::Done,
    }
}

impl GpuSolver {
    /// The backend on the process's shared GPU context (made on first use: adapter, device,
    /// shaders compiled). `Err` names why there is none (no adapter, device refused).
    pub fn new(options: GpuOptions) -> Result<Self, String> {
        let forced = options.force_no_adapter || std::env::var(FORCE_NO_ADAPTER_ENV).is_ok_and(|v| v == "1");
        if forced {
            return Err("no GPU adapter (forced off)".into());
        }
        let t0 = Instant::now();
        let (ctx, made) = GpuContext::shared()?;
        Ok(Self {
            ctx,
            setup: GpuSetup { context_made: made, seconds: t0.elapsed().as_secs_f64() },
            buffers: None,
            binds: None,
            uploaded: None,
            dirty: true,
            mesh_hash_valid: false,
            stage_timing: std::env::var(timing::STAGE_TIMES_ENV).is_ok_and(|v| v == "1"),
            kernel_timing: false,
            kernel_times: Vec::new(),
            timing: None,
        })
    }

    /// Whether frames report per-stage GPU times: stage (or kernel) timing is on and the
    /// device writes timestamps inside passes.
    pub fn timestamps(&self) -> bool {
        (self.stage_timing || self.kernel_timing) && self.ctx.timestamps
    }

    /// Turns per-stage GPU times on or off (off by default, or on with
    /// `TAILOR_GPU_STAGE_TIMES=1`): a timestamp after each run of one stage's dispatches costs
    /// the frame 5-9 % on lavapipe (docs/gpu.md). Returns whether frames will report them
    /// (false where the device has no timestamps inside passes).
    pub fn set_stage_timing(&mut self, on: bool) -> bool {
        self.stage_timing = on;
        self.timestamps()
    }

    /// Turns a profile on or off: a timestamp after every dispatch, so that each frame (while
    /// its dispatches fit one query set) records the time of each kernel, read with
    /// `kernel_times`; the per-stage times come from the same timestamps. The barriers the
    /// timestamps add make a profiled frame slower than a plain one: read the shares, and time
    /// frames with it off. Returns whether frames will be profiled.
    pub fn set_kernel_timing(&mut self, on: bool) -> bool {
        self.kernel_timing = on;
        self.kernel_times.clear();
        on && self.ctx.timestamps
    }

    /// The last profiled frame's seconds per kernel (`set_kernel_timing`), each kernel's
    /// dispatches summed, in the order each first ran; empty before one.
    pub fn kernel_times(&self) -> &[(&'static str, f64)] {
        &self.kernel_times
    }

    /// How this backend's creation went: whether it made the shared context, and in how long.
    pub fn setup(&self) -> GpuSetup {
        self.setup
    }

    /// The adapter in use (name, backend, device type, driver).
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.ctx.info
    }

    /// Whether the adapter is a discrete GPU (the only kind `Auto` picks, `engine::auto_uses_gpu`).
    pub fn is_discrete(&self) -> bool {
        self.ctx.info.device_type == wgpu::DeviceType::DiscreteGpu
    }

    /// The simulation was edited on the CPU: upload everything again before the next step.
    pub fn mark_dirty(&mut self) {
        self.dirty = true;
    }

    fn take_error(&self) -> Option<String> {
        self.ctx.take_error()
    }

    fn wait(&self) -> Result<(), GpuFailure> {
        self.ctx.device.poll(wgpu::PollType::Wait).map_err(|e| GpuFailure::Device(e.to_string()))?;
        match self.take_error() {
            Some(e) => Err(GpuFailure::Device(e)),
            None => Ok(()),
        }
    }

    /// Maps the first `len` bytes of the readback buffer (after the submitted copies).
    fn read(&self, len: u64) -> Result<Vec<u8>, GpuFailure> {
        let b = self.buffers.as_ref().ok_or_else(|| GpuFailure::Device("buffers missing".into()))?;
        let out = map_read(&self.ctx.device, &b.readback, len)?;
        match self.take_error() {
            Some(e) => Err(GpuFailure::Device(e)),
            None => Ok(out),
        }
    }

    /// Downloads the velocities into `sim` (they are not read back every frame).
    pub fn sync_velocities(&mut self, sim: &mut Simulation) -> Result<(), GpuFailure> {
        let (Some(b), Some(u)) = (&self.buffers, &self.uploaded) else {
            return Ok(());
        };
        if self.dirty || u.n != sim.num_particles() {
            // The CPU copy is the newer one (an edit since the last upload).
            return Ok(());
        }
        let bytes = u.n as u64 * VEC4;
        let mut enc =
            self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("velocities") });
        enc.copy_buffer_to_buffer(&b.v, 0, &b.readback, 0, bytes);
        self.ctx.queue.submit([enc.finish()]);
        let data = self.read(bytes)?;
        sim.accept_backend_velocities(bytemuck::cast_slice(&data));
        Ok(())
    }

    /// Dispatches one frame of `substeps` × `iterations` records for the uploaded scene (the
    /// collider hash counted as built every substep, i.e. a moving collider).
    pub fn dispatches_per_frame(&self, substeps: u32, iterations: u32) -> usize {
        let (Some(u), Some(g)) = (&self.uploaded, &self.binds) else { return 0 };
        // A moving collider's hash is rebuilt every substep (the benchmarks' case).
        plan::frame(&self.ctx.pipelines, g, u, substeps, iterations, u.n_meshes > 0, false).len()
    }

    /// Runs one frame's worth of dispatches ([`GpuSolver::dispatches_per_frame`]) of one
    /// workgroup each and returns its wall time: the fixed cost of a frame, for benchmarks.
    /// It scribbles on the GPU state, so the next step uploads again from the simulation
    /// (call [`GpuSolver::sync_velocities`] first to keep the velocities).
    pub fn dispatch_overhead(&mut self, substeps: u32, iterations: u32) -> Result<f64, GpuFailure> {
        let count = self.dispatches_per_frame(substeps, iterations);
        let (Some(_), Some(g)) = (&self.buffers, &self.binds) else {
            return Err(GpuFailure::Device("nothing uploaded".into()));
        };
        let pl = &self.ctx.pipelines;
        let t0 = Instant::now();
        let mut enc = self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("empty") });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
            // The extrapolation kernel returns at once for indices past n: with n read from the
            // uniform, a single workgroup per dispatch measures launch cost only.
            pass.set_pipeline(&pl.extrapolate);
            pass.set_bind_group(0, &g.extrapolate, &[]);
            for _ in 0..count {
                pass.dispatch_workgroups(1, 1, 1);
            }
        }
        self.ctx.queue.submit([enc.finish()]);
        self.dirty = true;
        self.wait()?;
        Ok(t0.elapsed().as_secs_f64())
    }
}

/// The first `len` bytes of a `MAP_READ` buffer whose copies were submitted and waited for.
fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer, len: u64) -> Result<Vec<u8>, GpuFailure> {
    let slice = buffer.slice(..len);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::Wait).map_err(|e| GpuFailure::Device(e.to_string()))?;
    match rx.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(GpuFailure::Device(format!("readback failed: {e}"))),
        Err(_) => return Err(GpuFailure::Device("readback never completed".into())),
    }
    let out = slice.get_mapped_range().to_vec();
    buffer.unmap();
    Ok(out)
}
