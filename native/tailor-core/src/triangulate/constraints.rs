//! The constraint vertices and segments handed to the CDT.
//!
//! Vertex order matters: the resampled outline comes first, so outline sample `j` is vertex
//! `j` (the contour is then found from vertex 0); then the holes, then the internal lines,
//! whose attached ends reuse the outline or hole sample at their pin instead of adding a
//! second vertex at (almost) the same place.

use super::pins::Attach;
use super::resample::{arc_lengths, resample, sharp_vertices, Resampled};
use crate::pattern::{Piece, Point2};

pub(crate) struct Constraints {
    pub points: Vec<Point2>,
    /// Segments of the closed loops (outline, holes).
    pub loop_edges: Vec<[usize; 2]>,
    /// Segments of the internal lines.
    pub line_edges: Vec<[usize; 2]>,
}

/// Builds the constraints from the resampled outline and holes and the raw internal lines
/// (resampled here at `h`, keeping vertices turning by at least `turn_deg`).
pub(crate) fn build(
    piece: &Piece,
    r_out: &Resampled,
    r_holes: &[Resampled],
    line_ends: &[[Attach; 2]],
    h: f64,
    turn_deg: f64,
    eps: f64,
) -> Constraints {
    let mut points: Vec<Point2> = r_out.points.clone();
    let mut loop_edges: Vec<[usize; 2]> = Vec::new();
    let mut line_edges: Vec<[usize; 2]> = Vec::new();
    push_loop(&mut loop_edges, 0, r_out.points.len());
    let mut hole_start = Vec::new();
    for r in r_holes {
        hole_start.push(points.len());
        push_loop(&mut loop_edges, points.len(), r.points.len());
        points.extend_from_slice(&r.points);
    }
    // Free line points by position, so that lines meeting inside the piece (a dart's legs at its
    // tip, a grid of construction lines) share one vertex instead of two coinciding ones.
    let key = |p: Point2| ((p[0] / eps).round() as i64, (p[1] / eps).round() as i64);
    let mut free: std::collections::HashMap<(i64, i64), usize> = std::collections::HashMap::new();
    for (line, ends) in piece.internal_lines.iter().zip(line_ends) {
        let lp = sharp_vertices(line, false, turn_deg);
        let lc = arc_lengths(line, false);
        let r = resample(line, false, lp.iter().map(|&i| lc[i]).collect(), h, eps);
        let mut ids = Vec::with_capacity(r.points.len());
        for (j, &p) in r.points.iter().enumerate() {
            let end = if j == 0 {
                Some(ends[0])
            } else if j + 1 == r.points.len() {
                Some(ends[1])
            } else {
                None
            };
            let id = match end {
                Some(Attach::Outline(s)) => pin_point(r_out, s),
                Some(Attach::Hole(k, s)) => hole_start[k] + pin_point(&r_holes[k], s),
                _ => *free.entry(key(p)).or_insert_with(|| {
                    points.push(p);
                    points.len() - 1
                }),
            };
            ids.push(id);
        }
        for w in ids.windows(2) {
            if w[0] != w[1] {
                line_edges.push([w[0], w[1]]);
            }
        }
    }

    Constraints { points, loop_edges, line_edges }
}

fn push_loop(edges: &mut Vec<[usize; 2]>, start: usize, n: usize) {
    for i in 0..n {
        edges.push([start + i, start + (i + 1) % n]);
    }
}

/// Index (in `r.points`) of the pin nearest arc length `s`.
pub(crate) fn pin_point(r: &Resampled, s: f64) -> usize {
    let k = (0..r.pins.len()).min_by(|&a, &b| (r.pins[a] - s).abs().total_cmp(&(r.pins[b] - s).abs())).unwrap_or(0);
    r.pin_points[k]
}
