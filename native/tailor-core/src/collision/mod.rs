//! Collision building blocks (Nylén et al. 2020, section 6), independent of the solver: the
//! geometric kernels that the solver's contacts ([`crate::solver::collide`]), the quality
//! metrics ([`crate::quality`]) and the GPU backend's shaders share. Imports nothing above
//! [`crate::mesh`].
//!
//! * [`hash`]: the spatial hash of Eq. 1-3, rebuilt from scratch every substep by a parallel
//!   counting sort; buckets hold `(cell_id, index)` entries so primitives of different cells
//!   that share a bucket are never compared.
//! * [`collider_hash`]: collider triangles inserted per Alg. 1 (optionally also every cell the
//!   triangle's plane crosses, so large triangles are never lost).
//! * [`geometry`]: stateless kernels: closest point on a triangle, side tests, the paper's
//!   particle-vs-cell test.
//! * [`intersect`]: segment-triangle and triangle-triangle intersection predicates.
//! * [`self_collision`]: particle pairs closer than `2r` found through the hash.
//! * [`closed_mesh`]: the inside (ray parity) and distance queries of a closed body, behind
//!   the penetration and on-body measures of [`crate::quality`]; [`near_surface`]: how many
//!   points are near it, decided mostly by its vertices.
//!
//! Positions come either as structure-of-arrays `f32` slices (the solver's layout) or as
//! `&[[f32; 3]]` (meshes). Everything called per substep reuses its buffers: after the first
//! call with a given problem size it does not allocate.

pub mod closed_mesh;
pub mod collider_hash;
pub mod geometry;
pub mod hash;
pub mod intersect;
pub mod near_surface;
pub mod self_collision;

pub use closed_mesh::{ClosedMesh, Penetration};
pub use collider_hash::{ColliderHash, InsertionRule};
pub use geometry::Contact;
pub use hash::{Cell, SpatialHash};
pub use self_collision::{ExclusionSet, SelfCollision};
