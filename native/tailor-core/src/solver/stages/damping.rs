//! Air damping and the seam-closing ramp (Nylén et al. 2020, section 4).
//!
//! When a simulation starts, seams pull their sides together abruptly. To keep that stable the
//! air damping is raised while seams are open; once the seams have met it returns linearly to
//! its base value over `release_time` and then stays there. Adding seams restarts the ramp.
//! While seams are open, gravity is scaled by `ramp.closing_gravity` (0 by default): the
//! pieces assemble where they were placed instead of falling off the body before they are sewn.
//!
//! **When the seams have met** is measured, not timed: `closed_fraction` of the pairs within
//! `gap_threshold` *and* the widest pair within `release_gap`. The paper's fraction alone
//! released gravity while a few pairs were still 20 cm apart (the GarmentCode flared skirt's
//! side seams at 5 cm, the sampler's skirts likewise), and the garment dropped with a seam
//! still open. A seam that cannot close (held apart by the body, or sewn wrong) must not keep
//! the garment weightless for ever, so once every pair's closing schedule has run out the ramp
//! also releases when the widest gap has stopped shrinking (by [`STALL_SHRINK`] over
//! [`STALL_TIME`]).

use crate::solver::model::settings::SolverSettings;

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

/// Seconds the widest gap may go without shrinking (after every pair's closing schedule has
/// run out) before the ramp releases anyway.
pub const STALL_TIME: f32 = 0.5;
/// The widest gap counts as shrinking while it gets below this share of its best so far.
pub const STALL_SHRINK: f32 = 0.95;

/// The measured state of the seams that the ramp advances on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamGaps {
    /// The widest sewn pair's gap, m.
    pub widest: f32,
    /// Fraction of pairs within `ramp.gap_threshold`.
    pub closed_fraction: f32,
    /// Every pair's closing schedule has run out (no rest length left to shrink).
    pub scheduled: bool,
}

/// The ramp's state machine.
#[derive(Debug, Clone, Default)]
pub struct Ramp {
    pub phase: RampPhase,
    /// While closing after the schedule ran out: the smallest widest gap seen, m, and the
    /// seconds since it last shrank (see [`STALL_TIME`]).
    pub(crate) stall: Option<(f32, f32)>,
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

    /// Advances by `h` seconds given the measured seam gaps (see the module docs).
    pub fn advance(&mut self, s: &SolverSettings, gaps: SeamGaps, has_seams: bool, h: f32) {
        let met = gaps.closed_fraction >= s.ramp.closed_fraction && gaps.widest <= s.ramp.release_gap;
        let stalled = self.phase == RampPhase::Closing && gaps.scheduled && self.stalled(gaps.widest, h);
        self.phase = match self.phase {
            _ if !has_seams => RampPhase::Done,
            RampPhase::Closing if met || stalled => RampPhase::Releasing { elapsed: 0.0 },
            RampPhase::Releasing { elapsed } if elapsed + h >= s.ramp.release_time => RampPhase::Done,
            RampPhase::Releasing { elapsed } => RampPhase::Releasing { elapsed: elapsed + h },
            p => p,
        };
    }
}

impl Ramp {
    /// Tracks the widest gap after the schedule ran out; true once it has not shrunk for
    /// [`STALL_TIME`].
    fn stalled(&mut self, widest: f32, h: f32) -> bool {
        let (best, since) = match self.stall {
            Some((best, since)) if widest >= STALL_SHRINK * best => (best, since + h),
            _ => (widest, 0.0),
        };
        self.stall = Some((best, since));
        since >= STALL_TIME
    }
}

/// Velocity factor of air damping over a substep: exact decay `exp(−c·h)`.
pub fn decay(c: f32, h: f32) -> f32 {
    (-c * h).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seams at `widest` m with `closed_fraction` met, schedule still running.
    fn gaps(widest: f32, closed_fraction: f32) -> SeamGaps {
        SeamGaps { widest, closed_fraction, scheduled: false }
    }

    #[test]
    fn ramp_raises_then_releases_linearly() {
        let s = SolverSettings::default();
        let mut r = Ramp::default();
        assert_eq!(r.damping(&s), s.ramp.closing_damping);
        r.advance(&s, gaps(0.2, 0.5), true, 0.01);
        assert_eq!(r.phase, RampPhase::Closing);
        r.advance(&s, gaps(0.001, 0.99), true, 0.01);
        assert!(matches!(r.phase, RampPhase::Releasing { .. }));
        let h = s.ramp.release_time / 2.0;
        r.advance(&s, gaps(0.0, 1.0), true, h);
        let mid = (s.ramp.closing_damping + s.air_damping) / 2.0;
        assert!((r.damping(&s) - mid).abs() < 1e-4, "{} vs {mid}", r.damping(&s));
        r.advance(&s, gaps(0.0, 1.0), true, h);
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
        r.advance(&s, gaps(0.0, 1.0), true, 0.01);
        assert_eq!(r.gravity_scale(&s, true), 1.0, "full gravity from the release on");
        s.ramp.enabled = false;
        assert_eq!(Ramp::default().gravity_scale(&s, true), 1.0);
    }

    #[test]
    fn a_few_pairs_far_apart_hold_the_release() {
        let s = SolverSettings::default();
        let mut r = Ramp::default();
        // 97 % of the pairs met, but one side seam still 20 cm open: no release.
        for _ in 0..100 {
            r.advance(&s, gaps(0.2, 0.97), true, 0.01);
        }
        assert_eq!(r.phase, RampPhase::Closing);
        r.advance(&s, gaps(0.5 * s.ramp.release_gap, 0.97), true, 0.01);
        assert!(matches!(r.phase, RampPhase::Releasing { .. }));
    }

    #[test]
    fn a_seam_that_stops_closing_releases_after_the_stall_time() {
        let s = SolverSettings::default();
        let h = 0.01;
        let stuck = SeamGaps { widest: 0.05, closed_fraction: 0.9, scheduled: true };
        // Still shrinking by more than STALL_SHRINK per step: no release however long.
        let mut r = Ramp::default();
        let mut w = 0.2;
        for _ in 0..200 {
            w *= 0.9 * STALL_SHRINK;
            r.advance(&s, SeamGaps { widest: w.max(0.02), ..stuck }, true, h);
            if w < 0.02 {
                break;
            }
        }
        assert_eq!(r.phase, RampPhase::Closing);
        // Stuck at 5 cm: released once STALL_TIME has passed, not before.
        let mut r = Ramp::default();
        let steps = (STALL_TIME / h).round() as usize;
        for _ in 0..steps - 1 {
            r.advance(&s, stuck, true, h);
        }
        assert_eq!(r.phase, RampPhase::Closing, "released before the stall time");
        for _ in 0..3 {
            // (a step or two more for the rounding of the summed time)
            r.advance(&s, stuck, true, h);
        }
        assert!(matches!(r.phase, RampPhase::Releasing { .. }));
        // While the schedule still runs, a stuck gap does not release.
        let mut r = Ramp::default();
        for _ in 0..3 * steps {
            r.advance(&s, SeamGaps { scheduled: false, ..stuck }, true, h);
        }
        assert_eq!(r.phase, RampPhase::Closing);
    }
}
