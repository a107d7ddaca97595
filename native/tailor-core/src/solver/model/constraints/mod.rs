//! Constraint kernels of the Projective Dynamics objective.
//!
//! Every constraint has the form `w/2 · ‖A x − p‖²` where `A x` is a fixed linear combination of
//! particle positions and `p` the projection of `A x` onto the constraint's set (the *local
//! step*). The global matrix `Σ w AᵀA` is therefore constant while the topology is; only `p`
//! changes. Kernels are stateless functions over rest data, with the maths in their docs.
//!
//! * [`triangle`]: in-plane stretch and shear of each triangle against its flat 2D rest shape.
//! * [`stencil`]: one-vector constraints `v = Σ cₖ xₖ` with a distance-like projection, used by
//!   quadratic hinge bending, zero-rest-length seams and their hinges.
//! * [`bending`]: cotangent weights of the quadratic bending model (Bergou et al. 2006).
//! * [`seam`]: seams (equal or unequal counts) and the hinges across sewn edges.
//! * [`attachment`]: soft attachments of particles to target positions.

pub mod attachment;
pub mod bending;
pub mod seam;
pub mod stencil;
pub mod triangle;

pub use attachment::{Attachment, ColliderAttachment};
pub use seam::{Seam, SeamPoint};
pub use stencil::StencilSet;
pub use triangle::TriangleSet;
