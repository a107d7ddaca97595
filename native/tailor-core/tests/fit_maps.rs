//! The fit maps of a settled drape (issue 28): a sheet lying on a box's top face is pressed by
//! its own weight alone, so the pressure map reads the fabric's weight per area; it lies at the
//! collision thickness, unstretched.

mod collision_common;

use collision_common::*;
use glam::Vec3;
use tailor_core::solver::{MeshColliderOptions, SolverSettings};

#[test]
fn a_sheet_resting_on_a_box_is_pressed_by_its_weight() {
    let (bv, bt) = box_mesh(0.3, Vec3::ZERO);
    let (p, r, t) = cloth_grid(0.4, 16, 0.0, 0.0, 0.32);
    let mut sim = sim_of(p, r, t, SolverSettings::default());
    let thickness = 0.004;
    sim.set_thickness(thickness).unwrap();
    let id = sim.add_mesh_collider(&bv, &bt, MeshColliderOptions::default()).unwrap();
    for _ in 0..60 {
        sim.step(1.0 / 30.0).unwrap();
    }
    let maps = sim.fit_maps(Some(id)).unwrap();
    let (d, pr) = (maps.distance.unwrap(), maps.pressure.unwrap());
    // sim_of's fabric: 0.2 kg/m², so 0.2 · 9.81 = 1.962 Pa; interior vertices (the edges'
    // share of the area is cut by the sheet's border).
    let weight = 0.2 * 9.81;
    let interior: Vec<usize> =
        (0..17 * 17).filter(|&k| (1..16).contains(&(k % 17)) && (1..16).contains(&(k / 17))).collect();
    let mut p_in: Vec<f32> = interior.iter().map(|&k| pr[k]).collect();
    p_in.sort_by(f32::total_cmp);
    let median = p_in[p_in.len() / 2];
    println!("pressure: median {median:.3} Pa (weight {weight:.3}), range {:.3}-{:.3}", p_in[0], p_in[p_in.len() - 1]);
    assert!((median - weight).abs() < 0.1 * weight, "median pressure {median} Pa, weight {weight}");
    assert!(
        d.iter().all(|&x| (x - thickness).abs() < 2e-3),
        "distances {:?}",
        d.iter().fold((f32::MAX, f32::MIN), |a, &x| (a.0.min(x), a.1.max(x)))
    );
    assert!(
        maps.strain.iter().all(|s| s.abs() < 0.01),
        "strain up to {}",
        maps.strain.iter().fold(0.0f32, |a, &s| a.max(s.abs()))
    );
    // Without a body: the strain map alone.
    let alone = sim.fit_maps(None).unwrap();
    assert!(alone.distance.is_none() && alone.pressure.is_none() && alone.strain == maps.strain);
}
