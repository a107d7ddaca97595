//! Seams between pattern pieces (paper Sec. 4, "Sewing System"), extended to unequal counts.
//!
//! * [`paths`]: contour paths, the picking steps of the manual seam tool.
//! * [`corners`]: contour corners and the corner-to-corner seam suggestion.
//! * [`model`]: the resolution-independent [`Seam`] (endpoints by rest position), resolved
//!   against the current meshes, which also remaps it after a re-triangulation.
//! * [`pairs`]: the solver's inputs, sewn [`SeamPair`]s (vertex-to-vertex, or vertex-to-edge
//!   point by arc length) and [`SeamHinge`]s for bending across the seam.
//! * [`validate`]: the checks, each error naming the seam.
//! * [`assemble`]: pieces and seams concatenated into the solver's cloth mesh.

pub mod assemble;
pub mod corners;
pub mod model;
pub mod pairs;
pub mod paths;
pub mod validate;

pub use assemble::{sew, SewnGarment};
pub use corners::{contour_angles_deg, find_corners, nearest_corner_segment};
pub use model::{remap_path, ResolvedSeam, Seam, SeamMode, SeamSide};
pub use pairs::{SeamHinge, SeamPair, WeightedPoint};
pub use paths::{
    candidate_paths, nearer_candidate, nearest_contour_position, nearest_contour_position_3d, path_between, path_of_n,
    shortest_path, span_path, ContourPath, Direction,
};
pub use validate::{check_side, path_from_vertices, validate_seam};
