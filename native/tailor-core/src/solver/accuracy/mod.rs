//! How accurate a step is: tools for tests, benchmarks and `examples/accuracy.rs`, never the
//! real-time path.
//!
//! * [`reference`]: the exact minimiser of one implicit step's objective (direct global solve,
//!   Anderson-accelerated local/global iterations);
//! * [`cholesky`]: the direct sparse solver behind it (reverse Cuthill-McKee, envelope
//!   Cholesky in f64);
//! * [`objective`]: the objective one step minimises and its gradient;
//! * [`measures`]: the error measures of a step against the reference, per iteration and per
//!   second ([`Simulation::measure_step`](crate::solver::Simulation::measure_step)).
//!
//! These sit above the simulation: they freeze one substep's problem and run its stages, and
//! nothing in the solver's step imports them.

mod cholesky;
pub mod measures;
mod objective;
mod reference;

pub use measures::{ErrorMeasures, IterationRecord, MethodRun, MethodsMeasurement, ReferenceOptions, StepMeasurement};
pub use reference::ReferenceInfo;
