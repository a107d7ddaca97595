//! Synthetic pattern pieces shared by the triangulation and seam tests.
#![allow(dead_code)]

use tailor_core::pattern::{OutlineSpan, Piece, Point2};

pub fn piece(name: &str, outline: Vec<Point2>, fixed: Vec<usize>) -> Piece {
    Piece {
        name: name.into(),
        outline,
        fixed_vertices: fixed,
        holes: vec![],
        internal_lines: vec![],
        notches: vec![],
        grain: None,
        placement: None,
        edges: vec![],
    }
}

/// A w × h rectangle with its lower-left corner at the origin, corners fixed, one span per side.
pub fn rectangle(name: &str, w: f64, h: f64) -> Piece {
    let mut p = piece(name, vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]], vec![0, 1, 2, 3]);
    p.edges = (0..4).map(|i| OutlineSpan { start: i, end: (i + 1) % 4 }).collect();
    p
}

/// An L: 0.4 × 0.4 with the upper-right 0.25 × 0.25 removed; no fixed vertices (corners are
/// found by their turning angle).
pub fn l_shape() -> Piece {
    piece("L", vec![[0.0, 0.0], [0.4, 0.0], [0.4, 0.15], [0.15, 0.15], [0.15, 0.4], [0.0, 0.4]], vec![])
}

/// A 0.4 m square with a clockwise square hole, a free internal line and a dart line that
/// starts on the outline.
pub fn holed() -> Piece {
    let mut p = piece("holed", vec![[0.0, 0.0], [0.4, 0.0], [0.4, 0.4], [0.0, 0.4]], vec![0, 1, 2, 3]);
    p.holes = vec![vec![[0.15, 0.15], [0.15, 0.25], [0.25, 0.25], [0.25, 0.15]]];
    p.internal_lines = vec![vec![[0.06, 0.07], [0.06, 0.33]], vec![[0.32, 0.0], [0.32, 0.12]]];
    p.notches = vec![[0.2, 0.4]];
    p
}

/// Polygon area of the outline minus the holes.
pub fn polygon_area(p: &Piece) -> f64 {
    let a = |pts: &[Point2]| {
        let m = pts.len();
        (0..m).map(|i| pts[i][0] * pts[(i + 1) % m][1] - pts[(i + 1) % m][0] * pts[i][1]).sum::<f64>() * 0.5
    };
    a(&p.outline) - p.holes.iter().map(|h| a(h).abs()).sum::<f64>()
}

/// A sleeve: straight cuff 0.26 m wide, tapered sides up to a half-ellipse cap (flattened to
/// 64 chords). Corners (cuff ends and underarm points) are fixed; the cap is one span.
pub fn sleeve() -> Piece {
    let mut outline = vec![[-0.13, 0.0], [0.13, 0.0], [0.2, 0.45]];
    for k in 1..64 {
        let t = std::f64::consts::PI * k as f64 / 64.0;
        outline.push([0.2 * t.cos(), 0.45 + 0.15 * t.sin()]);
    }
    outline.push([-0.2, 0.45]);
    let n = outline.len();
    let mut p = piece("sleeve", outline, vec![0, 1, 2, n - 1]);
    p.edges = vec![
        OutlineSpan { start: 0, end: 1 },
        OutlineSpan { start: 1, end: 2 },
        OutlineSpan { start: 2, end: n - 1 },
        OutlineSpan { start: n - 1, end: 0 },
    ];
    p
}
