//! # tailor-core
//!
//! The pure-Rust heart of Tailor: everything that does not need Python or Blender.
//!
//! * [`mesh`]: the cloth mesh the solver simulates (3D positions, the flat 2D rest shape of each
//!   pattern piece, triangles) and its derived topology (edges, bending hinges).
//! * [`solver`]: Projective Dynamics (Bouaziz et al. 2014) solved Vivace-style (Fratarcangeli et
//!   al. 2016): randomized graph colouring, parallel Gauss-Seidel, Chebyshev acceleration, the
//!   seam-closing damping ramp of Nylén et al. 2020, plus an f64 reference solver and error
//!   measures.
//! * [`pattern`]: 2D sewing patterns (DXF, SVG, GarmentCode) as outlines in metres.
//! * [`collision`]: the spatial hash of Nylén et al. 2020 and the collision kernels built on
//!   it (mesh collider, self-collision pairs, intersection tests, quality metrics).
//! * [`io`]: triangle meshes from OBJ, PLY and glTF (skinned animation included) and the
//!   Point Cache 2 vertex-animation format.
//!
//! The `tailor` Python module (crate `tailor-py`) is a thin layer over this crate.

pub mod collision;
pub mod error;
pub mod io;
pub mod mesh;
pub mod pattern;
pub mod solver;

#[cfg(test)]
mod test_util;

pub use error::{Result, TailorError};
