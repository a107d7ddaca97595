//! The frame rate and frame count of a baked or simulated run, checked once for every caller
//! (`tailor simulate`, `tailor.bake.Bake`, the add-on).
//!
//! `--fps nan` reached the glTF sampler as a NaN time and panicked; `--fps 0` divided by zero;
//! `--frames -5` ran nothing and exited 0. Each is now refused with the setting's name.

use crate::error::{Result, TailorError};

/// The highest frame rate accepted: far above any animation, low enough that `1/fps` is a
/// time step the solver can take.
pub const MAX_FPS: f64 = 10_000.0;
/// The most frames one run may ask for (an hour at 240 fps is under a million).
pub const MAX_FRAMES: i64 = 1_000_000;

/// Checks `fps` (a positive, finite rate up to [`MAX_FPS`]) and, when given, `frames` (1 to
/// [`MAX_FRAMES`]).
pub fn check_playback(fps: f64, frames: Option<i64>) -> Result<()> {
    if !(fps.is_finite() && fps > 0.0 && fps <= MAX_FPS) {
        return Err(TailorError::setting("fps", fps, format!("must be a frame rate above 0 and at most {MAX_FPS}")));
    }
    if let Some(n) = frames {
        if !(1..=MAX_FRAMES).contains(&n) {
            return Err(TailorError::setting("frames", n, format!("must be between 1 and {MAX_FRAMES}")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_rates_and_counts_are_named() {
        assert!(check_playback(30.0, Some(1)).is_ok());
        assert!(check_playback(24.0, None).is_ok());
        for fps in [0.0, -30.0, f64::NAN, f64::INFINITY, 1e9] {
            let e = check_playback(fps, Some(10)).unwrap_err();
            assert!(matches!(e, TailorError::InvalidSetting { name: "fps", .. }), "{fps}: {e}");
        }
        for frames in [0, -5, MAX_FRAMES + 1] {
            let e = check_playback(30.0, Some(frames)).unwrap_err();
            assert!(matches!(e, TailorError::InvalidSetting { name: "frames", .. }), "{frames}: {e}");
        }
    }
}
