//! One GPU frame: the closing holds brought up to date, an upload when the model changed, the
//! colliders' positions for the frame, every substep's dispatches (`plan.rs`) in one compute
//! pass with per-stage timestamps when on, one readback of positions, the step state and the
//! seams' closing schedule, and the state handed back to the simulation.

use std::time::Instant;

use super::buffers::{STATE_BYTES, VEC4};
use super::common::StepState;
use super::{close_seams, map_read, phase_from_gpu, plan, timing, GpuFailure, GpuSolver};
use crate::error::TailorError;
use crate::solver::model::settings::Method;
use crate::solver::simulation::view::{BackendState, SeamClosing};
use crate::solver::stages::damping::Ramp;
use crate::solver::{ActiveBackend, CollisionStats, Simulation, StepStats};

impl GpuSolver {
    /// Advances `sim` by `dt` on the GPU; afterwards `sim`'s positions, ramp and clock are
    /// current (its velocities only after [`GpuSolver::sync_velocities`]). On divergence the
    /// GPU state is rolled back and [`GpuFailure::Step`] returned, as the CPU step does.
    pub fn step(&mut self, sim: &mut Simulation, dt: f32) -> Result<StepStats, GpuFailure> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(GpuFailure::Step(TailorError::setting("dt", dt, "the time step must be positive and finite")));
        }
        let t0 = Instant::now();
        let substeps = sim.settings().substeps;
        let iterations = sim.settings().iterations;
        let h = dt / substeps as f32;
        // The body's holds of the closing phase come or go (an edit of the model, as on the
        // CPU at the start of its step): the GPU's velocities come down first, then the
        // model goes up again.
        self.update_closing_holds(sim)?;
        let stale = self.uploaded.as_ref().is_none_or(|u| u.h != h || u.method != sim.settings().method);
        let mut upload = self.dirty || stale;
        if upload {
            if !self.dirty {
                // A new substep length re-uploads from the CPU copy: bring its velocities up
                // to date first (the GPU's are the current ones).
                self.sync_velocities(sim)?;
            }
            // Refuse before the colliders' frame begins, so the CPU runs the whole frame.
            if let Some(why) = Self::unsupported(&sim.gpu_view(h)) {
                self.dirty = true;
                return Err(GpuFailure::Unsupported(why));
            }
        }
        // The positions given since the last frame become this frame's end; from here on a
        // failure hands the begun frame to the CPU (`Simulation::step` does not begin it again).
        sim.begin_backend_frame(dt);
        let meshes = &sim.collide.meshes;
        let moving = meshes.iter().any(|m| m.moving);
        if !upload && moving {
            let cap = self.buffers.as_ref().map_or(0, |b| b.caps.mesh_entries);
            if Self::mesh_entry_bound(meshes) > cap {
                // The colliders deformed beyond the hash's capacity: re-upload with room.
                self.sync_velocities(sim)?;
                upload = true;
            }
        }
        if upload {
            let view = sim.gpu_view(h);
            let ctx = self.ctx.clone();
            let (r, invalid) = ctx.validated(|| self.upload(&view));
            if let Some(e) = invalid {
                self.dirty = true;
                return Err(GpuFailure::Device(e));
            }
            if r.is_err() {
                self.dirty = true;
            }
            r?;
        }
        let stage_timed = self.timestamps();
        let (Some(b), Some(g), Some(u)) = (&self.buffers, &self.binds, &mut self.uploaded) else {
            return Err(GpuFailure::Device("nothing uploaded".into()));
        };
        if u.n_meshes > 0 {
            // Collider positions go up once per frame (only for colliders that move), with
            // the per-frame uniform; the GPU interpolates them per substep.
            let nv = u.n_mesh_verts as u64;
            for (c, m) in sim.collide.meshes.iter().enumerate() {
                u.meshes.m[c].moving = m.moving as u32;
                if m.moving && !upload {
                    let next: Vec<[f32; 4]> = m.next.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect();
                    let off = (nv + u.mesh_vert_off[c] as u64) * VEC4;
                    self.ctx.queue.write_buffer(&b.mverts, off, bytemuck::cast_slice(&next));
                }
            }
            u.meshes.inv_dt = 1.0 / dt;
            self.ctx.queue.write_buffer(&b.meshes, 0, bytemuck::bytes_of(&u.meshes));
        }
        // Build the colliders' hash every substep while one moves, else once after an upload.
        let rebuild_each_substep = u.n_meshes > 0 && moving;
        let rebuild_first = u.n_meshes > 0 && !self.mesh_hash_valid;
        let rebuilds = if rebuild_each_substep { substeps } else { rebuild_first as u32 };
        let n = u.n;
        let accelerate = u.method == Method::Chebyshev;
        if stage_timed && self.timing.is_none() {
            self.timing = Some(timing::Timing::new(&self.ctx.device));
        }
        let pl = &self.ctx.pipelines;
        // The frame's iteration count (the early stop may run fewer) and its top speed start at zero.
        let at = std::mem::offset_of!(StepState, iterations_run) as u64;
        self.ctx.queue.write_buffer(&b.state, at, bytemuck::bytes_of(&[0u32; 2]));
        let plan = plan::frame(pl, g, u, substeps, iterations, rebuild_each_substep, rebuild_first);
        let dispatches = plan.len();
        // Per-stage times where the device writes timestamps inside passes (and the frame's
        // marks fit one query set).
        let marks = match (stage_timed, self.kernel_timing) {
            (true, true) => plan::kernel_marks(&plan),
            (true, false) => plan::stage_marks(&plan),
            (false, _) => Vec::new(),
        };
        let mark_kernels: Vec<&'static str> = marks.iter().map(|&(k, _)| plan[k].kernel).collect();
        let timed = self.timing.as_ref().filter(|_| !marks.is_empty() && marks.len() < timing::MAX_QUERIES as usize);
        let mut enc = self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let xbytes = n as u64 * VEC4;
        enc.copy_buffer_to_buffer(&b.x, 0, &b.x_backup, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.v, 0, &b.v_backup, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state, 0, &b.state_backup, 0, STATE_BYTES);
        {
            // One pass for the whole frame: wgpu orders successive dispatches that share
            // storage buffers, so colours and stages see each other's writes.
            let mut pass = enc
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("substeps"), timestamp_writes: None });
            if let Some(t) = timed {
                pass.write_timestamp(&t.set, 0);
            }
            let mut next_mark = marks.iter().map(|&(k, _)| k).enumerate().peekable();
            for (k, d) in plan.iter().enumerate() {
                pass.set_pipeline(d.pipeline);
                pass.set_bind_group(0, d.bind, &[]);
                pass.dispatch_workgroups(d.groups, 1, 1);
                if let (Some(t), Some(&(m, at))) = (timed, next_mark.peek()) {
                    if at == k {
                        pass.write_timestamp(&t.set, m as u32 + 1);
                        next_mark.next();
                    }
                }
            }
        }
        if let Some(t) = timed {
            let count = marks.len() as u32 + 1;
            enc.resolve_query_set(&t.set, 0..count, &t.resolve, 0);
            enc.copy_buffer_to_buffer(&t.resolve, 0, &t.read, 0, count as u64 * 8);
        }
        enc.copy_buffer_to_buffer(&b.x, 0, &b.readback, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state, 0, &b.readback, xbytes, STATE_BYTES);
        // While seams close, their schedule comes back too (the CPU takes over from it).
        let pair_bytes = if u.closing_scheduled { u.n_seam_pairs as u64 * VEC4 } else { 0 };
        if pair_bytes > 0 {
            enc.copy_buffer_to_buffer(&b.closing, 0, &b.readback, xbytes + STATE_BYTES, pair_bytes);
        }
        let (n_colours, rho, n_tris_total) = (u.colours.len(), u.rho, u.n_mesh_tris);
        let has_meshes = u.n_meshes > 0;
        self.ctx.queue.submit([enc.finish()]);
        let bytes = self.read(xbytes + STATE_BYTES + pair_bytes)?;
        let stage_times = match timed {
            Some(t) => {
                let ticks = map_read(&self.ctx.device, &t.read, (marks.len() as u64 + 1) * 8)?;
                let ticks: &[u64] = bytemuck::cast_slice(&ticks);
                if self.kernel_timing {
                    self.kernel_times = timing::kernel_times(&mark_kernels, ticks, self.ctx.timestamp_period);
                }
                Some(timing::stage_times(&marks, ticks, self.ctx.timestamp_period))
            }
            None => None,
        };
        let (xs, rest) = bytes.split_at(xbytes as usize);
        let (st, pairs) = rest.split_at(STATE_BYTES as usize);
        let x: &[[f32; 4]] = bytemuck::cast_slice(xs);
        let state: StepState = *bytemuck::from_bytes(st);
        let pairs: Vec<(f32, f32)> =
            bytemuck::cast_slice::<u8, close_seams::PairState>(pairs).iter().map(|p| (p[1], p[3])).collect();
        if has_meshes {
            self.mesh_hash_valid = true;
        }
        // As on the CPU, the colliders' frame has happened whatever the outcome below.
        sim.end_backend_frame();
        if x.iter().any(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite())) {
            self.restore_backup(xbytes)?;
            return Err(GpuFailure::Step(TailorError::Diverged {
                reason: "positions became non-finite on the GPU; the state was rolled back (lower the time step or \
                         stiffness, or raise substeps)"
                    .into(),
            }));
        }
        let phase = phase_from_gpu(state.phase, state.elapsed);
        let stall = (state.stall_on != 0).then_some((state.stall_best, state.stall_since));
        sim.accept_backend_state(BackendState {
            x: Some(x),
            ramp: Ramp { phase, stall },
            elapsed: h as f64 * substeps as f64,
            seams: (pair_bytes > 0).then_some(SeamClosing { closing: state.closing != 0, pairs: &pairs }),
        });
        if sim.backend_after_step(f32::from_bits(state.max_speed_bits)) {
            // Fallen asleep: the CPU zeroed the velocities; the GPU takes them from there when
            // the cloth wakes.
            self.dirty = true;
        }
        // As the CPU at the end of its step: the holds go once the seams have met.
        self.update_closing_holds(sim)?;
        let mut stats = StepStats {
            substeps,
            iterations: state.iterations_run,
            residual: state.residual,
            colours: n_colours,
            rho: if accelerate { rho } else { 0.0 },
            damping: Ramp { phase, stall: None }.damping(sim.settings()),
            ramp_phase: phase,
            seam_gap_max: state.gap_max,
            seam_closed_fraction: state.closed_fraction,
            contacts: state.contacts as usize,
            collision: CollisionStats {
                rebuilds,
                reuses: if n_tris_total > 0 { substeps - rebuilds } else { 0 },
                triangles_kept: n_tris_total,
                mesh_contacts: state.mesh_contacts as usize,
                self_pairs: state.self_pairs as usize,
                ..Default::default()
            },
            backend: ActiveBackend::Gpu,
            warning: None,
            dispatches,
            ..Default::default()
        };
        match stage_times {
            // The GPU's own time per stage (timestamps); upload and readback are outside them.
            Some(t) => stats.timings = t,
            // Without timestamps the whole frame, upload and readback included, is reported as
            // the global stage.
            None => stats.timings[crate::solver::Stage::Global] = t0.elapsed().as_secs_f64(),
        }
        Ok(stats)
    }

    /// Places or releases the body's holds of the closing phase when due
    /// (`Simulation::update_closing_holds`): the velocities come down first (the GPU's are the
    /// current ones) and the edited model goes up before the next frame.
    fn update_closing_holds(&mut self, sim: &mut Simulation) -> Result<(), GpuFailure> {
        if !sim.closing_holds_due() {
            return Ok(());
        }
        self.sync_velocities(sim)?;
        sim.update_closing_holds().map_err(GpuFailure::Step)?;
        self.dirty = true;
        Ok(())
    }

    /// Copies the backups of x, v and the state back (after a diverged frame).
    fn restore_backup(&mut self, xbytes: u64) -> Result<(), GpuFailure> {
        let b = self.buffers.as_ref().ok_or_else(|| GpuFailure::Device("buffers missing".into()))?;
        let mut enc =
            self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("rollback") });
        enc.copy_buffer_to_buffer(&b.x_backup, 0, &b.x, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.v_backup, 0, &b.v, 0, xbytes);
        enc.copy_buffer_to_buffer(&b.state_backup, 0, &b.state, 0, STATE_BYTES);
        self.ctx.queue.submit([enc.finish()]);
        self.wait()
    }
}
