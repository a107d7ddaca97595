//! Quality figures of a piece mesh, so that artists and tests can see what a resolution gives.

use serde::{Deserialize, Serialize};

/// Measured quality of a triangulation (lengths in metres, angles in degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshQuality {
    pub vertices: usize,
    pub triangles: usize,
    /// Smallest and largest triangle angle.
    pub min_angle_deg: f64,
    pub max_angle_deg: f64,
    /// Edge lengths over all undirected edges.
    pub min_edge: f64,
    pub mean_edge: f64,
    pub max_edge: f64,
    /// Fraction of edges whose length is within ±35 % of the target edge length.
    pub edges_within_35pct: f64,
    /// Shortest and longest contour (outer boundary) edge.
    pub contour_min_edge: f64,
    pub contour_max_edge: f64,
    /// Total rest area, m².
    pub area: f64,
    /// False when refinement stopped at its vertex budget (quality bounds may not hold).
    pub refinement_complete: bool,
}

pub(crate) fn measure(
    rest: &[[f64; 2]],
    triangles: &[[u32; 3]],
    contour: &[u32],
    target: f64,
    refinement_complete: bool,
) -> MeshQuality {
    let d = |a: u32, b: u32| {
        let (p, q) = (rest[a as usize], rest[b as usize]);
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
    };
    let (mut min_a, mut max_a, mut area) = (f64::INFINITY, 0.0f64, 0.0);
    // A sorted list, not a hash set, so that the sums (and the struct) are reproducible.
    let mut edges = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        let l = [d(t[1], t[2]), d(t[2], t[0]), d(t[0], t[1])];
        for k in 0..3 {
            let (a, b, c) = (l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
            let cos = ((b * b + c * c - a * a) / (2.0 * b * c)).clamp(-1.0, 1.0);
            let ang = cos.acos().to_degrees();
            min_a = min_a.min(ang);
            max_a = max_a.max(ang);
            let (u, v) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            edges.push((u.min(v), u.max(v)));
        }
        let (p, q, r) = (rest[t[0] as usize], rest[t[1] as usize], rest[t[2] as usize]);
        area += 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
    }
    edges.sort_unstable();
    edges.dedup();
    let lengths: Vec<f64> = edges.iter().map(|&(a, b)| d(a, b)).collect();
    let n = lengths.len().max(1) as f64;
    let within = lengths.iter().filter(|&&l| (l - target).abs() <= 0.35 * target).count() as f64 / n;
    let cl: Vec<f64> = (0..contour.len()).map(|i| d(contour[i], contour[(i + 1) % contour.len()])).collect();
    MeshQuality {
        vertices: rest.len(),
        triangles: triangles.len(),
        min_angle_deg: min_a,
        max_angle_deg: max_a,
        min_edge: lengths.iter().copied().fold(f64::INFINITY, f64::min),
        mean_edge: lengths.iter().sum::<f64>() / n,
        max_edge: lengths.iter().copied().fold(0.0, f64::max),
        edges_within_35pct: within,
        contour_min_edge: cl.iter().copied().fold(f64::INFINITY, f64::min),
        contour_max_edge: cl.iter().copied().fold(0.0, f64::max),
        area,
        refinement_complete,
    }
}
