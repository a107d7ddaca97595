//! The simulation's collisions (see [`collide`](crate::solver::collide) for the machinery):
//! the mesh colliders' and self-collision's public API, and the hooks the stages call.
//!
//! Where each hook runs in a substep (see [`STAGES`](crate::solver::stages::STAGES)):
//!
//! 1. [`Stage::Prediction`](crate::solver::stages::Stage::Prediction), after the prediction:
//!    [`Simulation::prepare_mesh_collisions`]: every mesh collider takes its positions for this
//!    substep (interpolated within the frame) and rebuilds its hash;
//! 2. [`Stage::Local`](crate::solver::stages::Stage::Local), each iteration, with the analytic
//!    colliders: [`Simulation::detect_mesh_contacts`]: every particle runs the particle-vs-cell
//!    test against every mesh collider; a hit becomes the particle's contact in the shared
//!    [`ContactSet`](crate::solver::collide::contacts::ContactSet), living for this iteration;
//! 3. [`Stage::Global`](crate::solver::stages::Stage::Global), after each sweep:
//!    [`Simulation::self_collide_iteration`] pushes overlapping particle spheres apart;
//! 4. [`Stage::Damping`](crate::solver::stages::Stage::Damping):
//!    [`Simulation::resolve_mesh_penetrations`] puts particles still behind a mesh collider on
//!    their target, and Coulomb friction acts on the velocity relative to the touched triangle.
//!
//! Kept out of `collide/` so that the collision machinery does not import the simulation that
//! owns it (no import cycle): `simulation/` uses `collide/`, never the other way.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;

use super::Simulation;
use crate::error::{Result, TailorError};
use crate::solver::collide::contacts::CONTACT_WEIGHT_FACTOR;
use crate::solver::collide::levels;
use crate::solver::collide::mesh_broad_phase::{rounding_margin, Reuse, Shortlist};
use crate::solver::collide::mesh_collider::MeshCollider;
use crate::solver::collide::occupancy::ClothMotion;
use crate::solver::collide::self_collide::PassInput;
use crate::solver::collide::self_triangles::TrianglePassInput;
use crate::solver::collide::{
    ColliderId, CollisionSkips, MeshColliderOptions, SelfCollisionSettings, SelfContacts, MESH_CONTACT,
};
use crate::solver::model::settings::DEFAULT_THICKNESS;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// Box of the positions `a ∪ b`.
fn box_of(a: &crate::solver::model::soa::Vec3Soa, b: &crate::solver::model::soa::Vec3Soa) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for s in [a, b] {
        for i in 0..s.len() {
            let p = s.get(i);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo, hi)
}

/// Where the cloth is expected to go until the frame ends: the box of every particle's
/// substep motion `x_start → y` carried on `steps` times (the hash of a moving collider is
/// culled for it, `MeshCollider::prepare`; a cloth that leaves it only costs a rebuild).
fn reach_of(
    a: &crate::solver::model::soa::Vec3Soa,
    b: &crate::solver::model::soa::Vec3Soa,
    steps: f32,
) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for i in 0..a.len() {
        let p = a.get(i) + (b.get(i) - a.get(i)) * steps;
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (lo, hi)
}

fn check_coefficients(name: &'static str, v: &[f32], n: usize) -> Result<()> {
    if v.len() != n {
        return Err(TailorError::shape(name, format!("{} values for {n} particles", v.len())));
    }
    if let Some((i, &bad)) = v.iter().enumerate().find(|(_, &c)| !(c.is_finite() && c >= 0.0)) {
        return Err(TailorError::setting(name, bad, format!("particle {i}: friction must be finite and non-negative")));
    }
    Ok(())
}

impl Simulation {
    // ----- public API -----

    /// Adds an animated mesh collider (outward-facing triangles). Positions follow with
    /// [`set_collider_positions`](Self::set_collider_positions), once per frame.
    pub fn add_mesh_collider(
        &mut self,
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
        options: MeshColliderOptions,
    ) -> Result<ColliderId> {
        self.sleep.wake();
        let m = MeshCollider::new(vertices, triangles, options)?;
        self.collide.meshes.push(m);
        Ok(ColliderId(self.collide.meshes.len() as u32 - 1))
    }

    pub fn num_mesh_colliders(&self) -> usize {
        self.collide.meshes.len()
    }

    pub(crate) fn mesh(&self, id: ColliderId) -> Result<&MeshCollider> {
        let n = self.collide.meshes.len();
        self.collide
            .meshes
            .get(id.0 as usize)
            .ok_or_else(|| TailorError::index("collider id", id.0 as i64, n, "mesh colliders"))
    }

    fn mesh_mut(&mut self, id: ColliderId) -> Result<&mut MeshCollider> {
        self.mesh(id)?;
        Ok(&mut self.collide.meshes[id.0 as usize])
    }

    /// The collider's vertex positions at the end of the next `step` (the solver interpolates
    /// from the previous ones across the substeps).
    pub fn set_collider_positions(&mut self, id: ColliderId, positions: &[[f32; 3]]) -> Result<()> {
        self.mesh_mut(id)?.set_positions(positions)
    }

    /// Collider positions of the last substep run (interpolated within the frame).
    pub fn collider_positions(&self, id: ColliderId) -> Result<&[[f32; 3]]> {
        Ok(&self.mesh(id)?.cur)
    }

    pub fn collider_triangles(&self, id: ColliderId) -> Result<&[[u32; 3]]> {
        Ok(&self.mesh(id)?.tris)
    }

    /// Collision levels of a collider, per vertex or per triangle (see [`levels`]).
    pub fn set_collider_levels(&mut self, id: ColliderId, levels: &[i32]) -> Result<()> {
        levels::check_levels("collider levels", levels)?;
        self.sleep.wake();
        self.mesh_mut(id)?.set_levels(levels)
    }

    /// Default friction of particles touching this collider.
    pub fn set_collider_friction(&mut self, id: ColliderId, static_friction: f32, kinetic_friction: f32) -> Result<()> {
        self.sleep.wake();
        crate::solver::model::settings::non_negative("static_friction", static_friction)?;
        crate::solver::model::settings::non_negative("kinetic_friction", kinetic_friction)?;
        let m = self.mesh_mut(id)?;
        m.opts.static_friction = static_friction;
        m.opts.kinetic_friction = kinetic_friction;
        Ok(())
    }

    /// Collision level per cloth particle (see [`levels`]).
    pub fn set_particle_levels(&mut self, levels: &[i32]) -> Result<()> {
        levels::check_levels("particle levels", levels)?;
        self.sleep.wake();
        if levels.len() != self.num_particles() {
            return Err(TailorError::shape(
                "particle levels",
                format!("{} levels for {} particles", levels.len(), self.num_particles()),
            ));
        }
        self.collide.levels = levels.to_vec();
        self.collide.self_state.forget_pairs();
        Ok(())
    }

    pub fn particle_levels(&self) -> &[i32] {
        &self.collide.levels
    }

    /// Per-particle static and kinetic friction, used for mesh contacts and cloth-cloth pairs
    /// instead of the colliders' and self-collision defaults; `None` restores the defaults.
    pub fn set_particle_friction(&mut self, coefficients: Option<(&[f32], &[f32])>) -> Result<()> {
        self.sleep.wake();
        let n = self.num_particles();
        self.collide.friction = match coefficients {
            Some((s, k)) => {
                check_coefficients("static_friction", s, n)?;
                check_coefficients("kinetic_friction", k, n)?;
                Some((s.to_vec(), k.to_vec()))
            }
            None => None,
        };
        Ok(())
    }

    pub fn set_self_collision(&mut self, s: SelfCollisionSettings) -> Result<()> {
        self.sleep.wake();
        s.validate()?;
        self.collide.self_settings = s;
        self.h_prepared = 0.0; // the two-level step is on only without self-collision
        Ok(())
    }

    pub fn self_collision(&self) -> SelfCollisionSettings {
        self.collide.self_settings
    }

    /// Switches the scene's collision skips (benchmarks and equivalence tests).
    pub fn set_collision_skips(&mut self, skips: CollisionSkips) {
        self.sleep.wake();
        self.collide.skips = skips;
    }

    /// Self-collision sphere radius in effect.
    pub fn self_collision_radius(&self) -> f32 {
        let s = self.collide.self_settings;
        s.radius.unwrap_or(match s.contacts {
            SelfContacts::Spheres => 0.5 * self.model.mesh.mean_edge_length() as f32,
            SelfContacts::Triangles => DEFAULT_THICKNESS,
        })
    }

    // ----- solver hooks -----

    /// After the prediction: this substep's collider positions and hashes.
    pub(crate) fn prepare_mesh_collisions(&mut self) {
        if self.collide.meshes.is_empty() {
            return;
        }
        let t0 = Instant::now();
        let cloth = box_of(&self.x_start, &self.y);
        let c = &mut self.collide;
        let moving = c.any_collider_moving();
        let reach = if moving { reach_of(&self.x_start, &self.y, c.alphas_left.len() as f32) } else { cloth };
        let skips = c.skips;
        let (mut kept, mut culled) = (0, 0);
        let motion = ClothMotion { x_start: &self.x_start, y: &self.y, steps: c.alphas_left.len() as f32 };
        for m in &mut c.meshes {
            let out = m.prepare(
                &c.alphas_left,
                cloth,
                reach,
                !skips.reuse_collider_hashes,
                skips.cull_far_triangles,
                Some(&motion),
            );
            if out.rebuilt {
                c.stats.rebuilds += 1;
            } else {
                c.stats.reuses += 1;
            }
            kept += out.kept;
            culled += out.culled;
        }
        (c.stats.triangles_kept, c.stats.triangles_culled) = (kept, culled);
        // New positions for the colliders (or new culling): every particle is tested again.
        c.reuse.clear();
        c.reuse.resize(self.x.len(), Reuse::default());
        c.stats.hash_seconds += t0.elapsed().as_secs_f64();
    }

    /// The deepest mesh contact of every particle at the end of the substep:
    /// `(collider, contact)`, `None` for pinned or free particles. A particle whose motion
    /// since the substep's start passed through the front of a triangle gets that contact
    /// instead ([`MeshCollider::crossing`]): the side it came from, however deep it went.
    fn substep_end_mesh_contacts(&self) -> Vec<Option<(u32, crate::collision::Contact)>> {
        let (x, x0, meshes, levels, pinned, th) =
            (&self.x, &self.x_start, &self.collide.meshes, &self.collide.levels, &self.model.pinned, self.thickness);
        let (reuse, broad_phase, one) = (&self.collide.reuse, self.collide.skips.mesh_broad_phase, meshes.len() == 1);
        (0..x.len())
            .into_par_iter()
            .with_min_len(512)
            .map(|i| {
                if pinned[i] {
                    return None;
                }
                let p = x.get(i);
                let mut best: Option<(u32, crate::collision::Contact)> = None;
                let from = x0.get(i);
                for (c, m) in meshes.iter().enumerate() {
                    if let Some(hit) = m.crossing(from, p, levels[i], th) {
                        if best.as_ref().is_none_or(|(_, b)| hit.depth > b.depth) {
                            best = Some((c as u32, hit));
                        }
                    }
                }
                if best.is_some() {
                    return best;
                }
                // The colliders have not moved since the iterations: the broad phase's answer
                // (free, or the shortlist's) holds here as it did for them.
                let r = reuse.get(i).filter(|r| {
                    broad_phase && one && r.radius > 0.0 && p.distance_squared(Vec3::from(r.at)) < r.radius * r.radius
                });
                if let Some(r) = r {
                    if r.len == 0 {
                        return None;
                    }
                    if let Some(hit) = meshes[0].test_shortlist(p, &r.near[..r.len as usize], th) {
                        return hit.map(|h| (0, h));
                    }
                }
                for (c, m) in meshes.iter().enumerate() {
                    if let Some(hit) = m.contact(p, levels[i], th) {
                        if best.as_ref().is_none_or(|(_, b)| hit.depth > b.depth) {
                            best = Some((c as u32, hit));
                        }
                    }
                }
                best
            })
            .collect()
    }

    /// In the local step, after the analytic colliders: mesh contacts into the `ContactSet`
    /// (an analytic contact already found for a particle is kept), each particle tested by
    /// [`iteration_contact`] and its contact written in the same parallel loop (collecting
    /// the contacts first and writing them after on one thread cost a large share of the
    /// stage: a 64-byte answer a particle, every iteration).
    pub(crate) fn detect_mesh_contacts(&mut self) {
        if self.collide.meshes.is_empty() {
            return;
        }
        let t0 = Instant::now();
        let (x, diag, pinned, th) = (&self.x, &self.diag, &self.model.pinned, self.thickness);
        let c = &mut self.collide;
        let test = IterationTest {
            meshes: &c.meshes,
            one: c.meshes.len() == 1,
            broad_phase: c.skips.mesh_broad_phase,
            thickness: th,
            skipped: AtomicU64::new(0),
            listed: AtomicU64::new(0),
        };
        c.reuse.resize(x.len(), Reuse::default());
        let cs = &mut self.contacts;
        let (target, normal) = (&mut cs.target, &mut cs.normal);
        (
            c.reuse.par_iter_mut(),
            cs.weight.par_iter_mut(),
            cs.collider.par_iter_mut(),
            target.x.par_iter_mut(),
            target.y.par_iter_mut(),
            target.z.par_iter_mut(),
            normal.x.par_iter_mut(),
            normal.y.par_iter_mut(),
            normal.z.par_iter_mut(),
            c.contact_tri.par_iter_mut(),
            c.contact_bary.par_iter_mut(),
        )
            .into_par_iter()
            .enumerate()
            .with_min_len(512)
            .for_each(|(i, (r, w, col, tx, ty, tz, nx, ny, nz, tri, bary))| {
                let hit = if pinned[i] { None } else { test.contact(x.get(i), c.levels[i], r) };
                // An analytic contact found for this particle is kept.
                if *w > 0.0 && *col & MESH_CONTACT == 0 {
                    return;
                }
                match hit {
                    Some((k, h)) => {
                        *w = CONTACT_WEIGHT_FACTOR * diag[i];
                        (*tx, *ty, *tz) = (h.target.x, h.target.y, h.target.z);
                        (*nx, *ny, *nz) = (h.normal.x, h.normal.y, h.normal.z);
                        *col = MESH_CONTACT | k;
                        (*tri, *bary) = (h.triangle, h.bary);
                    }
                    None => {
                        *w = 0.0;
                        *col = u32::MAX;
                    }
                }
            });
        let (skipped, listed) = (test.skipped.into_inner(), test.listed.into_inner());
        c.stats.contact_skips += skipped;
        c.stats.contact_nearest += listed;
        c.stats.contact_tests += x.len() as u64 - skipped - listed;
        c.stats.contact_seconds += t0.elapsed().as_secs_f64();
    }

    /// After each iteration's global step: the self-collision pass, spheres or triangles.
    pub(crate) fn self_collide_iteration(&mut self) {
        let s = self.collide.self_settings;
        if !s.enabled {
            return;
        }
        let t0 = Instant::now();
        let radius = self.self_collision_radius();
        let c = &mut self.collide;
        let friction = c.friction.as_ref().map(|(a, b)| (a.as_slice(), b.as_slice()));
        let fr = move |i: usize| match friction {
            Some((a, b)) => (a[i], b[i]),
            None => (s.static_friction, s.kinetic_friction),
        };
        match s.contacts {
            SelfContacts::Spheres => {
                let cell = (self.model.mesh.mean_edge_length() as f32).max(2.0 * radius);
                let inp = PassInput {
                    model: &self.model,
                    levels: &c.levels,
                    x_start: &self.x_start,
                    radius,
                    cell,
                    friction: &fr,
                    reuse: c.skips.reuse_self_pairs,
                };
                c.self_state.pass(&inp, &mut self.x);
                c.stats.self_pairs = c.self_state.last_pairs;
                c.stats.self_searches += std::mem::take(&mut c.self_state.searches);
                c.stats.self_partial_searches += std::mem::take(&mut c.self_state.partial_searches);
            }
            SelfContacts::Triangles => {
                let inp = TrianglePassInput {
                    model: &self.model,
                    levels: &c.levels,
                    x_start: &self.x_start,
                    thickness: radius,
                    margin: radius.max(0.5 * self.model.mesh.mean_edge_length() as f32),
                    friction: &fr,
                    reuse: c.skips.reuse_self_pairs,
                };
                c.self_triangles.pass(&inp, &mut self.x);
                c.stats.self_pairs = c.self_triangles.last_contacts;
                c.stats.self_searches += std::mem::take(&mut c.self_triangles.searches);
                c.stats.self_partial_searches += std::mem::take(&mut c.self_triangles.partial_searches);
            }
        }
        c.stats.self_seconds += t0.elapsed().as_secs_f64();
    }

    /// At the end of the substep, before velocities: particles still behind a mesh collider go
    /// to their target (so no substep ends inside), then Coulomb friction acts on every mesh
    /// contact of the substep. A particle whose motion over the substep passed through the
    /// front of a triangle goes back out on that side, whatever its nearest surface now: a
    /// seam closing round a limb otherwise drags its edge through the limb (the samples'
    /// sleeves: up to 39 mm deep).
    ///
    /// Friction is applied to positions (Macklin et al. 2014, Eq. 24), on the particle's
    /// displacement over the substep relative to the triangle's (its velocity at the contact's
    /// barycentric point times `h`): the tangential part is removed when under `μs·d`, else
    /// shortened by `μk·d`, where `d` is the normal impulse divided by `m/h`: the larger of
    /// `(x − y)·n`, how far the contact pushed the particle out of its free-flight prediction,
    /// and the contact's own push against the cloth ([`Self::contact_pushes`]). This is
    /// Coulomb's law on the relative velocity `Δx/h`; doing it on velocities only would let a
    /// resting particle creep `g·h²·sin θ` per substep down a slope steeper than nothing.
    pub(crate) fn resolve_mesh_penetrations(&mut self, h: f32) {
        if self.collide.meshes.is_empty() {
            return;
        }
        let t0 = Instant::now();
        let found = self.substep_end_mesh_contacts();
        for (i, hit) in found.into_iter().enumerate() {
            if let Some((c, h)) = hit {
                if self.contacts.weight[i] > 0.0 && self.contacts.collider[i] & MESH_CONTACT == 0 {
                    continue;
                }
                self.x.set(i, h.target);
                self.contacts.normal.set(i, h.normal);
                self.contacts.collider[i] = MESH_CONTACT | c;
                self.collide.contact_tri[i] = h.triangle;
                self.collide.contact_bary[i] = h.bary;
            }
        }
        let mut contacts = 0;
        let mut corrected = Vec::new();
        for i in 0..self.x.len() {
            let c = self.contacts.collider[i];
            if c == u32::MAX || c & MESH_CONTACT == 0 {
                continue;
            }
            contacts += 1;
            corrected.push(i as u32);
            let m = &self.collide.meshes[(c & !MESH_CONTACT) as usize];
            let n = self.contacts.normal.get(i);
            let x = self.x.get(i);
            let d = (x - self.y.get(i)).dot(n).max(self.collide.pushes[i]);
            if d <= 0.0 {
                continue;
            }
            let vc = m.velocity_at(self.collide.contact_tri[i], self.collide.contact_bary[i]);
            let rel = x - self.x_start.get(i) - vc * h;
            let rel_t = rel - n * rel.dot(n);
            let lt = rel_t.length();
            let (mu_s, mu_k) = self.collide.particle_friction(i, (m.opts.static_friction, m.opts.kinetic_friction));
            if lt <= mu_s * d {
                self.x.set(i, x - rel_t);
            } else {
                self.x.set(i, x - rel_t * (mu_k * d / lt).min(1.0));
            }
        }
        self.keep_corrections_in_front(&corrected);
        self.collide.stats.mesh_contacts = contacts;
        self.collide.stats.resolve_seconds += t0.elapsed().as_secs_f64();
    }

    /// The normal push of each particle's contact over the substep as a displacement, m: the
    /// contact's force in the last local/global iteration, `w·((p − x)·n)` (its penalty weight
    /// times how far the solve left the particle behind its target), times `h²/m`. It is what
    /// the body pushes back against everything that presses the particle into it: gravity and
    /// inertia, and the cloth's own tension, as a waistband's round the hips or a shirt's over
    /// the shoulders. `(x − y)·n` alone (the contact's net effect on free flight) sees only
    /// the first: where tension presses the cloth on and the body holds it, the two cancel,
    /// and such contacts had no friction at all: the GarmentCode flared skirt's waistband slid
    /// over the hips under 1 N of skirt even at friction 2, and fell to the floor.
    /// Zero while the seams close (see there), and on sewn particles (`Model::sewn`):
    /// a seam's two sides are one line of the garment, and the body's grip on them held the
    /// last millimetres open against the seam (the sample skirt's waistband side seams 1.9 mm,
    /// the T-shirt's 2.6 mm at worst; 0.5 and 0.25 mm without it). The cloth round a seam
    /// still holds the garment.
    /// Fills `collide.pushes` (reused, no allocation once warm).
    pub(crate) fn contact_pushes(&mut self, h: f32) {
        let mut push = std::mem::take(&mut self.collide.pushes);
        push.clear();
        let closing = self.ramp_closing();
        let (cs, x, mass, sewn) = (&self.contacts, &self.x, &self.model.mass, &self.model.sewn);
        push.extend((0..x.len()).map(|i| {
            // While seams close their pull is an assembly force: what it presses onto the body
            // must slide there, as pieces slide into place over shoulders and hips.
            if closing || cs.weight[i] <= 0.0 || cs.collider[i] == u32::MAX || sewn[i] {
                return 0.0;
            }
            let behind = (cs.target.get(i) - x.get(i)).dot(cs.normal.get(i)).max(0.0);
            cs.weight[i] * behind * h * h / mass[i].max(f32::MIN_POSITIVE)
        }));
        self.collide.pushes = push;
    }

    /// A correction must not leave a particle behind a surface that its path from the
    /// substep's start crosses. The push out of a triangle goes along that triangle's normal,
    /// keeping the motion along it, and friction moves the particle in that triangle's plane;
    /// in a crease (the armpit, where the arm's underside faces the chest) either can land it
    /// behind the other side, where nothing sees it: the particle-vs-cell test finds it in
    /// front of that side's triangles in its cell, and the next substep starts inside.
    /// Such a particle stays where the substep began (its path from there crossed nothing
    /// when the substep began; the cloth's constraints move it on in the next one).
    fn keep_corrections_in_front(&mut self, corrected: &[u32]) {
        let (x0, meshes, levels, th) = (&self.x_start, &self.collide.meshes, &self.collide.levels, self.thickness);
        let x = &self.x;
        let back: Vec<u32> = corrected
            .par_iter()
            .with_min_len(256)
            .copied()
            .filter(|&i| {
                let (from, to) = (x0.get(i as usize), x.get(i as usize));
                meshes.iter().any(|m| m.crossing(from, to, levels[i as usize], th).is_some())
            })
            .collect();
        for i in back {
            self.x.set(i as usize, self.x_start.get(i as usize));
        }
    }
}

/// The iterations' test of a particle against the mesh colliders, with a broad phase that is
/// exact (`mesh_broad_phase.rs`): within a substep the colliders do not move, and a particle
/// that stayed within the radius its last test found is free without a test, or is tested
/// against its shortlist of nearest candidates alone. With several mesh colliders only the
/// first kind applies (the least radius over them). The contacts are exactly those of testing
/// every candidate of every particle in every iteration.
struct IterationTest<'a> {
    meshes: &'a [MeshCollider],
    one: bool,
    broad_phase: bool,
    thickness: f32,
    /// Tests skipped (free within the radius) and answered from a shortlist.
    skipped: AtomicU64,
    listed: AtomicU64,
}

impl IterationTest<'_> {
    /// The deepest contact of the particle at `p` (level `level`), `None` if free; `r` is what
    /// its last test in this substep left, updated by a full test.
    fn contact(&self, p: Vec3, level: i32, r: &mut Reuse) -> Option<(u32, crate::collision::Contact)> {
        let th = self.thickness;
        if self.broad_phase && r.radius > 0.0 && p.distance_squared(Vec3::from(r.at)) < r.radius * r.radius {
            if r.len == 0 {
                self.skipped.fetch_add(1, Relaxed);
                return None;
            }
            if let Some(hit) = self.meshes[0].test_shortlist(p, &r.near[..r.len as usize], th) {
                self.listed.fetch_add(1, Relaxed);
                return hit.map(|h| (0, h));
            }
        }
        let mut best: Option<(u32, crate::collision::Contact)> = None;
        let (mut radius, mut near) = (f32::INFINITY, Shortlist::FREE);
        for (k, m) in self.meshes.iter().enumerate() {
            let (hit, rad, list) = m.test_for_reuse(p, level, th, self.broad_phase);
            radius = radius.min(rad);
            if !list.is_free() {
                // A shortlist of one collider's triangles is a reuse for one collider only.
                (radius, near) = if self.one { (radius, list) } else { (0.0, Shortlist::FREE) };
            }
            if let Some(hit) = hit {
                if best.as_ref().is_none_or(|(_, b)| hit.depth > b.depth) {
                    best = Some((k as u32, hit));
                }
            }
        }
        *r = Reuse { at: p.into(), radius: radius - rounding_margin(p), near: near.near, len: near.len };
        best
    }
}
