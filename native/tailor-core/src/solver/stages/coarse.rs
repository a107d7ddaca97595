//! A two-level global step: after each Gauss-Seidel sweep, the error's smooth part is removed on
//! a coarse grid of particle aggregates (aggregation multigrid's coarse correction).
//!
//! Gauss-Seidel removes an error component in a number of sweeps that grows with the mesh's
//! resolution for the smoothest components (bending a whole panel is one): on a strip of 2 mm
//! edges the bending that 8 × 15 sweeps should resist is barely felt (`docs/accuracy.md`, "The
//! standard tests"). The coarse correction solves for those components directly:
//!
//! * aggregates `I` of neighbouring free particles (each free particle with its unaggregated
//!   matrix neighbours, greedily; leftovers join a neighbour's), `P` the piecewise-constant
//!   prolongation (`P[i, I] = 1` for `i ∈ I`);
//! * the residual `r = b − A x` of the sweep's system (`A = M/h² + L + C`, `b` its right-hand
//!   side with this iteration's projections), restricted `r_c = Pᵀ r`;
//! * `A_c e = r_c` with the Galerkin matrix `A_c = Pᵀ A P` (its entries sums of `A`'s over
//!   aggregate pairs; the contacts' diagonal `C` adds to an aggregate's diagonal), solved by
//!   conjugate gradients, and `x ← x + P e`.
//!
//! `A` is symmetric positive definite, so with `e` exact the correction is the `A`-orthogonal
//! projection of the error onto the coarse space: it never increases the error's energy norm.

use glam::Vec3A;
use rayon::prelude::*;

use super::global::GlobalSystem;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::system::SparseSym32;

/// The aggregate of a pinned particle (in none); the GPU's `coarse.wgsl` reads the same value.
pub(crate) const NONE: u32 = u32::MAX;
const DIAG: u32 = u32::MAX - 1;

/// The two-level step's coarse correction follows every sweep, with at most this many
/// diagonally preconditioned conjugate-gradient iterations on the coarse grid. Measured on the
/// cantilever of `tests/solver_physics.rs` at Final (the chord's angle; beam theory 41.5°, plain
/// 89.5°): after every sweep 55.6°, every second 71.6°, every third 79.2°; 5 iterations 78.7°,
/// 10 and 30 both 55.6° (without the preconditioner 10 gave 70.1°).
pub(crate) const COARSE_CG_ITERATIONS: usize = 10;

/// Particles per parallel task of the residual (a small garment's runs on one thread: waking the
/// pool for it cost more than the rows).
const RESIDUAL_CHUNK: usize = 4096;

/// The coarse grid of one model (rebuilt with it) and its values for one substep length.
#[derive(Debug, Default)]
pub(crate) struct CoarseLevel {
    /// Aggregate of each particle (`NONE`: pinned).
    agg: Vec<u32>,
    n_c: usize,
    offsets: Vec<u32>,
    cols: Vec<u32>,
    vals: Vec<f32>,
    /// `Σ_{i,j∈I} A_ij` without contacts.
    diag0: Vec<f32>,
    /// For each off-diagonal entry of the fine matrix: its coarse entry, `DIAG` or `NONE`.
    fine_map: Vec<u32>,
    // Scratch.
    diag: Vec<f32>,
    rc: Vec<Vec3A>,
    /// The inverse of the coarse diagonal (the CG's preconditioner).
    inv: Vec<f32>,
    e: Vec<Vec3A>,
    p: Vec<Vec3A>,
    q: Vec<Vec3A>,
    res: Vec<Vec3A>,
}

/// A coarse grid as the GPU reads it ([`CoarseLevel::gpu_layout`]).
#[cfg(feature = "gpu")]
pub(crate) struct CoarseLayout<'a> {
    pub agg: &'a [u32],
    pub member_offsets: Vec<u32>,
    pub members: Vec<u32>,
    pub offsets: &'a [u32],
    pub cols: &'a [u32],
    pub vals: &'a [f32],
    pub diag0: &'a [f32],
}

impl CoarseLevel {
    /// Aggregates the free particles `free` (sorted) of `matrix`'s graph.
    pub fn build(matrix: &SparseSym32, free: &[u32]) -> Self {
        let n = matrix.offsets.len() - 1;
        let mut agg = vec![NONE; n];
        let mut is_free = vec![false; n];
        for &i in free {
            is_free[i as usize] = true;
        }
        let row = |i: usize| &matrix.cols[matrix.offsets[i] as usize..matrix.offsets[i + 1] as usize];
        let mut n_c = 0u32;
        for &i in free {
            let i = i as usize;
            if agg[i] != NONE || row(i).iter().any(|&j| agg[j as usize] != NONE) {
                continue;
            }
            agg[i] = n_c;
            for &j in row(i) {
                if is_free[j as usize] {
                    agg[j as usize] = n_c;
                }
            }
            n_c += 1;
        }
        // Leftovers join the aggregate of a neighbour (or start their own when isolated).
        for &i in free {
            let i = i as usize;
            if agg[i] == NONE {
                agg[i] = row(i).iter().map(|&j| agg[j as usize]).find(|&a| a != NONE).unwrap_or_else(|| {
                    n_c += 1;
                    n_c - 1
                });
            }
        }
        let n_c = n_c as usize;
        // The coarse pattern: aggregate pairs joined by a fine entry.
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for i in 0..n {
            let a = agg[i];
            if a == NONE {
                continue;
            }
            for &j in row(i) {
                let b = agg[j as usize];
                if b != NONE && b != a {
                    pairs.push((a, b));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut offsets = vec![0u32; n_c + 1];
        for &(a, _) in &pairs {
            offsets[a as usize + 1] += 1;
        }
        for k in 0..n_c {
            offsets[k + 1] += offsets[k];
        }
        let cols: Vec<u32> = pairs.iter().map(|&(_, b)| b).collect();
        let mut fine_map = vec![NONE; matrix.cols.len()];
        for i in 0..n {
            let a = agg[i];
            if a == NONE {
                continue;
            }
            for k in matrix.offsets[i] as usize..matrix.offsets[i + 1] as usize {
                let b = agg[matrix.cols[k] as usize];
                fine_map[k] = if b == NONE {
                    NONE
                } else if b == a {
                    DIAG
                } else {
                    let r = &cols[offsets[a as usize] as usize..offsets[a as usize + 1] as usize];
                    offsets[a as usize] + r.binary_search(&b).expect("pair listed") as u32
                };
            }
        }
        let nnz = cols.len();
        Self { agg, n_c, offsets, vals: vec![0.0; nnz], cols, diag0: vec![0.0; n_c], fine_map, ..Default::default() }
    }

    /// What the GPU's coarse correction (`gpu/coarse.wgsl`) uploads: each particle's aggregate
    /// (`NONE`: pinned), each aggregate's members in ascending order as compressed rows (so that
    /// the GPU's sums run in the CPU's order), the coarse matrix's rows, columns and values and
    /// its diagonal without contacts, for the substep length last given to `set_values`.
    #[cfg(feature = "gpu")]
    pub(crate) fn gpu_layout(&self) -> CoarseLayout<'_> {
        let mut member_offsets = vec![0u32; self.n_c + 1];
        for &a in &self.agg {
            if a != NONE {
                member_offsets[a as usize + 1] += 1;
            }
        }
        for a in 0..self.n_c {
            member_offsets[a + 1] += member_offsets[a];
        }
        let mut fill = member_offsets.clone();
        let mut members = vec![0u32; member_offsets[self.n_c] as usize];
        for (i, &a) in self.agg.iter().enumerate() {
            if a != NONE {
                members[fill[a as usize] as usize] = i as u32;
                fill[a as usize] += 1;
            }
        }
        CoarseLayout {
            agg: &self.agg,
            member_offsets,
            members,
            offsets: &self.offsets,
            cols: &self.cols,
            vals: &self.vals,
            diag0: &self.diag0,
        }
    }

    /// Coarse grid points.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.n_c
    }

    /// Heap bytes held (the aggregates, the coarse matrix, the fine-entry map and the scratch).
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.agg)
            + vec_bytes(&self.offsets)
            + vec_bytes(&self.cols)
            + vec_bytes(&self.vals)
            + vec_bytes(&self.diag0)
            + vec_bytes(&self.fine_map)
            + vec_bytes(&self.diag)
            + vec_bytes(&self.inv)
            + [&self.rc, &self.e, &self.p, &self.q, &self.res].iter().map(|v| vec_bytes(v)).sum::<usize>()
    }

    /// The Galerkin matrix's values for the fine diagonal `diag` (`M/h² + L_ii`, no contacts).
    pub fn set_values(&mut self, matrix: &SparseSym32, diag: &[f32]) {
        self.vals.iter_mut().for_each(|v| *v = 0.0);
        self.diag0.iter_mut().for_each(|v| *v = 0.0);
        for (i, &a) in self.agg.iter().enumerate() {
            if a == NONE {
                continue;
            }
            self.diag0[a as usize] += diag[i];
            for k in matrix.offsets[i] as usize..matrix.offsets[i + 1] as usize {
                match self.fine_map[k] {
                    NONE => {}
                    DIAG => self.diag0[a as usize] += matrix.vals[k],
                    c => self.vals[c as usize] += matrix.vals[k],
                }
            }
        }
    }

    /// The coarse correction of `x` (see the module docs), with at most `cg_iterations`
    /// conjugate-gradient iterations on the coarse system.
    pub fn correct(&mut self, sys: &GlobalSystem, x: &mut Vec3Soa, cg_iterations: usize) {
        let n = self.agg.len();
        self.res.resize(n, Vec3A::ZERO);
        // The fine residual, in parallel (each row reads x, writes its own entry).
        let agg = &self.agg;
        self.res.par_chunks_mut(RESIDUAL_CHUNK).enumerate().for_each(|(c, out)| {
            for (k, r) in out.iter_mut().enumerate() {
                let i = c * RESIDUAL_CHUNK + k;
                *r = if agg[i] == NONE {
                    Vec3A::ZERO
                } else {
                    let xi = Vec3A::from(x.get(i));
                    let (target, d) = sys.row(i, |j| Vec3A::from(x.get(j)));
                    (target - xi) * d
                };
            }
        });
        self.rc.clear();
        self.rc.resize(self.n_c, Vec3A::ZERO);
        self.diag.clear();
        self.diag.extend_from_slice(&self.diag0);
        for i in 0..n {
            let a = self.agg[i];
            if a != NONE {
                self.rc[a as usize] += self.res[i];
                self.diag[a as usize] += sys.contact_weight[i];
            }
        }
        self.solve(cg_iterations);
        for i in 0..n {
            let a = self.agg[i];
            if a != NONE {
                let p = Vec3A::from(x.get(i)) + self.e[a as usize];
                x.set(i, p.into());
            }
        }
    }

    fn apply(&self, v: &[Vec3A], out: &mut [Vec3A]) {
        for a in 0..self.n_c {
            let mut s = v[a] * self.diag[a];
            for k in self.offsets[a] as usize..self.offsets[a + 1] as usize {
                s += v[self.cols[k] as usize] * self.vals[k];
            }
            out[a] = s;
        }
    }

    /// `A_c e = r_c` by conjugate gradients preconditioned by the diagonal, the three
    /// coordinates as three systems in lockstep.
    fn solve(&mut self, iterations: usize) {
        let m = self.n_c;
        self.e.clear();
        self.e.resize(m, Vec3A::ZERO);
        let mut r = std::mem::take(&mut self.rc);
        let mut p = std::mem::take(&mut self.p);
        let mut q = std::mem::take(&mut self.q);
        let mut inv = std::mem::take(&mut self.inv);
        inv.clear();
        inv.extend(self.diag.iter().map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 }));
        p.clear();
        p.extend(r.iter().zip(&inv).map(|(r, i)| *r * *i));
        q.resize(m, Vec3A::ZERO);
        let dot = |a: &[Vec3A], b: &[Vec3A]| a.iter().zip(b).fold(Vec3A::ZERO, |s, (x, y)| s + *x * *y);
        let mut rz = dot(&r, &p);
        let r0 = rz;
        for _ in 0..iterations {
            if rz.cmple(r0 * 1e-10).all() {
                break;
            }
            self.apply(&p, &mut q);
            let pq = dot(&p, &q);
            let alpha = Vec3A::select(pq.cmpgt(Vec3A::ZERO), rz / pq, Vec3A::ZERO);
            let mut rz_new = Vec3A::ZERO;
            for k in 0..m {
                self.e[k] += p[k] * alpha;
                r[k] -= q[k] * alpha;
                rz_new += r[k] * r[k] * inv[k];
            }
            let beta = Vec3A::select(rz.cmpgt(Vec3A::ZERO), rz_new / rz, Vec3A::ZERO);
            for k in 0..m {
                p[k] = r[k] * inv[k] + p[k] * beta;
            }
            rz = rz_new;
        }
        (self.rc, self.p, self.q, self.inv) = (r, p, q, inv);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The matrix graph of a path of `n` particles, each joined to its neighbours one and two
    /// apart (a bending stencil's reach).
    fn path(n: usize) -> SparseSym32 {
        let mut m = SparseSym32 { diag: vec![4.0; n], offsets: vec![0], ..Default::default() };
        for i in 0..n {
            for j in [i.wrapping_sub(2), i.wrapping_sub(1), i + 1, i + 2] {
                if j < n {
                    m.cols.push(j as u32);
                    m.vals.push(-1.0);
                }
            }
            m.offsets.push(m.cols.len() as u32);
        }
        m
    }

    #[test]
    fn every_free_particle_is_in_one_aggregate_of_its_neighbours_and_pinned_ones_in_none() {
        let m = path(40);
        let free: Vec<u32> = (0..40).filter(|&i| i != 0 && i != 39).collect();
        let c = CoarseLevel::build(&m, &free);
        assert_eq!(c.agg[0], NONE);
        assert_eq!(c.agg[39], NONE);
        assert!(free.iter().all(|&i| (c.agg[i as usize] as usize) < c.len()));
        // Each aggregate is joined (a particle's aggregate holds one of its matrix neighbours
        // or is its own), and the grid is several times coarser.
        for &i in &free {
            let i = i as usize;
            let row = &m.cols[m.offsets[i] as usize..m.offsets[i + 1] as usize];
            let alone = free.iter().filter(|&&j| c.agg[j as usize] == c.agg[i]).count() == 1;
            assert!(alone || row.iter().any(|&j| c.agg[j as usize] == c.agg[i]), "particle {i}");
        }
        assert!(c.len() >= 5 && c.len() <= 40 / 3, "{} aggregates", c.len());
    }

    #[test]
    fn the_galerkin_matrix_sums_the_fine_entries_over_aggregate_pairs() {
        let m = path(12);
        let free: Vec<u32> = (0..12).collect();
        let mut c = CoarseLevel::build(&m, &free);
        c.set_values(&m, &m.diag);
        // Pᵀ A P by brute force.
        let mut dense = vec![vec![0.0f32; c.len()]; c.len()];
        for i in 0..12 {
            dense[c.agg[i] as usize][c.agg[i] as usize] += m.diag[i];
            for k in m.offsets[i] as usize..m.offsets[i + 1] as usize {
                dense[c.agg[i] as usize][c.agg[m.cols[k] as usize] as usize] += m.vals[k];
            }
        }
        for a in 0..c.len() {
            assert_eq!(c.diag0[a], dense[a][a], "diagonal {a}");
            for k in c.offsets[a] as usize..c.offsets[a + 1] as usize {
                assert_eq!(c.vals[k], dense[a][c.cols[k] as usize], "entry {a}, {}", c.cols[k]);
            }
            let listed = c.offsets[a + 1] - c.offsets[a];
            let nonzero = (0..c.len()).filter(|&b| b != a && dense[a][b] != 0.0).count() as u32;
            assert_eq!(listed, nonzero);
        }
        // The coarse solve inverts it: A_c e = r for a right-hand side made from a known e.
        c.diag = c.diag0.clone();
        let want: Vec<Vec3A> = (0..c.len()).map(|a| Vec3A::new(a as f32, 1.0, -0.5 * a as f32)).collect();
        let mut r = vec![Vec3A::ZERO; c.len()];
        c.apply(&want, &mut r);
        c.rc = r;
        c.solve(100);
        for a in 0..c.len() {
            assert!((c.e[a] - want[a]).length() < 1e-3, "{a}: {:?} vs {:?}", c.e[a], want[a]);
        }
    }
}
