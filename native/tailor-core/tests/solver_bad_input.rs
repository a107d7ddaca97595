//! Bad input gets a typed error naming the offending element, never a panic.

use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::rectangle;
use tailor_core::solver::{Attachment, Fabric, Seam, Simulation, SolverSettings};
use tailor_core::TailorError;

fn sim() -> Simulation {
    let (rest, tris) = rectangle(0.2, 0.2, 4, 4);
    let pos = rest.iter().map(|r| [r[0], r[1], 0.0]).collect();
    Simulation::new(ClothMesh::new(pos, rest, tris).unwrap(), Fabric::default(), SolverSettings::default()).unwrap()
}

#[test]
fn seam_pairing_different_counts_is_refused() {
    let e = Seam::one_to_one("side", &[0, 1, 2], &[5, 6], 100.0, 0.0).unwrap_err();
    assert!(matches!(&e, TailorError::InvalidSeam { seam, .. } if seam == "side"), "{e}");
    assert!(e.to_string().contains("3") && e.to_string().contains("2"));
}

#[test]
fn seam_out_of_range_or_self_sewn_is_refused() {
    let mut s = sim();
    let e = s.add_seam(Seam::one_to_one("far", &[0, 1], &[3, 99], 100.0, 0.0).unwrap()).unwrap_err();
    assert!(matches!(e, TailorError::IndexOutOfRange { index: 99, .. }), "{e}");
    let e = s.add_seam(Seam::one_to_one("self", &[0, 1], &[0, 2], 100.0, 0.0).unwrap()).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { .. }), "{e}");
    let e = s.add_seam(Seam::one_to_one("soft", &[0], &[4], 0.0, 0.0).unwrap()).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { .. }), "{e}");
}

#[test]
fn invalid_masses_are_refused_naming_the_particle() {
    let mut s = sim();
    let mut scale = vec![1.0; s.num_particles()];
    scale[7] = 0.0;
    let e = s.set_mass_scale(&scale).unwrap_err();
    assert!(matches!(e, TailorError::InvalidMass { particle: 7, .. }), "{e}");
    scale[7] = -2.0;
    assert!(matches!(s.set_mass_scale(&scale).unwrap_err(), TailorError::InvalidMass { particle: 7, .. }));
    scale[7] = f32::NAN;
    assert!(s.set_mass_scale(&scale).is_err());
    let e = s.set_mass_scale(&[1.0; 3]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    let e = Simulation::new(
        {
            let (rest, tris) = rectangle(0.2, 0.2, 2, 2);
            ClothMesh::new(rest.iter().map(|r| [r[0], r[1], 0.0]).collect(), rest, tris).unwrap()
        },
        Fabric { density: 0.0, ..Default::default() },
        SolverSettings::default(),
    )
    .err()
    .unwrap();
    assert!(matches!(e, TailorError::InvalidSetting { name: "fabric.density", .. }), "{e}");
}

#[test]
fn non_finite_positions_and_settings_are_refused() {
    let mut s = sim();
    let mut p = s.positions().to_aos();
    p[3][2] = f32::INFINITY;
    let e = s.set_positions(&p).unwrap_err();
    assert!(matches!(e, TailorError::NonFinite { index: 3, .. }), "{e}");
    assert!(s.step(f32::NAN).is_err());
    assert!(s.step(0.0).is_err());
    let bad = SolverSettings { substeps: 0, ..Default::default() };
    assert!(matches!(s.set_settings(bad).unwrap_err(), TailorError::InvalidSetting { name: "substeps", .. }));
    let e = s.pin(&[1000], None).unwrap_err();
    assert!(matches!(e, TailorError::IndexOutOfRange { index: 1000, .. }), "{e}");
    let e = s.add_attachment(Attachment { particle: 0, target: [f32::NAN, 0.0, 0.0], weight: 1.0 }).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    // Nothing was changed by the refused calls: the simulation still steps.
    s.step(1.0 / 30.0).unwrap();
}

#[test]
fn an_exploding_step_is_rolled_back() {
    let mut s = sim();
    let before = s.positions().clone();
    // Absurd velocities overflow to infinity within a step.
    let v = vec![[3.0e38f32, 3.0e38, 3.0e38]; s.num_particles()];
    s.set_velocities(&v).unwrap();
    let e = s.step(1.0).unwrap_err();
    assert!(matches!(e, TailorError::Diverged { .. }), "{e}");
    assert_eq!(s.positions(), &before, "state must be rolled back");
}
