//! Seam points as the weld sees them: each side of a sewn pair is a vertex, or a point strictly
//! inside a triangle edge (the unequal seams' arc-length pairing, `x = (1 − t)·x_lo + t·x_hi`).
//!
//! A point inside an edge becomes a new vertex of that edge, shared by every triangle that has
//! the edge, so the triangles on both sides of the seam meet at the same vertices after the
//! weld (no T-junction). Points of one edge closer than [`SAME_POINT`] in the edge parameter
//! are one vertex: two seams, or both sides of one unequal seam, may land on the same spot.

use std::collections::{HashMap, HashSet};

use crate::error::{Result, TailorError};
use crate::solver::SeamPoint;

/// Within this edge parameter of an end a point is that vertex (as the seam pairing snaps).
pub(super) const SNAP: f32 = 1e-6;
/// Two points of one edge closer than this (edge parameter) are the same vertex.
pub(super) const SAME_POINT: f32 = 1e-5;
/// How far weights may stray from a convex combination (float rounding of stored pairs).
const WEIGHT_SLACK: f32 = 1e-3;

/// A seam point, classified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Point {
    Vertex(u32),
    /// Inside edge `(lo, hi)`, `lo < hi`, at parameter `t ∈ (0, 1)` from `lo`.
    Edge {
        lo: u32,
        hi: u32,
        t: f32,
    },
}

/// Classifies side `side` ('A' or 'B') of pair `pair` of seam `seam`, checking its indices
/// against `n` vertices and its weights (finite, in [0, 1], summing to 1).
pub(super) fn classify(p: &SeamPoint, n: usize, seam: &str, pair: usize, side: char) -> Result<Point> {
    let context = || format!("weld: seam '{seam}' pair {pair} side {side}");
    for &v in &p.verts {
        if v as usize >= n {
            return Err(TailorError::index(context(), v as i64, n, "vertices"));
        }
    }
    let [w0, w1] = p.weights;
    let bad = |reason: String| TailorError::InvalidSeam {
        seam: seam.to_string(),
        reason: format!("pair {pair} side {side}: {reason}"),
    };
    if !(w0.is_finite() && w1.is_finite()) {
        return Err(bad(format!("weights ({w0}, {w1}) are not finite")));
    }
    if w0 < -WEIGHT_SLACK || w1 < -WEIGHT_SLACK || (w0 + w1 - 1.0).abs() > WEIGHT_SLACK {
        return Err(bad(format!("weights ({w0}, {w1}) are not a point of an edge (each in [0, 1], summing to 1)")));
    }
    let [v0, v1] = p.verts;
    let s = (w1 / (w0 + w1)).clamp(0.0, 1.0);
    if v0 == v1 || s <= SNAP {
        return Ok(Point::Vertex(v0));
    }
    if s >= 1.0 - SNAP {
        return Ok(Point::Vertex(v1));
    }
    Ok(if v0 < v1 { Point::Edge { lo: v0, hi: v1, t: s } } else { Point::Edge { lo: v1, hi: v0, t: 1.0 - s } })
}

/// Undirected edge key.
pub(super) fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The points inserted on each edge: `(t, node)` in the order found (sorted by [`EdgePoints::sorted`]).
#[derive(Default)]
pub(super) struct EdgePoints {
    map: HashMap<(u32, u32), Vec<(f32, u32)>>,
}

impl EdgePoints {
    /// The node of the point at `t` on edge `(lo, hi)`: an existing one within [`SAME_POINT`], or
    /// `new_node()`. Returns the node and whether it is new.
    pub fn insert(&mut self, lo: u32, hi: u32, t: f32, new_node: impl FnOnce() -> u32) -> (u32, bool) {
        let list = self.map.entry((lo, hi)).or_default();
        if let Some(&(_, node)) = list.iter().find(|(s, _)| (s - t).abs() <= SAME_POINT) {
            return (node, false);
        }
        let node = new_node();
        list.push((t, node));
        (node, true)
    }

    /// Sorts every edge's points by parameter (call once, after the last insert).
    pub fn sort(&mut self) {
        self.map.values_mut().for_each(|l| l.sort_by(|a, b| a.0.total_cmp(&b.0)));
    }

    /// The points inside edge `(a, b)` (either order), by parameter from the lower index.
    pub fn on(&self, a: u32, b: u32) -> &[(f32, u32)] {
        self.map.get(&key(a, b)).map_or(&[], |l| l.as_slice())
    }
}

/// Every undirected edge of `triangles`.
pub(super) fn edge_set(triangles: &[[u32; 3]]) -> HashSet<(u32, u32)> {
    let mut out = HashSet::with_capacity(triangles.len() * 2);
    for t in triangles {
        for k in 0..3 {
            out.insert(key(t[k], t[(k + 1) % 3]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(verts: [u32; 2], weights: [f32; 2]) -> SeamPoint {
        SeamPoint { verts, weights }
    }

    #[test]
    fn vertices_edge_points_and_snapping() {
        assert_eq!(classify(&pt([3, 3], [1.0, 0.0]), 5, "s", 0, 'A').unwrap(), Point::Vertex(3));
        assert_eq!(classify(&pt([3, 4], [1.0, 0.0]), 5, "s", 0, 'A').unwrap(), Point::Vertex(3));
        assert_eq!(classify(&pt([3, 4], [0.0, 1.0]), 5, "s", 0, 'A').unwrap(), Point::Vertex(4));
        assert_eq!(classify(&pt([3, 4], [1e-8, 1.0]), 5, "s", 0, 'A').unwrap(), Point::Vertex(4));
        assert_eq!(classify(&pt([4, 1], [0.75, 0.25]), 5, "s", 0, 'A').unwrap(), Point::Edge { lo: 1, hi: 4, t: 0.75 });
    }

    #[test]
    fn bad_points_name_seam_pair_and_side() {
        let e = classify(&pt([0, 9], [0.5, 0.5]), 5, "collar", 7, 'B').unwrap_err();
        assert_eq!(e.to_string(), "weld: seam 'collar' pair 7 side B: index 9 is out of range (only 5 vertices)");
        let e = classify(&pt([0, 1], [f32::NAN, 0.5]), 5, "collar", 2, 'A').unwrap_err();
        assert!(e.to_string().starts_with("seam collar: pair 2 side A: weights (NaN, 0.5)"), "{e}");
        let e = classify(&pt([0, 1], [0.7, 0.7]), 5, "collar", 2, 'A').unwrap_err();
        assert!(matches!(e, TailorError::InvalidSeam { .. }), "{e}");
    }

    #[test]
    fn nearby_points_on_an_edge_are_one() {
        let mut pts = EdgePoints::default();
        let mut next = 10;
        let mut new = || {
            next += 1;
            next
        };
        let (a, fresh_a) = pts.insert(0, 1, 0.5, &mut new);
        let (b, fresh_b) = pts.insert(0, 1, 0.5 + SAME_POINT / 2.0, &mut new);
        let (c, _) = pts.insert(0, 1, 0.25, &mut new);
        assert!(fresh_a && !fresh_b);
        assert_eq!(a, b);
        assert_ne!(a, c);
        pts.sort();
        assert_eq!(pts.on(1, 0), &[(0.25, c), (0.5, a)]);
        assert!(pts.on(1, 2).is_empty());
    }
}
