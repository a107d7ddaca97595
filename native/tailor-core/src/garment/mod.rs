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
//! * [`build`]: triangulate, place (pattern placement or side by side, or the positions stored
//!   as placed), bend, sew, and convert the sewn pairs into the solver's weighted
//!   [`solver::Seam`](crate::solver::Seam)s.
//! * [`setup`]: the garment's setup (fabric per piece, painted maps, pins, collision) applied
//!   to the simulation built from it.

pub mod build;
pub mod from_pattern;
pub mod resolution;
pub mod setup;
pub mod stitches;

pub use build::{
    build_configured, build_simulation, layout_of, solver_input, triangulate_all, BuildOptions, SolverInput,
    DEFAULT_SEAM_BEND_STIFFNESS, DEFAULT_SEAM_STIFFNESS,
};
pub use from_pattern::{garment_from_pattern, import_warnings, read_garment};
pub use resolution::set_resolution;
pub use setup::{
    apply_collision, apply_fabric, apply_friction, apply_levels, apply_setup, pin_groups, pin_weights, Applied, Layout,
    PinGroup,
};
pub use stitches::stitch_seam;
