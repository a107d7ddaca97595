//! The isometric bend ([`BendMode::Roll`], the default): the piece rolls onto a cylinder, each point keeping its distance
//! along the surface, so nothing is stretched (the paper's rotation by an angle growing with
//! the distance from the axis stretched a piece bent 15 degrees by 32 %).
//!
//! # Formula
//!
//! Inputs: the piece's 3D positions `p_i` (flat, as placed from its pattern), its 2D rest
//! positions `r_i`, the axis through `o` with unit direction `d̂`, the angle `α`, an optional
//! symmetry line in the rest frame (point `q`), a threshold `τ ≥ 0` (metres) and an optional
//! radius `R`.
//!
//! * A frame round the axis: `ê` the piece's normal (of the least-squares affine map from its
//!   rest shape to its positions) with its component along `d̂` removed, pointing from the axis
//!   to the piece's centroid `c`; `t̂ = d̂ × ê`. Each point has `a_i = (p_i − o)·d̂` along the axis,
//!   `t_i = (p_i − o)·t̂` across it and `e_i = (p_i − o)·ê` out from it; the piece's plane is at
//!   `e = E = (c − o)·ê`, and `h_i = e_i − E` is a point's height off it.
//! * The arc coordinate `w_i`, measured in the rest frame so that it is a true pattern length:
//!   `w_i = ū + (r_i − r̄)·ĝ`, where `ĝ` is the unit rest-frame direction along which `t` grows
//!   (the least-squares fit of `t_i − ū` by `(r_i − r̄)·g`, `ū`, `r̄` the means): for a piece
//!   placed flat and parallel to the axis, `w_i = t_i` exactly.
//! * Where the rolling starts: with a symmetry line, `u_i = w_i − w(q)`, and both sides roll
//!   (the line is the sleeve's centre line, parallel to the axis); without, `u_i = w_i − min w`,
//!   the piece rolling up from its edge nearest `−t̂`. The distance rolled is
//!   `s_i = max(|u_i| − τ, 0)`: within `τ` of the start nothing moves.
//! * Radius: `R` when given, else `max s / |α|` (so the farthest point turns by `α`); each point
//!   turns by `φ_i = s_i / R` (angle = arc length / radius) about the line at `u = ±τ`, `R`
//!   towards the axis (`α > 0`; away for `α < 0`), in the sense that rolls its side up:
//!   `t_i' = t_i + σ_i((R + h_i)·sin φ_i − s_i)`, `e_i' = e_i − (R + h_i)(1 − cos φ_i)`
//!   (`σ_i = sign u_i`; for `α < 0`, `h_i → −h_i` and `e_i' = e_i + (R − h_i)(1 − cos φ_i)`),
//!   `a_i` unchanged. The cylinder is tangent to the plane where the rolling starts, so the
//!   bent piece is smooth there (no kink at the threshold).
//!
//! A flat piece's points stay on a surface isometric to its plane: distances along the surface
//! are kept exactly, and an edge, a straight chord of the bent surface, is shorter by at most
//! `ℓ·(ℓ/R)²/24` (0.1 % for an edge of 0.155 R). The 2D rest shape is never modified: stretch is
//! still measured against the true pattern. Bending always starts from the flat piece (the
//! add-on keeps its flat positions); bending a bent piece again rolls it further.
//!
//! With a taper (`taper_deg` ≠ 0) the same `s_i`, `σ_i`, `h_i` and `R` place each point on a
//! cone instead, tangent to the plane along the same start line ([`cone`](super::cone)).

use super::cone::Cone;
use super::BendParams;
use crate::error::{Result, TailorError};

use super::V3;

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Rolls `positions` in place (see the module docs for the formula); `d` the unit axis.
pub(super) fn roll(positions: &mut [[f32; 3]], rest: &[[f32; 2]], params: &BendParams, d: V3) -> Result<()> {
    if positions.is_empty() || (params.radius.is_none() && params.angle_deg == 0.0) {
        return Ok(());
    }
    let n = positions.len() as f64;
    let o = params.axis_point;
    let rel: Vec<V3> = positions.iter().map(|p| [0, 1, 2].map(|k| p[k] as f64 - o[k])).collect();
    let c = [0, 1, 2].map(|k| rel.iter().map(|v| v[k]).sum::<f64>() / n);
    // Out from the axis: the piece's normal across the axis, turned to point away from it
    // (the centroid's direction would tilt it wherever the centroid is off the foot of the
    // axis, and with it the heights, which the roll keeps: a stretch).
    let normal = piece_normal(&rel, c, rest);
    let across = [0, 1, 2].map(|k| normal[k] - dot(normal, d) * d[k]);
    let an = dot(across, across).sqrt();
    if !(an > 1e-6) {
        return Err(TailorError::setting(
            "axis_direction",
            format!("{:?}", params.axis_direction),
            "the axis is perpendicular to the piece: give one along it (a sleeve's length)",
        ));
    }
    let e_hat = across.map(|x| x / an);
    // An axis in the piece's plane (distance 0) leaves the normal as it is: positive angles
    // then roll the piece to its back.
    let e_hat = if dot(c, e_hat) < -1e-9 { e_hat.map(|x| -x) } else { e_hat };
    let dist = dot(c, e_hat);
    let t_hat = cross(d, e_hat);
    let t: Vec<f64> = rel.iter().map(|&v| dot(v, t_hat)).collect();
    let e: Vec<f64> = rel.iter().map(|&v| dot(v, e_hat)).collect();
    let w = arc_coordinates(&t, rest)?;
    let u: Vec<f64> = match params.symmetry {
        Some(line) => {
            let w0 = w.at(line.point);
            w.values.iter().map(|x| x - w0).collect()
        }
        None => {
            let lo = w.values.iter().copied().fold(f64::INFINITY, f64::min);
            w.values.iter().map(|x| x - lo).collect()
        }
    };
    let s: Vec<f64> = u.iter().map(|x| (x.abs() - params.threshold).max(0.0)).collect();
    let s_max = s.iter().copied().fold(0.0, f64::max);
    // The angle's sign says which way, also when a radius sets how far.
    let towards = params.angle_deg >= 0.0;
    let r = match params.radius {
        Some(r) => r,
        None if s_max > 0.0 => s_max / params.angle_deg.to_radians().abs(),
        None => return Ok(()),
    };
    if params.taper_deg != 0.0 {
        let along: Vec<f64> = rel.iter().map(|&v| dot(v, d)).collect();
        let cone = Cone::new(params.taper_deg, r, &along)?;
        for i in 0..positions.len() {
            if s[i] <= 0.0 {
                continue;
            }
            let sigma = if u[i] < 0.0 { -1.0 } else { 1.0 };
            let [da, dt, de] = cone.displacement(along[i], s[i], sigma, e[i] - dist, towards);
            for k in 0..3 {
                positions[i][k] = (o[k] + rel[i][k] + da * d[k] + dt * t_hat[k] + de * e_hat[k]) as f32;
            }
        }
        return Ok(());
    }
    for i in 0..positions.len() {
        if s[i] <= 0.0 {
            continue;
        }
        let phi = s[i] / r;
        let sigma = if u[i] < 0.0 { -1.0 } else { 1.0 };
        let h = e[i] - dist;
        // The point's radius about the line it turns round: R plus its height on the side away
        // from that line.
        let rho = if towards { r + h } else { r - h };
        let dt = sigma * (rho * phi.sin() - s[i]);
        let de = if towards { -rho * (1.0 - phi.cos()) } else { rho * (1.0 - phi.cos()) };
        for k in 0..3 {
            positions[i][k] = (o[k] + rel[i][k] + dt * t_hat[k] + de * e_hat[k]) as f32;
        }
    }
    Ok(())
}

/// Unit normal of the plane the rest shape is placed in: the cross product of the columns of
/// the least-squares affine map `r − r̄ ↦ p − c` (zero for a degenerate piece).
fn piece_normal(rel: &[V3], c: V3, rest: &[[f32; 2]]) -> V3 {
    let n = rest.len() as f64;
    let mean_r = [0, 1].map(|k| rest.iter().map(|r| r[k] as f64).sum::<f64>() / n);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let (mut px, mut py) = ([0.0; 3], [0.0; 3]);
    for (r, v) in rest.iter().zip(rel) {
        let (x, y) = (r[0] as f64 - mean_r[0], r[1] as f64 - mean_r[1]);
        (sxx, sxy, syy) = (sxx + x * x, sxy + x * y, syy + y * y);
        for k in 0..3 {
            px[k] += x * (v[k] - c[k]);
            py[k] += y * (v[k] - c[k]);
        }
    }
    let det = sxx * syy - sxy * sxy;
    if !(det.abs() > 1e-30) {
        return [0.0; 3];
    }
    // A = [Σ(p−c)xᵀ Σ(p−c)yᵀ] · Cov(r)⁻¹, column by column.
    let a1 = [0, 1, 2].map(|k| (px[k] * syy - py[k] * sxy) / det);
    let a2 = [0, 1, 2].map(|k| (py[k] * sxx - px[k] * sxy) / det);
    let m = cross(a1, a2);
    let mn = dot(m, m).sqrt();
    if mn > 0.0 {
        m.map(|x| x / mn)
    } else {
        [0.0; 3]
    }
}

/// The arc coordinates `w_i` of the module docs and the fit that gives them.
struct ArcCoordinates {
    values: Vec<f64>,
    mean_t: f64,
    mean_r: [f64; 2],
    g: [f64; 2],
}

impl ArcCoordinates {
    /// `w` at rest-frame point `q`.
    fn at(&self, q: [f64; 2]) -> f64 {
        self.mean_t + (q[0] - self.mean_r[0]) * self.g[0] + (q[1] - self.mean_r[1]) * self.g[1]
    }
}

/// Fits `t_i − t̄ ≈ (r_i − r̄)·g` (least squares, 2×2 normal equations) and measures along `ĝ`.
fn arc_coordinates(t: &[f64], rest: &[[f32; 2]]) -> Result<ArcCoordinates> {
    let n = t.len() as f64;
    let mean_t = t.iter().sum::<f64>() / n;
    let mean_r = [0, 1].map(|k| rest.iter().map(|r| r[k] as f64).sum::<f64>() / n);
    let (mut sxx, mut sxy, mut syy, mut sxt, mut syt) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (r, &ti) in rest.iter().zip(t) {
        let (x, y, dt) = (r[0] as f64 - mean_r[0], r[1] as f64 - mean_r[1], ti - mean_t);
        (sxx, sxy, syy, sxt, syt) = (sxx + x * x, sxy + x * y, syy + y * y, sxt + x * dt, syt + y * dt);
    }
    let det = sxx * syy - sxy * sxy;
    let g = if det.abs() > 1e-18 * (sxx * syy).max(1e-300) {
        [(syy * sxt - sxy * syt) / det, (sxx * syt - sxy * sxt) / det]
    } else {
        [0.0, 0.0]
    };
    let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
    if !(gn > 1e-9) {
        return Err(TailorError::setting(
            "bend",
            "the piece",
            "its rest shape does not match its placed positions across the axis (a degenerate piece, or one placed perpendicular to the axis)",
        ));
    }
    let g = [g[0] / gn, g[1] / gn];
    let values =
        rest.iter().map(|r| mean_t + (r[0] as f64 - mean_r[0]) * g[0] + (r[1] as f64 - mean_r[1]) * g[1]).collect();
    Ok(ArcCoordinates { values, mean_t, mean_r, g })
}

#[cfg(test)]
mod tests {
    use super::super::{bend_piece, BendMode};
    use super::*;

    /// A 0.4 × 0.3 sheet in the z = 0 plane, `nx × ny` vertices, and its triangles' edges.
    fn sheet(nx: usize, ny: usize) -> (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[usize; 2]>) {
        let mut rest = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                rest.push([i as f32 * 0.4 / (nx - 1) as f32 - 0.2, j as f32 * 0.3 / (ny - 1) as f32]);
            }
        }
        let edges = super::super::tests::grid_edges(nx, ny);
        (rest.iter().map(|r| [r[0], r[1], 0.0]).collect(), rest, edges)
    }

    fn params(angle: f64, symmetric: bool, threshold: f64) -> BendParams {
        super::super::tests::sheet_params(angle, symmetric, threshold, BendMode::Roll)
    }

    fn len(p: &[[f32; 3]], e: [usize; 2]) -> f64 {
        (0..3).map(|k| (p[e[0]][k] as f64 - p[e[1]][k] as f64).powi(2)).sum::<f64>().sqrt()
    }

    /// Every edge keeps its length up to the chord of its bent part (`ℓ·(ℓ/R)²/24`), and so
    /// within 0.1 % where edges are short beside the radius: angles up to 360 degrees, with and
    /// without symmetry and threshold, towards and away from the axis.
    #[test]
    fn the_bend_keeps_edge_lengths() {
        let (pos, rest, edges) = sheet(81, 31); // 5 mm edges
        for symmetric in [false, true] {
            for threshold in [0.0, 0.03] {
                for angle in [15.0, 90.0, 180.0, 270.0, 360.0, -120.0] {
                    let mut p = pos.clone();
                    let q = params(angle, symmetric, threshold);
                    bend_piece(&mut p, &rest, &q).unwrap();
                    assert!(p.iter().zip(&pos).any(|(a, b)| (a[2] - b[2]).abs() > 0.01), "nothing bent");
                    let reach = if symmetric { 0.2 } else { 0.4 } - threshold;
                    let r = reach / f64::to_radians(angle).abs();
                    for &e in &edges {
                        let (l0, l1) = (len(&pos, e), len(&p, e));
                        let bound = l0 * (l0 / r).powi(2) / 24.0 + 1e-6;
                        assert!((l1 - l0).abs() <= bound, "edge {e:?}: {l0} -> {l1}, bound {bound}");
                        if l0 / r < 0.155 {
                            assert!((l1 - l0).abs() / l0 < 1e-3, "edge {e:?}: {l0} -> {l1}");
                        }
                    }
                }
            }
        }
    }

    /// The farthest point turns by the angle (its tangent does), the two halves of a
    /// symmetric bend mirror each other, and at 180 degrees they meet: a tube.
    #[test]
    fn symmetric_bend_closes_a_tube_at_half_a_turn() {
        let (pos, rest, _) = sheet(41, 4);
        let mut p = pos.clone();
        bend_piece(&mut p, &rest, &params(180.0, true, 0.0)).unwrap();
        for (i, r) in rest.iter().enumerate() {
            let j = rest.iter().position(|q| (q[0] + r[0]).abs() < 1e-6 && q[1] == r[1]).unwrap();
            assert!((p[i][0] + p[j][0]).abs() < 1e-5 && (p[i][2] - p[j][2]).abs() < 1e-6);
            assert_eq!(p[i][1], pos[i][1], "a point moved along the axis");
        }
        let (left, right) = (0, 40);
        let gap = (0..3).map(|k| (p[left][k] - p[right][k]).powi(2)).sum::<f32>().sqrt();
        assert!(gap < 1e-5, "the edges did not meet: {gap}");
        // Radius 0.2/π: the edges meet at the bottom of the tube, 2R below the sheet.
        let r = 0.2 / std::f32::consts::PI;
        assert!((p[right][2] + 2.0 * r).abs() < 1e-5 && p[right][0].abs() < 1e-5, "{:?}", p[right]);
        // The last column's tangent has turned by the angle: it points back along -x.
        let (a, b) = (p[right - 1], p[right]);
        let turned = f64::atan2(-(b[2] - a[2]) as f64, (b[0] - a[0]) as f64).to_degrees();
        assert!((turned.abs() - 180.0).abs() < 5.0, "{turned}");
    }

    /// Within the threshold nothing moves; just past it the piece leaves its plane smoothly
    /// (tangent to it: height growing as the square of the distance rolled).
    #[test]
    fn the_bend_starts_smoothly_past_the_threshold() {
        let (pos, rest, _) = sheet(81, 3);
        let tau = 0.05;
        let mut p = pos.clone();
        bend_piece(&mut p, &rest, &params(90.0, true, tau)).unwrap();
        let r = (0.2 - tau) / f64::to_radians(90.0);
        for (a, b) in p.iter().zip(&pos) {
            let s = (b[0].abs() as f64 - tau).max(0.0);
            let moved = (0..3).map(|k| (a[k] - b[k]) as f64).map(|x| x * x).sum::<f64>().sqrt();
            if s == 0.0 {
                assert_eq!(moved, 0.0, "{b:?} within the threshold moved");
            } else {
                let drop = -(a[2] as f64);
                assert!((drop - r * (1.0 - (s / r).cos())).abs() < 1e-5, "{b:?}: {drop}");
                assert!(drop <= s * s / (2.0 * r) + 1e-6, "{b:?}: a kink");
            }
        }
    }

    /// A radius given rolls the piece onto that cylinder, whatever the angle: the farthest
    /// point of a one-sided bend turns by its arc length over the radius.
    #[test]
    fn a_radius_sets_the_cylinder() {
        let (pos, rest, _) = sheet(41, 3);
        let mut p = pos.clone();
        let q = BendParams { radius: Some(0.1), ..params(10.0, false, 0.0) };
        bend_piece(&mut p, &rest, &q).unwrap();
        // Rolled up from the edge x = -0.2 (nearest -t̂ = -x): the centre of the cylinder is
        // 0.1 below that edge; every point lies on it.
        for (a, b) in p.iter().zip(&pos) {
            let (dx, dz) = (a[0] as f64 + 0.2, a[2] as f64 + 0.1);
            assert!(((dx * dx + dz * dz).sqrt() - 0.1).abs() < 1e-5, "{b:?} -> {a:?}");
        }
    }

    /// With a radius, the angle's sign still says which way the piece rolls: a negative
    /// angle rolls it away from the axis, onto the cylinder on the other side.
    #[test]
    fn a_radius_rolls_away_for_a_negative_angle() {
        let (pos, rest, _) = sheet(41, 3);
        let mut p = pos.clone();
        let q = BendParams { radius: Some(0.1), ..params(-10.0, false, 0.0) };
        bend_piece(&mut p, &rest, &q).unwrap();
        for (a, b) in p.iter().zip(&pos) {
            let (dx, dz) = (a[0] as f64 + 0.2, a[2] as f64 - 0.1);
            assert!(((dx * dx + dz * dz).sqrt() - 0.1).abs() < 1e-5, "{b:?} -> {a:?}");
        }
    }

    #[test]
    fn bad_parameters_are_errors() {
        let (mut pos, rest, _) = sheet(5, 4);
        let mut q = params(10.0, false, 0.0);
        q.axis_direction = [0.0; 3];
        assert!(matches!(bend_piece(&mut pos, &rest, &q), Err(TailorError::InvalidSetting { .. })));
        let q = params(f64::NAN, false, 0.0);
        assert!(matches!(bend_piece(&mut pos, &rest, &q), Err(TailorError::InvalidSetting { .. })));
        let q = params(10.0, false, -1.0);
        assert!(matches!(bend_piece(&mut pos, &rest, &q), Err(TailorError::InvalidSetting { .. })));
        let q = BendParams { radius: Some(0.0), ..params(10.0, false, 0.0) };
        assert!(matches!(bend_piece(&mut pos, &rest, &q), Err(TailorError::InvalidSetting { .. })));
        // An axis across the piece (along its normal) gives nothing to roll round.
        let q = BendParams { axis_direction: [0.0, 0.0, 1.0], ..params(10.0, false, 0.0) };
        assert!(matches!(bend_piece(&mut pos, &rest, &q), Err(TailorError::InvalidSetting { .. })));
        assert!(matches!(
            bend_piece(&mut pos[..3], &rest, &params(1.0, false, 0.0)),
            Err(TailorError::ShapeMismatch { .. })
        ));
        let before = pos.clone();
        bend_piece(&mut pos, &rest, &params(0.0, true, 0.0)).unwrap();
        assert_eq!(pos, before, "a zero angle moved the piece");
    }
}
