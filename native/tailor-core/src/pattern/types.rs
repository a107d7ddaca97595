//! The pattern data model shared by every reader and by triangulation.
//!
//! Coordinates are in metres in the piece's own 2D frame (x to the right, y up). Outlines are
//! closed polylines stored without repeating the first point, counter-clockwise; holes are
//! clockwise. Curves are already flattened by the reader.

use serde::{Deserialize, Serialize};

/// A 2D point in metres.
pub type Point2 = [f64; 2];

/// Where a piece sits around the body: a rigid placement of its 2D frame in 3D (metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Placement {
    /// Translation of the piece's 2D origin, metres.
    pub translation: [f64; 3],
    /// Rotation as XYZ Euler angles in degrees (GarmentCode's convention).
    pub rotation_deg: [f64; 3],
    /// True when the file listed the outline clockwise and the reader reversed it to the
    /// model's counter-clockwise order. The file's order carried which side faces out
    /// (GarmentCode writes back panels clockwise so that their normal points away from the
    /// body): a flipped piece faces out along its local −z axis, an unflipped one along +z.
    #[serde(default)]
    pub flipped: bool,
}

/// A marked run of outline vertices, used to name the edges that a stitch joins.
/// `start..=end` indexes `Piece::outline`, walking forward (counter-clockwise) and wrapping.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutlineSpan {
    pub start: usize,
    pub end: usize,
}

/// One pattern piece.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Piece {
    pub name: String,
    /// Closed outer boundary, counter-clockwise, metres; no repeated closing point.
    pub outline: Vec<Point2>,
    /// Indices into `outline` that must stay vertices (corners of the drawn outline, notches).
    pub fixed_vertices: Vec<usize>,
    /// Holes (clockwise closed loops).
    pub holes: Vec<Vec<Point2>>,
    /// Internal lines (open polylines) that the triangulation must respect.
    pub internal_lines: Vec<Vec<Point2>>,
    /// Notch positions on the outline.
    pub notches: Vec<Point2>,
    /// Grain line (start, end), if the file has one.
    pub grain: Option<[Point2; 2]>,
    /// 3D placement, if the file gives one (GarmentCode does).
    pub placement: Option<Placement>,
    /// Named edges (GarmentCode edge index -> outline span), used to resolve stitches.
    pub edges: Vec<OutlineSpan>,
}

/// One side of a stitch: an edge of a piece.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StitchSide {
    pub piece: usize,
    pub edge: usize,
}

/// A stitch from the pattern file (GarmentCode): two piece edges to be sewn together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Stitch {
    pub a: StitchSide,
    pub b: StitchSide,
    /// Whether B's edge is walked clockwise (against A's, which is walked counter-clockwise)
    /// so that the two walks meet point for point. The file decides, not the placement:
    /// GarmentCode sews A's start to B's end in the file's vertex order (right side to right
    /// side) unless the stitch is marked `"right_wrong"`; see [`garmentcode`](super::garmentcode).
    pub b_clockwise: bool,
}

/// A whole pattern as read from one file (one size of a graded nest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pattern {
    /// The file it was read from (for error messages and provenance).
    pub source: String,
    pub pieces: Vec<Piece>,
    pub stitches: Vec<Stitch>,
    /// The sizes the file offers (empty when it is not graded).
    pub sizes: Vec<String>,
    /// The size that was imported, if the file is graded.
    pub size: Option<String>,
}
