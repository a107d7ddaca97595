//! The paper's bend (Sec. 4, Fig. 4; [`BendMode::Rotate`]): each point rotated about the axis by
//! an angle that grows with its distance from the centre. It stretches the piece (a sleeve
//! bent 15 degrees by 32 %); kept for garment files written before the isometric bend
//! ([`roll`](super::roll)), which open as they were made.
//!
//! # Formula
//!
//! Inputs: the piece's 3D positions `p_i`, its 2D rest positions `r_i`, the rotation axis
//! through `o` with unit direction `d̂`, the angle `α`, an optional symmetry line in the rest
//! frame (point `q`, unit direction `ê`) and a threshold `τ ≥ 0` (metres).
//!
//! * Bend fraction `s_i`, from the rest shape only:
//!   - without symmetry line: `s_i = |r_i − c| / max_j |r_j − c|`, `c` the mean rest position
//!     (vertices further from the centre rotate more, all in the same sense);
//!   - with a symmetry line: `s_i = δ_i / max_j |δ_j|`, `δ_i = (r_i − q) × ê` (2D cross product,
//!     signed distance from the line), so the two halves rotate in opposite senses and the piece
//!     wraps symmetrically (a sleeve around an arm whose axis runs along the sleeve's centre line).
//! * Threshold: with `ρ_i = |(p_i − o) − ((p_i − o)·d̂) d̂|` the distance of `p_i` from the axis,
//!   `θ_i = α s_i` when `ρ_i ≥ τ`, else `θ_i = 0` (nothing bends within `τ` of the axis).
//! * `p_i' = o + R(d̂, θ_i)(p_i − o)`, `R` the right-handed rotation (Rodrigues):
//!   `R v = v cos θ + (d̂ × v) sin θ + d̂ (d̂·v)(1 − cos θ)`.
//!
//! `s_i` depends only on the rest shape and `ρ_i` is unchanged by any rotation about the axis,
//! so bending by `−α` computes `θ_i' = −θ_i` for every vertex and exactly undoes bending by `α`
//! (to rounding). The 2D rest shape is never modified: stretch is still measured against the
//! true pattern.

use super::{BendParams, SymmetryLine};
use crate::error::{Result, TailorError};

/// Bends `positions` in place (see the module docs for the formula); `d` the unit axis.
pub(super) fn rotate(positions: &mut [[f32; 3]], rest: &[[f32; 2]], params: &BendParams, d: [f64; 3]) -> Result<()> {
    let s = bend_fractions(rest, params.symmetry)?;
    let o = params.axis_point;
    let alpha = params.angle_deg.to_radians();
    for (p, &si) in positions.iter_mut().zip(&s) {
        let v = [p[0] as f64 - o[0], p[1] as f64 - o[1], p[2] as f64 - o[2]];
        let along = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
        let perp = [v[0] - along * d[0], v[1] - along * d[1], v[2] - along * d[2]];
        let rho = (perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]).sqrt();
        if rho < params.threshold || si == 0.0 {
            continue;
        }
        let (sin, cos) = (alpha * si).sin_cos();
        let cross = [d[1] * v[2] - d[2] * v[1], d[2] * v[0] - d[0] * v[2], d[0] * v[1] - d[1] * v[0]];
        for k in 0..3 {
            let r = v[k] * cos + cross[k] * sin + d[k] * along * (1.0 - cos);
            p[k] = (o[k] + r) as f32;
        }
    }
    Ok(())
}

/// `s_i` of the module docs.
fn bend_fractions(rest: &[[f32; 2]], symmetry: Option<SymmetryLine>) -> Result<Vec<f64>> {
    let raw: Vec<f64> = match symmetry {
        None => {
            let n = rest.len().max(1) as f64;
            let c = [0, 1].map(|k| rest.iter().map(|r| r[k] as f64).sum::<f64>() / n);
            rest.iter().map(|r| ((r[0] as f64 - c[0]).powi(2) + (r[1] as f64 - c[1]).powi(2)).sqrt()).collect()
        }
        Some(line) => {
            let e = line.direction;
            let en = (e[0] * e[0] + e[1] * e[1]).sqrt();
            if !(en.is_finite() && en > 1e-12) || line.point.iter().any(|c| !c.is_finite()) {
                return Err(TailorError::setting(
                    "symmetry",
                    format!("{line:?}"),
                    "needs a finite point and a non-zero direction",
                ));
            }
            let (ex, ey) = (e[0] / en, e[1] / en);
            rest.iter().map(|r| (r[0] as f64 - line.point[0]) * ey - (r[1] as f64 - line.point[1]) * ex).collect()
        }
    };
    let max = raw.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    Ok(if max > 0.0 { raw.iter().map(|x| x / max).collect() } else { vec![0.0; raw.len()] })
}

#[cfg(test)]
mod tests {
    use super::super::{bend_piece, BendMode};
    use super::*;

    /// A 0.4 × 0.3 sheet in the z = 0 plane on a 5 × 4 grid.
    fn sheet() -> (Vec<[f32; 3]>, Vec<[f32; 2]>) {
        let mut rest = Vec::new();
        for j in 0..4 {
            for i in 0..5 {
                rest.push([i as f32 * 0.1 - 0.2, j as f32 * 0.1]);
            }
        }
        (rest.iter().map(|r| [r[0], r[1], 0.0]).collect(), rest)
    }

    fn params(angle: f64, symmetric: bool, threshold: f64) -> BendParams {
        super::super::tests::sheet_params(angle, symmetric, threshold, BendMode::Rotate)
    }

    #[test]
    fn bending_back_by_minus_the_angle_restores_the_input() {
        for symmetric in [false, true] {
            let (pos, rest) = sheet();
            let mut p = pos.clone();
            bend_piece(&mut p, &rest, &params(70.0, symmetric, 0.12)).unwrap();
            assert!(p.iter().zip(&pos).any(|(a, b)| (a[2] - b[2]).abs() > 0.01));
            bend_piece(&mut p, &rest, &params(-70.0, symmetric, 0.12)).unwrap();
            for (a, b) in p.iter().zip(&pos) {
                for k in 0..3 {
                    assert!((a[k] - b[k]).abs() < 1e-5, "{a:?} vs {b:?}");
                }
            }
        }
    }

    #[test]
    fn symmetric_bend_wraps_both_halves_alike_and_keeps_axis_distance() {
        let (pos, rest) = sheet();
        let mut p = pos.clone();
        bend_piece(&mut p, &rest, &params(60.0, true, 0.0)).unwrap();
        for (i, r) in rest.iter().enumerate() {
            // Mirror vertex across the symmetry line x = 0.
            let j = rest.iter().position(|q| (q[0] + r[0]).abs() < 1e-6 && q[1] == r[1]).unwrap();
            assert!((p[i][0] + p[j][0]).abs() < 1e-6 && (p[i][2] - p[j][2]).abs() < 1e-6);
            let rho = |q: [f32; 3]| (q[0].powi(2) + (q[2] + 0.1).powi(2)).sqrt();
            assert!((rho(p[i]) - rho(pos[i])).abs() < 1e-6);
            assert_eq!(p[i][1], pos[i][1]);
        }
        // The outermost column turned by the full angle, right-handed about +y (so towards -z,
        // wrapping round the axis below the sheet): measured in the (z, x) plane.
        let edge = rest.iter().position(|r| r[0] == 0.2).unwrap();
        let before = (0.2f64).atan2(0.1);
        let after = (p[edge][0] as f64).atan2((p[edge][2] + 0.1) as f64);
        assert!(((after - before).to_degrees() - 60.0).abs() < 1e-3, "{}", (after - before).to_degrees());
        assert!(p[edge][2] < 0.0);
    }

    #[test]
    fn nothing_bends_within_the_threshold() {
        let (pos, rest) = sheet();
        let mut p = pos.clone();
        bend_piece(&mut p, &rest, &params(45.0, true, 0.15)).unwrap();
        for (a, b) in p.iter().zip(&pos) {
            let rho = (b[0].powi(2) + (b[2] + 0.1).powi(2)).sqrt();
            let moved = (0..3).any(|k| (a[k] - b[k]).abs() > 1e-7);
            assert_eq!(moved, rho >= 0.15 && b[0] != 0.0, "{b:?}");
        }
    }
}
