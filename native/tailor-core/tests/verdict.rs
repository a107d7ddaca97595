//! The verdict on simulated garments (`quality::verdict`), through `Simulation::metrics`:
//! a sewn tube hung below a body falls off it and is reported as fallen, though its seams close
//! and nothing pierces the body; the same tube dropped over the top of the body rests on it and
//! passes every check.

use glam::Vec3;
use tailor_core::quality::verdict::{centroid_shift, judge, Check};
use tailor_core::scenes::{icosphere, sewn_tube};
use tailor_core::solver::{ColliderId, Fabric, MeshColliderOptions, QualityMetrics, Simulation, SolverSettings};

const FPS: f32 = 30.0;

/// A body: an icosphere of radius 0.2 m centred at `centre`.
fn body(centre: [f32; 3]) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (v, t) = icosphere(3, 0.2);
    (v.into_iter().map(|p| (Vec3::from(p) + Vec3::from(centre)).into()).collect(), t)
}

/// A tube of 0.8 m round (radius 13 cm), `height` tall, bottom at `bottom` (z up), seams 10 cm
/// open, with the body as mesh collider.
fn tube_and_body(height: f32, bottom: f32, centre: [f32; 3]) -> (Simulation, ColliderId) {
    let tube = sewn_tube(0.4, height, 0.04, 0.1, bottom, 1000.0).unwrap();
    let mut sim = Simulation::new(tube.mesh, Fabric::default(), SolverSettings::default()).unwrap();
    for s in tube.seams {
        sim.add_seam(s).unwrap();
    }
    let (v, t) = body(centre);
    let id = sim.add_mesh_collider(&v, &t, MeshColliderOptions::default()).unwrap();
    (sim, id)
}

/// Runs `frames` frames; returns the start's metrics, the last frame's, and the names of the
/// checks any frame failed.
fn run(sim: &mut Simulation, id: ColliderId, frames: usize) -> (QualityMetrics, QualityMetrics, Vec<&'static str>) {
    let start = sim.metrics(Some(id)).unwrap();
    assert!(start.seams_closing && judge(&start, &start, false).is_empty());
    let mut failed = Vec::new();
    let mut now = start;
    for _ in 0..frames {
        sim.step(1.0 / FPS).unwrap();
        now = sim.metrics(Some(id)).unwrap();
        for f in judge(&now, &start, false) {
            if !failed.contains(&f.check.name()) {
                failed.push(f.check.name());
            }
        }
    }
    (start, now, failed)
}

#[test]
fn a_tube_below_the_body_is_reported_as_fallen() {
    // The body 40 cm above the tube's top: nothing holds the tube once its seams have closed.
    let (mut sim, id) = tube_and_body(0.3, 0.0, [0.0, 0.0, 0.7]);
    let (start, last, failed) = run(&mut sim, id, 45);
    println!(
        "fallen: shift {:.2} m, on body {:?}, seam gap {:.2e} m, inside {}",
        centroid_shift(&start, &last),
        last.on_body_fraction,
        last.seam_gap,
        last.penetration_count
    );
    // Everything the old report said is fine ...
    assert!(!last.seams_closing && last.seam_gap < 1e-3 && last.penetration_count == 0, "{last:?}");
    // ... but it is a metre below where it started, with nothing near the body.
    assert!(centroid_shift(&start, &last) > 1.0 && last.on_body_fraction == Some(0.0), "{last:?}");
    assert_eq!(failed, ["fell"]);
    let f = judge(&last, &start, false);
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].check, Check::Fell);
    assert!(f[0].reason.contains("moved") && f[0].reason.contains("only 0 %"), "{}", f[0].reason);
}

#[test]
fn a_tube_over_the_body_rests_on_it_and_passes() {
    // A band 12 cm tall, its bottom 3 cm under the top of the body: its rim (radius 13 cm)
    // settles on the sphere where that is as wide, a band round the top of a head.
    let (mut sim, id) = tube_and_body(0.12, 0.27, [0.0, 0.0, 0.1]);
    let (start, last, failed) = run(&mut sim, id, 45);
    println!(
        "resting: shift {:.3} m, on body {:?}, seam gap {:.2e} m, inside {} ({:.2e} m)",
        centroid_shift(&start, &last),
        last.on_body_fraction,
        last.seam_gap,
        last.penetration_count,
        last.penetration_max_depth
    );
    assert!(!last.seams_closing, "still assembling");
    assert!(failed.is_empty(), "{failed:?}: {last:?}");
    assert!(last.on_body_fraction.unwrap() > 0.9 && centroid_shift(&start, &last) < 0.1, "{last:?}");
}
