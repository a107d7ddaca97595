//! What a step reports: per-stage timings, iterations used, the final residual, the collision
//! work. A leaf: the types here name no solver state, so the simulation, the collisions and
//! the GPU backend all fill them without importing each other.

use crate::solver::stages::damping::RampPhase;
use crate::solver::stages::StageTimings;

/// Which backend ran a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ActiveBackend {
    #[default]
    Cpu,
    Gpu,
}

/// Statistics of one call to `Simulation::step`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepStats {
    pub substeps: u32,
    /// Local/global iterations summed over the substeps.
    pub iterations: u32,
    /// Relative residual at the end of the last substep (GS residual over its first value).
    pub residual: f32,
    /// Number of colours of the particle graph.
    pub colours: usize,
    /// Spectral radius used by Chebyshev in the last substep (0 when not accelerating).
    pub rho: f32,
    pub timings: StageTimings,
    /// Air damping in effect at the end of the step, 1/s.
    pub damping: f32,
    pub ramp_phase: RampPhase,
    /// Largest distance between sewn points, metres (0 without seams).
    pub seam_gap_max: f32,
    /// Fraction of sewn pairs within the ramp's gap threshold.
    pub seam_closed_fraction: f32,
    /// Particles in contact with a collider at the end of the step.
    pub contacts: usize,
    /// Median distance the particles touching a mesh collider at the end of the step moved
    /// during it, metres (`None`: none touch it, or the GPU ran the step). Against a still
    /// body, the drape's jitter at rest (issue 23).
    pub contact_motion: Option<f32>,
    /// Mesh-collider and self-collision work (times also counted in the stages above).
    pub collision: CollisionStats,
    /// The cloth was asleep: nothing was solved (see `sleep.rs`).
    pub asleep: bool,
    /// The backend that ran the step.
    pub backend: ActiveBackend,
    /// Why a requested GPU backend is not in use (no adapter, unsupported feature), if so.
    pub warning: Option<String>,
    /// Compute dispatches the GPU recorded for the step (its frame plan's length; 0 on the CPU).
    pub dispatches: usize,
    /// CPU threads the step ran on (`Solver::set_threads`; 0 when stepped without a `Solver`).
    pub threads: usize,
}

/// Collision work of a step, summed over its substeps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CollisionStats {
    /// Interpolating collider positions and (re)building their hashes, seconds.
    pub hash_seconds: f64,
    /// Particle-vs-cell tests of the iterations (included in the local stage's time too).
    pub contact_seconds: f64,
    /// Self-collision passes (included in the global stage's time too).
    pub self_seconds: f64,
    /// End-of-substep penetration resolve and contact friction bookkeeping.
    pub resolve_seconds: f64,
    /// Collider hashes rebuilt / reused.
    pub rebuilds: u32,
    pub reuses: u32,
    /// Collider triangles filed / culled in the last substep (all colliders).
    pub triangles_kept: usize,
    pub triangles_culled: usize,
    /// Particles touching a mesh collider at the end of the step.
    pub mesh_contacts: usize,
    /// Overlapping cloth pairs corrected by the last self-collision pass.
    pub self_pairs: usize,
    /// Hash searches of the self-collision passes (a search serves passes until a particle
    /// has moved half the search margin).
    pub self_searches: u32,
    /// Self-collision passes that searched only the particles that had moved too far since
    /// the last search (`self_movers.rs`).
    pub self_partial_searches: u32,
    /// Particle-vs-mesh tests the iterations ran in full; those the broad phase skipped (a
    /// particle still free within the radius of its last test); and those it answered from the
    /// particle's shortlist of nearest candidates (`mesh_broad_phase.rs`; the name is from when
    /// the list held the nearest alone).
    pub contact_tests: u64,
    pub contact_skips: u64,
    pub contact_nearest: u64,
}
