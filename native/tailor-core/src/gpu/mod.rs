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
//! command buffer, submits it, and reads back positions plus a 96-byte state (residual, seam
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
pub mod collide_common;
pub mod common;
pub mod contacts;
mod context;
pub mod finish;
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
pub mod self_collide;
mod timing;
pub use timing::STAGE_TIMES_ENV;

use std::sync::Arc;
use std::time::Instant;

use bytemuck::Zeroable;

use crate::error::TailorError;
use crate::solver::model::settings::Method;
use crate::solver::model::SEAM_PAIRS_SET;
use crate::solver::simulation::view::{BackendState, SeamClosing};
use crate::solver::stages::damping::{Ramp, RampPhase};
use crate::solver::{ActiveBackend, Simulation, SolverView, StepStats};

use crate::collision::InsertionRule;
use crate::solver::collide::mesh_collider::{MeshCollider, PAD};
use crate::solver::CollisionStats;
use collide_common::{buckets_for, MeshInfo, Meshes, TableInfo, MAX_MESHES};
use common::{
    Collider, Contact, Params, StepState, KIND_CAPSULE, KIND_PLANE, KIND_SPHERE, PARTICLE_PINNED, PARTICLE_SEWN,
    PHASE_CLOSING, PHASE_DONE, PHASE_RELEASING,
};
use gauss_seidel::ColourRange;
use predict::Particle;

pub use buffers::Buffers;
use buffers::{Capacities, STATE_BYTES, VEC4};
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
            timing: None,
        })
    }

    /// Whether frames report per-stage GPU times: stage timing is on and the device writes
    /// timestamps inside passes.
    pub fn timestamps(&self) -> bool {
        self.stage_timing && self.ctx.timestamps
    }

    /// Turns per-stage GPU times on or off (off by default, or on with
    /// `TAILOR_GPU_STAGE_TIMES=1`): a timestamp after each run of one stage's dispatches costs
    /// the frame 5-9 % on lavapipe (docs/gpu.md). Returns whether frames will report them
    /// (false where the device has no timestamps inside passes).
    pub fn set_stage_timing(&mut self, on: bool) -> bool {
        self.stage_timing = on;
        self.timestamps()
    }

    /// How this backend's creation went: whether it made the shared context, and in how long.
    pub fn setup(&self) -> GpuSetup {
        self.setup
    }

    /// The adapter in use (name, backend, device type, driver).
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.ctx.info
    }

    /// Whether the adapter is a software rasteriser (lavapipe, SwiftShader, WARP).
    pub fn is_software(&self) -> bool {
        self.ctx.info.device_type == wgpu::DeviceType::Cpu
    }

    /// The simulation was edited on the CPU: upload everything again before the next step.
    pub fn mark_dirty(&mut self) {
        self.dirty = true;
    }

    fn take_error(&self) -> Option<String> {
        self.ctx.take_error()
    }

    /// Why `sim` cannot run on the GPU yet, if it cannot (call after `gpu_view`).
    fn unsupported(view: &SolverView<'_>) -> Option<String> {
        if view.settings.method == Method::Jacobi {
            return Some("the Jacobi method".into());
        }
        // One dimension of dispatches covers 65535 workgroups of 64.
        let m = view.model;
        const DISPATCH: usize = 65_535 * 64;
        if view.x.len() > DISPATCH || m.triangles.len() > DISPATCH || m.slots.curved.len() > DISPATCH {
            return Some(format!("more than {DISPATCH} particles or triangles"));
        }
        let meshes = &view.collide.meshes;
        if meshes.len() > MAX_MESHES {
            return Some(format!("more than {MAX_MESHES} mesh colliders ({})", meshes.len()));
        }
        let tris: usize = meshes.iter().map(|m| m.tris.len()).sum();
        let verts: usize = meshes.iter().map(|m| m.next.len()).sum();
        let buckets: usize = meshes.iter().map(|m| buckets_for(m.tris.len())).sum();
        if tris > DISPATCH || verts > DISPATCH || buckets > DISPATCH || buckets_for(view.x.len()) > DISPATCH {
            return Some(format!("more than {DISPATCH} collider vertices, triangles or hash buckets"));
        }
        None
    }

    /// Upper bound on the insertions of the colliders' hash at any substep of the coming
    /// frame: per triangle, the cells of its padded AABB, whose extent along each axis is at
    /// most the larger of its extents at the frame's two ends (linear interpolation).
    fn mesh_entry_bound(meshes: &[MeshCollider]) -> usize {
        let mut total = 0usize;
        for m in meshes {
            let l = m.cell;
            for t in &m.tris {
                let mut cells = 1usize;
                for k in 0..3 {
                    let mut e = 0.0f32;
                    for p in [&m.prev, &m.next, &m.cur] {
                        let v = t.map(|i| p[i as usize][k]);
                        e = e.max(v[0].max(v[1]).max(v[2]) - v[0].min(v[1]).min(v[2]));
                    }
                    // An interval of length e covers at most floor(e/l) + 2 cells; the margin
                    // covers rounding of the padded bounds.
                    cells *= ((e + 2.0 * PAD * l) / l * (1.0 + 1e-4)) as usize + 2;
                }
                total += cells;
            }
        }
        total
    }

    /// Uploads the model and state (reusing buffers that are large enough).
    fn upload(&mut self, view: &SolverView<'_>) -> Result<(), GpuFailure> {
        if let Some(why) = Self::unsupported(view) {
            return Err(GpuFailure::Unsupported(why));
        }
        let m = view.model;
        let n = m.n();
        let nt = m.triangles.len();
        let sp = &m.seam_pairs;
        let mat = &m.matrix32;
        let lay = &m.slots;

        // Packed index data, sections in the order of `Params`.
        let mut idx: Vec<u32> = Vec::new();
        let base = |idx: &mut Vec<u32>, data: &[u32]| {
            let b = idx.len() as u32;
            idx.extend_from_slice(data);
            b
        };
        let mut p = Params::zeroed();
        p.mat_off = base(&mut idx, &mat.offsets);
        p.mat_cols = base(&mut idx, &mat.cols);
        p.slot_off = base(&mut idx, &lay.particle_offsets);
        p.slot_idx = base(&mut idx, &lay.particle_slots);
        let tv: Vec<u32> = m.triangles.verts.iter().flatten().copied().collect();
        p.tri_verts = base(&mut idx, &tv);
        p.seam_off = base(&mut idx, &sp.offsets);
        p.seam_verts = base(&mut idx, &sp.verts);
        let mut colours = Vec::with_capacity(m.colouring.groups.len());
        let order: Vec<u32> = m.colouring.groups.iter().flatten().copied().collect();
        let mut start = 0u32;
        for g in &m.colouring.groups {
            colours.push(ColourRange { start, count: g.len() as u32, _pad0: 0, _pad1: 0 });
            start += g.len() as u32;
        }
        p.order = base(&mut idx, &order);
        // Curved stencils as one compressed-row set, in slot order.
        let (mut c_off, mut c_verts, mut c_coefs, mut c_wr) = (vec![0u32], Vec::new(), Vec::new(), Vec::new());
        for &(set_id, st) in &lay.curved {
            let set = m.stencil_set(set_id);
            let st = st as usize;
            for t in set.range(st) {
                c_verts.push(set.verts[t]);
                c_coefs.push(set.coefs[t]);
            }
            c_off.push(c_verts.len() as u32);
            c_wr.extend_from_slice(&[set.weights[st], set.rest[st]]);
        }
        // Each seam pair's closing state; its rest length lives in its curved stencil, if any.
        let mut pair_state: Vec<close_seams::PairState> = (0..sp.len())
            .map(|s| {
                let left = view.closing_left.get(s).copied().unwrap_or(0.0);
                let gap0 = view.closing_gap0.get(s).copied().unwrap_or(0.0);
                [gap0, left, f32::from_bits(close_seams::NOT_CURVED), sp.rest[s]]
            })
            .collect();
        for (c, &(set_id, st)) in lay.curved.iter().enumerate() {
            if set_id == SEAM_PAIRS_SET {
                pair_state[st as usize][2] = f32::from_bits(c as u32);
            }
        }
        p.curved_off = base(&mut idx, &c_off);
        p.curved_verts = base(&mut idx, &c_verts);

        // Mesh colliders: global triangle vertices and levels, per-collider layout.
        let col = view.collide;
        let mut meshes = Meshes::zeroed();
        let (mut tri_idx, mut tri_levels, mut mesh_vert_off) = (Vec::new(), Vec::new(), Vec::new());
        let (mut voff, mut toff, mut boff) = (0u32, 0u32, 0u32);
        for (c, mc) in col.meshes.iter().enumerate() {
            let nb = buckets_for(mc.tris.len()) as u32;
            meshes.m[c] = MeshInfo {
                cell: mc.cell,
                vert_off: voff,
                n_verts: mc.next.len() as u32,
                tri_off: toff,
                n_tris: mc.tris.len() as u32,
                bucket_off: boff,
                mask: nb - 1,
                rule: match mc.opts.rule {
                    InsertionRule::Paper => collide_common::RULE_PAPER,
                    InsertionRule::PaperOrPlane => collide_common::RULE_PAPER_OR_PLANE,
                    InsertionRule::Aabb => collide_common::RULE_AABB,
                },
                moving: mc.moving as u32,
                static_friction: mc.opts.static_friction,
                kinetic_friction: mc.opts.kinetic_friction,
                _pad0: 0,
            };
            mesh_vert_off.push(voff);
            tri_idx.extend(mc.tris.iter().flat_map(|t| t.map(|v| v + voff)));
            tri_levels.extend(mc.tri_level.iter().map(|&l| l as u32));
            voff += mc.next.len() as u32;
            toff += mc.tris.len() as u32;
            boff += nb;
        }
        let (n_mesh_verts, n_mesh_tris, mesh_buckets) = (voff as usize, toff as usize, boff as usize);
        // Collider attachments: each bound triangle's vertices as global `mverts` indices.
        let attachments: Vec<attach::Attachment> = m
            .collider_attachments
            .iter()
            .map(|a| {
                let c = a.collider as usize;
                let tri = col.meshes[c].tris[a.triangle as usize];
                attach::Attachment {
                    particle: a.particle,
                    verts: tri.map(|v| v + mesh_vert_off[c]),
                    bary: a.bary,
                    weight: a.weight,
                    local: a.local,
                    last: a.target,
                    ..Default::default()
                }
            })
            .collect();
        let mesh_entries = if col.meshes.is_empty() { 0 } else { Self::mesh_entry_bound(&col.meshes) * 5 / 4 };
        meshes.entries_off = boff + 1;
        p.n_meshes = col.meshes.len() as u32;
        p.n_mesh_verts = voff;
        p.n_mesh_tris = toff;
        p.mesh_tris = base(&mut idx, &tri_idx);
        p.tri_levels = base(&mut idx, &tri_levels);
        let levels: Vec<u32> = col.levels.iter().map(|&l| l as u32).collect();
        p.particle_levels = base(&mut idx, &levels);
        let pinned: Vec<u32> = m.pinned.iter().map(|&b| b as u32).collect();
        p.pinned = base(&mut idx, &pinned);
        // Self-collision: the CPU's exclusion set (it skips the pass when that cannot be built).
        let excl = if col.self_settings.enabled {
            crate::solver::collide::self_collide::build_exclusions(m, view.self_radius).ok()
        } else {
            None
        };
        let self_enabled = excl.is_some();
        if let Some(ex) = &excl {
            let (off, nbr) = ex.csr();
            p.excl_off = base(&mut idx, off);
            p.excl_nbr = base(&mut idx, nbr);
        }
        let self_buckets = if self_enabled { buckets_for(n) } else { 0 };
        p.self_enabled = self_enabled as u32;
        p.self_radius = view.self_radius;
        p.self_cell = view.self_cell;
        p.self_mu_s = col.self_settings.static_friction;
        p.self_mu_k = col.self_settings.kinetic_friction;
        p.self_mask = self_buckets.max(1) as u32 - 1;

        let mut fdata: Vec<f32> = Vec::new();
        let fbase = |f: &mut Vec<f32>, data: &[f32]| {
            let b = f.len() as u32;
            f.extend_from_slice(data);
            b
        };
        p.mat_vals = fbase(&mut fdata, &mat.vals);
        p.diag = fbase(&mut fdata, view.diag);
        let mut td = Vec::with_capacity(nt * project_triangles::TRI_FLOATS);
        for t in 0..nt {
            let g = m.triangles.g[t];
            td.extend_from_slice(&[g[0][0], g[0][1], g[1][0], g[1][1], g[2][0], g[2][1]]);
            td.push(m.triangles.w_stretch[t]);
            td.push(m.triangles.w_shear[t]);
        }
        p.tri_data = fbase(&mut fdata, &td);
        p.seam_coefs = fbase(&mut fdata, &sp.coefs);
        p.curved_coefs = fbase(&mut fdata, &c_coefs);
        p.curved_wr = fbase(&mut fdata, &c_wr);
        if let Some((fs, fk)) = &col.friction {
            let pairs: Vec<f32> = fs.iter().zip(fk).flat_map(|(&a, &b)| [a, b]).collect();
            p.has_friction = 1;
            p.friction = fbase(&mut fdata, &pairs);
        }
        p.n_curved = lay.curved.len() as u32;
        let colliders: Vec<Collider> = view
            .colliders
            .iter()
            .map(|c| {
                let (kind, p0, p1, radius) = match c.shape {
                    crate::solver::Shape::Plane { point, normal } => (KIND_PLANE, point, normal, 0.0),
                    crate::solver::Shape::Sphere { center, radius } => (KIND_SPHERE, center, [0.0; 3], radius),
                    crate::solver::Shape::Capsule { a, b, radius } => (KIND_CAPSULE, a, b, radius),
                };
                Collider {
                    p0,
                    radius,
                    p1,
                    kind,
                    static_friction: c.static_friction,
                    kinetic_friction: c.kinetic_friction,
                    _pad0: 0,
                    _pad1: 0,
                }
            })
            .collect();
        p.n_colliders = colliders.len() as u32;
        p.thickness = view.thickness;

        let s = view.settings;
        let h = view.h;
        p.gravity = s.gravity;
        p.h = h;
        p.inv_h = 1.0 / h;
        p.inv_h2 = 1.0 / (h * h);
        p.rho = view.rho;
        p.n = n as u32;
        p.n_tris = nt as u32;
        p.n_seam_pairs = sp.len() as u32;
        p.delay = s.chebyshev.delay;
        p.ramp_enabled = s.ramp.enabled as u32;
        p.air_damping = s.air_damping;
        p.closing_damping = s.ramp.closing_damping;
        p.gap_threshold = s.ramp.gap_threshold;
        p.closed_fraction = s.ramp.closed_fraction;
        p.release_time = s.ramp.release_time;
        p.has_seams = (!sp.is_empty()) as u32;
        p.substeps = s.substeps;
        p.iterations = s.iterations;
        p.release_gap = s.ramp.release_gap;
        p.closing_gravity = s.ramp.closing_gravity;
        p.closing_speed = s.ramp.closing_speed;
        let closing_scheduled = view.seams_closing && !sp.is_empty();
        p.closing_scheduled = closing_scheduled as u32;

        let need = Capacities {
            n,
            slots: lay.total,
            idx: idx.len(),
            fdata: fdata.len(),
            colours: colours.len(),
            colliders: colliders.len(),
            mesh_verts: n_mesh_verts,
            mesh_tris: n_mesh_tris,
            mesh_buckets,
            mesh_entries,
            self_buckets,
            attachments: attachments.len(),
            seam_pairs: sp.len(),
        };
        let stride = self.ctx.device.limits().min_uniform_buffer_offset_alignment.max(16) as u64;
        let realloc = self.buffers.as_ref().is_none_or(|b| !b.caps.fits(&need));
        if realloc {
            self.buffers = Some(Buffers::new(&self.ctx.device, need, stride));
            self.binds = None;
        }
        let b = self.buffers.as_ref().ok_or_else(|| GpuFailure::Device("buffers missing".into()))?;
        let q = &self.ctx.queue;
        let vec4 = |s: &crate::solver::Vec3Soa| -> Vec<[f32; 4]> {
            (0..s.len()).map(|i| [s.x[i], s.y[i], s.z[i], 0.0]).collect()
        };
        let sewn = &m.sewn;
        let particles: Vec<Particle> = (0..n)
            .map(|i| Particle {
                b_const: m.b_const.get(i).to_array(),
                mass: m.mass[i],
                pin_target: view.pin_target.get(i).to_array(),
                flags: if m.pinned[i] { PARTICLE_PINNED } else { 0 } | if sewn[i] { PARTICLE_SEWN } else { 0 },
            })
            .collect();
        let (phase, elapsed) = phase_to_gpu(view.ramp.phase);
        // The early stop's floor, as `Simulation::prepare` computes it (from the full gravity,
        // also while the ramp holds it).
        let g2 = view.settings.gravity.iter().map(|&g| (g as f64).powi(2)).sum::<f64>();
        let weight_norm = (0..n).filter(|&i| !m.pinned[i]).map(|i| (m.mass[i] as f64).powi(2) * g2).sum::<f64>().sqrt();
        let (stall_on, (stall_best, stall_since)) = (view.ramp.stall.is_some(), view.ramp.stall.unwrap_or_default());
        let state = StepState {
            omega: 1.0,
            phase,
            elapsed,
            tolerance: view.settings.tolerance,
            weight_norm: weight_norm as f32,
            closing: view.seams_closing as u32,
            stall_on: stall_on as u32,
            stall_best,
            stall_since,
            ..StepState::zeroed()
        };
        q.write_buffer(&b.params, 0, bytemuck::bytes_of(&p));
        q.write_buffer(&b.state, 0, bytemuck::bytes_of(&state));
        q.write_buffer(&b.particles, 0, bytemuck::cast_slice(&particles));
        q.write_buffer(&b.x, 0, bytemuck::cast_slice(&vec4(view.x)));
        q.write_buffer(&b.v, 0, bytemuck::cast_slice(&vec4(view.v)));
        // Pinned particles are in no colour, so their update norms must read zero.
        q.write_buffer(&b.norms, 0, bytemuck::cast_slice(&vec![[0.0f32; 2]; n]));
        let no_contact = Contact { collider: u32::MAX, ..Contact::zeroed() };
        q.write_buffer(&b.contacts, 0, bytemuck::cast_slice(&vec![no_contact; n]));
        if !colliders.is_empty() {
            q.write_buffer(&b.colliders, 0, bytemuck::cast_slice(&colliders));
        }
        if !idx.is_empty() {
            q.write_buffer(&b.idx, 0, bytemuck::cast_slice(&idx));
        }
        if !fdata.is_empty() {
            q.write_buffer(&b.fdata, 0, bytemuck::cast_slice(&fdata));
        }
        if n_mesh_verts > 0 {
            // Sections: previous, next, this substep's positions, velocities, then normals.
            let mut mv = vec![[0.0f32; 4]; 4 * n_mesh_verts];
            let v4 = |p: [f32; 3]| [p[0], p[1], p[2], 0.0];
            for (c, mc) in col.meshes.iter().enumerate() {
                let o = mesh_vert_off[c] as usize;
                for (k, v) in mc.next.iter().enumerate() {
                    mv[o + k] = v4(mc.prev[k]);
                    mv[n_mesh_verts + o + k] = v4(*v);
                    mv[2 * n_mesh_verts + o + k] = v4(mc.cur[k]);
                    mv[3 * n_mesh_verts + o + k] = v4(mc.vel[k].into());
                }
            }
            q.write_buffer(&b.mverts, 0, bytemuck::cast_slice(&mv));
            q.write_buffer(&b.mcounts, 0, bytemuck::cast_slice(&vec![0u32; mesh_buckets]));
        }
        let table = |n_buckets: usize, n_entries: usize| TableInfo {
            n_buckets: n_buckets as u32,
            n_entries: n_entries as u32,
            ..Default::default()
        };
        q.write_buffer(&b.mesh_table_info, 0, bytemuck::bytes_of(&table(mesh_buckets, mesh_entries)));
        q.write_buffer(&b.self_table_info, 0, bytemuck::bytes_of(&table(self_buckets, n)));
        q.write_buffer(&b.meshes, 0, bytemuck::bytes_of(&meshes));
        let info = attach::AttachInfo { n: attachments.len() as u32, ..Default::default() };
        q.write_buffer(&b.attach_info, 0, bytemuck::bytes_of(&info));
        if !attachments.is_empty() {
            q.write_buffer(&b.attachments, 0, bytemuck::cast_slice(&attachments));
        }
        if !pair_state.is_empty() {
            q.write_buffer(&b.closing, 0, bytemuck::cast_slice(&pair_state));
        }
        if self_enabled {
            q.write_buffer(&b.scounts, 0, bytemuck::cast_slice(&vec![0u32; self_buckets]));
        }
        q.write_buffer(&b.sdelta, 0, bytemuck::cast_slice(&vec![[0.0f32; 4]; n]));
        let mut cbytes = vec![0u8; colours.len().max(1) * stride as usize];
        for (c, r) in colours.iter().enumerate() {
            let o = c * stride as usize;
            cbytes[o..o + 16].copy_from_slice(bytemuck::bytes_of(r));
        }
        q.write_buffer(&b.colours, 0, &cbytes);

        // Bind groups depend on the buffers and on the colour count only.
        let rebind = self.binds.as_ref().is_none_or(|g| g.gauss_seidel.len() != colours.len());
        if rebind {
            self.binds = Some(BindGroups::new(&self.ctx.device, &self.ctx.pipelines, b, colours.len(), stride));
        }
        self.uploaded = Some(Uploaded {
            n,
            n_tris: nt,
            n_curved: lay.curved.len(),
            n_colliders: colliders.len(),
            n_meshes: col.meshes.len(),
            n_mesh_verts,
            n_mesh_tris,
            mesh_buckets,
            mesh_vert_off,
            meshes,
            self_enabled,
            self_buckets,
            n_attach: attachments.len(),
            early_stop: s.tolerance > 0.0,
            closing_scheduled,
            n_seam_pairs: sp.len(),
            colours,
            h,
            rho: view.rho,
            method: s.method,
        });
        self.dirty = false;
        self.mesh_hash_valid = false;
        Ok(())
    }

    /// Advances `sim` by `dt` on the GPU; afterwards `sim`'s positions, ramp and clock are
    /// current (its velocities only after [`GpuSolver::sync_velocities`]). On divergence the
    /// GPU state is rolled back and [`GpuFailure::Step`] returned, as the CPU step does.
    pub fn step(&mut self, sim: &mut Simulation, dt: f32) -> Result<StepStats, GpuFailure> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(GpuFailure::Step(TailorError::setting("dt", dt, "the time step must be positive and finite")));
        }
        let t0 = Instant::now();
        let substeps = sim.settings().substeps;
        let iterations = sim.settings().iterations;
        let h = dt / substeps as f32;
        // The body's holds of the closing phase come or go (an edit of the model, as on the
        // CPU at the start of its step): the GPU's velocities come down first, then the
        // model goes up again.
        self.update_closing_holds(sim)?;
        let stale = self.uploaded.as_ref().is_none_or(|u| u.h != h || u.method != sim.settings().method);
        let mut upload = self.dirty || stale;
        if upload {
            if !self.dirty {
                // A new substep length re-uploads from the CPU copy: bring its velocities up
                // to date first (the GPU's are the current ones).
                self.sync_velocities(sim)?;
            }
            // Refuse before the colliders' frame begins, so the CPU runs the whole frame.
            if let Some(why) = Self::unsupported(&sim.gpu_view(h)) {
                self.dirty = true;
                return Err(GpuFailure::Unsupported(why));
            }
        }
        // The positions given since the last frame become this frame's end; from here on a
        // failure hands the begun frame to the CPU (`Simulation::step` does not begin it again).
        sim.begin_backend_frame(dt);
        let meshes = &sim.collide.meshes;
        let moving = meshes.iter().any(|m| m.moving);
        if !upload && moving {
            let cap = self.buffers.as_ref().map_or(0, |b| b.caps.mesh_entries);
            if Self::mesh_entry_bound(meshes) > cap {
                // The colliders deformed beyond the hash's capacity: re-upload with room.
                self.sync_velocities(sim)?;
                upload = true;
            }
        }
        if upload {
            let view = sim.gpu_view(h);
            let ctx = self.ctx.clone();
            let (r, invalid) = ctx.validated(|| self.upload(&view));
            if let Some(e) = invalid {
                self.dirty = true;
                return Err(GpuFailure::Device(e));
            }
            if r.is_err() {
                self.dirty = true;
            }
            r?;
        }
        let stage_timed = self.timestamps();
        let (Some(b), Some(g), Some(u)) = (&self.buffers, &self.binds, &mut self.uploaded) else {
            return Err(GpuFailure::Device("nothing uploaded".into()));
        };
        if u.n_meshes > 0 {
            // Collider positions go up once per frame (only for colliders that move), with
            // the per-frame uniform; the GPU interpolates them per substep.
            let nv = u.n_mesh_verts as u64;
            for (c, m) in sim.collide.meshes.iter().enumerate() {
                u.meshes.m[c].moving = m.moving as u32;
                if m.moving && !upload {
                    let next: Vec<[f32; 4]> = m.next.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect();
                    let off = (nv + u.mesh_vert_off[c] as u64) * VEC4;
                    self.ctx.queue.write_buffer(&b.mverts, off, bytemuck::cast_slice(&next));
                }
            }
            u.meshes.inv_dt = 1.0 / dt;
            self.ctx.queue.write_buffer(&b.meshes, 0, bytemuck::bytes_of(&u.meshes));
        }
        // Build the colliders' hash every substep while one moves, else once after an upload.
        let rebuild_each_substep = u.n_meshes > 0 && moving;
        let rebuild_first = u.n_meshes > 0 && !self.mesh_hash_valid;
        let rebuilds = if rebuild_each_substep { substeps } else { rebuild_first as u32 };
        let n = u.n;
        let accelerate = u.method == Method::Chebyshev;
        if stage_timed && self.timing.is_none() {
            self.timing = Some(timing::Timing::new(&self.ctx.device));
        }
        let pl = &self.ctx.pipelines;
        // The frame's iteration count starts at zero (the early stop may run fewer).
        // So do the frame's iteration count (the early stop may run fewer) and its top speed.
        let at = std::mem::offset_of!(StepState, iterations_run) as u64;
        self.ctx.queue.write_buffer(&b.state, at, bytemuck::bytes_of(&[0u32; 2]));
        let plan = plan::frame(pl, g, u, substeps, iterations, rebuild_each_substep, rebuild_first);
        let dispatches = plan.len();
        // Per-stage times where the device writes timestamps inside passes (and the frame's
        // marks fit one query set).
        let marks = if stage_timed { plan::stage_marks(&plan) } else { Vec::new() };
        let timed = self.timing.as_ref().filter(|_| !marks.is_empty() && marks.len() < timing::MAX_QUERIES as usize);
        let mut enc = self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let xbytes = n as u64 * VEC4;
        enc.copy_buffer_to_buffer(&b.x, 0, &b.x_backup, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.v, 0, &b.v_backup, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state, 0, &b.state_backup, 0, STATE_BYTES);
        {
            // One pass for the whole frame: wgpu orders successive dispatches that share
            // storage buffers, so colours and stages see each other's writes.
            let mut pass = enc
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("substeps"), timestamp_writes: None });
            if let Some(t) = timed {
                pass.write_timestamp(&t.set, 0);
            }
            let mut next_mark = marks.iter().map(|&(k, _)| k).enumerate().peekable();
            for (k, d) in plan.iter().enumerate() {
                pass.set_pipeline(d.pipeline);
                pass.set_bind_group(0, d.bind, &[]);
                pass.dispatch_workgroups(d.groups, 1, 1);
                if let (Some(t), Some(&(m, at))) = (timed, next_mark.peek()) {
                    if at == k {
                        pass.write_timestamp(&t.set, m as u32 + 1);
                        next_mark.next();
                    }
                }
            }
        }
        if let Some(t) = timed {
            let count = marks.len() as u32 + 1;
            enc.resolve_query_set(&t.set, 0..count, &t.resolve, 0);
            enc.copy_buffer_to_buffer(&t.resolve, 0, &t.read, 0, count as u64 * 8);
        }
        enc.copy_buffer_to_buffer(&b.x, 0, &b.readback, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state, 0, &b.readback, xbytes, STATE_BYTES);
        // While seams close, their schedule comes back too (the CPU takes over from it).
        let pair_bytes = if u.closing_scheduled { u.n_seam_pairs as u64 * VEC4 } else { 0 };
        if pair_bytes > 0 {
            enc.copy_buffer_to_buffer(&b.closing, 0, &b.readback, xbytes + STATE_BYTES, pair_bytes);
        }
        let (n_colours, rho, n_tris_total) = (u.colours.len(), u.rho, u.n_mesh_tris);
        let has_meshes = u.n_meshes > 0;
        self.ctx.queue.submit([enc.finish()]);
        let bytes = self.read(xbytes + STATE_BYTES + pair_bytes)?;
        let stage_times = match timed {
            Some(t) => {
                let ticks = map_read(&self.ctx.device, &t.read, (marks.len() as u64 + 1) * 8)?;
                Some(timing::stage_times(&marks, bytemuck::cast_slice(&ticks), self.ctx.timestamp_period))
            }
            None => None,
        };
        let (xs, rest) = bytes.split_at(xbytes as usize);
        let (st, pairs) = rest.split_at(STATE_BYTES as usize);
        let x: &[[f32; 4]] = bytemuck::cast_slice(xs);
        let state: StepState = *bytemuck::from_bytes(st);
        let pairs: Vec<(f32, f32)> =
            bytemuck::cast_slice::<u8, close_seams::PairState>(pairs).iter().map(|p| (p[1], p[3])).collect();
        if has_meshes {
            self.mesh_hash_valid = true;
        }
        // As on the CPU, the colliders' frame has happened whatever the outcome below.
        sim.end_backend_frame();
        if x.iter().any(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite())) {
            self.restore_backup(xbytes)?;
            return Err(GpuFailure::Step(TailorError::Diverged {
                reason: "positions became non-finite on the GPU; the state was rolled back (lower the time step or \
                         stiffness, or raise substeps)"
                    .into(),
            }));
        }
        let phase = phase_from_gpu(state.phase, state.elapsed);
        let stall = (state.stall_on != 0).then_some((state.stall_best, state.stall_since));
        sim.accept_backend_state(BackendState {
            x: Some(x),
            ramp: Ramp { phase, stall },
            elapsed: h as f64 * substeps as f64,
            seams: (pair_bytes > 0).then_some(SeamClosing { closing: state.closing != 0, pairs: &pairs }),
        });
        if sim.backend_after_step(f32::from_bits(state.max_speed_bits)) {
            // Fallen asleep: the CPU zeroed the velocities; the GPU takes them from there when
            // the cloth wakes.
            self.dirty = true;
        }
        // As the CPU at the end of its step: the holds go once the seams have met.
        self.update_closing_holds(sim)?;
        let mut stats = StepStats {
            substeps,
            iterations: state.iterations_run,
            residual: state.residual,
            colours: n_colours,
            rho: if accelerate { rho } else { 0.0 },
            damping: Ramp { phase, stall: None }.damping(sim.settings()),
            ramp_phase: phase,
            seam_gap_max: state.gap_max,
            seam_closed_fraction: state.closed_fraction,
            contacts: state.contacts as usize,
            collision: CollisionStats {
                rebuilds,
                reuses: if n_tris_total > 0 { substeps - rebuilds } else { 0 },
                triangles_kept: n_tris_total,
                mesh_contacts: state.mesh_contacts as usize,
                self_pairs: state.self_pairs as usize,
                ..Default::default()
            },
            backend: ActiveBackend::Gpu,
            warning: None,
            dispatches,
            ..Default::default()
        };
        match stage_times {
            // The GPU's own time per stage (timestamps); upload and readback are outside them.
            Some(t) => stats.timings = t,
            // Without timestamps the whole frame, upload and readback included, is reported as
            // the global stage.
            None => stats.timings[crate::solver::Stage::Global] = t0.elapsed().as_secs_f64(),
        }
        Ok(stats)
    }

    /// Places or releases the body's holds of the closing phase when due
    /// (`Simulation::update_closing_holds`): the velocities come down first (the GPU's are the
    /// current ones) and the edited model goes up before the next frame.
    fn update_closing_holds(&mut self, sim: &mut Simulation) -> Result<(), GpuFailure> {
        if !sim.closing_holds_due() {
            return Ok(());
        }
        self.sync_velocities(sim)?;
        sim.update_closing_holds().map_err(GpuFailure::Step)?;
        self.dirty = true;
        Ok(())
    }

    /// Copies the backups of x, v and the state back (after a diverged frame).
    fn restore_backup(&mut self, xbytes: u64) -> Result<(), GpuFailure> {
        let b = self.buffers.as_ref().ok_or_else(|| GpuFailure::Device("buffers missing".into()))?;
        let mut enc =
            self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("rollback") });
        enc.copy_buffer_to_buffer(&b.x_backup, 0, &b.x, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.v_backup, 0, &b.v, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state_backup, 0, &b.state, 0, STATE_BYTES);
        self.ctx.queue.submit([enc.finish()]);
        self.wait()
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
