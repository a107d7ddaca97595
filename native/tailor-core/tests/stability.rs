//! The numerical stress cases of `tailor_core::stability` at their quick size (a few hundred
//! particles, tens of frames each): every case must end finite, with bounded kinetic energy and
//! edge strain. `make stress` runs them all at full size and writes `docs/stability.md`.

use tailor_core::stability::{cases, run, Size};

#[test]
fn every_stress_case_stays_finite_and_bounded_at_quick_size() {
    let mut failed = Vec::new();
    for case in cases() {
        let r = run(&case, Size::Quick).unwrap();
        println!(
            "{:<20} {:>4} particles {:>3} frames {:6.2} s | KE max {:.2e} end {:.2e} J/kg | strain max {:.3} end {:.3} \
             | seam gap {:.1} mm | penetrations {} ({:.1} mm) | {}",
            r.name,
            r.particles,
            r.frames,
            r.seconds,
            r.ke_max,
            r.ke_end,
            r.strain_max,
            r.strain_end,
            r.seam_gap_end * 1e3,
            r.penetrations_end,
            r.penetration_depth_end * 1e3,
            r.error.as_deref().unwrap_or("ok")
        );
        if !r.passed() {
            failed.push(format!("{}: {r:?}", r.name));
        }
    }
    assert!(failed.is_empty(), "unstable cases:\n{}", failed.join("\n"));
}
