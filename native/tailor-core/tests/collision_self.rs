//! Cloth-cloth collisions, with both contact models (spheres, particles against triangles):
//! two stacked layers falling on a floor stay apart, collision levels switch the layers'
//! collision on and off, a four-piece junction closes, a layer thrown fast does not pass
//! through another, and the candidate lists change nothing but time.

mod collision_common;

use collision_common::*;
use glam::Vec3;
use tailor_core::quality::metrics::count_self_intersections;
use tailor_core::scenes::grid_column;
use tailor_core::solver::{
    CollisionSkips, MeshColliderOptions, Seam, SelfCollisionSettings, SelfContacts, Simulation, SolverSettings,
};

fn self_settings(on: bool, contacts: SelfContacts) -> SelfCollisionSettings {
    SelfCollisionSettings { enabled: on, contacts, ..Default::default() }
}

/// Two 0.4 m layers of 16 × 16 cells, 4 cm apart (the upper one shifted by a third of a cell,
/// so its particles are not above the lower ones'), in one cloth, falling on a floor mesh.
fn two_layers(levels: Option<(i32, i32)>, self_on: bool, contacts: SelfContacts) -> (Simulation, usize) {
    let (mut sim, n0) = two_layers_placed(levels, self_settings(self_on, contacts), CollisionSkips::default());
    for _ in 0..24 {
        sim.step(1.0 / 30.0).unwrap();
    }
    (sim, n0)
}

/// The two layers as placed, before any step.
fn two_layers_placed(
    levels: Option<(i32, i32)>,
    own: SelfCollisionSettings,
    skips: CollisionSkips,
) -> (Simulation, usize) {
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
    sim.set_self_collision(own).unwrap();
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

/// The distance the layers must keep: two sphere radii, or the triangles' thickness (both
/// less a little for the averaging of corrections and the floor's own give).
fn kept_apart(sim: &Simulation, contacts: SelfContacts) -> f32 {
    let r = sim.self_collision_radius();
    match contacts {
        SelfContacts::Spheres => 1.5 * r,
        SelfContacts::Triangles => 0.9 * r,
    }
}

#[test]
fn stacked_layers_fall_on_a_floor_and_stay_apart() {
    for contacts in SelfContacts::ALL {
        let (sim, n0) = two_layers(None, true, contacts);
        let x = sim.positions().to_aos();
        let crossings = count_self_intersections(&x, sim.model().mesh.triangles()).unwrap();
        let (lo, hi) = layer_heights(&sim, n0);
        let r = sim.self_collision_radius();
        println!("{contacts:?}: mean heights {lo:.4} / {hi:.4} m, radius {r:.4} m, {crossings} intersecting pairs");
        assert_eq!(crossings, 0, "{contacts:?}: the layers intersect");
        assert!(lo < 0.01 && hi - lo > kept_apart(&sim, contacts), "{contacts:?}: layers not stacked: {lo} / {hi}");
        let m = sim.metrics(None).unwrap();
        assert_eq!(m.self_intersections, 0);
    }
}

/// Upper-layer particles below a lower-layer triangle they are over (in plan): particles that
/// passed through the lower layer.
fn particles_through(x: &[[f32; 3]], tris: &[[u32; 3]], n0: usize) -> usize {
    let lower: Vec<[Vec3; 3]> =
        tris.iter().filter(|t| (t[0] as usize) < n0).map(|t| t.map(|v| Vec3::from(x[v as usize]))).collect();
    x[n0..]
        .iter()
        .filter(|p| {
            let p = Vec3::from(**p);
            lower.iter().any(|&[a, b, c]| {
                // Barycentrics in plan, then the triangle's height there.
                let d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
                let u = ((b.x - p.x) * (c.y - p.y) - (c.x - p.x) * (b.y - p.y)) / d;
                let v = ((c.x - p.x) * (a.y - p.y) - (a.x - p.x) * (c.y - p.y)) / d;
                let w = 1.0 - u - v;
                u >= 0.0 && v >= 0.0 && w >= 0.0 && p.z < u * a.z + v * b.z + w * c.z
            })
        })
        .count()
}

/// The upper layer thrown down at 3 m/s from 1.5 cm above the lower one (lying on the floor):
/// it travels 12.5 mm a substep, three times the triangles' thickness, past the lower layer's
/// particles between two iterations. Particles against triangles keep the side each particle
/// started its substep on, so no particle passes through the other layer; with the spheres
/// (diameter the mean edge, 2.5 cm) the layer is stopped by a thicker shell.
///
/// What particle-triangle contacts do not cover: two edges crossing with every particle on
/// its side. At the impact the lower layer's free border (outside the upper layer, which is
/// shifted by a third of a cell) flaps up round the upper layer's edge: three pairs of
/// triangles cross in the first frame, none from the second on (measured; edge-edge contacts
/// are not built).
#[test]
fn a_layer_thrown_fast_does_not_pass_through_another() {
    for contacts in SelfContacts::ALL {
        let (mut sim, n0) = two_layers_placed(None, self_settings(true, contacts), CollisionSkips::default());
        let mut x = sim.positions().to_aos();
        for p in &mut x[..n0] {
            p[2] = 0.004;
        }
        for p in &mut x[n0..] {
            p[2] = 0.019;
        }
        sim.set_positions(&x).unwrap();
        let v: Vec<[f32; 3]> = (0..x.len()).map(|i| if i < n0 { [0.0; 3] } else { [0.0, 0.0, -3.0] }).collect();
        sim.set_velocities(&v).unwrap();
        let (mut through, mut crossings) = (0, Vec::new());
        for _ in 0..10 {
            sim.step(1.0 / 30.0).unwrap();
            through = through.max(particles_through(&sim.positions().to_aos(), sim.model().mesh.triangles(), n0));
            crossings.push(sim.metrics(None).unwrap().self_intersections);
        }
        let (lo, hi) = layer_heights(&sim, n0);
        println!(
            "{contacts:?}: thrown layer at {hi:.4} m over {lo:.4} m, {through} particles through at worst, \
             intersecting pairs per frame {crossings:?}"
        );
        assert_eq!(through, 0, "{contacts:?}: particles of the thrown layer passed through");
        assert!(crossings[1..].iter().all(|&c| c == 0), "{contacts:?}: the layers stay crossed: {crossings:?}");
        // Apart by at least the triangles' 4 mm (the spheres are squashed by the impact).
        assert!(hi - lo > 0.0035, "{contacts:?}: {lo} / {hi}");
    }
}

/// Levels 1 and 2 do not collide: the upper layer falls through the lower onto the floor.
/// Levels 1 and 1 (and 0 with 2) do.
#[test]
fn levels_switch_cloth_cloth_collisions_both_ways() {
    for contacts in SelfContacts::ALL {
        for (levels, collide) in [((1, 2), false), ((1, 1), true), ((0, 2), true)] {
            let (sim, n0) = two_layers(Some(levels), true, contacts);
            let (lo, hi) = layer_heights(&sim, n0);
            println!("{contacts:?}, levels {levels:?}: mean heights {lo:.4} / {hi:.4} m");
            if collide {
                assert!(hi - lo > 0.0035, "{contacts:?}, levels {levels:?} should keep the layers apart: {lo} / {hi}");
            } else {
                assert!((hi - lo).abs() < 0.003, "{contacts:?}, levels {levels:?} should let the layers through");
            }
        }
    }
    // Self-collision off: the same as non-colliding levels.
    let (sim, n0) = two_layers(None, false, SelfContacts::Spheres);
    let (lo, hi) = layer_heights(&sim, n0);
    assert!((hi - lo).abs() < 0.003, "self-collision off should let the layers through: {lo} / {hi}");
}

/// Keeping the self-collision candidates (searched with a margin) across passes, with the
/// pairs of the particles that moved too far searched alone (`self_movers.rs`), gives
/// bit-identical positions to a hash search every pass, with far fewer searches.
#[test]
fn reusing_self_collision_candidates_does_not_change_results() {
    reusing_candidates_does_not_change_results(SelfContacts::Spheres);
}

/// The same for the triangles' list (kept while every particle moved less than half the
/// margin, the cloth's common translation taken out; the movers' pairs searched alone).
#[test]
fn reusing_triangle_contact_candidates_does_not_change_results() {
    reusing_candidates_does_not_change_results(SelfContacts::Triangles);
}

fn reusing_candidates_does_not_change_results(contacts: SelfContacts) {
    let mut searches = Vec::new();
    let mut partial = Vec::new();
    let mut hashes = Vec::new();
    for reuse in [true, false] {
        let skips = CollisionSkips { reuse_self_pairs: reuse, ..Default::default() };
        // The layers fall onto the floor and settle: passes with and without movers.
        let (mut sim, _) = two_layers_placed(None, self_settings(true, contacts), skips);
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
        "{contacts:?}: self-collision searches in 25 frames: reused {} (and {} of the movers alone) / every pass {}",
        searches[0], partial[0], searches[1]
    );
    assert_eq!(hashes[0], hashes[1], "{contacts:?}: reusing candidates changed the result");
    assert!(searches[0] * 4 < searches[1], "{searches:?}");
    assert_eq!(partial[1], 0);
    assert!(partial[0] > 0, "{contacts:?}: no pass searched the movers alone: the path is untested here");
}

/// A 0.4 m sheet lying on the floor and a 7.5 cm patch (16 of the 305 particles) 6 cm above it,
/// thrown down at 2 m/s: a few particles moving fast towards cloth that does not move.
fn patch_thrown_on_a_sheet(own: SelfCollisionSettings, skips: CollisionSkips) -> Simulation {
    let (p0, r0, t0) = cloth_grid(0.4, 16, 0.0, 0.0, 0.004);
    let (p1, r1, t1) = cloth_grid(0.075, 3, 0.0083, 0.0083, 0.064);
    let n0 = p0.len();
    let pos: Vec<[f32; 3]> = p0.iter().chain(&p1).copied().collect();
    let rest: Vec<[f32; 2]> = r0.iter().copied().chain(r1.iter().map(|r| [r[0] + 1.0, r[1]])).collect();
    let tris: Vec<[u32; 3]> = t0.iter().copied().chain(t1.iter().map(|t| t.map(|v| v + n0 as u32))).collect();
    let mut sim = sim_of(pos, rest, tris, SolverSettings::default());
    let (fv, ft) = plane_mesh(2.0, 10, Vec3::ZERO, Vec3::X, Vec3::Y);
    sim.add_mesh_collider(&fv, &ft, MeshColliderOptions::default()).unwrap();
    sim.set_self_collision(own).unwrap();
    sim.set_collision_skips(skips);
    let v: Vec<[f32; 3]> = (0..sim.num_particles()).map(|i| if i < n0 { [0.0; 3] } else { [0.0, 0.0, -2.0] }).collect();
    sim.set_velocities(&v).unwrap();
    sim
}

/// The triangles' list when a few particles move fast and the rest not at all: the patch's
/// particles are the movers, their pairs with the sheet's triangles are searched alone (the
/// full search found none: the patch was 6 cm above), and they stop it on the sheet. Bit for
/// bit a search every pass.
#[test]
fn the_movers_pairs_alone_give_the_result_of_a_search_every_pass() {
    let own = self_settings(true, SelfContacts::Triangles);
    let mut runs = Vec::new();
    for reuse in [true, false] {
        let skips = CollisionSkips { reuse_self_pairs: reuse, ..Default::default() };
        let mut sim = patch_thrown_on_a_sheet(own, skips);
        let (mut full, mut partial) = (0, 0);
        for _ in 0..6 {
            let s = sim.step(1.0 / 30.0).unwrap();
            full += s.collision.self_searches;
            partial += s.collision.self_partial_searches;
        }
        let x = sim.positions().to_aos();
        let crossings = count_self_intersections(&x, sim.model().mesh.triangles()).unwrap();
        let patch_low = x[289..].iter().map(|p| p[2]).fold(f32::INFINITY, f32::min);
        runs.push((full, partial, crossings, patch_low, sim.state_hash()));
    }
    println!(
        "patch: (searches, movers alone, crossings, patch's lowest z, state) reused {:?} / every pass {:?}",
        runs[0], runs[1]
    );
    assert_eq!(runs[0].4, runs[1].4, "searching the movers alone changed the result");
    assert!(runs[0].1 > 0 && runs[0].0 * 4 < runs[1].0, "{runs:?}");
    assert_eq!(runs[0].2, 0, "the patch passed through the sheet");
    assert!(runs[0].3 > 0.006, "the patch is not on the sheet: {runs:?}");
}

/// Four 0.1 m panels (5 × 5 cells) laid out as the quadrants of a square, 2 cm apart, sewn
/// along the four half-lines between them (lower left to lower right, lower right to upper
/// right, upper right to upper left, upper left to lower left), 6 cm above a single 0.3 m
/// sheet lying on a floor. Returns the simulation and the index of the first sewn particle.
fn four_panels_over_a_sheet(own: SelfCollisionSettings) -> (Simulation, usize) {
    let (mut sim, n0) = four_panels_placed(own, CollisionSkips::default());
    for _ in 0..20 {
        sim.step(1.0 / 30.0).unwrap();
    }
    (sim, n0)
}

/// The four panels and the sheet as placed, before any step.
fn four_panels_placed(own: SelfCollisionSettings, skips: CollisionSkips) -> (Simulation, usize) {
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
    sim.set_self_collision(own).unwrap();
    sim.set_collision_skips(skips);
    (sim, n0)
}

/// Where four pieces meet, the corner of each is sewn to its two neighbours' corners only, yet
/// all four close onto one point: the corners two seams apart (and their neighbours) must not
/// repel either, or they hold the junction open by about a sphere diameter. The sewn panels
/// still do not pass through the separate sheet they fall on.
#[test]
fn a_four_piece_junction_closes_with_self_collision_on_and_stays_off_the_sheet_below() {
    let runs = [(false, SelfContacts::Spheres), (true, SelfContacts::Spheres), (true, SelfContacts::Triangles)];
    for (self_on, contacts) in runs {
        let (sim, n0) = four_panels_over_a_sheet(self_settings(self_on, contacts));
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
            "self-collision {self_on} ({contacts:?}): seam gap {:.3} mm, sheet / panels at {lo:.4} / {hi:.4} m \
             (radius {r:.4}), {crossings} sheet-panel intersecting pairs",
            gap * 1e3
        );
        assert!(gap < 1e-3, "self-collision {self_on} ({contacts:?}): the junction stays {:.2} mm open", gap * 1e3);
        if self_on {
            assert_eq!(crossings, 0, "{contacts:?}: the sewn panels cross the sheet");
            assert!(hi - lo > kept_apart(&sim, contacts), "{contacts:?}: panels not on the sheet: {lo} / {hi}");
        }
    }
}
