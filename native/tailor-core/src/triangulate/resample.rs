//! Even resampling of polylines by arc length, keeping chosen positions ("pins") as vertices.
//!
//! A polyline with points `p_0 … p_{m-1}` (closed: the segment `p_{m-1} p_0` is implied) has the
//! cumulative arc length `s_0 = 0, s_{i+1} = s_i + |p_{i+1} - p_i|`. Pins are arc-length values
//! that must become vertices (corners, fixed vertices, notches, span ends). Between two
//! consecutive pins at distance `d` along the curve, `k = max(1, round(d / h))` intervals of
//! equal arc length `d / k` are laid, so every boundary edge is within `[2h/3, 2h)` of the
//! target `h` except where two pins are closer than `h/2` (then the one short edge is the
//! input's own feature). Points are taken on the polyline, so a curve is replaced by chords of
//! length about `h` (area lost per chord ≈ `h³ / (12 R)` for a curvature radius `R`).

use crate::pattern::Point2;

/// Cumulative arc lengths: `m` values for an open polyline, `m + 1` for a closed one (the last
/// is the total length, back at `p_0`).
pub(crate) fn arc_lengths(pts: &[Point2], closed: bool) -> Vec<f64> {
    let m = pts.len();
    let segs = if closed { m } else { m.saturating_sub(1) };
    let mut cum = Vec::with_capacity(segs + 1);
    cum.push(0.0);
    for i in 0..segs {
        let (a, b) = (pts[i], pts[(i + 1) % m]);
        cum.push(cum[i] + dist(a, b));
    }
    cum
}

/// The point at arc length `s` (clamped to the curve; wraps when closed).
pub(crate) fn point_at(pts: &[Point2], cum: &[f64], closed: bool, s: f64) -> Point2 {
    let total = *cum.last().unwrap_or(&0.0);
    let s = if closed && total > 0.0 { s.rem_euclid(total) } else { s.clamp(0.0, total) };
    // The segment i with cum[i] <= s < cum[i+1].
    let i = match cum.binary_search_by(|c| c.partial_cmp(&s).unwrap_or(std::cmp::Ordering::Less)) {
        Ok(i) => i,
        Err(i) => i.saturating_sub(1),
    };
    let m = pts.len();
    if i + 1 >= cum.len() {
        return if closed { pts[0] } else { pts[m - 1] };
    }
    let len = cum[i + 1] - cum[i];
    let t = if len > 0.0 { (s - cum[i]) / len } else { 0.0 };
    let (a, b) = (pts[i], pts[(i + 1) % m]);
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// The arc length of the point of the polyline nearest `p`, and the distance to it.
pub(crate) fn project(pts: &[Point2], cum: &[f64], closed: bool, p: Point2) -> (f64, f64) {
    let m = pts.len();
    let segs = if closed { m } else { m.saturating_sub(1) };
    let mut best = (0.0, f64::INFINITY);
    if segs == 0 {
        return (0.0, pts.first().map_or(f64::INFINITY, |&a| dist(a, p)));
    }
    for i in 0..segs {
        let (a, b) = (pts[i], pts[(i + 1) % m]);
        let (t, d) = segment_projection(a, b, p);
        if d < best.1 {
            best = (cum[i] + t * (cum[i + 1] - cum[i]), d);
        }
    }
    best
}

/// Parameter `t ∈ [0, 1]` of the point of segment `ab` nearest `p`, and its distance.
pub(crate) fn segment_projection(a: Point2, b: Point2, p: Point2) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0) } else { 0.0 };
    let q = [a[0] + t * dx, a[1] + t * dy];
    (t, dist(q, p))
}

/// Indices of the polyline vertices where the direction turns by at least `turn_deg`
/// (the interior ends of an open polyline are considered; its two ends are not).
pub(crate) fn sharp_vertices(pts: &[Point2], closed: bool, turn_deg: f64) -> Vec<usize> {
    let m = pts.len();
    let range = if closed { 0..m } else { 1..m.saturating_sub(1) };
    range
        .filter(|&i| {
            let prev = pts[(i + m - 1) % m];
            let next = pts[(i + 1) % m];
            turn_angle_deg(prev, pts[i], next) >= turn_deg
        })
        .collect()
}

/// How far the direction turns at `b` walking `a → b → c`, degrees in `[0, 180]`.
pub(crate) fn turn_angle_deg(a: Point2, b: Point2, c: Point2) -> f64 {
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let (vx, vy) = (c[0] - b[0], c[1] - b[1]);
    let cross = ux * vy - uy * vx;
    let dot = ux * vx + uy * vy;
    cross.atan2(dot).abs().to_degrees()
}

/// A resampled polyline: the new points, their arc length on the input polyline, and for each
/// pin (in sorted order) the index of the point that sits on it.
pub(crate) struct Resampled {
    pub points: Vec<Point2>,
    pub params: Vec<f64>,
    pub pins: Vec<f64>,
    pub pin_points: Vec<usize>,
}

/// Resamples at target length `h`, keeping every pin. Pins closer than `eps` are merged. A
/// closed polyline with no pin is pinned at its first point; an open one is always pinned at
/// both ends.
pub(crate) fn resample(pts: &[Point2], closed: bool, mut pins: Vec<f64>, h: f64, eps: f64) -> Resampled {
    let cum = arc_lengths(pts, closed);
    let total = *cum.last().unwrap_or(&0.0);
    if closed {
        for p in pins.iter_mut() {
            *p = p.rem_euclid(total.max(f64::MIN_POSITIVE));
        }
        if pins.is_empty() {
            pins.push(0.0);
        }
    } else {
        pins.push(0.0);
        pins.push(total);
    }
    pins.sort_by(f64::total_cmp);
    pins.dedup_by(|b, a| (*b - *a).abs() <= eps);
    if closed && pins.len() > 1 && total - pins[pins.len() - 1] + pins[0] <= eps {
        pins.pop();
    }
    let mut out = Resampled { points: Vec::new(), params: Vec::new(), pins: pins.clone(), pin_points: Vec::new() };
    let intervals = if closed { pins.len() } else { pins.len() - 1 };
    for k in 0..intervals {
        let s0 = pins[k];
        let s1 = if k + 1 < pins.len() { pins[k + 1] } else { pins[0] + total };
        let d = s1 - s0;
        let n = ((d / h).round() as usize).max(1);
        out.pin_points.push(out.points.len());
        for j in 0..n {
            let s = s0 + d * j as f64 / n as f64;
            out.points.push(point_at(pts, &cum, closed, s));
            out.params.push(if closed { s.rem_euclid(total) } else { s });
        }
    }
    if !closed {
        out.pin_points.push(out.points.len());
        out.points.push(point_at(pts, &cum, closed, total));
        out.params.push(total);
    }
    out
}

pub(crate) fn dist(a: Point2, b: Point2) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Signed area of a closed polygon (positive when counter-clockwise).
pub(crate) fn signed_area(pts: &[Point2]) -> f64 {
    let m = pts.len();
    (0..m).map(|i| pts[i][0] * pts[(i + 1) % m][1] - pts[(i + 1) % m][0] * pts[i][1]).sum::<f64>() * 0.5
}

/// Even-odd point-in-polygon test.
pub(crate) fn inside(poly: &[Point2], p: Point2) -> bool {
    let m = poly.len();
    let mut c = false;
    let mut j = m - 1;
    for i in 0..m {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0] {
            c = !c;
        }
        j = i;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resamples_a_square_keeping_corners() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let cum = arc_lengths(&sq, true);
        let r = resample(&sq, true, vec![cum[0], cum[1], cum[2], cum[3]], 0.3, 1e-9);
        assert_eq!(r.points.len(), 12);
        assert_eq!(r.pin_points, vec![0, 3, 6, 9]);
        assert_eq!(r.points[3], [1.0, 0.0]);
        let open = resample(&sq, false, vec![], 0.3, 1e-9);
        assert_eq!(open.points.len(), 11);
        assert_eq!(*open.points.last().unwrap(), [0.0, 1.0]);
    }
}
