//! SVG geometry to flattened subpaths in user units: path data (every command, absolute and
//! relative, with smooth-curve reflection and arcs) and the basic shapes.

use crate::pattern::{flatten, Point2};
use svgtypes::{PathParser, PathSegment};

/// A flattened subpath in user units.
#[derive(Debug, Clone)]
pub struct SubPath {
    pub points: Vec<Point2>,
    pub closed: bool,
}

/// Upper bound on path segments per element, so a pathological `d` cannot run away.
const MAX_SEGMENTS: usize = 200_000;

/// Flattens path data. On a syntax error the SVG rules say to render up to the error; we
/// instead return the message so the user learns the file is damaged.
pub fn parse_path(d: &str, tol: f64) -> Result<Vec<SubPath>, String> {
    let mut subs: Vec<SubPath> = Vec::new();
    let mut cur: Vec<Point2> = Vec::new();
    let (mut pos, mut start) = ([0.0, 0.0], [0.0, 0.0]);
    // Last control point of a cubic / quadratic, for S and T reflection.
    let (mut last_c, mut last_q): (Option<Point2>, Option<Point2>) = (None, None);
    let finish = |cur: &mut Vec<Point2>, subs: &mut Vec<SubPath>, closed: bool| {
        if cur.len() > 1 || (closed && !cur.is_empty()) {
            subs.push(SubPath { points: std::mem::take(cur), closed });
        } else {
            cur.clear();
        }
    };
    for (count, seg) in PathParser::from(d).enumerate() {
        if count > MAX_SEGMENTS {
            return Err(format!("more than {MAX_SEGMENTS} path segments"));
        }
        let seg = seg.map_err(|e| format!("path data: {e}"))?;
        let rel = |abs: bool, x: f64, y: f64, pos: Point2| if abs { [x, y] } else { [pos[0] + x, pos[1] + y] };
        let (mut nc, mut nq) = (None, None);
        match seg {
            PathSegment::MoveTo { abs, x, y } => {
                finish(&mut cur, &mut subs, false);
                pos = rel(abs, x, y, pos);
                start = pos;
                cur.push(pos);
            }
            PathSegment::LineTo { abs, x, y } => {
                pos = rel(abs, x, y, pos);
                push_start(&mut cur, start);
                cur.push(pos);
            }
            PathSegment::HorizontalLineTo { abs, x } => {
                pos = [if abs { x } else { pos[0] + x }, pos[1]];
                push_start(&mut cur, start);
                cur.push(pos);
            }
            PathSegment::VerticalLineTo { abs, y } => {
                pos = [pos[0], if abs { y } else { pos[1] + y }];
                push_start(&mut cur, start);
                cur.push(pos);
            }
            PathSegment::CurveTo { abs, x1, y1, x2, y2, x, y } => {
                let (c1, c2, p) = (rel(abs, x1, y1, pos), rel(abs, x2, y2, pos), rel(abs, x, y, pos));
                push_start(&mut cur, start);
                flatten::cubic(pos, c1, c2, p, tol, &mut cur);
                nc = Some(c2);
                pos = p;
            }
            PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                let c1 = last_c.map(|c| [2.0 * pos[0] - c[0], 2.0 * pos[1] - c[1]]).unwrap_or(pos);
                let (c2, p) = (rel(abs, x2, y2, pos), rel(abs, x, y, pos));
                push_start(&mut cur, start);
                flatten::cubic(pos, c1, c2, p, tol, &mut cur);
                nc = Some(c2);
                pos = p;
            }
            PathSegment::Quadratic { abs, x1, y1, x, y } => {
                let (c, p) = (rel(abs, x1, y1, pos), rel(abs, x, y, pos));
                push_start(&mut cur, start);
                flatten::quadratic(pos, c, p, tol, &mut cur);
                nq = Some(c);
                pos = p;
            }
            PathSegment::SmoothQuadratic { abs, x, y } => {
                let c = last_q.map(|c| [2.0 * pos[0] - c[0], 2.0 * pos[1] - c[1]]).unwrap_or(pos);
                let p = rel(abs, x, y, pos);
                push_start(&mut cur, start);
                flatten::quadratic(pos, c, p, tol, &mut cur);
                nq = Some(c);
                pos = p;
            }
            PathSegment::EllipticalArc { abs, rx, ry, x_axis_rotation, large_arc, sweep, x, y } => {
                let p = rel(abs, x, y, pos);
                push_start(&mut cur, start);
                flatten::svg_arc(pos, p, rx, ry, x_axis_rotation, large_arc, sweep, tol, &mut cur);
                pos = p;
            }
            PathSegment::ClosePath { .. } => {
                if !cur.is_empty() {
                    finish(&mut cur, &mut subs, true);
                }
                pos = start;
            }
        }
        last_c = nc;
        last_q = nq;
        if cur.len() > MAX_SEGMENTS * 4 {
            return Err("path flattens to too many points".into());
        }
    }
    finish(&mut cur, &mut subs, false);
    Ok(subs)
}

/// After a `Z`, drawing continues from the subpath start without a new `M`.
fn push_start(cur: &mut Vec<Point2>, start: Point2) {
    if cur.is_empty() {
        cur.push(start);
    }
}

/// `<rect>` with optional rounded corners (rx/ry clamped to half the sides, as SVG says).
pub fn rect(x: f64, y: f64, w: f64, h: f64, rx: Option<f64>, ry: Option<f64>, tol: f64) -> SubPath {
    let (rx, ry) = match (rx, ry) {
        (None, None) => (0.0, 0.0),
        (Some(r), None) | (None, Some(r)) => (r, r),
        (Some(a), Some(b)) => (a, b),
    };
    let (rx, ry) = (rx.clamp(0.0, w / 2.0), ry.clamp(0.0, h / 2.0));
    if rx <= 0.0 || ry <= 0.0 {
        return SubPath { points: vec![[x, y], [x + w, y], [x + w, y + h], [x, y + h]], closed: true };
    }
    let mut p = vec![[x + rx, y]];
    let corners = [
        ([x + w - rx, y], [x + w, y + ry]),
        ([x + w, y + h - ry], [x + w - rx, y + h]),
        ([x + rx, y + h], [x, y + h - ry]),
        ([x, y + ry], [x + rx, y]),
    ];
    for (line_end, arc_end) in corners {
        p.push(line_end);
        flatten::svg_arc(line_end, arc_end, rx, ry, 0.0, false, true, tol, &mut p);
    }
    p.pop();
    SubPath { points: p, closed: true }
}

/// `<ellipse>` / `<circle>`.
pub fn ellipse(cx: f64, cy: f64, rx: f64, ry: f64, tol: f64) -> SubPath {
    let mut p = vec![[cx + rx, cy]];
    flatten::ellipse_arc([cx, cy], [rx, ry], 0.0, 0.0, 2.0 * std::f64::consts::PI, tol, &mut p);
    p.pop();
    SubPath { points: p, closed: true }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_and_smooth_commands() {
        let s = parse_path("m10 10 h10 v10 H10 z M0 0 l1 0 0 1 -1 0 Z", 0.01).unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].points, vec![[10.0, 10.0], [20.0, 10.0], [20.0, 20.0], [10.0, 20.0]]);
        assert!(s[0].closed && s[1].closed);
        let c = parse_path("M0 0 C 0 1 1 1 1 0 S 2 -1 2 0 T 3 0 Q 4 1 5 0 t 1 0 A 1 1 0 0 1 8 0", 0.001).unwrap();
        assert_eq!(*c[0].points.last().unwrap(), [8.0, 0.0]);
        assert!(!c[0].closed);
        assert!(parse_path("M 0 0 L x", 0.1).is_err());
    }
}
