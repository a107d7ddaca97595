//! The global step: Gauss-Seidel (or Jacobi) sweeps over the linear system
//! `(M/h² + L + C)·x = M/h²·y + b_const + Σ slots + C·t` (one scalar matrix, three right-hand
//! sides). Row `i` gives `xᵢ = (rᵢ − Σⱼ Lᵢⱼ xⱼ) / Dᵢ`.
//!
//! Gauss-Seidel runs colour by colour; within a colour no two particles share a matrix entry,
//! so their updates are independent and run in parallel (Vivace). Each sweep returns the
//! squared GS residual `Σ Dᵢ²‖Δxᵢ‖²` (the gradient of the objective at the partially updated
//! state) and the squared update norm `Σ‖Δxᵢ‖²`, summed in a fixed chunk order so results do
//! not depend on thread scheduling.

use glam::Vec3;
use rayon::prelude::*;

use super::soa::{SoaPtr, Vec3Soa};
use super::system::SparseSym32;

/// Particles per parallel task; fixed so that partial sums have a fixed order.
const CHUNK: usize = 256;

/// Borrowed view of everything one sweep reads.
pub(crate) struct GlobalSystem<'a> {
    pub matrix: &'a SparseSym32,
    /// `Dᵢ = mᵢ/h² + Lᵢᵢ` (without contacts).
    pub diag: &'a [f32],
    /// `mᵢ/h²·yᵢ + b_constᵢ`.
    pub rhs_fixed: &'a Vec3Soa,
    pub slots: &'a [Vec3],
    pub slot_offsets: &'a [u32],
    pub slot_index: &'a [u32],
    pub contact_weight: &'a [f32],
    pub contact_target: &'a Vec3Soa,
}

/// Squared residual and squared update norm of a sweep.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SweepNorms {
    pub residual2: f64,
    pub update2: f64,
}

impl SweepNorms {
    fn add(self, o: SweepNorms) -> SweepNorms {
        SweepNorms { residual2: self.residual2 + o.residual2, update2: self.update2 + o.update2 }
    }
}

impl GlobalSystem<'_> {
    /// The row solve: the new value of particle `i` given its neighbours (read via `get`) and
    /// the row's diagonal.
    #[inline(always)]
    fn row(&self, i: usize, get: impl Fn(usize) -> Vec3) -> (Vec3, f32) {
        let m = self.matrix;
        let mut r = self.rhs_fixed.get(i);
        for s in self.slot_offsets[i]..self.slot_offsets[i + 1] {
            r += self.slots[self.slot_index[s as usize] as usize];
        }
        for k in m.offsets[i] as usize..m.offsets[i + 1] as usize {
            r -= get(m.cols[k] as usize) * m.vals[k];
        }
        let mut d = self.diag[i];
        let cw = self.contact_weight[i];
        if cw > 0.0 {
            r += self.contact_target.get(i) * cw;
            d += cw;
        }
        (r / d, d)
    }

    /// One Gauss-Seidel sweep over the colour groups, in place.
    pub fn gauss_seidel(&self, groups: &[Vec<u32>], x: &mut Vec3Soa) -> SweepNorms {
        let xp = SoaPtr::new(x);
        let mut total = SweepNorms::default();
        for group in groups {
            let parts: Vec<SweepNorms> = group
                .par_chunks(CHUNK)
                .map(|chunk| {
                    let mut acc = SweepNorms::default();
                    for &i in chunk {
                        let i = i as usize;
                        // SAFETY: particles of one colour share no matrix entry, so this
                        // update reads only particles of other colours, which no thread writes
                        // during this colour; each particle is written by its own task only.
                        let (new, d) = self.row(i, |j| unsafe { xp.get(j) });
                        let old = unsafe { xp.get(i) };
                        unsafe { xp.set(i, new) };
                        let u2 = (new - old).length_squared() as f64;
                        acc.update2 += u2;
                        acc.residual2 += u2 * (d as f64) * (d as f64);
                    }
                    acc
                })
                .collect();
            total = parts.into_iter().fold(total, SweepNorms::add);
        }
        total
    }

    /// One under-relaxed Jacobi sweep: every row reads `old`, writes `x`.
    pub fn jacobi(&self, free: &[u32], old: &Vec3Soa, x: &mut Vec3Soa, relaxation: f32) -> SweepNorms {
        let xp = SoaPtr::new(x);
        let parts: Vec<SweepNorms> = free
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut acc = SweepNorms::default();
                for &i in chunk {
                    let i = i as usize;
                    let (target, d) = self.row(i, |j| old.get(j));
                    let o = old.get(i);
                    let new = o + (target - o) * relaxation;
                    // SAFETY: each index is written by one task; reads go to `old`.
                    unsafe { xp.set(i, new) };
                    let u2 = (new - o).length_squared() as f64;
                    acc.update2 += u2;
                    acc.residual2 += (target - o).length_squared() as f64 * (d as f64) * (d as f64);
                }
                acc
            })
            .collect();
        parts.into_iter().fold(SweepNorms::default(), SweepNorms::add)
    }
}

/// `x ← ω·(x − prev) + prev` for every particle (Chebyshev extrapolation).
pub(crate) fn extrapolate(x: &mut Vec3Soa, prev: &Vec3Soa, omega: f32) {
    for (xs, ps) in [(&mut x.x, &prev.x), (&mut x.y, &prev.y), (&mut x.z, &prev.z)] {
        xs.par_chunks_mut(4096).zip(ps.par_chunks(4096)).for_each(|(a, b)| {
            for (v, p) in a.iter_mut().zip(b) {
                *v = omega * (*v - p) + p;
            }
        });
    }
}
