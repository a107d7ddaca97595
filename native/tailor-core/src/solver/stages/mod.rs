//! The stages of a substep, in the order they run, and the kernels each stage calls.
//!
//! [`STAGES`] is the one ordered list: [`Simulation`](crate::solver::Simulation)'s substep walks
//! it (a `match` on each [`Stage`], so a stage added here must be run there), and
//! [`StageTimings`] is indexed by it, so the per-stage times a step reports (and the keys of
//! the Python module's `stats["timings"]`, [`Stage::name`]) follow the same list.
//!
//! * [`Stage::Prediction`]: `y = x + h·v + h²·g`, pins, the fixed right-hand side, the collider
//!   positions and hashes of the substep (run by the simulation itself);
//! * [`Stage::Local`]: contact detection and constraint projections ([`local`]);
//! * [`Stage::Global`]: one coloured Gauss-Seidel (or Jacobi) sweep ([`global`]), Chebyshev
//!   extrapolation ([`chebyshev`]), the two-level step's coarse correction when it is on
//!   ([`coarse`]), the self-collision pass;
//! * [`Stage::Damping`]: penetrations resolved, velocities, friction, air damping and the
//!   seam-closing ramp ([`damping`]).
//!
//! `Local` and `Global` alternate for the substep's iterations (with an optional early stop);
//! each of the others runs once per substep.

pub mod chebyshev;
pub(crate) mod coarse;
pub mod damping;
pub(crate) mod global;
pub(crate) mod local;

use std::ops::{Index, IndexMut};

/// One stage of a substep (see the [module](self) docs for what each runs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Inertial prediction `y = x + h·v + h²·g` and the fixed part of the right-hand side.
    Prediction,
    /// Local step: constraint projections (and contact detection against colliders).
    Local,
    /// Global step: the Gauss-Seidel (or Jacobi) sweeps, Chebyshev included.
    Global,
    /// Velocity update, friction, air damping and the seam-closing ramp.
    Damping,
}

/// Every stage, in the order a substep runs them.
pub const STAGES: [Stage; Stage::COUNT] = [Stage::Prediction, Stage::Local, Stage::Global, Stage::Damping];

impl Stage {
    /// The number of stages.
    pub const COUNT: usize = 4;

    /// The stage's name, as reports and the Python module's `stats["timings"]` key it.
    pub const fn name(self) -> &'static str {
        match self {
            Stage::Prediction => "prediction",
            Stage::Local => "local",
            Stage::Global => "global",
            Stage::Damping => "damping",
        }
    }

    /// Whether the stage runs once per iteration (else once per substep).
    pub const fn per_iteration(self) -> bool {
        matches!(self, Stage::Local | Stage::Global)
    }

    /// The stage's position in [`STAGES`].
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// Wall time per solver stage, seconds, summed over a step's substeps; `timings[stage]`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings([f64; Stage::COUNT]);

impl StageTimings {
    pub fn total(&self) -> f64 {
        self.0.iter().sum()
    }

    /// Each stage with its time, in the order of [`STAGES`].
    pub fn iter(&self) -> impl Iterator<Item = (Stage, f64)> + '_ {
        STAGES.iter().map(|&s| (s, self[s]))
    }

    pub(crate) fn add(&mut self, o: &StageTimings) {
        for s in STAGES {
            self[s] += o[s];
        }
    }
}

impl Index<Stage> for StageTimings {
    type Output = f64;
    fn index(&self, s: Stage) -> &f64 {
        &self.0[s.index()]
    }
}

impl IndexMut<Stage> for StageTimings {
    fn index_mut(&mut self, s: Stage) -> &mut f64 {
        &mut self.0[s.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_is_in_order_and_names_are_the_reported_keys() {
        for (i, s) in STAGES.iter().enumerate() {
            assert_eq!(s.index(), i, "{s:?} is not at its place in STAGES");
        }
        let names: Vec<_> = STAGES.iter().map(|s| s.name()).collect();
        assert_eq!(names, ["prediction", "local", "global", "damping"]);
        let mut t = StageTimings::default();
        t[Stage::Global] = 2.0;
        t[Stage::Damping] = 0.5;
        assert_eq!(t.total(), 2.5);
        assert_eq!(t.iter().map(|(_, v)| v).collect::<Vec<_>>(), [0.0, 0.0, 2.0, 0.5]);
    }
}
