//! Seam validation: every error names the seam and says what is wrong with which side.
//!
//! A side is valid when it has at least two vertices, all on its piece's contour, each step
//! going to the next contour vertex in the side's one direction (consistent orientation), and
//! no vertex twice. When both sides are on the same piece (a dart, a tube) they may share only
//! a vertex that is sewn to itself: both first vertices or both last vertices (a dart tip).
//! In [`SeamMode::Equal`] both sides must have the same vertex count.

use std::collections::HashSet;

use super::model::SeamMode;
use super::paths::{ContourPath, Direction};
use crate::error::{Result, TailorError};
use crate::triangulate::PieceMesh;

fn invalid(seam: &str, reason: String) -> TailorError {
    TailorError::InvalidSeam { seam: seam.to_string(), reason }
}

/// A path from explicitly chosen vertices (for example a selection made in Blender), checked to
/// be consecutive contour vertices in one direction.
pub fn path_from_vertices(seam: &str, side: &str, mesh: &PieceMesh, vertices: &[u32]) -> Result<ContourPath> {
    let mut pos_of = vec![usize::MAX; mesh.rest.len()];
    for (i, &v) in mesh.contour.iter().enumerate() {
        pos_of[v as usize] = i;
    }
    let mut positions = Vec::with_capacity(vertices.len());
    for (k, &v) in vertices.iter().enumerate() {
        match pos_of.get(v as usize) {
            Some(&p) if p != usize::MAX => positions.push(p),
            _ => {
                return Err(invalid(
                    seam,
                    format!(
                        "side {side}: vertex {v} (number {k} of the side) is not on the contour of piece {}",
                        mesh.name
                    ),
                ))
            }
        }
    }
    let n = mesh.contour.len();
    let direction = match positions.as_slice() {
        [a, b, ..] if (a + 1) % n == *b => Direction::Ccw,
        _ => Direction::Cw,
    };
    let path = ContourPath { positions, direction };
    check_side(seam, side, mesh, &path)?;
    Ok(path)
}

/// Checks one side: length, range, steps in one direction, no repeated vertex.
pub fn check_side(seam: &str, side: &str, mesh: &PieceMesh, path: &ContourPath) -> Result<()> {
    let n = mesh.contour.len();
    if path.len() < 2 {
        return Err(invalid(seam, format!("side {side} has {} vertex(es); a seam side needs at least 2", path.len())));
    }
    if let Some(&p) = path.positions.iter().find(|&&p| p >= n) {
        return Err(invalid(
            seam,
            format!("side {side}: contour position {p} is off the contour of piece {} ({n} vertices)", mesh.name),
        ));
    }
    for (k, w) in path.positions.windows(2).enumerate() {
        let expected = match path.direction {
            Direction::Ccw => (w[0] + 1) % n,
            Direction::Cw => (w[0] + n - 1) % n,
        };
        if w[1] != expected {
            return Err(invalid(
                seam,
                format!(
                    "side {side}: vertices {} and {} (steps {k}, {}) are not consecutive {:?} on the contour of piece {}",
                    mesh.contour[w[0]],
                    mesh.contour[w[1]],
                    k + 1,
                    path.direction,
                    mesh.name
                ),
            ));
        }
    }
    let mut seen = HashSet::with_capacity(path.len());
    for &p in &path.positions {
        if !seen.insert(p) {
            return Err(invalid(seam, format!("side {side}: vertex {} is used twice", mesh.contour[p])));
        }
    }
    Ok(())
}

/// Checks a whole seam; `same_piece` when both sides are on one piece.
pub fn validate_seam(
    seam: &str,
    mesh_a: &PieceMesh,
    a: &ContourPath,
    mesh_b: &PieceMesh,
    b: &ContourPath,
    same_piece: bool,
    mode: SeamMode,
) -> Result<()> {
    check_side(seam, "A", mesh_a, a)?;
    check_side(seam, "B", mesh_b, b)?;
    if same_piece {
        let allowed: HashSet<usize> =
            [(a.first() == b.first()).then_some(a.first()), (a.last() == b.last()).then_some(a.last())]
                .into_iter()
                .flatten()
                .collect();
        let on_a: HashSet<usize> = a.positions.iter().copied().collect();
        if let Some(&p) = b.positions.iter().find(|p| on_a.contains(p) && !allowed.contains(p)) {
            return Err(invalid(
                seam,
                format!("vertex {} of piece {} is used by both sides", mesh_a.contour[p], mesh_a.name),
            ));
        }
    }
    if mode == SeamMode::Equal && a.len() != b.len() {
        return Err(invalid(
            seam,
            format!(
                "one-to-one (equal) seam with {} vertices on side A ({}) but {} on side B ({}); use the unequal mode to sew different counts",
                a.len(),
                mesh_a.name,
                b.len(),
                mesh_b.name
            ),
        ));
    }
    Ok(())
}
