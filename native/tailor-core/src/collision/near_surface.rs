//! How many points lie within a distance of a closed mesh's surface, decided mostly by the
//! mesh's vertices: the on-body measure ([`crate::quality::metrics::on_body_fraction`]) asks it
//! of every particle every frame.
//!
//! **Why not the exact test alone.** [`ClosedMesh::is_within`] searches shells of the triangle
//! hash out to the distance asked. A point that is *not* within (a skirt's hem 15 cm from the
//! legs, a piece still placed away from the body) costs every cell of a cube of side twice the
//! distance: about 9,000 cells for 10 cm round the character's 1 cm triangles. That made the
//! quality metrics of a frame cost more than its solve (the T-shirt sample at frame 5, its
//! pieces still round the body: metrics 134-147 ms, its step 54-90 ms; docs/benchmarks.md).
//!
//! **Bounds from the vertices.** A vertex lies on the surface, so a point within `within` of a
//! vertex is within `within` of the surface. The other way round, let `L_v` be the longest
//! edge of the triangles round vertex `v`: if a triangle `T` has a point within `within` of
//! `p`, each vertex `v` of `T` is within `within + L_v` of `p` (every point of a triangle is
//! within its longest edge of each of its vertices). So the triangles worth testing are those
//! round the vertices with `|p − v| ≤ within + L_v`, and a point with no such vertex is not
//! within. With `L` the longest edge of all, the vertices are hashed in cells of side
//! `within + L`: the 27 cells round a point's cell hold every vertex that can decide it, and a
//! point far from the mesh finds them empty. Each triangle test is [`ClosedMesh::is_within`]'s
//! own (the distance to [`closest_point_on_triangle`]), so the count is the same.

use glam::Vec3;
use rayon::prelude::*;

use super::closed_mesh::ClosedMesh;
use super::geometry::closest_point_on_triangle;
use super::hash::{cell_of, SpatialHash};

/// Relative slack on `within + L_v`, so that rounding never skips a triangle that counts.
const SLACK: f32 = 1e-5;

/// Counts the points of `points` within `within` metres of `mesh`'s surface: the same count as
/// [`ClosedMesh::is_within`] point by point, in parallel.
pub fn count_within(mesh: &ClosedMesh, points: &[[f32; 3]], within: f32) -> usize {
    let (vertices, triangles) = (mesh.vertices(), mesh.triangles());
    // Per vertex: the longest edge round it, and its triangles (CSR).
    let mut longest = vec![0.0f32; vertices.len()];
    let mut starts = vec![0u32; vertices.len() + 1];
    for t in triangles {
        let [a, b, c] = t.map(|i| Vec3::from(vertices[i as usize]));
        let e = a.distance(b).max(b.distance(c)).max(c.distance(a));
        for &v in t {
            longest[v as usize] = longest[v as usize].max(e);
            starts[v as usize + 1] += 1;
        }
    }
    for v in 0..vertices.len() {
        starts[v + 1] += starts[v];
    }
    let mut fill = starts.clone();
    let mut round = vec![0u32; starts[vertices.len()] as usize];
    for (k, t) in triangles.iter().enumerate() {
        for &v in t {
            round[fill[v as usize] as usize] = k as u32;
            fill[v as usize] += 1;
        }
    }
    let reach = (within + longest.iter().copied().fold(0.0f32, f32::max)) * (1.0 + SLACK);
    let mut hash = SpatialHash::new();
    let usable = within.is_finite()
        && within >= 0.0
        && reach.is_finite()
        && reach > 0.0
        && hash.build_with(vertices.len(), reach, |i, emit| emit(cell_of(vertices[i], reach))).is_ok();
    if !usable {
        // NaN, negative or unbounded distances: the exact test answers them (mostly no).
        mesh.prepare_queries();
        return points.par_iter().filter(|&&p| mesh.is_within(p, within)).count();
    }
    let near = |pv: Vec3, k: u32| {
        let [a, b, c] = triangles[k as usize].map(|i| Vec3::from(vertices[i as usize]));
        closest_point_on_triangle(pv, a, b, c).0.distance(pv) <= within
    };
    points
        .par_iter()
        .filter(|&&p| {
            let pv = Vec3::from(p);
            if !pv.is_finite() {
                return false;
            }
            let c = hash.cell_of(p);
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        for v in hash.query_cell([c[0] + dx, c[1] + dy, c[2] + dz]) {
                            let d = Vec3::from(vertices[v as usize]).distance(pv);
                            if d > (within + longest[v as usize]) * (1.0 + SLACK) {
                                continue;
                            }
                            let ts = &round[starts[v as usize] as usize..starts[v as usize + 1] as usize];
                            if ts.iter().any(|&k| near(pv, k)) {
                                return true;
                            }
                        }
                    }
                }
            }
            false
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{box_mesh, icosphere, Rng};

    /// The vertex bounds give the exact test's count, for points on every side of the limit:
    /// near a fine sphere, round a box of long edges (most candidates are its few big
    /// triangles), far away, and for the odd distances (0, huge, NaN).
    #[test]
    fn the_count_is_the_exact_tests() {
        let mut rng = Rng::new(3);
        for (v, t) in [icosphere(4, 0.3), box_mesh([-0.2, -0.1, -0.4], [0.3, 0.1, 0.5])] {
            let mesh = ClosedMesh::new(&v, &t).unwrap();
            let mut points: Vec<[f32; 3]> =
                (0..4000).map(|k| (rng.vec3(0.8) * if k % 5 == 0 { 20.0 } else { 1.0 }).into()).collect();
            points.extend(v.iter().map(|p| [p[0] + 0.05, p[1], p[2]]));
            points.push([f32::NAN, 0.0, 0.0]);
            for within in [0.0, 0.01, 0.1, 0.25, 3.0, 1e30, f32::INFINITY, f32::NAN, -1.0] {
                let exact = points.iter().filter(|&&p| mesh.is_within(p, within)).count();
                assert_eq!(count_within(&mesh, &points, within), exact, "within {within}");
            }
        }
    }
}
