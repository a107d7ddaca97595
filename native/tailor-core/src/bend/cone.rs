//! The isometric bend onto a cone ([`BendParams::taper_deg`] ≠ 0), for tapered limbs: the roll
//! of [`roll`](super::roll) with a radius that grows (or shrinks) linearly along the axis. A
//! cone is developable, so each point still keeps its distances along the surface.
//!
//! # Formula
//!
//! The roll's frame and coordinates (see [`roll`](super::roll)): a point `i` at `a_i` along the
//! axis `d̂`, rolled a distance `s_i ≥ 0` (past the start line `u = ±τ`, on side `σ_i`), at height
//! `h_i` off the piece's plane; `R` the radius (given, or `max s / |α|`).
//!
//! * The cone, of half-angle `β = |taper_deg|`, is tangent to the piece's plane along the start
//!   line `L` (as the cylinder is), so the piece still leaves its plane smoothly. Its radius, the
//!   distance from a point of `L` to the cone's axis, is `R` level with the axis point (`a = 0`)
//!   and grows by `sin β` per metre along `L` in the sense `ĝ = sign(taper_deg)·d̂`. The apex `A`
//!   is on `L` at `a_A = −sign(taper_deg)·R / sin β`; every point must lie beyond it:
//!   `x_i = sign(taper_deg)·(a_i − a_A) > 0` (else the apex is inside the piece: an error).
//! * Unrolled, the cone is a plane sector about `A`: a point at `x_i` along `L` and `s_i` off it
//!   has polar coordinates `ρ_i = √(x_i² + s_i²)`, `ψ_i = atan2(s_i, x_i)`, and lands on the
//!   generator at azimuth `φ_i = ψ_i / sin β` (the cone's metric `dρ² + ρ² sin²β dφ²` is the
//!   plane's `dρ² + ρ² dψ²`: an isometry).
//! * With `n̂` the unit normal from the plane into the cone (`−ê` rolling towards the axis, `+ê`
//!   away) and `h'_i` the height outwards (`h_i`, or `−h_i` away), the cone's axis is
//!   `â = cos β ĝ + sin β n̂`, the radial direction at azimuth `φ` is
//!   `r̂(φ) = cos φ (sin β ĝ − cos β n̂) + sin φ σ_i t̂` and the outward normal
//!   `N(φ) = cos β r̂(φ) − sin β â`. The point goes to `A + ρ_i (cos β â + sin β r̂(φ_i)) + h'_i N(φ_i)`;
//!   its displacement from where it lay flat (`A + x_i ĝ + σ_i s_i t̂ − h'_i n̂`) is, along
//!   `ĝ`, `n̂` and `t̂`:
//!   `Δg = ρ_i (cos²β + sin²β cos φ_i) − h'_i sin β cos β (1 − cos φ_i) − x_i`,
//!   `Δn = (1 − cos φ_i)(ρ_i sin β cos β + h'_i cos²β)`,
//!   `Δt = σ_i ((ρ_i sin β + h'_i cos β) sin φ_i − s_i)`.
//!   As `β → 0` with `x_i sin β → R` this is the cylinder's roll (`Δg → 0`).
//!
//! An edge, a chord of the cone, is shorter by at most `ℓ·(ℓ/r)²/24`, `r` the cone's radius
//! where it lies (smallest at the narrow end): 0.1 % for an edge of 0.155 r, as on the cylinder.

use crate::error::{Result, TailorError};

/// The cone a piece rolls onto, in the roll's frame (see the module docs).
pub(super) struct Cone {
    /// `sign(taper_deg)`: `ĝ = sign·d̂`.
    sign: f64,
    /// `a_A`, the apex along the axis.
    apex: f64,
    sin_b: f64,
    cos_b: f64,
}

impl Cone {
    /// The cone of half-angle `taper_deg` whose radius level with the axis point is `radius`;
    /// `along` the points' `a_i`, all of which must lie beyond the apex.
    pub(super) fn new(taper_deg: f64, radius: f64, along: &[f64]) -> Result<Self> {
        let beta = taper_deg.abs().to_radians();
        let (sin_b, cos_b) = beta.sin_cos();
        let sign = taper_deg.signum();
        let apex = -sign * radius / sin_b;
        let nearest = along.iter().map(|a| sign * (a - apex)).fold(f64::INFINITY, f64::min);
        if !(nearest > 0.0) {
            return Err(TailorError::setting(
                "taper_deg",
                taper_deg,
                format!(
                    "puts the cone's apex (radius 0) inside the piece, {:.4} m along the axis from its point: \
                     give a smaller taper or a larger radius",
                    apex
                ),
            ));
        }
        Ok(Self { sign, apex, sin_b, cos_b })
    }

    /// Displacement of a point along `(d̂, t̂, ê)`: at `a` along the axis, rolled `s` on side
    /// `sigma`, `h` off the plane (towards `ê`), rolling towards the axis or away from it.
    pub(super) fn displacement(&self, a: f64, s: f64, sigma: f64, h: f64, towards: bool) -> [f64; 3] {
        let (sb, cb) = (self.sin_b, self.cos_b);
        let x = self.sign * (a - self.apex);
        let rho = x.hypot(s);
        let phi = s.atan2(x) / sb;
        let (sin_p, cos_p) = phi.sin_cos();
        let h_out = if towards { h } else { -h };
        let dg = rho * (cb * cb + sb * sb * cos_p) - h_out * sb * cb * (1.0 - cos_p) - x;
        let dn = (1.0 - cos_p) * (rho * sb * cb + h_out * cb * cb);
        let dt = sigma * ((rho * sb + h_out * cb) * sin_p - s);
        // n̂ = −ê towards the axis, +ê away.
        [self.sign * dg, dt, if towards { -dn } else { dn }]
    }
}

#[cfg(test)]
mod tests {
    use super::super::{bend_piece, BendMode, BendParams, SymmetryLine};
    use super::*;

    /// A sleeve-like trapezoid in z = 0: 0.26 m wide at y = 0, 0.40 m at y = 0.45, centred on
    /// x = 0; `nx` columns across (each row spaced evenly), `ny` rows; and its triangles' edges.
    fn trapezoid(nx: usize, ny: usize) -> (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[usize; 2]>) {
        let mut rest = Vec::new();
        for j in 0..ny {
            let y = 0.45 * j as f64 / (ny - 1) as f64;
            let half = 0.13 + 0.07 * y / 0.45;
            for i in 0..nx {
                rest.push([(-half + 2.0 * half * i as f64 / (nx - 1) as f64) as f32, y as f32]);
            }
        }
        let edges = super::super::tests::grid_edges(nx, ny);
        (rest.iter().map(|r| [r[0], r[1], 0.0]).collect(), rest, edges)
    }

    /// An arm's axis along y, 6 cm behind the sleeve, level with its middle (y = 0.225).
    fn arm(angle: f64, symmetric: bool, taper_deg: f64, radius: Option<f64>) -> BendParams {
        BendParams {
            axis_point: [0.0, 0.225, -0.06],
            axis_direction: [0.0, 1.0, 0.0],
            angle_deg: angle,
            symmetry: symmetric.then_some(SymmetryLine { point: [0.0, 0.0], direction: [0.0, 1.0] }),
            threshold: 0.0,
            radius,
            mode: BendMode::Roll,
            taper_deg,
        }
    }

    fn len(p: &[[f32; 3]], e: [usize; 2]) -> f64 {
        (0..3).map(|k| (p[e[0]][k] as f64 - p[e[1]][k] as f64).powi(2)).sum::<f64>().sqrt()
    }

    /// The largest relative change of an edge's length.
    fn worst(before: &[[f32; 3]], after: &[[f32; 3]], edges: &[[usize; 2]]) -> f64 {
        edges.iter().map(|&e| (len(after, e) - len(before, e)).abs() / len(before, e)).fold(0.0, f64::max)
    }

    /// A sleeve rolled round a tapered arm (issue 25): no edge changes length by 0.1 %, on the
    /// cylinder and on cones tapering either way, for angles up to a whole turn, with and
    /// without symmetry. Meshed at 2.5 mm both ways: the cone's narrowest radius at a whole
    /// turn of a symmetric half is 2 cm, and there the generators cross the sleeve's columns
    /// at 25 degrees, so edges along the sleeve are curved too (at 5 mm along, a diagonal
    /// there changed by 0.14 %: the chord, not the map).
    #[test]
    fn sleeve_rolled_onto_a_cone_or_cylinder_keeps_edge_lengths() {
        let (pos, rest, edges) = trapezoid(161, 181);
        for taper in [0.0, 2.8, -2.8] {
            for symmetric in [false, true] {
                for angle in [15.0, 90.0, 180.0, 270.0, 360.0, -120.0] {
                    let mut p = pos.clone();
                    bend_piece(&mut p, &rest, &arm(angle, symmetric, taper, None)).unwrap();
                    let moved = p.iter().zip(&pos).map(|(a, b)| (a[2] - b[2]).abs()).fold(0.0, f32::max);
                    assert!(moved > 0.01, "nothing bent");
                    let w = worst(&pos, &p, &edges);
                    assert!(
                        w < 1e-3,
                        "taper {taper}, symmetric {symmetric}, {angle}°: an edge changed by {:.4} %",
                        w * 100.0
                    );
                }
            }
        }
    }

    /// Every point lands on the cone: apex on the sleeve's centre line (the start line of both
    /// halves) `R / sin β` before the axis point, axis `â` tilted by `β` from `d̂` into the
    /// cone, each point at the angle `β` from it seen from the apex; so the cone's radius is `R`
    /// level with the axis point and grows by `sin β` per metre along the start line.
    #[test]
    fn every_point_lands_on_the_cone() {
        let (pos, rest, _) = trapezoid(81, 10);
        for (r, taper) in [(0.05, 4.0f64), (0.08, -6.0)] {
            let mut p = pos.clone();
            bend_piece(&mut p, &rest, &arm(180.0, true, taper, Some(r))).unwrap();
            let (sb, cb) = taper.abs().to_radians().sin_cos();
            let sign = taper.signum();
            let apex = [0.0, 0.225 - sign * r / sb, 0.0];
            // ĝ = sign·y, n̂ = −z (the axis is behind the sheet).
            let axis = [0.0, sign * cb, -sb];
            for q in &p {
                let v = [0, 1, 2].map(|k| q[k] as f64 - apex[k]);
                let along = v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2];
                let off = [0, 1, 2].map(|k| v[k] - along * axis[k]);
                let off = (off[0] * off[0] + off[1] * off[1] + off[2] * off[2]).sqrt();
                assert!((off - along * sb / cb).abs() < 2e-5, "{q:?}: {off} from the axis at {along}");
            }
        }
    }

    /// A taper of 0 is the cylinder exactly; a tiny taper is nearly it.
    #[test]
    fn a_small_taper_tends_to_the_cylinder() {
        let (pos, rest, _) = trapezoid(41, 10);
        let (mut cyl, mut cone) = (pos.clone(), pos.clone());
        bend_piece(&mut cyl, &rest, &arm(150.0, true, 0.0, None)).unwrap();
        bend_piece(&mut cone, &rest, &arm(150.0, true, 1e-4, None)).unwrap();
        let gap = cyl
            .iter()
            .zip(&cone)
            .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max))
            .fold(0.0, f32::max);
        assert!(gap < 1e-4, "{gap}");
    }

    /// Degenerate cones are errors naming the setting: the apex inside the piece, a taper of
    /// 90 degrees or more, NaN, and a taper on the paper's rotation (which has no cone).
    #[test]
    fn degenerate_cones_are_errors_naming_the_taper() {
        let (pos, rest, _) = trapezoid(9, 5);
        let named = |q: BendParams| {
            let mut p = pos.clone();
            match bend_piece(&mut p, &rest, &q) {
                Err(TailorError::InvalidSetting { name, .. }) => name,
                other => panic!("{other:?}"),
            }
        };
        // 30 degrees with a 5 cm radius: the apex 10 cm below the axis point, inside the piece.
        assert_eq!(named(arm(90.0, true, 30.0, Some(0.05))), "taper_deg");
        assert_eq!(named(arm(90.0, true, -30.0, Some(0.05))), "taper_deg");
        assert_eq!(named(arm(90.0, true, 90.0, None)), "taper_deg");
        assert_eq!(named(arm(90.0, true, f64::NAN, None)), "taper_deg");
        assert_eq!(named(BendParams { mode: BendMode::Rotate, ..arm(90.0, true, 3.0, None) }), "taper_deg");
        assert_eq!(named(arm(90.0, true, 3.0, Some(-0.05))), "radius");
        assert_eq!(named(arm(90.0, true, 3.0, Some(0.0))), "radius");
        assert_eq!(named(arm(f64::NAN, true, 3.0, None)), "angle_deg");
    }
}
