//! How far a body part reaches from its place's axis, binned along the axis and round it: what
//! a piece placed on the place must clear. A cylinder of the part's mean radius would cut
//! through it wherever the part is not round (a torso is wider than deep, by 10 cm on the
//! GarmentCode body), and one of its largest reach would hold the front of a shirt off the
//! chest by what the shoulders reach at the sides; binning lets a piece clear only what lies
//! under it (its span along the axis, its sector round it).

use serde::{Deserialize, Serialize};

use super::{cross, dot, sub, V3};

/// Round the axis, the grid's sectors (10 degrees each).
pub const SECTORS: usize = 36;

/// The largest distance from the axis of a body part's surface, per bin along the axis (`step`
/// metres, the first starting at `start` from the place's origin) and per sector round it
/// (angle from the place's facing, right-handed about the axis). 0 where the part has no surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reach {
    pub start: f64,
    pub step: f64,
    pub sectors: usize,
    /// `bins × sectors` values, row by row.
    pub values: Vec<f64>,
}

impl Reach {
    /// Bins the `samples` (surface points) round the axis through `origin` along unit `axis`,
    /// angles measured from unit `facing` (perpendicular to the axis).
    pub fn from_samples(samples: &[V3], origin: V3, axis: V3, facing: V3, step: f64) -> Reach {
        let side = cross(axis, facing);
        let coords: Vec<(f64, f64, f64)> = samples
            .iter()
            .map(|&p| {
                let r = sub(p, origin);
                let along = dot(r, axis);
                let (x, y) = (dot(r, facing), dot(r, side));
                (along, y.atan2(x), (x * x + y * y).sqrt())
            })
            .collect();
        let lo = coords.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
        let hi = coords.iter().map(|c| c.0).fold(f64::NEG_INFINITY, f64::max);
        if coords.is_empty() {
            return Reach { start: 0.0, step, sectors: SECTORS, values: Vec::new() };
        }
        let bins = ((hi - lo) / step).floor() as usize + 1;
        let mut values = vec![0.0; bins * SECTORS];
        for (along, angle, dist) in coords {
            let i = (((along - lo) / step) as usize).min(bins - 1);
            let j = sector_of(angle);
            values[i * SECTORS + j] = f64::max(values[i * SECTORS + j], dist);
        }
        Reach { start: lo, step, sectors: SECTORS, values }
    }

    /// Number of bins along the axis.
    pub fn bins(&self) -> usize {
        self.values.len().checked_div(self.sectors).unwrap_or(0)
    }

    /// The largest reach between `along` `[a0, a1]` and angles `[t0, t1]` (radians from the
    /// facing, `t0 ≤ t1`, a span of 2π or more is all round), widened by a bin and a sector
    /// each way, since a sample near a bin's edge stands for surface just beyond it.
    pub fn max_in(&self, a0: f64, a1: f64, t0: f64, t1: f64) -> f64 {
        let bins = self.bins();
        if bins == 0 || self.sectors == 0 {
            return 0.0;
        }
        let first = ((a0 - self.start) / self.step).floor() as i64 - 1;
        let last = ((a1 - self.start) / self.step).floor() as i64 + 1;
        let (first, last) = (first.max(0), last.min(bins as i64 - 1));
        let width = std::f64::consts::TAU / self.sectors as f64;
        let all_round = t1 - t0 + 2.0 * width >= std::f64::consts::TAU;
        let (s0, count) = if all_round {
            (0, self.sectors)
        } else {
            let s0 = sector_index(t0, self.sectors) as i64 - 1;
            let s1 = sector_index(t1, self.sectors) as i64 + 1;
            let span = (s1 - s0).rem_euclid(self.sectors as i64) as usize + 1;
            (s0.rem_euclid(self.sectors as i64) as usize, span.min(self.sectors))
        };
        let mut best = 0.0f64;
        for i in first..=last {
            let row = &self.values[i as usize * self.sectors..(i as usize + 1) * self.sectors];
            for k in 0..count {
                best = best.max(row[(s0 + k) % self.sectors]);
            }
        }
        best
    }
}

fn sector_index(angle: f64, sectors: usize) -> usize {
    let turn = angle.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
    ((turn * sectors as f64) as usize).min(sectors - 1)
}

fn sector_of(angle: f64) -> usize {
    sector_index(angle, SECTORS)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples on an ellipse (0.2 wide, 0.1 deep) round a vertical axis: the reach facing the
    /// front is the depth, at the sides the width, and all round the largest.
    #[test]
    fn reach_follows_the_shape_round_the_axis() {
        let mut samples = Vec::new();
        for k in 0..360 {
            let t = (k as f64).to_radians();
            for h in 0..10 {
                samples.push([0.2 * t.sin(), h as f64 * 0.01, 0.1 * t.cos()]);
            }
        }
        let r = Reach::from_samples(&samples, [0.0; 3], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], 0.01);
        assert_eq!(r.bins(), 10);
        let front = r.max_in(0.0, 0.05, -0.01, 0.01);
        assert!((0.1..0.11).contains(&front), "{front}");
        let side = r.max_in(0.0, 0.05, 1.5, 1.6);
        assert!(side > 0.195, "{side}");
        assert!((r.max_in(0.0, 0.09, -4.0, 4.0) - 0.2).abs() < 1e-9);
        // Beyond the samples along the axis: nothing to clear.
        assert_eq!(r.max_in(0.5, 0.6, -4.0, 4.0), 0.0);
    }
}
