//! Contour corners and the automatic seam suggestion (paper Sec. 4, Fig. 3).
//!
//! At contour vertex `v_i` the angle between its two contour edges is
//! `φ_i = ∠(v_{i-1} − v_i, v_{i+1} − v_i) ∈ [0°, 180°]` (180° on a straight run; a convex or a
//! concave right-angle corner both give 90°). A corner is a vertex with `φ_i` under a
//! threshold. Seams usually join two "symmetric portions of contour delimited by corners", so
//! hovering near the contour suggests the run between the two corners around the nearest
//! contour edge.

use super::paths::{path_between, ContourPath, Direction};
use crate::error::{Result, TailorError};
use crate::triangulate::resample::segment_projection;
use crate::triangulate::PieceMesh;

/// `φ_i` in degrees for every contour position.
pub fn contour_angles_deg(mesh: &PieceMesh) -> Vec<f64> {
    let n = mesh.contour.len();
    (0..n)
        .map(|i| {
            let p = mesh.contour_point(i);
            let a = mesh.contour_point(i + n - 1);
            let b = mesh.contour_point(i + 1);
            let (ux, uy) = ((a[0] - p[0]) as f64, (a[1] - p[1]) as f64);
            let (vx, vy) = ((b[0] - p[0]) as f64, (b[1] - p[1]) as f64);
            (ux * vy - uy * vx).atan2(ux * vx + uy * vy).abs().to_degrees()
        })
        .collect()
}

/// Contour positions with `φ_i < max_angle_deg`, ascending.
pub fn find_corners(mesh: &PieceMesh, max_angle_deg: f64) -> Vec<usize> {
    contour_angles_deg(mesh).iter().enumerate().filter(|(_, &a)| a < max_angle_deg).map(|(i, _)| i).collect()
}

/// The counter-clockwise run of contour between the two consecutive `corners` (ascending
/// contour positions) that enclose the contour edge nearest `point` (rest coordinates).
pub fn nearest_corner_segment(mesh: &PieceMesh, corners: &[usize], point: [f32; 2]) -> Result<ContourPath> {
    let n = mesh.contour.len();
    if corners.len() < 2 {
        return Err(TailorError::shape(
            format!("piece {}", mesh.name),
            format!("{} corner(s) on the contour: a corner-to-corner seam needs at least two", corners.len()),
        ));
    }
    if let Some(&c) = corners.iter().find(|&&c| c >= n) {
        return Err(TailorError::index(format!("piece {} corners", mesh.name), c as i64, n, "contour vertices"));
    }
    let mut corners = corners.to_vec();
    corners.sort_unstable();
    corners.dedup();
    let p = [point[0] as f64, point[1] as f64];
    let f = |q: [f32; 2]| [q[0] as f64, q[1] as f64];
    let edge = (0..n)
        .min_by(|&i, &j| {
            let di = segment_projection(f(mesh.contour_point(i)), f(mesh.contour_point(i + 1)), p).1;
            let dj = segment_projection(f(mesh.contour_point(j)), f(mesh.contour_point(j + 1)), p).1;
            di.total_cmp(&dj)
        })
        .unwrap_or(0);
    // The last corner at or before the edge start, and the first corner after it (cyclically).
    let start = corners.iter().rev().find(|&&c| c <= edge).copied().unwrap_or(corners[corners.len() - 1]);
    let end = corners.iter().find(|&&c| c > edge).copied().unwrap_or(corners[0]);
    path_between(mesh, start, end, Direction::Ccw)
}
