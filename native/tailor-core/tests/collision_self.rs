//! Cloth-cloth collisions: two stacked layers falling on a floor stay apart, and collision
//! levels switch the layers' collision on and off.

mod collision_common;

use collision_common::*;
use glam::Vec3;
use tailor_core::quality::metrics::count_self_intersections;
use tailor_core::scenes::grid_column;
use tailor_core::solver::{
    CollisionSkips, MeshColliderOptions, Seam, SelfCollisionSettings, Simulation, SolverSettings,
};

/// Two 0.4 m layers of 16 × 16 cells, 4 cm apart (the upper one shifted by a third of a cell,
/// so its particles are not above the lower ones'), in one cloth, falling on a floor mesh.
fn two_layers(levels: Option<(i32, i32)>, self_on: bool) -> (Simulation, usize) {
    two_layers_with(levels, self_on, CollisionSkips::default())
}

fn two_layers_with(levels: Option<(i32, i32)>, self_on: bool, skips: CollisionSkips) -> (Simulation, usize) {
    let (mut sim, n0) = two_layers_placed(levels, self_on, skips);
    for _ in 0..24 {
        sim.step(1.0 / 30.0).unwrap();
    }
    (sim, n0)
}

/// The two layers as placed, before any step.
fn two_layers_placed(levels: Option<(i32, i32)>, self_on: bool, skips: CollisionSkips) -> (Simulation, usize) {
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

/// Keeping the self-collision candidates (searched with a margin) across passes, with the
/// pairs of the particles that moved too far searched alone (`self_movers.rs`), gives
/// bit-identical positions to a hash search every pass, with far fewer searches.
#[test]
fn reusing_self_collision_candidates_does_not_change_results() {
    let mut searches = Vec::new();
    let mut partial = Vec::new();
    let mut hashes = Vec::new();
    for reuse in [true, false] {
        let skips = CollisionSkips { reuse_self_pairs: reuse, ..Default::default() };
        // The layers fall onto the floor and settle: passes with and without movers.
        let (mut sim, _) = two_layers_placed(None, true, skips);
        let (mut full, mut movers) = (0, 0);
        for _ in 0..25 {
            let s = sim.step(1.0 / 30.0).unwrap();
            full += s.collision.self_searches;
            movers += s.collision.self_partial_searches;
        }
        searches.push(full);
        partial.push(movers);
        hashes.push(sim.state_hash());
    }
    println!(
        "self-collision searches in 25 frames: reused {} (and {} of the movers alone) / every pass {}",
        searches[0], partial[0], searches[1]
    );
    assert_eq!(hashes[0], hashes[1], "reusing candidates changed the result");
    assert!(searches[0] * 4 < searches[1], "{searches:?}");
    assert_eq!(partial[1], 0);
    assert!(partial[0] > 0, "no pass searched the movers alone: the path is untested here");
}

/// Four 0.1 m panels (5 × 5 cells) laid out as the quadrants of a square, 2 cm apart, sewn
/// along the four half-lines between them (lower left to lower right, lower right to upper
/// right, upper right to upper left, upper left to lower left), 6 cm above a single 0.3 m
/// sheet lying on a floor. Returns the simulation and the index of the first sewn particle.
fn four_panels_over_a_sheet(self_on: bool) -> (Simulation, usize) {
    let (n, side, gap) = (5usize, 0.1f32, 0.02f32);
    let (sp, sr, st) = cloth_grid(0.3, 15, 0.0, 0.0, 0.01);
    let (rest, tris) = tailor_core::scenes::rectangle(side, side, n, n);
    let mut pos = sp.clone();
    let mut all_rest = sr.clone();
    let mut all_tris = st.clone();
    let mut first = Vec::new();
    // Quadrant offsets: lower left, lower right, upper right, upper left.
    let half = 0.5 * gap + side;
    for (k, (ox, oy)) in
        [(-half, -half), (0.5 * gap, -half), (0.5 * gap, 0.5 * gap), (-half, 0.5 * gap)].into_iter().enumerate()
    {
        let base = pos.len() as u32;
        first.push(base);
        pos.extend(rest.iter().map(|r| [ox + r[0], oy + r[1], 0.07]));
        all_rest.extend(rest.iter().map(|r| [r[0] + 0.4 * (k + 1) as f32, r[1] + 1.0]));
        all_tris.extend(tris.iter().map(|t| t.map(|v| v + base)));
    }
    let n0 = first[0] as usize;
    let mut settings = SolverSettings::default();
    settings.ramp.closing_speed = 0.5;
    let mut sim = sim_of(pos, all_rest, all_tris, settings);
    let col = |p: usize, i: usize| -> Vec<u32> { grid_column(n, n, i).into_iter().map(|v| v + first[p]).collect() };
    let row = |p: usize, j: usize| -> Vec<u32> { (0..=n).map(|i| (j * (n + 1) + i) as u32 + first[p]).collect() };
    for (name, a, b) in [
        ("lower", col(0, n), col(1, 0)),
        ("right", row(1, n), row(2, 0)),
        ("upper", col(3, n), col(2, 0)),
        ("left", row(0, n), row(3, 0)),
    ] {
        sim.add_seam(Seam::one_to_one(name, &a, &b, 1e4, 1e-5).unwrap()).unwrap();
    }
    let (fv, ft) = plane_mesh(2.0, 10, Vec3::ZERO, Vec3::X, Vec3::Y);
    sim.add_mesh_collider(&fv, &ft, MeshColliderOptions::default()).unwrap();
    sim.set_self_collision(SelfCollisionSettings { enabled: self_on, ..Default::default() }).unwrap();
    for _ in 0..20 {
        sim.step(1.0 / 30.0).unwrap();
    }
    (sim, n0)
}

/// Where four pieces meet, the corner of each is sewn to its two neighbours' corners only, yet
/// all four close onto one point: the corners two seams apart (and their neighbours) must not
/// repel either, or they hold the junction open by about a sphere diameter. The sewn panels
/// still do not pass through the separate sheet they fall on.
#[test]
fn a_four_piece_junction_closes_with_self_collision_on_and_stays_off_the_sheet_below() {
    for self_on in [false, true] {
        let (sim, n0) = four_panels_over_a_sheet(self_on);
        let (gap, _) = sim.seam_gaps();
        let x = sim.positions().to_aos();
        // Sheet against panels: all intersecting pairs less the panels' own (the sheet is flat);
        // the closed seams' triangles touch, and count among the panels' own.
        let tris = sim.model().mesh.triangles();
        let panels: Vec<[u32; 3]> = tris.iter().copied().filter(|t| t[0] as usize >= n0).collect();
        let crossings = count_self_intersections(&x, tris).unwrap() - count_self_intersections(&x, &panels).unwrap();
        let (lo, hi) = layer_heights(&sim, n0);
        let r = sim.self_collision_radius();
        println!(
            "self-collision {self_on}: seam gap {:.3} mm, sheet / panels at {lo:.4} / {hi:.4} m (radius {r:.4}), \
             {crossings} sheet-panel intersecting pairs",
            gap * 1e3
        );
        assert!(gap < 1e-3, "self-collision {self_on}: the junction stays {:.2} mm open", gap * 1e3);
        if self_on {
            assert_eq!(crossings, 0, "the sewn panels cross the sheet");
            assert!(hi - lo > 1.5 * r, "panels not on the sheet: {lo} / {hi}");
        }
    }
}
