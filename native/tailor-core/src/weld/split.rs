//! Cutting a triangle at the seam points on its edges, so that it shares those vertices with
//! the triangles across the seam.
//!
//! The triangle `(c₀, c₁, c₂)` with points on its edges is the polygon
//! `c₀, p₀₁…, c₁, p₁₂…, c₂, p₂₀…` (every point collinear with its edge). It is triangulated
//! without zero-area triangles:
//!
//! * points on one edge only: a fan from the opposite corner, `(pᵢ, pᵢ₊₁, c_opp)` along the
//!   edge (a fan from any other corner would put collinear points in one triangle);
//! * points on two or three edges: a fan from a new vertex at the centroid,
//!   `(qᵢ, qᵢ₊₁, centroid)` around the polygon, the one apex collinear with no edge.
//!
//! Every sub-triangle keeps the winding of the original. Each corner carries its barycentric
//! coordinates in the original triangle, so per-corner attributes (UVs) carry over exactly.

/// A corner of a sub-triangle: its node and its barycentric coordinates in the source triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Corner {
    pub node: u32,
    pub bary: [f32; 3],
}

fn unit(k: usize) -> [f32; 3] {
    let mut b = [0.0; 3];
    b[k] = 1.0;
    b
}

/// The boundary of triangle `tri` with the points of each edge, from corner 0 around.
/// `points[k]` are the points inside edge `(tri[k], tri[k+1])`, `(t, node)` sorted by `t` from
/// the edge's lower vertex index.
fn boundary(tri: [u32; 3], points: [&[(f32, u32)]; 3]) -> Vec<Corner> {
    let mut out = Vec::with_capacity(3 + points.iter().map(|p| p.len()).sum::<usize>());
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        out.push(Corner { node: a, bary: unit(k) });
        let along = |&(t, node): &(f32, u32)| {
            let u = if a < b { t } else { 1.0 - t };
            let mut bary = [0.0; 3];
            bary[k] = 1.0 - u;
            bary[(k + 1) % 3] = u;
            Corner { node, bary }
        };
        if a < b {
            out.extend(points[k].iter().map(along));
        } else {
            out.extend(points[k].iter().rev().map(along));
        }
    }
    out
}

/// Sub-triangles of `tri` cut at `points` (see [`boundary`]); `centroid()` makes the node of a
/// new centroid vertex when one is needed. A triangle without points comes back whole.
pub(super) fn split(tri: [u32; 3], points: [&[(f32, u32)]; 3], centroid: impl FnOnce() -> u32) -> Vec<[Corner; 3]> {
    let cut: Vec<usize> = (0..3).filter(|&k| !points[k].is_empty()).collect();
    let ring = boundary(tri, points);
    match cut.as_slice() {
        [] => vec![[ring[0], ring[1], ring[2]]],
        &[k] => {
            // Rotate so the cut edge runs from ring[0] (corner k) to corner k+1; the rest of
            // the ring is then [corner k+1, corner k+2] (the opposite corner is last).
            let start = ring.iter().position(|c| c.bary[k] == 1.0).expect("corner k is on the ring");
            let rotated: Vec<Corner> = ring[start..].iter().chain(&ring[..start]).copied().collect();
            let apex = *rotated.last().expect("three corners at least");
            rotated[..rotated.len() - 1].windows(2).map(|w| [w[0], w[1], apex]).collect()
        }
        _ => {
            let apex = Corner { node: centroid(), bary: [1.0 / 3.0; 3] };
            (0..ring.len()).map(|i| [ring[i], ring[(i + 1) % ring.len()], apex]).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(p: &[[f64; 2]; 3], c: &[Corner; 3]) -> f64 {
        let q = c.map(|c| {
            let mut x = [0.0; 2];
            for k in 0..3 {
                x[0] += c.bary[k] as f64 * p[k][0];
                x[1] += c.bary[k] as f64 * p[k][1];
            }
            x
        });
        0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]))
    }

    const P: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

    #[test]
    fn one_cut_edge_fans_from_the_opposite_corner() {
        // Triangle (5, 2, 7): edge (2, 7) is k = 1, walked from 2 (its lower index) to 7.
        let pts: &[(f32, u32)] = &[(0.25, 10), (0.5, 11)];
        let subs = split([5, 2, 7], [&[], pts, &[]], || unreachable!());
        assert_eq!(subs.len(), 3);
        assert!(subs.iter().all(|s| s[2].node == 5));
        assert_eq!(subs.iter().map(|s| [s[0].node, s[1].node]).collect::<Vec<_>>(), [[2, 10], [10, 11], [11, 7]]);
        let total: f64 = subs.iter().map(|s| area(&P, s)).sum();
        assert!((total - 0.5).abs() < 1e-6 && subs.iter().all(|s| area(&P, s) > 0.0));
        assert_eq!(subs[0][1].bary, [0.0, 0.75, 0.25]);
    }

    #[test]
    fn reversed_edge_walks_points_backwards() {
        // Edge k = 0 of (7, 2, 5) runs from 7 down to 2: points come in decreasing t.
        let pts: &[(f32, u32)] = &[(0.25, 10), (0.5, 11)];
        let subs = split([7, 2, 5], [pts, &[], &[]], || unreachable!());
        assert_eq!(subs.iter().map(|s| [s[0].node, s[1].node]).collect::<Vec<_>>(), [[7, 11], [11, 10], [10, 2]]);
        assert!(subs.iter().all(|s| area(&P, s) > 0.0));
    }

    #[test]
    fn cuts_on_two_edges_fan_from_a_centroid() {
        let (a, b): (&[(f32, u32)], &[(f32, u32)]) = (&[(0.5, 10)], &[(0.3, 11), (0.6, 12)]);
        let subs = split([0, 1, 2], [a, &[], b], || 99);
        assert_eq!(subs.len(), 6);
        assert!(subs.iter().all(|s| s[2].node == 99 && area(&P, s) > 0.0));
        let total: f64 = subs.iter().map(|s| area(&P, s)).sum();
        assert!((total - 0.5).abs() < 1e-6);
    }

    #[test]
    fn an_uncut_triangle_is_unchanged() {
        let subs = split([4, 5, 6], [&[], &[], &[]], || unreachable!());
        assert_eq!(subs.len(), 1);
        assert_eq!(subs[0].map(|c| c.node), [4, 5, 6]);
    }
}
