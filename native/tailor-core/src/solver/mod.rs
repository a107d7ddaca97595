//! The cloth solver: implicit Euler by Projective Dynamics (Bouaziz et al. 2014), solved
//! Vivace-style (Fratarcangeli, Tibaldo and Pellacini 2016) on the CPU with rayon.
//!
//! Stages of a substep, in order (see [`simulation`]): prediction, then iterations of local
//! (projections, [`local`]) and global (coloured Gauss-Seidel with Chebyshev, [`global`],
//! [`colouring`], [`chebyshev`]) steps, then damping (velocities, friction, the seam-closing
//! ramp, [`damping`]). [`reference`] and [`measures`] say how accurate a step is.

mod backend;
pub mod chebyshev;
mod cholesky;
pub mod collide;
pub mod colouring;
pub mod constraints;
pub mod contacts;
pub mod damping;
mod global;
mod local;
pub mod measures;
pub mod model;
mod objective;
mod reference;
pub mod settings;
mod shape_check;
pub mod simulation;
pub mod sleep;
pub mod soa;
pub mod stats;
pub mod system;
mod view;

pub use backend::{Backend, Solver, SolverOptions, AUTO_GPU_MIN_PARTICLES};
pub use collide::{
    ColliderId, CollisionSkips, CollisionStats, MeshColliderOptions, QualityMetrics, SelfCollisionSettings,
};
pub use constraints::{Attachment, ColliderAttachment, Seam, SeamPoint};
pub use contacts::{ImplicitCollider, Shape};
pub use damping::RampPhase;
pub use measures::{ErrorMeasures, IterationRecord, MethodsMeasurement, ReferenceOptions, StepMeasurement};
pub use reference::ReferenceInfo;
pub use settings::{ChebyshevSettings, Fabric, Method, SeamRamp, SolverSettings, DEFAULT_THICKNESS, PRESETS};
pub use simulation::Simulation;
pub use soa::Vec3Soa;
pub use stats::{ActiveBackend, StageTimings, StepStats};
pub use view::SolverView;
