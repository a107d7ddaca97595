//! Pins: arc-length positions on the outline and holes that must stay vertices, and where the
//! ends of internal lines attach.

use super::options::TriangulateOptions;
use super::resample::{self, arc_lengths, project, sharp_vertices};
use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Point2};

/// Where an internal line's end sits: free inside, or on the outline / a hole at arc length s.
#[derive(Clone, Copy)]
pub(crate) enum Attach {
    Free,
    Outline(f64),
    Hole(usize, f64),
}

/// Pins of a piece, as arc lengths on the outline / each hole.
pub(crate) struct Pins {
    /// Cumulative arc length of the outline points (`m + 1` values).
    pub cum: Vec<f64>,
    pub outline: Vec<f64>,
    pub holes: Vec<Vec<f64>>,
    /// Outline points turning by at least `corner_turn_deg`.
    pub sharp: Vec<usize>,
    /// Arc length of each notch, when within `h/2` of the outline.
    pub notches: Vec<Option<f64>>,
    pub line_ends: Vec<[Attach; 2]>,
}

/// Gathers the pins: fixed vertices, span ends, sharp vertices, notches, attached line ends.
/// `origin[k]` is the index in the input piece of internal line `k` (for error messages).
pub(crate) fn gather(piece: &Piece, options: &TriangulateOptions, snap: f64, origin: &[usize]) -> Result<Pins> {
    let (outline, h) = (&piece.outline, options.edge_length);
    let m = outline.len();
    let cum = arc_lengths(outline, true);
    let mut pins = Vec::new();
    let at = |i: usize, what: String| -> Result<f64> {
        if i >= m {
            return Err(TailorError::index(what, i as i64, m, "outline points"));
        }
        Ok(cum[i])
    };
    for &i in &piece.fixed_vertices {
        pins.push(at(i, format!("piece {} fixed vertex", piece.name))?);
    }
    for (k, span) in piece.edges.iter().enumerate() {
        for i in [span.start, span.end] {
            pins.push(at(i, format!("piece {} edge {k}", piece.name))?);
        }
    }
    let sharp = sharp_vertices(outline, true, options.corner_turn_deg);
    pins.extend(sharp.iter().map(|&i| cum[i]));
    let notches: Vec<Option<f64>> = piece
        .notches
        .iter()
        .map(|&p| {
            let (s, d) = project(outline, &cum, true, p);
            (d <= 0.5 * h).then_some(s)
        })
        .collect();
    pins.extend(notches.iter().flatten());

    let hole_cums: Vec<Vec<f64>> = piece.holes.iter().map(|hl| arc_lengths(hl, true)).collect();
    let mut holes: Vec<Vec<f64>> = piece
        .holes
        .iter()
        .zip(&hole_cums)
        .map(|(hl, c)| sharp_vertices(hl, true, options.corner_turn_deg).iter().map(|&i| c[i]).collect())
        .collect();
    let attach = |p: Point2| -> Attach {
        let (s, d) = project(outline, &cum, true, p);
        if d <= snap {
            return Attach::Outline(s);
        }
        for (k, hl) in piece.holes.iter().enumerate() {
            let (s, d) = project(hl, &hole_cums[k], true, p);
            if d <= snap {
                return Attach::Hole(k, s);
            }
        }
        Attach::Free
    };
    let line_ends: Vec<[Attach; 2]> =
        piece.internal_lines.iter().map(|l| [attach(l[0]), attach(l[l.len() - 1])]).collect();
    check_lines_inside(piece, &line_ends, snap, origin)?;
    for a in line_ends.iter().flatten() {
        match *a {
            Attach::Outline(s) => pins.push(s),
            Attach::Hole(k, s) => holes[k].push(s),
            Attach::Free => {}
        }
    }
    Ok(Pins { cum, outline: pins, holes, sharp, notches, line_ends })
}

/// Internal lines must stay inside the piece: every point not snapped to the outline or a hole
/// strictly inside, and no segment crossing the outline or a hole.
fn check_lines_inside(piece: &Piece, ends: &[[Attach; 2]], snap: f64, origin: &[usize]) -> Result<()> {
    let loops: Vec<&Vec<Point2>> = std::iter::once(&piece.outline).chain(&piece.holes).collect();
    for (k, line) in piece.internal_lines.iter().enumerate() {
        let err = |what: &str| {
            TailorError::shape(
                format!("piece {}", piece.name),
                format!("internal line {} {what}", origin.get(k).copied().unwrap_or(k)),
            )
        };
        for (j, &p) in line.iter().enumerate() {
            let snapped = (j == 0 && !matches!(ends[k][0], Attach::Free))
                || (j + 1 == line.len() && !matches!(ends[k][1], Attach::Free));
            let inside_piece =
                resample::inside(&piece.outline, p) && !piece.holes.iter().any(|h| resample::inside(h, p));
            if !snapped && !inside_piece {
                return Err(err(&format!("leaves the piece at point {j} ({:.4}, {:.4})", p[0], p[1])));
            }
        }
        for w in line.windows(2) {
            for lp in &loops {
                for i in 0..lp.len() {
                    if segments_cross(w[0], w[1], lp[i], lp[(i + 1) % lp.len()], snap) {
                        return Err(err("crosses the outline or a hole"));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Proper crossing of segments ab and cd: each strictly separates the other's ends by more
/// than `tol` (so touching at an end is not a crossing).
fn segments_cross(a: Point2, b: Point2, c: Point2, d: Point2, tol: f64) -> bool {
    let side = |p: Point2, q: Point2, r: Point2| {
        let l = resample::dist(p, q).max(f64::MIN_POSITIVE);
        ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / l
    };
    let opposite = |x: f64, y: f64| (x > tol && y < -tol) || (x < -tol && y > tol);
    opposite(side(a, b, c), side(a, b, d)) && opposite(side(c, d, a), side(c, d, b))
}
