//! Randomized graph colouring of the particle graph (Vivace, Fratarcangeli et al. 2016).
//!
//! Particles that share a constraint (a non-zero off-diagonal of the global matrix) must get
//! different colours, so that all particles of one colour can be updated by Gauss-Seidel in
//! parallel. Each particle starts with a palette of `⌈deg/shrink⌉` colours; in each round every
//! uncoloured particle tries a random colour of its palette and keeps it when no uncoloured
//! neighbour tried the same colour with a smaller index (the index breaks ties so every round
//! makes progress); kept colours leave the neighbours' palettes, and a particle whose palette
//! runs dry gets a fresh colour ("feed the hungry"). Shrinking palettes keeps the colour count
//! near the graph's maximum degree over `shrink` rather than the degree itself.
//!
//! The random choices come from a hash of `(seed, particle, round)`, so the colouring is the
//! same for a seed whatever the thread count. It is recomputed only when topology changes.

use rayon::prelude::*;

/// A colouring: a colour per node and the nodes of each colour.
#[derive(Debug, Clone, Default)]
pub struct Colouring {
    pub colour: Vec<u32>,
    pub groups: Vec<Vec<u32>>,
    pub rounds: u32,
}

impl Colouring {
    pub fn count(&self) -> usize {
        self.groups.len()
    }

    /// Heap bytes of the colours and the groups (the outer vector and each group).
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.colour) + vec_bytes(&self.groups) + self.groups.iter().map(vec_bytes).sum::<usize>()
    }
}

/// Colours the graph given by symmetric adjacency rows (`offsets`, `adj`).
pub fn colour_graph(offsets: &[u32], adj: &[u32], seed: u64) -> Colouring {
    const SHRINK: usize = 2;
    let n = offsets.len() - 1;
    let nbrs = |i: usize| &adj[offsets[i] as usize..offsets[i + 1] as usize];
    let mut palette: Vec<Vec<u32>> =
        (0..n).map(|i| (0..(nbrs(i).len().div_ceil(SHRINK)).max(1) as u32).collect()).collect();
    let mut next_fresh: Vec<u32> = palette.iter().map(|p| p.len() as u32).collect();
    let mut colour = vec![u32::MAX; n];
    let mut tentative = vec![u32::MAX; n];
    let mut uncoloured: Vec<u32> = (0..n as u32).collect();
    let mut rounds = 0;
    while !uncoloured.is_empty() {
        rounds += 1;
        let pick: Vec<u32> = uncoloured
            .par_iter()
            .map(|&i| {
                let p = &palette[i as usize];
                p[(hash3(seed, i as u64, rounds as u64) % p.len() as u64) as usize]
            })
            .collect();
        for (&i, &c) in uncoloured.iter().zip(&pick) {
            tentative[i as usize] = c;
        }
        let keep: Vec<bool> = uncoloured
            .par_iter()
            .map(|&i| {
                let c = tentative[i as usize];
                nbrs(i as usize).iter().all(|&j| {
                    let j = j as usize;
                    colour[j] != c && !(colour[j] == u32::MAX && tentative[j] == c && j < i as usize)
                })
            })
            .collect();
        for (&i, &k) in uncoloured.iter().zip(&keep) {
            if k {
                colour[i as usize] = tentative[i as usize];
            }
        }
        for &i in &uncoloured {
            tentative[i as usize] = u32::MAX;
        }
        uncoloured = uncoloured.iter().zip(&keep).filter(|(_, &k)| !k).map(|(&i, _)| i).collect();
        // Remove the neighbours' colours from each remaining palette; refill an empty one.
        let updates: Vec<Vec<u32>> = uncoloured
            .par_iter()
            .map(|&i| {
                let mut p = palette[i as usize].clone();
                p.retain(|&c| nbrs(i as usize).iter().all(|&j| colour[j as usize] != c));
                p
            })
            .collect();
        for (&i, mut p) in uncoloured.iter().zip(updates) {
            if p.is_empty() {
                p.push(next_fresh[i as usize]);
                next_fresh[i as usize] += 1;
            }
            palette[i as usize] = p;
        }
    }
    // Compact colour ids (some palette colours may be unused).
    let max = colour.iter().copied().max().unwrap_or(0) as usize;
    let mut remap = vec![u32::MAX; max + 1];
    let mut groups: Vec<Vec<u32>> = Vec::new();
    for i in 0..n {
        let c = colour[i] as usize;
        if remap[c] == u32::MAX {
            remap[c] = groups.len() as u32;
            groups.push(Vec::new());
        }
        colour[i] = remap[c];
        groups[colour[i] as usize].push(i as u32);
    }
    Colouring { colour, groups, rounds }
}

/// SplitMix64-style mixing of three words.
fn hash3(a: u64, b: u64, c: u64) -> u64 {
    let mut z = a ^ b.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ c.wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_graph(w: usize, h: usize) -> (Vec<u32>, Vec<u32>) {
        // 8-neighbourhood plus distance-2 along axes: like a triangle mesh with bending stencils.
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); w * h];
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                for (dx, dy) in [(1, 0), (0, 1), (1, 1), (-1, 1), (2, 0), (0, 2)] {
                    let (u, v) = (x + dx, y + dy);
                    if u >= 0 && v >= 0 && (u as usize) < w && (v as usize) < h {
                        let (a, b) = ((y as usize) * w + x as usize, (v as usize) * w + u as usize);
                        rows[a].push(b as u32);
                        rows[b].push(a as u32);
                    }
                }
            }
        }
        let mut offsets = vec![0u32];
        let mut adj = Vec::new();
        for r in rows {
            adj.extend(r);
            offsets.push(adj.len() as u32);
        }
        (offsets, adj)
    }

    #[test]
    fn colouring_is_valid_compact_and_deterministic() {
        let (off, adj) = grid_graph(60, 40);
        let c = colour_graph(&off, &adj, 7);
        for i in 0..off.len() - 1 {
            for &j in &adj[off[i] as usize..off[i + 1] as usize] {
                assert_ne!(c.colour[i], c.colour[j as usize], "neighbours {i} and {j} share a colour");
            }
        }
        let max_deg = (0..off.len() - 1).map(|i| off[i + 1] - off[i]).max().unwrap() as usize;
        assert!(c.count() <= max_deg + 1, "{} colours for max degree {max_deg}", c.count());
        assert_eq!(c.groups.iter().map(Vec::len).sum::<usize>(), off.len() - 1);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let c1 = pool.install(|| colour_graph(&off, &adj, 7));
        assert_eq!(c.colour, c1.colour, "colouring depends on the thread count");
        let c2 = colour_graph(&off, &adj, 8);
        assert_ne!(c.colour, c2.colour, "the seed should randomize the colouring");
    }
}
