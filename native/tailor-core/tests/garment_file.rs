//! Garment file round trip, and its refusal of damaged, mismatched or newer files.

mod common;

use common::*;
use tailor_core::bend::{BendMode, BendParams, SymmetryLine};
use tailor_core::garment_file::*;
use tailor_core::pattern::Placement;
use tailor_core::seam::{path_between, Direction, Seam, SeamMode};
use tailor_core::triangulate::{triangulate_piece, TriangulateOptions};
use tailor_core::TailorError;

fn garment() -> Garment {
    let (front, sl) = (rectangle("front", 0.3, 0.4), sleeve());
    let (fo, so) = (TriangulateOptions::new(0.02), TriangulateOptions::new(0.015));
    let (mf, ms) = (triangulate_piece(&front, &fo).unwrap(), triangulate_piece(&sl, &so).unwrap());
    let a = path_between(&mf, mf.span_map[1][0], mf.span_map[1][1], Direction::Ccw).unwrap();
    let b = path_between(&ms, ms.span_map[1][0], ms.span_map[1][1], Direction::Ccw).unwrap();
    let seam = Seam::from_paths("side", 0, &mf, &a, 1, &ms, &b, SeamMode::Unequal).unwrap();
    let bend = BendParams {
        axis_point: [0.0, 0.2, -0.05],
        axis_direction: [0.0, 1.0, 0.0],
        angle_deg: 120.0,
        symmetry: Some(SymmetryLine { point: [0.0, 0.0], direction: [0.0, 1.0] }),
        threshold: 0.01,
        radius: None,
        mode: BendMode::Roll,
        // A cone (issue 25): written and read back like the rest.
        taper_deg: 3.0,
    };
    let n = ms.rest.len();
    let mut g = Garment::default();
    g.pieces.push(GarmentPiece { source: front, options: fo, placement: None, bend: None });
    g.pieces.push(GarmentPiece {
        source: sl,
        options: so,
        placement: Some(Placement { translation: [0.3, 1.2, 0.0], rotation_deg: [0.0, 0.0, -80.0], flipped: false }),
        bend: Some(bend),
    });
    g.seams.push(seam);
    g.particle_params = vec![
        ParticleParam {
            name: "friction".into(),
            piece: 1,
            values: ParticleValues::F32((0..n).map(|i| i as f32 * 0.001).collect()),
        },
        ParticleParam {
            name: "collision_level".into(),
            piece: 1,
            values: ParticleValues::I32((0..n as i32).map(|i| i % 3 - 1).collect()),
        },
        ParticleParam {
            name: "pinned".into(),
            piece: 0,
            values: ParticleValues::Bool((0..mf.rest.len()).map(|i| i % 7 == 0).collect()),
        },
    ];
    g.settings.insert("gravity".into(), serde_json::json!([0.0, -9.81, 0.0]));
    g.settings.insert("substeps".into(), serde_json::json!(20));
    g
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tailor-garment-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("shirt.json")
}

#[test]
fn round_trip_through_files() {
    let g = garment();
    let path = temp("roundtrip");
    save(&g, &path).unwrap();
    assert!(sidecar_path(&path).exists());
    let back = load(&path).unwrap();
    assert_eq!(back, g);
    // The stored pieces rebuild the same meshes and the seams resolve on them.
    let meshes: Vec<_> = back.pieces.iter().map(|p| triangulate_piece(&p.source, &p.options).unwrap()).collect();
    let r = back.seams[0].resolve(&meshes).unwrap();
    assert!(!r.pairs(&meshes[0], &meshes[1]).unwrap().is_empty());
    assert_eq!(back.particle_params[0].values.len(), meshes[1].rest.len());
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn damaged_mismatched_and_newer_files_are_refused() {
    let g = garment();
    let (json, bin) = encode(&g, "shirt.bin").unwrap();
    assert_eq!(decode(&json, &bin, "shirt.json").unwrap(), g);

    let mut flipped = bin.clone();
    let last = flipped.len() - 1;
    flipped[last] ^= 1;
    let e = decode(&json, &flipped, "shirt.json").unwrap_err();
    assert!(matches!(e, TailorError::Parse { ref entity, .. } if entity.contains("sidecar")), "{e}");
    let e = decode(&json, &bin[..bin.len() - 4], "shirt.json").unwrap_err();
    assert!(matches!(e, TailorError::Parse { .. }), "{e}");

    let newer = json.replacen(&format!("\"version\": {VERSION}"), "\"version\": 99", 1);
    let e = decode(&newer, &bin, "shirt.json").unwrap_err();
    assert!(matches!(e, TailorError::Unsupported { .. }), "{e}");
    let other = json.replacen(FORMAT, "something-else", 1);
    assert!(matches!(decode(&other, &bin, "x.json"), Err(TailorError::Parse { .. })));
    assert!(matches!(decode("{ not json", &bin, "x.json"), Err(TailorError::Parse { .. })));

    // A manifest may not point its sidecar outside its own folder.
    let escape = json.replacen("\"shirt.bin\"", "\"../etc/passwd\"", 1);
    let path = temp("escape");
    std::fs::write(&path, escape).unwrap();
    assert!(matches!(load(&path), Err(TailorError::Parse { .. })));
    assert!(matches!(load(&path.with_file_name("missing.json")), Err(TailorError::Io { .. })));
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}
