//! Air damping and the seam-closing ramp (Nylén et al. 2020, section 4).
//!
//! When a simulation starts, seams pull their sides together abruptly. To keep that stable the
//! air damping is raised while seams are open; once most pairs meet (the fraction of pairs
//! under a gap threshold reaches `closed_fraction`) it returns linearly to its base value over
//! `release_time` and then stays there. Adding seams restarts the ramp. While seams are open,
//! gravity is scaled by `ramp.closing_gravity` (0 by default): the pieces assemble where they
//! were placed instead of falling off the body before they are sewn.

use super::settings::SolverSettings;

/// Where the ramp is.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum RampPhase {
    /// Seams are open: damping is raised.
    #[default]
    Closing,
    /// Seams have met: damping returns to its base value; `elapsed` seconds so far.
    Releasing { elapsed: f32 },
    /// The ramp is over (or there are no seams): base damping.
    Done,
}

/// The ramp's state machine.
#[derive(Debug, Clone, Default)]
pub struct Ramp {
    pub phase: RampPhase,
}

impl Ramp {
    /// Damping in effect now, 1/s.
    pub fn damping(&self, s: &SolverSettings) -> f32 {
        if !s.ramp.enabled {
            return s.air_damping;
        }
        let high = s.ramp.closing_damping.max(s.air_damping);
        match self.phase {
            RampPhase::Closing => high,
            RampPhase::Releasing { elapsed } => {
                let t = if s.ramp.release_time > 0.0 { (elapsed / s.ramp.release_time).min(1.0) } else { 1.0 };
                high + (s.air_damping - high) * t
            }
            RampPhase::Done => s.air_damping,
        }
    }

    /// Factor on gravity now: `ramp.closing_gravity` while seams close (only when there are
    /// seams: a cloth without seams is never held), 1 otherwise.
    pub fn gravity_scale(&self, s: &SolverSettings, has_seams: bool) -> f32 {
        if s.ramp.enabled && has_seams && self.phase == RampPhase::Closing {
            s.ramp.closing_gravity
        } else {
            1.0
        }
    }

    /// Advances by `h` seconds given the fraction of seam pairs that have met.
    pub fn advance(&mut self, s: &SolverSettings, closed_fraction: f32, has_seams: bool, h: f32) {
        self.phase = match self.phase {
            _ if !has_seams => RampPhase::Done,
            RampPhase::Closing if closed_fraction >= s.ramp.closed_fraction => RampPhase::Releasing { elapsed: 0.0 },
            RampPhase::Releasing { elapsed } if elapsed + h >= s.ramp.release_time => RampPhase::Done,
            RampPhase::Releasing { elapsed } => RampPhase::Releasing { elapsed: elapsed + h },
            p => p,
        };
    }
}

/// Velocity factor of air damping over a substep: exact decay `exp(−c·h)`.
pub fn decay(c: f32, h: f32) -> f32 {
    (-c * h).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_raises_then_releases_linearly() {
        let s = SolverSettings::default();
        let mut r = Ramp::default();
        assert_eq!(r.damping(&s), s.ramp.closing_damping);
        r.advance(&s, 0.5, true, 0.01);
        assert_eq!(r.phase, RampPhase::Closing);
        r.advance(&s, 0.99, true, 0.01);
        assert!(matches!(r.phase, RampPhase::Releasing { .. }));
        let h = s.ramp.release_time / 2.0;
        r.advance(&s, 1.0, true, h);
        let mid = (s.ramp.closing_damping + s.air_damping) / 2.0;
        assert!((r.damping(&s) - mid).abs() < 1e-4, "{} vs {mid}", r.damping(&s));
        r.advance(&s, 1.0, true, h);
        assert_eq!(r.phase, RampPhase::Done);
        assert_eq!(r.damping(&s), s.air_damping);
    }

    #[test]
    fn gravity_is_held_only_while_seams_close() {
        let mut s = SolverSettings::default();
        s.ramp.closing_gravity = 0.25;
        let mut r = Ramp::default();
        assert_eq!(r.gravity_scale(&s, true), 0.25);
        assert_eq!(r.gravity_scale(&s, false), 1.0, "a cloth without seams falls from the start");
        r.advance(&s, 1.0, true, 0.01);
        assert_eq!(r.gravity_scale(&s, true), 1.0, "full gravity from the release on");
        s.ramp.enabled = false;
        assert_eq!(Ramp::default().gravity_scale(&s, true), 1.0);
    }
}
