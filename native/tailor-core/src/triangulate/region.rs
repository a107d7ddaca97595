//! A piece's region (outline minus holes) indexed for many point-in-region queries.
//!
//! The lattice fill and the triangle filter ask "is this point inside the piece?" once per
//! lattice point and once per triangle; the plain even-odd test ([`super::resample::inside`])
//! walks every outline edge each time, so a long thin piece (a 1.28 km strip at 1 cm: 256,000
//! outline points) took quadratic time: 21 s, and over a minute at 5 km. Here the edges are
//! bucketed in bands across the region's longer side, and the ray of the even-odd test runs
//! across the bands, so a query visits only the edges of its own band: a few for any strip,
//! whatever its length.

use crate::pattern::Point2;

/// Outline and holes, their edges bucketed in bands along the longer side of the bounding box.
pub(crate) struct Region {
    /// Edges `(a, b, loop)`; loop 0 is the outline, `k + 1` hole `k`.
    edges: Vec<(Point2, Point2, u32)>,
    /// The axis the bands are cut along (0: bands of x, ray towards +y; 1: bands of y, ray +x).
    axis: usize,
    lo: f64,
    width: f64,
    bands: Vec<Vec<u32>>,
    loops: usize,
}

impl Region {
    /// Indexes `outline` and `holes` with about one band per `h` along the longer side (at
    /// most one band per edge, so the index stays linear in the edge count).
    pub(crate) fn new(outline: &[Point2], holes: &[Vec<Point2>], h: f64) -> Self {
        let mut edges = Vec::new();
        for (k, poly) in std::iter::once(outline).chain(holes.iter().map(Vec::as_slice)).enumerate() {
            for i in 0..poly.len() {
                edges.push((poly[i], poly[(i + 1) % poly.len()], k as u32));
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in outline {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let axis = if hi[0] - lo[0] >= hi[1] - lo[1] { 0 } else { 1 };
        let span = (hi[axis] - lo[axis]).max(0.0);
        let mut n =
            if span.is_finite() && h > 0.0 { ((span / h).ceil() as usize).clamp(1, edges.len().max(1)) } else { 1 };
        // Edges that span many bands (a sawtooth of long teeth) are listed in each: halve the
        // band count until the lists stay linear in the edge count.
        let entries = |n: usize| -> usize {
            let width = if span > 0.0 { span / n as f64 } else { 1.0 };
            let band = |v: f64| (((v - lo[axis]) / width).floor().max(0.0) as usize).min(n - 1);
            edges.iter().map(|(a, b, _)| band(a[axis].max(b[axis])) - band(a[axis].min(b[axis])) + 1).sum()
        };
        while n > 1 && entries(n) > 16 * edges.len() {
            n /= 2;
        }
        let width = if span > 0.0 { span / n as f64 } else { 1.0 };
        let mut r = Region { edges, axis, lo: lo[axis], width, bands: vec![Vec::new(); n], loops: holes.len() + 1 };
        for (e, &(a, b, _)) in r.edges.iter().enumerate() {
            let (b0, b1) = (r.band(a[axis].min(b[axis])), r.band(a[axis].max(b[axis])));
            for band in &mut r.bands[b0..=b1] {
                band.push(e as u32);
            }
        }
        r
    }

    fn band(&self, v: f64) -> usize {
        (((v - self.lo) / self.width).floor().max(0.0) as usize).min(self.bands.len() - 1)
    }

    /// Whether `p` is inside the outline and outside every hole (even-odd per loop, as
    /// [`super::resample::inside`] decides it for each).
    pub(crate) fn contains(&self, p: Point2) -> bool {
        let (u, v) = (self.axis, 1 - self.axis);
        let mut odd = [false; 8];
        let mut odd_more = Vec::new();
        for &e in &self.bands[self.band(p[u])] {
            let (a, b, k) = self.edges[e as usize];
            // The crossing test of `resample::inside` with the roles of the axes chosen above.
            if (a[u] > p[u]) != (b[u] > p[u]) && p[v] < (b[v] - a[v]) * (p[u] - a[u]) / (b[u] - a[u]) + a[v] {
                let k = k as usize;
                if k < odd.len() {
                    odd[k] = !odd[k];
                } else {
                    odd_more.push(k);
                }
            }
        }
        if !odd[0] {
            return false;
        }
        if odd[1..].iter().any(|&o| o) {
            return false;
        }
        if self.loops > odd.len() {
            // Many holes: count the crossings of each hole met here.
            odd_more.sort_unstable();
            let mut i = 0;
            while i < odd_more.len() {
                let j = odd_more[i..].iter().take_while(|&&k| k == odd_more[i]).count();
                if j % 2 == 1 {
                    return false;
                }
                i += j;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::resample::inside;
    use super::*;

    /// Agrees with the plain test (outline and each hole) on a grid of points over shapes with
    /// slanted edges, holes (more than the fixed parity slots) and both orientations.
    #[test]
    fn agrees_with_the_plain_even_odd_test() {
        let outline: Vec<Point2> = vec![[0.0, 0.0], [3.0, 0.2], [3.2, 1.1], [1.5, 2.0], [-0.2, 1.0]];
        let holes: Vec<Vec<Point2>> = (0..10)
            .map(|k| {
                let (x, y) = (0.3 + 0.25 * k as f64, 0.5 + 0.05 * k as f64);
                vec![[x, y], [x + 0.1, y], [x + 0.05, y + 0.2]]
            })
            .collect();
        let tall: Vec<Point2> = outline.iter().map(|p| [p[1], p[0]]).collect();
        for (o, hs) in [(&outline, &holes), (&tall, &Vec::new())] {
            for h in [0.01, 0.3, 5.0] {
                let r = Region::new(o, hs, h);
                for i in 0..70 {
                    for j in 0..70 {
                        let p = [-0.3 + i as f64 * 0.05 + 1e-4, -0.3 + j as f64 * 0.05 + 2e-4];
                        let want = inside(o, p) && !hs.iter().any(|hl| inside(hl, p));
                        assert_eq!(r.contains(p), want, "{p:?} h {h}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_long_strip_costs_a_few_edges_per_query() {
        let n = 200_000;
        let mut outline: Vec<Point2> = (0..=n).map(|i| [i as f64 * 0.01, 0.0]).collect();
        outline.extend((0..=n).rev().map(|i| [i as f64 * 0.01, 0.01]));
        let r = Region::new(&outline, &[], 0.01);
        let t = std::time::Instant::now();
        let inside_count = (0..n).filter(|&i| r.contains([i as f64 * 0.01 + 0.005, 0.005])).count();
        assert_eq!(inside_count, n);
        assert!(t.elapsed().as_secs_f64() < 1.0, "{:?}", t.elapsed());
    }
}
