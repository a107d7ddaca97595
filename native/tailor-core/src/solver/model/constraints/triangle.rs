//! Stretch and shear of a triangle against its flat 2D rest shape.
//!
//! With rest edge matrix `Dm = [r₁−r₀, r₂−r₀]` (2×2, from the pattern) and current edges
//! `Ds = [x₁−x₀, x₂−x₀]` (3×2), the deformation gradient is `F = Ds·Dm⁻¹ = [c₁ c₂]`: `c₁` is
//! the image of the pattern's x axis (warp), `c₂` of its y axis (weft). Both are linear in the
//! three positions, `c_j = Σₖ g[k][j]·xₖ`, with `g[1][j] = Dm⁻¹[0][j]`, `g[2][j] = Dm⁻¹[1][j]`,
//! `g[0][j] = −g[1][j] − g[2][j]`.
//!
//! * **Stretch** projects each column to unit length, `pⱼ = cⱼ/‖cⱼ‖`; energy
//!   `A/2 · Σⱼ kⱼ·(‖cⱼ‖−1)²` with `k₁` along the pattern's x axis (the fabric's `u`) and `k₂`
//!   along its y axis (`v`), so a uniaxial tension `T` (N/m) along `u` stretches by `ε = T/k₁`.
//!   A woven or knit fabric is anisotropic (the library's denim is 4.8 times stiffer along `v`
//!   than along `u`); an isotropic one has `k₁ = k₂`.
//! * **Shear** projects `(c₁, c₂)` onto the closest pair with `a·b = 0`. Lagrange conditions
//!   give `a = (c₁−λc₂)/(1−λ²)`, `b = (c₂−λc₁)/(1−λ²)` with `dλ² − sλ + d = 0`, `d = c₁·c₂`,
//!   `s = ‖c₁‖²+‖c₂‖²`; the root with `|λ| ≤ 1` is `λ = 2d / (s + √(s²−4d²))`.
//!
//! Both use the same `A`, so the system matrix gets `A·Σⱼ (kⱼ + k_sh)·gⱼgⱼᵀ` per triangle
//! (`(k_s + k_sh)·A·GGᵀ` when `k₁ = k₂ = k_s`).
//!
//! [`rhs_contributions_x4`] runs four triangles at once, one a lane: the projection is a chain
//! of dependent square roots and divisions (about 60 cycles of latency a triangle, measured as
//! the local step's hot spots), which four lanes pay once for four triangles. Each lane does the
//! scalar kernel's operations in the same order, so its results are bit for bit the same.

use glam::{BVec4A, Mat4, Vec3A, Vec4};

/// The triangles' strain constraints, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct TriangleSet {
    pub verts: Vec<[u32; 3]>,
    /// `g[k][j]`: coefficient of vertex k in column j of F.
    pub g: Vec<[[f32; 2]; 3]>,
    /// Stretch weight along the pattern's x axis (`u`), `k₁ · rest area`.
    pub w_stretch: Vec<f32>,
    /// Stretch weight along the pattern's y axis (`v`), `k₂ · rest area` (equal to `w_stretch`
    /// for an isotropic fabric).
    pub w_stretch_v: Vec<f32>,
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
        self.w_stretch_v.shrink_to_fit();
        self.w_shear.shrink_to_fit();
    }

    /// Heap bytes of the per-triangle arrays.
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.verts)
            + vec_bytes(&self.g)
            + vec_bytes(&self.w_stretch)
            + vec_bytes(&self.w_stretch_v)
            + vec_bytes(&self.w_shear)
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
pub fn columns(g: &[[f32; 2]; 3], x: [Vec3A; 3]) -> [Vec3A; 2] {
    [x[0] * g[0][0] + x[1] * g[1][0] + x[2] * g[2][0], x[0] * g[0][1] + x[1] * g[1][1] + x[2] * g[2][1]]
}

/// Stretch projection: each column to unit length.
#[inline(always)]
pub fn project_stretch(c: [Vec3A; 2]) -> [Vec3A; 2] {
    [unit_or_same(c[0]), unit_or_same(c[1])]
}

#[inline(always)]
fn unit_or_same(c: Vec3A) -> Vec3A {
    let l = c.length();
    if l > 1e-12 {
        c / l
    } else {
        c
    }
}

/// Shear projection: the closest pair of orthogonal vectors (see the module doc).
#[inline(always)]
pub fn project_shear(c: [Vec3A; 2]) -> [Vec3A; 2] {
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
/// vertices, where `qⱼ = w_sⱼ·p_stretchⱼ + w_sh·p_shearⱼ` (`ws`: the stretch weights along `u`
/// and `v`).
#[inline(always)]
pub fn rhs_contributions(g: &[[f32; 2]; 3], x: [Vec3A; 3], ws: [f32; 2], wsh: f32) -> [Vec3A; 3] {
    let c = columns(g, x);
    let ps = project_stretch(c);
    let ph = project_shear(c);
    let q = [ps[0] * ws[0] + ph[0] * wsh, ps[1] * ws[1] + ph[1] * wsh];
    [q[0] * g[0][0] + q[1] * g[0][1], q[0] * g[1][0] + q[1] * g[1][1], q[0] * g[2][0] + q[1] * g[2][1]]
}

/// Four triangles' local step, triangle `i` in lane `i` of every `Vec4`: `x[k]` holds vertex
/// `k`'s coordinates (`[x, y, z]` lanes), `g[k][j]` the coefficients, `ws` (along `u`, `v`) and
/// `wsh` the weights. Returns each triangle's three contributions, as [`rhs_contributions`]
/// would, bit for bit.
#[inline(always)]
pub fn rhs_contributions_x4(g: &[[Vec4; 2]; 3], x: &[[Vec4; 3]; 3], ws: [Vec4; 2], wsh: Vec4) -> [[Vec3A; 3]; 4] {
    // c[j][axis] = x0·g0j + x1·g1j + x2·g2j, left to right as `columns`.
    let c: [[Vec4; 3]; 2] =
        [0, 1].map(|j| [0, 1, 2].map(|a| x[0][a] * g[0][j] + x[1][a] * g[1][j] + x[2][a] * g[2][j]));
    let dot = |u: &[Vec4; 3], v: &[Vec4; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    // Stretch: `unit_or_same` per column.
    let ps = c.map(|cj| {
        let l = sqrt4(dot(&cj, &cj));
        let keep: BVec4A = l.cmpgt(Vec4::splat(1e-12));
        cj.map(|ca| Vec4::select(keep, ca / l, ca))
    });
    // Shear: `project_shear`.
    let d = dot(&c[0], &c[1]);
    let s = dot(&c[0], &c[0]) + dot(&c[1], &c[1]);
    let disc = (s * s - Vec4::splat(4.0) * d * d).max(Vec4::ZERO);
    let lambda = Vec4::splat(2.0) * d / (s + sqrt4(disc)).max(Vec4::splat(1e-30));
    let denom = Vec4::ONE - lambda * lambda;
    let keep_state = denom.cmplt(Vec4::splat(1e-6));
    let inv = Vec4::ONE / denom;
    let ph = [
        [0, 1, 2].map(|a| Vec4::select(keep_state, c[0][a], (c[0][a] - c[1][a] * lambda) * inv)),
        [0, 1, 2].map(|a| Vec4::select(keep_state, c[1][a], (c[1][a] - c[0][a] * lambda) * inv)),
    ];
    let q = [0, 1].map(|j| [0, 1, 2].map(|a| ps[j][a] * ws[j] + ph[j][a] * wsh));
    // Vertex k's contribution, lanes per axis, then transposed to one `Vec3A` a triangle.
    let mut out = [[Vec3A::ZERO; 3]; 4];
    for k in 0..3 {
        let o = [0, 1, 2].map(|a| q[0][a] * g[k][0] + q[1][a] * g[k][1]);
        let t = Mat4::from_cols(o[0], o[1], o[2], Vec4::ZERO).transpose();
        for (i, col) in [t.x_axis, t.y_axis, t.z_axis, t.w_axis].into_iter().enumerate() {
            out[i][k] = Vec3A::from_vec4(col);
        }
    }
    out
}

/// Lane-wise square root (correctly rounded, as `f32::sqrt`).
#[inline(always)]
fn sqrt4(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_loadu_ps, _mm_sqrt_ps, _mm_storeu_ps};
        let a = v.to_array();
        let mut r = [0.0f32; 4];
        // SAFETY: SSE2 is part of x86-64; both pointers are to 4 f32s.
        unsafe { _mm_storeu_ps(r.as_mut_ptr(), _mm_sqrt_ps(_mm_loadu_ps(a.as_ptr()))) };
        Vec4::from_array(r)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(v.to_array().map(f32::sqrt))
    }
}

/// Energy `Σⱼ w_sⱼ/2·‖cⱼ−p_sⱼ‖² + w_sh/2·Σ‖cⱼ−p_shⱼ‖²` (f64 for the error measures).
pub fn energy(g: &[[f32; 2]; 3], x: [Vec3A; 3], ws: [f32; 2], wsh: f32) -> f64 {
    let c = columns(g, x);
    let ps = project_stretch(c);
    let ph = project_shear(c);
    let es: f64 = (0..2).map(|j| ws[j] as f64 * (c[j] - ps[j]).length_squared() as f64).sum();
    let eh: f64 = (0..2).map(|j| (c[j] - ph[j]).length_squared() as f64).sum();
    0.5 * (es + wsh as f64 * eh)
}

/// The system matrix's entry of vertices `k`, `l` of one triangle: `Σⱼ (w_sⱼ + w_sh)·g[k][j]·g[l][j]`
/// (f64, as the assembly sums it). An isotropic triangle computes it as before anisotropy,
/// `(w_s + w_sh)·(g[k][0]·g[l][0] + g[k][1]·g[l][1])`, so its matrix is bit for bit the same.
#[inline]
pub fn matrix_entry(g: &[[f32; 2]; 3], k: usize, l: usize, ws: [f32; 2], wsh: f32) -> f64 {
    let gg = |j: usize| g[k][j] as f64 * g[l][j] as f64;
    if ws[0] == ws[1] {
        (ws[0] + wsh) as f64 * (gg(0) + gg(1))
    } else {
        (ws[0] + wsh) as f64 * gg(0) + (ws[1] + wsh) as f64 * gg(1)
    }
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
        let x = [a, b, c].map(|r| Vec3A::new(r[0] as f32, r[1] as f32, 0.0));
        let f = columns(&g, x);
        assert!((f[0] - Vec3A::X).length() < 1e-5 && (f[1] - Vec3A::Y).length() < 1e-5, "{f:?}");
        assert!(energy(&g, x, [1.0, 1.0], 1.0) < 1e-10);
    }

    #[test]
    fn shear_projection_is_orthogonal_and_closest() {
        let c = [Vec3A::new(1.0, 0.3, 0.1), Vec3A::new(0.5, 0.9, -0.2)];
        let p = project_shear(c);
        assert!(p[0].dot(p[1]).abs() < 1e-5);
        let dist = |q: [Vec3A; 2]| (q[0] - c[0]).length_squared() + (q[1] - c[1]).length_squared();
        // No orthogonal pair obtained by rotating p within its plane is closer.
        let n = p[0].cross(p[1]).normalize();
        for k in -20..=20 {
            let t = k as f32 * 0.01;
            let r = glam::Quat::from_axis_angle(n.into(), t);
            let q = [r * p[0], r * p[1]];
            assert!(dist(q) >= dist(p) - 1e-5, "rotation {t} is closer");
        }
    }

    #[test]
    fn stretch_projection_normalises() {
        let p = project_stretch([Vec3A::new(2.0, 0.0, 0.0), Vec3A::new(0.0, 0.5, 0.0)]);
        assert!((p[0].length() - 1.0).abs() < 1e-6 && (p[1].length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn degenerate_rest_is_rejected() {
        assert!(strain_coefficients([0.0, 0.0], [1.0, 0.0], [2.0, 0.0]).is_none());
    }

    #[test]
    fn four_lanes_are_the_scalar_kernel_bit_for_bit() {
        // Stretched, sheared, compressed, zero-length and parallel columns, in every lane.
        let (a, b, c) = rest();
        let g0 = strain_coefficients(a, b, c).unwrap();
        let g1 = strain_coefficients([0.0, 0.0], [0.01, 0.0], [0.003, 0.012]).unwrap();
        let mut seed = 7u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        };
        let mut cases: Vec<([[f32; 2]; 3], [Vec3A; 3], [f32; 2], f32)> = Vec::new();
        for k in 0..40 {
            let g = if k % 2 == 0 { g0 } else { g1 };
            let x = [0; 3].map(|_| Vec3A::new(next(), next(), next()));
            // Isotropic and anisotropic stretch weights, lane by lane.
            let wu = 1.0 + next();
            let wv = if k % 3 == 0 { wu } else { 1.0 + next() };
            cases.push((g, x, [wu, wv], 0.1 + next().abs()));
        }
        let p = Vec3A::new(0.2, 0.1, 0.3);
        cases.push((g0, [p; 3], [600.0, 600.0], 60.0)); // every column zero
        cases.push((g1, [p, p + Vec3A::X * 0.01, p + Vec3A::X * 0.01], [600.0, 150.0], 60.0)); // parallel columns
        for quad in cases.chunks_exact(4) {
            let lanes = |f: &dyn Fn(usize) -> f32| Vec4::new(f(0), f(1), f(2), f(3));
            let g = [0, 1, 2].map(|k| [0, 1].map(|j| lanes(&|i| quad[i].0[k][j])));
            let x = [0, 1, 2].map(|k| [0, 1, 2].map(|a| lanes(&|i| quad[i].1[k][a])));
            let ws = [0, 1].map(|j| lanes(&|i| quad[i].2[j]));
            let out = rhs_contributions_x4(&g, &x, ws, lanes(&|i| quad[i].3));
            for (i, (g, x, ws, wsh)) in quad.iter().enumerate() {
                let want = rhs_contributions(g, *x, *ws, *wsh);
                for k in 0..3 {
                    let (got, want) = (out[i][k].to_array().map(f32::to_bits), want[k].to_array().map(f32::to_bits));
                    assert_eq!(got, want, "lane {i}, vertex {k}");
                }
            }
        }
    }

    /// The anisotropic energy is the sum of each column's spring along its own axis: a rest
    /// triangle stretched by `ε` along `u` alone costs `w_u/2·ε²·(…)`, along `v` alone `w_v/2`;
    /// the local step's right-hand side is the energy's target (the gradient vanishes at the
    /// projections held fixed: `Σ g·q = Σⱼ (w_sⱼ + w_sh)·g·cⱼ` at rest).
    #[test]
    fn stretch_along_u_and_v_costs_its_own_stiffness() {
        let (a, b, c) = ([0.0, 0.0], [0.01, 0.0], [0.0, 0.01]);
        let g = strain_coefficients(a, b, c).unwrap();
        let at = |sx: f32, sy: f32| [a, b, c].map(|r| Vec3A::new(r[0] as f32 * sx, r[1] as f32 * sy, 0.0));
        let (wu, wv) = (4.0f32, 1.0f32);
        let eu = energy(&g, at(1.1, 1.0), [wu, wv], 0.0);
        let ev = energy(&g, at(1.0, 1.1), [wu, wv], 0.0);
        assert!((eu - 0.5 * 4.0 * 0.01).abs() < 1e-6, "{eu}");
        assert!((ev - 0.5 * 1.0 * 0.01).abs() < 1e-6, "{ev}");
        // At rest the right-hand side equals the matrix times the positions (a fixed point).
        let x = at(1.0, 1.0);
        let rhs = rhs_contributions(&g, x, [wu, wv], 0.5);
        for k in 0..3 {
            let ax: Vec3A = (0..3).map(|l| x[l] * matrix_entry(&g, k, l, [wu, wv], 0.5) as f32).sum();
            assert!((ax - rhs[k]).length() < 1e-3, "vertex {k}: {ax:?} against {:?}", rhs[k]);
        }
    }

    /// Isotropic weights give the matrix entries of the formula before anisotropy, bit for bit.
    #[test]
    fn isotropic_matrix_entries_are_unchanged() {
        let (a, b, c) = rest();
        let g = strain_coefficients(a, b, c).unwrap();
        for k in 0..3 {
            for l in 0..3 {
                let old =
                    (600.0f32 + 60.0) as f64 * (g[k][0] as f64 * g[l][0] as f64 + g[k][1] as f64 * g[l][1] as f64);
                assert_eq!(matrix_entry(&g, k, l, [600.0, 600.0], 60.0).to_bits(), old.to_bits());
            }
        }
    }
}
