//! GarmentCode stitches as seams.
//!
//! A stitch names two piece edges ([`OutlineSpan`]s, each running counter-clockwise from
//! `start` to `end` along its outline). Side A is A's span walked counter-clockwise. Side B is
//! B's span walked either counter-clockwise (`b.start → b.end`) or clockwise (`b.end →
//! b.start`); the file does not say which. Both spans are sampled at the same [`SAMPLES`]
//! fractions of their arc length, placed in 3D, and the direction of B with the smaller
//! `Σ_k |A(t_k) − B(t_k)|` wins, because GarmentCode places panels around the body with sewn
//! edges facing each other. Whole curves, not just endpoints, decide: edges whose ends are
//! equidistant crosswise (a dart, a sleeve cap opposite an armhole) are still told apart by
//! their middles. Without placements, B runs clockwise: two counter-clockwise panels sewn edge
//! to edge walk their shared edge in opposite senses.

use super::super::placement::euler_xyz_intrinsic;
use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Placement, Point2, Stitch};
use crate::seam::{Direction, Seam, SeamMode, SeamSide};

fn world(p: Point2, placement: Option<&Placement>) -> [f64; 3] {
    match placement {
        None => [p[0], p[1], 0.0],
        Some(pl) => {
            let r = euler_xyz_intrinsic(pl.rotation_deg);
            [0, 1, 2].map(|i| r[i][0] * p[0] + r[i][1] * p[1] + pl.translation[i])
        }
    }
}

/// Samples per span used to choose the direction.
pub const SAMPLES: usize = 9;

/// `SAMPLES` points along `outline` from index `start` counter-clockwise to index `end`
/// (wrapping), evenly spaced by arc length.
fn span_samples(outline: &[Point2], start: usize, end: usize) -> Vec<Point2> {
    let n = outline.len();
    let mut pts = vec![outline[start]];
    let mut i = start;
    while i != end && pts.len() <= n {
        i = (i + 1) % n;
        pts.push(outline[i]);
    }
    let seg: Vec<f64> =
        pts.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt()).collect();
    let total: f64 = seg.iter().sum();
    (0..SAMPLES)
        .map(|k| {
            let mut target = total * k as f64 / (SAMPLES - 1) as f64;
            for (j, &l) in seg.iter().enumerate() {
                if target <= l || j + 1 == seg.len() {
                    let s = if l > 0.0 { (target / l).clamp(0.0, 1.0) } else { 0.0 };
                    return [pts[j][0] + s * (pts[j + 1][0] - pts[j][0]), pts[j][1] + s * (pts[j + 1][1] - pts[j][1])];
                }
                target -= l;
            }
            pts[0]
        })
        .collect()
}

fn d3(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The seam for stitch number `index` of a pattern whose pieces are `pieces` (with the 3D
/// placement of each, `placements[i]`, when there is one). `mode` is decided by the caller
/// (equal when the triangulated sides have the same vertex count).
pub fn stitch_seam(
    index: usize,
    stitch: &Stitch,
    pieces: &[Piece],
    placements: &[Option<Placement>],
    mode: SeamMode,
) -> Result<Seam> {
    let name = |p: usize| pieces.get(p).map(|x| x.name.as_str()).unwrap_or("?");
    let seam_name = format!(
        "stitch {index}: {} edge {} - {} edge {}",
        name(stitch.a.piece),
        stitch.a.edge,
        name(stitch.b.piece),
        stitch.b.edge
    );
    let span = |piece: usize, edge: usize| -> Result<(Point2, Point2, Vec<Point2>)> {
        let p = pieces.get(piece).ok_or_else(|| TailorError::InvalidSeam {
            seam: seam_name.clone(),
            reason: format!("piece {piece} does not exist ({} pieces)", pieces.len()),
        })?;
        let s = p.edges.get(edge).ok_or_else(|| TailorError::InvalidSeam {
            seam: seam_name.clone(),
            reason: format!("piece {} has no edge {edge} ({} edges)", p.name, p.edges.len()),
        })?;
        match (p.outline.get(s.start), p.outline.get(s.end)) {
            (Some(&a), Some(&b)) => Ok((a, b, span_samples(&p.outline, s.start, s.end))),
            _ => Err(TailorError::InvalidSeam {
                seam: seam_name.clone(),
                reason: format!("piece {} edge {edge} points past its outline", p.name),
            }),
        }
    };
    let (a0, a1, sa) = span(stitch.a.piece, stitch.a.edge)?;
    let (b0, b1, sb) = span(stitch.b.piece, stitch.b.edge)?;
    let (pa, pb) = (
        placements.get(stitch.a.piece).and_then(Option::as_ref),
        placements.get(stitch.b.piece).and_then(Option::as_ref),
    );
    let reversed = match (pa, pb) {
        (Some(_), Some(_)) => {
            let wa: Vec<[f64; 3]> = sa.iter().map(|&p| world(p, pa)).collect();
            let wb: Vec<[f64; 3]> = sb.iter().map(|&p| world(p, pb)).collect();
            let forward: f64 = wa.iter().zip(&wb).map(|(&x, &y)| d3(x, y)).sum();
            let backward: f64 = wa.iter().zip(wb.iter().rev()).map(|(&x, &y)| d3(x, y)).sum();
            backward <= forward
        }
        _ => true,
    };
    let b = if reversed {
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
