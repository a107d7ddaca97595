//! Mesh colliders in the solver: resting on still meshes, a fast spinning mesh checked at
//! every substep, Coulomb friction on an incline, collision levels, insertion rules, skips
//! and bad input.

mod collision_common;

use collision_common::*;
use glam::Vec3;
use tailor_core::collision::InsertionRule;
use tailor_core::solver::{
    ColliderId, CollisionSkips, MeshColliderOptions, SelfCollisionSettings, Simulation, SolverSettings,
};
use tailor_core::TailorError;

const FPS: f32 = 30.0;

fn run(sim: &mut Simulation, frames: usize) {
    for _ in 0..frames {
        sim.step(1.0 / FPS).unwrap();
    }
}

fn lowest_z(sim: &Simulation) -> f32 {
    sim.positions().z.iter().copied().fold(f32::INFINITY, f32::min)
}

/// A 0.8 m cloth dropped on a 1280-triangle sphere of radius 0.3 m drapes over it: the top
/// particle rests at the radius plus the thickness and none is inside.
#[test]
fn cloth_rests_on_a_sphere_mesh() {
    let (sv, st) = icosphere(3, 0.3, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.8, 24, 0.0, 0.0, 0.36);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
    let mut worst = 0.0f32;
    for _ in 0..45 {
        sim.step(1.0 / FPS).unwrap();
        worst = worst.max(max_depth(&sim, &sv, &st));
    }
    let top = sim.positions().z[12 * 25 + 12];
    println!("sphere: top particle z {top:.4} m, deepest particle {worst:.2e} m");
    assert!(worst <= 1e-3, "a particle went {worst} m inside the sphere");
    assert!((top - 0.303).abs() < 0.01, "top particle at {top}, not resting on the sphere");
    let m = sim.metrics(Some(id)).unwrap();
    assert!(m.penetration_max_depth <= 1e-3);
}

/// Same on a 12-triangle box (triangles much larger than typical cells): the cloth rests on
/// its top face.
#[test]
fn cloth_rests_on_a_box_mesh() {
    let (bv, bt) = box_mesh(0.2, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.7, 21, 0.0, 0.0, 0.26);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
    let mut worst = 0.0f32;
    for _ in 0..45 {
        sim.step(1.0 / FPS).unwrap();
        worst = worst.max(max_depth(&sim, &bv, &bt));
    }
    let centre = sim.positions().z[10 * 22 + 10];
    println!("box: centre particle z {centre:.4} m, deepest particle {worst:.2e} m");
    assert!(worst <= 1e-3, "a particle went {worst} m inside the box");
    assert!((centre - 0.203).abs() < 0.01, "centre particle at {centre}");
}

/// Alg. 1 alone loses large triangles' interiors: with 10 cm cells a two-triangle floor 4 m
/// wide is missing from the cells under the cloth, which falls through; with the plane cells
/// (the default rule) it rests on the floor.
#[test]
fn paper_rule_misses_large_triangles_and_the_default_rule_does_not() {
    let floor =
        (vec![[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]], vec![[0, 1, 2], [0, 2, 3]]);
    let mut z = Vec::new();
    for rule in [InsertionRule::Paper, InsertionRule::PaperOrPlane] {
        let (p, r, t) = cloth_grid(0.3, 10, 0.13, 0.17, 0.05);
        let mut sim = sim_of(p, r, t, SolverSettings::default());
        let opts = MeshColliderOptions { cell_size: Some(0.1), rule, ..Default::default() };
        sim.add_mesh_collider(&floor.0, &floor.1, opts).unwrap();
        run(&mut sim, 20);
        z.push(lowest_z(&sim));
    }
    println!("lowest particle: paper rule {:.3} m, paper-or-plane {:.4} m", z[0], z[1]);
    assert!(z[0] < -0.1, "expected the paper rule to lose the floor");
    assert!(z[1] > 0.0, "the default rule let the cloth through");
}

/// A sphere spinning at 2 turns per second about a horizontal axis (its vertices move up to
/// 3.8 m/s, 12.6 cm per frame) with the cloth draped on it: at every substep no particle is
/// more than 1 mm inside the collider at that substep's interpolated positions.
#[test]
fn cloth_stays_outside_a_fast_spinning_sphere_at_every_substep() {
    let (sv, st) = icosphere(2, 0.3, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.7, 20, 0.0, 0.0, 0.33);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
    let omega = 2.0 * std::f32::consts::TAU;
    let mut worst = 0.0f32;
    let mut checked = 0;
    for frame in 1..=40 {
        let rot = glam::Quat::from_rotation_x(omega * frame as f32 / FPS);
        let moved: Vec<[f32; 3]> = sv.iter().map(|v| (rot * Vec3::from(*v)).into()).collect();
        sim.set_collider_positions(id, &moved).unwrap();
        sim.step_observed(1.0 / FPS, |_, s| {
            let (cv, ct) = (s.collider_positions(id).unwrap(), s.collider_triangles(id).unwrap());
            worst = worst.max(max_depth(s, cv, ct));
            checked += 1;
        })
        .unwrap();
    }
    println!("spinning sphere: deepest particle over {checked} substeps {worst:.2e} m");
    assert_eq!(checked, 40 * SolverSettings::default().substeps);
    assert!(worst <= 1e-3, "a particle went {worst} m inside the spinning sphere");
}

/// A small patch thrown at a sphere of 1 cm triangles (1 cm hash cells) so fast that one
/// substep takes it from 8 mm outside to far inside, along an axis and along the diagonal: it
/// ends every substep outside, on the side it came from. The particle-vs-cell test sees
/// nothing there (the cells deep inside hold no triangle), so only the crossing test of the
/// substep's motion can put it back; a 7 cm diagonal move spans 5 × 5 × 5 cells of the
/// segment's box, and the crossing test once gave up on boxes over 27 cells (the layered
/// sample's hoody went 36 mm into the arm in one such substep while its side seam closed).
#[test]
fn a_fast_particle_goes_back_out_on_its_side_however_far_it_moved() {
    let r = 0.15;
    let (sv, st) = icosphere(4, r, Vec3::ZERO);
    for dir in [Vec3::X, Vec3::ONE.normalize(), Vec3::new(-1.0, 0.5, -0.8).normalize()] {
        for travel in [0.03f32, 0.07, 0.12] {
            let (p0, rest, tris) = cloth_grid(0.004, 1, 0.0, 0.0, 0.0);
            let start = dir * (r + 0.008);
            let pos: Vec<[f32; 3]> = p0.iter().map(|p| (Vec3::from(*p) + start).into()).collect();
            let settings = SolverSettings { substeps: 1, gravity: [0.0; 3], ..Default::default() };
            let mut sim = sim_of(pos, rest, tris, settings);
            let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
            let h = 1.0 / 240.0;
            let v: [f32; 3] = (-dir * (travel / h)).into();
            sim.set_velocities(&vec![v; sim.num_particles()]).unwrap();
            sim.step(h).unwrap();
            let depth = max_depth(&sim, &sv, &st);
            let x = sim.positions();
            let side = (0..x.len()).map(|i| x.get(i).dot(dir)).fold(f32::INFINITY, f32::min);
            let m = sim.metrics(Some(id)).unwrap();
            println!(
                "dir {dir:.2} travel {:.0} mm: deepest {:.2} mm, nearest approach along dir {:.1} mm from the centre",
                travel * 1e3,
                depth * 1e3,
                side * 1e3
            );
            assert!(depth <= 1e-3, "thrown {travel} m along {dir}: a particle ended {depth} m inside");
            assert!(side > 0.9 * r, "thrown {travel} m along {dir}: pushed out on the far side ({side} m)");
            assert_eq!(m.penetration_count, 0);
        }
    }
}

/// A 20 cm block with a narrow V groove cut into its top (2 cm wide, 10 cm deep, apex on the
/// y axis at z = 0): two faces meeting at an acute crease, as an arm's underside meets the
/// chest at the armpit. Outward triangles, closed.
fn grooved_block() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    // The profile in (x, z), counter-clockwise, extruded along y over ±10 cm.
    let profile = [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [0.01, 0.1], [0.0, 0.0], [-0.01, 0.1], [-0.1, 0.1]];
    let h = 0.1f32;
    let n = profile.len() as u32;
    let mut v: Vec<[f32; 3]> = profile.iter().map(|p| [p[0], -h, p[1]]).collect();
    v.extend(profile.iter().map(|p| [p[0], h, p[1]]));
    let mut t = Vec::new();
    for k in 0..n {
        let (p0, q0, p1, q1) = (k, (k + 1) % n, k + n, (k + 1) % n + n);
        t.push([p0, q1, q0]);
        t.push([p0, p1, q1]);
    }
    // Caps: the groove splits the profile into a bottom triangle and the two sides.
    for [a, b, c] in [[0, 1, 4], [1, 2, 3], [1, 3, 4], [0, 4, 5], [0, 5, 6]] {
        t.push([a, b, c]);
        t.push([a + n, c + n, b + n]);
    }
    (v, t)
}

/// A patch driven down a narrow groove and into one of its faces, below the crease's apex:
/// the crossing resolve pushes it back along that face's normal, keeping its motion along the
/// face, which lands it behind the other face (inside the block, 9 mm from the surface). A
/// correction must not leave a particle behind a surface its path from the substep's start
/// crossed, so there it stays where the substep began, in the groove. (The particle-vs-cell
/// test does not see it: it is in front of the other face's triangles in its cell.) The
/// layered sample's hoody went 37 mm into the chest this way at the armpit.
#[test]
fn a_push_out_of_one_face_of_a_crease_does_not_land_behind_the_other() {
    let (bv, bt) = grooved_block();
    let closed = tailor_core::collision::ClosedMesh::new(&bv, &bt).unwrap();
    let inside = closed.penetration(&[[0.0, 0.0, -0.05], [0.0, 0.0, 0.05], [0.05, 0.0, 0.05]]);
    assert_eq!(inside.count, 2, "the block is not closed and outward");
    let (p0, rest, tris) = cloth_grid(0.001, 1, 0.0, 0.0, 0.05);
    let settings = SolverSettings { substeps: 1, gravity: [0.0; 3], ..Default::default() };
    let mut sim = sim_of(p0.clone(), rest, tris, settings);
    sim.set_thickness(0.002).unwrap();
    let opts = MeshColliderOptions { cell_size: Some(0.01), ..Default::default() };
    sim.add_mesh_collider(&bv, &bt, opts).unwrap();
    // From 5 cm up the groove's middle to 6 mm right of and 1 cm below the apex, in one
    // substep: through the right face, ending in front of the left face's plane.
    let h = 1.0 / 240.0;
    let v = [0.006 / h, 0.0, -0.06 / h];
    sim.set_velocities(&vec![v; sim.num_particles()]).unwrap();
    sim.step(h).unwrap();
    let depth = max_depth(&sim, &bv, &bt);
    let x = sim.positions();
    println!("groove: deepest {:.2} mm, particle 0 at {:?}", depth * 1e3, x.get(0));
    assert!(depth <= 1e-4, "a particle ended {depth} m inside the block");
}

/// Distance a small cloth slides in 1 s down a 20° incline mesh (tan 20° = 0.364).
fn slide(mu_s: f32, mu_k: f32, per_particle: bool) -> f32 {
    let angle = 20f32.to_radians();
    let down = Vec3::new(0.0, -angle.cos(), -angle.sin()); // down the slope
    let u = Vec3::X;
    let w = -down; // up the slope; normal u × w points up and out of the slope
    let (pv, pt) = plane_mesh(4.0, 20, Vec3::ZERO, u, w);
    let n = u.cross(w);
    let (p0, r, t) = cloth_grid(0.2, 8, 0.0, 0.0, 0.0);
    // Lay the cloth on the slope, 3 mm (the thickness) above it.
    let pos: Vec<[f32; 3]> = p0.iter().map(|p| (u * p[0] + w * p[1] + n * 0.003).into()).collect();
    let settings = SolverSettings { air_damping: 0.0, ..Default::default() };
    let mut sim = sim_of(pos.clone(), r, t, settings);
    let opts = if per_particle {
        MeshColliderOptions { static_friction: 2.0, kinetic_friction: 2.0, ..Default::default() }
    } else {
        MeshColliderOptions { static_friction: mu_s, kinetic_friction: mu_k, ..Default::default() }
    };
    sim.add_mesh_collider(&pv, &pt, opts).unwrap();
    if per_particle {
        let k = sim.num_particles();
        sim.set_particle_friction(Some((&vec![mu_s; k], &vec![mu_k; k]))).unwrap();
    }
    run(&mut sim, 30);
    let x = sim.positions();
    (0..x.len()).map(|i| (x.get(i) - Vec3::from(pos[i])).dot(down)).sum::<f32>() / x.len() as f32
}

/// Static friction above tan θ holds the cloth; below, it slides with the kinetic
/// acceleration g (sin θ − μk cos θ), here about 0.98 m in the first second. Per-particle
/// coefficients override the collider's.
#[test]
fn friction_on_an_incline_sticks_or_slides_by_the_coefficients() {
    let stick = slide(0.5, 0.4, false);
    let slip = slide(0.25, 0.15, false);
    let slip_pp = slide(0.25, 0.15, true);
    let stick_pp = slide(0.5, 0.4, true);
    let angle = 20f32.to_radians();
    let expected = 0.5 * 9.81 * (angle.sin() - 0.15 * angle.cos());
    println!(
        "incline: μs 0.5 → {stick:.4} m; μs 0.25 μk 0.15 → {slip:.3} m (analytic {expected:.3}); per particle {slip_pp:.3} / {stick_pp:.4}"
    );
    assert!(stick.abs() < 0.01, "static friction above tan θ should hold: slid {stick} m");
    assert!(stick_pp.abs() < 0.01, "per-particle static friction should hold: slid {stick_pp} m");
    assert!((slip - expected).abs() < 0.25 * expected, "slid {slip} m, expected about {expected}");
    assert!((slip_pp - slip).abs() < 1e-3, "per-particle coefficients differ from equal collider ones");
}

/// Levels: a cloth of level 1 falls through a sphere of level 2 and rests on one of level 1
/// or 0; a cloth of level 0 rests on any.
#[test]
fn collision_levels_select_what_collides() {
    let (sv, st) = icosphere(2, 0.2, Vec3::ZERO);
    let mut ends = Vec::new();
    for (cloth_level, sphere_level, collides) in
        [(1, 2, false), (1, 1, true), (1, 0, true), (0, 2, true), (2, 1, false)]
    {
        let (p, r, t) = cloth_grid(0.3, 10, 0.0, 0.0, 0.25);
        let mut sim = sim_of(p, r, t, SolverSettings::default());
        let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
        sim.set_collider_levels(id, &vec![sphere_level; sv.len()]).unwrap();
        sim.set_particle_levels(&vec![cloth_level; sim.num_particles()]).unwrap();
        run(&mut sim, 20);
        let top = sim.positions().z[5 * 11 + 5];
        ends.push(top);
        if collides {
            assert!(top > 0.19, "levels {cloth_level}/{sphere_level} should collide: top at {top}");
        } else {
            assert!(top < -0.2, "levels {cloth_level}/{sphere_level} should not collide: top at {top}");
        }
    }
    println!("levels: centre particle z per case {ends:?}");
}

/// Skips change nothing: a still collider's hash reused for every substep gives bit-identical
/// positions to a hash rebuilt every substep, and culling far triangles does not change a
/// moving collider's result either.
#[test]
fn skips_do_not_change_results() {
    let (sv, st) = icosphere(3, 0.3, Vec3::ZERO);
    let run_with = |skips: CollisionSkips, moving: bool| {
        let (p, r, t) = cloth_grid(0.5, 14, 0.05, 0.0, 0.35);
        let mut sim = sim_of(p, r, t, SolverSettings::default());
        sim.set_collision_skips(skips);
        // A second, far collider that culling removes entirely.
        let (fv, ft) = icosphere(2, 0.2, Vec3::new(5.0, 0.0, 0.0));
        sim.add_mesh_collider(&fv, &ft, MeshColliderOptions::default()).unwrap();
        let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
        let mut st_sum = (0, 0, 0);
        for f in 1..=15 {
            if moving {
                let off = Vec3::new(0.0, 0.01 * f as f32, 0.0);
                let m: Vec<[f32; 3]> = sv.iter().map(|v| (Vec3::from(*v) + off).into()).collect();
                sim.set_collider_positions(id, &m).unwrap();
            }
            let s = sim.step(1.0 / FPS).unwrap();
            st_sum = (st_sum.0 + s.collision.rebuilds, st_sum.1 + s.collision.reuses, s.collision.triangles_culled);
        }
        (sim.state_hash(), st_sum)
    };
    let all = CollisionSkips::default();
    let (h_reuse, s_reuse) = run_with(all, false);
    let (h_rebuild, s_rebuild) = run_with(CollisionSkips { reuse_collider_hashes: false, ..all }, false);
    println!("still: reuse {s_reuse:?}, forced rebuild {s_rebuild:?}");
    assert_eq!(h_reuse, h_rebuild, "reusing a still collider's hash changed the result");
    assert!(s_reuse.1 > 100 && s_rebuild.1 == 0, "the skip did not happen: {s_reuse:?}");
    let (h_frame, s_frame) = run_with(all, true);
    let (h_substeps, s_substeps) = run_with(CollisionSkips { reuse_collider_hashes: false, ..all }, true);
    println!("moving: one build a frame {s_frame:?}, one a substep {s_substeps:?}");
    assert_eq!(h_frame, h_substeps, "filing a moving collider once a frame changed the result");
    assert!(s_frame.0 < s_substeps.0 && s_frame.1 > 0, "the moving collider's hash was not kept: {s_frame:?}");
    let (h_cull, s_cull) = run_with(all, true);
    let (h_nocull, _) = run_with(CollisionSkips { cull_far_triangles: false, ..all }, true);
    println!("moving: culling {s_cull:?}");
    assert_eq!(h_cull, h_nocull, "culling far triangles changed the result");
    assert!(s_cull.2 > 320, "the far collider was not culled: {s_cull:?}");
    let (h_all, _) = run_with(all, true);
    let (h_test_all, _) = run_with(CollisionSkips { mesh_broad_phase: false, ..all }, true);
    assert_eq!(h_all, h_test_all, "the iterations' broad phase changed the result");
}

/// The iterations' broad phase against mesh colliders is exact (`mesh_broad_phase.rs`): a
/// particle skipped because it stayed free within its radius, or tested against its nearest
/// candidate alone, gets the answer the full test would give. On a cloth draped over a moving
/// sphere, where some particles rest on it and others hover, testing every candidate of every
/// particle in every iteration gives the same positions bit for bit, while the broad phase
/// spares most of the full tests.
#[test]
fn the_mesh_broad_phase_spares_tests_without_changing_contacts() {
    let (sv, st) = icosphere(3, 0.3, Vec3::ZERO);
    let run_with = |broad: bool| {
        let (p, r, t) = cloth_grid(0.8, 24, 0.05, 0.0, 0.33);
        let mut sim = sim_of(p, r, t, SolverSettings::default());
        sim.set_collision_skips(CollisionSkips { mesh_broad_phase: broad, ..Default::default() });
        let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
        let (mut n, mut contacts) = ([0u64; 3], 0usize);
        for f in 1..=30 {
            let off = Vec3::new(0.004 * f as f32, 0.0, 0.002 * (f as f32 * 0.7).sin());
            let m: Vec<[f32; 3]> = sv.iter().map(|v| (Vec3::from(*v) + off).into()).collect();
            sim.set_collider_positions(id, &m).unwrap();
            let s = sim.step(1.0 / FPS).unwrap();
            n[0] += s.collision.contact_tests;
            n[1] += s.collision.contact_skips;
            n[2] += s.collision.contact_nearest;
            contacts = contacts.max(s.collision.mesh_contacts);
        }
        let per_particle = sim.memory_bytes() as f64 / sim.num_particles() as f64;
        (sim.state_hash(), n, contacts, per_particle)
    };
    let (h_broad, [tests, skips, nearest], contacts, bytes) = run_with(true);
    let (h_all, [all_tests, all_skips, all_nearest], _, _) = run_with(false);
    println!(
        "broad phase: {tests} full tests, {skips} skipped, {nearest} from the shortlists, up to {contacts} \
         contacts; without: {all_tests} full tests; state {bytes:.0} B per particle"
    );
    // The memory budget holds with the shortlists and the rest of the collision state counted.
    assert!(bytes < 1024.0, "the solver's state takes {bytes:.0} B per particle, over 1 KB");
    assert_eq!(h_broad, h_all, "the broad phase changed the result");
    assert_eq!((all_skips, all_nearest), (0, 0));
    assert_eq!(tests + skips + nearest, all_tests, "both runs test the same particle-iterations");
    assert!(contacts > 100, "the scene has too few contacts to mean anything ({contacts})");
    assert!(tests < all_tests / 3, "the broad phase spared only {} of {all_tests} full tests", all_tests - tests);
    // The budget holds with the two-level step's coarse grid too (the aggregates, the map of
    // the fine matrix's entries onto the coarse one, the residual).
    let (p, r, t) = cloth_grid(0.8, 24, 0.05, 0.0, 0.33);
    let mut sim = sim_of(p, r, t, SolverSettings { two_level: true, ..Default::default() });
    sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
    for _ in 0..3 {
        sim.step(1.0 / FPS).unwrap();
    }
    let two_level = sim.memory_bytes() as f64 / sim.num_particles() as f64;
    println!("with the two-level step: {two_level:.0} B per particle");
    assert!(two_level < 1024.0, "with the two-level step the state takes {two_level:.0} B per particle");
    assert!(skips > 0 && nearest > 0, "one kind of reuse never happened: {skips} skipped, {nearest} from shortlists");
}

#[test]
fn bad_collider_input_is_refused_with_typed_errors() {
    let (p, r, t) = cloth_grid(0.2, 4, 0.0, 0.0, 0.0);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let v = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let o = MeshColliderOptions::default();
    let e = sim.add_mesh_collider(&v, &[[0, 1, 3]], o).unwrap_err();
    assert!(matches!(e, TailorError::IndexOutOfRange { index: 3, .. }), "{e}");
    let e = sim.add_mesh_collider(&[], &[], o).unwrap_err();
    assert!(matches!(e, TailorError::EmptyMesh { .. }), "{e}");
    let e = sim.add_mesh_collider(&[[f32::NAN; 3], v[1], v[2]], &[[0, 1, 2]], o).unwrap_err();
    assert!(matches!(e, TailorError::NonFinite { .. }), "{e}");
    let e = sim.add_mesh_collider(&v, &[[0, 0, 0]], o).unwrap_err();
    assert!(matches!(e, TailorError::EmptyMesh { .. }), "only degenerate triangles: {e}");
    let e = sim.add_mesh_collider(&v, &[[0, 1, 2]], MeshColliderOptions { static_friction: -1.0, ..o }).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSetting { .. }), "{e}");
    let e = sim.add_mesh_collider(&v, &[[0, 1, 2]], MeshColliderOptions { cell_size: Some(1e-5), ..o }).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSetting { name: "cell_size", .. }), "{e}");
    // Degenerate and duplicate triangles next to good ones are tolerated.
    let id = sim.add_mesh_collider(&v, &[[0, 1, 2], [0, 1, 2], [1, 1, 2]], o).unwrap();
    let e = sim.set_collider_positions(id, &v[..2]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    let e = sim.set_collider_positions(ColliderId(7), &v).unwrap_err();
    assert!(matches!(e, TailorError::IndexOutOfRange { index: 7, .. }), "{e}");
    let e = sim.set_collider_levels(id, &[1, 2]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    let e = sim.set_particle_levels(&[1]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    let k = sim.num_particles();
    let mut bad = vec![0.1; k];
    bad[3] = f32::NAN;
    let e = sim.set_particle_friction(Some((&bad, &vec![0.1; k]))).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSetting { .. }) && e.to_string().contains("particle 3"), "{e}");
    let e = sim.set_self_collision(SelfCollisionSettings { radius: Some(0.0), ..Default::default() }).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSetting { .. }), "{e}");
    sim.step(1.0 / FPS).unwrap();
}

/// The step reports how far the particles resting on a mesh collider moved (issue 23's rest
/// jitter): nothing without a collider; on a still sphere, once the sheet has settled, far
/// less than while it landed; on the sphere moved rigidly, about the sphere's own motion (the
/// resting particles ride on it).
#[test]
fn steps_report_the_motion_of_the_particles_resting_on_the_body() {
    let (sv, st) = icosphere(3, 0.3, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.5, 14, 0.05, 0.0, 0.33);
    let mut free = sim_of(p.clone(), r.clone(), t.clone(), SolverSettings::default());
    assert_eq!(free.step(1.0 / FPS).unwrap().contact_motion, None, "no collider, no contact motion");
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let id = sim.add_mesh_collider(&sv, &st, MeshColliderOptions::default()).unwrap();
    let motion: Vec<Option<f32>> = (0..90).map(|_| sim.step(1.0 / FPS).unwrap().contact_motion).collect();
    let first = motion.iter().position(|m| m.is_some()).expect("the sheet never touched the sphere");
    let landing = motion[first].unwrap();
    let settled = motion[80..].iter().map(|m| m.expect("the settled sheet left the sphere")).fold(0.0, f32::max);
    println!("contact motion: landing {landing:.2e} m, settled at most {settled:.2e} m a frame");
    assert!(landing > 0.0 && settled < 0.5 * landing, "landing {landing}, settled {settled}");
    // The sphere moves 4 mm a frame sideways: the resting particles ride along.
    let step = 0.004;
    let mut ride = Vec::new();
    for f in 1..=10 {
        let off = Vec3::new(step * f as f32, 0.0, 0.0);
        let m: Vec<[f32; 3]> = sv.iter().map(|v| (Vec3::from(*v) + off).into()).collect();
        sim.set_collider_positions(id, &m).unwrap();
        ride.push(sim.step(1.0 / FPS).unwrap().contact_motion.expect("the sheet left the moving sphere"));
    }
    let late = &ride[5..];
    println!("riding: {late:?}");
    assert!(late.iter().all(|&m| m > 0.5 * step && m < 1.5 * step), "{late:?} against {step} a frame");
}
