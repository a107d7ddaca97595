//! Stateless point-triangle kernels: closest point, side test, and the particle-vs-cell test of
//! the mesh collider (Nylén et al. 2020, section 6).
//!
//! Triangles are oriented by their winding: the normal is `n = (b - a) × (c - a) / |…|`, and a
//! point is *in front* of a triangle when `(p - a) · n > 0`, *behind* otherwise. Collider meshes
//! are expected to have outward normals.

use glam::Vec3;

/// Closest point to `p` on triangle `abc` and its barycentric coordinates `(u, v, w)`
/// (`point = u·a + v·b + w·c`, all in `[0, 1]`, summing to one).
///
/// Ericson, *Real-Time Collision Detection*, 5.1.5: the plane of the triangle is split into
/// seven Voronoi regions (three vertices, three edges, the face); the signs of the dot products
/// `d1..d6` of `p - a`, `p - b`, `p - c` with the edges `ab`, `ac` tell which region holds `p`,
/// and only that region's projection is computed. Zero-area triangles fall back to the closest
/// of their three edges.
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, [f32; 3]) {
    let ab = b - a;
    let ac = c - a;
    if ab.cross(ac).length_squared() <= f32::EPSILON * f32::EPSILON * ab.length_squared() * ac.length_squared() {
        return closest_on_degenerate(p, a, b, c);
    }
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

/// Closest point on segment `ab` and its parameter `t` (`a + t (b - a)`).
pub fn closest_point_on_segment(p: Vec3, a: Vec3, b: Vec3) -> (Vec3, f32) {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t, t)
}

fn closest_on_degenerate(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, [f32; 3]) {
    let (qab, t) = closest_point_on_segment(p, a, b);
    let (qbc, s) = closest_point_on_segment(p, b, c);
    let (qca, r) = closest_point_on_segment(p, c, a);
    let cands = [(qab, [1.0 - t, t, 0.0]), (qbc, [0.0, 1.0 - s, s]), (qca, [r, 0.0, 1.0 - r])];
    let mut best = cands[0];
    for cand in &cands[1..] {
        if cand.0.distance_squared(p) < best.0.distance_squared(p) {
            best = *cand;
        }
    }
    best
}

/// Unit normal of triangle `abc` (right-handed winding), `None` when its area is zero.
#[inline]
pub fn triangle_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    (b - a).cross(c - a).try_normalize()
}

/// Signed distance from `p` to the plane of `abc`: positive in front (normal side), negative
/// behind; `None` for a zero-area triangle.
#[inline]
pub fn signed_plane_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    triangle_normal(a, b, c).map(|n| (p - a).dot(n))
}

/// A particle found behind the collider surface and where it must go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The nearest triangle of the cell.
    pub triangle: u32,
    /// Closest point on that triangle.
    pub closest: Vec3,
    /// Barycentric coordinates of `closest` (for friction: the triangle's velocity there).
    pub bary: [f32; 3],
    /// Unit outward normal of that triangle.
    pub normal: Vec3,
    /// Projection target of the inequality constraint: `p + depth · normal`, the particle moved
    /// along the triangle's normal onto the triangle's plane offset by the thickness.
    pub target: Vec3,
    /// How far the particle is behind the offset surface: `thickness - (p - closest) · normal`.
    pub depth: f32,
}

/// The particle-vs-cell test of the mesh collider.
///
/// `candidates` are the triangles filed in the particle's cell (same bucket and `cell_id`).
/// The particle collides when it lies behind *every* candidate's plane offset by `thickness`
/// (`(p - a) · n < thickness` for all of them): being behind only some of them means it is
/// outside a convex corner or next to a fold, not inside the body. The nearest triangle (by its
/// closest point) then gives the constraint: the half-space in front of that triangle's plane
/// offset by `thickness`, and the target is the particle projected onto that plane along the
/// normal (the least move that satisfies it).
///
/// The paper targets the closest point itself pushed out by the thickness. The two agree
/// inside a triangle's face; where the closest point lies on an edge or corner (a particle
/// beside a convex ridge such as the crotch or an armpit fold) the closest-point target also
/// moves the particle sideways, up to the thickness and more, onto the ridge. At the end of
/// a substep that sideways snap tore sewn pairs apart (trousers' inseam 3-9 mm for one
/// substep, the T-shirt's armholes 5 mm for one frame); inside the iterations it anchored the
/// particle at the ridge against its seams. An empty cell, or one holding only zero-area triangles, reports no contact:
/// "behind all of none" would otherwise catch every particle in empty space. Candidate
/// indices out of range are ignored.
pub fn particle_vs_cell<I>(
    p: Vec3,
    candidates: I,
    vertices: &[[f32; 3]],
    triangles: &[[u32; 3]],
    thickness: f32,
) -> Option<Contact>
where
    I: IntoIterator<Item = u32>,
{
    let mut best: Option<(f32, Contact)> = None;
    for t in candidates {
        let Some(&[i, j, k]) = triangles.get(t as usize) else { continue };
        let (Some(a), Some(b), Some(c)) =
            (vertices.get(i as usize), vertices.get(j as usize), vertices.get(k as usize))
        else {
            continue;
        };
        let (a, b, c) = (Vec3::from(*a), Vec3::from(*b), Vec3::from(*c));
        let Some(n) = triangle_normal(a, b, c) else { continue };
        let side = (p - a).dot(n);
        if side >= thickness {
            return None;
        }
        let (q, bary) = closest_point_on_triangle(p, a, b, c);
        let d2 = q.distance_squared(p);
        if best.as_ref().is_none_or(|(bd2, _)| d2 < *bd2) {
            let depth = thickness - (p - q).dot(n);
            let contact = Contact { triangle: t, closest: q, bary, normal: n, target: p + n * depth, depth };
            best = Some((d2, contact));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn closest_point_matches_brute_force_sampling() {
        let mut rng = Rng::new(7);
        for _ in 0..300 {
            let a = rng.vec3(1.0);
            let b = rng.vec3(1.0);
            let c = rng.vec3(1.0);
            let p = rng.vec3(2.0);
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            let recon = a * bary[0] + b * bary[1] + c * bary[2];
            assert!(recon.distance(q) < 1e-4, "barycentrics do not reproduce the point");
            assert!(bary.iter().all(|&w| (-1e-5..=1.0 + 1e-5).contains(&w)));
            // Dense barycentric sampling: nothing on the triangle is closer than `q`.
            let n = 60;
            let mut best = f32::INFINITY;
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                    best = best.min((a + (b - a) * u + (c - a) * v).distance(p));
                }
            }
            let d = q.distance(p);
            assert!(d <= best + 1e-5, "closest {d} worse than sampled {best}");
            let spacing = (b - a).length().max((c - a).length()) / n as f32;
            assert!(best - d <= spacing + 1e-5, "closest {d} far better than sampled {best}");
        }
    }

    #[test]
    fn closest_point_on_degenerate_triangle_is_on_its_segment() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::X * 2.0);
        let (q, _) = closest_point_on_triangle(Vec3::new(1.5, 1.0, 0.0), a, b, c);
        assert!(q.distance(Vec3::new(1.5, 0.0, 0.0)) < 1e-6);
        let (q, _) = closest_point_on_triangle(Vec3::ONE, a, a, a);
        assert_eq!(q, a);
    }

    #[test]
    fn particle_behind_all_triangles_collides() {
        // Two triangles of the floor z = 0 facing +z.
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let t = [[0, 1, 2], [0, 2, 3]];
        let c = particle_vs_cell(Vec3::new(0.2, 0.7, -0.05), [0, 1], &v, &t, 0.01).expect("behind both");
        assert_eq!(c.triangle, 1);
        assert!((c.target - Vec3::new(0.2, 0.7, 0.01)).length() < 1e-6);
        assert!((c.depth - 0.06).abs() < 1e-6);
        // Beside the floor's edge (its closest point on the edge x = 1): pushed straight up
        // onto the offset plane, not sideways onto the edge.
        let c = particle_vs_cell(Vec3::new(1.003, 0.5, -0.002), [0], &v, &t, 0.01).expect("behind");
        assert!((c.closest - Vec3::new(1.0, 0.5, 0.0)).length() < 1e-6);
        assert!((c.target - Vec3::new(1.003, 0.5, 0.01)).length() < 1e-6, "{:?}", c.target);
        // Within the thickness layer: still pushed out.
        assert!(particle_vs_cell(Vec3::new(0.2, 0.7, 0.005), [0, 1], &v, &t, 0.01).is_some());
        // In front: free.
        assert!(particle_vs_cell(Vec3::new(0.2, 0.7, 0.05), [0, 1], &v, &t, 0.01).is_none());
        // Empty cell: free.
        assert!(particle_vs_cell(Vec3::new(0.2, 0.7, -0.05), [], &v, &t, 0.01).is_none());
        // Behind one triangle but in front of another (a wall at x = 2 facing +x): free.
        let v2 = [v[0], v[1], v[2], [2.0, 0.0, -1.0], [2.0, 1.0, -1.0], [2.0, 0.0, 1.0]];
        let t2 = [[0, 1, 2], [3, 4, 5]];
        assert!(particle_vs_cell(Vec3::new(2.5, 0.3, -0.05), [0, 1], &v2, &t2, 0.0).is_none());
    }
}
