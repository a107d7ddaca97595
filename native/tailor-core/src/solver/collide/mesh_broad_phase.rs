//! The iterations' broad phase against a mesh collider: within a substep the collider does not
//! move, so a particle's contact can change between iterations only as far as the particle
//! moves. Each test leaves a radius within which the answer is known:
//!
//! * **free**, every candidate of the particle's cell in front of its offset plane: each side
//!   `(p − a)·n` changes by at most the distance moved (unit normals), so within the least
//!   `side − thickness`, and within the cell (whose faces bound its candidates), nothing
//!   touches: the test is skipped;
//! * **a unique nearest candidate** `T` (the rule of `nearest_feature_contact` decides by the
//!   nearest candidate): distances change by at most the distance moved, so within half the
//!   gap to the second nearest `T` stays the nearest, and within the closest point's distance to
//!   `T`'s edges (less twice `SHARED_FEATURE`) no shared edge can free the particle: the test
//!   is `T` alone (one closest point instead of the cell's candidates).
//!
//! Each radius is shortened by a margin for rounding, so the answers are bit for bit those of
//! testing every candidate in every iteration (`tests/collision_mesh.rs`).

use glam::Vec3;

use super::levels::levels_collide;
use super::mesh_collider::MeshCollider;
use crate::collision::geometry::{
    closest_point_on_triangle, distance_to_edges, nearest_feature_contact_or_clearance, on_shared_feature, Contact,
    SHARED_FEATURE,
};

/// Candidates of a cell gathered on the stack for one test (more: read from the table).
const GATHERED: usize = 64;

/// `nearest` of a particle whose last test found it free.
pub(crate) const FREE: u32 = u32::MAX;

/// What a particle's last test in this substep leaves for the next iterations: within `radius`
/// of `at`, it is free (`nearest == FREE`) or its nearest candidate is kept triangle `nearest`
/// of the (single) mesh collider. `radius ≤ 0`: test it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Reuse {
    pub at: [f32; 3],
    pub radius: f32,
    pub nearest: u32,
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
    /// its answer is known and the nearest candidate it rests on (`FREE`: none needed), before
    /// the rounding margin.
    pub(crate) fn test_for_reuse(
        &self,
        p: Vec3,
        level: i32,
        thickness: f32,
        reuse: bool,
    ) -> (Option<Contact>, f32, u32) {
        if self.kept.is_empty() {
            return (None, f32::INFINITY, FREE);
        }
        let cell = self.hash.cell_of(p.into());
        // The cell's candidates, read from the table once (the rule reads them up to three
        // times, and the reuse radius once more: each read a binary search in the bucket and
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
        let overflow = count > GATHERED;
        let cands = || {
            let table = overflow.then(|| {
                self.hash
                    .query_cell_for(cell, self.bit)
                    .filter(move |&k| levels_collide(level, self.tri_level[self.kept[k as usize] as usize]))
            });
            gathered.iter().copied().take(if overflow { 0 } else { count }).chain(table.into_iter().flatten())
        };
        let corners = |k: u32| self.tris[self.kept[k as usize] as usize].map(|v| Vec3::from(self.cur[v as usize]));
        let answer = nearest_feature_contact_or_clearance(p, thickness, || {
            cands().filter_map(|k| {
                let n = self.normals[k as usize];
                (n != Vec3::ZERO).then(|| (self.kept[k as usize], corners(k), n))
            })
        });
        if !reuse {
            return (answer.ok().flatten(), 0.0, FREE);
        }
        let l = self.cell;
        let lo = Vec3::new(cell[0] as f32, cell[1] as f32, cell[2] as f32) * l;
        let to_faces = (p - lo).min(lo + l - p).min_element();
        let hit = match answer {
            Err(clearance) => return (None, clearance.min(to_faces), FREE),
            Ok(hit) => hit,
        };
        // The nearest candidate and the second nearest distance, over the same candidates.
        let (mut d1, mut k1, mut d2, mut near) = (f32::INFINITY, FREE, f32::INFINITY, (Vec3::ZERO, [0.0; 3]));
        for k in cands() {
            if self.normals[k as usize] == Vec3::ZERO {
                continue;
            }
            let [a, b, c] = corners(k);
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            let d = q.distance(p);
            if d < d1 {
                (d2, d1, k1, near) = (d1, d, k, (q, bary));
            } else if d < d2 {
                d2 = d;
            }
        }
        if k1 == FREE {
            return (hit, 0.0, FREE);
        }
        // The answer must be the nearest's own: its contact, or none because it is in front
        // (not a shared edge's freeing, which depends on the other candidates).
        let n1 = self.normals[k1 as usize];
        let own = match &hit {
            Some(c) => c.triangle == self.kept[k1 as usize],
            None => thickness - (p - near.0).dot(n1) <= 0.0,
        };
        if !own {
            return (hit, 0.0, FREE);
        }
        let radius = (0.5 * (d2 - d1)).min(to_faces).min(distance_to_edges(corners(k1), near.1) - 2.0 * SHARED_FEATURE);
        (hit, radius, k1)
    }

    /// The test at `p` when kept triangle `k` is known to be its nearest candidate (within the
    /// radius [`test_for_reuse`](Self::test_for_reuse) gave): `T`'s closest point decides, as
    /// in the rule. `None` where the rule's answer also depends on the other candidates (a
    /// depth that rounds positive while `T`'s side rounds onto its offset plane, or a closest
    /// point on a shared edge): test it in full.
    #[inline]
    pub(crate) fn test_nearest(&self, p: Vec3, k: u32, thickness: f32) -> Option<Option<Contact>> {
        let t = self.kept[k as usize];
        let tri = self.tris[t as usize].map(|v| Vec3::from(self.cur[v as usize]));
        let normal = self.normals[k as usize];
        let (closest, bary) = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
        let depth = thickness - (p - closest).dot(normal);
        if depth <= 0.0 {
            return Some(None);
        }
        // The rule looks for the nearest only when some candidate is behind its offset plane,
        // by the side to its first corner; the closest point's depth can round positive where
        // that side rounds to the plane. Whether another candidate is behind then decides:
        // test in full. So does a closest point on a shared edge.
        if !((p - tri[0]).dot(normal) < thickness) || on_shared_feature(tri, bary) {
            return None;
        }
        Some(Some(Contact { triangle: t, closest, bary, normal, target: p + normal * depth, depth }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::collide::mesh_collider::MeshColliderOptions;
    use crate::test_util::{icosphere, Rng};

    /// Wherever the broad phase answers without the full test (free within the radius, or
    /// the nearest candidate alone), the full test gives the same answer, bit for bit: points
    /// in the thickness band round a bumpy sphere (concave and convex cells), each moved to a
    /// second point inside the radius its first test gave, many of them right at the offset
    /// plane where rounding decides.
    #[test]
    fn answers_inside_the_radius_are_the_full_tests() {
        let (mut v, t) = icosphere(3, 0.3);
        for (k, p) in v.iter_mut().enumerate() {
            let s = 1.0 + 0.08 * ((k as f32 * 1.7).sin());
            *p = (Vec3::from(*p) * s + Vec3::new(0.3, -1.2, 1.1)).into();
        }
        let mut m = MeshCollider::new(&v, &t, MeshColliderOptions::default()).unwrap();
        let all = (Vec3::splat(-10.0), Vec3::splat(10.0));
        m.prepare(&[1.0], all, all, true, false);
        let th = 0.003;
        let mut rng = Rng::new(7);
        let (mut free, mut near, mut fallbacks) = (0, 0, 0);
        for _ in 0..200_000 {
            let base = Vec3::from(v[(rng.next_u64() % v.len() as u64) as usize]);
            let c = Vec3::new(0.3, -1.2, 1.1);
            let out = (base - c).normalize();
            // In the thickness band, a quarter of them within a micrometre of the offset plane.
            let h = if rng.f32() < 0.25 { th + (rng.f32() - 0.5) * 2e-6 } else { (rng.f32() - 0.3) * 3.0 * th };
            let p = base + out * h + rng.vec3(0.01);
            let (_, radius, k) = m.test_for_reuse(p, 0, th, true);
            let radius = radius - rounding_margin(p);
            if !(radius > 0.0) {
                continue;
            }
            let dir = rng.vec3(1.0).normalize_or_zero();
            let q0 = p + dir * radius * rng.f32() * 0.5;
            if k == FREE {
                free += 1;
                let full = m.contact(q0, 0, th);
                assert!(full.is_none(), "skipped as free at {q0:?}, but the full test touches: {full:?}");
                continue;
            }
            // Also onto the nearest's offset plane and a few ulps either side of it,
            // where the side and the closest point's depth round differently.
            let t = m.kept[k as usize] as usize;
            let (a, n) = (Vec3::from(m.cur[m.tris[t][0] as usize]), m.normals[k as usize]);
            let on_plane = q0 + n * (th - (q0 - a).dot(n));
            let tries = std::iter::once(q0).chain((-8..=8).map(|j| on_plane + n * (j as f32 * 3e-8)));
            for q in tries.filter(|q| q.distance_squared(p) < radius * radius) {
                let full = m.contact(q, 0, th);
                match m.test_nearest(q, k, th) {
                    Some(fast) => {
                        near += 1;
                        let same = match (&fast, &full) {
                            (None, None) => true,
                            (Some(a), Some(b)) => a.triangle == b.triangle && a.target == b.target && a.bary == b.bary,
                            _ => false,
                        };
                        assert!(same, "nearest-only at {q:?}: {fast:?}, the full test: {full:?}");
                    }
                    None => fallbacks += 1,
                }
            }
        }
        println!("free {free}, nearest alone {near}, fell back to the full test {fallbacks}");
        assert!(free > 1000 && near > 1000, "too few reuses exercised: free {free}, nearest {near}");
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
            m.prepare(&[1.0], all, all, true, false);
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
