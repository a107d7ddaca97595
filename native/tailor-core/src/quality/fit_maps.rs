//! Per-vertex fit maps of a garment state, the three garment tools show to judge fit (issue 28):
//!
//! * **strain**: the stretch of the cloth round each vertex against its 2D pattern, the
//!   area-weighted mean over the vertex's triangles of `σ₁ − 1`, where `σ₁` is the largest
//!   singular value of the triangle's deformation gradient `F = Ds·Dm⁻¹` (3×2, see
//!   `solver::model::constraints::triangle`): 0.05 is 5 % stretch along the most stretched
//!   direction, whatever the direction (warp, weft or bias). `σ₁² ` is the larger eigenvalue of
//!   `FᵀF = [[a, b], [b, c]]`: `(a + c)/2 + √(((a − c)/2)² + b²)`.
//! * **distance**: the signed distance of each vertex to the body's surface, metres, positive
//!   outside (a closed mesh: [`ClosedMesh`]): how tight or loose the garment sits.
//! * **pressure**: the body's push on the cloth per unit area, pascals, at vertices within a
//!   contact band of the surface: at rest the body balances the cloth's own forces, so its
//!   reaction is `R = −(f_elastic + m·g)` and the pressure `max(0, R·n̂) / A`, with `n̂` the
//!   outward direction from the surface's closest point and `A` the vertex's share of the
//!   pattern's area (a third of each of its triangles). `f_elastic` is given by the caller (the
//!   solver's stretch and shear forces: `Simulation::fit_maps`). A static reading: in motion the
//!   cloth's inertia is left out, as garment tools show fit at rest.

use glam::Vec3;

use crate::collision::closed_mesh::ClosedMesh;
use crate::collision::geometry::{closest_point_on_triangle, triangle_normal};
use crate::error::{Result, TailorError};

/// The maps of one state (see the module docs); `distance` and `pressure` need a body.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FitMaps {
    /// Per vertex, `σ₁ − 1` averaged over its triangles by rest area.
    pub strain: Vec<f32>,
    /// Per vertex, signed distance to the body, metres (positive outside).
    pub distance: Option<Vec<f32>>,
    /// Per vertex, the body's pressure on the cloth, pascals (0 off the body).
    pub pressure: Option<Vec<f32>>,
}

fn check_triangles(n: usize, triangles: &[[u32; 3]], what: &str) -> Result<()> {
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
            return Err(TailorError::index(format!("{what} triangle {t}"), v as i64, n, "vertices"));
        }
    }
    Ok(())
}

/// `(σ₁ − 1, rest area)` of one triangle; `None` for a degenerate rest triangle.
fn triangle_stretch(x: [Vec3; 3], r: [[f32; 2]; 3]) -> Option<(f32, f32)> {
    let (d1x, d1y) = ((r[1][0] - r[0][0]) as f64, (r[1][1] - r[0][1]) as f64);
    let (d2x, d2y) = ((r[2][0] - r[0][0]) as f64, (r[2][1] - r[0][1]) as f64);
    let det = d1x * d2y - d2x * d1y;
    if det.abs() < 1e-14 {
        return None;
    }
    // F = Ds · Dm⁻¹, Dm⁻¹ = 1/det [[d2y, −d2x], [−d1y, d1x]].
    let e1 = (x[1] - x[0]).as_dvec3();
    let e2 = (x[2] - x[0]).as_dvec3();
    let f1 = (e1 * d2y - e2 * d1y) / det;
    let f2 = (-e1 * d2x + e2 * d1x) / det;
    let (a, b, c) = (f1.dot(f1), f1.dot(f2), f2.dot(f2));
    let s1 = ((a + c) / 2.0 + (((a - c) / 2.0).powi(2) + b * b).sqrt()).sqrt();
    Some(((s1 - 1.0) as f32, (det.abs() / 2.0) as f32))
}

/// The strain map: per vertex the rest-area-weighted mean of its triangles' `σ₁ − 1` (0 for a
/// vertex in no non-degenerate triangle).
pub fn vertex_strain(positions: &[[f32; 3]], rest: &[[f32; 2]], triangles: &[[u32; 3]]) -> Result<Vec<f32>> {
    let n = positions.len();
    if rest.len() != n {
        return Err(TailorError::shape("strain map", format!("{n} positions but {} rest points", rest.len())));
    }
    check_triangles(n, triangles, "cloth")?;
    let mut sum = vec![0.0f64; n];
    let mut area = vec![0.0f64; n];
    for tri in triangles {
        let x = tri.map(|v| Vec3::from(positions[v as usize]));
        let r = tri.map(|v| rest[v as usize]);
        if let Some((s, a)) = triangle_stretch(x, r) {
            for &v in tri {
                sum[v as usize] += (s * a) as f64;
                area[v as usize] += a as f64;
            }
        }
    }
    Ok(sum.iter().zip(&area).map(|(&s, &a)| if a > 0.0 { (s / a) as f32 } else { 0.0 }).collect())
}

/// Each vertex's share of the pattern's area: a third of each non-degenerate rest triangle.
pub fn vertex_areas(rest: &[[f32; 2]], triangles: &[[u32; 3]]) -> Result<Vec<f32>> {
    check_triangles(rest.len(), triangles, "cloth")?;
    let mut area = vec![0.0f32; rest.len()];
    for tri in triangles {
        let [p, q, s] = tri.map(|v| rest[v as usize]);
        let a = ((q[0] - p[0]) * (s[1] - p[1]) - (s[0] - p[0]) * (q[1] - p[1])).abs() / 2.0;
        for &v in tri {
            area[v as usize] += a / 3.0;
        }
    }
    Ok(area)
}

/// Signed distance of each point to `body`'s surface (positive outside), with the outward unit
/// direction at the closest point (from it to the point, flipped inside; the face normal
/// oriented away from `centre`, the body's surface centroid, when the point is on the surface).
fn signed_distance_and_normal(body: &ClosedMesh, centre: Vec3, p: [f32; 3]) -> (f32, Vec3) {
    let (d, t) = body.distance(p);
    let inside = body.contains(p);
    let [a, b, c] = body.triangles()[t as usize].map(|i| Vec3::from(body.vertices()[i as usize]));
    let pv = Vec3::from(p);
    let q = closest_point_on_triangle(pv, a, b, c).0;
    let sign = if inside { -1.0 } else { 1.0 };
    let away = (pv - q) * sign;
    let n = if away.length() > 1e-9 {
        away.normalize()
    } else {
        let face = triangle_normal(a, b, c).unwrap_or(Vec3::Z);
        // Outward: the side away from the body's centroid, for want of a better witness.
        if face.dot(q - centre) >= 0.0 {
            face
        } else {
            -face
        }
    };
    (d * sign, n)
}

/// The distance map: signed distance of every point to `body`, metres, positive outside.
pub fn signed_distances(points: &[[f32; 3]], body: &ClosedMesh) -> Vec<f32> {
    use rayon::prelude::*;
    body.prepare_queries();
    let centre = Vec3::from(body.surface_centroid());
    points.par_iter().map(|&p| signed_distance_and_normal(body, centre, p).0).collect()
}

/// The pressure map (see the module docs): `forces` are the cloth's own forces on each vertex
/// (elastic and gravity, newtons), `areas` its share of the pattern's area; vertices farther
/// than `band` from the surface (outside) get 0.
pub fn contact_pressure(
    points: &[[f32; 3]],
    forces: &[Vec3],
    areas: &[f32],
    body: &ClosedMesh,
    band: f32,
) -> Result<Vec<f32>> {
    use rayon::prelude::*;
    if forces.len() != points.len() || areas.len() != points.len() {
        return Err(TailorError::shape(
            "pressure map",
            format!("{} points, {} forces, {} areas", points.len(), forces.len(), areas.len()),
        ));
    }
    body.prepare_queries();
    let centre = Vec3::from(body.surface_centroid());
    Ok(points
        .par_iter()
        .zip(forces)
        .zip(areas)
        .map(|((&p, &f), &a)| {
            let (d, n) = signed_distance_and_normal(body, centre, p);
            if d > band || a <= 0.0 {
                return 0.0;
            }
            (-f.dot(n)).max(0.0) / a
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(k: usize, size: f32) -> (Vec<[f32; 2]>, Vec<[u32; 3]>) {
        let mut rest = Vec::new();
        for j in 0..=k {
            for i in 0..=k {
                rest.push([i as f32 * size / k as f32, j as f32 * size / k as f32]);
            }
        }
        let mut tris = Vec::new();
        let at = |i: usize, j: usize| (j * (k + 1) + i) as u32;
        for j in 0..k {
            for i in 0..k {
                tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        (rest, tris)
    }

    #[test]
    fn strain_is_the_largest_stretch_in_any_direction() {
        let (rest, tris) = grid(6, 0.3);
        // Unstretched, turned into 3D: 0 everywhere.
        let flat: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], 0.2, r[1]]).collect();
        assert!(vertex_strain(&flat, &rest, &tris).unwrap().iter().all(|s| s.abs() < 1e-5));
        // 5 % along the weft only, then 4 % along a bias (a 45° shear-free stretch): each reads
        // as its own amount, whatever its direction.
        let weft: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], r[1] * 1.05, 0.0]).collect();
        assert!(vertex_strain(&weft, &rest, &tris).unwrap().iter().all(|s| (s - 0.05).abs() < 1e-4));
        let u = glam::Vec2::new(1.0, 1.0).normalize();
        let bias: Vec<[f32; 3]> = rest
            .iter()
            .map(|r| {
                let p = glam::Vec2::from(*r);
                let q = p + u * (p.dot(u) * 0.04);
                [q.x, q.y, 0.0]
            })
            .collect();
        assert!(vertex_strain(&bias, &rest, &tris).unwrap().iter().all(|s| (s - 0.04).abs() < 1e-4));
        // Shape errors name what.
        let err = vertex_strain(&flat[1..], &rest, &tris).unwrap_err().to_string();
        assert!(err.contains("strain map"), "{err}");
        let err = vertex_strain(&flat, &rest, &[[0, 1, 99]]).unwrap_err().to_string();
        assert!(err.contains("cloth triangle 0"), "{err}");
    }

    #[test]
    fn areas_share_the_pattern() {
        let (rest, tris) = grid(4, 0.2);
        let a = vertex_areas(&rest, &tris).unwrap();
        assert!((a.iter().sum::<f32>() - 0.04).abs() < 1e-6);
    }

    #[test]
    fn distance_is_signed_and_pressure_is_the_bodys_reaction() {
        let (v, t) = crate::scenes::box_mesh([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]);
        let body = ClosedMesh::new(&v, &t).unwrap();
        let points = [[0.0, 0.0, 0.503], [0.1, 0.0, 0.6], [0.0, 0.0, 0.45]];
        let d = signed_distances(&points, &body);
        assert!((d[0] - 0.003).abs() < 1e-5 && (d[1] - 0.1).abs() < 1e-5 && (d[2] + 0.05).abs() < 1e-5, "{d:?}");
        // Cloth on the top face pressed down by 1.5 N/m² of weight: 1.5 Pa; pulled up, none; off
        // the band, none.
        let down = Vec3::new(0.0, 0.0, -1.5e-4);
        let p = contact_pressure(&points, &[down, down, -down], &[1e-4; 3], &body, 0.005).unwrap();
        assert!((p[0] - 1.5).abs() < 1e-4 && p[1] == 0.0 && p[2] == 0.0, "{p:?}");
        let err = contact_pressure(&points, &[down], &[1e-4; 3], &body, 0.005).unwrap_err().to_string();
        assert!(err.contains("pressure map"), "{err}");
    }
}
