//! A garment's typed setup: stored in the garment file (version 1's settings read into it),
//! applied in one place (`garment::apply_setup`), with one pin rule.

mod common;

use common::*;
use tailor_core::garment::{build_configured, build_simulation, pin_weights, BuildOptions};
use tailor_core::garment_file::setup::{maps, ColliderLevels, PinMode};
use tailor_core::garment_file::*;
use tailor_core::pattern::Placement;
use tailor_core::seam::{path_between, Direction, Seam, SeamMode};
use tailor_core::solver::{bend_at_angle, Fabric, SolverSettings};
use tailor_core::triangulate::{triangulate_piece, TriangulateOptions};

/// Two rectangles 10 cm apart, sewn along one side.
fn garment() -> Garment {
    let (a, b) = (rectangle("front", 0.3, 0.4), rectangle("back", 0.3, 0.4));
    let o = TriangulateOptions::new(0.04);
    let (ma, mb) = (triangulate_piece(&a, &o).unwrap(), triangulate_piece(&b, &o).unwrap());
    let pa = path_between(&ma, ma.span_map[1][0], ma.span_map[1][1], Direction::Ccw).unwrap();
    let pb = path_between(&mb, mb.span_map[3][1], mb.span_map[3][0], Direction::Cw).unwrap();
    let mut g = Garment::default();
    for (piece, z) in [(a, 0.0), (b, 0.1)] {
        let placement = Placement { translation: [0.0, 0.0, z], rotation_deg: [0.0; 3], flipped: false };
        g.pieces.push(GarmentPiece { source: piece, options: o.clone(), placement: Some(placement), bend: None });
    }
    g.seams.push(Seam::from_paths("side", 0, &ma, &pa, 1, &mb, &pb, SeamMode::Unequal).unwrap());
    g
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tailor-setup-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("g.json")
}

fn vertices(g: &Garment, piece: usize) -> usize {
    triangulate_piece(&g.pieces[piece].source, &g.pieces[piece].options).unwrap().rest.len()
}

fn steps(sim: &mut tailor_core::solver::Simulation, n: usize) -> Vec<[f32; 3]> {
    for _ in 0..n {
        sim.step(1.0 / 30.0).unwrap();
    }
    (0..sim.num_particles()).map(|i| sim.positions().get(i).to_array()).collect()
}

#[test]
fn the_setup_and_three_float_maps_round_trip_through_the_file() {
    let mut g = garment();
    let n0 = vertices(&g, 0);
    g.setup.name = "coat".into();
    g.setup.fabrics = vec![Fabric::default(), Fabric { density: 0.3, ..Fabric::default() }];
    g.setup.pin_mode = PinMode::Fixed;
    g.setup.collider_levels = Some(ColliderLevels::encode(&[0, 0, 2, 2, 0, 3]));
    g.particle_params.push(ParticleParam {
        name: maps::POSITION.into(),
        piece: 0,
        values: ParticleValues::Vec3((0..n0).map(|i| [i as f32, 0.5, -1.0]).collect()),
    });
    let path = temp("roundtrip");
    save(&g, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"version\": 2") && text.contains("\"pin_mode\": \"fixed\""), "{text}");
    assert_eq!(load(&path).unwrap(), g);
    assert_eq!(g.setup.collider_levels.unwrap().decode().unwrap(), vec![0, 0, 2, 2, 0, 3]);
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn a_version_1_files_setup_is_read_from_its_settings() {
    let g = garment();
    let path = temp("v1");
    save(&g, &path).unwrap();
    // Version 1 as the sample garments and the add-on wrote it: no `setup`, the values under
    // `settings.tailor_sample`, a piece's missing fabric keys taken from the first piece.
    let mut head: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    head["version"] = 1.into();
    head.as_object_mut().unwrap().remove("setup");
    head["settings"]["tailor_sample"] = serde_json::json!({
        "name": "skirt", "character": "character.glb", "up": "y", "thickness": 0.005, "self_collision": true,
        "fabric_per_piece": [{"density": 0.1, "stretch": 500.0, "shear": 50.0, "bend": 1e-5}, {"stretch": 900.0}],
        "collider_levels": {"vertices": 4, "runs": [[1, 2, 3]]}
    });
    std::fs::write(&path, serde_json::to_string(&head).unwrap()).unwrap();
    let back = load(&path).unwrap();
    let s = &back.setup;
    assert_eq!((s.name.as_str(), s.thickness, s.self_collision), ("skirt", 0.005, true));
    assert_eq!(s.fabrics[1], Fabric::isotropic(0.1, 900.0, 50.0, 1e-5));
    // No friction recorded: self-collision's own default, as version 1 simulated it.
    assert_eq!((s.friction.static_friction, s.friction.kinetic_friction), (0.3, 0.2));
    assert_eq!((s.pin_mode, s.pin_stiffness), (PinMode::Attach, 100.0));
    assert_eq!(s.collider_levels.as_ref().unwrap().decode().unwrap(), vec![0, 3, 3, 0]);
    // What the setup did not take stays in the settings.
    assert_eq!(back.settings["tailor_sample"], serde_json::json!({"character": "character.glb", "up": "y"}));
    // A damaged one says where.
    head["settings"]["tailor_sample"]["thickness"] = "thick".into();
    std::fs::write(&path, serde_json::to_string(&head).unwrap()).unwrap();
    let err = load(&path).unwrap_err().to_string();
    assert!(err.contains("tailor_sample.thickness") && err.contains("number"), "{err}");
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn a_bad_setup_in_the_manifest_is_refused_with_its_key() {
    let g = garment();
    let path = temp("bad");
    save(&g, &path).unwrap();
    let mut head: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (key, value, says) in [
        ("thickness", serde_json::json!(-0.004), "thickness"),
        ("pin_mode", serde_json::json!("glued"), "glued"),
        ("thicknes", serde_json::json!(0.004), "thicknes"),
        (
            "fabrics",
            serde_json::json!([{"density": 0.1, "stretch": 1.0, "shear": 1.0, "bend": 0.0}]),
            "one fabric per piece",
        ),
        ("collider_levels", serde_json::json!({"vertices": 3, "runs": [[2, 5, 1]]}), "outside"),
    ] {
        let mut h = head.clone();
        h["setup"][key] = value;
        std::fs::write(&path, serde_json::to_string(&h).unwrap()).unwrap();
        let err = load(&path).unwrap_err().to_string();
        assert!(err.contains(says), "{key}: {err}");
    }
    head["setup"]["thickness"] = 0.006.into();
    std::fs::write(&path, serde_json::to_string(&head).unwrap()).unwrap();
    assert_eq!(load(&path).unwrap().setup.thickness, 0.006);
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn one_fabric_and_nothing_painted_solves_exactly_as_built() {
    // The setup sets fabric per element whatever the values; with one fabric and scale 1 it
    // gives what the build gave, to the bit (so the command line's sample runs did not change).
    let g = garment();
    let settings = SolverSettings { substeps: 4, iterations: 10, ..SolverSettings::default() };
    let (mut plain, _) = build_simulation(&g, Fabric::default(), settings.clone(), &BuildOptions::default()).unwrap();
    plain.set_thickness(g.setup.thickness).unwrap();
    plain.set_self_collision(g.setup.self_collision_settings()).unwrap();
    let (mut set, _, applied) = build_configured(&g, None, settings, &BuildOptions::default(), true).unwrap();
    assert!(applied.warnings.is_empty() && applied.attach.is_empty());
    assert_eq!(steps(&mut plain, 5), steps(&mut set, 5));
}

#[test]
fn fabric_per_piece_painted_maps_and_pins_are_applied() {
    let mut g = garment();
    let (n0, n1) = (vertices(&g, 0), vertices(&g, 1));
    g.setup.fabrics = vec![Fabric::default(), Fabric { density: 0.3, ..Fabric::default() }];
    let mut pin = vec![0.0f32; n0];
    pin[0] = 1.0;
    pin[1] = 0.999;
    pin[2] = 0.52;
    g.particle_params.push(ParticleParam { name: maps::PIN.into(), piece: 0, values: ParticleValues::F32(pin) });
    g.particle_params.push(ParticleParam {
        name: maps::COLLISION_LEVEL.into(),
        piece: 1,
        values: ParticleValues::I32(vec![2; n1]),
    });
    g.particle_params.push(ParticleParam {
        name: maps::MASS_SCALE.into(),
        piece: 1,
        values: ParticleValues::F32(vec![2.0; n1 + 1]), // painted on another mesh
    });
    let (sim, _, applied) =
        build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    let m = sim.masses();
    let (plain, _) =
        build_simulation(&g, Fabric::default(), SolverSettings::default(), &BuildOptions::default()).unwrap();
    assert!((m[n0] / plain.masses()[n0] - 2.0).abs() < 1e-5, "density 0.3 against 0.15");
    assert!((m[0] - plain.masses()[0]).abs() < 1e-9);
    assert_eq!(sim.particle_levels()[n0..], vec![2; n1][..]);
    assert!(applied.warnings.len() == 1 && applied.warnings[0].contains("'mass_scale'"), "{:?}", applied.warnings);
    // Riding pins: weight 1 (0.999 included) at the pin stiffness, 0.52 rounded to 0.5.
    let groups: Vec<_> = applied.attach.iter().map(|p| (p.particles.clone(), p.stiffness)).collect();
    assert_eq!(groups, vec![(vec![0, 1], 100.0), (vec![2], 50.0)]);
    // Fixed: weight 1 pinned where placed, lighter ones attached softly; no collider to ride
    // on: the same, with a warning.
    g.setup.pin_mode = PinMode::Fixed;
    let (fixed, _, applied) =
        build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    assert!(
        applied.attach.is_empty() && fixed.model().pinned[0] && fixed.model().pinned[1] && !fixed.model().pinned[2]
    );
    assert_eq!(fixed.model().attachments.len(), 1);
    assert_eq!(fixed.model().attachments[0].weight, 50.0);
    g.setup.pin_mode = PinMode::Attach;
    let (_, _, applied) =
        build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), false).unwrap();
    assert!(applied.attach.is_empty() && applied.warnings.iter().any(|w| w.contains("no collider")));
}

#[test]
fn stored_positions_are_used_instead_of_the_placement() {
    let mut g = garment();
    let n0 = vertices(&g, 0);
    let placed: Vec<[f32; 3]> = (0..n0).map(|i| [i as f32 * 0.01, 1.0, 2.0]).collect();
    g.particle_params.push(ParticleParam {
        name: maps::POSITION.into(),
        piece: 0,
        values: ParticleValues::Vec3(placed.clone()),
    });
    let (sim, _) =
        build_simulation(&g, Fabric::default(), SolverSettings::default(), &BuildOptions::default()).unwrap();
    let got: Vec<[f32; 3]> = (0..n0).map(|i| sim.positions().get(i).to_array()).collect();
    assert_eq!(got, placed);
    assert_eq!(sim.positions().get(n0).to_array()[2], 0.1, "piece 1 stays where its placement puts it");
}

#[test]
fn pin_weights_group_by_rounded_weight_hard_first() {
    let w = [0.0, 1.0, 0.02, 0.03, 0.999, 0.5, 0.52, 1.5, -1.0];
    let groups = pin_weights(&w);
    assert_eq!(groups, vec![(1.0, vec![1, 4, 7]), (0.05, vec![3]), (0.5, vec![5, 6])]);
}

/// A piece of an anisotropic fabric (a library name in the file, or its values): the file keeps
/// its directions, the built simulation gives that piece's triangles their stretch along `v` and
/// its hinges their bending by direction (the painted bend scale on all three), and the
/// isotropic piece beside it is built as before, bit for bit.
#[test]
fn an_anisotropic_piece_is_stored_and_simulated_by_direction() {
    let denim = tailor_core::fabrics::named("11oz-black-denim").unwrap().fabric();
    let mut g = garment();
    let (n0, n1) = (vertices(&g, 0), vertices(&g, 1));
    g.setup.fabrics = vec![Fabric::default(), denim];
    g.particle_params.push(ParticleParam {
        name: maps::BEND_SCALE.into(),
        piece: 1,
        values: ParticleValues::F32(vec![2.0; n1]),
    });
    let path = temp("anisotropic");
    save(&g, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"stretch_v\"") && text.contains("\"bend_bias\""), "{text}");
    assert!(text.matches("\"stretch_v\"").count() == 1, "the isotropic piece writes no direction");
    let back = load(&path).unwrap();
    assert_eq!(back, g);
    // By name in a file: the library's anisotropic fabric.
    let mut head: serde_json::Value = serde_json::from_str(&text).unwrap();
    head["setup"]["fabrics"][1] = "11oz-black-denim".into();
    std::fs::write(&path, serde_json::to_string(&head).unwrap()).unwrap();
    assert_eq!(load(&path).unwrap().setup.fabrics[1], denim);
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();

    let (sim, _, _) = build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    let t = &sim.model().triangles;
    let m0 = t.verts.iter().filter(|v| (v[0] as usize) < n0).count();
    assert!(t.w_stretch[..m0].iter().zip(&t.w_stretch_v[..m0]).all(|(u, v)| u == v));
    let ratio = denim.stretch_v.unwrap() / denim.stretch;
    assert!(t.w_stretch[m0..].iter().zip(&t.w_stretch_v[m0..]).all(|(u, v)| (v / u - ratio).abs() < 1e-4 * ratio));
    // The same garment of one isotropic fabric: piece 0's hinges are bit for bit its hinges.
    let mut iso = g.clone();
    iso.setup.fabrics = vec![Fabric::default(), Fabric::default()];
    iso.particle_params.clear();
    let (plain, _, _) =
        build_configured(&iso, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    let hinges = &sim.model().mesh.topology().hinges;
    let (w, w_iso) = (&sim.model().bending.weights, &plain.model().bending.weights);
    let piece0 = |h: usize| (hinges[h].vertices[0] as usize) < n0;
    assert!((0..hinges.len()).filter(|&h| piece0(h)).all(|h| w[h] == w_iso[h]));
    // Piece 1's hinges: the denim's bending at each hinge's direction in the pattern, doubled
    // by the bend scale.
    let rest = sim.model().mesh.rest();
    let mut spread = (f32::MAX, 0.0f32);
    for h in (0..hinges.len()).filter(|&h| !piece0(h)) {
        let [a, b, _, _] = hinges[h].vertices;
        let (p, q) = (rest[a as usize], rest[b as usize]);
        let angle = ((q[1] - p[1]) as f64).atan2((q[0] - p[0]) as f64);
        let want = 2.0 * bend_at_angle(denim.bend_directions(), angle) as f32;
        let got = w[h] / w_iso[h] * Fabric::default().bend;
        assert!((got - want).abs() < 1e-4 * want, "hinge {h} at {angle} rad: {got} against {want}");
        spread = (spread.0.min(got), spread.1.max(got));
    }
    assert!(spread.1 > 1.2 * spread.0, "the hinges' bending does not vary with direction: {spread:?}");
}

/// An anisotropic piece lies along its pattern's grain line (`v` on the line): a grain line at
/// 45° turns its triangles' fabric by -45°, a vertical one (or none) leaves the pattern's axes,
/// and an isotropic piece keeps the pattern's axes whatever its grain line (its results as
/// before, bit for bit).
#[test]
fn an_anisotropic_piece_lies_along_its_grain_line() {
    use tailor_core::garment::setup::fabric_grain;
    let denim = tailor_core::fabrics::named("11oz-black-denim").unwrap().fabric();
    let mut g = garment();
    let quarter = std::f32::consts::FRAC_PI_4;
    assert_eq!(fabric_grain(&g.pieces[0].source), 0.0); // no grain line
    g.pieces[0].source.grain = Some([[0.1, 0.0], [0.1, 0.3]]);
    assert_eq!(fabric_grain(&g.pieces[0].source), 0.0); // vertical
    g.pieces[0].source.grain = Some([[0.1, 0.3], [0.1, 0.0]]);
    assert_eq!(fabric_grain(&g.pieces[0].source), 0.0); // drawn downwards: the same
    g.pieces[1].source.grain = Some([[0.0, 0.0], [0.2, 0.2]]);
    assert!((fabric_grain(&g.pieces[1].source) + quarter).abs() < 1e-6);
    g.setup.fabrics = vec![denim, denim];
    let m0 = triangulate_piece(&g.pieces[0].source, &g.pieces[0].options).unwrap().triangles.len();
    let (sim, _, _) = build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    let grain = &sim.model().grain;
    assert!(grain[..m0].iter().all(|&a| a == 0.0) && grain[m0..].iter().all(|&a| (a + quarter).abs() < 1e-6));
    // Isotropic pieces: the pattern's axes, whatever the grain line.
    g.setup.fabrics = vec![Fabric::default(), Fabric::default()];
    let (iso, _, _) = build_configured(&g, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    assert!(iso.model().grain.iter().all(|&a| a == 0.0));
    let mut plain = garment();
    plain.setup.fabrics = g.setup.fabrics.clone();
    let (p, _, _) = build_configured(&plain, None, SolverSettings::default(), &BuildOptions::default(), true).unwrap();
    assert_eq!(iso.model().triangles.g, p.model().triangles.g);
}
