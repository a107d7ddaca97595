//! The triangulated piece, the unit that seams and the solver work on.

use serde::{Deserialize, Serialize};

use super::MeshQuality;

/// A triangulated piece: the flat rest mesh plus its outer contour, the unit of sewing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PieceMesh {
    pub name: String,
    /// Target edge length it was built with, metres.
    pub edge_length: f64,
    /// 2D rest coordinates, metres, in the piece's frame.
    pub rest: Vec<[f32; 2]>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The outer boundary loop, counter-clockwise, as vertex indices; `contour[0]` lies on the
    /// piece's first pin (its first fixed vertex, or outline point 0 when there is none).
    pub contour: Vec<u32>,
    /// Arc length along the contour from `contour[0]` to each contour vertex, metres.
    pub contour_param: Vec<f64>,
    /// Total contour length, metres.
    pub contour_length: f64,
    /// Contour positions of the corners: fixed vertices and vertices turning by at least
    /// `corner_turn_deg`, ascending.
    pub corners: Vec<usize>,
    /// Contour position of each `Piece::fixed_vertices` entry.
    pub fixed_map: Vec<usize>,
    /// Contour positions `[start, end]` of each `Piece::edges` span.
    pub span_map: Vec<[usize; 2]>,
    /// Contour position of each notch (None when it is farther than `h/2` from the outline).
    pub notch_map: Vec<Option<usize>>,
    /// Contour position nearest (by arc length) to each `Piece::outline` point; exact for pins.
    pub outline_map: Vec<usize>,
    pub quality: MeshQuality,
    /// What triangulation had to change in the piece's internal lines: one line per line
    /// clipped at the outline or dropped (see `triangulate::snap_tolerance`); empty when
    /// nothing was.
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl PieceMesh {
    /// Rest position of contour position `i` (wrapping).
    pub fn contour_point(&self, i: usize) -> [f32; 2] {
        self.rest[self.contour[i % self.contour.len()] as usize]
    }

    /// Contour position of a vertex, if it is on the contour.
    pub fn contour_position(&self, vertex: u32) -> Option<usize> {
        self.contour.iter().position(|&v| v == vertex)
    }
}
