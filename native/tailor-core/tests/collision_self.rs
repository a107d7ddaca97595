//! Cloth-cloth collisions: two stacked layers falling on a floor stay apart, and collision
//! levels switch the layers' collision on and off.

mod collision_common;

use collision_common::*;
use glam::Vec3;
use tailor_core::collision::metrics::count_self_intersections;
use tailor_core::solver::{CollisionSkips, MeshColliderOptions, SelfCollisionSettings, Simulation, SolverSettings};

/// Two 0.4 m layers of 16 × 16 cells, 4 cm apart (the upper one shifted by a third of a cell,
/// so its particles are not above the lower ones'), in one cloth, falling on a floor mesh.
fn two_layers(levels: Option<(i32, i32)>, self_on: bool) -> (Simulation, usize) {
    two_layers_with(levels, self_on, CollisionSkips::default())
}

fn two_layers_with(levels: Option<(i32, i32)>, self_on: bool, skips: CollisionSkips) -> (Simulation, usize) {
    let (p0, r0, t0) = cloth_grid(0.4, 16, 0.0, 0.0, 0.05);
    let (p1, _, t1) = cloth_grid(0.4, 16, 0.0083, 0.0083, 0.09);
    let n0 = p0.len() as u32;
    let pos: Vec<[f32; 3]> = p0.iter().chain(&p1).copied().collect();
    // Second layer's rest shape side by side with the first in the pattern plane.
    let rest: Vec<[f32; 2]> = r0.iter().copied().chain(r0.iter().map(|r| [r[0] + 1.0, r[1]])).collect();
    let tris: Vec<[u32; 3]> = t0.iter().copied().chain(t1.iter().map(|t| t.map(|v| v + n0))).collect();
    let mut sim = sim_of(pos, rest, tris, SolverSettings::default());
    sim.set_collision_skips(skips);
    let (fv, ft) = plane_mesh(2.0, 10, Vec3::ZERO, Vec3::X, Vec3::Y);
    sim.add_mesh_collider(&fv, &ft, MeshColliderOptions::default()).unwrap();
    sim.set_self_collision(SelfCollisionSettings { enabled: self_on, ..Default::default() }).unwrap();
    if let Some((a, b)) = levels {
        let lv: Vec<i32> = (0..sim.num_particles()).map(|i| if (i as u32) < n0 { a } else { b }).collect();
        sim.set_particle_levels(&lv).unwrap();
    }
    for _ in 0..24 {
        sim.step(1.0 / 30.0).unwrap();
    }
    (sim, n0 as usize)
}

fn layer_heights(sim: &Simulation, n0: usize) -> (f32, f32) {
    let z = &sim.positions().z;
    let mean = |s: &[f32]| s.iter().sum::<f32>() / s.len() as f32;
    (mean(&z[..n0]), mean(&z[n0..]))
}

#[test]
fn stacked_layers_fall_on_a_floor_and_stay_apart() {
    let (sim, n0) = two_layers(None, true);
    let x = sim.positions().to_aos();
    let crossings = count_self_intersections(&x, sim.model().mesh.triangles()).unwrap();
    let (lo, hi) = layer_heights(&sim, n0);
    let r = sim.self_collision_radius();
    println!("layers: mean heights {lo:.4} / {hi:.4} m, radius {r:.4} m, {crossings} intersecting pairs");
    assert_eq!(crossings, 0, "the layers intersect");
    assert!(lo < 0.01 && hi - lo > 1.5 * r, "layers not stacked: {lo} / {hi}");
    let m = sim.metrics(None).unwrap();
    assert_eq!(m.self_intersections, 0);
}

/// Levels 1 and 2 do not collide: the upper layer falls through the lower onto the floor.
/// Levels 1 and 1 (and 0 with 2) do.
#[test]
fn levels_switch_cloth_cloth_collisions_both_ways() {
    for (levels, collide) in [((1, 2), false), ((1, 1), true), ((0, 2), true)] {
        let (sim, n0) = two_layers(Some(levels), true);
        let (lo, hi) = layer_heights(&sim, n0);
        println!("levels {levels:?}: mean heights {lo:.4} / {hi:.4} m");
        if collide {
            assert!(hi - lo > 0.01, "levels {levels:?} should keep the layers apart: {lo} / {hi}");
        } else {
            assert!((hi - lo).abs() < 0.003, "levels {levels:?} should let the layers through: {lo} / {hi}");
        }
    }
    // Self-collision off: the same as non-colliding levels.
    let (sim, n0) = two_layers(None, false);
    let (lo, hi) = layer_heights(&sim, n0);
    assert!((hi - lo).abs() < 0.003, "self-collision off should let the layers through: {lo} / {hi}");
}

/// Keeping the self-collision candidates (searched with a margin) across passes gives
/// bit-identical positions to a hash search every pass, with far fewer searches.
#[test]
fn reusing_self_collision_candidates_does_not_change_results() {
    let mut searches = Vec::new();
    let mut hashes = Vec::new();
    for reuse in [true, false] {
        let skips = CollisionSkips { reuse_self_pairs: reuse, ..Default::default() };
        let (mut sim, _) = two_layers_with(None, true, skips);
        let s = sim.step(1.0 / 30.0).unwrap();
        searches.push(s.collision.self_searches);
        hashes.push(sim.state_hash());
    }
    println!("self-collision searches in one frame: reused {} / every pass {}", searches[0], searches[1]);
    assert_eq!(hashes[0], hashes[1], "reusing candidates changed the result");
    assert!(searches[0] * 4 < searches[1], "{searches:?}");
}
