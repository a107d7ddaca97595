//! The step: [`Simulation::step`] runs `settings.substeps` substeps, each walking
//! [`STAGES`] in order and timing each stage into [`StageTimings`]; the stages' own methods
//! (prediction, the local/global iterations, damping) follow in that order.

use std::time::Instant;

use glam::{Vec3, Vec3A};

use super::Simulation;
use crate::error::{Result, TailorError};
use crate::solver::collide::contacts::{coulomb, resolve_penetrations};
use crate::solver::collide::MESH_CONTACT;
use crate::solver::model::settings::Method;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::stages::coarse::{CoarseLevel, COARSE_CG_ITERATIONS};
use crate::solver::stages::damping::{decay, SeamGaps};
use crate::solver::stages::global::{unpack, unpack_extrapolated, GlobalSystem, SweepNorms};
use crate::solver::stages::local::project_all;
use crate::solver::stages::{Stage, StageTimings, STAGES};
use crate::solver::stats::StepStats;

/// Power-iteration sweeps that measure Chebyshev's spectral radius (see `stages/chebyshev.rs`).
const RHO_SWEEPS: u32 = 60;

/// Outcome of one substep's iterations.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct IterationOutcome {
    pub iterations: u32,
    pub residual: f32,
    pub rho: f32,
}

impl Simulation {
    /// Advances by `dt` seconds in `settings.substeps` substeps.
    pub fn step(&mut self, dt: f32) -> Result<StepStats> {
        self.step_observed(dt, |_, _| {})
    }

    /// [`step`](Self::step), calling `observe(k, self)` after each substep `k` (tests check
    /// invariants that must hold at every substep, not only at frame ends).
    pub fn step_observed(&mut self, dt: f32, mut observe: impl FnMut(u32, &Simulation)) -> Result<StepStats> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(TailorError::setting("dt", dt, "the time step must be positive and finite"));
        }
        let substeps = self.settings.substeps;
        let h = dt / substeps as f32;
        let mut stats = StepStats { substeps, ..Default::default() };
        if !std::mem::take(&mut self.collide.frame_begun) {
            self.collide.begin_frame(dt);
        }
        if self.collide.any_collider_moving() || self.seams_closing {
            self.sleep.wake();
        }
        if self.sleep.asleep {
            self.time += dt as f64;
            self.fill_stats(&mut stats);
            stats.contact_motion = self.contact_motion(&self.x);
            stats.asleep = true;
            return Ok(stats);
        }
        self.update_closing_holds()?;
        let backup = self.save_state();
        for k in 0..substeps {
            self.collide.set_substep(k, substeps);
            let (out, t) = self.substep(h);
            observe(k, self);
            stats.iterations += out.iterations;
            stats.residual = out.residual;
            stats.rho = out.rho;
            stats.timings.add(&t);
        }
        if !self.x.all_finite() || !self.v.all_finite() {
            self.restore_state(backup);
            return Err(TailorError::Diverged {
                reason: "positions became non-finite; the state was rolled back (lower the time step or \
                         stiffness, or raise substeps)"
                    .into(),
            });
        }
        stats.contact_motion = self.contact_motion(&backup.x);
        self.update_closing_holds()?;
        let quiet = !self.seams_closing && !self.collide.any_collider_moving();
        if self.sleep.after_step(self.v.max_length(), quiet) {
            self.v = Vec3Soa::zeros(self.num_particles());
        }
        self.fill_stats(&mut stats);
        Ok(stats)
    }

    /// Median distance from `start` of the particles touching a mesh collider now (`None`
    /// when none does).
    fn contact_motion(&self, start: &Vec3Soa) -> Option<f32> {
        let touching = |c: u32| c != u32::MAX && c & MESH_CONTACT != 0;
        let mut moved: Vec<f32> = (0..self.x.len())
            .filter(|&i| touching(self.contacts.collider[i]))
            .map(|i| self.x.get(i).distance(start.get(i)))
            .collect();
        if moved.is_empty() {
            return None;
        }
        let mid = moved.len() / 2;
        let (_, m, _) = moved.select_nth_unstable_by(mid, f32::total_cmp);
        Some(*m)
    }

    /// The end-of-step figures of `stats` that do not depend on the substeps.
    fn fill_stats(&mut self, stats: &mut StepStats) {
        let (gap, frac) = self.seam_gaps();
        stats.seam_gap_max = gap;
        stats.seam_closed_fraction = frac;
        stats.colours = self.model.colouring.count();
        stats.damping = self.ramp.damping(&self.settings);
        stats.ramp_phase = self.ramp.phase;
        stats.contacts = self.contacts.count();
        stats.collision = self.collide.take_stats();
    }

    /// Rebuilds derived structures and per-`h` quantities when needed.
    pub(crate) fn prepare(&mut self, h: f32) {
        let rebuilt = self.model.dirty;
        self.model.rebuild_if_dirty(self.settings.colouring_seed);
        if rebuilt || h != self.h_prepared {
            let inv_h2 = 1.0 / (h * h);
            let m = &self.model;
            self.diag = (0..m.n()).map(|i| m.mass[i] * inv_h2 + m.matrix32.diag[i]).collect();
            self.slots = vec![Vec3A::ZERO; m.slots.total];
            self.free = m.colouring.groups.iter().flatten().copied().collect();
            self.free.sort_unstable();
            // Not with self-collision: its pass moves particles outside the linear system, and the
            // coarse correction, seeing that as error, undid it (the layered outfit's walk: 11
            // particles 26 mm inside the body, 3007 crossing pairs against 0 and 1015).
            if !self.settings.two_level || self.collide.self_settings.enabled {
                self.coarse = None;
            } else {
                if rebuilt || self.coarse.is_none() {
                    self.coarse = Some(CoarseLevel::build(&self.model.matrix32, &self.free));
                }
                if let Some(c) = self.coarse.as_mut() {
                    c.set_values(&self.model.matrix32, &self.diag);
                }
            }
            let g2 = Vec3::from(self.settings.gravity).length_squared() as f64;
            self.weight_norm = self.free.iter().map(|&i| (m.mass[i as usize] as f64).powi(2) * g2).sum::<f64>().sqrt();
            self.h_prepared = h;
            if self.settings.method == Method::Chebyshev && self.settings.chebyshev.rho.is_none() {
                let m = &self.model;
                self.cheb.rho_gs = Some(crate::solver::stages::chebyshev::spectral_radius_gs(
                    &m.matrix32,
                    &self.diag,
                    &m.colouring.groups,
                    RHO_SWEEPS,
                ));
            }
        }
    }

    /// Advances the seams' closing schedule: what is left of each pair's schedule shrinks, the
    /// widest pair's (by its gap when it was sewn) by `closing_speed·h`, every other's by its
    /// share of that, so that all pairs' schedules run out together; a pair's rest length is
    /// what is left of its schedule, never above its current gap (a pair that closed faster is
    /// not pushed apart). See `SeamRamp::closing_speed` for why all at once. The schedule runs
    /// on time alone: shrinking the rest length from the current gap instead never ran out for
    /// a short pair held a fraction of a millimetre open, whose share of the step is tiny, so
    /// the garment counted as still closing (and stayed off the GPU) for good.
    fn close_seams(&mut self, h: f32) {
        let speed = if self.settings.ramp.enabled { self.settings.ramp.closing_speed } else { f32::INFINITY };
        let (pairs, gap0, left) = (&mut self.model.seam_pairs, &self.closing_gap0, &mut self.closing_left);
        let widest = (0..left.len()).filter(|&s| left[s] > 0.0).map(|s| gap0[s]).fold(f32::MIN_POSITIVE, f32::max);
        let mut open = false;
        for s in 0..left.len() {
            if left[s] > 0.0 {
                left[s] = (left[s] - speed * h * (gap0[s] / widest)).max(0.0);
                pairs.rest[s] = left[s].min(pairs.vector(s, &self.x).length());
                open |= left[s] > 0.0;
            }
        }
        self.seams_closing = open;
    }

    /// Prediction stage: `y`, pins, initial guess, fixed right-hand side.
    pub(crate) fn predict(&mut self, h: f32) {
        if self.seams_closing {
            self.close_seams(h);
        }
        let g = Vec3::from(self.settings.gravity) * self.gravity_scale();
        let inv_h2 = 1.0 / (h * h);
        self.x_start.copy_from(&self.x);
        for i in 0..self.num_particles() {
            let y = if self.model.pinned[i] {
                self.pin_target.get(i)
            } else {
                self.x.get(i) + self.v.get(i) * h + g * (h * h)
            };
            self.y.set(i, y);
            self.x.set(i, y);
            let r = y * (self.model.mass[i] * inv_h2) + self.model.b_const.get(i);
            self.rhs_fixed.set(i, r);
        }
        self.apply_collider_attachments();
    }

    fn global_system(&self) -> GlobalSystem<'_> {
        GlobalSystem {
            matrix: &self.model.matrix32,
            diag: &self.diag,
            rhs_fixed: &self.rhs_fixed,
            slots: &self.slots,
            slot_offsets: &self.model.slots.particle_offsets,
            slot_index: &self.model.slots.particle_slots,
            sweep: &self.model.sweep,
            contact_weight: &self.contacts.weight,
            contact_target: &self.contacts.target,
        }
    }

    /// Local/global iterations of one substep. `detect` re-detects contacts every iteration;
    /// `observe(k, x)` is called after each iteration (used by the error measures).
    pub(crate) fn iterate(
        &mut self,
        method: Method,
        max_iterations: u32,
        tolerance: f32,
        detect: bool,
        timings: &mut StageTimings,
        mut observe: impl FnMut(u32, &Vec3Soa),
    ) -> IterationOutcome {
        self.cheb.begin_substep();
        self.x_prev_iter.copy_from(&self.x);
        let mut out = IterationOutcome::default();
        let mut r0 = 0.0f64;
        for k in 0..max_iterations {
            let t0 = Instant::now();
            if detect {
                self.detect_contacts_now();
            }
            let mut slots = std::mem::take(&mut self.slots);
            project_all(&self.model, &self.x, &mut slots);
            self.slots = slots;
            let t1 = Instant::now();
            let norms: SweepNorms = match method {
                Method::Jacobi => {
                    if self.x_this_iter.len() != self.x.len() {
                        self.x_this_iter = self.x.clone();
                    }
                    self.x_this_iter.copy_from(&self.x);
                    let mut x = std::mem::take(&mut self.x);
                    let n = self.global_system().jacobi(
                        &self.free,
                        &self.x_this_iter,
                        &mut x,
                        self.settings.jacobi_relaxation,
                    );
                    self.x = x;
                    n
                }
                Method::GaussSeidel | Method::Chebyshev => {
                    // The sweep leaves x̂ in `sweep_work` and `self.x` (= xᵏ) untouched.
                    let (mut work, mut parts) =
                        (std::mem::take(&mut self.sweep_work), std::mem::take(&mut self.sweep_parts));
                    let n = self.global_system().gauss_seidel(&self.x, &mut work, &mut parts);
                    (self.sweep_work, self.sweep_parts) = (work, parts);
                    if method == Method::Chebyshev {
                        let omega =
                            self.cheb.omega(k, max_iterations, n.update2.sqrt() as f32, &self.settings.chebyshev);
                        out.rho = self.cheb.rho(&self.settings.chebyshev);
                        // xᵏ⁺¹ = ω·(x̂ − xᵏ⁻¹) + xᵏ⁻¹ (just x̂ when ω = 1) overwrites xᵏ⁻¹; the swap
                        // then makes it the iterate and keeps xᵏ as the next "previous".
                        if omega != 1.0 {
                            unpack_extrapolated(&self.sweep_work, &mut self.x_prev_iter, omega);
                        } else {
                            unpack(&self.sweep_work, &mut self.x_prev_iter);
                        }
                        std::mem::swap(&mut self.x, &mut self.x_prev_iter);
                    } else {
                        unpack(&self.sweep_work, &mut self.x);
                    }
                    n
                }
            };
            if let Some(mut c) = self.coarse.take() {
                let mut x = std::mem::take(&mut self.x);
                c.correct(&self.global_system(), &mut x, COARSE_CG_ITERATIONS);
                self.x = x;
                self.coarse = Some(c);
            }
            if detect {
                self.self_collide_iteration();
            }
            timings[Stage::Local] += (t1 - t0).as_secs_f64();
            timings[Stage::Global] += t1.elapsed().as_secs_f64();
            if k == 0 {
                r0 = norms.residual2.sqrt().max(1e-30);
            }
            out.iterations = k + 1;
            out.residual = (norms.residual2.sqrt() / r0) as f32;
            observe(k, &self.x);
            // Relative to the larger of the first residual and the cloth's weight: a step that
            // starts nearly solved (a cloth at rest) stops once the force left is a small
            // fraction of its weight, instead of chasing a relative reduction of a tiny start.
            if tolerance > 0.0 && k > 0 && norms.residual2.sqrt() < tolerance as f64 * r0.max(self.weight_norm) {
                break;
            }
        }
        out
    }

    /// One substep of length `h`: the stages of [`STAGES`], in order.
    fn substep(&mut self, h: f32) -> (IterationOutcome, StageTimings) {
        let mut t = StageTimings::default();
        let mut out = IterationOutcome::default();
        for stage in STAGES {
            match stage {
                Stage::Prediction => {
                    let t0 = Instant::now();
                    self.prepare(h);
                    self.predict(h);
                    self.prepare_mesh_collisions();
                    // Triangle self-contacts take their sides from this substep's start.
                    self.collide.self_triangles.begin_substep();
                    t[stage] = t0.elapsed().as_secs_f64();
                }
                // The iterations alternate the local and the global stage (`iterate` times each).
                Stage::Local => {
                    let (method, iters, tol) =
                        (self.settings.method, self.settings.iterations, self.settings.tolerance);
                    out = self.iterate(method, iters, tol, true, &mut t, |_, _| {});
                }
                Stage::Global => {}
                Stage::Damping => {
                    let t0 = Instant::now();
                    self.finish_substep(h);
                    t[stage] = t0.elapsed().as_secs_f64();
                }
            }
        }
        (out, t)
    }

    /// Damping stage: penetrations, velocities, friction, air damping, ramp.
    fn finish_substep(&mut self, h: f32) {
        // The contacts' pushes as the iterations left them, before any is resolved.
        self.contact_pushes(h);
        self.resolve_mesh_penetrations(h);
        if !self.colliders.is_empty() {
            resolve_penetrations(&self.colliders, self.thickness, &mut self.x, &self.model.pinned);
        }
        let inv_h = 1.0 / h;
        let damping = decay(self.ramp.damping(&self.settings), h);
        for i in 0..self.num_particles() {
            let mut v = (self.x.get(i) - self.x_start.get(i)) * inv_h;
            let c = self.contacts.collider[i];
            // Mesh contacts had their friction in `resolve_mesh_penetrations`.
            if c != u32::MAX && c & MESH_CONTACT == 0 {
                let col = &self.colliders[c as usize];
                let n = self.contacts.normal.get(i);
                let v_pred = (self.y.get(i) - self.x_start.get(i)) * inv_h;
                let dvn = (v - v_pred).dot(n).max(self.collide.pushes[i] * inv_h).max(0.0);
                v = coulomb(v, n, dvn, col.static_friction, col.kinetic_friction);
            }
            self.v.set(i, v * damping);
        }
        let (widest, frac) = self.seam_gaps();
        let gaps = SeamGaps { widest, closed_fraction: frac, scheduled: !self.seams_closing };
        self.ramp.advance(&self.settings, gaps, !self.model.seam_pairs.is_empty(), h);
        self.time += h as f64;
    }
}
