//! The global step: Gauss-Seidel (or Jacobi) sweeps over the linear system
//! `(M/h² + L + C)·x = M/h²·y + b_const + Σ slots + C·t` (one scalar matrix, three right-hand
//! sides). Row `i` gives `xᵢ = (rᵢ − Σⱼ Lᵢⱼ xⱼ) / Dᵢ`.
//!
//! Gauss-Seidel runs colour by colour; within a colour no two particles share a matrix entry,
//! so their updates are independent and run in parallel (Vivace). Each sweep returns the
//! squared GS residual `Σ Dᵢ²‖Δxᵢ‖²` (the gradient of the objective at the partially updated
//! state) and the squared update norm `Σ‖Δxᵢ‖²`, summed in a fixed chunk order so results do
//! not depend on thread scheduling.
//!
//! The sweep runs on an interleaved copy of the positions (`Vec3A`, 16 bytes per particle,
//! see [`AosPtr`]) rather than on the three coordinate arrays: a neighbour read is then one
//! aligned load from one cache line instead of three, and the `xⱼ·Lᵢⱼ` products are SSE
//! lane-wise operations. Lane-wise IEEE arithmetic gives bit-identical results to the scalar
//! code, so this changes speed only.

use glam::Vec3A;
use rayon::prelude::*;

use crate::solver::model::soa::{SoaPtr, Vec3Soa};
use crate::solver::model::system::SparseSym32;
use crate::solver::model::SweepRows;

/// Particles per parallel task; fixed so that partial sums have a fixed order.
const CHUNK: usize = 256;

/// Borrowed view of everything one sweep reads.
pub(crate) struct GlobalSystem<'a> {
    pub matrix: &'a SparseSym32,
    /// `Dᵢ = mᵢ/h² + Lᵢᵢ` (without contacts).
    pub diag: &'a [f32],
    /// `mᵢ/h²·yᵢ + b_constᵢ`.
    pub rhs_fixed: &'a Vec3Soa,
    pub slots: &'a [Vec3A],
    pub slot_offsets: &'a [u32],
    pub slot_index: &'a [u32],
    /// The same rows in sweep order (Gauss-Seidel).
    pub sweep: &'a SweepRows,
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
    /// the row's diagonal. The sums run in the same order as the scalar formula
    /// `(rhsᵢ + Σ slots − Σⱼ Lᵢⱼ·xⱼ + wᵢ·tᵢ) / (Dᵢ + wᵢ)`, lane by lane.
    #[inline(always)]
    pub(crate) fn row(&self, i: usize, get: impl Fn(usize) -> Vec3A) -> (Vec3A, f32) {
        let m = self.matrix;
        let slots = &self.slot_index[self.slot_offsets[i] as usize..self.slot_offsets[i + 1] as usize];
        let (a, b) = (m.offsets[i] as usize, m.offsets[i + 1] as usize);
        self.row_with(i, slots, &m.cols[a..b], &m.vals[a..b], get)
    }

    /// [`Self::row`] given the particle's slot list and off-diagonal entries.
    #[inline(always)]
    fn row_with(
        &self,
        i: usize,
        slots: &[u32],
        cols: &[u32],
        vals: &[f32],
        get: impl Fn(usize) -> Vec3A,
    ) -> (Vec3A, f32) {
        let mut r = Vec3A::from(self.rhs_fixed.get(i));
        for &s in slots {
            r += self.slots[s as usize];
        }
        for (&j, &l) in cols.iter().zip(vals) {
            r -= get(j as usize) * l;
        }
        let mut d = self.diag[i];
        let cw = self.contact_weight[i];
        if cw > 0.0 {
            r += Vec3A::from(self.contact_target.get(i)) * cw;
            d += cw;
        }
        (r / d, d)
    }

    /// One Gauss-Seidel sweep over the colour groups starting from `x`. The result is left in
    /// `work`, the interleaved copy (see the module doc); `x` is not modified, so the caller can
    /// use it as the previous iterate and write the result back with [`unpack`] or
    /// [`unpack_extrapolated`]. `parts` is scratch for the per-chunk sums; both buffers keep
    /// their allocations between calls.
    pub fn gauss_seidel(&self, x: &Vec3Soa, work: &mut Vec<Vec3A>, parts: &mut Vec<SweepNorms>) -> SweepNorms {
        pack(x, work);
        let xp = AosPtr(work.as_mut_ptr(), work.len());
        let sw = self.sweep;
        let mut total = SweepNorms::default();
        for c in sw.group_start.windows(2) {
            // Sweep positions of this colour, in chunks of CHUNK from the colour's start (the
            // same partition as chunking the colour's particle list).
            let (start, end) = (c[0] as usize, c[1] as usize);
            (start..end)
                .into_par_iter()
                .step_by(CHUNK)
                .map(|a| {
                    let mut acc = SweepNorms::default();
                    for p in a..(a + CHUNK).min(end) {
                        let i = sw.particle[p] as usize;
                        let (r0, r1) = (sw.row_offsets[p] as usize, sw.row_offsets[p + 1] as usize);
                        let (s0, s1) = (sw.slot_offsets[p] as usize, sw.slot_offsets[p + 1] as usize);
                        // SAFETY: particles of one colour share no matrix entry, so this
                        // update reads only particles of other colours, which no thread writes
                        // during this colour; each particle is written by its own task only.
                        let (new, d) =
                            self.row_with(i, &sw.slot_index[s0..s1], &sw.cols[r0..r1], &sw.vals[r0..r1], |j| unsafe {
                                xp.get(j)
                            });
                        let old = unsafe { xp.get(i) };
                        unsafe { xp.set(i, new) };
                        let u2 = (new - old).length_squared() as f64;
                        acc.update2 += u2;
                        acc.residual2 += u2 * (d as f64) * (d as f64);
                    }
                    acc
                })
                .collect_into_vec(parts);
            // Chunk order, not completion order: the sums do not depend on the thread count.
            total = parts.iter().copied().fold(total, SweepNorms::add);
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
                    let (target, d) = self.row(i, |j| Vec3A::from(old.get(j)));
                    let o = Vec3A::from(old.get(i));
                    let new = o + (target - o) * relaxation;
                    // SAFETY: each index is written by one task; reads go to `old`.
                    unsafe { xp.set(i, new.into()) };
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

/// Particles per task of the pack and unpack copies.
const COPY_CHUNK: usize = 4096;

/// `work ← x` in the interleaved layout.
fn pack(x: &Vec3Soa, work: &mut Vec<Vec3A>) {
    work.resize(x.len(), Vec3A::ZERO);
    work.par_chunks_mut(COPY_CHUNK).enumerate().for_each(|(c, out)| {
        let base = c * COPY_CHUNK;
        let (xs, ys, zs) = (&x.x[base..base + out.len()], &x.y[base..base + out.len()], &x.z[base..base + out.len()]);
        for (k, o) in out.iter_mut().enumerate() {
            *o = Vec3A::new(xs[k], ys[k], zs[k]);
        }
    });
}

/// `x ← work` back to the coordinate arrays.
pub(crate) fn unpack(work: &[Vec3A], x: &mut Vec3Soa) {
    let Vec3Soa { x: xs, y: ys, z: zs } = x;
    xs.par_chunks_mut(COPY_CHUNK)
        .zip(ys.par_chunks_mut(COPY_CHUNK))
        .zip(zs.par_chunks_mut(COPY_CHUNK))
        .zip(work.par_chunks(COPY_CHUNK))
        .for_each(|(((a, b), c), w)| {
            for k in 0..w.len() {
                a[k] = w[k].x;
                b[k] = w[k].y;
                c[k] = w[k].z;
            }
        });
}

/// A raw view of the interleaved positions that the sweep writes through; same safety
/// contract as [`SoaPtr`].
#[derive(Clone, Copy)]
struct AosPtr(*mut Vec3A, usize);

unsafe impl Send for AosPtr {}
unsafe impl Sync for AosPtr {}

impl AosPtr {
    #[inline(always)]
    unsafe fn get(&self, i: usize) -> Vec3A {
        debug_assert!(i < self.1);
        *self.0.add(i)
    }

    #[inline(always)]
    unsafe fn set(&self, i: usize, v: Vec3A) {
        debug_assert!(i < self.1);
        *self.0.add(i) = v;
    }
}

/// `prev ← ω·(work − prev) + prev` for every particle: Chebyshev's extrapolation of the swept
/// iterate `work` against the iterate before last, written over the latter (the caller then
/// swaps it in as the new iterate). Fusing it into the copy back saves a pass over the
/// positions and a copy of the previous iterate per iteration.
pub(crate) fn unpack_extrapolated(work: &[Vec3A], prev: &mut Vec3Soa, omega: f32) {
    let Vec3Soa { x: xs, y: ys, z: zs } = prev;
    xs.par_chunks_mut(COPY_CHUNK)
        .zip(ys.par_chunks_mut(COPY_CHUNK))
        .zip(zs.par_chunks_mut(COPY_CHUNK))
        .zip(work.par_chunks(COPY_CHUNK))
        .for_each(|(((a, b), c), w)| {
            for k in 0..w.len() {
                a[k] = omega * (w[k].x - a[k]) + a[k];
                b[k] = omega * (w[k].y - b[k]) + b[k];
                c[k] = omega * (w[k].z - c[k]) + c[k];
            }
        });
}
