//! # tailor-core
//!
//! The pure-Rust heart of Tailor: everything that does not need Python or Blender.
//!
//! * [`mesh`]: the cloth mesh the solver simulates (3D positions, the flat 2D rest shape of each
//!   pattern piece, triangles) and its derived topology (edges, bending hinges).
//! * [`solver`]: Projective Dynamics (Bouaziz et al. 2014) solved Vivace-style (Fratarcangeli et
//!   al. 2016) on the CPU, in folders that follow its pipeline: `model/` (the data, with the
//!   randomized graph colouring), `stages/` (the ordered list of a substep's stages and their
//!   kernels: parallel Gauss-Seidel, Chebyshev acceleration, the seam-closing damping ramp of
//!   Nylén et al. 2020), `collide/` (contacts and collisions), `simulation/` (the state and the
//!   step), `accuracy/` (an f64 reference solver and error measures).
//! * [`pattern`]: 2D sewing patterns (DXF, SVG, GarmentCode) as outlines in metres.
//! * [`triangulate`]: a pattern piece becomes an isotropic triangle mesh at a target edge length,
//!   with its ordered outer contour.
//! * [`seam`]: resolution-independent seams between contours, the paper's picking steps, corner
//!   suggestions, and the sewn pairs and hinges the solver consumes.
//! * [`bend`]: wrapping a placed piece around an axis before simulation (paper Fig. 4).
//! * [`arrange`]: named places found on a humanoid body from its shape, and pieces put on them,
//!   facing the body at a clearance and rolled round it (issue 25).
//! * [`playback`]: the frame rate and frame count of a run, checked once for every caller.
//! * [`placement`]: initial 3D positions from a pattern's placement, or a flat layout.
//! * [`scenes`]: procedural scenes (rectangles, a sewn tube) for tests, benchmarks and the demo.
//! * [`garment`]: a pattern assembled into a garment (stitches as seams), and a garment into a
//!   solver ready to step.
//! * [`garment_file`]: the versioned garment file (JSON manifest plus binary sidecar).
//! * [`collision`]: the spatial hash of Nylén et al. 2020 and the geometric kernels built on it
//!   (collider hash, closest points, self-collision pairs, intersection tests, closed meshes),
//!   free of solver state.
//! * [`quality`]: quality metrics of a simulated frame and the verdict on them.
//! * `gpu` (feature `gpu`): the per-frame solve on the GPU with wgpu (WGSL compute shaders).
//! * [`engine`]: the backend facade, [`engine::Solver`]: steps a simulation on the CPU solver or
//!   on `gpu`, as [`engine::Backend`] asks, falling back to the CPU.
//! * [`stability`]: the numerical stress cases (`tests/stability.rs`, `make stress`).
//! * [`weld`]: the sewn pieces merged along their seams into one mesh, for export (unequal seams
//!   split so the result stays watertight).
//! * [`files`]: reading what a user names and what their files name (confined, size-checked),
//!   and checking a run's outputs before it runs.
//! * [`io`]: triangle meshes from OBJ, PLY and glTF (skinned animation included) and the
//!   Point Cache 2 vertex-animation format.
//!
//! The `tailor` Python module (crate `tailor-py`) is a thin layer over this crate.
//!
//! Layers, from the bottom: `collision` < `quality` < `solver` < `gpu` < `engine`; a module
//! imports only those below it (`tests/layers.rs` checks it, with the order inside `solver`).

pub mod arrange;
pub mod bend;
pub mod collision;
pub mod engine;
pub mod error;
pub mod fabrics;
pub mod files;
pub mod garment;
pub mod garment_file;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod io;
pub mod mesh;
pub mod pattern;
pub mod placement;
pub mod playback;
pub mod quality;
pub mod scenes;
pub mod seam;
pub mod solver;
pub mod stability;
pub mod triangulate;
pub mod weld;

#[cfg(test)]
mod test_util;

pub use error::{Result, TailorError};
