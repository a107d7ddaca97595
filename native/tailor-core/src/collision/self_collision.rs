//! Self-collision candidates: pairs of cloth particles whose spheres (radius `r`) overlap.
//!
//! Each particle is filed in the cell containing it (hash of Eq. 1-3, cell side `l`). Two
//! particles closer than `2r ≤ l` differ by less than `l` along every axis, so their cells
//! differ by at most one along every axis: the pair lies within the 27-cell block around
//! either particle. Each cell pair is visited once, from one side: particle `i` visits its own
//! cell (taking only `j > i`) and the 13 "forward" neighbours `cell(i) + d` whose last
//! non-zero offset component is positive; the 13 others are `−d` of these and are covered when
//! the other particle visits *its* forward cells. In each cell only the entries with that
//! cell's `cell_id` are taken, never the other cells sharing the bucket. A pair is reported
//! once, as `[min, max]`, when `|x_i − x_j|² < (2r)²` and the exclusion predicate (called with
//! `min, max`) does not reject it: particles joined by an edge, a triangle or a seam are meant
//! to be close and must never repel.
//!
//! Work is split in fixed blocks of particles, each with its own reusable pair buffer; the
//! buffers are concatenated and sorted, so the pair list is identical from run to run, and
//! nothing is allocated once the buffers have grown.

use rayon::prelude::*;

use super::hash::SpatialHash;
use crate::error::{Result, TailorError};

const BLOCK: usize = 512;

/// The 13 neighbour offsets `(dx, dy, dz)` whose last non-zero component is positive: half of
/// the 26 neighbours, one of each pair `±d`.
const FORWARD: [[i64; 3]; 13] = [
    [1, 0, 0],
    [-1, 1, 0],
    [0, 1, 0],
    [1, 1, 0],
    [-1, -1, 1],
    [0, -1, 1],
    [1, -1, 1],
    [-1, 0, 1],
    [0, 0, 1],
    [1, 0, 1],
    [-1, 1, 1],
    [0, 1, 1],
    [1, 1, 1],
];

/// Particle pairs that never collide, stored as a sorted adjacency list (CSR).
#[derive(Debug, Clone, Default)]
pub struct ExclusionSet {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl ExclusionSet {
    /// From explicit pairs (order and duplicates do not matter).
    pub fn from_pairs(num_particles: usize, pairs: impl IntoIterator<Item = [u32; 2]>) -> Result<Self> {
        let mut directed = Vec::new();
        for (k, [a, b]) in pairs.into_iter().enumerate() {
            for v in [a, b] {
                if v as usize >= num_particles {
                    return Err(TailorError::index(format!("excluded pair {k}"), v as i64, num_particles, "particles"));
                }
            }
            if a != b {
                directed.push((a, b));
                directed.push((b, a));
            }
        }
        directed.sort_unstable();
        directed.dedup();
        let mut offsets = vec![0u32; num_particles + 1];
        for &(a, _) in &directed {
            offsets[a as usize + 1] += 1;
        }
        for i in 0..num_particles {
            offsets[i + 1] += offsets[i];
        }
        Ok(Self { offsets, neighbours: directed.into_iter().map(|(_, b)| b).collect() })
    }

    /// Every two vertices of a triangle (hence every edge) and every seam pair.
    pub fn from_mesh(num_particles: usize, triangles: &[[u32; 3]], seams: &[[u32; 2]]) -> Result<Self> {
        let tri_pairs = triangles.iter().flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]]);
        Self::from_pairs(num_particles, tri_pairs.chain(seams.iter().copied()))
    }

    /// The set as compressed rows: `neighbours[offsets[a]..offsets[a + 1]]` are the particles
    /// `a` must not collide with, sorted (the GPU backend uploads this).
    pub fn csr(&self) -> (&[u32], &[u32]) {
        (&self.offsets, &self.neighbours)
    }

    /// Whether `a` and `b` must not collide.
    #[inline]
    pub fn contains(&self, a: u32, b: u32) -> bool {
        let a = a as usize;
        if a + 1 >= self.offsets.len() {
            return false;
        }
        self.neighbours[self.offsets[a] as usize..self.offsets[a + 1] as usize].binary_search(&b).is_ok()
    }
}

/// Finds overlapping particle pairs; keeps its hash and buffers between substeps.
#[derive(Debug, Default)]
pub struct SelfCollision {
    hash: SpatialHash,
    blocks: Vec<Vec<[u32; 2]>>,
    pairs: Vec<[u32; 2]>,
}

impl SelfCollision {
    pub fn new() -> Self {
        Self::default()
    }

    /// The pairs of the last search, `[i, j]` with `i < j`, sorted.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// The particle hash of the last search.
    pub fn hash(&self) -> &SpatialHash {
        &self.hash
    }

    /// Rebuilds the hash with cell side `cell_size` (≥ `2·radius`; the paper uses the mean
    /// edge length) and returns every non-excluded pair closer than `2·radius`.
    pub fn find_pairs<E>(
        &mut self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        radius: f32,
        cell_size: f32,
        exclude: E,
    ) -> Result<&[[u32; 2]]>
    where
        E: Fn(u32, u32) -> bool + Sync,
    {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(TailorError::setting("radius", radius, "the collision radius must be positive and finite"));
        }
        if cell_size.is_nan() || cell_size < 2.0 * radius {
            return Err(TailorError::setting(
                "cell_size",
                cell_size,
                format!("must be at least twice the collision radius ({radius}) or close pairs would be missed"),
            ));
        }
        self.hash.build_points(x, y, z, cell_size)?;
        let n = x.len();
        let num_blocks = n.div_ceil(BLOCK);
        if self.blocks.len() < num_blocks {
            self.blocks.resize_with(num_blocks, Vec::new);
        }
        let d2max = 4.0 * radius * radius;
        let hash = &self.hash;
        self.blocks[..num_blocks].par_iter_mut().enumerate().for_each(|(b, out)| {
            out.clear();
            for i in b * BLOCK..((b + 1) * BLOCK).min(n) {
                let p = [x[i], y[i], z[i]];
                let c = hash.cell_of(p);
                let mut test = |j: u32| {
                    let ju = j as usize;
                    let (ex, ey, ez) = (x[ju] - p[0], y[ju] - p[1], z[ju] - p[2]);
                    let pair = if ju < i { [j, i as u32] } else { [i as u32, j] };
                    if ex * ex + ey * ey + ez * ez < d2max && !exclude(pair[0], pair[1]) {
                        out.push(pair);
                    }
                };
                // Own cell: entries are sorted by index, so skip to those after `i`.
                for j in hash.query_cell(c).skip_while(|&j| j as usize <= i) {
                    test(j);
                }
                for d in FORWARD {
                    for j in hash.query_cell([c[0] + d[0], c[1] + d[1], c[2] + d[2]]) {
                        test(j);
                    }
                }
            }
        });
        self.pairs.clear();
        for out in &self.blocks[..num_blocks] {
            self.pairs.extend_from_slice(out);
        }
        self.pairs.par_sort_unstable();
        Ok(&self.pairs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    fn brute_force(x: &[f32], y: &[f32], z: &[f32], r: f32) -> Vec<[u32; 2]> {
        let mut out = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let d2 = (x[i] - x[j]).powi(2) + (y[i] - y[j]).powi(2) + (z[i] - z[j]).powi(2);
                if d2 < 4.0 * r * r {
                    out.push([i as u32, j as u32]);
                }
            }
        }
        out
    }

    #[test]
    fn hash_finds_exactly_the_brute_force_pairs() {
        let mut rng = Rng::new(42);
        let mut sc = SelfCollision::new();
        for round in 0..20 {
            let n = 200 + (rng.f32() * 2000.0) as usize;
            let extent = 0.2 + rng.f32() * 2.0;
            // Offset so cells of negative coordinates are exercised too.
            let offset = rng.vec3(5.0);
            let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
            for _ in 0..n {
                let p = offset + rng.vec3(extent);
                x.push(p.x);
                y.push(p.y);
                z.push(p.z);
            }
            let r = 0.005 + rng.f32() * 0.05;
            let l = 2.0 * r * (1.0 + 2.0 * rng.f32() * (round % 2) as f32);
            let got = sc.find_pairs(&x, &y, &z, r, l, |_, _| false).unwrap().to_vec();
            let mut want = brute_force(&x, &y, &z, r);
            want.sort_unstable();
            assert_eq!(got, want, "round {round}: n {n}, r {r}, l {l}");
        }
    }

    #[test]
    fn excluded_pairs_never_repel_and_bad_settings_are_refused() {
        // A strip of 4 particles 1 cm apart: triangles (0,1,2), (1,3,2), a seam 0-3.
        let x = [0.0, 0.01, 0.0, 0.01];
        let y = [0.0, 0.0, 0.01, 0.01];
        let z = [0.0; 4];
        let ex = ExclusionSet::from_mesh(4, &[[0, 1, 2], [1, 3, 2]], &[]).unwrap();
        let mut sc = SelfCollision::new();
        let pairs = sc.find_pairs(&x, &y, &z, 0.01, 0.02, |a, b| ex.contains(a, b)).unwrap();
        assert_eq!(pairs, &[[0, 3]]);
        let ex = ExclusionSet::from_mesh(4, &[[0, 1, 2], [1, 3, 2]], &[[3, 0]]).unwrap();
        assert!(sc.find_pairs(&x, &y, &z, 0.01, 0.02, |a, b| ex.contains(a, b)).unwrap().is_empty());
        assert!(ex.contains(2, 1) && ex.contains(0, 3) && !ex.contains(0, 0));
        let e = sc.find_pairs(&x, &y, &z, 0.01, 0.015, |_, _| false).unwrap_err();
        assert!(matches!(e, TailorError::InvalidSetting { name: "cell_size", .. }), "{e}");
        let e = sc.find_pairs(&x, &y[..3], &z, 0.01, 0.02, |_, _| false).unwrap_err();
        assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
        let e = ExclusionSet::from_pairs(4, [[0, 4]]).unwrap_err();
        assert!(matches!(e, TailorError::IndexOutOfRange { index: 4, .. }), "{e}");
    }
}
