//! A read-only view of a prepared simulation for other backends (the GPU solver uploads from
//! it), and the narrow write-back they need to hand their state back to the CPU.
//!
//! Kept apart from the step (`step.rs`) so that the CPU step does not grow backend concerns.

use crate::solver::collide::contacts::ImplicitCollider;
use crate::solver::model::settings::SolverSettings;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::Model;
use crate::solver::simulation::Simulation;
use crate::solver::stages::damping::Ramp;

/// Everything a backend needs to run the same substeps as [`Simulation::step`].
pub struct SolverView<'a> {
    pub model: &'a Model,
    pub settings: &'a SolverSettings,
    pub x: &'a Vec3Soa,
    pub v: &'a Vec3Soa,
    pub pin_target: &'a Vec3Soa,
    /// `Dᵢ = mᵢ/h² + Lᵢᵢ` for the substep length the view was prepared for.
    pub diag: &'a [f32],
    /// The substep length the derived data was prepared for, seconds.
    pub h: f32,
    /// The Chebyshev radius the CPU would use (0 when not accelerating).
    pub rho: f32,
    /// The seam-closing ramp's state machine (phase and stall watch).
    pub ramp: &'a Ramp,
    /// Some seam pair still has closing schedule left ([`Simulation::seams_closing`]).
    pub seams_closing: bool,
    /// Each seam pair's gap when sewn and schedule left, m (shorter than the pairs when
    /// some were sewn without a schedule: those have none).
    pub closing_gap0: &'a [f32],
    pub closing_left: &'a [f32],
    pub colliders: &'a [ImplicitCollider],
    /// Collision thickness, metres.
    pub thickness: f32,
    /// Mesh colliders, levels, friction and self-collision settings.
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub(crate) collide: &'a crate::solver::collide::Collisions,
    /// Self-collision sphere radius and hash cell side in effect, metres.
    pub self_radius: f32,
    pub self_cell: f32,
    /// The two-level step's coarse grid, when it runs (two-level on, self-collision off).
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub(crate) coarse: Option<&'a crate::solver::stages::coarse::CoarseLevel>,
}

impl Simulation {
    /// Prepares the derived data for substeps of `h` seconds (matrix, colouring, diagonal,
    /// Chebyshev's measured radius: exactly what the CPU step would use) and exposes it.
    pub fn gpu_view(&mut self, h: f32) -> SolverView<'_> {
        self.prepare(h);
        let self_radius = self.self_collision_radius();
        let self_cell = (self.model.mesh.mean_edge_length() as f32).max(2.0 * self_radius);
        let rho = match self.settings.method {
            crate::solver::model::settings::Method::Chebyshev => self.cheb.rho(&self.settings.chebyshev),
            _ => 0.0,
        };
        SolverView {
            model: &self.model,
            settings: &self.settings,
            x: &self.x,
            v: &self.v,
            pin_target: &self.pin_target,
            diag: &self.diag,
            h: self.h_prepared,
            rho,
            ramp: &self.ramp,
            seams_closing: self.seams_closing,
            closing_gap0: &self.closing_gap0,
            closing_left: &self.closing_left,
            colliders: &self.colliders,
            thickness: self.thickness,
            collide: &self.collide,
            self_radius,
            self_cell,
            coarse: self.coarse.as_ref(),
        }
    }

    /// Takes back the state another backend computed (positions already checked finite by
    /// the caller) and advances the clock as the CPU step would have.
    #[cfg(feature = "gpu")]
    pub(crate) fn accept_backend_state(&mut self, back: BackendState<'_>) {
        if let Some(x) = back.x {
            for (i, p) in x.iter().enumerate() {
                self.x.set(i, glam::Vec3::new(p[0], p[1], p[2]));
            }
        }
        self.ramp = back.ramp;
        if let Some(seams) = back.seams {
            self.seams_closing = seams.closing;
            let pairs = &mut self.model.seam_pairs;
            for (s, &(left, rest)) in seams.pairs.iter().enumerate().take(self.closing_left.len()) {
                self.closing_left[s] = left;
                pairs.rest[s] = rest;
            }
        }
        self.time += back.elapsed;
    }

    /// Whether the next step has nothing to solve (the cloth is asleep and nothing drives it),
    /// for another backend, which lets the CPU take such a step (it only advances the clock).
    #[cfg(feature = "gpu")]
    pub(crate) fn backend_asleep(&mut self) -> bool {
        if self.collide.any_collider_moving() || self.seams_closing {
            self.sleep.wake();
        }
        self.sleep.asleep
    }

    /// After another backend's step whose fastest particle ends at `max_speed`: the CPU's
    /// sleep test (`sleep.rs`). Returns whether the cloth fell asleep (velocities zeroed).
    #[cfg(feature = "gpu")]
    pub(crate) fn backend_after_step(&mut self, max_speed: f32) -> bool {
        let quiet = !self.seams_closing && !self.collide.any_collider_moving();
        let asleep = self.sleep.after_step(max_speed, quiet);
        if asleep {
            self.v = crate::solver::model::soa::Vec3Soa::zeros(self.num_particles());
        }
        asleep
    }

    /// Begins a frame of `dt` seconds for the mesh colliders on behalf of another backend
    /// (the positions given since the last frame become the frame's end); if that backend
    /// then hands the frame to the CPU, the CPU step does not begin it again.
    #[cfg(feature = "gpu")]
    pub(crate) fn begin_backend_frame(&mut self, dt: f32) {
        self.collide.begin_frame(dt);
        self.collide.frame_begun = true;
    }

    /// The other backend finished the frame: colliders at their frame-end positions.
    #[cfg(feature = "gpu")]
    pub(crate) fn end_backend_frame(&mut self) {
        self.collide.frame_begun = false;
        self.collide.end_frame_elsewhere();
    }

    /// Takes back velocities computed elsewhere.
    #[cfg(feature = "gpu")]
    pub(crate) fn accept_backend_velocities(&mut self, v: &[[f32; 4]]) {
        for (i, p) in v.iter().enumerate() {
            self.v.set(i, glam::Vec3::new(p[0], p[1], p[2]));
        }
    }
}

/// What another backend hands back after its frame (see [`Simulation::accept_backend_state`]).
#[cfg(feature = "gpu")]
pub(crate) struct BackendState<'a> {
    /// Positions (xyz of each vec4), when they changed.
    pub x: Option<&'a [[f32; 4]]>,
    pub ramp: Ramp,
    /// Seconds the frame advanced.
    pub elapsed: f64,
    /// The seams' closing schedule, when the frame ran it.
    pub seams: Option<SeamClosing<'a>>,
}

/// The seams' closing schedule after another backend's frame.
#[cfg(feature = "gpu")]
pub(crate) struct SeamClosing<'a> {
    /// Some pair still has schedule left.
    pub closing: bool,
    /// Per pair: the schedule left and the rest length, m.
    pub pairs: &'a [(f32, f32)],
}
