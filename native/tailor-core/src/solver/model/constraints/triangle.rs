//! Stretch and shear of a triangle against its flat 2D rest shape.
//!
//! With rest edge matrix `Dm = [r₁−r₀, r₂−r₀]` (2×2, from the pattern) and current edges
//! `Ds = [x₁−x₀, x₂−x₀]` (3×2), the deformation gradient is `F = Ds·Dm⁻¹ = [c₁ c₂]`: `c₁` is
//! the image of the pattern's x axis (warp), `c₂` of its y axis (weft). Both are linear in the
//! three positions, `c_j = Σₖ g[k][j]·xₖ`, with `g[1][j] = Dm⁻¹[0][j]`, `g[2][j] = Dm⁻¹[1][j]`,
//! `g[0][j] = −g[1][j] − g[2][j]`.
//!
//! * **Stretch** projects each column to unit length, `pⱼ = cⱼ/‖cⱼ‖`; energy
//!   `k_s·A/2 · Σⱼ (‖cⱼ‖−1)²`, so a uniaxial tension `T` (N/m) stretches by `ε = T/k_s`.
//! * **Shear** projects `(c₁, c₂)` onto the closest pair with `a·b = 0`. Lagrange conditions
//!   give `a = (c₁−λc₂)/(1−λ²)`, `b = (c₂−λc₁)/(1−λ²)` with `dλ² − sλ + d = 0`, `d = c₁·c₂`,
//!   `s = ‖c₁‖²+‖c₂‖²`; the root with `|λ| ≤ 1` is `λ = 2d / (s + √(s²−4d²))`.
//!
//! Both use the same `A`, so the system matrix gets `(k_s + k_sh)·A · G Gᵀ` per triangle.

use glam::Vec3;

/// The triangles' strain constraints, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct TriangleSet {
    pub verts: Vec<[u32; 3]>,
    /// `g[k][j]`: coefficient of vertex k in column j of F.
    pub g: Vec<[[f32; 2]; 3]>,
    /// Stretch weight `k_s · rest area`.
    pub w_stretch: Vec<f32>,
    /// Shear weight `k_sh · rest area`.
    pub w_shear: Vec<f32>,
}

impl TriangleSet {
    pub fn len(&self) -> usize {
        self.verts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.verts.is_empty()
    }

    /// Releases unused capacity (after building by pushing).
    pub fn shrink_to_fit(&mut self) {
        self.verts.shrink_to_fit();
        self.g.shrink_to_fit();
        self.w_stretch.shrink_to_fit();
        self.w_shear.shrink_to_fit();
    }

    /// Heap bytes of the per-triangle arrays.
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.verts) + vec_bytes(&self.g) + vec_bytes(&self.w_stretch) + vec_bytes(&self.w_shear)
    }
}

/// The F-coefficients `g` of a rest triangle (see the module doc). `None` if degenerate.
pub fn strain_coefficients(r0: [f64; 2], r1: [f64; 2], r2: [f64; 2]) -> Option<[[f32; 2]; 3]> {
    let (d1x, d1y) = (r1[0] - r0[0], r1[1] - r0[1]);
    let (d2x, d2y) = (r2[0] - r0[0], r2[1] - r0[1]);
    let det = d1x * d2y - d2x * d1y;
    if det.abs() < 1e-14 {
        return None;
    }
    // Dm⁻¹ = 1/det · [[d2y, −d2x], [−d1y, d1x]], rows indexed by the edge, columns by the axis.
    let inv = [[d2y / det, -d2x / det], [-d1y / det, d1x / det]];
    let mut g = [[0.0f32; 2]; 3];
    for j in 0..2 {
        g[1][j] = inv[0][j] as f32;
        g[2][j] = inv[1][j] as f32;
        g[0][j] = -(inv[0][j] + inv[1][j]) as f32;
    }
    Some(g)
}

/// The columns `c₁, c₂` of F.
#[inline(always)]
pub fn columns(g: &[[f32; 2]; 3], x: [Vec3; 3]) -> [Vec3; 2] {
    [x[0] * g[0][0] + x[1] * g[1][0] + x[2] * g[2][0], x[0] * g[0][1] + x[1] * g[1][1] + x[2] * g[2][1]]
}

/// Stretch projection: each column to unit length.
#[inline(always)]
pub fn project_stretch(c: [Vec3; 2]) -> [Vec3; 2] {
    [unit_or_same(c[0]), unit_or_same(c[1])]
}

#[inline(always)]
fn unit_or_same(c: Vec3) -> Vec3 {
    let l = c.length();
    if l > 1e-12 {
        c / l
    } else {
        c
    }
}

/// Shear projection: the closest pair of orthogonal vectors (see the module doc).
#[inline(always)]
pub fn project_shear(c: [Vec3; 2]) -> [Vec3; 2] {
    let d = c[0].dot(c[1]);
    let s = c[0].length_squared() + c[1].length_squared();
    let disc = (s * s - 4.0 * d * d).max(0.0);
    let lambda = 2.0 * d / (s + disc.sqrt()).max(1e-30);
    let denom = 1.0 - lambda * lambda;
    if denom < 1e-6 {
        // Parallel columns of equal length: every rotation is as close; keep the state.
        return c;
    }
    let inv = 1.0 / denom;
    [(c[0] - c[1] * lambda) * inv, (c[1] - c[0] * lambda) * inv]
}

/// Local step of one triangle: the right-hand-side contributions `Σⱼ g[k][j]·qⱼ` for its three
/// vertices, where `qⱼ = w_s·p_stretchⱼ + w_sh·p_shearⱼ`.
#[inline(always)]
pub fn rhs_contributions(g: &[[f32; 2]; 3], x: [Vec3; 3], ws: f32, wsh: f32) -> [Vec3; 3] {
    let c = columns(g, x);
    let ps = project_stretch(c);
    let ph = project_shear(c);
    let q = [ps[0] * ws + ph[0] * wsh, ps[1] * ws + ph[1] * wsh];
    [q[0] * g[0][0] + q[1] * g[0][1], q[0] * g[1][0] + q[1] * g[1][1], q[0] * g[2][0] + q[1] * g[2][1]]
}

/// Energy `w_s/2·Σ‖cⱼ−p_sⱼ‖² + w_sh/2·Σ‖cⱼ−p_shⱼ‖²` (f64 for the error measures).
pub fn energy(g: &[[f32; 2]; 3], x: [Vec3; 3], ws: f32, wsh: f32) -> f64 {
    let c = columns(g, x);
    let ps = project_stretch(c);
    let ph = project_shear(c);
    let es: f64 = (0..2).map(|j| (c[j] - ps[j]).length_squared() as f64).sum();
    let eh: f64 = (0..2).map(|j| (c[j] - ph[j]).length_squared() as f64).sum();
    0.5 * (ws as f64 * es + wsh as f64 * eh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rest() -> ([f64; 2], [f64; 2], [f64; 2]) {
        ([0.1, 0.2], [0.4, 0.25], [0.15, 0.6])
    }

    #[test]
    fn f_is_identity_on_the_rest_shape() {
        let (a, b, c) = rest();
        let g = strain_coefficients(a, b, c).unwrap();
        let x = [a, b, c].map(|r| Vec3::new(r[0] as f32, r[1] as f32, 0.0));
        let f = columns(&g, x);
        assert!((f[0] - Vec3::X).length() < 1e-5 && (f[1] - Vec3::Y).length() < 1e-5, "{f:?}");
        assert!(energy(&g, x, 1.0, 1.0) < 1e-10);
    }

    #[test]
    fn shear_projection_is_orthogonal_and_closest() {
        let c = [Vec3::new(1.0, 0.3, 0.1), Vec3::new(0.5, 0.9, -0.2)];
        let p = project_shear(c);
        assert!(p[0].dot(p[1]).abs() < 1e-5);
        let dist = |q: [Vec3; 2]| (q[0] - c[0]).length_squared() + (q[1] - c[1]).length_squared();
        // No orthogonal pair obtained by rotating p within its plane is closer.
        let n = p[0].cross(p[1]).normalize();
        for k in -20..=20 {
            let t = k as f32 * 0.01;
            let r = glam::Quat::from_axis_angle(n, t);
            let q = [r * p[0], r * p[1]];
            assert!(dist(q) >= dist(p) - 1e-5, "rotation {t} is closer");
        }
    }

    #[test]
    fn stretch_projection_normalises() {
        let p = project_stretch([Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0)]);
        assert!((p[0].length() - 1.0).abs() < 1e-6 && (p[1].length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn degenerate_rest_is_rejected() {
        assert!(strain_coefficients([0.0, 0.0], [1.0, 0.0], [2.0, 0.0]).is_none());
    }
}
