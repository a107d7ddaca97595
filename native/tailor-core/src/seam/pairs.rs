//! What the solver needs from a resolved seam: sewn point pairs and hinges across the seam.
//!
//! **Pairs.** Each [`SeamPair`] is a zero-rest-length distance constraint between a point of
//! side A and a point of side B, each point a convex combination of at most two vertices,
//! `x = w₀ x_{v₀} + w₁ x_{v₁}` with `w₀ + w₁ = 1`. A point that is a vertex has `w₀ = 1` and
//! repeats the vertex with `w₁ = 0`.
//!
//! * Equal mode (the paper): `a_i ↔ b_i`, vertex to vertex.
//! * Unequal mode: each side is parametrised by normalised rest arc length,
//!   `t(a_i) = Σ_{k<i} |a_{k+1} − a_k| / L_A ∈ [0, 1]` (same for B). Every vertex of A at `t` is
//!   sewn to the point of B at `t` (on the B segment `[b_j, b_{j+1}]` with `t_j ≤ t ≤ t_{j+1}`,
//!   weights `(1 − s, s)`, `s = (t − t_j)/(t_{j+1} − t_j)`), and every vertex of B not already
//!   matched by an A vertex at the same `t` is sewn to the point of A at its `t`. Both sides'
//!   vertices are thus held on the other side's curve whatever the two resolutions, and when
//!   `L_A ≠ L_B` the longer side is eased (gathered) evenly onto the shorter. With equal counts
//!   and equal spacing this reduces to the one-to-one pairs.
//!
//! **Hinges.** For each A contour edge `(a_i, a_{i+1})` of the seam: its triangle's opposite
//! vertex on A, the points of B matching its two ends, and the opposite vertex of the B
//! triangle on the B edge containing the edge's midpoint. Once sewn, edge + two opposite
//! vertices form the stencil of the quadratic bending energy across the seam (Bergou et al.
//! 2006), as the paper prescribes for seams.
//!
//! Vertex indices are local to each piece; [`SeamPair::offset`] and [`SeamHinge::offset`]
//! shift them into a concatenated cloth mesh.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use super::model::{ResolvedSeam, SeamMode};
use super::paths::{dist, ContourPath};
use super::validate::validate_seam;
use crate::error::{Result, TailorError};
use crate::triangulate::PieceMesh;

/// A point as up to two weighted vertices (weights sum to 1).
pub type WeightedPoint = [(u32, f32); 2];

/// One sewn pair: a point of side A held at a point of side B.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeamPair {
    pub a: WeightedPoint,
    pub b: WeightedPoint,
}

/// A bending hinge across the seam.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeamHinge {
    /// The A contour edge (piece A vertices).
    pub a_edge: [u32; 2],
    /// The vertex opposite `a_edge` in its (only) triangle of piece A.
    pub a_opposite: u32,
    /// The points of B sewn to `a_edge[0]` and `a_edge[1]`.
    pub b_edge: [WeightedPoint; 2],
    /// The vertex opposite the matching B contour edge in its triangle of piece B.
    pub b_opposite: u32,
}

fn vertex(v: u32) -> WeightedPoint {
    [(v, 1.0), (v, 0.0)]
}

fn shift(p: WeightedPoint, off: u32) -> WeightedPoint {
    [(p[0].0 + off, p[0].1), (p[1].0 + off, p[1].1)]
}

impl SeamPair {
    /// Shifts A indices by `a` and B indices by `b` (piece offsets in a concatenated mesh).
    pub fn offset(self, a: u32, b: u32) -> Self {
        SeamPair { a: shift(self.a, a), b: shift(self.b, b) }
    }
}

impl SeamHinge {
    pub fn offset(self, a: u32, b: u32) -> Self {
        SeamHinge {
            a_edge: [self.a_edge[0] + a, self.a_edge[1] + a],
            a_opposite: self.a_opposite + a,
            b_edge: [shift(self.b_edge[0], b), shift(self.b_edge[1], b)],
            b_opposite: self.b_opposite + b,
        }
    }
}

/// Normalised arc-length parameter of each vertex of a path, `0 … 1`.
fn params(mesh: &PieceMesh, path: &ContourPath) -> Vec<f64> {
    let mut t = Vec::with_capacity(path.len());
    let mut acc = 0.0;
    t.push(0.0);
    for w in path.positions.windows(2) {
        acc += dist(mesh.contour_point(w[0]), mesh.contour_point(w[1]));
        t.push(acc);
    }
    let total = acc.max(f64::MIN_POSITIVE);
    t.iter_mut().for_each(|x| *x /= total);
    t
}

/// Within this parameter distance two points are the same (snaps weights to exactly 0 / 1).
const SNAP: f64 = 1e-6;

/// The point at parameter `t` of a path with vertex parameters `ts`, and its segment index.
fn locate(verts: &[u32], ts: &[f64], t: f64) -> (WeightedPoint, usize) {
    let j = ts.partition_point(|&x| x <= t).saturating_sub(1).min(ts.len().saturating_sub(2));
    let (t0, t1) = (ts[j], ts[j + 1]);
    let s = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 0.0 };
    let p = if s <= SNAP {
        vertex(verts[j])
    } else if s >= 1.0 - SNAP {
        vertex(verts[j + 1])
    } else {
        [(verts[j], (1.0 - s) as f32), (verts[j + 1], s as f32)]
    };
    (p, j)
}

impl ResolvedSeam {
    /// The sewn pairs, ordered along the seam (the seam is validated first).
    pub fn pairs(&self, mesh_a: &PieceMesh, mesh_b: &PieceMesh) -> Result<Vec<SeamPair>> {
        self.validate(mesh_a, mesh_b)?;
        let (va, vb) = (self.a.vertices(mesh_a), self.b.vertices(mesh_b));
        if self.mode == SeamMode::Equal {
            return Ok(va.iter().zip(&vb).map(|(&a, &b)| SeamPair { a: vertex(a), b: vertex(b) }).collect());
        }
        let (ta, tb) = (params(mesh_a, &self.a), params(mesh_b, &self.b));
        let mut out: Vec<(f64, SeamPair)> = Vec::with_capacity(va.len() + vb.len());
        for (i, &t) in ta.iter().enumerate() {
            out.push((t, SeamPair { a: vertex(va[i]), b: locate(&vb, &tb, t).0 }));
        }
        for (j, &t) in tb.iter().enumerate() {
            let k = ta.partition_point(|&x| x < t - SNAP);
            if k < ta.len() && (ta[k] - t).abs() <= SNAP {
                continue;
            }
            out.push((t, SeamPair { a: locate(&va, &ta, t).0, b: vertex(vb[j]) }));
        }
        out.sort_by(|x, y| x.0.total_cmp(&y.0));
        Ok(out.into_iter().map(|(_, p)| p).collect())
    }

    /// Re-checks the paths against the meshes (the fields are public and may have been edited).
    pub fn validate(&self, mesh_a: &PieceMesh, mesh_b: &PieceMesh) -> Result<()> {
        validate_seam(&self.name, mesh_a, &self.a, mesh_b, &self.b, self.piece_a == self.piece_b, self.mode)
    }

    /// The bending hinges across the seam, one per A contour edge.
    pub fn hinges(&self, mesh_a: &PieceMesh, mesh_b: &PieceMesh) -> Result<Vec<SeamHinge>> {
        self.validate(mesh_a, mesh_b)?;
        let (va, vb) = (self.a.vertices(mesh_a), self.b.vertices(mesh_b));
        let (oa, ob) = (boundary_opposites(mesh_a), boundary_opposites(mesh_b));
        let opp = |map: &HashMap<(u32, u32), u32>, u: u32, v: u32, mesh: &PieceMesh| {
            map.get(&(u.min(v), u.max(v))).copied().ok_or_else(|| TailorError::InvalidSeam {
                seam: self.name.clone(),
                reason: format!("edge ({u}, {v}) of piece {} is not a boundary edge", mesh.name),
            })
        };
        let (ta, tb) = match self.mode {
            SeamMode::Equal => {
                let even = |n: usize| (0..n).map(|i| i as f64 / (n - 1).max(1) as f64).collect::<Vec<_>>();
                (even(va.len()), even(vb.len()))
            }
            SeamMode::Unequal => (params(mesh_a, &self.a), params(mesh_b, &self.b)),
        };
        let mut out = Vec::with_capacity(va.len().saturating_sub(1));
        for i in 0..va.len().saturating_sub(1) {
            let (b0, _) = locate(&vb, &tb, ta[i]);
            let (b1, _) = locate(&vb, &tb, ta[i + 1]);
            let (_, j) = locate(&vb, &tb, 0.5 * (ta[i] + ta[i + 1]));
            out.push(SeamHinge {
                a_edge: [va[i], va[i + 1]],
                a_opposite: opp(&oa, va[i], va[i + 1], mesh_a)?,
                b_edge: [b0, b1],
                b_opposite: opp(&ob, vb[j], vb[j + 1], mesh_b)?,
            });
        }
        Ok(out)
    }
}

/// Boundary edge (undirected) → the vertex opposite it in its one triangle.
fn boundary_opposites(mesh: &PieceMesh) -> HashMap<(u32, u32), u32> {
    let mut count: HashMap<(u32, u32), (u32, u32)> = HashMap::with_capacity(mesh.triangles.len() * 2);
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b, o) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let e = count.entry((a.min(b), a.max(b))).or_insert((0, o));
            e.0 += 1;
        }
    }
    count.into_iter().filter(|(_, (c, _))| *c == 1).map(|(k, (_, o))| (k, o)).collect()
}
