//! 2D sewing patterns: pieces as closed outlines in metres, read from pattern files.
//!
//! The readers (DXF, SVG, GarmentCode JSON) each produce a [`Pattern`]; triangulation and
//! seams work on [`Piece`]s and know nothing of the file they came from.

mod types;

pub use types::*;
