//! GarmentCode stitches as seams.
//!
//! A stitch names two piece edges ([`OutlineSpan`](crate::pattern::OutlineSpan)s, each running
//! counter-clockwise from `start` to `end` along its outline). Side A is A's span walked
//! counter-clockwise; side B is B's span walked clockwise (`b.end → b.start`) or
//! counter-clockwise as the file says ([`Stitch::b_clockwise`], decided by the reader from
//! GarmentCode's sewing convention). The pieces' 3D placement plays no part: it is where the
//! pieces start, not how they are sewn, and a placement that holds two edges crosswise (a hood
//! beside the head, its neckline's back corner nearer the shoulder) must not turn a seam round.

use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Point2, Stitch};
use crate::seam::{Direction, Seam, SeamMode, SeamSide};

/// The seam for stitch number `index` of a pattern whose pieces are `pieces`. `mode` is
/// decided by the caller (equal when the triangulated sides have the same vertex count).
pub fn stitch_seam(index: usize, stitch: &Stitch, pieces: &[Piece], mode: SeamMode) -> Result<Seam> {
    let name = |p: usize| pieces.get(p).map(|x| x.name.as_str()).unwrap_or("?");
    let seam_name = format!(
        "stitch {index}: {} edge {} - {} edge {}",
        name(stitch.a.piece),
        stitch.a.edge,
        name(stitch.b.piece),
        stitch.b.edge
    );
    let ends = |piece: usize, edge: usize| -> Result<(Point2, Point2)> {
        let p = pieces.get(piece).ok_or_else(|| TailorError::InvalidSeam {
            seam: seam_name.clone(),
            reason: format!("piece {piece} does not exist ({} pieces)", pieces.len()),
        })?;
        let s = p.edges.get(edge).ok_or_else(|| TailorError::InvalidSeam {
            seam: seam_name.clone(),
            reason: format!("piece {} has no edge {edge} ({} edges)", p.name, p.edges.len()),
        })?;
        match (p.outline.get(s.start), p.outline.get(s.end)) {
            (Some(&a), Some(&b)) => Ok((a, b)),
            _ => Err(TailorError::InvalidSeam {
                seam: seam_name.clone(),
                reason: format!("piece {} edge {edge} points past its outline", p.name),
            }),
        }
    };
    let (a0, a1) = ends(stitch.a.piece, stitch.a.edge)?;
    let (b0, b1) = ends(stitch.b.piece, stitch.b.edge)?;
    let b = if stitch.b_clockwise {
        SeamSide { piece: stitch.b.piece, start: b1, end: b0, direction: Direction::Cw }
    } else {
        SeamSide { piece: stitch.b.piece, start: b0, end: b1, direction: Direction::Ccw }
    };
    Ok(Seam {
        name: seam_name,
        a: SeamSide { piece: stitch.a.piece, start: a0, end: a1, direction: Direction::Ccw },
        b,
        mode,
        stiffness: 1.0,
        bend_stiffness: 1.0,
    })
}
