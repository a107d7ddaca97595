//! Attachments of cloth particles to a mesh collider: a painted pin (a waistband, the top of a
//! shoulder line) that rides on the animated body instead of staying where it was in world
//! space.
//!
//! **Binding** (once, at [`Simulation::attach_to_collider`]): each particle is bound to the
//! collider triangle nearest to it at the collider's current positions, by the barycentric
//! coordinates `b` of its closest point `q` on that triangle and its offset `o = F⁻¹·(x − q)`
//! in the triangle's orthonormal frame `F = [ê, n̂, n̂ × ê]` (`ê` along the first edge, `n̂` the
//! face normal). **Every substep** the target is `t = Σₖ bₖ·vₖ + F·o` with the vertices `vₖ`
//! (and so `F`) of that substep, interpolated within the frame as the collisions use them.
//!
//! Why a triangle and a frame rather than the nearest vertex plus a normal offset (what the
//! module-side demo did in Python): the target equals the particle's position at attach time,
//! so attaching does not yank the garment; the tangential position is kept exactly instead of
//! being rounded to the body's vertex spacing (with a vertex anchor, all the cloth particles
//! nearest one body vertex are pulled onto the same point, bunching a waistband finer than the
//! body); and a target costs one triangle's vertices per substep, with no pass over the body to
//! average vertex normals. A face frame turns abruptly between neighbouring triangles, but each
//! particle keeps its one triangle, whose frame turns continuously as the body moves.
//!
//! The attachment is soft (`w/2·‖x − t‖²`, weight on the system diagonal, `w·t` on the
//! right-hand side), so the cloth can still be pushed off by contacts and seams.

use glam::Vec3;
use rayon::prelude::*;

use crate::collision::geometry::{closest_point_on_triangle, triangle_normal};
use crate::error::{Result, TailorError};
use crate::solver::collide::mesh_collider::MeshCollider;
use crate::solver::collide::ColliderId;
use crate::solver::model::constraints::ColliderAttachment;
use crate::solver::simulation::Simulation;

/// The orthonormal frame `(ê, n̂, n̂ × ê)` of triangle `abc`; `None` when it has no area.
fn frame(a: Vec3, b: Vec3, c: Vec3) -> Option<[Vec3; 3]> {
    let n = triangle_normal(a, b, c)?;
    let e = (b - a).try_normalize()?;
    Some([e, n, n.cross(e)])
}

/// Vertex `v` of collider `m` at substep fraction `alpha` of the current frame (the positions
/// the collisions of that substep use; see `MeshCollider::prepare`).
#[inline]
fn vertex_at(m: &MeshCollider, v: u32, alpha: f32) -> Vec3 {
    let v = v as usize;
    if m.moving {
        Vec3::from(m.prev[v]).lerp(Vec3::from(m.next[v]), alpha)
    } else {
        Vec3::from(m.next[v])
    }
}

/// The target of `a` on collider `m` with vertex positions given by `at`; `None` when the bound
/// triangle has collapsed to no area (the target then stays where it was).
#[inline]
fn target_of(a: &ColliderAttachment, m: &MeshCollider, at: impl Fn(u32) -> Vec3) -> Option<Vec3> {
    let [p0, p1, p2] = m.tris[a.triangle as usize].map(at);
    let f = frame(p0, p1, p2)?;
    let q = p0 * a.bary[0] + p1 * a.bary[1] + p2 * a.bary[2];
    Some(q + f[0] * a.local[0] + f[1] * a.local[1] + f[2] * a.local[2])
}

/// Binds point `p` to its nearest non-degenerate triangle of `positions`/`tris`:
/// `(triangle, barycentrics, local offset)`, or `None` when every triangle is degenerate.
fn bind(p: Vec3, positions: &[[f32; 3]], tris: &[[u32; 3]], boxes: &[(Vec3, Vec3)]) -> Option<(u32, [f32; 3], Vec3)> {
    let mut best: Option<(f32, u32, Vec3, [f32; 3])> = None;
    for (t, tri) in tris.iter().enumerate() {
        // The distance to the triangle's box bounds its distance from below.
        let (lo, hi) = boxes[t];
        let d_box = (lo - p).max(p - hi).max(Vec3::ZERO).length_squared();
        if best.as_ref().is_some_and(|b| d_box >= b.0) {
            continue;
        }
        let [a, b, c] = tri.map(|v| Vec3::from(positions[v as usize]));
        if frame(a, b, c).is_none() {
            continue;
        }
        let (q, bary) = closest_point_on_triangle(p, a, b, c);
        let d = q.distance_squared(p);
        if best.as_ref().is_none_or(|b| d < b.0) {
            best = Some((d, t as u32, q, bary));
        }
    }
    let (_, t, q, bary) = best?;
    let [a, b, c] = tris[t as usize].map(|v| Vec3::from(positions[v as usize]));
    let f = frame(a, b, c)?;
    let o = p - q;
    Some((t, bary, Vec3::new(o.dot(f[0]), o.dot(f[1]), o.dot(f[2]))))
}

impl Simulation {
    /// Attaches `particles` softly (`stiffness`, N/m each) to mesh collider `collider`: each is
    /// bound where it is now to the nearest triangle of the collider's current positions (the
    /// last substep run, or as given to `add_mesh_collider` before any step), and from then on
    /// is pulled every substep towards that bound point as the collider moves and deforms (see
    /// the module docs). Attaching an already attached particle rebinds it. Errors, changing
    /// nothing: an unknown collider, a particle out of range, a stiffness not positive and
    /// finite, or a collider whose triangles all have zero area.
    pub fn attach_to_collider(&mut self, particles: &[u32], collider: ColliderId, stiffness: f32) -> Result<()> {
        self.sleep.wake();
        let n_meshes = self.collide.meshes.len();
        let m = self.collide.meshes.get(collider.0 as usize).ok_or_else(|| {
            TailorError::index("attach_to_collider: collider id", collider.0 as i64, n_meshes, "mesh colliders")
        })?;
        let n = self.num_particles();
        if let Some(&bad) = particles.iter().find(|&&p| p as usize >= n) {
            return Err(TailorError::index("attach_to_collider: particle", bad as i64, n, "particles"));
        }
        if !(stiffness > 0.0 && stiffness.is_finite()) {
            return Err(TailorError::setting(
                "stiffness",
                stiffness,
                "an attachment's stiffness must be positive and finite",
            ));
        }
        let (pos, tris) = (&m.cur, &m.tris);
        let boxes: Vec<(Vec3, Vec3)> = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| Vec3::from(pos[v as usize]));
                (a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let x = &self.x;
        let bound: Vec<Option<(u32, [f32; 3], Vec3)>> =
            particles.par_iter().map(|&p| bind(x.get(p as usize), pos, tris, &boxes)).collect();
        let mut new = Vec::with_capacity(particles.len());
        for (&p, b) in particles.iter().zip(bound) {
            let (triangle, bary, local) = b.ok_or_else(|| TailorError::EmptyMesh {
                what: format!("mesh collider {} for attachments (every triangle has zero area)", collider.0),
            })?;
            new.push(ColliderAttachment {
                particle: p,
                collider: collider.0,
                triangle,
                bary,
                local: local.into(),
                weight: stiffness,
                target: x.get(p as usize).into(),
            });
        }
        let mut replaced = vec![false; n];
        particles.iter().for_each(|&p| replaced[p as usize] = true);
        // An attachment asked for takes a particle over from the closing holds (which are
        // removed on release): it stays.
        self.collide.holds.retain(|&p| !replaced[p as usize]);
        let list = &mut self.model.collider_attachments;
        list.retain(|a| !replaced[a.particle as usize]);
        // A particle given twice is bound once.
        for a in new {
            if replaced[a.particle as usize] {
                replaced[a.particle as usize] = false;
                list.push(a);
            }
        }
        self.model.dirty = true;
        Ok(())
    }

    /// Removes the collider attachments of `particles` (all of them with `None`). Particles
    /// not attached are ignored; an index out of range is an error.
    pub fn detach_from_collider(&mut self, particles: Option<&[u32]>) -> Result<()> {
        self.sleep.wake();
        let n = self.num_particles();
        let before = self.model.collider_attachments.len();
        match particles {
            None => {
                self.model.collider_attachments.clear();
                self.collide.holds.clear();
            }
            Some(ps) => {
                if let Some(&bad) = ps.iter().find(|&&p| p as usize >= n) {
                    return Err(TailorError::index("detach_from_collider: particle", bad as i64, n, "particles"));
                }
                let mut drop = vec![false; n];
                ps.iter().for_each(|&p| drop[p as usize] = true);
                self.model.collider_attachments.retain(|a| !drop[a.particle as usize]);
                self.collide.holds.retain(|&p| !drop[p as usize]);
            }
        }
        if self.model.collider_attachments.len() != before {
            self.model.dirty = true;
        }
        Ok(())
    }

    /// The collider attachments: particle, collider, bound triangle and current target each,
    /// the body's holds while seams close (`closing_holds`) included.
    pub fn collider_attachments(&self) -> &[ColliderAttachment] {
        &self.model.collider_attachments
    }

    /// The collider attachments asked for (`attach_to_collider`), the holds left out.
    pub fn asked_attachments(&self) -> Vec<&ColliderAttachment> {
        let mut held = vec![false; self.num_particles()];
        self.collide.holds.iter().for_each(|&p| held[p as usize] = true);
        self.model.collider_attachments.iter().filter(|a| !held[a.particle as usize]).collect()
    }

    /// Prediction stage: every collider attachment's target at this substep's collider
    /// positions, and `w·t` onto the fixed right-hand side.
    pub(crate) fn apply_collider_attachments(&mut self) {
        if self.model.collider_attachments.is_empty() {
            return;
        }
        let alpha = self.collide.alpha;
        let meshes = &self.collide.meshes;
        for a in &mut self.model.collider_attachments {
            let m = &meshes[a.collider as usize];
            if let Some(t) = target_of(a, m, |v| vertex_at(m, v, alpha)) {
                a.target = t.into();
            }
            let i = a.particle as usize;
            self.rhs_fixed.set(i, self.rhs_fixed.get(i) + Vec3::from(a.target) * a.weight);
        }
    }
}
