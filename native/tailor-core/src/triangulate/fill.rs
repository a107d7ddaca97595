//! Interior seed points on a hexagonal lattice.
//!
//! Delaunay refinement alone (Ruppert/Chew) only inserts what the angle and area bounds demand,
//! which leaves triangle sizes spread over a factor of two or more. Seeding the interior with
//! the vertices of the equilateral lattice of side `h` (rows `h·√3/2` apart, every other row
//! shifted by `h/2`) makes the Delaunay triangulation of the interior exactly that lattice:
//! every interior edge has length `h`. Lattice points closer than `margin·h` to a constraint
//! (outline, hole, internal line) are dropped so no sliver forms against the resampled
//! boundary; refinement then repairs the thin band between lattice and boundary.

use super::region::Region;
use super::resample::segment_projection;
use crate::pattern::Point2;

/// Lattice points inside `outline`, outside every hole, at least `margin·h` from every segment.
pub(crate) fn lattice_points(
    outline: &[Point2],
    holes: &[Vec<Point2>],
    segments: &[[Point2; 2]],
    h: f64,
    margin: f64,
) -> Vec<Point2> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in outline {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let grid = SegmentGrid::new(segments, lo, hi, h);
    let region = Region::new(outline, holes, h);
    let r = margin * h;
    let dy = h * 3f64.sqrt() / 2.0;
    let rows = ((hi[1] - lo[1]) / dy).floor() as usize;
    let cols = ((hi[0] - lo[0]) / h).floor() as usize + 1;
    // Centre the lattice in the bounding box so symmetric pieces get symmetric meshes.
    let y0 = lo[1] + 0.5 * ((hi[1] - lo[1]) - rows as f64 * dy);
    let x0 = lo[0] + 0.5 * ((hi[0] - lo[0]) - (cols as f64 - 0.5) * h);
    let mut out = Vec::new();
    for j in 0..=rows {
        let y = y0 + j as f64 * dy;
        let shift = if j % 2 == 1 { 0.5 * h } else { 0.0 };
        for i in 0..=cols {
            let p = [x0 + shift + i as f64 * h, y];
            if region.contains(p) && grid.clear_of(segments, p, r) {
                out.push(p);
            }
        }
    }
    out
}

/// Segments bucketed on a uniform grid of cell size `h`, for "is anything within r" queries.
struct SegmentGrid {
    lo: Point2,
    cell: f64,
    nx: usize,
    ny: usize,
    buckets: Vec<Vec<u32>>,
}

impl SegmentGrid {
    fn new(segments: &[[Point2; 2]], lo: Point2, hi: Point2, h: f64) -> Self {
        let cell = h;
        let nx = ((hi[0] - lo[0]) / cell).floor() as usize + 1;
        let ny = ((hi[1] - lo[1]) / cell).floor() as usize + 1;
        let mut g = SegmentGrid { lo, cell, nx, ny, buckets: vec![Vec::new(); nx * ny] };
        for (s, [a, b]) in segments.iter().enumerate() {
            let (i0, j0) = g.cell_of([a[0].min(b[0]), a[1].min(b[1])]);
            let (i1, j1) = g.cell_of([a[0].max(b[0]), a[1].max(b[1])]);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    g.buckets[j * nx + i].push(s as u32);
                }
            }
        }
        g
    }

    fn cell_of(&self, p: Point2) -> (usize, usize) {
        let i = ((p[0] - self.lo[0]) / self.cell).floor().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = ((p[1] - self.lo[1]) / self.cell).floor().clamp(0.0, (self.ny - 1) as f64) as usize;
        (i, j)
    }

    /// True when no segment is within `r` (≤ one cell) of `p`.
    fn clear_of(&self, segments: &[[Point2; 2]], p: Point2, r: f64) -> bool {
        let (ci, cj) = self.cell_of(p);
        for j in cj.saturating_sub(1)..=(cj + 1).min(self.ny - 1) {
            for i in ci.saturating_sub(1)..=(ci + 1).min(self.nx - 1) {
                for &s in &self.buckets[j * self.nx + i] {
                    let [a, b] = segments[s as usize];
                    if segment_projection(a, b, p).1 < r {
                        return false;
                    }
                }
            }
        }
        true
    }
}
