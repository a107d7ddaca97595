//! The reference solver: the exact minimiser of one implicit step's objective, for tests and
//! benchmarks (never the real-time path).
//!
//! Projective Dynamics' local/global iteration is a monotone descent on the objective; with an
//! exact global solve it converges to the minimiser. Here the global solve is direct: the
//! constant matrix `M/h² + L + C` over the free particles is factored once (reverse
//! Cuthill-McKee ordering, envelope Cholesky in f64, `cholesky.rs`), and local/global
//! iterations, sped up by Anderson acceleration, run until the positions stop changing.

use std::time::Instant;

use crate::error::Result;
use crate::solver::accuracy::cholesky::{reverse_cuthill_mckee, Skyline};
use crate::solver::model::soa::Vec3Soa;
use crate::solver::simulation::Simulation;
use crate::solver::stages::local::project_all;

/// How the reference iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceInfo {
    pub iterations: u32,
    /// Largest position change in the last iteration, metres.
    pub last_change: f64,
    /// `‖∇E(x*)‖ / ‖∇E(x₀)‖`: how close to the true minimiser the reference is.
    pub gradient_rel: f64,
    pub seconds: f64,
    /// Stored entries of the Cholesky factor.
    pub envelope: usize,
}

impl Simulation {
    /// Solves the current step problem (after `predict`, contacts frozen) to convergence,
    /// starting from the current positions. Returns the solution.
    /// `observe(k, seconds, xₖ)` is called with each accepted iterate (1-based `k`; seconds
    /// since the start, factorisation included, the observer's own time excluded).
    pub(crate) fn reference_solve_observed(
        &mut self,
        max_iterations: u32,
        tol_m: f64,
        observe: &mut dyn FnMut(u32, f64, &Vec3Soa),
    ) -> Result<(Vec3Soa, ReferenceInfo)> {
        let t0 = Instant::now();
        let mut excluded = 0.0f64;
        let n = self.num_particles();
        let m = &self.model;
        // Free particles in RCM order over the free subgraph.
        let free: Vec<u32> = (0..n as u32).filter(|&i| !m.pinned[i as usize]).collect();
        let mut local = vec![u32::MAX; n];
        for (k, &i) in free.iter().enumerate() {
            local[i as usize] = k as u32;
        }
        let a = &m.matrix32;
        let mut off = vec![0u32];
        let mut adj = Vec::new();
        for &i in &free {
            let i = i as usize;
            adj.extend(
                a.cols[a.offsets[i] as usize..a.offsets[i + 1] as usize]
                    .iter()
                    .filter(|&&j| local[j as usize] != u32::MAX)
                    .map(|&j| local[j as usize]),
            );
            off.push(adj.len() as u32);
        }
        let perm = reverse_cuthill_mckee(&off, &adj);
        let mut pos = vec![0usize; free.len()];
        for (new, &old) in perm.iter().enumerate() {
            pos[old as usize] = new;
        }
        // Row `new` of the permuted matrix is free particle `free[perm[new]]`.
        let matrix = m.assemble_matrix();
        let diag: Vec<f64> = perm
            .iter()
            .map(|&k| {
                let i = free[k as usize] as usize;
                matrix.diag[i] + m.mass[i] as f64 / (self.h_prepared as f64).powi(2) + self.contacts.weight[i] as f64
            })
            .collect();
        let mat = &matrix;
        let factor = Skyline::factor(&diag, |new| {
            let i = free[perm[new] as usize] as usize;
            mat.row(i).filter_map(|k| {
                let j = local[mat.cols[k] as usize];
                (j != u32::MAX).then(|| (pos[j as usize], mat.vals[k]))
            })
        })?;

        // Unknowns as one f64 vector: coordinate d of free particle k at 3k + d.
        let nf = free.len();
        let to_soa = |v: &[f64], base: &Vec3Soa| {
            let mut out = base.clone();
            for (k, &i) in free.iter().enumerate() {
                out.set(i as usize, glam::Vec3::new(v[3 * k] as f32, v[3 * k + 1] as f32, v[3 * k + 2] as f32));
            }
            out
        };
        let mut x: Vec<f64> = free.iter().flat_map(|&i| self.x.get(i as usize).to_array().map(|c| c as f64)).collect();
        let base = self.x.clone();
        let mut slots = std::mem::take(&mut self.slots);
        let mut rhs = vec![0.0f64; nf];
        // The local/global map G(x) = (M/h² + L + C)⁻¹·b(x).
        let mut global = |this: &Self, x32: &Vec3Soa, slots: &mut Vec<glam::Vec3A>| -> Vec<f64> {
            project_all(&this.model, x32, slots);
            let m = &this.model;
            let mut out = vec![0.0f64; 3 * nf];
            for d in 0..3 {
                for (new, &k) in perm.iter().enumerate() {
                    let i = free[k as usize] as usize;
                    let mut r = this.rhs_fixed.get(i)[d] as f64;
                    for s in m.slots.particle_offsets[i]..m.slots.particle_offsets[i + 1] {
                        r += slots[m.slots.particle_slots[s as usize] as usize][d] as f64;
                    }
                    let w = this.contacts.weight[i];
                    if w > 0.0 {
                        r += w as f64 * this.contacts.target.get(i)[d] as f64;
                    }
                    // Pinned neighbours are known values: move them to the right-hand side.
                    for kk in mat.row(i) {
                        let j = mat.cols[kk] as usize;
                        if m.pinned[j] {
                            r -= mat.vals[kk] * x32.get(j)[d] as f64;
                        }
                    }
                    rhs[new] = r;
                }
                factor.solve(&mut rhs);
                for (new, &k) in perm.iter().enumerate() {
                    out[3 * k as usize + d] = rhs[new];
                }
            }
            out
        };
        let mut info = ReferenceInfo {
            iterations: 0,
            last_change: f64::INFINITY,
            gradient_rel: 0.0,
            seconds: 0.0,
            envelope: factor.envelope(),
        };
        // Anderson acceleration of the local/global map (Peng et al. 2018), with their
        // safeguard: an accelerated iterate that raises the objective is replaced by the plain
        // local/global step and the history restarts.
        const DEPTH: usize = 6;
        let mut hist_f: Vec<Vec<f64>> = Vec::new();
        let mut hist_g: Vec<Vec<f64>> = Vec::new();
        let (mut prev_f, mut prev_g): (Option<Vec<f64>>, Option<Vec<f64>>) = (None, None);
        let mut x32 = to_soa(&x, &base);
        let mut e_prev = self.objective(&x32);
        for it in 0..max_iterations {
            let g = global(self, &x32, &mut slots);
            let f: Vec<f64> = g.iter().zip(&x).map(|(a, b)| a - b).collect();
            let change = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            info.iterations = it + 1;
            info.last_change = change;
            if change < tol_m {
                x = g;
                break;
            }
            if let (Some(pf), Some(pg)) = (&prev_f, &prev_g) {
                hist_f.push(f.iter().zip(pf).map(|(a, b)| a - b).collect());
                hist_g.push(g.iter().zip(pg).map(|(a, b)| a - b).collect());
                if hist_f.len() > DEPTH {
                    hist_f.remove(0);
                    hist_g.remove(0);
                }
            }
            let mut candidate = g.clone();
            if let Some(gamma) = least_squares(&hist_f, &f) {
                for (c, dg) in gamma.iter().zip(&hist_g) {
                    for (v, d) in candidate.iter_mut().zip(dg) {
                        *v -= c * d;
                    }
                }
            }
            let cand32 = to_soa(&candidate, &base);
            let e_cand = self.objective(&cand32);
            if e_cand <= e_prev {
                x = candidate;
                x32 = cand32;
                e_prev = e_cand;
            } else {
                hist_f.clear();
                hist_g.clear();
                x32 = to_soa(&g, &base);
                e_prev = self.objective(&x32);
                x = g.clone();
            }
            prev_f = Some(f);
            prev_g = Some(g);
            let t = Instant::now();
            observe(it + 1, (t - t0).as_secs_f64() - excluded, &x32);
            excluded += t.elapsed().as_secs_f64();
        }
        let x32 = to_soa(&x, &base);
        self.slots = slots;
        info.seconds = t0.elapsed().as_secs_f64() - excluded;
        Ok((x32, info))
    }
}

/// Least-squares coefficients `γ = argmin ‖f − Σ γⱼ·dfⱼ‖` by the normal equations (with a tiny
/// Tikhonov term), or `None` without history or when the system is singular.
fn least_squares(df: &[Vec<f64>], f: &[f64]) -> Option<Vec<f64>> {
    let m = df.len();
    if m == 0 {
        return None;
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut a = vec![vec![0.0f64; m + 1]; m];
    for i in 0..m {
        for j in 0..m {
            a[i][j] = dot(&df[i], &df[j]);
        }
        a[i][i] *= 1.0 + 1e-10;
        a[i][m] = dot(&df[i], f);
    }
    // Gaussian elimination with partial pivoting on the small m×m system.
    for c in 0..m {
        let p = (c..m).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, p);
        let pivot = a[c].clone();
        for row in a.iter_mut().skip(c + 1) {
            let k = row[c] / pivot[c];
            for (v, p) in row.iter_mut().zip(&pivot).skip(c) {
                *v -= k * p;
            }
        }
    }
    let mut g = vec![0.0f64; m];
    for r in (0..m).rev() {
        let s: f64 = (r + 1..m).map(|c| a[r][c] * g[c]).sum();
        g[r] = (a[r][m] - s) / a[r][r];
    }
    g.iter().all(|v| v.is_finite()).then_some(g)
}
