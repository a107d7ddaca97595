//! Garment assembly: from a read [`Pattern`](crate::pattern::Pattern) to a
//! [`Garment`](crate::garment_file::Garment), and from a garment to a solver ready to step.
//!
//! This module only wires together what already exists (pattern readers, triangulation, seams,
//! placement, bend, sewing and the solver); it holds no geometry of its own.
//!
//! * [`stitches`]: GarmentCode stitches (two named piece edges) become resolution-independent
//!   [`Seam`](crate::seam::Seam)s, walking direction as the file sews them.
//! * [`from_pattern`]: every piece triangulated at one edge length, stitches turned into seams.
//! * [`resolution`]: re-triangulating one piece and remapping the seams that touch it.
//! * [`build`]: triangulate, place (pattern placement or side by side), bend, sew, and convert
//!   the sewn pairs into the solver's weighted [`solver::Seam`](crate::solver::Seam)s.

pub mod build;
pub mod from_pattern;
pub mod resolution;
pub mod stitches;

pub use build::{build_simulation, solver_input, triangulate_all, BuildOptions, SolverInput, DEFAULT_SEAM_STIFFNESS};
pub use from_pattern::{garment_from_pattern, import_warnings, read_garment};
pub use resolution::set_resolution;
pub use stitches::stitch_seam;
