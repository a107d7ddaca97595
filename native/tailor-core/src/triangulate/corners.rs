//! Input corners: where the piece's own geometry forces an angle, so the minimum-angle promise
//! of [`TriangulateOptions::min_angle_deg`] cannot hold there.
//!
//! An *input corner* is a point where two constraint segments of the piece meet (outline, hole
//! or internal-line segments, with the internal lines as the mesher attaches them), and its
//! angle is the angle between two such segments that are neighbours around the point, on the
//! side that lies inside the piece: a sharp outline vertex, a dart tip, an internal line meeting
//! the outline at a slant. Every triangle that has that point as a vertex and lies in that wedge
//! has its angle there at most the corner's angle. Such a triangle is excused; any other angle
//! below the minimum is a defect of the mesher ([`unexcused_angles`]).

use std::collections::HashMap;

use super::options::TriangulateOptions;
use super::resample::{dist, inside};
use super::PieceMesh;
use crate::pattern::{Piece, Point2};

/// One input corner: its point and the angles (degrees) of the wedges inside the piece there.
#[derive(Debug, Clone, PartialEq)]
pub struct InputCorner {
    pub point: Point2,
    pub angles_deg: Vec<f64>,
}

/// The input corners of `piece` sharper than `below_deg` (see the module docs).
pub fn input_corners(piece: &Piece, options: &TriangulateOptions, below_deg: f64) -> Vec<InputCorner> {
    let piece = super::lines::attach_lines(piece, options).0;
    // Segments of the closed loops, split where an internal line ends on them.
    let ends: Vec<Point2> = piece.internal_lines.iter().flat_map(|l| [l[0], l[l.len() - 1]]).collect();
    let mut segments: Vec<[Point2; 2]> = Vec::new();
    for lp in std::iter::once(&piece.outline).chain(&piece.holes) {
        let m = lp.len();
        for i in 0..m {
            let (a, b) = (lp[i], lp[(i + 1) % m]);
            let mut cuts: Vec<(f64, Point2)> = ends
                .iter()
                .filter_map(|&e| {
                    let (t, d) = super::resample::segment_projection(a, b, e);
                    (d <= 1e-9 && t > 0.0 && t < 1.0 && dist(a, e) > 1e-12 && dist(b, e) > 1e-12).then_some((t, e))
                })
                .collect();
            cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut prev = a;
            for (_, c) in cuts {
                segments.push([prev, c]);
                prev = c;
            }
            segments.push([prev, b]);
        }
    }
    for l in &piece.internal_lines {
        segments.extend(l.windows(2).map(|w| [w[0], w[1]]));
    }
    segments.retain(|[a, b]| dist(*a, *b) > 1e-12);
    let key = |p: Point2| ((p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64);
    let mut at: HashMap<(i64, i64), (Point2, Vec<f64>)> = HashMap::new();
    for &[a, b] in &segments {
        for (p, q) in [(a, b), (b, a)] {
            let e = at.entry(key(p)).or_insert((p, Vec::new()));
            e.1.push((q[1] - p[1]).atan2(q[0] - p[0]));
        }
    }
    let mut out = Vec::new();
    let mut keys: Vec<_> = at.keys().copied().collect();
    keys.sort_unstable();
    for k in keys {
        let (p, dirs) = &at[&k];
        let mut dirs = dirs.clone();
        dirs.sort_by(f64::total_cmp);
        dirs.dedup_by(|b, a| (*b - *a).abs() < 1e-12);
        if dirs.len() < 2 {
            continue;
        }
        let mut angles = Vec::new();
        for i in 0..dirs.len() {
            let (d0, d1) = (dirs[i], if i + 1 < dirs.len() { dirs[i + 1] } else { dirs[0] + std::f64::consts::TAU });
            let gap = d1 - d0;
            if gap.to_degrees() >= below_deg {
                continue;
            }
            // Is this wedge inside the piece? Probe along its bisector.
            let mid = 0.5 * (d0 + d1);
            let r = 1e-6 * options.edge_length.max(1e-3);
            let probe = [p[0] + r * mid.cos(), p[1] + r * mid.sin()];
            if inside(&piece.outline, probe) && !piece.holes.iter().any(|h| inside(h, probe)) {
                angles.push(gap.to_degrees());
            }
        }
        if !angles.is_empty() {
            out.push(InputCorner { point: *p, angles_deg: angles });
        }
    }
    out
}

/// The sharpest input corner of `piece` (degrees; 180 when it has none below 180).
pub fn sharpest_input_corner_deg(piece: &Piece, options: &TriangulateOptions) -> f64 {
    input_corners(piece, options, 180.0).iter().flat_map(|c| c.angles_deg.iter().copied()).fold(180.0, f64::min)
}

/// The triangle angles of `mesh` (triangle index, angle in degrees) below
/// `options.min_angle_deg` that no input corner of `piece` explains: the angle's vertex is not
/// an input corner, or the angle is larger than every wedge of that corner (allowing 1e-3° for
/// the rest shape's f32 rounding).
pub fn unexcused_angles(mesh: &PieceMesh, piece: &Piece, options: &TriangulateOptions) -> Vec<(usize, f64)> {
    let slack = 1e-3;
    let limit = options.min_angle_deg - slack;
    let corners = input_corners(piece, options, options.min_angle_deg);
    let mut out = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let p = tri.map(|v| {
            let r = mesh.rest[v as usize];
            [r[0] as f64, r[1] as f64]
        });
        for k in 0..3 {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            let ang = (u[0] * v[1] - u[1] * v[0]).abs().atan2(u[0] * v[0] + u[1] * v[1]).to_degrees();
            if ang >= limit {
                continue;
            }
            let excused = corners.iter().any(|c| {
                dist(c.point, a) <= 1e-6 * options.edge_length.max(1.0)
                    && c.angles_deg.iter().any(|&w| ang <= w + slack)
            });
            if !excused {
                out.push((t, ang));
            }
        }
    }
    out
}
