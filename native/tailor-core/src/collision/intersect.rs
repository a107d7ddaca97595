//! Segment-triangle and triangle-triangle intersection predicates (used to count
//! self-intersections of the cloth).
//!
//! All decisions are signs of orientation determinants evaluated in `f64` on `f32` input:
//!
//! ```text
//! orient3d(a, b, c, d) = ((b - a) × (c - a)) · (d - a)
//! ```
//!
//! which is positive when `d` lies on the normal side of `abc`. A segment `pq` meets a
//! non-degenerate triangle `abc` iff `p` and `q` are not strictly on the same side of its plane
//! and the line `pq` passes inside the triangle, i.e. `orient3d(p, q, a, b)`,
//! `orient3d(p, q, b, c)`, `orient3d(p, q, c, a)` do not have strictly mixed signs. When the
//! segment lies in the triangle's plane, the test is done in 2D on the projection that drops
//! the normal's dominant axis (endpoint-in-triangle or edge-edge crossing, collinear overlaps
//! included).
//!
//! Two triangles (closed sets) intersect iff an edge of one meets the other: for non-coplanar
//! triangles the intersection is a segment of the planes' common line whose endpoints lie on
//! edges; for coplanar ones, either edges cross or one triangle contains the other's edges.
//! Touching (a shared point, a vertex on a face) counts as intersecting. Zero-area triangles
//! are handled as their longest edge.

use glam::{DVec2, DVec3, Vec3};

#[inline]
fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).cross(c - a).dot(d - a)
}

#[inline]
fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

#[inline]
fn opposite(a: f64, b: f64) -> bool {
    (a > 0.0 && b < 0.0) || (a < 0.0 && b > 0.0)
}

/// Drops the axis `drop` of a 3D point.
#[inline]
fn project(p: DVec3, drop: usize) -> DVec2 {
    match drop {
        0 => DVec2::new(p.y, p.z),
        1 => DVec2::new(p.z, p.x),
        _ => DVec2::new(p.x, p.y),
    }
}

fn dominant_axis(n: DVec3) -> usize {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    }
}

fn on_segment_2d(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Closed 2D segments `ab` and `cd` share a point (collinear overlaps included).
fn segments_intersect_2d(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let d1 = orient2d(c, d, a);
    let d2 = orient2d(c, d, b);
    let d3 = orient2d(a, b, c);
    let d4 = orient2d(a, b, d);
    if opposite(d1, d2) && opposite(d3, d4) {
        return true;
    }
    (d1 == 0.0 && on_segment_2d(c, d, a))
        || (d2 == 0.0 && on_segment_2d(c, d, b))
        || (d3 == 0.0 && on_segment_2d(a, b, c))
        || (d4 == 0.0 && on_segment_2d(a, b, d))
}

fn point_in_triangle_2d(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    let s1 = orient2d(a, b, p);
    let s2 = orient2d(b, c, p);
    let s3 = orient2d(c, a, p);
    (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
}

/// Closed 3D segments `pq` and `rs` share a point.
fn segments_intersect_3d(p: DVec3, q: DVec3, r: DVec3, s: DVec3) -> bool {
    if orient3d(p, q, r, s) != 0.0 {
        return false; // skew lines
    }
    // Coplanar: pick a plane containing both, falling back for parallel or collinear segments.
    let mut n = (q - p).cross(s - r);
    if n == DVec3::ZERO {
        n = (q - p).cross(r - p);
    }
    if n == DVec3::ZERO {
        n = (s - r).cross(q - r);
    }
    let drop = if n == DVec3::ZERO {
        // All four points collinear (or coincident): drop the axis the line varies least along.
        let dir = if q != p { q - p } else { s - r };
        let a = dir.abs();
        if a.x <= a.y && a.x <= a.z {
            0
        } else if a.y <= a.z {
            1
        } else {
            2
        }
    } else {
        dominant_axis(n)
    };
    segments_intersect_2d(project(p, drop), project(q, drop), project(r, drop), project(s, drop))
}

fn segment_triangle_f64(p: DVec3, q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> bool {
    let n = (b - a).cross(c - a);
    if n == DVec3::ZERO {
        let (e0, e1) = longest_edge(a, b, c);
        return segments_intersect_3d(p, q, e0, e1);
    }
    let dp = orient3d(a, b, c, p);
    let dq = orient3d(a, b, c, q);
    if dp == 0.0 && dq == 0.0 {
        let drop = dominant_axis(n);
        let (p2, q2) = (project(p, drop), project(q, drop));
        let (a2, b2, c2) = (project(a, drop), project(b, drop), project(c, drop));
        return point_in_triangle_2d(p2, a2, b2, c2)
            || point_in_triangle_2d(q2, a2, b2, c2)
            || segments_intersect_2d(p2, q2, a2, b2)
            || segments_intersect_2d(p2, q2, b2, c2)
            || segments_intersect_2d(p2, q2, c2, a2);
    }
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) {
        return false;
    }
    let s1 = orient3d(p, q, a, b);
    let s2 = orient3d(p, q, b, c);
    let s3 = orient3d(p, q, c, a);
    (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
}

fn longest_edge(a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3) {
    let (lab, lbc, lca) = (a.distance_squared(b), b.distance_squared(c), c.distance_squared(a));
    if lab >= lbc && lab >= lca {
        (a, b)
    } else if lbc >= lca {
        (b, c)
    } else {
        (c, a)
    }
}

/// Whether the closed segment `pq` and the closed triangle `abc` share a point.
pub fn segment_triangle_intersect(p: Vec3, q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    segment_triangle_f64(p.as_dvec3(), q.as_dvec3(), a.as_dvec3(), b.as_dvec3(), c.as_dvec3())
}

/// Whether two closed triangles share a point (touching counts). See the module docs.
pub fn triangles_intersect(t1: [Vec3; 3], t2: [Vec3; 3]) -> bool {
    let u = t1.map(|v| v.as_dvec3());
    let v = t2.map(|v| v.as_dvec3());
    // Cheap rejection: one triangle strictly on one side of the other's plane.
    let strictly_one_side = |t: &[DVec3; 3], o: &[DVec3; 3]| {
        let d = o.map(|p| orient3d(t[0], t[1], t[2], p));
        (d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0)
    };
    if strictly_one_side(&u, &v) || strictly_one_side(&v, &u) {
        return false;
    }
    (0..3).any(|i| segment_triangle_f64(u[i], u[(i + 1) % 3], v[0], v[1], v[2]))
        || (0..3).any(|i| segment_triangle_f64(v[i], v[(i + 1) % 3], u[0], u[1], u[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [Vec3; 3] {
        [a.into(), b.into(), c.into()]
    }

    #[test]
    fn constructed_triangle_pairs() {
        let base = t([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        // Crossing: a vertical triangle piercing the base.
        assert!(triangles_intersect(base, t([0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.5])));
        // Touching at a vertex only.
        assert!(triangles_intersect(base, t([2.0, 0.0, 0.0], [3.0, 0.0, 1.0], [3.0, 1.0, 1.0])));
        // A vertex resting on the face.
        assert!(triangles_intersect(base, t([0.5, 0.5, 0.0], [0.5, 0.5, 1.0], [1.0, 0.5, 1.0])));
        // Coplanar overlapping, and coplanar contained (no edges cross).
        assert!(triangles_intersect(base, t([1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [3.0, 0.0, 0.0])));
        assert!(triangles_intersect(base, t([0.2, 0.2, 0.0], [0.6, 0.2, 0.0], [0.2, 0.6, 0.0])));
        // Coplanar disjoint.
        assert!(!triangles_intersect(base, t([3.0, 3.0, 0.0], [4.0, 3.0, 0.0], [3.0, 4.0, 0.0])));
        // Disjoint: parallel above, and crossing the plane outside the triangle.
        assert!(!triangles_intersect(base, t([0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 2.0, 1.0])));
        assert!(!triangles_intersect(base, t([3.0, 3.0, -1.0], [3.0, 3.0, 1.0], [4.0, 3.0, 0.0])));
        // Degenerate (zero-area) triangle crossing the face, and one beside it.
        assert!(triangles_intersect(base, t([0.5, 0.5, -1.0], [0.5, 0.5, 0.0], [0.5, 0.5, 1.0])));
        assert!(!triangles_intersect(base, t([5.0, 0.5, -1.0], [5.0, 0.5, 0.0], [5.0, 0.5, 1.0])));
    }

    #[test]
    fn segment_triangle_cases() {
        let [a, b, c] = t([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let s = |p: [f32; 3], q: [f32; 3]| segment_triangle_intersect(p.into(), q.into(), a, b, c);
        assert!(s([0.2, 0.2, -1.0], [0.2, 0.2, 1.0]));
        assert!(!s([0.8, 0.8, -1.0], [0.8, 0.8, 1.0]));
        assert!(!s([0.2, 0.2, 0.5], [0.2, 0.2, 1.0]));
        assert!(s([0.2, 0.2, 0.0], [0.2, 0.2, 1.0])); // endpoint on the face
        assert!(s([-1.0, 0.5, 0.0], [2.0, 0.5, 0.0])); // in the plane, across
        assert!(!s([-1.0, 2.0, 0.0], [2.0, 2.0, 0.0])); // in the plane, beside
        assert!(s([1.0, 0.0, -1.0], [1.0, 0.0, 1.0])); // through a vertex
    }
}
