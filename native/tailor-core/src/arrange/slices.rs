//! Cross-sections of a body mesh by horizontal planes: each plane cuts the closed surface in
//! loops (a torso, two legs, two arms, fingers), found exactly from the triangles the plane
//! crosses rather than from vertices near it, so that the loops do not depend on how densely
//! the body is meshed.
//!
//! A triangle the plane crosses gives one segment between two points on two of its edges; a
//! point is keyed by its mesh edge, so the segments of neighbouring triangles share their end
//! points, and the loops are the connected components of the segments (union-find). Nothing
//! needs the segments in order: a loop's centroid weights its points by segment length, and
//! point-in-loop counts the segments a ray crosses (parity), which works for unordered ones.

use std::collections::HashMap;

/// One closed cross-section in the plane's 2D coordinates `(lateral, front)`.
#[derive(Debug, Clone)]
pub(super) struct Loop {
    /// The points where the plane cuts mesh edges.
    pub points: Vec<[f64; 2]>,
    /// Segments between points (indices into `points`).
    segments: Vec<[usize; 2]>,
    /// Length-weighted centroid of the segments.
    pub centroid: [f64; 2],
    /// Total length of the segments.
    pub perimeter: f64,
    /// Bounding box, `[lateral, front]` minima and maxima.
    pub lo: [f64; 2],
    pub hi: [f64; 2],
}

impl Loop {
    /// Whether `p` is inside: a ray along `+lateral` crosses an odd number of segments (an end
    /// point on the ray counts for the segment whose other end is above it, so a vertex shared
    /// by two segments counts once).
    pub fn contains(&self, p: [f64; 2]) -> bool {
        let mut inside = false;
        for &[a, b] in &self.segments {
            let (a, b) = (self.points[a], self.points[b]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if x > p[0] {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Lateral width.
    pub fn width(&self) -> f64 {
        self.hi[0] - self.lo[0]
    }
}

fn find(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

/// The loops cut by the plane at height `level`. `height[v]` and `flat[v]` are vertex `v`'s
/// height and `(lateral, front)` coordinates; every index of `triangles` must be in range.
/// A vertex exactly on the plane counts as above it, so no segment is cut twice.
pub(super) fn slice(height: &[f64], flat: &[[f64; 2]], triangles: &[[u32; 3]], level: f64) -> Vec<Loop> {
    let mut index: HashMap<(u32, u32), usize> = HashMap::new();
    let mut points: Vec<[f64; 2]> = Vec::new();
    let mut segments: Vec<[usize; 2]> = Vec::new();
    for t in triangles {
        let above = t.map(|v| height[v as usize] >= level);
        if above[0] == above[1] && above[1] == above[2] {
            continue;
        }
        let mut ends = [0usize; 2];
        let mut n = 0;
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            if above[a] == above[b] {
                continue;
            }
            let (i, j) = (t[a].min(t[b]), t[a].max(t[b]));
            let k = *index.entry((i, j)).or_insert_with(|| {
                let (hi, hj) = (height[i as usize], height[j as usize]);
                let f = (level - hi) / (hj - hi);
                let (pi, pj) = (flat[i as usize], flat[j as usize]);
                points.push([pi[0] + f * (pj[0] - pi[0]), pi[1] + f * (pj[1] - pi[1])]);
                points.len() - 1
            });
            if n < 2 {
                ends[n] = k;
                n += 1;
            }
        }
        if n == 2 {
            segments.push(ends);
        }
    }
    let mut parent: Vec<usize> = (0..points.len()).collect();
    for &[a, b] in &segments {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            parent[ra] = rb;
        }
    }
    let mut group: HashMap<usize, usize> = HashMap::new();
    let mut loops: Vec<(Vec<usize>, Vec<[usize; 2]>)> = Vec::new();
    for &[a, b] in &segments {
        let root = find(&mut parent, a);
        let g = *group.entry(root).or_insert_with(|| {
            loops.push((Vec::new(), Vec::new()));
            loops.len() - 1
        });
        loops[g].1.push([a, b]);
    }
    loops
        .into_iter()
        .map(|(_, segs)| {
            // Renumber the loop's points from 0.
            let mut local: HashMap<usize, usize> = HashMap::new();
            let mut pts = Vec::new();
            let mut local_segs = Vec::with_capacity(segs.len());
            for [a, b] in segs {
                let mut id = |k: usize| {
                    *local.entry(k).or_insert_with(|| {
                        pts.push(points[k]);
                        pts.len() - 1
                    })
                };
                local_segs.push([id(a), id(b)]);
            }
            finish(pts, local_segs)
        })
        .collect()
}

fn finish(points: Vec<[f64; 2]>, segments: Vec<[usize; 2]>) -> Loop {
    let (mut sum, mut total) = ([0.0; 2], 0.0);
    for &[a, b] in &segments {
        let (p, q) = (points[a], points[b]);
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        for k in 0..2 {
            sum[k] += len * 0.5 * (p[k] + q[k]);
        }
        total += len;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let centroid = if total > 0.0 {
        [sum[0] / total, sum[1] / total]
    } else {
        let n = points.len().max(1) as f64;
        [points.iter().map(|p| p[0]).sum::<f64>() / n, points.iter().map(|p| p[1]).sum::<f64>() / n]
    };
    Loop { points, segments, centroid, perimeter: total, lo, hi }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::box_mesh;

    /// A plane through two boxes side by side cuts two square loops, each containing its own
    /// centre and not the other's, with the boxes' perimeters.
    #[test]
    fn two_boxes_give_two_loops() {
        let (mut v, mut t) = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let (v2, t2) = box_mesh([3.0, 0.0, 0.0], [4.0, 1.0, 1.0]);
        let n = v.len() as u32;
        v.extend(v2);
        t.extend(t2.iter().map(|tri| tri.map(|i| i + n)));
        // Up is y; the plane's coordinates are (x, z).
        let height: Vec<f64> = v.iter().map(|p| p[1] as f64).collect();
        let flat: Vec<[f64; 2]> = v.iter().map(|p| [p[0] as f64, p[2] as f64]).collect();
        let mut loops = slice(&height, &flat, &t, 0.4);
        loops.sort_by(|a, b| a.centroid[0].total_cmp(&b.centroid[0]));
        assert_eq!(loops.len(), 2);
        for (l, cx) in loops.iter().zip([0.5, 3.5]) {
            assert!((l.centroid[0] - cx).abs() < 1e-9 && (l.centroid[1] - 0.5).abs() < 1e-9, "{:?}", l.centroid);
            assert!((l.perimeter - 4.0).abs() < 1e-9, "{}", l.perimeter);
            assert!(l.contains([cx, 0.5]) && !l.contains([cx + 1.5, 0.5]));
            assert!((l.width() - 1.0).abs() < 1e-9);
        }
        assert!(slice(&height, &flat, &t, 2.0).is_empty());
    }
}
