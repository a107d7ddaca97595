//! Particles attached to a mesh collider (`Simulation::attach_to_collider`): they ride on it
//! as it moves and turns, attaching does not move them, a deforming collider carries them by
//! their barycentric point, and bad ids, indices and stiffness are errors that change nothing.

mod collision_common;

use collision_common::{box_mesh, cloth_grid, plane_mesh, sim_of};
use glam::{Quat, Vec3};
use tailor_core::solver::{ColliderId, MeshColliderOptions, Simulation, SolverSettings};
use tailor_core::TailorError;

const FPS: f32 = 30.0;

fn transformed(v: &[[f32; 3]], rot: Quat, centre: Vec3, shift: Vec3) -> Vec<[f32; 3]> {
    v.iter().map(|&p| (rot * (Vec3::from(p) - centre) + centre + shift).into()).collect()
}

/// A 0.3 m cloth 2 cm above a box, every particle attached (100 N/m); the box turns 90° about
/// z and slides 0.2 m over one second. Each particle stays within 1 mm of where the same rigid
/// motion takes its start position (measured: 2.7e-5 m); an identical cloth not attached stays
/// behind (0.14 m).
#[test]
fn attached_cloth_rides_on_a_moving_turning_collider() {
    let (bv, bt) = box_mesh(0.1, Vec3::ZERO);
    let run = |attach: bool| -> (f32, Vec<[f32; 3]>, Vec<[f32; 3]>) {
        let (p, r, t) = cloth_grid(0.3, 10, 0.0, 0.0, 0.12);
        let start = p.clone();
        let mut sim = sim_of(p, r, t, SolverSettings::default());
        let id = sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
        if attach {
            let all: Vec<u32> = (0..sim.num_particles() as u32).collect();
            sim.attach_to_collider(&all, id, 100.0).unwrap();
            assert_eq!(sim.collider_attachments().len(), all.len());
        }
        let frames = 30;
        let mut worst = 0.0f32;
        for f in 1..=frames {
            let s = f as f32 / frames as f32;
            let (rot, shift) = (Quat::from_rotation_z(s * std::f32::consts::FRAC_PI_2), Vec3::new(0.2 * s, 0.0, 0.0));
            sim.set_collider_positions(id, &transformed(&bv, rot, Vec3::ZERO, shift)).unwrap();
            sim.step(1.0 / FPS).unwrap();
            let expect = transformed(&start, rot, Vec3::ZERO, shift);
            let now = sim.positions().to_aos();
            for (a, b) in now.iter().zip(&expect) {
                worst = worst.max(Vec3::from(*a).distance(Vec3::from(*b)));
            }
        }
        let expect = transformed(&start, Quat::from_rotation_z(std::f32::consts::FRAC_PI_2), Vec3::ZERO, Vec3::X * 0.2);
        (worst, sim.positions().to_aos(), expect)
    };
    let (worst, end, expect) = run(true);
    let end_err = end.iter().zip(&expect).map(|(a, b)| Vec3::from(*a).distance(Vec3::from(*b))).fold(0.0, f32::max);
    println!(
        "attached: worst distance from the rigid motion over the frames {worst:.2e} m, at the end {end_err:.2e} m"
    );
    assert!(end_err < 1e-3, "attached particles ended {end_err} m from the collider's motion");
    assert!(worst < 1e-3, "attached particles lagged {worst} m behind the collider");
    let (_, free, _) = run(false);
    let free_err = free.iter().zip(&expect).map(|(a, b)| Vec3::from(*a).distance(Vec3::from(*b))).fold(0.0, f32::max);
    println!("not attached: {free_err:.3} m from the collider's motion");
    assert!(free_err > 0.1, "the unattached cloth followed the box too ({free_err} m): the test shows nothing");
}

/// Attaching binds each particle where it is: under no gravity and a still collider nothing
/// moves, whatever the particles' distance and side relative to the nearest triangle.
#[test]
fn attaching_does_not_move_the_particles() {
    let (bv, bt) = box_mesh(0.1, Vec3::ZERO);
    // Over the box's top edge: the nearest points are on edges and corners as well as faces.
    let (p, r, t) = cloth_grid(0.4, 8, 0.1, 0.05, 0.13);
    let settings = SolverSettings { gravity: [0.0; 3], ..Default::default() };
    let mut sim = sim_of(p.clone(), r, t, settings);
    let id = sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
    let all: Vec<u32> = (0..sim.num_particles() as u32).collect();
    sim.attach_to_collider(&all, id, 50.0).unwrap();
    for _ in 0..10 {
        sim.step(1.0 / FPS).unwrap();
    }
    let moved = sim
        .positions()
        .to_aos()
        .iter()
        .zip(&p)
        .map(|(a, b)| Vec3::from(*a).distance(Vec3::from(*b)))
        .fold(0.0, f32::max);
    assert!(moved < 1e-5, "attaching moved a particle by {moved} m");
}

/// A stretching collider (a floor patch scaled 1.5× in x over the frames) carries an attached
/// particle by its barycentric point: it ends at the scaled position, 1 cm above the floor.
#[test]
fn deforming_collider_carries_the_barycentric_point() {
    let (fv, ft) = plane_mesh(1.0, 4, Vec3::ZERO, Vec3::X, Vec3::Y);
    let (p, r, t) = cloth_grid(0.2, 4, 0.2, 0.1, 0.01);
    let settings = SolverSettings { gravity: [0.0; 3], ..Default::default() };
    let mut sim = sim_of(p.clone(), r, t, settings);
    let id = sim.add_mesh_collider(&fv, &ft, MeshColliderOptions::default()).unwrap();
    let all: Vec<u32> = (0..sim.num_particles() as u32).collect();
    sim.attach_to_collider(&all, id, 200.0).unwrap();
    for f in 1..=20 {
        let s = 1.0 + 0.5 * f as f32 / 20.0;
        let v: Vec<[f32; 3]> = fv.iter().map(|q| [q[0] * s, q[1], q[2]]).collect();
        sim.set_collider_positions(id, &v).unwrap();
        sim.step(1.0 / FPS).unwrap();
    }
    for _ in 0..10 {
        sim.step(1.0 / FPS).unwrap();
    }
    let err = sim
        .positions()
        .to_aos()
        .iter()
        .zip(&p)
        .map(|(a, b)| Vec3::from(*a).distance(Vec3::new(b[0] * 1.5, b[1], b[2])))
        .fold(0.0, f32::max);
    println!("stretched floor: largest distance from the scaled positions {err:.2e} m");
    // The cloth resists the 1.5× stretch (60 N/m against 200 N/m per particle): a few mm
    // (measured 6.0e-3 m).
    assert!(err < 1e-2, "attached particles {err} m from the stretched floor's points");
}

fn small() -> (Simulation, ColliderId) {
    let (bv, bt) = box_mesh(0.1, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.2, 4, 0.0, 0.0, 0.12);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let id = sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
    (sim, id)
}

#[test]
fn bad_collider_particle_or_stiffness_is_an_error_and_changes_nothing() {
    let (mut sim, id) = small();
    sim.attach_to_collider(&[0, 1], id, 100.0).unwrap();
    let n = sim.num_particles() as u32;
    let cases: [(&[u32], ColliderId, f32, &str); 5] = [
        (&[2], ColliderId(1), 100.0, "collider id"),
        (&[2, n], id, 100.0, "particle"),
        (&[2], id, 0.0, "stiffness"),
        (&[2], id, f32::NAN, "stiffness"),
        (&[2], id, -1.0, "stiffness"),
    ];
    for (particles, cid, k, what) in cases {
        let e = sim.attach_to_collider(particles, cid, k).unwrap_err();
        match (&e, what) {
            (TailorError::IndexOutOfRange { .. }, "collider id" | "particle") => {}
            (TailorError::InvalidSetting { name: "stiffness", .. }, "stiffness") => {}
            _ => panic!("{what}: unexpected error {e:?}"),
        }
        assert!(e.to_string().contains(what), "{e}");
        assert_eq!(sim.collider_attachments().len(), 2, "a failed attach changed the attachments");
    }
    assert!(matches!(sim.detach_from_collider(Some(&[n])), Err(TailorError::IndexOutOfRange { .. })));
    assert_eq!(sim.collider_attachments().len(), 2);
}

#[test]
fn reattaching_rebinds_and_detaching_removes() {
    let (mut sim, id) = small();
    sim.attach_to_collider(&[0, 1, 1, 2], id, 100.0).unwrap();
    assert_eq!(sim.collider_attachments().len(), 3, "a particle given twice is bound once");
    sim.attach_to_collider(&[1, 3], id, 40.0).unwrap();
    let mut parts: Vec<(u32, f32)> = sim.collider_attachments().iter().map(|a| (a.particle, a.weight)).collect();
    parts.sort_by_key(|a| a.0);
    assert_eq!(parts, vec![(0, 100.0), (1, 40.0), (2, 100.0), (3, 40.0)]);
    sim.detach_from_collider(Some(&[0, 7])).unwrap();
    assert_eq!(sim.collider_attachments().len(), 3);
    sim.detach_from_collider(None).unwrap();
    assert!(sim.collider_attachments().is_empty());
    sim.step(1.0 / FPS).unwrap();
}

/// The body holds the cloth near it while seams close (`SeamRamp::closing_hold`). Two 0.2 m
/// squares, gravity off: `near` lies 2 cm above a box, `far` 0.4 m beside it, sewn edge to
/// edge. Held, `near` stays within 5 cm of where it was placed and `far` comes to it; not
/// held (`closing_hold` 0) the two meet in the middle, `near` dragged 0.15 m or more off the
/// box (measured: held, near 0.027 m and far 0.43 m; not held, 0.26 m and 0.14 m). Once
/// the seam has met the holds are gone, and attachments asked for stay.
#[test]
fn the_body_holds_the_cloth_near_it_while_seams_close() {
    use tailor_core::solver::Seam;
    let (bv, bt) = box_mesh(0.1, Vec3::ZERO);
    let run = |hold: f32| -> (f32, f32, Simulation) {
        let (pa, ra, ta) = cloth_grid(0.2, 8, 0.0, 0.0, 0.12);
        let (pb, rb, tb) = cloth_grid(0.2, 8, 0.6, 0.0, 0.12);
        let na = pa.len() as u32;
        let pos: Vec<[f32; 3]> = pa.iter().chain(&pb).copied().collect();
        let rest: Vec<[f32; 2]> = ra.iter().chain(rb.iter()).map(|r| *r).collect();
        let tris: Vec<[u32; 3]> = ta.iter().copied().chain(tb.iter().map(|t| t.map(|v| v + na))).collect();
        let mut settings = SolverSettings { gravity: [0.0; 3], ..Default::default() };
        settings.ramp.closing_hold = hold;
        let mut sim = sim_of(pos.clone(), rest, tris, settings);
        // The right edge of `near` (x = 0.1) to the left edge of `far` (x = 0.5).
        let right: Vec<u32> = (0..na).filter(|&i| pos[i as usize][0] > 0.099).collect();
        let left: Vec<u32> = (na..pos.len() as u32).filter(|&i| pos[i as usize][0] < 0.501).collect();
        assert_eq!(right.len(), left.len());
        sim.add_seam(Seam::one_to_one("side", &right, &left, 1e4, 1e-5).unwrap()).unwrap();
        let id = sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
        if hold > 0.0 {
            // A pin the user asked for on a particle the hold would take: it must stay.
            sim.attach_to_collider(&[0], id, 50.0).unwrap();
        }
        let centre = |sim: &Simulation, r: std::ops::Range<usize>| {
            let x = sim.positions().to_aos();
            r.clone().map(|i| Vec3::from(x[i])).sum::<Vec3>() / r.len() as f32
        };
        let (a0, b0) = (centre(&sim, 0..na as usize), centre(&sim, na as usize..pos.len()));
        let mut held_while_closing = 0;
        for _ in 0..60 {
            sim.step(1.0 / FPS).unwrap();
            if sim.ramp_closing() {
                held_while_closing = held_while_closing.max(sim.closing_holds().len());
            }
        }
        assert!(!sim.ramp_closing(), "the seam never met");
        if hold > 0.0 {
            assert_eq!(held_while_closing, na as usize - 1, "every particle of `near` but the pinned one is held");
        }
        assert!(sim.closing_holds().is_empty(), "holds left after closing");
        assert_eq!(sim.collider_attachments().len(), usize::from(hold > 0.0), "the asked-for attachment stays");
        assert_eq!(sim.asked_attachments().len(), usize::from(hold > 0.0));
        let (a1, b1) = (centre(&sim, 0..na as usize), centre(&sim, na as usize..pos.len()));
        (a1.distance(a0), b1.distance(b0), sim)
    };
    let (near_held, far_held, _) = run(100.0);
    let (near_free, far_free, _) = run(0.0);
    println!(
        "held: near moved {near_held:.3} m, far {far_held:.3} m; not held: near {near_free:.3} m, far {far_free:.3} m"
    );
    assert!(near_held < 0.05, "held cloth moved {near_held} m");
    assert!(far_held > 0.3, "the far piece moved only {far_held} m");
    assert!(near_free > 0.15, "without the hold, near moved only {near_free} m (the test shows nothing)");
}

/// A mesh collider whose triangles all have zero area gives the closing hold nothing to ride
/// on: the seams still close and the step is not an error.
#[test]
fn a_collider_of_zero_area_holds_nothing_and_the_step_goes_on() {
    use tailor_core::solver::Seam;
    let (p, r, t) = cloth_grid(0.2, 4, 0.0, 0.0, 0.0);
    let mut pos = p.clone();
    let n = p.len() as u32;
    pos.extend(p.iter().map(|q| [q[0], q[1], q[2] + 0.05]));
    let rest: Vec<[f32; 2]> = r.iter().chain(r.iter()).copied().collect();
    let tris: Vec<[u32; 3]> = t.iter().copied().chain(t.iter().map(|x| x.map(|v| v + n))).collect();
    let mut sim = sim_of(pos, rest, tris, SolverSettings { gravity: [0.0; 3], ..Default::default() });
    let edge: Vec<u32> = (0..n).filter(|&i| p[i as usize][0] > 0.099).collect();
    let other: Vec<u32> = edge.iter().map(|&i| i + n).collect();
    sim.add_seam(Seam::one_to_one("edge", &edge, &other, 1e4, 1e-5).unwrap()).unwrap();
    // Three collinear points: every triangle has zero area.
    let (v, tr) = (vec![[0.0, 0.0, 0.01], [0.05, 0.0, 0.01], [0.1, 0.0, 0.01]], vec![[0u32, 1, 2]]);
    sim.add_mesh_collider(&v, &tr, MeshColliderOptions::default()).unwrap();
    for _ in 0..10 {
        sim.step(1.0 / FPS).unwrap();
    }
    assert!(sim.closing_holds().is_empty());
}
