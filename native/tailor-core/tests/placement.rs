//! Initial 3D positions of piece meshes.

mod common;

use common::*;
use tailor_core::pattern::Placement;
use tailor_core::placement::{place_piece, place_pieces};
use tailor_core::triangulate::{triangulate_piece, TriangulateOptions};

#[test]
fn placement_rotates_then_translates() {
    let mut p = rectangle("front", 0.3, 0.4);
    let m = triangulate_piece(&p, &TriangulateOptions::new(0.05)).unwrap();
    // 90° about y: the piece's +x goes to world -z; then shifted by t.
    let pl = Placement { translation: [0.1, 1.0, 0.2], rotation_deg: [0.0, 90.0, 0.0], flipped: false };
    let world = place_piece(&m, &pl).unwrap();
    for (w, r) in world.iter().zip(&m.rest) {
        assert!((w[0] - 0.1).abs() < 1e-6 && (w[1] - (1.0 + r[1])).abs() < 1e-6 && (w[2] - (0.2 - r[0])).abs() < 1e-6);
    }
    p.placement = Some(pl);
    let q = rectangle("back", 0.2, 0.2);
    let mq = triangulate_piece(&q, &TriangulateOptions::new(0.05)).unwrap();
    let r = rectangle("yoke", 0.1, 0.1);
    let mr = triangulate_piece(&r, &TriangulateOptions::new(0.05)).unwrap();
    let all = place_pieces(&[p, q, r], &[m, mq, mr], 0.05).unwrap();
    assert_eq!(all[0], world);
    // Unplaced pieces: flat, side by side, not overlapping.
    let max_x = all[1].iter().map(|v| v[0]).fold(f32::MIN, f32::max);
    let min_x = all[2].iter().map(|v| v[0]).fold(f32::MAX, f32::min);
    assert!((min_x - max_x - 0.05).abs() < 1e-6);
    assert!(all[1].iter().chain(&all[2]).all(|v| v[2] == 0.0 && v[1] >= 0.0));
}

#[test]
fn sleeve_bent_round_an_arm_and_back() {
    use tailor_core::bend::{bend_piece, BendParams, SymmetryLine};
    let p = sleeve();
    let m = triangulate_piece(&p, &TriangulateOptions::new(0.01)).unwrap();
    let flat: Vec<[f32; 3]> = m.rest.iter().map(|r| [r[0], r[1], 0.0]).collect();
    let params = |angle: f64| BendParams {
        axis_point: [0.0, 0.0, -0.06],
        axis_direction: [0.0, 1.0, 0.0],
        angle_deg: angle,
        symmetry: Some(SymmetryLine { point: [0.0, 0.0], direction: [0.0, 1.0] }),
        threshold: 0.0,
    };
    let mut pos = flat.clone();
    bend_piece(&mut pos, &m.rest, &params(150.0)).unwrap();
    // Wrapped: the underarm points (x = ±0.2) come round below the axis.
    let low = pos.iter().map(|v| v[2]).fold(f32::MAX, f32::min);
    assert!(low < -0.06, "{low}");
    bend_piece(&mut pos, &m.rest, &params(-150.0)).unwrap();
    let err =
        pos.iter().zip(&flat).map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max)).fold(0.0, f32::max);
    assert!(err < 1e-5, "{err}");
}
