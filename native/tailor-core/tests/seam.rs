//! Seams: the paper's five picking steps, corner suggestions, remapping after a change of
//! resolution, unequal-count (arc-length) pairing, hinges and validation errors.

mod common;

use common::*;
use tailor_core::seam::*;
use tailor_core::triangulate::{triangulate_piece, PieceMesh, TriangulateOptions};
use tailor_core::TailorError;

fn tri(p: &tailor_core::pattern::Piece, h: f64) -> PieceMesh {
    triangulate_piece(p, &TriangulateOptions::new(h)).unwrap()
}

fn pt(m: &PieceMesh, w: WeightedPoint) -> [f64; 2] {
    let mut out = [0.0; 2];
    for (v, wt) in w {
        for (o, &r) in out.iter_mut().zip(&m.rest[v as usize]) {
            *o += wt as f64 * r as f64;
        }
    }
    out
}

fn near(a: [f32; 2], b: [f64; 2], tol: f64) -> bool {
    (a[0] as f64 - b[0]).abs() <= tol && (a[1] as f64 - b[1]).abs() <= tol
}

#[test]
fn papers_five_steps_on_two_pieces() {
    let (pa, pb) = (rectangle("front", 0.3, 0.4), rectangle("back", 0.3, 0.4));
    let (ma, mb) = (tri(&pa, 0.02), tri(&pb, 0.02));
    // 1. a1 picked near the lower-right corner of A.
    let a1 = nearest_contour_position(&ma, [0.301, -0.002]);
    assert!(near(ma.contour_point(a1), [0.3, 0.0], 1e-6));
    // 2-3. hovering, then clicking, near the upper-right corner: the shortest path is the right side.
    let path_a = shortest_path(&ma, a1, nearest_contour_position(&ma, [0.299, 0.405])).unwrap();
    assert_eq!(path_a.direction, Direction::Ccw);
    let n = path_a.len();
    assert_eq!(n, 21);
    assert!(path_a.positions.iter().all(|&p| near(ma.contour_point(p), [0.3, ma.contour_point(p)[1] as f64], 1e-6)));
    // Hovering near the lower-left instead gives the bottom edge walked clockwise.
    let other = shortest_path(&ma, a1, nearest_contour_position(&ma, [0.0, 0.0])).unwrap();
    assert_eq!((other.direction, other.len()), (Direction::Cw, 16));
    // 4. b1 near B's lower-left corner.
    let b1 = nearest_contour_position(&mb, [0.0, 0.0]);
    // 5. two n-vertex candidates; the cursor near B's upper-left picks the clockwise one (up the left side).
    let [ccw, cw] = candidate_paths(&mb, b1, n).unwrap();
    assert!(near(mb.contour_point(ccw.last()), [0.3, 0.1], 1e-6));
    assert!(near(mb.contour_point(cw.last()), [0.0, 0.4], 1e-6));
    let path_b = nearer_candidate(&mb, b1, n, [0.02, 0.37]).unwrap();
    assert_eq!(path_b, cw);
    assert_eq!(nearer_candidate(&mb, b1, n, [0.28, 0.12]).unwrap(), ccw);

    let seam = Seam::from_paths("side seam", 0, &ma, &path_a, 1, &mb, &path_b, SeamMode::Equal).unwrap();
    let meshes = vec![ma.clone(), mb.clone()];
    let r = seam.resolve(&meshes).unwrap();
    assert_eq!((&r.a, &r.b), (&path_a, &path_b));
    assert!((r.length_ratio - 1.0).abs() < 1e-6);
    let pairs = r.pairs(&ma, &mb).unwrap();
    assert_eq!(pairs.len(), 21);
    for p in &pairs {
        assert_eq!((p.a[0].1, p.b[0].1), (1.0, 1.0));
        let (qa, qb) = (pt(&ma, p.a), pt(&mb, p.b));
        assert!((qa[0] - 0.3).abs() < 1e-6 && qb[0].abs() < 1e-6 && (qa[1] - qb[1]).abs() < 1e-6);
    }
    let hinges = r.hinges(&ma, &mb).unwrap();
    assert_eq!(hinges.len(), 20);
    for h in &hinges {
        assert!(ma.rest[h.a_opposite as usize][0] < 0.3 - 1e-3);
        assert!(mb.rest[h.b_opposite as usize][0] > 1e-3);
        assert!(ma
            .triangles
            .iter()
            .any(|t| t.contains(&h.a_edge[0]) && t.contains(&h.a_edge[1]) && t.contains(&h.a_opposite)));
    }
}

#[test]
fn corners_and_the_corner_to_corner_suggestion() {
    let m = tri(&rectangle("r", 0.3, 0.4), 0.02);
    let corners = find_corners(&m, 135.0);
    assert_eq!(corners, m.corners);
    let seg = nearest_corner_segment(&m, &corners, [0.31, 0.2]).unwrap();
    assert!(near(m.contour_point(seg.first()), [0.3, 0.0], 1e-6));
    assert!(near(m.contour_point(seg.last()), [0.3, 0.4], 1e-6));
    assert_eq!(seg.len(), 21);
    // Near the top edge: the run from the upper-right to the upper-left corner.
    let top = nearest_corner_segment(&m, &corners, [0.1, 0.39]).unwrap();
    assert!(
        near(m.contour_point(top.first()), [0.3, 0.4], 1e-6) && near(m.contour_point(top.last()), [0.0, 0.4], 1e-6)
    );
    // Wrap-around: the left side runs from the last corner to contour position 0.
    let left = nearest_corner_segment(&m, &corners, [-0.01, 0.2]).unwrap();
    assert_eq!(left.last(), 0);

    let l = tri(&l_shape(), 0.02);
    assert_eq!(find_corners(&l, 135.0).len(), 6); // the concave corner too
    let s = tri(&sleeve(), 0.02);
    assert_eq!(find_corners(&s, 135.0).len(), 2); // the cuff; the cap joins smoothly
    let e = nearest_corner_segment(&s, &[3], [0.0, 0.0]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
}

#[test]
fn remap_after_changing_resolution_keeps_the_endpoints() {
    let (pa, pb) = (rectangle("front", 0.3, 0.4), rectangle("back", 0.3, 0.4));
    let (ma, mb) = (tri(&pa, 0.02), tri(&pb, 0.02));
    let corners_a = find_corners(&ma, 135.0);
    let corners_b = find_corners(&mb, 135.0);
    let path_a = nearest_corner_segment(&ma, &corners_a, [0.3, 0.2]).unwrap();
    let mut path_b = nearest_corner_segment(&mb, &corners_b, [0.0, 0.2]).unwrap();
    path_b.positions.reverse();
    path_b.direction = path_b.direction.reversed();
    let seam = Seam::from_paths("side", 0, &ma, &path_a, 1, &mb, &path_b, SeamMode::Equal).unwrap();

    for h in [0.013, 0.031] {
        let meshes = vec![tri(&pa, h), tri(&pb, h)];
        let r = seam.resolve(&meshes).unwrap();
        let (na, nb) = (&meshes[0], &meshes[1]);
        for (m, path, ends) in [(na, &r.a, [[0.3, 0.0], [0.3, 0.4]]), (nb, &r.b, [[0.0, 0.0], [0.0, 0.4]])] {
            assert!(near(m.contour_point(path.first()), ends[0], h));
            assert!(near(m.contour_point(path.last()), ends[1], h));
        }
        assert_eq!(r.a.len(), (0.4f64 / h).round() as usize + 1);
        assert_eq!(r.pairs(na, nb).unwrap().len(), r.a.len());
    }

    // A run between arbitrary points (not corners) lands within one edge length.
    let run = path_between(
        &ma,
        nearest_contour_position(&ma, [0.05, 0.0]),
        nearest_contour_position(&ma, [0.21, 0.0]),
        Direction::Ccw,
    )
    .unwrap();
    let finer = tri(&pa, 0.007);
    let moved = remap_path(&ma, &run, &finer).unwrap();
    let old = |p: usize| ma.contour_point(p).map(|c| c as f64);
    assert!(near(finer.contour_point(moved.first()), old(run.first()), 0.007));
    assert!(near(finer.contour_point(moved.last()), old(run.last()), 0.007));
    assert_eq!(moved.direction, Direction::Ccw);
}

fn check_weights(pairs: &[SeamPair]) {
    for p in pairs {
        for side in [p.a, p.b] {
            assert!((side[0].1 + side[1].1 - 1.0).abs() < 1e-6, "{p:?}");
            assert!(side.iter().all(|&(_, w)| (0.0..=1.0).contains(&w)));
        }
    }
}

#[test]
fn unequal_counts_sew_arc_length_matched_points() {
    let (pa, pb) = (rectangle("front", 0.3, 0.4), rectangle("back", 0.3, 0.4));
    let (ma, mb) = (tri(&pa, 0.02), tri(&pb, 0.013));
    let a = span_path(&ma, 1).unwrap();
    let b = path_between(&mb, mb.span_map[3][1], mb.span_map[3][0], Direction::Cw).unwrap();
    assert_ne!(a.len(), b.len());
    let e = Seam::from_paths("mismatch", 0, &ma, &a, 1, &mb, &b, SeamMode::Equal).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { ref seam, .. } if seam == "mismatch"), "{e}");

    let seam = Seam::from_paths("side", 0, &ma, &a, 1, &mb, &b, SeamMode::Unequal).unwrap();
    let r = seam.resolve(&[ma.clone(), mb.clone()]).unwrap();
    let pairs = r.pairs(&ma, &mb).unwrap();
    check_weights(&pairs);
    // Shared ends (t = 0 and t = 1) are paired once: nA + nB - 2 pairs.
    assert_eq!(pairs.len(), a.len() + b.len() - 2);
    for p in &pairs {
        let (qa, qb) = (pt(&ma, p.a), pt(&mb, p.b));
        assert!((qa[1] - qb[1]).abs() < 1e-5 && (qa[0] - 0.3).abs() < 1e-6 && qb[0].abs() < 1e-6, "{qa:?} {qb:?}");
    }
    let hinges = r.hinges(&ma, &mb).unwrap();
    assert_eq!(hinges.len(), a.len() - 1);
    for h in &hinges {
        for (k, &v) in h.a_edge.iter().enumerate() {
            assert!((pt(&mb, h.b_edge[k])[1] - ma.rest[v as usize][1] as f64).abs() < 1e-5);
        }
    }

    // Identical curves at different resolutions: the sleeve cap against itself.
    let s = sleeve();
    let (m1, m2) = (tri(&s, 0.02), tri(&s, 0.011));
    let cap = |m: &PieceMesh| path_between(m, m.span_map[2][0], m.span_map[2][1], Direction::Ccw).unwrap();
    let (c1, c2) = (cap(&m1), cap(&m2));
    let seam = Seam::from_paths("cap", 0, &m1, &c1, 1, &m2, &c2, SeamMode::Unequal).unwrap();
    let r = seam.resolve(&[m1.clone(), m2.clone()]).unwrap();
    assert!((r.length_ratio - 1.0).abs() < 1e-3);
    let pairs = r.pairs(&m1, &m2).unwrap();
    check_weights(&pairs);
    let worst = pairs.iter().map(|p| {
        let (qa, qb) = (pt(&m1, p.a), pt(&m2, p.b));
        ((qa[0] - qb[0]).powi(2) + (qa[1] - qb[1]).powi(2)).sqrt()
    });
    let worst = worst.fold(0.0, f64::max);
    assert!(worst < 1e-3, "sewn points of identical curves are {worst} m apart");
}

#[test]
fn eased_seam_spreads_the_longer_side_evenly() {
    let (pa, pb) = (rectangle("sleeve", 0.3, 0.4), rectangle("armhole", 0.3, 0.3));
    let (ma, mb) = (tri(&pa, 0.02), tri(&pb, 0.02));
    let a = path_between(&ma, ma.span_map[1][0], ma.span_map[1][1], Direction::Ccw).unwrap();
    let b = path_between(&mb, mb.span_map[3][1], mb.span_map[3][0], Direction::Cw).unwrap();
    let seam = Seam::from_paths("ease", 0, &ma, &a, 1, &mb, &b, SeamMode::Unequal).unwrap();
    let r = seam.resolve(&[ma.clone(), mb.clone()]).unwrap();
    assert!((r.length_ratio - 4.0 / 3.0).abs() < 1e-6);
    let pairs = r.pairs(&ma, &mb).unwrap();
    check_weights(&pairs);
    for p in &pairs {
        let (qa, qb) = (pt(&ma, p.a), pt(&mb, p.b));
        assert!((qa[1] / 0.4 - qb[1] / 0.3).abs() < 1e-5);
    }
}

#[test]
fn validation_errors_name_the_seam() {
    let m = tri(&rectangle("r", 0.3, 0.4), 0.02);
    let interior = (0..m.rest.len() as u32).find(|v| !m.contour.contains(v)).unwrap();
    let e = path_from_vertices("s1", "A", &m, &[m.contour[0], interior]).unwrap_err();
    assert!(
        matches!(e, TailorError::InvalidSeam { ref seam, ref reason } if seam == "s1" && reason.contains("not on the contour")),
        "{e}"
    );
    let e = path_from_vertices("s2", "A", &m, &[m.contour[0], m.contour[2]]).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { ref reason, .. } if reason.contains("not consecutive")), "{e}");
    let e = path_from_vertices("s3", "B", &m, &[m.contour[0]]).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { .. }), "{e}");
    let ok = path_from_vertices("s4", "A", &m, &[m.contour[3], m.contour[2], m.contour[1]]).unwrap();
    assert_eq!(ok.direction, Direction::Cw);
    // Direction inconsistent with the steps.
    let bad = ContourPath { positions: vec![1, 2, 3], direction: Direction::Cw };
    assert!(matches!(check_side("s5", "A", &m, &bad), Err(TailorError::InvalidSeam { .. })));

    // Same piece: overlapping sides are rejected, a shared dart tip is allowed.
    let a = path_of_n(&m, 5, 4, Direction::Ccw).unwrap();
    let b = path_of_n(&m, 7, 4, Direction::Ccw).unwrap();
    let e = Seam::from_paths("overlap", 0, &m, &a, 0, &m, &b, SeamMode::Equal).unwrap_err();
    assert!(
        matches!(e, TailorError::InvalidSeam { ref seam, ref reason } if seam == "overlap" && reason.contains("both sides")),
        "{e}"
    );
    let tip_a = path_of_n(&m, 10, 4, Direction::Ccw).unwrap();
    let tip_b = path_of_n(&m, 10, 4, Direction::Cw).unwrap();
    Seam::from_paths("dart", 0, &m, &tip_a, 0, &m, &tip_b, SeamMode::Equal).unwrap();

    // A seam referring to a missing piece.
    let s = Seam::from_paths("x", 0, &m, &a, 1, &m, &tip_b, SeamMode::Equal).unwrap();
    let e = s.resolve(std::slice::from_ref(&m)).unwrap_err();
    assert!(matches!(e, TailorError::InvalidSeam { ref seam, .. } if seam == "x"), "{e}");
    assert!(matches!(path_of_n(&m, 0, 999, Direction::Ccw), Err(TailorError::InvalidSetting { .. })));
    assert!(matches!(shortest_path(&m, 0, 999), Err(TailorError::IndexOutOfRange { .. })));
    assert!(matches!(span_path(&m, 4), Err(TailorError::IndexOutOfRange { index: 4, .. })));
    let empty = ContourPath { positions: vec![], direction: Direction::Ccw };
    assert!(SeamSide::from_path(0, &m, &empty).is_err());
    assert!(remap_path(&m, &bad, &m).is_ok());
    let off = ContourPath { positions: vec![1, 99999], direction: Direction::Ccw };
    assert!(remap_path(&m, &off, &m).is_err());
}

#[test]
fn sewing_concatenates_pieces_and_shifts_the_seams() {
    let (pa, pb) = (rectangle("front", 0.3, 0.4), rectangle("back", 0.3, 0.4));
    let (ma, mb) = (tri(&pa, 0.02), tri(&pb, 0.013));
    let a = span_path(&ma, 1).unwrap();
    let b = path_between(&mb, mb.span_map[3][1], mb.span_map[3][0], Direction::Cw).unwrap();
    let seam = Seam::from_paths("side", 0, &ma, &a, 1, &mb, &b, SeamMode::Unequal).unwrap();
    let meshes = vec![ma.clone(), mb.clone()];
    // Back piece placed 0.3 m to the left of the front, so the sewn sides already touch.
    let pos = vec![
        ma.rest.iter().map(|r| [r[0], r[1], 0.0]).collect(),
        mb.rest.iter().map(|r| [r[0] + 0.3, r[1], 0.0]).collect::<Vec<_>>(),
    ];
    let g = sew(&meshes, &pos, &[seam]).unwrap();
    assert_eq!(g.mesh.num_vertices(), ma.rest.len() + mb.rest.len());
    assert_eq!(g.offsets, vec![0, ma.rest.len() as u32]);
    assert_eq!(g.pairs.len(), g.pair_seam.len());
    assert_eq!(g.hinges.len(), a.len() - 1);
    let at = |w: WeightedPoint| {
        let mut p = [0.0f64; 3];
        for (v, wt) in w {
            for (o, &c) in p.iter_mut().zip(&g.mesh.positions()[v as usize]) {
                *o += wt as f64 * c as f64;
            }
        }
        p
    };
    for p in &g.pairs {
        let (x, y) = (at(p.a), at(p.b));
        assert!((0..3).all(|k| (x[k] - y[k]).abs() < 1e-5), "{x:?} {y:?}");
    }
    assert!(sew(&meshes, &pos[..1], &[]).is_err());
}
