//! Seams: zero-rest-length springs between sewn points, and hinge bending across sewn edges.
//!
//! Each sewn pair joins a point on side A to a point on side B. A point is one vertex (the
//! paper's one-to-one seams of equal vertex counts) or an edge point with barycentric weights
//! (seams of unequal counts: each particle is sewn to the matching arc-length point of the
//! other side). The pair becomes a stencil `v = Σ αₖ x_{aₖ} − Σ βₖ x_{bₖ}` with rest length 0.
//!
//! Seams strongly change how a garment bends (Pabst et al. 2008), so, as in the paper, the two
//! faces on either side of each sewn edge also get a quadratic bending hinge: its edge is the
//! midpoint of the sewn pairs, its wings are the boundary triangles of A and B. Each seam has
//! its own distance and bending stiffness.

use crate::error::{Result, TailorError};
use crate::mesh::ClothMesh;

use super::bending::{hinge_weights, HingeTriangle};
use super::stencil::StencilSet;

/// A point on one side of a seam: up to two vertices with weights summing to one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamPoint {
    pub verts: [u32; 2],
    pub weights: [f32; 2],
}

impl SeamPoint {
    /// A single vertex.
    pub fn vertex(v: u32) -> Self {
        Self { verts: [v, v], weights: [1.0, 0.0] }
    }

    /// The point `(1−t)·x_a + t·x_b` on edge `(a, b)`.
    pub fn on_edge(a: u32, b: u32, t: f32) -> Self {
        Self { verts: [a, b], weights: [1.0 - t, t] }
    }

    fn terms(&self, sign: f32) -> impl Iterator<Item = (u32, f32)> + '_ {
        (0..2).filter(move |&k| self.weights[k] != 0.0).map(move |k| (self.verts[k], sign * self.weights[k]))
    }

    fn support(&self) -> impl Iterator<Item = u32> + '_ {
        (0..2).filter(move |&k| self.weights[k] != 0.0).map(move |k| self.verts[k])
    }

    fn is_vertex(&self) -> bool {
        self.weights[1] == 0.0 || self.verts[0] == self.verts[1]
    }
}

/// A seam between two contour paths.
#[derive(Debug, Clone, PartialEq)]
pub struct Seam {
    pub name: String,
    /// Sewn pairs, in order along the seam.
    pub pairs: Vec<(SeamPoint, SeamPoint)>,
    /// Spring constant of each pair, N/m.
    pub stiffness: f32,
    /// Bending stiffness of the hinges across the sewn edges, N·m.
    pub bend_stiffness: f32,
}

impl Seam {
    /// A one-to-one seam between two vertex paths of equal length (the paper's seams).
    pub fn one_to_one(name: &str, a: &[u32], b: &[u32], stiffness: f32, bend_stiffness: f32) -> Result<Self> {
        if a.len() != b.len() {
            return Err(TailorError::InvalidSeam {
                seam: name.into(),
                reason: format!(
                    "side A has {} vertices and side B {}: a one-to-one seam pairs equal counts \
                     (use an unequal-count seam to sew different resolutions)",
                    a.len(),
                    b.len()
                ),
            });
        }
        let pairs = a.iter().zip(b).map(|(&u, &v)| (SeamPoint::vertex(u), SeamPoint::vertex(v))).collect();
        Ok(Self { name: name.into(), pairs, stiffness, bend_stiffness })
    }

    /// Checks indices, weights and stiffness against a mesh of `n` vertices.
    pub fn validate(&self, n: usize) -> Result<()> {
        let err = |reason: String| TailorError::InvalidSeam { seam: self.name.clone(), reason };
        if self.pairs.is_empty() {
            return Err(err("it has no sewn pairs".into()));
        }
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return Err(err(format!("stiffness {} must be positive and finite", self.stiffness)));
        }
        if !(self.bend_stiffness.is_finite() && self.bend_stiffness >= 0.0) {
            return Err(err(format!("bending stiffness {} must be non-negative", self.bend_stiffness)));
        }
        for (i, (a, b)) in self.pairs.iter().enumerate() {
            for (side, p) in [("A", a), ("B", b)] {
                for k in 0..2 {
                    if p.verts[k] as usize >= n {
                        return Err(TailorError::index(
                            format!("seam {} pair {i} side {side}", self.name),
                            p.verts[k] as i64,
                            n,
                            "vertices",
                        ));
                    }
                }
                let s = p.weights[0] + p.weights[1];
                if !(s - 1.0).abs().lt(&1e-4) || p.weights.iter().any(|w| !(0.0..=1.0).contains(w)) {
                    return Err(err(format!(
                        "pair {i} side {side}: weights {:?} must be in 0..1 and sum to 1",
                        p.weights
                    )));
                }
            }
            if a.is_vertex() && b.is_vertex() && a.verts[0] == b.verts[0] {
                return Err(err(format!("pair {i} sews vertex {} to itself", a.verts[0])));
            }
        }
        Ok(())
    }

    /// Appends the seam's distance constraints (rest length 0) to `out`.
    pub fn push_pairs(&self, out: &mut StencilSet) {
        let mut terms = Vec::with_capacity(4);
        for (a, b) in &self.pairs {
            terms.clear();
            terms.extend(a.terms(1.0));
            terms.extend(b.terms(-1.0));
            out.push(&terms, self.stiffness, 0.0);
        }
    }

    /// Appends the hinges across the sewn edges to `out` (none when bend stiffness is 0).
    /// A hinge exists where consecutive pairs span a boundary edge on both sides.
    pub fn push_hinges(&self, mesh: &ClothMesh, boundary: &BoundaryEdges, out: &mut StencilSet) -> usize {
        if self.bend_stiffness == 0.0 {
            return 0;
        }
        let rest = mesh.rest();
        let r = |v: u32| [rest[v as usize][0] as f64, rest[v as usize][1] as f64];
        let mut seen = std::collections::HashSet::new();
        let mut added = 0;
        for w in self.pairs.windows(2) {
            let ((a0, b0), (a1, b1)) = (w[0], w[1]);
            let (Some(ea), Some(eb)) = (boundary.spanning(a0, a1), boundary.spanning(b0, b1)) else { continue };
            if !seen.insert((ea.triangle, eb.triangle)) {
                continue;
            }
            let ta = HingeTriangle { e0: r(ea.v0), e1: r(ea.v1), o: r(ea.opposite) };
            let tb = HingeTriangle { e0: r(eb.v0), e1: r(eb.v1), o: r(eb.opposite) };
            let Some((k, area)) = hinge_weights(&ta, &tb) else { continue };
            let k = k.map(|c| c as f32);
            // The hinge edge is the midpoint of the sewn pairs on either side.
            let mut terms: Vec<(u32, f32)> = Vec::with_capacity(10);
            terms.extend(a0.terms(0.5 * k[0]).chain(b0.terms(0.5 * k[0])));
            terms.extend(a1.terms(0.5 * k[1]).chain(b1.terms(0.5 * k[1])));
            terms.push((ea.opposite, k[2]));
            terms.push((eb.opposite, k[3]));
            out.push(&terms, 3.0 * self.bend_stiffness / area as f32, 0.0);
            added += 1;
        }
        added
    }
}

/// A boundary edge oriented from the first seam point towards the next, with its triangle.
#[derive(Debug, Clone, Copy)]
pub struct BoundaryEdge {
    pub v0: u32,
    pub v1: u32,
    pub opposite: u32,
    pub triangle: u32,
}

/// Lookup of the mesh's boundary edges (edges with one triangle).
pub struct BoundaryEdges {
    map: std::collections::HashMap<(u32, u32), (u32, u32)>,
}

impl BoundaryEdges {
    pub fn new(mesh: &ClothMesh) -> Self {
        let mut count: std::collections::HashMap<(u32, u32), (u32, u32, u32)> = Default::default();
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for k in 0..3 {
                let (a, b, o) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let e = count.entry((a.min(b), a.max(b))).or_insert((0, o, t as u32));
                e.0 += 1;
            }
        }
        let map = count.into_iter().filter(|(_, (c, _, _))| *c == 1).map(|(k, (_, o, t))| (k, (o, t))).collect();
        Self { map }
    }

    /// The boundary edge joining the supports of two consecutive seam points, if any.
    fn spanning(&self, p: SeamPoint, q: SeamPoint) -> Option<BoundaryEdge> {
        let mut cands: Vec<u32> = p.support().chain(q.support()).collect();
        cands.dedup();
        for &u in p.support().collect::<Vec<_>>().iter().chain(cands.iter()) {
            for &v in q.support().collect::<Vec<_>>().iter().chain(cands.iter()) {
                if u == v {
                    continue;
                }
                if let Some(&(o, t)) = self.map.get(&(u.min(v), u.max(v))) {
                    return Some(BoundaryEdge { v0: u, v1: v, opposite: o, triangle: t });
                }
            }
        }
        None
    }
}
