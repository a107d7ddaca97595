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

/// Two candidates whose closest points to a particle are closer than this (m) share the
/// feature (edge or corner) nearest to it.
pub const SHARED_FEATURE: f32 = 1e-5;

/// The particle-vs-cell test of the mesh collider.
///
/// `candidates` are the triangles filed in the particle's cell (same bucket and `cell_id`).
/// The nearest candidate (by its closest point) decides: the particle collides when it lies
/// behind that triangle's plane offset by `thickness`, and, where the closest point is an
/// edge or corner several candidates share, behind the offset plane of every one of them —
/// outside a convex ridge it is in front of one of them and free, as the paper intends. The
/// constraint is then the half-space in front of the nearest triangle's offset plane, and the
/// target the particle projected onto that plane along the normal (the least move that
/// satisfies it).
///
/// Two departures from the paper, both measured on the samples. (1) The paper's particle
/// collides only when behind *every* triangle of its cell. In a crease (the armpit) a
/// particle inside the arm is still in front of the chest's triangles in the same cell, so it
/// went undetected until it had sunk several millimetres, and was then caught at once: within
/// a solve a sewn pair flipped open and closed from one iteration to the next (2.5-4.5 mm deep
/// on first detection, thousands of times over 40 frames of the add-on's shirt on its 2 cm
/// proxy), and the end of the substep froze whichever state the last iteration gave. Cloth
/// sunk into the armpits also held an unpinned shirt up on the sample character; with the
/// creases colliding it slides down the sloped arms (tests/test_simulate.py). (2) The paper targets the closest point itself
/// pushed out by the thickness. Inside a face the two agree; where the closest point lies on
/// an edge or corner it also moves the particle sideways, up to the thickness and more, onto
/// the ridge: at the end of a substep that tore sewn pairs apart (trousers' inseam 3-9 mm for
/// one substep) and inside the iterations it anchored the particle at the ridge against its
/// seams. An empty cell, or one holding only zero-area triangles, reports no contact.
/// Candidate indices out of range are ignored.
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
    let tris: Vec<(u32, [Vec3; 3], Vec3)> = candidates
        .into_iter()
        .filter_map(|t| {
            let &[i, j, k] = triangles.get(t as usize)?;
            let corner = |v: u32| vertices.get(v as usize).map(|c| Vec3::from(*c));
            let (a, b, c) = (corner(i)?, corner(j)?, corner(k)?);
            Some((t, [a, b, c], triangle_normal(a, b, c)?))
        })
        .collect();
    nearest_feature_contact(p, thickness, || tris.iter().copied())
}

/// Whether the point of barycentrics `bary` on triangle `[a, b, c]` lies on (or within a few
/// [`SHARED_FEATURE`] of) one of its edges, where another triangle can share it: the distance
/// to the edge opposite corner i is `wᵢ·2A/‖eᵢ‖`.
#[inline]
pub fn on_shared_feature(tri: [Vec3; 3], bary: [f32; 3]) -> bool {
    let (twice_area, edges) = area_and_edges(tri);
    (0..3).any(|i| bary[i] * twice_area <= 2.0 * SHARED_FEATURE * edges[i])
}

/// Twice the area of `[a, b, c]` and the lengths of the edges opposite a, b and c.
#[inline]
fn area_and_edges([a, b, c]: [Vec3; 3]) -> (f32, [f32; 3]) {
    ((b - a).cross(c - a).length(), [(c - b).length(), (a - c).length(), (b - a).length()])
}

/// The distance from the point of barycentrics `bary` on triangle `[a, b, c]` to the nearest
/// of its edges, in its plane (`wᵢ·2A/‖eᵢ‖`, the least over i).
#[inline]
pub fn distance_to_edges(tri: [Vec3; 3], bary: [f32; 3]) -> f32 {
    let (twice_area, edges) = area_and_edges(tri);
    (0..3).map(|i| bary[i] * twice_area / edges[i].max(f32::MIN_POSITIVE)).fold(f32::INFINITY, f32::min)
}

/// The rule of [`particle_vs_cell`] over candidates given as `(triangle, corners, unit
/// normal)` (degenerate ones left out); `candidates` is called up to three times and must
/// give the same sequence each time. Three passes, so that most particles leave after the
/// cheap one: side tests alone (in front of every offset plane: free), which also pick the
/// candidate whose plane is nearest; the nearest candidate, starting from that one and
/// skipping those whose plane is already farther than the best distance (a triangle is never
/// nearer than its plane); then the candidates in front of their offset plane that share the
/// nearest closest point.
#[inline]
pub fn nearest_feature_contact<F, I>(p: Vec3, thickness: f32, candidates: F) -> Option<Contact>
where
    F: Fn() -> I,
    I: Iterator<Item = (u32, [Vec3; 3], Vec3)>,
{
    nearest_feature_contact_or_clearance(p, thickness, candidates).ok().flatten()
}

/// [`nearest_feature_contact`], telling apart the case where `p` is in front of every
/// candidate's offset plane: `Err(clearance)`, the least `side − thickness` over the
/// candidates (infinite without any). Every side `(p − a)·n` changes by at most `|Δp|` when `p`
/// moves (unit normals), so while `p` moves less than the clearance among the same candidates,
/// the answer stays "no contact" without being computed again (the mesh colliders' broad
/// phase, `MeshCollider::contact_or_clearance`). `Ok` is the rule's answer otherwise.
#[inline]
pub fn nearest_feature_contact_or_clearance<F, I>(
    p: Vec3,
    thickness: f32,
    candidates: F,
) -> std::result::Result<Option<Contact>, f32>
where
    F: Fn() -> I,
    I: Iterator<Item = (u32, [Vec3; 3], Vec3)>,
{
    // The candidate whose plane is nearest seeds the search: its distance bounds the rest.
    let mut least_side = f32::INFINITY;
    let mut seed: Option<(f32, u32, [Vec3; 3], Vec3)> = None;
    for (t, tri, n) in candidates() {
        let side = (p - tri[0]).dot(n);
        least_side = least_side.min(side);
        if seed.is_none_or(|(s, ..)| side.abs() < s) {
            seed = Some((side.abs(), t, tri, n));
        }
    }
    // In front of every offset plane (or no candidate at all): free.
    if !(least_side < thickness) {
        return Err(least_side - thickness);
    }
    let Some((_, t0, [a0, b0, c0], n0)) = seed else { return Ok(None) };
    let (q0, bary0) = closest_point_on_triangle(p, a0, b0, c0);
    let mut best = (q0.distance_squared(p), t0, q0, bary0, n0);
    let mut best_tri = [a0, b0, c0];
    // Its projection inside it: no candidate is nearer than its plane, so none is nearer.
    let interior = bary0.iter().all(|&w| w > 0.0);
    if !interior {
        for (t, [a, b, c], n) in candidates() {
            let side = (p - a).dot(n);
            if t == t0 || side * side >= best.0 {
                continue;
            }
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            let d2 = q.distance_squared(p);
            if d2 < best.0 {
                best = (d2, t, q, bary, n);
                best_tri = [a, b, c];
            }
        }
    }
    let (d2, triangle, closest, bary, normal) = best;
    let depth = thickness - (p - closest).dot(normal);
    if depth <= 0.0 {
        return Ok(None);
    }
    // Only a closest point on (or within a few SHARED_FEATURE of) an edge of its triangle can
    // be shared: the distance to the edge opposite corner i is wᵢ·2A/‖eᵢ‖.
    if on_shared_feature(best_tri, bary) {
        for (_, [a, b, c], n) in candidates() {
            let side = (p - a).dot(n);
            if side < thickness || side > d2.sqrt() + SHARED_FEATURE {
                continue;
            }
            if closest_point_on_triangle(p, a, b, c).0.distance_squared(closest) <= SHARED_FEATURE * SHARED_FEATURE {
                return Ok(None);
            }
        }
    }
    Ok(Some(Contact { triangle, closest, bary, normal, target: p + normal * depth, depth }))
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

    #[test]
    fn particle_sunk_into_a_crease_collides_with_the_surface_it_is_behind() {
        // A crease (an armpit): the floor z = 0 (solid below, facing +z) meets a wall x = 0
        // (solid at x < 0, facing +x). 2 mm into the floor and 5 cm in front of the wall, the
        // paper's "behind every triangle of the cell" missed it; the nearest surface decides.
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
        let t = [[0, 1, 2], [0, 2, 3], [0, 3, 5], [0, 5, 4]];
        let c = particle_vs_cell(Vec3::new(0.05, 0.5, -0.002), 0..4, &v, &t, 0.01).expect("inside the floor");
        assert!(c.triangle < 2 && (c.normal - Vec3::Z).length() < 1e-6);
        assert!((c.depth - 0.012).abs() < 1e-6 && (c.target - Vec3::new(0.05, 0.5, 0.01)).length() < 1e-6);
        // In the open corner, clear of both surfaces by more than the thickness: free.
        assert!(particle_vs_cell(Vec3::new(0.05, 0.5, 0.05), 0..4, &v, &t, 0.01).is_none());
        // Within the thickness of the wall only: pushed out of the wall.
        let c = particle_vs_cell(Vec3::new(0.004, 0.5, 0.5), 0..4, &v, &t, 0.01).expect("near the wall");
        assert!((c.normal - Vec3::X).length() < 1e-6 && (c.depth - 0.006).abs() < 1e-6);
    }

    #[test]
    fn particle_outside_a_convex_ridge_is_free() {
        // A ridge along y: faces z = 0 (x < 0, facing +z) and x = 0 (z < 0, facing +x). A
        // particle up and out from the edge is in front of the face x = 0 by more than the
        // thickness while its nearest point is the shared edge: free, as in the paper.
        let v =
            [[-1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, -1.0]];
        let t = [[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]];
        assert!(particle_vs_cell(Vec3::new(0.02, 0.5, 0.005), 0..4, &v, &t, 0.01).is_none());
        // Right on top of the ridge, within the thickness of both faces: held out.
        assert!(particle_vs_cell(Vec3::new(0.003, 0.5, 0.004), 0..4, &v, &t, 0.01).is_some());
    }
}
