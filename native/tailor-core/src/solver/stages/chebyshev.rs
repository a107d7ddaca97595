//! Chebyshev semi-iterative acceleration (Wang 2015) of the Gauss-Seidel sweeps.
//!
//! After a sweep produced `x̂ᵏ⁺¹`, the accelerated iterate is
//! `xᵏ⁺¹ = ωₖ₊₁·(x̂ᵏ⁺¹ − xᵏ⁻¹) + xᵏ⁻¹` with `ω = 1` for the first `S` (delay) iterations,
//! `ω_S = 2/(2−ρ²)`, then `ωₖ₊₁ = 4/(4−ρ²·ωₖ)`.
//!
//! **The rule for ρ.** ρ must approximate the spectral radius of the plain iteration. We take
//! the spectral radius of the Gauss-Seidel iteration matrix of the constant system
//! `M/h² + L` (same colour order as the solver), measured by power iteration: sweeps of the
//! homogeneous system `(M/h² + L)·e = 0` from a smooth start, `ρ_GS = ‖e_K‖/‖e_{K−1}‖`. It is
//! measured whenever the topology, the stiffness or `h` changes (never per substep), and
//! used as `ρ = min(safety·ρ_GS, max_rho)`: the local projections make the real iteration
//! slightly different from the linear one, and over-estimating ρ makes Chebyshev oscillate
//! while under-estimating it only loses some speed, hence `safety < 1`. A fixed ρ in the
//! settings overrides the measurement.
//!
//! **Restarts and the guard.** When an accelerated sweep's update norm grew over the last one,
//! that sweep is plain and the sequence starts again from `ω_S`. When an update outgrows the
//! substep's first sweep's [`RUNAWAY`] times, the extrapolation is running away from the
//! prediction it started from, and the substep ends in plain sweeps (which closed the seams
//! where the extrapolation diverged, below). The restart alone did not hold: it extrapolates again at once with
//! `ω_S ≈ 1.98` from the overshoot that grew, and on the skirt sample at 240 iterations a
//! substep that cycle (ω ≈ 1.98, 1.96, 1) grew a mode at the waist, where four seams meet, by
//! about 4 % an iteration until the step diverged at frame 23; with the seams at full stiffness
//! from the first step it diverged in the first frame, where plain Gauss-Seidel closes them to
//! 0.36 mm (`tests/test_solver.py`; docs/architecture.md has what else was measured).
//!
//! **The last iteration of the budget is a plain sweep** (ω = 1; a solve that a tolerance ends
//! earlier ends on an extrapolated iterate, as before): the substep ends on the Gauss-Seidel
//! update of the contacts detected for it rather than on an extrapolation past it. Where a
//! particle gains or loses a contact between iterations the extrapolated iterate swings to the
//! other side of the sweep (a sewn pair at an armhole alternated 0.2 / 3.5 mm from one
//! iteration to the next) and the frame froze whichever state the last iteration gave: the
//! add-on's shirt test scene had one frame at 1.15 mm with the extrapolated last iteration and
//! 0.25-0.51 mm at every frame with a plain one; the samples at rest kept their gaps (T-shirt
//! 0.66 / 0.74 mm median / worst over frames 6-11, skirt 0.50 / 0.53, trousers 0.39 / 0.48).

use rayon::prelude::*;

use crate::solver::model::settings::ChebyshevSettings;
use crate::solver::model::system::SparseSym32;

/// An update this many times the substep's first sweep's is a runaway: plain sweeps to the
/// substep's end. A converging substep's updates stay under its first sweep's, apart from the
/// few where contacts or self-collision change between sweeps (the layered sample's grow past
/// it, and ending its extrapolation there opened a seam 3.5 mm); a runaway passes any factor.
pub const RUNAWAY: f32 = 10.0;

/// Per-simulation Chebyshev state.
#[derive(Debug, Clone, Default)]
pub struct Chebyshev {
    /// Measured spectral radius of the Gauss-Seidel iteration (None until measured).
    pub rho_gs: Option<f32>,
    omega: f32,
    started: bool,
    last_delta: f32,
    /// The substep's first sweep's update norm.
    first_delta: f32,
    /// An update outgrew the first sweep's [`RUNAWAY`] times: plain sweeps to the substep's end.
    diverging: bool,
}

impl Chebyshev {
    /// Resets the per-substep ω sequence.
    pub fn begin_substep(&mut self) {
        self.omega = 1.0;
        self.started = false;
        self.last_delta = f32::INFINITY;
        self.first_delta = f32::INFINITY;
        self.diverging = false;
    }

    /// The radius that acceleration uses.
    pub fn rho(&self, s: &ChebyshevSettings) -> f32 {
        s.rho.unwrap_or_else(|| (self.rho_gs.unwrap_or(0.0) * s.safety).min(s.max_rho))
    }

    /// Returns the ω for iteration `k` of `iterations` whose sweep moved particles by `delta`
    /// (1 = none).
    pub fn omega(&mut self, k: u32, iterations: u32, delta: f32, s: &ChebyshevSettings) -> f32 {
        let grew = self.started && delta > self.last_delta;
        self.last_delta = delta;
        if k == 0 {
            self.first_delta = delta;
        } else if delta > RUNAWAY * self.first_delta {
            self.diverging = true;
        }
        let rho = self.rho(s);
        if k < s.delay || rho <= 0.0 || grew || self.diverging || k + 1 >= iterations {
            self.started = false;
            self.omega = 1.0;
            return 1.0;
        }
        let rho2 = rho * rho;
        self.omega = if self.started { 4.0 / (4.0 - rho2 * self.omega) } else { 2.0 / (2.0 - rho2) };
        self.started = true;
        self.omega
    }
}

/// Spectral radius of the Gauss-Seidel iteration matrix of `A = diag + offdiag(L)` with the
/// given colour order, by `sweeps` power-iteration sweeps (see the module doc). Particles not in
/// any group (pinned) are held at zero.
pub fn spectral_radius_gs(matrix: &SparseSym32, diag: &[f32], groups: &[Vec<u32>], sweeps: u32) -> f32 {
    let n = diag.len();
    // A smooth start (the slowest Gauss-Seidel modes are the smoothest) plus a little noise.
    let mut e: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * (((i as u64 * 2_654_435_761) % 1000) as f64 / 1000.0)).collect();
    let mut in_group = vec![false; n];
    groups.iter().flatten().for_each(|&i| in_group[i as usize] = true);
    for (i, v) in e.iter_mut().enumerate() {
        if !in_group[i] {
            *v = 0.0;
        }
    }
    let norm = |e: &[f64]| e.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut prev = norm(&e);
    let mut rho = 0.0;
    for _ in 0..sweeps {
        for g in groups {
            let updates: Vec<f64> = g
                .par_iter()
                .with_min_len(256)
                .map(|&i| {
                    let i = i as usize;
                    let mut r = 0.0f64;
                    for k in matrix.offsets[i] as usize..matrix.offsets[i + 1] as usize {
                        r -= matrix.vals[k] as f64 * e[matrix.cols[k] as usize];
                    }
                    r / diag[i] as f64
                })
                .collect();
            for (&i, u) in g.iter().zip(updates) {
                e[i as usize] = u;
            }
        }
        let nrm = norm(&e);
        if nrm < 1e-300 || prev < 1e-300 {
            return 0.0;
        }
        rho = nrm / prev;
        e.iter_mut().for_each(|v| *v /= nrm);
        prev = 1.0;
    }
    rho.min(0.9999) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ω sequence: `delay` plain sweeps, then 2/(2−ρ²) and the recurrence; a growth restarts
    /// it; an update larger than the first sweep's ends it for the substep; the budget's last
    /// sweep is plain.
    #[test]
    fn an_update_that_outgrows_the_first_ends_the_extrapolation() {
        let s = ChebyshevSettings { rho: Some(0.9), ..Default::default() };
        let mut c = Chebyshev::default();
        c.begin_substep();
        let deltas = [8.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.3, 0.2, 0.1, 81.0, 0.05, 0.01];
        let omegas: Vec<f32> = deltas.iter().enumerate().map(|(k, &d)| c.omega(k as u32, 12, d, &s)).collect();
        let first = 2.0 / (2.0 - 0.81);
        assert_eq!(&omegas[..4], &[1.0; 4], "the delay");
        assert_eq!((omegas[4], omegas[5]), (first, 4.0 / (4.0 - 0.81 * first)));
        assert_eq!(omegas[6], 1.0, "a growth restarts");
        assert_eq!((omegas[7], omegas[8]), (first, 4.0 / (4.0 - 0.81 * first)), "from the start");
        assert_eq!(&omegas[9..], &[1.0; 3], "past the first sweep's update: plain to the end");
        // The next substep extrapolates again.
        c.begin_substep();
        let again: Vec<f32> = deltas[..5].iter().enumerate().map(|(k, &d)| c.omega(k as u32, 12, d, &s)).collect();
        assert_eq!(again[4], first);
    }

    /// 1D Poisson matrix tridiag(−1, 2, −1): the Gauss-Seidel iteration matrix has spectral
    /// radius cos²(π/(n+1)) for any red-black (two-colour) order.
    #[test]
    fn power_iteration_recovers_the_gauss_seidel_radius_of_1d_poisson() {
        let n = 40usize;
        let mut offsets = vec![0u32];
        let (mut cols, mut vals) = (Vec::new(), Vec::new());
        for i in 0..n {
            if i > 0 {
                cols.push(i as u32 - 1);
                vals.push(-1.0);
            }
            if i + 1 < n {
                cols.push(i as u32 + 1);
                vals.push(-1.0);
            }
            offsets.push(cols.len() as u32);
        }
        let m = SparseSym32 { diag: vec![2.0; n], offsets, cols, vals };
        let groups = vec![(0..n as u32).step_by(2).collect(), (1..n as u32).step_by(2).collect()];
        let exact = (std::f64::consts::PI / (n as f64 + 1.0)).cos().powi(2) as f32;
        let est = spectral_radius_gs(&m, &m.diag, &groups, 400);
        assert!((est - exact).abs() < 2e-3, "estimated {est}, exact {exact}");
    }
}
