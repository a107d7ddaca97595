//! Input checks: a piece that cannot be meshed is an error naming the piece and the element.

use super::resample::{self, signed_area};
use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Point2};

/// Above this many estimated vertices a resolution is refused rather than exhausting memory or
/// time: half a million vertices in one piece (a 1.7 m² piece at 2 mm) is far beyond what the
/// solver runs interactively, and meshes in seconds; 4 million, the budget before, took 20 s
/// and more, and a garment with a piece of a million took 13 s to import.
pub(crate) const MAX_VERTICES: f64 = 5.0e5;

/// Checks counts, finiteness, orientation, holes inside the outline, and the vertex budget.
pub(crate) fn validate_piece(piece: &Piece, h: f64) -> Result<()> {
    let ctx = format!("piece {}", piece.name);
    let check = |what: &'static str, pts: &[Point2]| -> Result<()> {
        for (i, p) in pts.iter().enumerate() {
            for &c in p {
                if !c.is_finite() {
                    return Err(TailorError::NonFinite { context: ctx.clone(), what, index: i, value: c as f32 });
                }
            }
        }
        Ok(())
    };
    if piece.outline.len() < 3 {
        return Err(TailorError::shape(ctx, format!("the outline has {} points (3 at least)", piece.outline.len())));
    }
    check("outline point", &piece.outline)?;
    if signed_area(&piece.outline) <= 0.0 {
        return Err(TailorError::shape(ctx, "the outline is clockwise or has no area (it must be counter-clockwise)"));
    }
    for (k, hl) in piece.holes.iter().enumerate() {
        if hl.len() < 3 {
            return Err(TailorError::shape(ctx, format!("hole {k} has {} points (3 at least)", hl.len())));
        }
        check("hole point", hl)?;
        if signed_area(hl).abs() <= 1e-12 {
            return Err(TailorError::shape(ctx, format!("hole {k} has no area")));
        }
        if let Some(j) = hl.iter().position(|&p| !resample::inside(&piece.outline, p)) {
            return Err(TailorError::shape(ctx, format!("hole {k} point {j} is outside the outline")));
        }
    }
    for (k, l) in piece.internal_lines.iter().enumerate() {
        if l.len() < 2 {
            return Err(TailorError::shape(ctx, format!("internal line {k} has {} points (2 at least)", l.len())));
        }
        check("internal line point", l)?;
    }
    check("notch", &piece.notches)?;
    // Equilateral triangles of side h: about area / (√3/2 h²) vertices. The lattice is laid
    // over the bounding box, so a thin diagonal piece is bounded by that too.
    let cell = 3f64.sqrt() / 2.0 * h * h;
    let estimate = signed_area(&piece.outline) / cell;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &piece.outline {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let lattice = (hi[0] - lo[0]) * (hi[1] - lo[1]) / cell;
    // Boundary vertices come from the length of the outline, holes and lines, which the area
    // does not bound: a strip 1e9 m long and 1 mm wide has little area and 2e11 outline points.
    let length: f64 = std::iter::once(&piece.outline)
        .chain(&piece.holes)
        .map(|l| resample::arc_lengths(l, true).last().copied().unwrap_or(0.0))
        .chain(piece.internal_lines.iter().map(|l| resample::arc_lengths(l, false).last().copied().unwrap_or(0.0)))
        .sum();
    let boundary = length / h;
    if !(boundary <= MAX_VERTICES) {
        return Err(TailorError::setting(
            "edge_length",
            h,
            format!(
                "piece {}: its outline, holes and lines ({length:.3e} m) would get about {boundary:.0} vertices (at most {MAX_VERTICES:.0})",
                piece.name
            ),
        ));
    }
    if !(estimate <= MAX_VERTICES && lattice <= 10.0 * MAX_VERTICES) {
        return Err(TailorError::setting(
            "edge_length",
            h,
            format!("piece {} would get about {estimate:.0} vertices (at most {MAX_VERTICES:.0})", piece.name),
        ));
    }
    Ok(())
}
