//! The welded garment: pieces merged along equal and unequal seams into one watertight mesh,
//! frames and per-corner attributes carried over, bad input refused with what and where.

mod common;

use std::collections::{HashMap, HashSet};
use std::path::Path;

use common::rectangle;
use tailor_core::garment::{solver_input, triangulate_all, BuildOptions};
use tailor_core::garment_file;
use tailor_core::scenes::{self, grid_column};
use tailor_core::seam::{nearest_contour_position, sew, shortest_path, Seam as PatternSeam, SeamMode};
use tailor_core::solver::{Seam, SeamPoint};
use tailor_core::triangulate::{triangulate_piece, PieceMesh, TriangulateOptions};
use tailor_core::weld::{weld, weld_garment, WeldedMesh};
use tailor_core::TailorError;

/// Undirected edge -> number of triangles.
fn edge_counts(tris: &[[u32; 3]]) -> HashMap<(u32, u32), usize> {
    let mut out = HashMap::new();
    for t in tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *out.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    out
}

fn area(p: &[[f32; 3]], tris: &[[u32; 3]]) -> f64 {
    tris.iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| p[v as usize].map(f64::from));
            let (u, v) = ([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
            let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
        })
        .sum()
}

/// The welded vertex of each pair (through whichever side is a vertex), in seam order; every
/// consecutive two must be an edge with exactly two triangles.
fn assert_seams_watertight(w: &WeldedMesh, seams: &[Seam]) -> usize {
    let counts = edge_counts(&w.triangles);
    let mut checked = 0;
    for s in seams {
        let welded: Vec<u32> = s
            .pairs
            .iter()
            .map(|(a, b)| {
                let v = |p: &SeamPoint| (p.weights[1] == 0.0 || p.verts[0] == p.verts[1]).then_some(p.verts[0]);
                let (va, vb) = (v(a), v(b));
                let w_of = |x: u32| w.vertex_map[x as usize];
                if let (Some(x), Some(y)) = (va, vb) {
                    assert_eq!(w_of(x), w_of(y), "seam {}: a vertex pair is not merged", s.name);
                }
                w_of(va.or(vb).expect("one side of a seam pair is a vertex"))
            })
            .collect();
        for e in welded.windows(2) {
            if e[0] == e[1] {
                continue;
            }
            let c = counts.get(&(e[0].min(e[1]), e[0].max(e[1]))).copied().unwrap_or(0);
            assert_eq!(c, 2, "seam {}: welded edge ({}, {}) has {c} triangles", s.name, e[0], e[1]);
            checked += 1;
        }
    }
    checked
}

fn euler(w: &WeldedMesh) -> i64 {
    w.num_vertices() as i64 - edge_counts(&w.triangles).len() as i64 + w.triangles.len() as i64
}

#[test]
fn two_squares_on_an_equal_seam_become_one_manifold_sheet() {
    let (n, side) = (4usize, 0.5f32);
    let (rest, tris) = scenes::rectangle(side, side, n, n);
    let nv = rest.len() as u32;
    let mut positions: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], r[1], 0.0]).collect();
    // B to the right of A, 1 mm off (an almost closed seam).
    positions.extend(rest.iter().map(|r| [r[0] + side, r[1], 0.001]));
    let mut triangles = tris.clone();
    triangles.extend(tris.iter().map(|t| t.map(|v| v + nv)));
    let b_left: Vec<u32> = grid_column(n, n, 0).into_iter().map(|v| v + nv).collect();
    let seam = Seam::one_to_one("side", &grid_column(n, n, n), &b_left, 1e3, 1e-5).unwrap();
    let w = weld(&positions, &triangles, std::slice::from_ref(&seam)).unwrap();

    assert_eq!(w.stats.merged, n + 1);
    assert_eq!(w.num_vertices(), 2 * nv as usize - (n + 1));
    assert_eq!((w.stats.inserted_points, w.stats.centroids, w.stats.collapsed_triangles), (0, 0, 0));
    assert_eq!(w.triangles.len(), triangles.len());
    // A (2n × n)-cell grid with one diagonal per cell.
    let (cols, rows) = (2 * n, n);
    let edges = cols * (rows + 1) + rows * (cols + 1) + cols * rows;
    assert_eq!(edge_counts(&w.triangles).len(), edges);
    assert_eq!(w.stats.boundary_edges, 2 * (cols + rows));
    assert_eq!((w.stats.non_manifold_edges, w.stats.misoriented_edges), (0, 0));
    assert_eq!(euler(&w), 1, "a disc");
    // No two welded vertices in the same place; the seam's are at the mean of their pair.
    let distinct: HashSet<[u32; 2]> =
        w.positions.iter().map(|p| [(p[0] * 1e4).round() as u32, (p[1] * 1e4).round() as u32]).collect();
    assert_eq!(distinct.len(), w.num_vertices());
    for &v in &grid_column(n, n, n) {
        assert!((w.positions[w.vertex_map[v as usize] as usize][2] - 0.0005).abs() < 1e-7);
    }
    assert_eq!(assert_seams_watertight(&w, &[seam]), n);
    // The map carries a frame over: the input positions weld to the welded positions.
    assert_eq!(w.apply(&positions).unwrap(), w.positions);
}

/// Two `0.3 × 0.4` rectangles triangulated at different edge lengths, A's right side sewn to
/// B's left side (unequal counts), B placed to the right of A.
fn unequal_pair(ha: f64, hb: f64) -> (Vec<PieceMesh>, tailor_core::seam::SewnGarment) {
    let opts = |h| TriangulateOptions::new(h);
    let (ma, mb) = (
        triangulate_piece(&rectangle("A", 0.3, 0.4), &opts(ha)).unwrap(),
        triangulate_piece(&rectangle("B", 0.3, 0.4), &opts(hb)).unwrap(),
    );
    let pa = shortest_path(&ma, nearest_contour_position(&ma, [0.3, 0.0]), nearest_contour_position(&ma, [0.3, 0.4]))
        .unwrap();
    let pb = shortest_path(&mb, nearest_contour_position(&mb, [0.0, 0.0]), nearest_contour_position(&mb, [0.0, 0.4]))
        .unwrap();
    let seam = PatternSeam::from_paths("side", 0, &ma, &pa, 1, &mb, &pb, SeamMode::Unequal).unwrap();
    let pos = |m: &PieceMesh, dx: f32| m.rest.iter().map(|r| [r[0] + dx, r[1], 0.0]).collect::<Vec<_>>();
    let positions = vec![pos(&ma, 0.0), pos(&mb, 0.3)];
    let meshes = vec![ma, mb];
    let sewn = sew(&meshes, &positions, &[seam]).unwrap();
    (meshes, sewn)
}

fn solver_seams(sewn: &tailor_core::seam::SewnGarment) -> Vec<Seam> {
    let pt = |p: [(u32, f32); 2]| SeamPoint { verts: [p[0].0, p[1].0], weights: [p[0].1, p[1].1] };
    vec![Seam {
        name: "side".into(),
        pairs: sewn.pairs.iter().map(|p| (pt(p.a), pt(p.b))).collect(),
        stiffness: 1e3,
        bend_stiffness: 1e-5,
    }]
}

#[test]
fn an_unequal_seam_welds_watertight() {
    // 5 vertices up A's right side against 8 up B's left side.
    let (meshes, sewn) = unequal_pair(0.1, 0.4 / 7.0);
    let side = |m: &PieceMesh, x: f32| m.rest.iter().filter(|r| (r[0] - x).abs() < 1e-6).count();
    assert_eq!((side(&meshes[0], 0.3), side(&meshes[1], 0.0)), (5, 8));
    let seams = solver_seams(&sewn);
    let positions = sewn.mesh.positions().to_vec();
    let w = weld(&positions, sewn.mesh.triangles(), &seams).unwrap();

    // A's 3 inner side vertices land inside B's edges, B's 6 inside A's: 9 new points, and the
    // 11 pairs (5 + 6) each merge two.
    assert_eq!((w.stats.inserted_points, w.stats.merged), (9, 11));
    let n_in = positions.len();
    assert_eq!(w.num_vertices(), n_in + 9 + w.stats.centroids - 11);
    assert_eq!(w.stats.collapsed_triangles, 0);
    assert!(w.stats.split_triangles >= 7, "{:?}", w.stats);
    // Watertight: every welded seam edge has two triangles, no border edge runs along x = 0.3,
    // and the surface lost or gained no area.
    assert_eq!(assert_seams_watertight(&w, &seams), 10, "11 seam points, 10 edges");
    let on_seam = |v: u32| (w.positions[v as usize][0] - 0.3).abs() < 1e-6;
    let open: Vec<_> =
        edge_counts(&w.triangles).into_iter().filter(|(e, c)| *c == 1 && on_seam(e.0) && on_seam(e.1)).collect();
    assert!(open.is_empty(), "T-junctions left along the seam: {open:?}");
    assert!((area(&w.positions, &w.triangles) - 2.0 * 0.12).abs() < 1e-6);
    assert_eq!((w.stats.non_manifold_edges, w.stats.misoriented_edges), (0, 0));
    assert_eq!(euler(&w), 1);
    let corners: usize = edge_counts(&w.triangles).values().filter(|&&c| c == 1).count();
    assert_eq!(corners, w.stats.boundary_edges);

    // UVs (the rest shape, per corner) carry over: every welded corner's UV is the rest
    // position of its point on its own piece.
    let rest = sewn.mesh.rest();
    let uv: Vec<f32> = sewn.mesh.triangles().iter().flat_map(|t| t.iter().flat_map(|&v| rest[v as usize])).collect();
    let out = w.apply_corners(&uv, 2).unwrap();
    assert_eq!(out.len(), 6 * w.triangles.len());
    for (t, tri) in w.triangles.iter().enumerate() {
        let src = w.triangle_source[t] as usize;
        let dx = if (src as usize) < meshes[0].triangles.len() { 0.0 } else { 0.3 };
        for (k, &v) in tri.iter().enumerate() {
            // Rest and placement differ by the piece's shift in x only.
            let p = w.positions[v as usize];
            assert!((out[6 * t + 2 * k] + dx - p[0]).abs() < 1e-5 && (out[6 * t + 2 * k + 1] - p[1]).abs() < 1e-5);
        }
    }
}

#[test]
fn a_sewn_tube_closes_along_its_seams() {
    let tube = scenes::sewn_tube(0.4, 0.3, 0.05, 0.02, 0.0, 1e3).unwrap();
    let m = &tube.mesh;
    let w = weld(m.positions(), m.triangles(), &tube.seams).unwrap();
    let (nx, ny) = (8, 6);
    assert_eq!(w.stats.merged, 2 * (ny + 1));
    assert_eq!(w.num_vertices(), m.num_vertices() - 2 * (ny + 1));
    // Only the two rims are open: nx edges per panel at the top and at the bottom.
    assert_eq!(w.stats.boundary_edges, 4 * nx);
    assert_eq!((w.stats.non_manifold_edges, w.stats.misoriented_edges), (0, 0));
    assert_eq!(euler(&w), 0, "a cylinder");
    assert_eq!(assert_seams_watertight(&w, &tube.seams), 2 * ny);
    // The open 2 cm seams weld at their middle.
    let v = tube.seams[0].pairs[0].0.verts[0];
    assert!(w.positions[w.vertex_map[v as usize] as usize][1].abs() < 1e-7);
}

#[test]
fn the_sample_garments_weld_with_every_seam_edge_shared_by_two_triangles() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample_blends");
    let (mut welded, mut unequal) = (0, 0);
    for name in ["skirt", "tshirt", "trousers", "layered"] {
        let path = dir.join(format!("{name}.json"));
        let garment = garment_file::load(&path).unwrap();
        let input = solver_input(&garment, triangulate_all(&garment).unwrap(), &BuildOptions::default()).unwrap();
        let w = weld_garment(&input, None).unwrap();
        let checked = assert_seams_watertight(&w, &input.seams);
        let s = w.stats;
        eprintln!(
            "{name}: {} -> {} vertices, {} seam edges shared by two triangles, {s:?}",
            s.input_vertices,
            w.num_vertices(),
            checked
        );
        assert!(checked > 0);
        assert_eq!(s.non_manifold_edges, 0, "{name}: {s:?}");
        // Flipping whole pieces makes every seam consistent (the layered sample on 2 cm pieces
        // kept 22 edges wound the same way on both sides; on its 1 cm pieces, none).
        assert_eq!(s.misoriented_edges, 0, "{name}: {s:?}");
        assert_eq!(w.num_vertices(), s.input_vertices + s.inserted_points + s.centroids - s.merged);
        // Unequal seams insert points (the layered sample's 1 cm pieces pair every seam equally).
        unequal += usize::from(s.inserted_points > 0);
        // Fewer borders than the pieces had: the seams are closed.
        let pieces_border = edge_counts(input.sewn.mesh.triangles()).values().filter(|&&c| c == 1).count();
        assert!(s.boundary_edges < pieces_border - checked, "{name}: {s:?}");
        welded += 1;
    }
    assert_eq!(welded, 4);
    assert_eq!(unequal, 3, "the skirt, T-shirt and trousers have unequal seams");
}

#[test]
fn bad_input_is_refused_with_what_and_where() {
    let (rest, tris) = scenes::rectangle(1.0, 1.0, 2, 2);
    let mut p: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], r[1], 0.0]).collect();
    let seam = |a: SeamPoint, b: SeamPoint| Seam {
        name: "hem".into(),
        pairs: vec![(a, b)],
        stiffness: 1.0,
        bend_stiffness: 0.0,
    };
    let ok = seam(SeamPoint::vertex(0), SeamPoint::vertex(2));
    weld(&p, &tris, std::slice::from_ref(&ok)).unwrap();

    let e = weld(&p, &tris, &[seam(SeamPoint::vertex(0), SeamPoint::vertex(42))]).unwrap_err();
    assert_eq!(e.to_string(), "weld: seam 'hem' pair 0 side B: index 42 is out of range (only 9 vertices)");
    let e = weld(&p, &tris, &[seam(SeamPoint::vertex(0), SeamPoint::on_edge(0, 8, 0.5))]).unwrap_err();
    assert!(
        matches!(&e, TailorError::InvalidSeam { seam, reason } if seam == "hem" && reason.contains("0 and 8")),
        "{e}"
    );
    let mut bad_w = SeamPoint::on_edge(0, 1, 0.5);
    bad_w.weights[0] = f32::NAN;
    let e = weld(&p, &tris, &[seam(SeamPoint::vertex(3), bad_w)]).unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");

    let mut bad_t = tris.clone();
    bad_t[3][1] = 99;
    let e = weld(&p, &bad_t, &[]).unwrap_err();
    assert_eq!(e.to_string(), "weld: triangle 3: index 99 is out of range (only 9 vertices)");
    p[5][2] = f32::NAN;
    let e = weld(&p, &tris, &[]).unwrap_err();
    assert_eq!(e.to_string(), "weld: positions: vertex 5 has a non-finite coordinate (NaN)");
    assert!(matches!(weld(&[], &[], &[]).unwrap_err(), TailorError::EmptyMesh { .. }));

    p[5][2] = 0.0;
    let w = weld(&p, &tris, &[ok]).unwrap();
    let e = w.apply(&p[..4]).unwrap_err();
    assert!(matches!(e, TailorError::ShapeMismatch { .. }), "{e}");
    let e = w.apply_corners(&[0.0; 5], 2).unwrap_err();
    assert!(e.to_string().contains("expected 24 corners"), "{e}");
}

#[test]
fn a_piece_wound_the_other_way_is_flipped_to_match() {
    let (n, side) = (3usize, 0.5f32);
    let (rest, tris) = scenes::rectangle(side, side, n, n);
    let nv = rest.len() as u32;
    let mut positions: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], r[1], 0.0]).collect();
    positions.extend(rest.iter().map(|r| [r[0] + side, r[1], 0.0]));
    // A, then B with every triangle reversed; A is the smaller part once C (below) joins B.
    let mut triangles = tris.clone();
    triangles.extend(tris.iter().map(|t| [t[0] + nv, t[2] + nv, t[1] + nv]));
    let b_left: Vec<u32> = grid_column(n, n, 0).into_iter().map(|v| v + nv).collect();
    let seam = Seam::one_to_one("side", &grid_column(n, n, n), &b_left, 1e3, 1e-5).unwrap();
    let w = weld(&positions, &triangles, std::slice::from_ref(&seam)).unwrap();
    assert_eq!((w.stats.flipped_pieces, w.stats.misoriented_edges), (1, 0));
    // The larger of the two parts keeps its winding (a tie keeps the first piece's).
    assert_eq!(&w.triangles[..tris.len()], &tris[..]);
    // Flipped corners keep their barycentric weights with them: corner k is still the source
    // triangle's vertex it came from.
    let t = tris.len();
    let src = triangles[w.triangle_source[t] as usize];
    for k in 0..3 {
        let from = w.corner_weights[t][k].iter().position(|&x| x == 1.0).unwrap();
        assert_eq!(w.vertex_map[src[from] as usize], w.triangles[t][k]);
    }
}

#[test]
fn a_dart_sewn_shut_drops_its_collapsed_tip_triangle() {
    // A fan of triangles around vertex 0; sewing 1 to 2 closes the wedge (0, 1, 2).
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]];
    let tris = vec![[0, 1, 2], [0, 2, 3]];
    let seam = Seam {
        name: "dart".into(),
        pairs: vec![(SeamPoint::vertex(1), SeamPoint::vertex(2))],
        stiffness: 1.0,
        bend_stiffness: 0.0,
    };
    let w = weld(&p, &tris, &[seam]).unwrap();
    assert_eq!((w.stats.collapsed_triangles, w.triangles.len(), w.num_vertices()), (1, 1, 3));
    assert_eq!(w.triangle_source, vec![1]);
}
