//! Curve flattening: Béziers, circular and elliptical arcs, DXF bulges and B-splines become
//! polylines whose chords stay within a tolerance of the true curve.
//!
//! Every function appends the points after the start point (the caller already has it), so
//! consecutive segments chain without duplicates. Segment counts come from closed-form error
//! bounds rather than recursion, and are capped at [`MAX_SEGMENTS`] so that absurd input
//! (a huge radius, a tolerance of 1e-300, NaN) cannot make a reader run away.

use super::Point2;
use std::f64::consts::PI;

/// Upper bound on the segments produced for one curve.
pub const MAX_SEGMENTS: usize = 4096;

fn count(n: f64) -> usize {
    if n.is_finite() && n >= 1.0 {
        (n.ceil() as usize).min(MAX_SEGMENTS)
    } else {
        1
    }
}

fn lerp(a: Point2, b: Point2, t: f64) -> Point2 {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
}

fn norm(v: Point2) -> f64 {
    v[0].hypot(v[1])
}

/// Quadratic Bézier. The second derivative is constant (2·(p0 − 2p1 + p2)), so a uniform step
/// h deviates at most |p0 − 2p1 + p2|·h²/4 from the curve.
pub fn quadratic(p0: Point2, p1: Point2, p2: Point2, tol: f64, out: &mut Vec<Point2>) {
    let d = norm([p0[0] - 2.0 * p1[0] + p2[0], p0[1] - 2.0 * p1[1] + p2[1]]);
    let n = count((d / (4.0 * tol)).sqrt());
    for i in 1..=n {
        let t = i as f64 / n as f64;
        out.push(lerp(lerp(p0, p1, t), lerp(p1, p2, t), t));
    }
}

/// Cubic Bézier: |B''| ≤ 6·max(|p0 − 2p1 + p2|, |p1 − 2p2 + p3|), chord error ≤ |B''|·h²/8.
pub fn cubic(p0: Point2, p1: Point2, p2: Point2, p3: Point2, tol: f64, out: &mut Vec<Point2>) {
    let d1 = norm([p0[0] - 2.0 * p1[0] + p2[0], p0[1] - 2.0 * p1[1] + p2[1]]);
    let d2 = norm([p1[0] - 2.0 * p2[0] + p3[0], p1[1] - 2.0 * p2[1] + p3[1]]);
    let n = count((0.75 * d1.max(d2) / tol).sqrt());
    for i in 1..=n {
        let t = i as f64 / n as f64;
        let a = lerp(lerp(p0, p1, t), lerp(p1, p2, t), t);
        let b = lerp(lerp(p1, p2, t), lerp(p2, p3, t), t);
        out.push(lerp(a, b, t));
    }
}

/// Segments needed for an arc of radius `r` sweeping `sweep` radians: each chord's sagitta
/// r·(1 − cos(θ/2)) must stay below `tol`.
fn arc_segments(r: f64, sweep: f64, tol: f64) -> usize {
    if r.is_nan() || r <= tol {
        return count(sweep.abs() / (PI / 2.0));
    }
    let step = 2.0 * (1.0 - tol / r).clamp(-1.0, 1.0).acos();
    count(sweep.abs() / step)
}

/// Circular arc around `center` from angle `a0` sweeping `sweep` radians (positive = CCW).
pub fn arc(center: Point2, r: f64, a0: f64, sweep: f64, tol: f64, out: &mut Vec<Point2>) {
    ellipse_arc(center, [r, r], 0.0, a0, sweep, tol, out);
}

/// Elliptical arc with radii `radii`, x axis rotated by `phi`, parameter from `a0` sweeping
/// `sweep`. The tolerance is applied to the larger radius, which bounds the error.
pub fn ellipse_arc(center: Point2, radii: Point2, phi: f64, a0: f64, sweep: f64, tol: f64, out: &mut Vec<Point2>) {
    let n = arc_segments(radii[0].abs().max(radii[1].abs()), sweep, tol);
    let (s, c) = phi.sin_cos();
    for i in 1..=n {
        let t = a0 + sweep * i as f64 / n as f64;
        let (x, y) = (radii[0] * t.cos(), radii[1] * t.sin());
        out.push([center[0] + c * x - s * y, center[1] + s * x + c * y]);
    }
}

/// A DXF polyline segment with bulge b = tan(θ/4) (θ the included angle, positive = CCW).
pub fn bulge(p0: Point2, p1: Point2, b: f64, tol: f64, out: &mut Vec<Point2>) {
    let chord = norm([p1[0] - p0[0], p1[1] - p0[1]]);
    if !b.is_finite() || b.abs() < 1e-12 || chord < 1e-15 {
        out.push(p1);
        return;
    }
    let theta = 4.0 * b.atan();
    let r = chord / (2.0 * (theta / 2.0).sin().abs());
    // The centre lies on the chord's perpendicular bisector, at distance r·cos(θ/2), on the
    // left for a CCW bulge.
    let mid = lerp(p0, p1, 0.5);
    let (ux, uy) = ((p1[0] - p0[0]) / chord, (p1[1] - p0[1]) / chord);
    let h = r * (theta / 2.0).cos() * theta.signum();
    let center = [mid[0] - uy * h, mid[1] + ux * h];
    let a0 = (p0[1] - center[1]).atan2(p0[0] - center[0]);
    let before = out.len();
    arc(center, r, a0, theta, tol, out);
    // Land exactly on the next vertex so that chained segments share it bit for bit.
    if out.len() > before {
        let last = out.len() - 1;
        out[last] = p1;
    }
}

/// SVG elliptical arc from `p0` to `p1` (endpoint parameterisation, SVG 1.1 appendix F.6).
#[allow(clippy::too_many_arguments)]
pub fn svg_arc(
    p0: Point2,
    p1: Point2,
    rx: f64,
    ry: f64,
    rot_deg: f64,
    large: bool,
    sweep: bool,
    tol: f64,
    out: &mut Vec<Point2>,
) {
    let (mut rx, mut ry) = (rx.abs(), ry.abs());
    if rx < 1e-15 || ry < 1e-15 || !(rx.is_finite() && ry.is_finite()) || p0 == p1 {
        out.push(p1);
        return;
    }
    let phi = rot_deg.to_radians();
    let (s, c) = phi.sin_cos();
    let (dx, dy) = ((p0[0] - p1[0]) / 2.0, (p0[1] - p1[1]) / 2.0);
    let (x1, y1) = (c * dx + s * dy, -s * dx + c * dy);
    let lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
    if lambda > 1.0 {
        rx *= lambda.sqrt();
        ry *= lambda.sqrt();
    }
    let num = (rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1).max(0.0);
    let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
    let mut k = if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    if large == sweep {
        k = -k;
    }
    let (cx1, cy1) = (k * rx * y1 / ry, -k * ry * x1 / rx);
    let center = [c * cx1 - s * cy1 + (p0[0] + p1[0]) / 2.0, s * cx1 + c * cy1 + (p0[1] + p1[1]) / 2.0];
    let a0 = ((y1 - cy1) / ry).atan2((x1 - cx1) / rx);
    let a1 = ((-y1 - cy1) / ry).atan2((-x1 - cx1) / rx);
    let mut d = a1 - a0;
    if sweep && d < 0.0 {
        d += 2.0 * PI;
    } else if !sweep && d > 0.0 {
        d -= 2.0 * PI;
    }
    let before = out.len();
    ellipse_arc(center, [rx, ry], phi, a0, d, tol, out);
    if out.len() > before {
        let last = out.len() - 1;
        out[last] = p1;
    }
}

/// Evaluates a (rational) B-spline of `degree` at `u` with de Boor's algorithm.
/// `knots.len()` must be `ctrl.len() + degree + 1`; checked by [`bspline`].
fn de_boor(degree: usize, knots: &[f64], ctrl: &[[f64; 3]], u: f64) -> Point2 {
    let n = ctrl.len();
    let mut span = degree;
    while span + 1 < n && knots[span + 1] <= u {
        span += 1;
    }
    let mut d: Vec<[f64; 3]> = (0..=degree).map(|j| ctrl[j + span - degree]).collect();
    for r in 1..=degree {
        for j in (r..=degree).rev() {
            let i = j + span - degree;
            let den = knots[i + degree + 1 - r] - knots[i];
            let a = if den.abs() > 0.0 { (u - knots[i]) / den } else { 0.0 };
            let prev = d[j - 1];
            for (v, p) in d[j].iter_mut().zip(prev) {
                *v = (1.0 - a) * p + a * *v;
            }
        }
    }
    let w = d[degree][2];
    if w.abs() > 1e-300 {
        [d[degree][0] / w, d[degree][1] / w]
    } else {
        [d[degree][0], d[degree][1]]
    }
}

/// A clamped (rational) B-spline as DXF SPLINE stores it. Returns `None` when the knot vector
/// does not match the control points, so that the caller can report the entity.
/// Sampling starts from a uniform parameter grid and bisects every interval whose midpoint
/// strays more than `tol` from the chord, to a fixed depth.
pub fn bspline(degree: usize, knots: &[f64], ctrl: &[Point2], weights: &[f64], tol: f64) -> Option<Vec<Point2>> {
    if degree == 0 || ctrl.len() <= degree || knots.len() != ctrl.len() + degree + 1 || ctrl.len() > 100_000 {
        return None;
    }
    if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
        return None;
    }
    let hom: Vec<[f64; 3]> = ctrl
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let w = weights.get(i).copied().filter(|w| w.is_finite() && *w > 0.0).unwrap_or(1.0);
            [p[0] * w, p[1] * w, w]
        })
        .collect();
    let (u0, u1) = (knots[degree], knots[ctrl.len()]);
    if u1 <= u0 {
        return None;
    }
    let eval = |u: f64| de_boor(degree, knots, &hom, u.clamp(u0, u1));
    let n0 = (ctrl.len() * 4).min(MAX_SEGMENTS);
    let mut out = vec![eval(u0)];
    for i in 0..n0 {
        let (a, b) = (u0 + (u1 - u0) * i as f64 / n0 as f64, u0 + (u1 - u0) * (i + 1) as f64 / n0 as f64);
        refine(&eval, (a, eval(a)), (b, eval(b)), tol, 8, &mut out);
    }
    Some(out)
}

/// Bisects the parameter interval between the samples `a` and `b` until its midpoint is
/// within `tol` of the chord, at most `depth` times.
fn refine(
    eval: &dyn Fn(f64) -> Point2,
    a: (f64, Point2),
    b: (f64, Point2),
    tol: f64,
    depth: u32,
    out: &mut Vec<Point2>,
) {
    let m = 0.5 * (a.0 + b.0);
    let pm = eval(m);
    if depth > 0 && distance_to_segment(pm, a.1, b.1) > tol {
        refine(eval, a, (m, pm), tol, depth - 1, out);
        refine(eval, (m, pm), b, tol, depth - 1, out);
    } else {
        out.push(b.1);
    }
}

/// Distance from `p` to the segment `a`–`b`.
pub fn distance_to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let (vx, vy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = vx * vx + vy * vy;
    let t = if l2 > 0.0 { (((p[0] - a[0]) * vx + (p[1] - a[1]) * vy) / l2).clamp(0.0, 1.0) } else { 0.0 };
    norm([p[0] - a[0] - t * vx, p[1] - a[1] - t * vy])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn length(start: Point2, pts: &[Point2]) -> f64 {
        let mut prev = start;
        pts.iter()
            .map(|p| {
                let l = norm([p[0] - prev[0], p[1] - prev[1]]);
                prev = *p;
                l
            })
            .sum()
    }

    #[test]
    fn half_circle_bulge_is_within_tolerance() {
        let mut out = Vec::new();
        bulge([0.0, 0.0], [2.0, 0.0], 1.0, 1e-4, &mut out);
        assert_eq!(*out.last().unwrap(), [2.0, 0.0]);
        // CCW bulge from (0,0) to (2,0): the arc goes below the chord, centre (1,0).
        assert!(out.iter().all(|p| p[1] <= 1e-12 && ((p[0] - 1.0).hypot(p[1]) - 1.0).abs() < 1e-9));
        assert!((length([0.0, 0.0], &out) - PI).abs() < 1e-3);
    }

    #[test]
    fn svg_arc_quarter_and_cubic_line() {
        let mut out = Vec::new();
        svg_arc([1.0, 0.0], [0.0, 1.0], 1.0, 1.0, 0.0, false, true, 1e-5, &mut out);
        assert!((length([1.0, 0.0], &out) - PI / 2.0).abs() < 1e-4);
        let mut c = Vec::new();
        cubic([0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], 1e-3, &mut c);
        assert_eq!(c, vec![[3.0, 0.0]]);
    }

    #[test]
    fn bspline_reproduces_its_control_polygon_for_degree_one() {
        let ctrl = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let pts = bspline(1, &[0.0, 0.0, 1.0, 2.0, 2.0], &ctrl, &[], 1e-6).unwrap();
        assert!((length(pts[0], &pts[1..]) - 2.0).abs() < 1e-9);
        assert!(bspline(3, &[0.0], &ctrl, &[], 1e-3).is_none());
    }

    #[test]
    fn absurd_tolerances_stay_bounded() {
        let mut out = Vec::new();
        arc([0.0, 0.0], 1e12, 0.0, 6.0, 1e-300, &mut out);
        arc([0.0, 0.0], f64::NAN, 0.0, 6.0, 1e-3, &mut out);
        assert!(out.len() <= 2 * MAX_SEGMENTS);
    }
}
