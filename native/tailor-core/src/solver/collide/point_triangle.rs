//! The point-triangle contact between a cloth particle and a cloth triangle: a one-sided
//! distance that keeps the particle on the side of the triangle it started the substep on
//! (issue 23; Bridson et al. 2002's proximity impulse, as a position-based projection).
//!
//! A particle `p` and a triangle `(a, b, c)` of the cloth, `n` the triangle's unit normal,
//! `(u, v, w)` the barycentrics of `p`'s projection onto its plane, `q = u·a + v·b + w·c`, and
//! `σ ∈ {−1, +1}` the side of the plane `p` was on at the start of the substep:
//!
//! ```text
//! C(p, a, b, c) = σ·(p − q)·n − h  ≥ 0        where u, v, w ≥ 0 (p over the triangle)
//! ```
//!
//! Holding `n` and `(u, v, w)` fixed (the usual linearisation), `∇ₚC = σn`, `∇ₐC = −u·σn`,
//! `∇_b C = −v·σn`, `∇_c C = −w·σn`, and the projection with inverse masses `wₚ, wₐ, w_b, w_c`
//! moves each point along its gradient by
//!
//! ```text
//! s = −C / (wₚ + u²wₐ + v²w_b + w²w_c),    Δp = wₚ·s·σn,   Δa = −u·wₐ·s·σn,  …
//! ```
//!
//! so that `C = 0` after it (the distance is exactly `h` on the right side). Because `σ` comes
//! from the substep's start and not from where the iterations have taken `p`, a particle that
//! an iteration carried through the triangle is carried back: the contact does not miss a
//! crossing between two iterations, as a test of the current distance alone would (a sphere
//! pair pushes a crossed particle further through).
//!
//! Friction acts at the position level as for the spheres and the body (Macklin et al. 2014,
//! Eq. 24) on the motion over the substep of `p` relative to the triangle's point `q`,
//! `r = (p − p₀) − Σ uᵢ(xᵢ − xᵢ₀)`: its tangential part `r_t` is removed when `|r_t| ≤ μs·d`,
//! else shortened by `μk·d`, `d = −C` the depth. The same weights split it, so the relative
//! motion changes by exactly the friction displacement.

use glam::Vec3;

/// One contact's inputs: current and substep-start positions of the particle and of the
/// triangle's corners, `[p, a, b, c]`.
#[derive(Debug, Clone, Copy)]
pub struct PointTriangle {
    pub x: [Vec3; 4],
    pub x_start: [Vec3; 4],
    /// Inverse masses `[wₚ, wₐ, w_b, w_c]` (0: pinned).
    pub inv_mass: [f32; 4],
    /// `σ`: the side of the triangle's plane the particle keeps (+1 in front, −1 behind; 0:
    /// none recorded, the side it is on now).
    pub side: f32,
    /// `h`: the distance kept from the triangle.
    pub thickness: f32,
    /// Static and kinetic friction coefficients.
    pub friction: (f32, f32),
}

/// The unit normal of the triangle `(a, b, c)` by its winding, `None` when degenerate.
#[inline]
fn unit_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    let n = (b - a).cross(c - a);
    let l2 = n.length_squared();
    (l2 > 1e-24).then(|| n / l2.sqrt())
}

/// Barycentrics of `p`'s projection onto the plane of `(a, b, c)` (unit normal `n`).
#[inline]
fn plane_barycentrics(p: Vec3, a: Vec3, b: Vec3, c: Vec3, n: Vec3) -> [f32; 3] {
    let area2 = (b - a).cross(c - a).dot(n);
    let u = (b - p).cross(c - p).dot(n) / area2;
    let v = (c - p).cross(a - p).dot(n) / area2;
    [u, v, 1.0 - u - v]
}

/// The side `σ` of the triangle's plane that `p` is on, `None` when the triangle is
/// degenerate or `p` lies in its plane (to rounding): the caller then takes another rule.
pub fn side_of(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let n = unit_normal(a, b, c)?;
    let s = (p - a).dot(n);
    (s.abs() > 1e-7).then(|| s.signum())
}

/// [`side_of`] where `p` is over the triangle (its projection inside it), else `None`.
pub fn side_over(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let n = unit_normal(a, b, c)?;
    if plane_barycentrics(p, a, b, c, n).iter().any(|&t| !(t >= 0.0)) {
        return None;
    }
    side_of(p, a, b, c)
}

/// Whether a particle at `p` on side `side` (0: the one it is on) of the triangle `abc` is
/// closer than `h` to it, over it: the contact's test on current positions alone, so that a
/// pass can skip the rest of [`project`] for the many listed pairs that do not act.
#[inline]
pub fn touches(p: Vec3, [a, b, c]: [Vec3; 3], side: f32, h: f32) -> bool {
    depth_over(p, a, b, c, side, h).is_some()
}

/// `(n, barycentrics, σ, depth)` of a particle closer than `h` over the triangle, else `None`.
#[inline]
fn depth_over(p: Vec3, a: Vec3, b: Vec3, c: Vec3, side: f32, h: f32) -> Option<(Vec3, [f32; 3], f32, f32)> {
    let n = unit_normal(a, b, c)?;
    let offset = (p - a).dot(n);
    // Cheap rejection first: farther than `h` from the plane on the kept side.
    if side != 0.0 && offset * side >= h {
        return None;
    }
    let bary = plane_barycentrics(p, a, b, c, n);
    if bary.iter().any(|&t| !(t >= 0.0)) {
        return None;
    }
    let side = if side != 0.0 {
        side
    } else if offset < 0.0 {
        -1.0
    } else {
        1.0
    };
    let depth = h - offset * side;
    (depth > 0.0).then_some((n, bary, side, depth))
}

/// The corrections `[Δp, Δa, Δb, Δc]` of one contact, `None` when it does not act: `p` is
/// not over the triangle, is at least `h` away on its side, or nothing can move.
pub fn project(k: &PointTriangle) -> Option<[Vec3; 4]> {
    let [p, a, b, c] = k.x;
    let (n, bary, side, depth) = depth_over(p, a, b, c, k.side, k.thickness)?;
    // A triangle turned over since the substep's start (crushed through itself) has no side
    // left to keep: its normal now points to the other side, and the side σ would push the
    // particle through it.
    let [p0, a0, b0, c0] = k.x_start;
    if k.side != 0.0 && (b0 - a0).cross(c0 - a0).dot(n) <= 0.0 {
        return None;
    }
    let nrm = n * side;
    let [wp, wa, wb, wc] = k.inv_mass;
    let denom = wp + bary[0] * bary[0] * wa + bary[1] * bary[1] * wb + bary[2] * bary[2] * wc;
    if !(denom > 0.0) {
        return None;
    }
    let mut corr = nrm * depth;
    let rel = (p - p0) - ((a - a0) * bary[0] + (b - b0) * bary[1] + (c - c0) * bary[2]);
    let rel_t = rel - nrm * rel.dot(nrm);
    let lt = rel_t.length();
    let (mu_s, mu_k) = k.friction;
    if lt > 0.0 {
        corr -= if lt <= mu_s * depth { rel_t } else { rel_t * (mu_k * depth / lt).min(1.0) };
    }
    let s = corr / denom;
    Some([s * wp, -s * (bary[0] * wa), -s * (bary[1] * wb), -s * (bary[2] * wc)])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contact(p: Vec3, side: f32) -> PointTriangle {
        let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        PointTriangle {
            x: [p, tri[0], tri[1], tri[2]],
            x_start: [p, tri[0], tri[1], tri[2]],
            inv_mass: [1.0; 4],
            side,
            thickness: 0.01,
            friction: (0.0, 0.0),
        }
    }

    fn apply(k: &PointTriangle, d: [Vec3; 4]) -> [Vec3; 4] {
        [k.x[0] + d[0], k.x[1] + d[1], k.x[2] + d[2], k.x[3] + d[3]]
    }

    fn signed_distance(x: [Vec3; 4]) -> f32 {
        let n = unit_normal(x[1], x[2], x[3]).unwrap();
        (x[0] - x[1]).dot(n)
    }

    #[test]
    fn a_close_particle_ends_exactly_the_thickness_away_on_its_side() {
        for (z, side) in [(0.004, 1.0), (-0.004, -1.0)] {
            let k = contact(Vec3::new(0.2, 0.3, z), side);
            let x = apply(&k, project(&k).unwrap());
            assert!((signed_distance(x) - side * 0.01).abs() < 1e-6, "{}", signed_distance(x));
        }
    }

    #[test]
    fn a_particle_carried_through_goes_back_to_the_side_it_started_on() {
        // Started in front (σ = +1), an iteration put it 3 mm behind: it returns to 1 cm in front.
        let k = contact(Vec3::new(0.2, 0.3, -0.003), 1.0);
        let x = apply(&k, project(&k).unwrap());
        assert!((signed_distance(x) - 0.01).abs() < 1e-6);
    }

    #[test]
    fn without_a_recorded_side_the_particle_keeps_the_one_it_is_on() {
        for z in [0.004, -0.004] {
            let k = contact(Vec3::new(0.2, 0.3, z), 0.0);
            let x = apply(&k, project(&k).unwrap());
            assert!((signed_distance(x) - z.signum() * 0.01).abs() < 1e-6);
        }
    }

    #[test]
    fn far_or_outside_the_triangle_does_nothing() {
        assert!(project(&contact(Vec3::new(0.2, 0.3, 0.02), 1.0)).is_none());
        assert!(project(&contact(Vec3::new(0.8, 0.8, 0.001), 1.0)).is_none());
        assert!(project(&contact(Vec3::new(-0.1, 0.3, 0.001), 1.0)).is_none());
    }

    #[test]
    fn momentum_is_kept_and_a_pinned_triangle_moves_only_the_particle() {
        let k = contact(Vec3::new(0.2, 0.3, 0.002), 1.0);
        let d = project(&k).unwrap();
        // Equal masses: the corrections sum to zero (no net push on the pair).
        assert!((d[0] + d[1] + d[2] + d[3]).length() < 1e-7);
        let mut pinned = k;
        pinned.inv_mass = [1.0, 0.0, 0.0, 0.0];
        let d = project(&pinned).unwrap();
        assert_eq!(d[1..], [Vec3::ZERO; 3]);
        assert!((d[0] - Vec3::new(0.0, 0.0, 0.008)).length() < 1e-7);
    }

    #[test]
    fn friction_stops_a_small_slide_and_shortens_a_long_one() {
        let mut k = contact(Vec3::new(0.2, 0.3, 0.002), 1.0);
        k.inv_mass = [1.0, 0.0, 0.0, 0.0];
        k.friction = (0.5, 0.25);
        // Slid 2 mm along x this substep, depth 8 mm: under μs·d = 4 mm, so it is undone.
        k.x_start[0] = k.x[0] - Vec3::new(0.002, 0.0, 0.0);
        let d = project(&k).unwrap();
        assert!((d[0].x + 0.002).abs() < 1e-7);
        // Slid 10 mm: shortened by μk·d = 2 mm.
        k.x_start[0] = k.x[0] - Vec3::new(0.01, 0.0, 0.0);
        let d = project(&k).unwrap();
        assert!((d[0].x + 0.002).abs() < 1e-7, "{}", d[0].x);
    }

    #[test]
    fn the_side_is_undecided_in_the_plane_and_for_a_degenerate_triangle() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert_eq!(side_of(Vec3::new(0.2, 0.2, 0.1), a, b, c), Some(1.0));
        assert_eq!(side_of(Vec3::new(0.2, 0.2, -0.1), a, b, c), Some(-1.0));
        assert_eq!(side_of(Vec3::new(0.2, 0.2, 0.0), a, b, c), None);
        assert_eq!(side_of(Vec3::new(0.2, 0.2, 0.1), a, b, b * 2.0), None);
        // Beside the triangle: no side over it.
        assert_eq!(side_over(Vec3::new(0.9, 0.9, 0.1), a, b, c), None);
        assert_eq!(side_over(Vec3::new(0.2, 0.2, -0.1), a, b, c), Some(-1.0));
    }
}
