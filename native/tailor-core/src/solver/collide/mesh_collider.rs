//! A mesh collider (an animated character): its triangles, its vertex positions at the start
//! and end of the current frame, and the spatial hash of the positions of the current substep.
//!
//! Positions are given once per frame; substep `k` of `K` sees the linear interpolation at
//! `α = (k + 1)/K` (the paper's anti-tunnelling: a fast limb moves a fraction of its frame
//! motion per substep, not all of it in the first), and every vertex moves at the constant
//! velocity `(next − prev)/dt` during the frame (used by friction).
//!
//! The hash is rebuilt from scratch for each substep's positions (Alg. 1), with two skips:
//!
//! * **culling**: a triangle whose AABB misses the cloth's box grown by a margin is not filed.
//!   A triangle filed in a cell always overlaps that cell (every insertion rule visits only the
//!   cells of the triangle's AABB), so for a particle inside the cloth box grown by one cell
//!   the culled triangles were never candidates: culling does not change any contact.
//! * **reuse**: a collider whose positions did not change between frames keeps its hash for
//!   every substep, rebuilt only when the cloth leaves the box the hash was culled for.

use glam::Vec3;

use super::collider_filing::{file_triangle, MAX_STATES, PAD};
use super::levels::{levels_collide, triangle_levels_from_vertices};
use super::occupancy::{ClothMotion, Occupancy};
use crate::collision::collider_hash::InsertionRule;
use crate::collision::geometry::{closest_point_on_triangle, triangle_normal, Contact};
use crate::collision::hash::{cell_of, segment_cells, SpatialHash};
use crate::error::{Result, TailorError};
use crate::mesh::check_finite3;

/// Handle of a mesh collider of a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ColliderId(pub u32);

/// Options of a mesh collider.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshColliderOptions {
    /// Default static friction μs of particles touching this collider.
    pub static_friction: f32,
    /// Default kinetic friction μk.
    pub kinetic_friction: f32,
    /// Hash cell side, metres; `None` = the mean collider edge length (the paper's choice).
    pub cell_size: Option<f32>,
    /// Which cells a triangle is filed in. Default [`InsertionRule::PaperOrPlane`]: Alg. 1 alone
    /// misses the interior of triangles larger than a cell (measured in `collider_hash.rs`:
    /// the nearest triangle is in the particle's cell for 96 % of near-surface points with the
    /// paper rule at cell = mean edge, 40 % at cell = edge/2, ≥ 99.7 % with the plane cells),
    /// and character meshes are rarely isotropic. `tests/collision_mesh.rs` shows a cloth
    /// falling through a two-triangle floor with the paper rule and resting on it with this.
    pub rule: InsertionRule,
}

impl Default for MeshColliderOptions {
    fn default() -> Self {
        Self { static_friction: 0.5, kinetic_friction: 0.3, cell_size: None, rule: InsertionRule::PaperOrPlane }
    }
}

/// At most this many cells in one triangle's AABB (as in `ColliderHash`): more means a cell
/// size far too small for the collider and is refused rather than looped over.
const MAX_AABB_CELLS: u64 = 1 << 20;

/// At most this many cells walked along a particle's motion for its crossing in one substep:
/// a particle usually moves less than a cell per substep (1 or 2 cells), but a closing seam
/// can snap a corner several centimetres (the layered sample: 41 mm, 4 cells along each axis);
/// the bound only refuses a jump across the whole collider (10 m of 1 cm cells).
const MAX_CROSSING_CELLS: usize = 1024;

#[derive(Debug)]
pub(crate) struct MeshCollider {
    pub tris: Vec<[u32; 3]>,
    pub tri_level: Vec<i32>,
    pub opts: MeshColliderOptions,
    pub cell: f32,
    /// Positions at the start and end of the current frame.
    pub prev: Vec<[f32; 3]>,
    pub next: Vec<[f32; 3]>,
    pending: Option<Vec<[f32; 3]>>,
    /// Positions of the current substep.
    pub cur: Vec<[f32; 3]>,
    /// Vertex velocities during the current frame.
    pub vel: Vec<Vec3>,
    /// Whether the collider moves during the current frame.
    pub moving: bool,
    pub(super) hash: SpatialHash,
    /// Triangles filed in `hash` (hash entries index this list).
    pub(super) kept: Vec<u32>,
    /// Unit normal of each kept triangle at `cur` (zero for zero-area ones), by hash entry.
    pub(super) normals: Vec<Vec3>,
    /// Cloth box the hash was culled for (`None` = no valid hash).
    built_for: Option<(Vec3, Vec3)>,
    /// Where the cloth could reach when the hash was filed round each particle's motion.
    occupancy: Option<Occupancy>,
    /// The frame fractions a moving collider's hash was filed for (bit `j` of an entry's mask:
    /// `states[j]`); empty for a still collider's (one state, every bit).
    states: Vec<f32>,
    /// The current substep's bit in the hash's masks.
    pub(super) bit: u32,
}

/// What one `prepare` did (for the statistics).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PrepareOutcome {
    pub rebuilt: bool,
    pub kept: usize,
    pub culled: usize,
}

fn validate(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> Result<()> {
    if vertices.is_empty() || triangles.is_empty() {
        return Err(TailorError::EmptyMesh { what: "mesh collider".into() });
    }
    check_finite3("collider vertices", vertices)?;
    let n = vertices.len();
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
            return Err(TailorError::index(format!("collider triangle {t}"), v as i64, n, "vertices"));
        }
    }
    Ok(())
}

fn check_cell_span(vertices: &[[f32; 3]], triangles: &[[u32; 3]], cell: f32) -> Result<()> {
    for (t, tri) in triangles.iter().enumerate() {
        let p = tri.map(|v| Vec3::from(vertices[v as usize]));
        let pad = PAD * cell;
        let lo = cell_of((p[0].min(p[1]).min(p[2]) - pad).into(), cell);
        let hi = cell_of((p[0].max(p[1]).max(p[2]) + pad).into(), cell);
        let cells: u64 = (0..3).map(|k| (hi[k] - lo[k] + 1) as u64).product();
        if cells > MAX_AABB_CELLS {
            return Err(TailorError::setting(
                "cell_size",
                cell,
                format!("collider triangle {t} spans {cells} hash cells; use a larger cell size"),
            ));
        }
    }
    Ok(())
}

/// Mean length of the triangles' edges (each shared edge counted twice; this is a cell size,
/// not a measurement).
fn mean_edge(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> f32 {
    let mut sum = 0.0f64;
    for t in triangles {
        let p = t.map(|v| Vec3::from(vertices[v as usize]));
        sum += (p[0].distance(p[1]) + p[1].distance(p[2]) + p[2].distance(p[0])) as f64;
    }
    (sum / (3 * triangles.len()) as f64) as f32
}

impl MeshCollider {
    pub fn new(vertices: &[[f32; 3]], triangles: &[[u32; 3]], opts: MeshColliderOptions) -> Result<Self> {
        validate(vertices, triangles)?;
        for (name, v) in [("static_friction", opts.static_friction), ("kinetic_friction", opts.kinetic_friction)] {
            crate::solver::model::settings::non_negative(name, v)?;
        }
        let cell = match opts.cell_size {
            Some(c) if !(c.is_finite() && c > 0.0) => {
                return Err(TailorError::setting("cell_size", c, "the hash cell size must be positive and finite"))
            }
            Some(c) => c,
            None => {
                let e = mean_edge(vertices, triangles);
                if !(e.is_finite() && e > 0.0) {
                    return Err(TailorError::EmptyMesh { what: "mesh collider (every triangle has zero size)".into() });
                }
                e
            }
        };
        check_cell_span(vertices, triangles, cell)?;
        Ok(Self {
            tris: triangles.to_vec(),
            tri_level: vec![0; triangles.len()],
            opts,
            cell,
            prev: vertices.to_vec(),
            next: vertices.to_vec(),
            pending: None,
            cur: vertices.to_vec(),
            vel: vec![Vec3::ZERO; vertices.len()],
            moving: false,
            hash: SpatialHash::new(),
            kept: Vec::new(),
            normals: Vec::new(),
            built_for: None,
            occupancy: None,
            states: Vec::new(),
            bit: u32::MAX,
        })
    }

    pub fn num_vertices(&self) -> usize {
        self.next.len()
    }

    /// Positions at the end of the next frame.
    pub fn set_positions(&mut self, p: &[[f32; 3]]) -> Result<()> {
        if p.len() != self.num_vertices() {
            return Err(TailorError::shape(
                "collider positions",
                format!("{} positions for {} collider vertices", p.len(), self.num_vertices()),
            ));
        }
        check_finite3("collider positions", p)?;
        check_cell_span(p, &self.tris, self.cell)?;
        self.pending = Some(p.to_vec());
        Ok(())
    }

    /// After a frame run by another backend: this collider's positions are the frame's end
    /// (substep α = 1), as the CPU's last `prepare` leaves them; its hash is stale.
    #[cfg(feature = "gpu")]
    pub fn end_frame_elsewhere(&mut self) {
        if self.moving {
            self.cur.clone_from(&self.next);
            self.built_for = None;
        }
    }

    /// Per-vertex (length = vertices) or per-triangle (length = triangles) levels.
    pub fn set_levels(&mut self, levels: &[i32]) -> Result<()> {
        if levels.len() == self.tris.len() {
            self.tri_level = levels.to_vec();
        } else if levels.len() == self.num_vertices() {
            self.tri_level = triangle_levels_from_vertices(levels, &self.tris);
        } else {
            return Err(TailorError::shape(
                "collider levels",
                format!(
                    "{} levels: give one per vertex ({}) or one per triangle ({})",
                    levels.len(),
                    self.num_vertices(),
                    self.tris.len()
                ),
            ));
        }
        Ok(())
    }

    /// Starts a frame of `dt` seconds: takes the pending positions as the frame's end.
    pub fn begin_frame(&mut self, dt: f32) {
        let was_moving = self.moving;
        match self.pending.take() {
            Some(p) => self.prev = std::mem::replace(&mut self.next, p),
            None => {
                if was_moving {
                    self.prev.clone_from(&self.next);
                }
            }
        }
        self.moving = self.prev != self.next;
        if self.moving {
            let inv = 1.0 / dt;
            for (v, (a, b)) in self.vel.iter_mut().zip(self.prev.iter().zip(&self.next)) {
                *v = (Vec3::from(*b) - Vec3::from(*a)) * inv;
            }
            self.built_for = None;
        } else if was_moving {
            self.vel.iter_mut().for_each(|v| *v = Vec3::ZERO);
            self.cur.clone_from(&self.next);
            self.built_for = None;
        }
    }

    /// Positions of substep fraction `alphas[0]` and a hash valid for them; `cloth` is the box
    /// of the cloth during the substep, `reach` a box the cloth is expected to stay in until
    /// the frame ends. `force` rebuilds every substep, `cull` enables culling.
    ///
    /// A moving collider's hash serves the rest of the frame: `alphas` lists this substep's
    /// fraction and those of the frame's later substeps, and each triangle is filed, in one
    /// build, in every cell the insertion rule gives it at each of them, with a mask saying at
    /// which (`SpatialHash::build_with_masks`); a query reads the current substep's bit
    /// ([`bit`](Self::bit)). Every substep thus sees exactly the candidates a build of its own
    /// would give (the positions at `alphas[j]` are computed as `cur` is), for one build a
    /// frame instead of one a substep while the cloth stays within `reach` ⊕ `l`.
    pub fn prepare(
        &mut self,
        alphas: &[f32],
        cloth: (Vec3, Vec3),
        reach: (Vec3, Vec3),
        force: bool,
        cull: bool,
        motion: Option<&ClothMotion<'_>>,
    ) -> PrepareOutcome {
        let alpha = alphas.first().copied().unwrap_or(1.0);
        if self.moving {
            for (c, (a, b)) in self.cur.iter_mut().zip(self.prev.iter().zip(&self.next)) {
                *c = (Vec3::from(*a).lerp(Vec3::from(*b), alpha)).into();
            }
        }
        let l = self.cell;
        // A moving collider's hash holds this substep when it was filed for its fraction.
        let state = if self.moving { self.states.iter().position(|&a| a == alpha) } else { Some(0) };
        let reusable = !force
            && state.is_some()
            && match self.built_for {
                // The hash was culled for `built ⊕ 2l`; valid while the cloth stays within `built ⊕ l`.
                Some((lo, hi)) => !cull || (cloth.0.cmpge(lo - l).all() && cloth.1.cmple(hi + l).all()),
                None => false,
            }
            // Filed round each particle's motion: valid while each stays within `l` of it.
            && match (&self.occupancy, motion) {
                (Some(occ), Some(m)) => occ.covers(m, l),
                (Some(_), None) => false,
                (None, _) => true,
            };
        if reusable {
            if self.moving {
                self.bit = 1 << state.unwrap_or(0);
                self.update_normals();
            }
            return PrepareOutcome { rebuilt: false, kept: self.kept.len(), culled: self.tris.len() - self.kept.len() };
        }
        // The fractions to file for: this substep's alone for a still collider (or when forced).
        self.states.clear();
        if self.moving {
            let span = if force { &alphas[..alphas.len().min(1)] } else { &alphas[..alphas.len().min(MAX_STATES)] };
            self.states.extend_from_slice(span);
            if self.states.is_empty() {
                self.states.push(alpha);
            }
        }
        let culled_for = if self.moving && !force { (cloth.0.min(reach.0), cloth.1.max(reach.1)) } else { cloth };
        let (prev, next, cur, states) = (&self.prev, &self.next, &self.cur, &self.states);
        let at = |tri: [u32; 3], j: usize| -> [Vec3; 3] {
            match states.get(j) {
                Some(&a) => tri.map(|v| Vec3::from(prev[v as usize]).lerp(Vec3::from(next[v as usize]), a)),
                None => tri.map(|v| Vec3::from(cur[v as usize])),
            }
        };
        let count = states.len().max(1);
        let (lo, hi) = (culled_for.0 - 2.0 * l, culled_for.1 + 2.0 * l);
        // A moving collider filed for the frame: round each particle's motion, not the whole
        // cloth's box (`occupancy.rs`).
        let occupancy = match motion {
            Some(m) if self.moving && cull && !force && count > 1 => Occupancy::new(m, 2.5 * l, 2.0 * l),
            _ => None,
        };
        self.kept.clear();
        for (t, tri) in self.tris.iter().enumerate() {
            if cull {
                // Over several fractions: the box of the frame's start and end positions holds
                // the triangle at every fraction between (a superset: nothing the fractions'
                // own boxes keep is culled).
                let p = if count == 1 {
                    at(*tri, 0).map(|v| (v, v))
                } else {
                    tri.map(|v| {
                        let (a, b) = (Vec3::from(prev[v as usize]), Vec3::from(next[v as usize]));
                        (a.min(b), a.max(b))
                    })
                };
                let (tlo, thi) = (p[0].0.min(p[1].0).min(p[2].0), p[0].1.max(p[1].1).max(p[2].1));
                let far = tlo.cmpgt(hi).any() || thi.cmplt(lo).any();
                if far || occupancy.as_ref().is_some_and(|o| !o.touches(tlo, thi)) {
                    continue;
                }
            }
            self.kept.push(t as u32);
        }
        let (tris, kept, rule) = (&self.tris, &self.kept, self.opts.rule);
        let pad = PAD * l;
        let filed = self.hash.build_with_masks(kept.len(), l, |i, emit| {
            file_triangle(count, |j| at(tris[kept[i] as usize], j), l, pad, rule, emit)
        });
        if filed.is_err() && count > 1 {
            // Too many cells for one table over the frame (a fast, coarse collider): this
            // substep alone, whose sizes were checked when its positions were given.
            self.states.truncate(1);
            let at = |tri: [u32; 3]| tri.map(|v| Vec3::from(self.cur[v as usize]));
            let _ = self.hash.build_with_masks(kept.len(), l, |i, emit| {
                file_triangle(1, |_| at(tris[kept[i] as usize]), l, pad, rule, emit)
            });
        }
        self.bit = if self.moving { 1 } else { u32::MAX };
        self.update_normals();
        self.built_for = Some(culled_for);
        self.occupancy = occupancy;
        PrepareOutcome { rebuilt: true, kept: self.kept.len(), culled: self.tris.len() - self.kept.len() }
    }

    /// Unit normals of the kept triangles at `cur`, by hash entry.
    fn update_normals(&mut self) {
        self.normals.clear();
        self.normals.extend(self.kept.iter().map(|&t| {
            let p = self.tris[t as usize].map(|v| Vec3::from(self.cur[v as usize]));
            triangle_normal(p[0], p[1], p[2]).unwrap_or(Vec3::ZERO)
        }));
    }

    /// The particle-vs-cell test at `p` against the triangles of its cell whose level
    /// collides with `level`; the same result as
    /// [`particle_vs_cell`](crate::collision::geometry::particle_vs_cell), with the normals
    /// cached at the build.
    #[inline]
    pub fn contact(&self, p: Vec3, level: i32, thickness: f32) -> Option<Contact> {
        self.test_for_reuse(p, level, thickness, false).0
    }

    /// Where the motion `from → to` of a particle over a substep first passes through the
    /// front of a triangle whose level collides with `level` (the previous position's side, as
    /// the paper's "opposite side of all triangles" test cannot tell once a particle is deeper
    /// than a cell: a limb's interior cells hold no triangles, and past the middle of a limb
    /// the nearest surface is the far one). The contact's target is `to` moved back along that
    /// triangle's normal to `thickness` in front of its plane (the tangential motion is kept).
    /// `None` when the segment crosses no triangle front to back, or passes through more than
    /// `MAX_CROSSING_CELLS` cells without crossing one (a jump that long is left to the
    /// particle-vs-cell test).
    pub fn crossing(&self, from: Vec3, to: Vec3, level: i32, thickness: f32) -> Option<Contact> {
        if self.kept.is_empty() {
            return None;
        }
        let l = self.cell;
        let d = to - from;
        let mut best: Option<(f32, Contact)> = None;
        // A triangle crossed at q is filed in q's cell (its AABB holds q and its plane passes
        // through the cell; padded by `PAD`, so rounding at a cell face loses nothing): the
        // cells the segment passes through hold every candidate, however long the motion.
        segment_cells(from.into(), to.into(), l, MAX_CROSSING_CELLS, |cell| {
            for k in self.hash.query_cell_for(cell, self.bit) {
                let t = self.kept[k as usize];
                let n = self.normals[k as usize];
                if n == Vec3::ZERO || !levels_collide(level, self.tri_level[t as usize]) {
                    continue;
                }
                let [a, b, c] = self.tris[t as usize].map(|v| Vec3::from(self.cur[v as usize]));
                let (side_from, side_to) = ((from - a).dot(n), (to - a).dot(n));
                if !(side_from >= 0.0 && side_to < 0.0) {
                    continue;
                }
                let s = side_from / (side_from - side_to);
                if best.as_ref().is_some_and(|(bs, _)| s >= *bs) {
                    continue;
                }
                let q = from + d * s;
                let (closest, bary) = closest_point_on_triangle(q, a, b, c);
                // The crossing point lies on the triangle (to rounding), not only on its plane.
                if closest.distance_squared(q) > (1e-4 * l) * (1e-4 * l) {
                    continue;
                }
                let depth = thickness - side_to;
                best = Some((s, Contact { triangle: t, closest, bary, normal: n, target: to + n * depth, depth }));
            }
        });
        // A jump longer than the walk's bound is searched in its first cells only; past them
        // it is left to the particle-vs-cell test.
        best.map(|(_, c)| c)
    }

    /// Velocity of the collider surface at barycentric point `bary` of triangle `t`.
    #[inline]
    pub fn velocity_at(&self, t: u32, bary: [f32; 3]) -> Vec3 {
        if !self.moving {
            return Vec3::ZERO;
        }
        let tri = self.tris[t as usize];
        self.vel[tri[0] as usize] * bary[0] + self.vel[tri[1] as usize] * bary[1] + self.vel[tri[2] as usize] * bary[2]
    }
}
