//! The pairs a self-collision candidate list lacks once a few particles have moved too far
//! (issue 22: candidate pairs found once, projected every iteration).
//!
//! The list ([`SelfCollide::pass`](super::self_collide::SelfCollide)) holds every pair closer
//! than `2r + m` at the positions `x_ref` of its search. A pair now closer than `2r` that it
//! lacks has moved more than `m` closer, so one of its particles moved at least `m/2` since the
//! search: a **mover**. On a walking body, a pass finds 0-50 movers among the layered outfit's
//! 15,139 particles (counted on its walk), while the whole search (a hash of every particle and
//! every pair) was redone as soon as there was one. Now the movers alone are searched:
//!
//! * a mover `i` and a particle `j` that stayed within `m/2` of its search position: that
//!   position is within `2r + m/2` of `i`'s current one, less than the search's cell (at least
//!   `2r + m`), so `j` is in one of the 27 cells round `i` in the search's hash;
//! * two movers: every pair of them is tested.
//!
//! Each pair found closer than `2r` (the correction's own test), not excluded, and not in the
//! list (the search's own test at `x_ref` fails) is a missing pair; the pass corrects the list
//! and these in one sorted order, so its corrections are exactly those of a fresh search
//! (`tests/collision_self.rs`). Past [`max_movers`] the whole search runs again.

use crate::collision::hash::SpatialHash;
use crate::solver::model::soa::Vec3Soa;

/// Most movers the partial search takes on among `n` particles (their pairs are tested all
/// against all, so a small cloth whose every particle moves is searched whole); more, and the
/// whole search runs again.
pub(crate) fn max_movers(n: usize) -> usize {
    (n / 8).min(512)
}

/// What the missing pairs are looked for in.
pub(crate) struct Movers<'a> {
    /// Current positions.
    pub x: &'a Vec3Soa,
    /// Positions at the search, and the search's hash of them.
    pub x_ref: &'a Vec3Soa,
    pub hash: &'a SpatialHash,
    /// The particles that moved at least `m/2` since the search, ascending.
    pub movers: &'a [u32],
    /// Twice the sphere radius: the correction's reach.
    pub two_r: f32,
    /// The search's squared pair distance, `(2·(r + m/2))²`, as `SelfCollision::find_pairs`
    /// computes it.
    pub listed_d2: f32,
}

impl Movers<'_> {
    /// Whether the search at `x_ref` listed the (not excluded) pair `a`, `b`: the finder's
    /// own test, with the same arithmetic.
    #[inline]
    fn listed(&self, a: usize, b: usize) -> bool {
        let r = self.x_ref;
        let (ex, ey, ez) = (r.x[b] - r.x[a], r.y[b] - r.y[a], r.z[b] - r.z[a]);
        ex * ex + ey * ey + ez * ez < self.listed_d2
    }

    /// Pair `a`, `b` if it is missing from the list and within reach of the correction.
    #[inline]
    fn missing(&self, a: u32, b: u32, exclude: &impl Fn(u32, u32) -> bool) -> Option<[u32; 2]> {
        let pair = if a < b { [a, b] } else { [b, a] };
        let (i, j) = (pair[0] as usize, pair[1] as usize);
        let near = self.x.get(i).distance_squared(self.x.get(j)) < self.two_r * self.two_r;
        (near && !self.listed(i, j) && !exclude(pair[0], pair[1])).then_some(pair)
    }

    /// The missing pairs (`[a, b]` with `a < b`), sorted, each once.
    pub fn missing_pairs(&self, exclude: impl Fn(u32, u32) -> bool) -> Vec<[u32; 2]> {
        let mut out = Vec::new();
        let is_mover = |j: u32| self.movers.binary_search(&j).is_ok();
        for (k, &i) in self.movers.iter().enumerate() {
            let p = self.x.get(i as usize);
            let c = self.hash.cell_of(p.into());
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        for j in self.hash.query_cell([c[0] + dx, c[1] + dy, c[2] + dz]) {
                            if j != i && !is_mover(j) {
                                out.extend(self.missing(i, j, &exclude));
                            }
                        }
                    }
                }
            }
            for &j in &self.movers[k + 1..] {
                out.extend(self.missing(i, j, &exclude));
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Calls `f` on each pair of two sorted lists with no pair in both, in their merged order.
pub(crate) fn merged(a: &[[u32; 2]], b: &[[u32; 2]], mut f: impl FnMut([u32; 2])) {
    let mut rest = b.iter().copied().peekable();
    for &pair in a {
        while let Some(e) = rest.next_if(|e| *e < pair) {
            f(e);
        }
        f(pair);
    }
    rest.for_each(f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_visits_both_lists_in_order() {
        let a = [[0, 3], [1, 2], [4, 9]];
        let b = [[0, 1], [1, 5], [7, 8], [8, 9]];
        let mut seen = Vec::new();
        merged(&a, &b, |p| seen.push(p));
        let mut want: Vec<[u32; 2]> = a.iter().chain(&b).copied().collect();
        want.sort();
        assert_eq!(seen, want);
    }
}
