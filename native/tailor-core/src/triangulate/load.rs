//! Building the constrained Delaunay triangulation of the input points and loop segments.
//!
//! spade's bulk loader sweeps a hull bucketed by angle round the points' centre. For a long
//! thin piece every point sits near one line through that centre, nearly all hull entries fall
//! in two buckets and each insertion scans them: quadratic time (a 1.28 km strip at 1 cm, 256,000
//! points: 18 s; 5 km: minutes). Such pieces are built by inserting the points one by one in
//! order along the piece's length instead, so that each point lands next to the previous one
//! with few flips: near-linear. (In input order it is quadratic too: a strip's whole bottom edge
//! goes in before its top edge, and each top point then flips a fan over the bottom.) Only
//! pieces of more than 50,000 points that are over 20 times longer than wide take this path;
//! every other piece keeps the bulk loader, so meshes of garments saved before come back as
//! they were.

use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, InsertionError, Point2 as SPoint, Triangulation};

type Cdt = ConstrainedDelaunayTriangulation<SPoint<f64>>;

/// Fewer points than this always take the bulk loader (fast enough whatever their shape).
const INCREMENTAL_MIN_POINTS: usize = 50_000;
/// Point clouds whose principal extents differ by more than this are "long and thin".
const INCREMENTAL_MIN_ELONGATION: f64 = 20.0;

/// The ratio of the longer to the shorter principal extent of `pts` (square roots of the
/// eigenvalues of their covariance): orientation-independent, so a diagonal strip counts too.
pub(crate) fn elongation(pts: &[SPoint<f64>]) -> f64 {
    let n = pts.len().max(1) as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(x, y), p| (x + p.x / n, y + p.y / n));
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in pts {
        let (dx, dy) = (p.x - mx, p.y - my);
        sxx += dx * dx / n;
        syy += dy * dy / n;
        sxy += dx * dy / n;
    }
    let (tr, det) = (sxx + syy, sxx * syy - sxy * sxy);
    let disc = (tr * tr / 4.0 - det).max(0.0).sqrt();
    let (big, small) = (tr / 2.0 + disc, (tr / 2.0 - disc).max(0.0));
    if small > 0.0 {
        (big / small).sqrt()
    } else {
        f64::INFINITY
    }
}

/// The order the constraint points went in when it was not the input's: spade numbers
/// vertices in insertion order, so vertex `k` of the triangulation is constraint point
/// `order[k]` for `k` below their count. Lattice seeds and Steiner points keep spade's numbers:
/// nothing downstream counts on theirs (and `refine` renumbers them when it removes a seed).
pub(crate) struct Order {
    order: Vec<usize>,
    spade_of: Vec<usize>,
}

impl Order {
    /// The triangulation's vertex number of constraint point `i`.
    pub(crate) fn spade(&self, i: usize) -> usize {
        self.spade_of.get(i).copied().unwrap_or(i)
    }

    /// The point number, in the output, of the triangulation's vertex `k`.
    pub(crate) fn input(&self, k: usize) -> usize {
        self.order.get(k).copied().unwrap_or(k)
    }
}

/// The triangulation of `verts` with the loop segments `edges` (input numbers) as constraints;
/// `on_conflict` hears of a segment that crosses another. Bulk-loaded (vertex `i` is input
/// point `i`), or for a long thin piece inserted along its length, the points before `split`
/// first and those after it next (so the first `split` vertices are still those points), with
/// the [`Order`] that maps the numbers. When two points coincide the result has fewer vertices
/// than `verts` and, on the incremental path, no constraints (the caller refuses it).
pub(crate) fn load_cdt(
    verts: Vec<SPoint<f64>>,
    edges: Vec<[usize; 2]>,
    split: usize,
    mut on_conflict: impl FnMut([usize; 2]),
) -> Result<(Cdt, Option<Order>), InsertionError> {
    if verts.len() < INCREMENTAL_MIN_POINTS || elongation(&verts) < INCREMENTAL_MIN_ELONGATION {
        return Ok((Cdt::try_bulk_load_cdt(verts, edges, on_conflict)?, None));
    }
    let n = verts.len();
    let axis = principal_axis(&verts);
    let key = |i: &usize| verts[*i].x * axis[0] + verts[*i].y * axis[1];
    let split = split.min(n);
    let mut order: Vec<usize> = (0..n).collect();
    order[..split].sort_by(|a, b| key(a).total_cmp(&key(b)));
    order[split..].sort_by(|a, b| key(a).total_cmp(&key(b)));
    let mut spade_of = vec![0; n];
    for (k, &i) in order.iter().enumerate() {
        spade_of[i] = k;
    }
    let mut cdt = Cdt::new();
    for &i in &order {
        cdt.insert(verts[i])?;
    }
    // Only the constraint points are numbered back (see `Order`).
    order.truncate(split);
    spade_of.truncate(split);
    let order = Order { order, spade_of };
    if cdt.num_vertices() != n {
        return Ok((cdt, Some(order)));
    }
    for [a, b] in edges {
        let (fa, fb) = (FixedVertexHandle::from_index(order.spade(a)), FixedVertexHandle::from_index(order.spade(b)));
        if a == b {
            continue;
        }
        if cdt.can_add_constraint(fa, fb) {
            cdt.add_constraint(fa, fb);
        } else {
            on_conflict([a, b]);
        }
    }
    Ok((cdt, Some(order)))
}

/// The unit direction of the larger principal extent of `pts`.
fn principal_axis(pts: &[SPoint<f64>]) -> [f64; 2] {
    let n = pts.len().max(1) as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(x, y), p| (x + p.x / n, y + p.y / n));
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in pts {
        let (dx, dy) = (p.x - mx, p.y - my);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    [angle.cos(), angle.sin()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elongation_is_orientation_free() {
        let strip = |angle: f64| -> Vec<SPoint<f64>> {
            let (c, s) = (angle.cos(), angle.sin());
            (0..1000)
                .flat_map(|i| [0.0, 1.0].map(|w| (i as f64, w)))
                .map(|(x, y)| SPoint::new(c * x - s * y, s * x + c * y))
                .collect()
        };
        for a in [0.0, 0.7, 1.2] {
            assert!(elongation(&strip(a)) > 100.0);
        }
        let square: Vec<SPoint<f64>> = (0..100).map(|i| SPoint::new((i % 10) as f64, (i / 10) as f64)).collect();
        assert!(elongation(&square) < 1.1);
    }

    #[test]
    fn an_order_maps_both_ways() {
        let o = Order { order: vec![2, 0, 1], spade_of: vec![1, 2, 0] };
        for i in 0..3 {
            assert_eq!(o.input(o.spade(i)), i);
        }
        assert_eq!(o.input(7), 7); // a lattice seed or Steiner point keeps its number
    }
}
