//! The work a scene skips by itself: sleeping at rest, early termination at the tolerance,
//! and reusing the matrix and colouring while the topology does not change. Each skip must
//! save work without changing what the user sees (`examples/skips.rs` measures how much).

use tailor_core::scenes::{box_mesh, hanging_sheet, sewn_tube};
use tailor_core::solver::sleep::{SLEEP_FRAMES, SLEEP_SPEED};
use tailor_core::solver::{Fabric, MeshColliderOptions, Simulation, SolverSettings};

const DT: f32 = 1.0 / 30.0;

/// A 0.3 m sheet of ~225 particles dropped from 2 cm onto a table (a box mesh collider): it
/// comes to rest lying on it.
fn on_table(sleeping: bool) -> (Simulation, tailor_core::solver::ColliderId, Vec<[f32; 3]>) {
    let (mesh, _) = hanging_sheet(225, 0.3, 0.02).unwrap();
    let mut sim = Simulation::new(mesh, Fabric::default(), SolverSettings::default()).unwrap();
    let (v, t) = box_mesh([-0.3, -0.3, -0.1], [0.3, 0.3, 0.0]);
    let id = sim.add_mesh_collider(&v, &t, MeshColliderOptions::default()).unwrap();
    sim.set_collider_friction(id, 0.8, 0.6).unwrap();
    sim.set_sleeping(sleeping);
    (sim, id, v)
}

fn max_distance(a: &Simulation, b: &Simulation) -> f32 {
    let (p, q) = (a.positions().to_aos(), b.positions().to_aos());
    p.iter()
        .zip(&q)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
        .fold(0.0, f32::max)
}

#[test]
fn a_cloth_at_rest_sleeps_without_visible_change_and_wakes_when_touched() {
    let (mut on, id, v) = on_table(true);
    let (mut off, _, _) = on_table(false);
    assert!(on.step(DT).unwrap().iterations > 0 && off.step(DT).unwrap().iterations > 0);
    let mut slept_at = None;
    for f in 0..90 {
        let s = on.step(DT).unwrap();
        off.step(DT).unwrap();
        if s.asleep && slept_at.is_none() {
            slept_at = Some(f);
            assert_eq!(s.iterations, 0, "nothing is solved while asleep");
        }
    }
    let slept_at = slept_at.expect("the draped sheet never fell asleep");
    let drift = max_distance(&on, &off);
    println!("asleep from frame {slept_at}; after 90 frames the sleeping and awake runs differ by {drift:.2e} m");
    // At most the creep an awake cloth has at under SLEEP_SPEED for the frames it slept.
    assert!(drift <= SLEEP_SPEED * (90 - slept_at + SLEEP_FRAMES as usize) as f32 * DT + 1e-5, "{drift}");
    assert!(drift < 1e-4, "sleeping changed the result visibly: {drift} m");
    assert!(on.velocities().max_length() == 0.0 && on.is_asleep());

    // Asleep, positions hold; a moving collider wakes it and it follows.
    let before = on.positions().to_aos();
    on.step(DT).unwrap();
    assert_eq!(on.positions().to_aos(), before);
    let lifted: Vec<[f32; 3]> = v.iter().map(|p| [p[0], p[1], p[2] + 0.02]).collect();
    on.set_collider_positions(id, &lifted).unwrap();
    let s = on.step(DT).unwrap();
    assert!(!s.asleep && s.iterations > 0 && !on.is_asleep());
    let rise = on.positions().to_aos().iter().zip(&before).map(|(a, b)| a[2] - b[2]).fold(f32::MIN, f32::max);
    assert!(rise > 0.01, "the woken sheet did not follow the collider up: {rise}");

    // Any input change wakes it too.
    for _ in 0..60 {
        on.step(DT).unwrap();
    }
    assert!(on.is_asleep());
    on.pin(&[0], None).unwrap();
    assert!(!on.is_asleep());
}

#[test]
fn closing_seams_keep_a_cloth_awake() {
    // Seams 30 cm apart close at 0.5 m/s: never asleep while they close.
    let tube = sewn_tube(0.3, 0.3, 0.03, 0.3, 0.0, 1000.0).unwrap();
    let settings = SolverSettings { gravity: [0.0; 3], ..Default::default() };
    let mut sim = Simulation::new(tube.mesh, Fabric::default(), settings).unwrap();
    for s in tube.seams {
        sim.add_seam(s).unwrap();
    }
    for _ in 0..20 {
        let s = sim.step(DT).unwrap();
        assert!(!s.asleep || !sim.seams_closing());
        if sim.seams_closing() {
            assert!(!s.asleep);
        }
    }
}

#[test]
fn early_termination_stops_at_the_tolerance() {
    // The sheet falling onto the table (sleeping off): iterations are cut once it lies still.
    let run = |tolerance: f32| {
        let (mut sim, _, _) = on_table(false);
        sim.set_settings(SolverSettings { tolerance, ..Default::default() }).unwrap();
        let its: Vec<u32> = (0..60).map(|_| sim.step(DT).unwrap().iterations).collect();
        (its, sim)
    };
    let (full, a) = run(0.0);
    let (early, b) = run(1e-2);
    let (sum_full, sum_early) = (full.iter().sum::<u32>(), early.iter().sum::<u32>());
    println!(
        "iterations over 60 frames: {sum_full} without a tolerance, {sum_early} stopping at 1e-2; per frame {early:?}"
    );
    assert!(full.iter().all(|&n| n == 4 * 20));
    assert!(sum_early < sum_full / 2, "early termination saved little: {sum_early} of {sum_full}");
    let d = max_distance(&a, &b);
    assert!(d < 1e-3, "early termination moved the cloth by {d} m");
}

#[test]
fn matrix_and_colouring_are_rebuilt_only_when_the_topology_changes() {
    let (mut sim, id, v) = on_table(false);
    sim.step(DT).unwrap();
    let built = sim.model().rebuilds;
    assert_eq!(built, 1);
    for f in 0..10 {
        // A moving collider and changing contacts do not touch the matrix.
        let moved: Vec<[f32; 3]> = v.iter().map(|p| [p[0] + 0.001 * f as f32, p[1], p[2]]).collect();
        sim.set_collider_positions(id, &moved).unwrap();
        sim.step(DT).unwrap();
    }
    assert_eq!(sim.model().rebuilds, built);
    sim.pin(&[0], None).unwrap();
    sim.step(DT).unwrap();
    assert_eq!(sim.model().rebuilds, built + 1);
}
