//! The cloth solver on the CPU: implicit Euler by Projective Dynamics (Bouaziz et al. 2014),
//! solved Vivace-style (Fratarcangeli, Tibaldo and Pellacini 2016) with rayon.
//!
//! The folders follow the pipeline, from data to step to checks:
//!
//! ```text
//! solver/
//!   model/       what is simulated: Model, constraints, global system, colouring, SoA, settings
//!   stages/      the ordered list of a substep's stages (STAGES) and their kernels:
//!                prediction → (local → global)×iterations → damping
//!   collide/     contacts and collisions: analytic shapes, mesh colliders, self-collision, levels
//!   stats.rs     what a step reports (StepStats, CollisionStats; timings per stage)
//!   sleep.rs     when a cloth at rest stops being solved
//!   simulation/  Simulation: the state, and the step that walks STAGES (step.rs); the hooks
//!                that run collide/ inside the stages; the view the GPU backend uploads from
//!   accuracy/    the reference solver and the error measures (tests and benchmarks)
//! ```
//!
//! Imports go down this list only (`model` < `stages` < `stats` < `collide` < `sleep` <
//! `simulation` < `accuracy`; `tests/layers.rs` checks it): the parts never import the
//! simulation that runs them. The solver imports neither the GPU backend ([`crate::gpu`]) nor
//! the facade that chooses between the two ([`crate::engine`]); both sit above it.

pub mod accuracy;
pub mod collide;
pub mod model;
pub mod simulation;
pub mod sleep;
pub mod stages;
pub mod stats;

pub use crate::quality::QualityMetrics;
pub use accuracy::{
    ErrorMeasures, IterationRecord, MethodRun, MethodsMeasurement, ReferenceInfo, ReferenceOptions, StepMeasurement,
};
pub use collide::{
    ColliderId, CollisionSkips, ImplicitCollider, MeshColliderOptions, SelfCollisionSettings, SelfContacts, Shape,
};
pub use model::constraints::{Attachment, ColliderAttachment, Seam, SeamPoint};
pub use model::settings::{
    bend_at_angle, ChebyshevSettings, Fabric, Method, SeamRamp, SolverSettings, DEFAULT_THICKNESS, PRESETS,
};
pub use model::soa::Vec3Soa;
pub use simulation::view::SolverView;
pub use simulation::Simulation;
pub use stages::damping::RampPhase;
pub use stages::{Stage, StageTimings, STAGES};
pub use stats::{ActiveBackend, CollisionStats, StepStats};
