//! Paths along a piece's contour: the picking steps of the paper's manual seam tool (Sec. 4).
//!
//! A contour is a closed loop of `N` vertices, counter-clockwise. A path is a run of contour
//! *positions* (indices into [`PieceMesh::contour`]) walked in one [`Direction`]; its vertices
//! are `contour[position]`. The paper's workflow maps onto these functions:
//!
//! 1. pick `a1`: [`nearest_contour_position`] to the cursor;
//! 2. hover: [`shortest_path`] from `a1` to the position nearest the cursor;
//! 3. click: that path fixes `an` and the vertex count `n`;
//! 4. pick `b1`: [`nearest_contour_position`] on piece B;
//! 5. hover: of the two `n`-vertex paths from `b1` ([`candidate_paths`]), the one whose end is
//!    nearer the cursor ([`nearer_candidate`]); click fixes `bn`.

use serde::{Deserialize, Serialize};

use crate::error::{Result, TailorError};
use crate::triangulate::PieceMesh;

/// Walking direction along a contour (the contour itself is counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Direction {
    Ccw,
    Cw,
}

impl Direction {
    pub fn reversed(self) -> Self {
        match self {
            Direction::Ccw => Direction::Cw,
            Direction::Cw => Direction::Ccw,
        }
    }
}

/// A run of contour positions walked in one direction.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ContourPath {
    pub positions: Vec<usize>,
    pub direction: Direction,
}

impl ContourPath {
    /// The mesh vertices of the path, in order.
    pub fn vertices(&self, mesh: &PieceMesh) -> Vec<u32> {
        self.positions.iter().map(|&p| mesh.contour[p]).collect()
    }
    pub fn len(&self) -> usize {
        self.positions.len()
    }
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
    /// First contour position (panics on an empty path; validated paths have two or more).
    pub fn first(&self) -> usize {
        self.positions[0]
    }
    /// Last contour position (panics on an empty path).
    pub fn last(&self) -> usize {
        self.positions[self.positions.len() - 1]
    }
    /// Rest (2D) arc length of the path, metres.
    pub fn length(&self, mesh: &PieceMesh) -> f64 {
        self.positions.windows(2).map(|w| dist(mesh.contour_point(w[0]), mesh.contour_point(w[1]))).sum()
    }
}

/// The contour position whose rest point is nearest `point` (metres, piece frame).
pub fn nearest_contour_position(mesh: &PieceMesh, point: [f32; 2]) -> usize {
    (0..mesh.contour.len())
        .min_by(|&a, &b| dist(mesh.contour_point(a), point).total_cmp(&dist(mesh.contour_point(b), point)))
        .unwrap_or(0)
}

/// The contour position whose 3D position is nearest `point` (for picking in the viewport);
/// `positions` are the piece's current vertex positions.
pub fn nearest_contour_position_3d(mesh: &PieceMesh, positions: &[[f32; 3]], point: [f32; 3]) -> Result<usize> {
    if positions.len() != mesh.rest.len() {
        return Err(TailorError::shape(
            format!("piece {}", mesh.name),
            format!("{} positions for {} vertices", positions.len(), mesh.rest.len()),
        ));
    }
    let d = |p: usize| {
        let q = positions[mesh.contour[p] as usize];
        (0..3).map(|k| (q[k] - point[k]).powi(2)).sum::<f32>()
    };
    Ok((0..mesh.contour.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).unwrap_or(0))
}

/// The path of `n` positions starting at `start` walking `direction`.
pub fn path_of_n(mesh: &PieceMesh, start: usize, n: usize, direction: Direction) -> Result<ContourPath> {
    let len = mesh.contour.len();
    check_position(mesh, start)?;
    if n == 0 || n > len {
        return Err(TailorError::setting("seam vertex count", n, format!("must be in 1..={len} (the contour size)")));
    }
    let positions = (0..n)
        .map(|k| match direction {
            Direction::Ccw => (start + k) % len,
            Direction::Cw => (start + len - k % len) % len,
        })
        .collect();
    Ok(ContourPath { positions, direction })
}

/// The path from `from` to `to` walking `direction` (both ends included).
pub fn path_between(mesh: &PieceMesh, from: usize, to: usize, direction: Direction) -> Result<ContourPath> {
    check_position(mesh, from)?;
    check_position(mesh, to)?;
    let len = mesh.contour.len();
    let steps = match direction {
        Direction::Ccw => (to + len - from) % len,
        Direction::Cw => (from + len - to) % len,
    };
    path_of_n(mesh, from, steps + 1, direction)
}

/// The counter-clockwise path along named edge `span` of the piece (`Piece::edges[span]`),
/// the side of a stitch read from a pattern file.
pub fn span_path(mesh: &PieceMesh, span: usize) -> Result<ContourPath> {
    let [s, e] = *mesh.span_map.get(span).ok_or_else(|| {
        TailorError::index(format!("piece {} edges", mesh.name), span as i64, mesh.span_map.len(), "named edges")
    })?;
    path_between(mesh, s, e, Direction::Ccw)
}

/// The shorter (by rest arc length) of the two contour paths from `from` to `to` (steps 2-3);
/// counter-clockwise on a tie.
pub fn shortest_path(mesh: &PieceMesh, from: usize, to: usize) -> Result<ContourPath> {
    check_position(mesh, from)?;
    check_position(mesh, to)?;
    let (p, total) = (&mesh.contour_param, mesh.contour_length);
    let ccw = (p[to] - p[from]).rem_euclid(total);
    let dir = if ccw <= total - ccw { Direction::Ccw } else { Direction::Cw };
    path_between(mesh, from, to, dir)
}

/// The two `n`-vertex paths from `b1`: `[counter-clockwise, clockwise]` (step 5).
pub fn candidate_paths(mesh: &PieceMesh, b1: usize, n: usize) -> Result<[ContourPath; 2]> {
    Ok([path_of_n(mesh, b1, n, Direction::Ccw)?, path_of_n(mesh, b1, n, Direction::Cw)?])
}

/// Of the two `n`-vertex paths from `b1`, the one whose last vertex is nearer `point` (step 5;
/// counter-clockwise on a tie).
pub fn nearer_candidate(mesh: &PieceMesh, b1: usize, n: usize, point: [f32; 2]) -> Result<ContourPath> {
    let [ccw, cw] = candidate_paths(mesh, b1, n)?;
    let d = |p: &ContourPath| dist(mesh.contour_point(p.last()), point);
    Ok(if d(&ccw) <= d(&cw) { ccw } else { cw })
}

fn check_position(mesh: &PieceMesh, p: usize) -> Result<()> {
    if p >= mesh.contour.len() {
        return Err(TailorError::index(
            format!("piece {} contour", mesh.name),
            p as i64,
            mesh.contour.len(),
            "contour vertices",
        ));
    }
    Ok(())
}

pub(crate) fn dist(a: [f32; 2], b: [f32; 2]) -> f64 {
    (((a[0] - b[0]) as f64).powi(2) + ((a[1] - b[1]) as f64).powi(2)).sqrt()
}
