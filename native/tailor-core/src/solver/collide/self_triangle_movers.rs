//! The (particle, triangle) pairs a triangle-contact list lacks once a few particles have moved
//! too far (issue 22: candidates found once, projected every iteration).
//!
//! The list ([`SelfTriangles`](super::self_triangles)) holds every pair closer than `h + m` at
//! the positions `x_ref` of its search. Take out of every particle's displacement since the
//! search the cloth's common translation `s`: a particle whose remaining displacement is at
//! least `m/2` is a **mover**. A pair without a mover (the particle and the triangle's three
//! corners) came less than `m` closer, so a pair the list lacks and that is now closer than `h`
//! has a mover. On the samples' walk a pass finds a handful (measured: often 1-3), while the
//! whole search (every triangle against the hash of every particle) ran as soon as there was
//! one. Now the movers' pairs alone are searched, in the search's hash of `x_ref`:
//!
//! * a triangle with a mover corner, against every particle that did not move: such a
//!   particle within `h + m` of the triangle now was, at the search, within the triangle's box
//!   grown by `h + m` and shifted by `−s`, grown again by `m/2`;
//! * a mover, against every triangle whose corners did not move: the triangle's corners are
//!   now within `h + m + L` of the mover (`L` the longest edge now), so at the search within
//!   that distance plus `m/2` of its position shifted by `−s`; their triangles are the
//!   candidates;
//! * a mover against a triangle with a mover corner: every such pair.
//!
//! The caller keeps those closer than `h + m` that its list lacks, and corrects the list and
//! them in one sorted order: the same corrections as a search every pass (tested).

use glam::Vec3;

use crate::collision::hash::{cell_of, SpatialHash};
use crate::solver::model::soa::Vec3Soa;

/// Triangles of each vertex, as compressed rows (`tris[offsets[v]..offsets[v + 1]]`).
#[derive(Debug, Default)]
pub(crate) struct VertexTriangles {
    offsets: Vec<u32>,
    tris: Vec<u32>,
}

impl VertexTriangles {
    pub fn new(n: usize, triangles: &[[u32; 3]]) -> Self {
        let mut offsets = vec![0u32; n + 1];
        for t in triangles {
            for &v in t {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            offsets[v + 1] += offsets[v];
        }
        let mut cursor = offsets.clone();
        let mut tris = vec![0u32; offsets[n] as usize];
        for (k, t) in triangles.iter().enumerate() {
            for &v in t {
                tris[cursor[v as usize] as usize] = k as u32;
                cursor[v as usize] += 1;
            }
        }
        VertexTriangles { offsets, tris }
    }

    /// The number of vertices.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn of(&self, v: u32) -> &[u32] {
        &self.tris[self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize]
    }

    pub fn memory_bytes(&self) -> usize {
        (self.offsets.capacity() + self.tris.capacity()) * std::mem::size_of::<u32>()
    }
}

/// What the movers' pairs are looked for in.
pub(crate) struct TriangleMovers<'a> {
    pub x: &'a Vec3Soa,
    /// The search's hash of the particles at `x_ref`.
    pub hash: &'a SpatialHash,
    pub cell: f32,
    pub triangles: &'a [[u32; 3]],
    pub vertex_triangles: &'a VertexTriangles,
    /// The cloth's common translation since the search.
    pub shift: Vec3,
    /// The movers, ascending.
    pub movers: &'a [u32],
    /// `h + m`.
    pub reach: f32,
    pub margin: f32,
    /// The longest edge of the cloth now.
    pub longest: f32,
}

impl TriangleMovers<'_> {
    fn is_mover(&self, v: u32) -> bool {
        self.movers.binary_search(&v).is_ok()
    }

    /// Particles filed in the cells of the box `[lo, hi]`.
    fn in_box(&self, lo: Vec3, hi: Vec3, mut visit: impl FnMut(u32)) {
        let (a, b) = (cell_of(lo.into(), self.cell), cell_of(hi.into(), self.cell));
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    for p in self.hash.query_cell([x, y, z]) {
                        visit(p);
                    }
                }
            }
        }
    }

    /// Every (particle, triangle) pair with a mover that may now be closer than `h + m`,
    /// sorted and without repeats (a superset: the caller tests them).
    pub fn candidates(&self) -> Vec<(u32, u32)> {
        let mut moved_tris: Vec<u32> = self.movers.iter().flat_map(|&v| self.vertex_triangles.of(v)).copied().collect();
        moved_tris.sort_unstable();
        moved_tris.dedup();
        let mut out = Vec::new();
        let grow = Vec3::splat(self.reach + 0.5 * self.margin);
        for &t in &moved_tris {
            let [a, b, c] = self.triangles[t as usize].map(|v| self.x.get(v as usize));
            let (lo, hi) = (a.min(b).min(c) - self.shift - grow, a.max(b).max(c) - self.shift + grow);
            self.in_box(lo, hi, |p| {
                if !self.is_mover(p) {
                    out.push((p, t));
                }
            });
            out.extend(self.movers.iter().map(|&p| (p, t)));
        }
        let around = Vec3::splat(self.reach + self.longest + 0.5 * self.margin);
        for &p in self.movers {
            let centre = self.x.get(p as usize) - self.shift;
            self.in_box(centre - around, centre + around, |v| {
                for &t in self.vertex_triangles.of(v) {
                    if !self.triangles[t as usize].iter().any(|&w| self.is_mover(w)) {
                        out.push((p, t));
                    }
                }
            });
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_triangles_list_each_triangle_at_its_corners() {
        let vt = VertexTriangles::new(4, &[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(vt.of(0), &[0, 1]);
        assert_eq!(vt.of(1), &[0]);
        assert_eq!(vt.of(2), &[0, 1]);
        assert_eq!(vt.of(3), &[1]);
    }
}
