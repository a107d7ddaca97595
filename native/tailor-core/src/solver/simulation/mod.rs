//! A running simulation: the model, the moving state, and the step.
//!
//! Each substep of length `h` walks [`STAGES`] in order, each stage timed into
//! [`StageTimings`] (the table of what each runs is in [`stages`](crate::solver::stages)):
//!
//! 1. **prediction**: `y = x + h·v + h²·g`, pinned particles at their targets, the initial
//!    guess `x = y`, and the fixed right-hand side `M/h²·y + b_const` plus the attachments
//!    riding on mesh colliders (targets of this substep, [`attach`]);
//! 2. per iteration, **local**: contacts against colliders and constraint projections;
//!    **global**: one Gauss-Seidel sweep over the colouring (or Jacobi), then Chebyshev
//!    extrapolation; optional early stop on the relative residual;
//! 3. **damping**: remaining penetrations resolved, `v = (x − x₀)/h`, Coulomb friction on
//!    contacts, air damping `exp(−c·h)` with `c` from the seam-closing ramp.
//!
//! A step whose result is not finite is rolled back and reported as an error.
//!
//! The simulation's methods are split by concern over this folder: this file holds the state
//! and the calls that edit it, [`step`] the step and its stages, collisions ([`colliders`],
//! [`attach`], [`closing_hold`]), quality ([`metrics`]) and the read-only view other backends
//! upload from ([`view`]). They are the only modules that use the solver's parts together;
//! the parts (`model/`, `stages/`, `collide/`) never import the simulation.

mod attach;
mod closing_hold;
mod colliders;
mod fit_maps;
mod metrics;
mod step;
pub(crate) mod view;

use glam::{Vec3, Vec3A};

use crate::error::{Result, TailorError};
use crate::mesh::{check_finite3, ClothMesh};
use crate::solver::collide::contacts::{ContactSet, ImplicitCollider};
use crate::solver::collide::Collisions;
use crate::solver::model::constraints::{Attachment, Seam};
use crate::solver::model::settings::{Fabric, SolverSettings};
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::Model;
use crate::solver::sleep::Sleep;
use crate::solver::stages::chebyshev::Chebyshev;
use crate::solver::stages::damping::Ramp;
use crate::solver::stages::global::SweepNorms;

/// A cloth simulation.
pub struct Simulation {
    pub(crate) model: Model,
    pub(crate) settings: SolverSettings,
    pub(crate) colliders: Vec<ImplicitCollider>,
    pub(crate) thickness: f32,
    pub(crate) x: Vec3Soa,
    pub(crate) v: Vec3Soa,
    pub(crate) x_start: Vec3Soa,
    pub(crate) y: Vec3Soa,
    x_prev_iter: Vec3Soa,
    x_this_iter: Vec3Soa,
    pub(crate) rhs_fixed: Vec3Soa,
    pub(crate) diag: Vec<f32>,
    pub(crate) slots: Vec<Vec3A>,
    /// Scratch of the Gauss-Seidel sweep: interleaved positions and per-chunk sums.
    sweep_work: Vec<Vec3A>,
    sweep_parts: Vec<SweepNorms>,
    pub(crate) contacts: ContactSet,
    /// Mesh colliders and self-collision (`collide/`).
    pub(crate) collide: Collisions,
    pub(crate) pin_target: Vec3Soa,
    pub(crate) ramp: Ramp,
    pub(crate) cheb: Chebyshev,
    pub(crate) free: Vec<u32>,
    /// The two-level global step's coarse grid (`stages/coarse.rs`), when it is on.
    pub(crate) coarse: Option<crate::solver::stages::coarse::CoarseLevel>,
    pub(crate) h_prepared: f32,
    /// Some seam pair still has a non-zero closing rest length.
    seams_closing: bool,
    /// Each seam pair's closing schedule, m: its gap when it was added, and what is left of
    /// it (the pair's rest length is never above this; 0 when the pair's schedule is done).
    closing_gap0: Vec<f32>,
    closing_left: Vec<f32>,
    pub(crate) sleep: Sleep,
    /// `‖M·g‖` over the free particles, N: the force scale of the early-termination test.
    weight_norm: f64,
    pub(crate) time: f64,
}

/// A snapshot of the moving state.
pub(crate) struct SavedState {
    x: Vec3Soa,
    v: Vec3Soa,
    ramp: Ramp,
    time: f64,
}

impl Simulation {
    /// Creates a simulation of `mesh` made of `fabric`.
    pub fn new(mesh: ClothMesh, fabric: Fabric, settings: SolverSettings) -> Result<Self> {
        settings.validate()?;
        let x = Vec3Soa::from_aos(mesh.positions());
        let n = x.len();
        let model = Model::new(mesh, fabric)?;
        let mut contacts = ContactSet::default();
        contacts.resize(n);
        Ok(Self {
            model,
            settings,
            colliders: Vec::new(),
            thickness: crate::solver::model::settings::DEFAULT_THICKNESS,
            v: Vec3Soa::zeros(n),
            x_start: x.clone(),
            y: x.clone(),
            x_prev_iter: x.clone(),
            // Only Jacobi needs it: allocated on first use.
            x_this_iter: Vec3Soa::default(),
            rhs_fixed: Vec3Soa::zeros(n),
            diag: vec![0.0; n],
            slots: Vec::new(),
            sweep_work: Vec::new(),
            sweep_parts: Vec::new(),
            contacts,
            collide: Collisions::new(n),
            pin_target: x.clone(),
            x,
            ramp: Ramp::default(),
            cheb: Chebyshev::default(),
            free: Vec::new(),
            coarse: None,
            h_prepared: 0.0,
            seams_closing: false,
            closing_gap0: Vec::new(),
            closing_left: Vec::new(),
            sleep: Sleep::default(),
            weight_norm: 0.0,
            time: 0.0,
        })
    }

    pub fn num_particles(&self) -> usize {
        self.x.len()
    }
    pub fn positions(&self) -> &Vec3Soa {
        &self.x
    }
    pub fn velocities(&self) -> &Vec3Soa {
        &self.v
    }
    pub fn masses(&self) -> &[f32] {
        &self.model.mass
    }
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }
    pub fn model(&self) -> &Model {
        &self.model
    }
    /// Whether some seam is still being drawn together at `ramp.closing_speed`.
    pub fn seams_closing(&self) -> bool {
        self.seams_closing
    }

    /// Whether the seam-closing ramp is still waiting for the seams to meet (enabled, with
    /// seams, phase `Closing`).
    pub fn ramp_closing(&self) -> bool {
        self.settings.ramp.enabled
            && !self.model.seam_pairs.is_empty()
            && self.ramp.phase == crate::solver::stages::damping::RampPhase::Closing
    }

    /// Factor on gravity in effect now (`ramp.closing_gravity` while seams close, else 1).
    pub fn gravity_scale(&self) -> f32 {
        self.ramp.gravity_scale(&self.settings, !self.model.seam_pairs.is_empty())
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// The heap size of the solver's whole state in bytes: the [`Model`] (see
    /// [`Model::memory_bytes`]) plus every per-particle array of the moving state and the
    /// scratch buffers (positions, velocities, predictions, iterates, right-hand side, diagonal,
    /// slots, contacts, pin targets, the free list, colliders) and the per-particle collision
    /// state (`Collisions::particle_bytes`, the broad phase's shortlists included). Counts
    /// `Vec` capacities, not allocator overhead or the fixed-size struct itself.
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        self.model.memory_bytes()
            + vec_bytes(&self.colliders)
            + [&self.x, &self.v, &self.x_start, &self.y, &self.x_prev_iter, &self.x_this_iter, &self.rhs_fixed]
                .iter()
                .map(|s| s.memory_bytes())
                .sum::<usize>()
            + vec_bytes(&self.diag)
            + vec_bytes(&self.slots)
            + vec_bytes(&self.sweep_work)
            + vec_bytes(&self.sweep_parts)
            + self.contacts.memory_bytes()
            + self.pin_target.memory_bytes()
            + vec_bytes(&self.free)
            + self.coarse.as_ref().map_or(0, |c| c.memory_bytes())
            + self.collide.particle_bytes()
    }

    /// Replaces the settings (validated first; nothing changes on error).
    pub fn set_settings(&mut self, settings: SolverSettings) -> Result<()> {
        self.sleep.wake();
        settings.validate()?;
        if settings.colouring_seed != self.settings.colouring_seed {
            self.model.dirty = true;
        }
        self.settings = settings;
        self.h_prepared = 0.0;
        Ok(())
    }

    /// Sets positions (for example after the artist moved a piece); finite values only.
    pub fn set_positions(&mut self, p: &[[f32; 3]]) -> Result<()> {
        self.sleep.wake();
        self.check_len("positions", p.len())?;
        check_finite3("positions", p)?;
        self.x = Vec3Soa::from_aos(p);
        Ok(())
    }

    pub fn set_velocities(&mut self, v: &[[f32; 3]]) -> Result<()> {
        self.sleep.wake();
        self.check_len("velocities", v.len())?;
        check_finite3("velocities", v)?;
        self.v = Vec3Soa::from_aos(v);
        Ok(())
    }

    fn check_len(&self, what: &str, len: usize) -> Result<()> {
        if len != self.num_particles() {
            return Err(TailorError::shape(what, format!("{len} values for {} particles", self.num_particles())));
        }
        Ok(())
    }

    pub fn set_mass_scale(&mut self, scale: &[f32]) -> Result<()> {
        self.sleep.wake();
        self.model.set_mass_scale(scale)?;
        self.h_prepared = 0.0;
        Ok(())
    }

    pub fn set_triangle_stiffness(&mut self, stretch: &[f32], shear: &[f32]) -> Result<()> {
        self.sleep.wake();
        self.model.set_triangle_stiffness(stretch, shear)
    }

    /// Per-triangle stretch along `u` and `v` and shear, N/m (`Model::set_triangle_stiffness_uv`).
    pub fn set_triangle_stiffness_uv(&mut self, stretch: &[f32], stretch_v: &[f32], shear: &[f32]) -> Result<()> {
        self.sleep.wake();
        self.model.set_triangle_stiffness_uv(stretch, stretch_v, shear)
    }

    /// Per-triangle bending stiffness, N·m (`Model::set_triangle_bending`).
    pub fn set_triangle_bending(&mut self, bend: &[f32]) -> Result<()> {
        self.sleep.wake();
        self.model.set_triangle_bending(bend)
    }

    /// Per-triangle fabric orientation, radians from the pattern's x axis (`Model::set_triangle_grain`).
    pub fn set_triangle_grain(&mut self, angle: &[f32]) -> Result<()> {
        self.sleep.wake();
        self.model.set_triangle_grain(angle)
    }

    /// Per-triangle bending stiffness by direction, N·m (`Model::set_triangle_bending_directional`).
    pub fn set_triangle_bending_directional(&mut self, bend: &[[f32; 3]]) -> Result<()> {
        self.sleep.wake();
        self.model.set_triangle_bending_directional(bend)
    }

    /// Takes the bending rest shape from a pose (creases are kept), or flat with `None`.
    pub fn set_bending_rest_pose(&mut self, pose: Option<&[[f32; 3]]>) -> Result<()> {
        self.sleep.wake();
        match pose {
            Some(p) => {
                self.check_len("bending rest pose", p.len())?;
                check_finite3("bending rest pose", p)?;
                self.model.set_bending_rest(Some(&Vec3Soa::from_aos(p)));
            }
            None => self.model.set_bending_rest(None),
        }
        Ok(())
    }

    /// Adds a seam; the seam-closing ramp starts again. Returns the hinges created.
    pub fn add_seam(&mut self, seam: Seam) -> Result<usize> {
        self.sleep.wake();
        let first = self.model.seam_pairs.len();
        let hinges = self.model.add_seam(seam)?;
        if self.settings.ramp.enabled && self.settings.ramp.closing_speed > 0.0 {
            // Start each pair at its current gap; `close_seams` shrinks it every substep.
            let pairs = &mut self.model.seam_pairs;
            for s in first..pairs.len() {
                let gap = pairs.vector(s, &self.x).length();
                pairs.rest[s] = if gap > crate::solver::model::constraints::stencil::FLAT_REST { gap } else { 0.0 };
                self.seams_closing |= pairs.rest[s] > 0.0;
            }
            self.closing_gap0.resize(pairs.len(), 0.0);
            self.closing_left.resize(pairs.len(), 0.0);
            for s in first..pairs.len() {
                self.closing_gap0[s] = pairs.rest[s];
                self.closing_left[s] = pairs.rest[s];
            }
        }
        self.collide.invalidate_topology();
        self.ramp = Ramp::default();
        // A new closing phase: the body holds the cloth again, where it is then.
        self.collide.holds_placed = false;
        Ok(hinges)
    }

    pub fn add_attachment(&mut self, a: Attachment) -> Result<()> {
        self.sleep.wake();
        self.model.add_attachment(a)
    }

    pub fn set_attachment_targets(&mut self, targets: &[[f32; 3]]) -> Result<()> {
        self.sleep.wake();
        self.model.set_attachment_targets(targets)
    }

    /// Pins particles (hard): at `targets`, or where they are now.
    pub fn pin(&mut self, particles: &[u32], targets: Option<&[[f32; 3]]>) -> Result<()> {
        self.sleep.wake();
        let n = self.num_particles();
        if let Some(t) = targets {
            if t.len() != particles.len() {
                return Err(TailorError::shape(
                    "pin",
                    format!("{} targets for {} particles", t.len(), particles.len()),
                ));
            }
            check_finite3("pin targets", t)?;
        }
        if let Some(&bad) = particles.iter().find(|&&p| p as usize >= n) {
            return Err(TailorError::index("pin", bad as i64, n, "particles"));
        }
        for (k, &p) in particles.iter().enumerate() {
            let target = targets.map(|t| Vec3::from(t[k])).unwrap_or_else(|| self.x.get(p as usize));
            self.pin_target.set(p as usize, target);
            if !self.model.pinned[p as usize] {
                self.model.pinned[p as usize] = true;
                self.model.dirty = true;
            }
        }
        Ok(())
    }

    pub fn unpin(&mut self, particles: &[u32]) -> Result<()> {
        self.sleep.wake();
        let n = self.num_particles();
        if let Some(&bad) = particles.iter().find(|&&p| p as usize >= n) {
            return Err(TailorError::index("unpin", bad as i64, n, "particles"));
        }
        for &p in particles {
            if self.model.pinned[p as usize] {
                self.model.pinned[p as usize] = false;
                self.model.dirty = true;
            }
        }
        Ok(())
    }

    pub fn add_collider(&mut self, c: ImplicitCollider) -> Result<()> {
        c.shape.validate()?;
        self.sleep.wake();
        for (name, v) in [("static_friction", c.static_friction), ("kinetic_friction", c.kinetic_friction)] {
            crate::solver::model::settings::non_negative(name, v)?;
        }
        self.colliders.push(c);
        Ok(())
    }

    /// Collision thickness: particles are kept this far outside colliders, metres.
    pub fn set_thickness(&mut self, t: f32) -> Result<()> {
        self.sleep.wake();
        crate::solver::model::settings::non_negative("thickness", t)?;
        self.thickness = t;
        Ok(())
    }

    /// Number of colours of the particle graph (after the next rebuild).
    pub fn colour_count(&mut self) -> usize {
        self.prepare(self.h_prepared.max(1e-3));
        self.model.colouring.count()
    }

    /// Whether the cloth is asleep (at rest and not being solved; see `sleep.rs`).
    pub fn is_asleep(&self) -> bool {
        self.sleep.asleep
    }

    /// Allows or forbids sleeping (on by default; benchmarks and equivalence tests switch it).
    pub fn set_sleeping(&mut self, enabled: bool) {
        self.sleep.enabled = enabled;
        self.sleep.wake();
    }

    /// Largest sewn-pair gap (m) and fraction of pairs under the ramp's gap threshold.
    pub fn seam_gaps(&self) -> (f32, f32) {
        let set = &self.model.seam_pairs;
        if set.is_empty() {
            return (0.0, 1.0);
        }
        let thr = self.settings.ramp.gap_threshold;
        let mut max = 0.0f32;
        let mut closed = 0usize;
        for s in 0..set.len() {
            let g = set.vector(s, &self.x).length();
            max = max.max(g);
            closed += (g < thr) as usize;
        }
        (max, closed as f32 / set.len() as f32)
    }

    /// FNV-1a hash of the position bits (determinism tests).
    pub fn state_hash(&self) -> u64 {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        for v in self.x.x.iter().chain(&self.x.y).chain(&self.x.z) {
            for b in v.to_bits().to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
        h
    }

    /// Everything a measurement may disturb.
    pub(crate) fn save_state(&self) -> SavedState {
        SavedState { x: self.x.clone(), v: self.v.clone(), ramp: self.ramp.clone(), time: self.time }
    }

    pub(crate) fn restore_state(&mut self, s: SavedState) {
        (self.x, self.v, self.ramp, self.time) = (s.x, s.v, s.ramp, s.time);
    }

    /// Detects contacts at the current positions (measurements freeze them for a whole step).
    pub(crate) fn detect_contacts_now(&mut self) {
        if self.colliders.is_empty() {
            self.contacts.clear();
        } else {
            self.contacts.detect(&self.colliders, self.thickness, &self.x, &self.diag, &self.model.pinned);
        }
        self.detect_mesh_contacts();
    }
}
