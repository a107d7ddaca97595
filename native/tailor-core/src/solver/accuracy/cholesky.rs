//! A direct sparse solver for the reference step: reverse Cuthill-McKee ordering and an
//! envelope (skyline) Cholesky factorisation in f64.
//!
//! Cloth meshes are planar-like graphs, so after RCM the envelope is about `n·√n` entries:
//! a few MB for 10k particles. The reference solver is for tests and benchmarks, never the
//! real-time path; [`MAX_ENVELOPE`] keeps it from exhausting memory on huge meshes.

use crate::error::{Result, TailorError};

/// Largest envelope (stored factor entries) accepted, about 800 MB of f64.
pub const MAX_ENVELOPE: usize = 100_000_000;

/// Reverse Cuthill-McKee order of a symmetric adjacency (`offsets`, `adj`): `perm[new] = old`.
pub fn reverse_cuthill_mckee(offsets: &[u32], adj: &[u32]) -> Vec<u32> {
    let n = offsets.len() - 1;
    let deg = |i: usize| offsets[i + 1] - offsets[i];
    let mut visited = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut by_degree: Vec<u32> = (0..n as u32).collect();
    by_degree.sort_by_key(|&i| deg(i as usize));
    let mut nbrs = Vec::new();
    for &start in &by_degree {
        if visited[start as usize] {
            continue;
        }
        visited[start as usize] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let v = order[head] as usize;
            head += 1;
            nbrs.clear();
            nbrs.extend(
                adj[offsets[v] as usize..offsets[v + 1] as usize].iter().copied().filter(|&u| !visited[u as usize]),
            );
            nbrs.sort_by_key(|&u| deg(u as usize));
            for &u in &nbrs {
                if !visited[u as usize] {
                    visited[u as usize] = true;
                    order.push(u);
                }
            }
        }
    }
    order.reverse();
    order
}

/// Envelope Cholesky factor `A = L·Lᵀ` of a symmetric positive definite matrix.
pub struct Skyline {
    /// First stored column of each row.
    first: Vec<usize>,
    /// Offset of row i's first stored entry in `data`; row i stores columns first[i]..=i.
    start: Vec<usize>,
    data: Vec<f64>,
}

impl Skyline {
    /// Factors the matrix given by `diag` and lower/upper entries `entries(i)` = `(j, a_ij)`
    /// for row `i` (any order, both triangles allowed; only `j < i` is used).
    pub fn factor<I: Iterator<Item = (usize, f64)>>(diag: &[f64], entries: impl Fn(usize) -> I) -> Result<Self> {
        let n = diag.len();
        let mut first: Vec<usize> = (0..n).collect();
        for (i, f) in first.iter_mut().enumerate() {
            for (j, _) in entries(i) {
                if j < *f {
                    *f = j;
                }
            }
        }
        let mut start = vec![0usize; n + 1];
        for i in 0..n {
            start[i + 1] = start[i] + (i - first[i] + 1);
        }
        if start[n] > MAX_ENVELOPE {
            return Err(TailorError::setting(
                "reference solver",
                n,
                format!("the matrix envelope has {} entries (limit {MAX_ENVELOPE}): use a smaller mesh", start[n]),
            ));
        }
        let mut data = vec![0.0f64; start[n]];
        for i in 0..n {
            data[start[i] + i - first[i]] = diag[i];
            for (j, v) in entries(i) {
                if j < i {
                    data[start[i] + j - first[i]] += v;
                }
            }
        }
        let mut s = Self { first, start, data };
        for i in 0..n {
            let fi = s.first[i];
            for j in fi..=i {
                let fj = s.first[j];
                let k0 = fi.max(fj);
                let mut sum = s.data[s.start[i] + j - fi];
                for k in k0..j {
                    sum -= s.data[s.start[i] + k - fi] * s.data[s.start[j] + k - fj];
                }
                if j < i {
                    sum /= s.data[s.start[j] + j - fj];
                    s.data[s.start[i] + j - fi] = sum;
                } else {
                    if sum.is_nan() || sum <= 0.0 {
                        return Err(TailorError::setting(
                            "reference solver",
                            i,
                            "the system matrix is not positive definite",
                        ));
                    }
                    s.data[s.start[i] + i - fi] = sum.sqrt();
                }
            }
        }
        Ok(s)
    }

    /// Solves `A·x = b` in place.
    pub fn solve(&self, b: &mut [f64]) {
        let n = b.len();
        for i in 0..n {
            let fi = self.first[i];
            let row = &self.data[self.start[i]..self.start[i + 1]];
            let mut s = b[i];
            for k in fi..i {
                s -= row[k - fi] * b[k];
            }
            b[i] = s / row[i - fi];
        }
        for i in (0..n).rev() {
            let fi = self.first[i];
            let row = &self.data[self.start[i]..self.start[i + 1]];
            b[i] /= row[i - fi];
            let bi = b[i];
            for k in fi..i {
                b[k] -= row[k - fi] * bi;
            }
        }
    }

    /// Stored entries (memory use in f64 words).
    pub fn envelope(&self) -> usize {
        self.data.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_random_spd_banded_system() {
        let n = 50;
        // A = tridiag(-1, 4, -1) plus a long-range coupling (0, 49).
        let entries = |i: usize| {
            let mut e = Vec::new();
            if i > 0 {
                e.push((i - 1, -1.0));
            }
            if i + 1 < n {
                e.push((i + 1, -1.0));
            }
            if i == 49 {
                e.push((0, 0.5));
            }
            if i == 0 {
                e.push((49, 0.5));
            }
            e.into_iter()
        };
        let diag = vec![4.0; n];
        let f = Skyline::factor(&diag, entries).unwrap();
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b: Vec<f64> =
            (0..n).map(|i| diag[i] * x_true[i] + entries(i).map(|(j, v)| v * x_true[j]).sum::<f64>()).collect();
        f.solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x_true[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn rcm_is_a_permutation() {
        let offsets = vec![0, 1, 3, 4];
        let adj = vec![1, 0, 2, 1];
        let mut p = reverse_cuthill_mckee(&offsets, &adj);
        p.sort();
        assert_eq!(p, vec![0, 1, 2]);
    }
}
