//! What a step reports: per-stage timings, iterations used, the final residual.

use super::collide::CollisionStats;
use super::damping::RampPhase;

/// Wall time per solver stage, seconds, summed over a step's substeps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    /// Inertial prediction `y = x + h·v + h²·g` and the fixed part of the right-hand side.
    pub prediction: f64,
    /// Local step: constraint projections (and contact detection against colliders).
    pub local: f64,
    /// Global step: the Gauss-Seidel (or Jacobi) sweeps, Chebyshev included.
    pub global: f64,
    /// Velocity update, friction, air damping and the seam-closing ramp.
    pub damping: f64,
}

impl StageTimings {
    pub fn total(&self) -> f64 {
        self.prediction + self.local + self.global + self.damping
    }

    pub(crate) fn add(&mut self, o: &StageTimings) {
        self.prediction += o.prediction;
        self.local += o.local;
        self.global += o.global;
        self.damping += o.damping;
    }
}

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
    /// Mesh-collider and self-collision work (times also counted in the stages above).
    pub collision: CollisionStats,
    /// The cloth was asleep: nothing was solved (see `sleep.rs`).
    pub asleep: bool,
    /// The backend that ran the step.
    pub backend: ActiveBackend,
    /// Why a requested GPU backend is not in use (no adapter, unsupported feature), if so.
    pub warning: Option<String>,
}
