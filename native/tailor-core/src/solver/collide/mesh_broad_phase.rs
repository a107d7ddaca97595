//! The iterations' broad phase against a mesh collider: within a substep the collider does not
//! move, so a particle's contact can change between iterations only as far as the particle
//! moves. Each full test (the rule of `nearest_feature_contact` over the particle's cell) leaves
//! a radius within which the answer is known, or known from a few candidates:
//!
//! * **free**, every candidate of the particle's cell in front of its offset plane: each side
//!   `(p − a)·n` changes by at most the distance moved (unit normals), so within the least
//!   `side − thickness`, and within the cell (whose faces bound its candidates), nothing
//!   touches: the test is skipped;
//! * **a shortlist**: the rule's answer depends only on the nearest candidate `T` (its depth)
//!   and on the candidates whose closest point shares `T`'s (an edge or corner that frees the
//!   particle), all within `d₁ + SHARED_FEATURE` of `p`. Distances change by at most the
//!   distance moved, so within `R` of the tested point (and within the cell) every candidate
//!   that can matter was within `d₁ + 2R + SHARED_FEATURE` there: the up to [`SHORTLIST`]
//!   nearest candidates, with `R` half the gap from the nearest to the first one left out (less
//!   `SHARED_FEATURE`). Each iteration inside `R` runs the rule over the shortlist alone
//!   ([`MeshCollider::test_shortlist`]): a few closest points instead of the cell's candidates,
//!   and no read of the hash. Where the answer over the shortlist could differ from the cell's
//!   by rounding (two nearest candidates within a rounding margin of each other, whose order in
//!   the cell decides; a side that rounds onto the offset plane) the full test runs.
//!
//! Each radius is shortened by a margin for rounding, so the answers are bit for bit those of
//! testing every candidate in every iteration (`tests/collision_mesh.rs`).
//!
//! The shortlist replaced a single nearest candidate kept within half the gap to the second
//! nearest: on a garment resting on a smooth body that gap is tiny wherever the closest point is
//! near an edge, and 77 % of the contact tests of the T-shirt sample's walk ended there.

use glam::Vec3;

use super::levels::levels_collide;
use super::mesh_collider::MeshCollider;
use crate::collision::geometry::{
    closest_point_on_triangle, nearest_feature_contact_or_clearance, on_shared_feature, Contact, SHARED_FEATURE,
};
use crate::collision::hash::Cell;

/// Candidates of a cell gathered on the stack for one test (more: read from the table).
const GATHERED: usize = 64;

/// Candidates whose corners and normals a test reads once and keeps on the stack (more: read
/// again in each pass).
const CACHED: usize = 16;

/// Candidates a particle's shortlist holds at most: more gives larger radii and dearer tests.
pub(crate) const SHORTLIST: usize = 4;

/// What a particle's last test in this substep leaves for the next iterations: within `radius`
/// of `at`, it is free (`len == 0`) or the rule over the `len` kept triangles `near` of the
/// (single) mesh collider gives its answer. `radius ≤ 0`: test it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Reuse {
    pub at: [f32; 3],
    pub radius: f32,
    pub near: [u32; SHORTLIST],
    pub len: u32,
}

/// A shortlist as the full test leaves it: kept-triangle indices, `len` of them (0: free).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Shortlist {
    pub near: [u32; SHORTLIST],
    pub len: u32,
}

impl Shortlist {
    pub const FREE: Self = Self { near: [0; SHORTLIST], len: 0 };

    pub fn is_free(&self) -> bool {
        self.len == 0
    }
}

/// What the broad phase takes off a radius for rounding, metres: the side, distance and cell
/// computations at `p` are exact to a few f32 ulps of its coordinates; 1 µm besides.
#[inline]
pub(crate) fn rounding_margin(p: Vec3) -> f32 {
    1e-6 + 8.0 * f32::EPSILON * p.abs().max_element()
}

impl MeshCollider {
    /// The particle-vs-cell test at `p` (the rule of `nearest_feature_contact` over the
    /// level-compatible candidates of `p`'s cell), and, with `reuse`, the radius within which
    /// its answer is known (free) or given by the shortlist, before the rounding margin.
    pub(crate) fn test_for_reuse(
        &self,
        p: Vec3,
        level: i32,
        thickness: f32,
        reuse: bool,
    ) -> (Option<Contact>, f32, Shortlist) {
        if self.kept.is_empty() {
            return (None, f32::INFINITY, Shortlist::FREE);
        }
        let cell = self.hash.cell_of(p.into());
        // The cell's candidates, read from the table once (the rule reads them up to three
        // times, and the shortlist once more: each read a binary search in the bucket and
        // the other substeps' entries skipped); a cell holding more than `GATHERED` reads the
        // table each time.
        let mut gathered = [0u32; GATHERED];
        let mut count = 0;
        for k in self.hash.query_cell_for(cell, self.bit) {
            if levels_collide(level, self.tri_level[self.kept[k as usize] as usize]) {
                if count < GATHERED {
                    gathered[count] = k;
                }
                count += 1;
            }
        }
        let gathered = &gathered[..count.min(GATHERED)];
        if count <= CACHED {
            // Few candidates (most cells): their corners and normals read once, for every pass
            // of the rule and the shortlist (each read is three scattered vertex loads).
            let mut geo = [(0u32, 0u32, [Vec3::ZERO; 3], Vec3::ZERO); CACHED];
            let mut m = 0;
            for &k in gathered {
                let n = self.normals[k as usize];
                if n != Vec3::ZERO {
                    geo[m] = (k, self.kept[k as usize], self.corners(k), n);
                    m += 1;
                }
            }
            let geo = &geo[..m];
            return self.decide(p, cell, thickness, reuse, || geo.iter().copied());
        }
        let overflow = count > GATHERED;
        let cands = || {
            let table = overflow.then(|| {
                self.hash
                    .query_cell_for(cell, self.bit)
                    .filter(move |&k| levels_collide(level, self.tri_level[self.kept[k as usize] as usize]))
            });
            gathered.iter().copied().take(if overflow { 0 } else { count }).chain(table.into_iter().flatten())
        };
        self.decide(p, cell, thickness, reuse, || {
            cands().filter_map(|k| {
                let n = self.normals[k as usize];
                (n != Vec3::ZERO).then(|| (k, self.kept[k as usize], self.corners(k), n))
            })
        })
    }

    /// The rule over `cands` (`(kept index, triangle, corners, unit normal)`, degenerate ones
    /// left out; called up to four times, the same sequence each time) at `p` in `cell`, and
    /// with `reuse` the radius and shortlist (see [`test_for_reuse`](Self::test_for_reuse)).
    #[inline]
    fn decide<F, I>(
        &self,
        p: Vec3,
        cell: Cell,
        thickness: f32,
        reuse: bool,
        cands: F,
    ) -> (Option<Contact>, f32, Shortlist)
    where
        F: Fn() -> I,
        I: Iterator<Item = (u32, u32, [Vec3; 3], Vec3)>,
    {
        let answer = nearest_feature_contact_or_clearance(p, thickness, || cands().map(|(_, t, c, n)| (t, c, n)));
        if !reuse {
            return (answer.ok().flatten(), 0.0, Shortlist::FREE);
        }
        let l = self.cell;
        let lo = Vec3::new(cell[0] as f32, cell[1] as f32, cell[2] as f32) * l;
        let to_faces = (p - lo).min(lo + l - p).min_element();
        let hit = match answer {
            Err(clearance) => return (None, clearance.min(to_faces), Shortlist::FREE),
            Ok(hit) => hit,
        };
        // The SHORTLIST + 1 nearest candidates, ascending. A candidate is never nearer than its
        // plane: one whose plane is farther than the last of them (by more than rounding)
        // cannot enter, and its closest point is not computed.
        let margin = rounding_margin(p);
        let mut best = [(f32::INFINITY, 0u32); SHORTLIST + 1];
        for (k, _, [a, b, c], n) in cands() {
            if (p - a).dot(n).abs() > best[SHORTLIST].0 + margin {
                continue;
            }
            let d = closest_point_on_triangle(p, a, b, c).0.distance(p);
            if d < best[SHORTLIST].0 {
                let mut j = SHORTLIST;
                while j > 0 && best[j - 1].0 > d {
                    best[j] = best[j - 1];
                    j -= 1;
                }
                best[j] = (d, k);
            }
        }
        let d1 = best[0].0;
        if !d1.is_finite() {
            return (hit, 0.0, Shortlist::FREE);
        }
        // Every candidate left out is at least `best[SHORTLIST]` away: within R of `p`, none
        // comes nearer than d₁ + R + SHARED_FEATURE while the nearest is within d₁ + R.
        let radius = (0.5 * (best[SHORTLIST].0 - d1 - SHARED_FEATURE)).min(to_faces);
        // Of the shortlist, only those that can come within reach of the nearest inside R.
        let reach = d1 + 2.0 * radius.max(0.0) + SHARED_FEATURE + margin;
        let mut list = Shortlist::FREE;
        for &(d, k) in &best[..SHORTLIST] {
            if d <= reach {
                list.near[list.len as usize] = k;
                list.len += 1;
            }
        }
        (hit, radius, list)
    }

    /// The corners of kept triangle `k` at this substep's positions.
    #[inline]
    fn corners(&self, k: u32) -> [Vec3; 3] {
        self.tris[self.kept[k as usize] as usize].map(|v| Vec3::from(self.cur[v as usize]))
    }

    /// The test at `p` when every candidate of its cell that can decide it is in `list` (within
    /// the radius [`test_for_reuse`](Self::test_for_reuse) gave): the rule over the list. With
    /// a nearest unique by more than rounding, the rule over the cell finds the same nearest
    /// whatever the order it reads the candidates in, so it gives the same depth and contact;
    /// the candidates sharing the nearest's closest point are all in the list. `None` where the
    /// answers could differ by rounding (two nearest within the margin, or every side in front
    /// of the offset plane by less than the margin, where the nearest's depth can round
    /// positive): test it in full.
    #[inline]
    pub(crate) fn test_shortlist(&self, p: Vec3, list: &[u32], thickness: f32) -> Option<Option<Contact>> {
        let margin = rounding_margin(p);
        let mut least_side = f32::INFINITY;
        let (mut d1, mut d2, mut k1, mut near) = (f32::INFINITY, f32::INFINITY, 0u32, (Vec3::ZERO, [0.0; 3]));
        for &k in list {
            let n = self.normals[k as usize];
            let [a, b, c] = self.corners(k);
            least_side = least_side.min((p - a).dot(n));
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            let d = q.distance(p);
            if d < d1 {
                (d2, d1, k1, near) = (d1, d, k, (q, bary));
            } else if d < d2 {
                d2 = d;
            }
        }
        if !(least_side < thickness) {
            return (least_side >= thickness + margin).then_some(None);
        }
        if !(d2 - d1 > margin) {
            return None;
        }
        let (closest, bary) = near;
        let normal = self.normals[k1 as usize];
        let depth = thickness - (p - closest).dot(normal);
        if depth <= 0.0 {
            return Some(None);
        }
        let tri = self.corners(k1);
        if on_shared_feature(tri, bary) {
            // As the rule's third pass: a candidate in front of its offset plane sharing the
            // nearest closest point frees the particle.
            for &k in list {
                let n = self.normals[k as usize];
                let [a, b, c] = self.corners(k);
                let side = (p - a).dot(n);
                if side < thickness || side > d1 + SHARED_FEATURE {
                    continue;
                }
                if closest_point_on_triangle(p, a, b, c).0.distance_squared(closest) <= SHARED_FEATURE * SHARED_FEATURE
                {
                    return Some(None);
                }
            }
        }
        let triangle = self.kept[k1 as usize];
        Some(Some(Contact { triangle, closest, bary, normal, target: p + normal * depth, depth }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::collide::mesh_collider::MeshColliderOptions;
    use crate::test_util::{icosphere, Rng};

    /// Wherever the broad phase answers without the full test (free within the radius, or
    /// the rule over the shortlist), the full test gives the same answer, bit for bit: points
    /// in the thickness band round a bumpy sphere (concave and convex cells), each moved to
    /// second points inside the radius its first test gave (up to its edge, where a candidate
    /// left out can come nearest), many of them right at a shortlisted triangle's offset plane
    /// where rounding decides.
    #[test]
    fn answers_inside_the_radius_are_the_full_tests() {
        let (mut v, t) = icosphere(3, 0.3);
        for (k, p) in v.iter_mut().enumerate() {
            let s = 1.0 + 0.08 * ((k as f32 * 1.7).sin());
            *p = (Vec3::from(*p) * s + Vec3::new(0.3, -1.2, 1.1)).into();
        }
        let mut m = MeshCollider::new(&v, &t, MeshColliderOptions::default()).unwrap();
        let all = (Vec3::splat(-10.0), Vec3::splat(10.0));
        m.prepare(&[1.0], all, all, true, false, None);
        let th = 0.003;
        let mut rng = Rng::new(7);
        let (mut free, mut listed, mut fallbacks, mut longer) = (0, 0, 0, 0);
        for _ in 0..200_000 {
            let base = Vec3::from(v[(rng.next_u64() % v.len() as u64) as usize]);
            let c = Vec3::new(0.3, -1.2, 1.1);
            let out = (base - c).normalize();
            // In the thickness band, a quarter of them within a micrometre of the offset plane.
            let h = if rng.f32() < 0.25 { th + (rng.f32() - 0.5) * 2e-6 } else { (rng.f32() - 0.3) * 3.0 * th };
            let p = base + out * h + rng.vec3(0.01);
            let (_, radius, list) = m.test_for_reuse(p, 0, th, true);
            let radius = radius - rounding_margin(p);
            if !(radius > 0.0) {
                continue;
            }
            let dir = rng.vec3(1.0).normalize_or_zero();
            let q0 = p + dir * radius * rng.f32().sqrt() * 0.9999;
            if list.is_free() {
                free += 1;
                let full = m.contact(q0, 0, th);
                assert!(full.is_none(), "skipped as free at {q0:?}, but the full test touches: {full:?}");
                continue;
            }
            longer += (list.len > 1) as usize;
            let list = &list.near[..list.len as usize];
            // Also onto each shortlisted triangle's offset plane and a few ulps either side of
            // it, where the side and the closest point's depth round differently.
            let planes = list.iter().flat_map(|&k| {
                let (a, n) = (m.corners(k)[0], m.normals[k as usize]);
                let on_plane = q0 + n * (th - (q0 - a).dot(n));
                (-8..=8).map(move |j| on_plane + n * (j as f32 * 3e-8))
            });
            let tries: Vec<Vec3> = std::iter::once(q0).chain(planes).collect();
            for q in tries.into_iter().filter(|q| q.distance_squared(p) < radius * radius) {
                let full = m.contact(q, 0, th);
                match m.test_shortlist(q, list, th) {
                    Some(fast) => {
                        listed += 1;
                        let same = match (&fast, &full) {
                            (None, None) => true,
                            (Some(a), Some(b)) => a.triangle == b.triangle && a.target == b.target && a.bary == b.bary,
                            _ => false,
                        };
                        assert!(same, "shortlist {list:?} at {q:?}: {fast:?}, the full test: {full:?}");
                    }
                    None => fallbacks += 1,
                }
            }
        }
        println!("free {free}, shortlist {listed} (longer than one {longer}), fell back to the full test {fallbacks}");
        assert!(
            free > 1000 && listed > 1000 && longer > 1000,
            "too few reuses exercised: free {free}, shortlist {listed}, longer than one {longer}"
        );
    }

    /// The candidates gathered on the stack and, in a cell holding more than `GATHERED` of
    /// them, read from the table: both give `particle_vs_cell`'s answer over the cell's
    /// triangles (a fine sphere in cells of 0.2 m: up to hundreds of triangles a cell).
    #[test]
    fn crowded_and_sparse_cells_give_the_reference_contact() {
        let (v, t) = icosphere(4, 0.3);
        let th = 0.004;
        for cell in [None, Some(0.2)] {
            let opts = MeshColliderOptions { cell_size: cell, ..MeshColliderOptions::default() };
            let mut m = MeshCollider::new(&v, &t, opts).unwrap();
            let all = (Vec3::splat(-10.0), Vec3::splat(10.0));
            m.prepare(&[1.0], all, all, true, false, None);
            let mut rng = Rng::new(5);
            let (mut crowded, mut hits) = (0, 0);
            for _ in 0..3000 {
                let base = Vec3::from(v[(rng.next_u64() % v.len() as u64) as usize]);
                let p = base * (1.0 + (rng.f32() - 0.6) * 0.03) + rng.vec3(0.002);
                let cands: Vec<u32> = m.hash.query_cell(m.hash.cell_of(p.into())).map(|k| m.kept[k as usize]).collect();
                crowded += (cands.len() > GATHERED) as usize;
                let want = crate::collision::geometry::particle_vs_cell(p, cands, &m.cur, &m.tris, th);
                let got = m.contact(p, 0, th);
                hits += got.is_some() as usize;
                assert_eq!(got.map(|c| (c.triangle, c.target)), want.map(|c| (c.triangle, c.target)), "{p:?}");
            }
            assert!(hits > 300, "too few contacts tested: {hits}");
            if cell.is_some() {
                assert!(crowded > 1000, "the crowded path was not taken: {crowded}");
            }
        }
    }
}
