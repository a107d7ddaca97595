//! The constant part of the global matrix, `L = Σ w·AᵀA`.
//!
//! Every constraint maps positions to vectors by scalar coefficients, so `L` is an `n×n` scalar
//! matrix shared by the x, y and z systems. The global step solves
//! `(M/h² + L + C) x = M/h²·y + b_const + Σ w·Aᵀp` where `C` is the diagonal of this substep's
//! contact weights. `L` is assembled in f64 once per topology change and kept only in f32
//! rows for the real-time sweep (the reference solver assembles its own f64 copy). Its
//! off-diagonal pattern is the graph the colouring separates.

use crate::solver::model::constraints::{triangle, StencilSet, TriangleSet};
use crate::solver::model::soa::vec_bytes;

/// Symmetric sparse matrix: diagonal plus off-diagonal entries by row (both triangles stored).
#[derive(Debug, Clone, Default)]
pub struct SparseSym {
    pub diag: Vec<f64>,
    pub offsets: Vec<u32>,
    pub cols: Vec<u32>,
    pub vals: Vec<f64>,
}

/// The same matrix in f32 for the real-time sweep.
#[derive(Debug, Clone, Default)]
pub struct SparseSym32 {
    pub diag: Vec<f32>,
    pub offsets: Vec<u32>,
    pub cols: Vec<u32>,
    pub vals: Vec<f32>,
}

impl SparseSym32 {
    /// Heap bytes of the rows.
    pub fn memory_bytes(&self) -> usize {
        vec_bytes(&self.diag) + vec_bytes(&self.offsets) + vec_bytes(&self.cols) + vec_bytes(&self.vals)
    }
}

impl SparseSym {
    pub fn n(&self) -> usize {
        self.diag.len()
    }

    /// Heap bytes of the rows.
    pub fn memory_bytes(&self) -> usize {
        vec_bytes(&self.diag) + vec_bytes(&self.offsets) + vec_bytes(&self.cols) + vec_bytes(&self.vals)
    }

    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// Assembles `L` from the constraints; `attachments` gives each soft attachment's
    /// (particle, weight), fixed or riding on a collider.
    pub fn assemble(
        n: usize,
        tris: &TriangleSet,
        stencils: &[&StencilSet],
        attachments: impl IntoIterator<Item = (u32, f32)>,
    ) -> Self {
        let mut trip: Vec<(u32, u32, f64)> = Vec::new();
        let mut diag = vec![0.0f64; n];
        for t in 0..tris.len() {
            let (ws, wsh) = ([tris.w_stretch[t], tris.w_stretch_v[t]], tris.w_shear[t]);
            let g = &tris.g[t];
            let v = tris.verts[t];
            for k in 0..3 {
                for l in 0..3 {
                    let c = triangle::matrix_entry(g, k, l, ws, wsh);
                    if k == l {
                        diag[v[k] as usize] += c;
                    } else {
                        trip.push((v[k], v[l], c));
                    }
                }
            }
        }
        for set in stencils {
            for s in 0..set.len() {
                let w = set.weights[s] as f64;
                let r = set.range(s);
                for a in r.clone() {
                    for b in r.clone() {
                        let c = w * set.coefs[a] as f64 * set.coefs[b] as f64;
                        if a == b {
                            diag[set.verts[a] as usize] += c;
                        } else {
                            trip.push((set.verts[a], set.verts[b], c));
                        }
                    }
                }
            }
        }
        for (particle, weight) in attachments {
            diag[particle as usize] += weight as f64;
        }
        trip.sort_unstable_by_key(|&(i, j, _)| ((i as u64) << 32) | j as u64);
        let mut offsets = vec![0u32; n + 1];
        let mut cols = Vec::with_capacity(trip.len() / 2);
        let mut vals = Vec::with_capacity(trip.len() / 2);
        let mut k = 0;
        while k < trip.len() {
            let (i, j, mut v) = trip[k];
            k += 1;
            while k < trip.len() && trip[k].0 == i && trip[k].1 == j {
                v += trip[k].2;
                k += 1;
            }
            cols.push(j);
            vals.push(v);
            offsets[i as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        // The reservation above counts duplicate triplets (entries shared by neighbouring
        // constraints), about twice the final size: give the excess back.
        cols.shrink_to_fit();
        vals.shrink_to_fit();
        Self { diag, offsets, cols, vals }
    }

    pub fn to_f32(&self) -> SparseSym32 {
        SparseSym32 {
            diag: self.diag.iter().map(|&v| v as f32).collect(),
            offsets: self.offsets.clone(),
            cols: self.cols.clone(),
            vals: self.vals.iter().map(|&v| v as f32).collect(),
        }
    }
}
