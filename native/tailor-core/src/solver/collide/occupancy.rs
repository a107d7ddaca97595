//! Where the cloth can be over a frame, cell by coarse cell (issue 22): a moving collider's
//! frame filing keeps only the triangles near some particle's motion, where the box of the
//! whole cloth kept everything inside it (a T-shirt's box holds the torso, the upper arms and
//! the hands hanging beside the hips: 13-14k triangles filed for every substep, 11 ms of a
//! 38 ms walking frame on 2 cores).
//!
//! Each particle marks the cells of side `size` that the box of its substep start, its
//! prediction and its prediction carried on over the frame's remaining substeps (the motion the
//! simulation's `reach_of` extrapolates for the whole cloth) reaches, grown by `grow`; a
//! triangle is filed when its box over the frame touches a marked cell. It is the whole-cloth
//! cull of `MeshCollider::prepare` particle by particle: filed for `2.5 l` round the motion,
//! valid while each particle's box stays within `l` of it ([`covers`](Occupancy::covers),
//! checked at every later substep; a particle that leaves it costs a rebuild, as a cloth
//! leaving its box did). A particle within `l` of its box queries a cell within `2l` of it,
//! and a triangle is filed only in cells within `PAD·l = l/4` of its box: `2.5 l` covers both.

use glam::Vec3;
use rayon::prelude::*;

use crate::solver::model::soa::Vec3Soa;

/// Most cells one grid holds: a cloth spread wider falls back on the whole cloth's box.
const MAX_CELLS: usize = 1 << 22;

/// The motion of the cloth over the frame's remaining substeps.
#[derive(Clone, Copy)]
pub(crate) struct ClothMotion<'a> {
    pub x_start: &'a Vec3Soa,
    pub y: &'a Vec3Soa,
    /// Substeps left in the frame, this one included.
    pub steps: f32,
}

impl ClothMotion<'_> {
    /// Particle `i`'s box: its substep start, prediction, and prediction carried on `steps`
    /// times (with `extrapolate`).
    #[inline]
    fn particle_box(&self, i: usize, extrapolate: bool) -> (Vec3, Vec3) {
        let (a, b) = (self.x_start.get(i), self.y.get(i));
        let (lo, hi) = (a.min(b), a.max(b));
        if !extrapolate {
            return (lo, hi);
        }
        let e = a + (b - a) * self.steps;
        (lo.min(e), hi.max(e))
    }
}

/// Coarse cells marked where the cloth can reach.
#[derive(Debug, Clone)]
pub(crate) struct Occupancy {
    origin: Vec3,
    size: f32,
    dims: [usize; 3],
    marked: Vec<bool>,
}

impl Occupancy {
    /// The cells (side `size`) reached by some particle's motion box grown by `grow`; `None`
    /// for a cloth without particles or spread over more than `MAX_CELLS` cells.
    pub fn new(motion: &ClothMotion<'_>, grow: f32, size: f32) -> Option<Self> {
        let n = motion.x_start.len();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for i in 0..n {
            let (a, b) = motion.particle_box(i, true);
            (lo, hi) = (lo.min(a), hi.max(b));
        }
        if n == 0 || !(lo.is_finite() && hi.is_finite() && size > 0.0) {
            return None;
        }
        let origin = lo - grow;
        let span = ((hi + grow - origin) / size).floor() + 1.0;
        if span.max_element() > MAX_CELLS as f32 || span.element_product() > MAX_CELLS as f32 {
            return None;
        }
        let dims = [span.x as usize, span.y as usize, span.z as usize];
        let mut occ = Self { origin, size, dims, marked: vec![false; dims[0] * dims[1] * dims[2]] };
        for i in 0..n {
            let (a, b) = motion.particle_box(i, true);
            if let Some((c0, c1)) = occ.range(a - grow, b + grow) {
                for z in c0[2]..=c1[2] {
                    for y in c0[1]..=c1[1] {
                        let row = (z * dims[1] + y) * dims[0];
                        occ.marked[row + c0[0]..=row + c1[0]].fill(true);
                    }
                }
            }
        }
        Some(occ)
    }

    /// The cells a box overlaps, clamped to the grid; `None` when it misses the grid.
    fn range(&self, lo: Vec3, hi: Vec3) -> Option<([usize; 3], [usize; 3])> {
        let (a, b) = ((lo - self.origin) / self.size, (hi - self.origin) / self.size);
        let d = Vec3::new(self.dims[0] as f32, self.dims[1] as f32, self.dims[2] as f32);
        if b.cmplt(Vec3::ZERO).any() || a.cmpge(d).any() {
            return None;
        }
        let (a, b) = (a.floor().max(Vec3::ZERO), b.floor().min(d - 1.0));
        Some(([a.x as usize, a.y as usize, a.z as usize], [b.x as usize, b.y as usize, b.z as usize]))
    }

    /// Whether the box `lo..hi` touches a marked cell.
    pub fn touches(&self, lo: Vec3, hi: Vec3) -> bool {
        let Some((c0, c1)) = self.range(lo, hi) else { return false };
        (c0[2]..=c1[2]).any(|z| {
            (c0[1]..=c1[1]).any(|y| {
                let row = (z * self.dims[1] + y) * self.dims[0];
                self.marked[row + c0[0]..=row + c1[0]].iter().any(|&m| m)
            })
        })
    }

    /// Whether every particle's box (start and prediction) grown by `grow` lies in marked cells.
    pub fn covers(&self, motion: &ClothMotion<'_>, grow: f32) -> bool {
        let d = Vec3::new(self.dims[0] as f32, self.dims[1] as f32, self.dims[2] as f32) * self.size;
        (0..motion.x_start.len()).into_par_iter().with_min_len(4096).all(|i| {
            let (a, b) = motion.particle_box(i, false);
            let (lo, hi) = (a - grow, b + grow);
            if lo.cmplt(self.origin).any() || hi.cmpge(self.origin + d).any() {
                return false;
            }
            let Some((c0, c1)) = self.range(lo, hi) else { return false };
            (c0[2]..=c1[2]).all(|z| {
                (c0[1]..=c1[1]).all(|y| {
                    let row = (z * self.dims[1] + y) * self.dims[0];
                    self.marked[row + c0[0]..=row + c1[0]].iter().all(|&m| m)
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soa(points: &[[f32; 3]]) -> Vec3Soa {
        let mut s = Vec3Soa::zeros(points.len());
        for (i, p) in points.iter().enumerate() {
            s.set(i, Vec3::from(*p));
        }
        s
    }

    /// Two particles far apart mark only the cells round their own motion: a box between them
    /// touches nothing, boxes at them do; their grown boxes are covered, a particle that
    /// moved away is not.
    #[test]
    fn marks_the_cells_round_each_particle_alone() {
        let x0 = soa(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        let y = soa(&[[0.0, 0.01, 0.0], [1.0, -0.01, 0.0]]);
        let motion = ClothMotion { x_start: &x0, y: &y, steps: 3.0 };
        let occ = Occupancy::new(&motion, 0.02, 0.02).unwrap();
        assert!(occ.touches(Vec3::new(-0.01, 0.0, 0.0), Vec3::new(0.01, 0.01, 0.01)));
        assert!(occ.touches(Vec3::new(0.99, -0.05, 0.0), Vec3::new(1.0, -0.04, 0.0)), "the extrapolated motion");
        assert!(!occ.touches(Vec3::new(0.4, -0.1, -0.1), Vec3::new(0.6, 0.1, 0.1)));
        assert!(occ.covers(&motion, 0.01));
        let moved = soa(&[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]);
        assert!(!occ.covers(&ClothMotion { x_start: &x0, y: &moved, steps: 1.0 }, 0.01));
    }
}
