//! Sleeping: a cloth at rest stops being solved until something touches it.
//!
//! After every step the fastest particle's speed is compared with [`SLEEP_SPEED`]; after
//! [`SLEEP_FRAMES`] steps in a row under it, with no seam closing and every mesh collider
//! still, the cloth falls asleep: its velocities are set to zero and later steps only advance
//! the clock. Anything that could move it wakes it before the next step: a mesh collider that
//! moves, and every call that changes the simulation's inputs (positions, velocities, pins and
//! their targets, attachments, seams, colliders, masses, stiffness, settings, thickness,
//! self-collision, levels, friction). The whole cloth sleeps or none of it: the solver's
//! Gauss-Seidel couples every particle, and a cloth asleep in parts would need its matrix
//! rebuilt whenever a part wakes.
//!
//! What it changes: a sleeping cloth keeps the positions it had when it fell asleep, where
//! an awake one would keep creeping at under `SLEEP_SPEED` (at most `SLEEP_SPEED · t`). The
//! benchmark (`examples/skips.rs`, `docs/benchmarks.md`) measures both the time saved and that
//! difference.

/// Speed under which a particle counts as at rest, m/s (0.5 mm/s: 17 µm per frame at 30 fps;
/// measured: a 1 m sheet of 2 500 particles resting on a table still creeps in its plane at up
/// to 0.09 mm/s after 20 frames, as Gauss-Seidel relaxes its in-plane stretch).
pub const SLEEP_SPEED: f32 = 5e-4;
/// Consecutive steps at rest before the cloth falls asleep.
pub const SLEEP_FRAMES: u32 = 15;

/// Sleep state of a simulation.
#[derive(Debug, Clone)]
pub(crate) struct Sleep {
    /// Whether the cloth may fall asleep (on by default; benchmarks and tests switch it).
    pub enabled: bool,
    /// Consecutive steps at rest.
    rest_steps: u32,
    pub asleep: bool,
}

impl Default for Sleep {
    fn default() -> Self {
        Self { enabled: true, rest_steps: 0, asleep: false }
    }
}

impl Sleep {
    /// Something may move the cloth: solve the next step.
    pub fn wake(&mut self) {
        self.asleep = false;
        self.rest_steps = 0;
    }

    /// After a solved step whose fastest particle moved at `max_speed`; `quiet` says that
    /// nothing drives the cloth (no seam closing, colliders still). Returns whether the cloth
    /// falls asleep now.
    pub fn after_step(&mut self, max_speed: f32, quiet: bool) -> bool {
        if !self.enabled || !quiet || !(max_speed < SLEEP_SPEED) {
            self.rest_steps = 0;
            return false;
        }
        self.rest_steps += 1;
        self.asleep = self.rest_steps >= SLEEP_FRAMES;
        self.asleep
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falls_asleep_after_enough_quiet_steps_and_wakes() {
        let mut s = Sleep::default();
        for _ in 0..SLEEP_FRAMES - 1 {
            assert!(!s.after_step(0.0, true));
        }
        // A fast step or a driven one starts the count again.
        assert!(!s.after_step(1.0, true));
        assert!(!s.after_step(0.0, false));
        assert!(!s.after_step(f32::NAN, true));
        for _ in 0..SLEEP_FRAMES - 1 {
            assert!(!s.after_step(0.0, true));
        }
        assert!(s.after_step(0.0, true) && s.asleep);
        s.wake();
        assert!(!s.asleep);
        let mut off = Sleep { enabled: false, ..Sleep::default() };
        assert!((0..100).all(|_| !off.after_step(0.0, true)));
    }
}
