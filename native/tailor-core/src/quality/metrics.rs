//! Quality metrics of a simulated frame (reported to the user, later exposed to Python).
//!
//! * penetration: points of the cloth inside the closed body ([`ClosedMesh`]);
//! * self-intersections: pairs of non-adjacent cloth triangles that intersect;
//! * edge strain: `|ℓ / ℓ₀ − 1|` per edge, max and mean;
//! * kinetic energy: `½ Σ mᵢ |vᵢ|²` (in `f64`: it is a sum of many small terms);
//! * seam gap: the largest distance between the two sides of a seam;
//! * on the body: the share of cloth points within [`ON_BODY_DISTANCE`] of the body's surface
//!   ([`on_body_fraction`]) and the cloth's [`centroid`]: a garment that fell off the body has
//!   few points near it and a centroid far from where it started.

use glam::Vec3;
use rayon::prelude::*;

use crate::collision::closed_mesh::{aabb_cell_size, ClosedMesh, Penetration};
use crate::collision::collider_hash::{aabb_cells, ColliderHash, InsertionRule};
use crate::collision::intersect::triangles_intersect;
use crate::error::{Result, TailorError};

/// Penetration of `points` into the closed mesh `(vertices, triangles)`: count and largest
/// depth. Build a [`ClosedMesh`] yourself to query several point sets against one body.
pub fn penetration(points: &[[f32; 3]], vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> Result<Penetration> {
    Ok(ClosedMesh::new(vertices, triangles)?.penetration(points))
}

/// Number of intersecting pairs of triangles that share no vertex.
///
/// Vertices at exactly the same position count as one (meshes exported with split UV or
/// normal seams have duplicated vertices; the triangles on both sides of such a seam are
/// neighbours, not an intersection).
///
/// Broad phase: every triangle is filed in all hash cells its AABB overlaps; two triangles are
/// candidates when they share a cell, and a pair is examined only in its *first* shared cell
/// (the componentwise max of the two AABBs' lowest cells), so it is counted once without a set
/// of seen pairs. Narrow phase: AABB overlap, then [`triangles_intersect`]. Triangles sharing a
/// vertex touch by construction and are skipped (so a crossing between two triangles of one
/// fan is not counted).
pub fn count_self_intersections(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> Result<usize> {
    Ok(self_intersecting_pairs(vertices, triangles, &[])?.len())
}

/// The pairs [`count_self_intersections`] counts, `[i, j]` with `i < j`, sorted: where the
/// cloth passes through itself. Vertices `joined` in pairs count as one as well (a garment's
/// sewn vertices: the two sides of a closed seam meet as the welded garment's neighbouring
/// triangles, not as an intersection).
pub fn self_intersecting_pairs(
    vertices: &[[f32; 3]],
    triangles: &[[u32; 3]],
    joined: &[[u32; 2]],
) -> Result<Vec<[u32; 2]>> {
    if triangles.is_empty() {
        return Ok(Vec::new());
    }
    let n = vertices.len();
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
            return Err(TailorError::index(format!("cloth triangle {t}"), v as i64, n, "vertices"));
        }
    }
    if let Some(&[a, b]) = joined.iter().find(|p| p.iter().any(|&v| v as usize >= n)) {
        return Err(TailorError::index("joined vertices", a.max(b) as i64, n, "vertices"));
    }
    // Weld by exact position (-0.0 and 0.0 alike) so split seams keep their adjacency, and
    // the joined pairs.
    let mut canonical = std::collections::HashMap::with_capacity(vertices.len());
    let mut classes = crate::mesh::union_find::UnionFind::new(n);
    for (i, p) in vertices.iter().enumerate() {
        let first = *canonical.entry(p.map(|c| (c + 0.0).to_bits())).or_insert(i as u32);
        classes.union(first, i as u32);
    }
    for &[a, b] in joined {
        classes.union(a, b);
    }
    let weld: Vec<u32> = (0..n as u32).map(|v| classes.find(v)).collect();
    let welded = |t: u32| triangles[t as usize].map(|v| weld[v as usize]);
    let l = aabb_cell_size(vertices, triangles);
    let mut hash = ColliderHash::new();
    hash.build(vertices, triangles, l, InsertionRule::Aabb)?;
    let tri = |t: u32| triangles[t as usize].map(|i| Vec3::from(vertices[i as usize]));
    let mut pairs: Vec<[u32; 2]> = (0..triangles.len() as u32)
        .into_par_iter()
        .flat_map_iter(|i| {
            let ti = tri(i);
            let (lo_i, hi_i) = aabb_cells(ti, l);
            let (bmin_i, bmax_i) = (ti[0].min(ti[1]).min(ti[2]), ti[0].max(ti[1]).max(ti[2]));
            let vi = welded(i);
            let mut found = Vec::new();
            for z in lo_i[2]..=hi_i[2] {
                for y in lo_i[1]..=hi_i[1] {
                    for x in lo_i[0]..=hi_i[0] {
                        for j in hash.hash().query_cell([x, y, z]) {
                            if j <= i {
                                continue;
                            }
                            let tj = tri(j);
                            let (lo_j, _) = aabb_cells(tj, l);
                            if [x, y, z] != [lo_i[0].max(lo_j[0]), lo_i[1].max(lo_j[1]), lo_i[2].max(lo_j[2])] {
                                continue;
                            }
                            let (bmin_j, bmax_j) = (tj[0].min(tj[1]).min(tj[2]), tj[0].max(tj[1]).max(tj[2]));
                            if bmin_i.cmpgt(bmax_j).any() || bmin_j.cmpgt(bmax_i).any() {
                                continue;
                            }
                            let vj = welded(j);
                            if vi.iter().any(|v| vj.contains(v)) {
                                continue;
                            }
                            if triangles_intersect(ti, tj) {
                                found.push([i, j]);
                            }
                        }
                    }
                }
            }
            found
        })
        .collect();
    pairs.sort_unstable();
    Ok(pairs)
}

/// Max and mean of `|ℓ / ℓ₀ − 1|` over edges.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Strain {
    pub max: f32,
    pub mean: f32,
}

/// Edge strain of `positions` for `edges` with rest lengths `rest_lengths` (metres, > 0).
pub fn edge_strain(positions: &[[f32; 3]], edges: &[[u32; 2]], rest_lengths: &[f32]) -> Result<Strain> {
    if edges.len() != rest_lengths.len() {
        return Err(TailorError::shape(
            "edge strain",
            format!("{} edges but {} rest lengths", edges.len(), rest_lengths.len()),
        ));
    }
    let n = positions.len();
    let mut max = 0.0f32;
    let mut sum = 0.0f64;
    for (k, (&[a, b], &l0)) in edges.iter().zip(rest_lengths).enumerate() {
        if let Some(&v) = [a, b].iter().find(|&&v| v as usize >= n) {
            return Err(TailorError::index(format!("edge {k}"), v as i64, n, "vertices"));
        }
        if !(l0.is_finite() && l0 > 0.0) {
            return Err(TailorError::shape(
                "edge strain",
                format!("edge {k} has rest length {l0}; it must be positive"),
            ));
        }
        let l = Vec3::from(positions[a as usize]).distance(Vec3::from(positions[b as usize]));
        let s = (l / l0 - 1.0).abs();
        max = max.max(s);
        sum += s as f64;
    }
    Ok(Strain { max, mean: (sum / edges.len().max(1) as f64) as f32 })
}

/// Kinetic energy `½ Σ mᵢ |vᵢ|²`, joules.
pub fn kinetic_energy(velocities: &[[f32; 3]], masses: &[f32]) -> Result<f64> {
    if velocities.len() != masses.len() {
        return Err(TailorError::shape(
            "kinetic energy",
            format!("{} velocities but {} masses", velocities.len(), masses.len()),
        ));
    }
    Ok(velocities.iter().zip(masses).map(|(v, &m)| 0.5 * m as f64 * Vec3::from(*v).length_squared() as f64).sum())
}

/// [`kinetic_energy`] for structure-of-arrays velocities (the solver's layout).
pub fn kinetic_energy_soa(vx: &[f32], vy: &[f32], vz: &[f32], masses: &[f32]) -> Result<f64> {
    let n = masses.len();
    if vx.len() != n || vy.len() != n || vz.len() != n {
        return Err(TailorError::shape(
            "kinetic energy",
            format!("velocity arrays of lengths {}, {}, {} for {n} masses", vx.len(), vy.len(), vz.len()),
        ));
    }
    Ok((0..n).map(|i| 0.5 * masses[i] as f64 * (vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]) as f64).sum())
}

/// How near the body's surface a cloth point must be to count as on the body, metres: 10 cm.
///
/// A worn garment lies on the body within its collision thickness (a few millimetres) where it
/// hangs from it, and what hangs free stands off it by centimetres: the sample skirt's flare on
/// the sample character, just assembled, has 45 % of its particles within 5 cm of the body, 79 %
/// within 10 cm (91-94 % once it settles). A garment that fell has none near it.
pub const ON_BODY_DISTANCE: f32 = 0.10;

/// Share of `points` within `within` metres of the surface of `body` (0 for no points).
pub fn on_body_fraction(points: &[[f32; 3]], body: &ClosedMesh, within: f32) -> f32 {
    if points.is_empty() {
        return 0.0;
    }
    (body.count_within(points, within) as f64 / points.len() as f64) as f32
}

/// The share of the cloth [`top`] averages: its highest twentieth.
pub const TOP_SHARE: f64 = 0.05;

/// The mean of the highest [`TOP_SHARE`] of `points` along `up` (at least one point): where a
/// garment hangs from. `up` zero (no gravity): the [`centroid`].
pub fn top(points: &[[f32; 3]], up: [f32; 3]) -> [f32; 3] {
    let norm = (up[0] * up[0] + up[1] * up[1] + up[2] * up[2]).sqrt();
    if points.is_empty() || norm.is_nan() || norm <= 0.0 {
        return centroid(points);
    }
    let height = |p: &[f32; 3]| (p[0] * up[0] + p[1] * up[1] + p[2] * up[2]) / norm;
    let k = ((points.len() as f64 * TOP_SHARE).ceil() as usize).clamp(1, points.len());
    let mut order: Vec<usize> = (0..points.len()).collect();
    // The k highest first (ties by index, so the choice is the same on every run).
    order.select_nth_unstable_by(k - 1, |&a, &b| height(&points[b]).total_cmp(&height(&points[a])).then(a.cmp(&b)));
    let highest: Vec<[f32; 3]> = order[..k].iter().map(|&i| points[i]).collect();
    centroid(&highest)
}

/// The mean of `points` (summed in `f64`; the origin for no points).
pub fn centroid(points: &[[f32; 3]]) -> [f32; 3] {
    let n = points.len().max(1) as f64;
    let s = points.iter().fold([0.0f64; 3], |s, p| [s[0] + p[0] as f64, s[1] + p[1] as f64, s[2] + p[2] as f64]);
    s.map(|c| (c / n) as f32)
}

/// Largest distance between the two points of any pair (0 for no pairs).
pub fn max_seam_gap(positions: &[[f32; 3]], pairs: &[[u32; 2]]) -> Result<f32> {
    let n = positions.len();
    let mut gap = 0.0f32;
    for (k, &[a, b]) in pairs.iter().enumerate() {
        if let Some(&v) = [a, b].iter().find(|&&v| v as usize >= n) {
            return Err(TailorError::index(format!("seam pair {k}"), v as i64, n, "vertices"));
        }
        gap = gap.max(Vec3::from(positions[a as usize]).distance(Vec3::from(positions[b as usize])));
    }
    Ok(gap)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{box_mesh, icosphere};

    #[test]
    fn self_intersections_of_constructed_meshes() {
        // A closed sphere does not intersect itself.
        let (v, t) = icosphere(3, 1.0);
        assert_eq!(count_self_intersections(&v, &t).unwrap(), 0);
        // Two boxes overlapping as one mesh: each crossing face pair is counted once.
        let (v1, t1) = box_mesh([0.0; 3], [1.0; 3]);
        let (v2, t2) = box_mesh([0.5, 0.25, 0.25], [1.5, 0.75, 0.75]);
        let mut v = v1.clone();
        v.extend(v2);
        let mut t = t1.clone();
        t.extend(t2.iter().map(|tri| tri.map(|i| i + 8)));
        // Box 2 pierces face x = 1 of box 1 with its four side faces (8 triangles); each of
        // them crosses one or both triangles of that face.
        let n = count_self_intersections(&v, &t).unwrap();
        let brute = (0..t.len())
            .flat_map(|i| (i + 1..t.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| !t[i].iter().any(|x| t[j].contains(x)))
            .filter(|&(i, j)| {
                let a = t[i].map(|k| Vec3::from(v[k as usize]));
                let b = t[j].map(|k| Vec3::from(v[k as usize]));
                triangles_intersect(a, b)
            })
            .count();
        assert_eq!(n, brute);
        assert!(n >= 8, "{n}");
        // Triangles sharing an edge (or a vertex) are adjacent, not intersecting, even with
        // the shared vertices duplicated (split seams).
        let quad = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(count_self_intersections(&quad, &[[0, 1, 2], [0, 2, 3]]).unwrap(), 0);
        let split = [quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]];
        assert_eq!(count_self_intersections(&split, &[[0, 1, 2], [3, 4, 5]]).unwrap(), 0);
        // A third triangle piercing the quad is counted against both halves it crosses.
        let mut v = quad.to_vec();
        v.extend([[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [2.0, 2.0, 0.5]]);
        assert_eq!(count_self_intersections(&v, &[[0, 1, 2], [0, 2, 3], [4, 5, 6]]).unwrap(), 2);
        // Two separated boxes: none.
        let (v2, _) = box_mesh([2.0; 3], [3.0; 3]);
        let mut v = v1;
        v.extend(v2);
        assert_eq!(count_self_intersections(&v, &t).unwrap(), 0);
    }

    #[test]
    fn sewn_vertices_join_the_two_sides_of_a_seam() {
        // Two pieces sewn along x = 1 (vertices 1-4 and 2-5), the second folded back a little
        // so that its first triangle overlaps the first piece's across the seam line.
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.99, 0.5, -0.1],
            [1.0, 0.0, 0.01],
            [1.0, 1.0, 0.01],
            [0.95, 0.5, 0.2],
        ];
        let t = [[0, 1, 2], [4, 5, 3], [4, 5, 6]];
        // Unsewn, the overlap at the seam counts; sewn, those triangles are neighbours.
        let apart = self_intersecting_pairs(&v, &t, &[]).unwrap();
        assert!(!apart.is_empty(), "{apart:?}");
        assert!(self_intersecting_pairs(&v, &t, &[[1, 4], [2, 5]]).unwrap().is_empty());
        // A crossing away from the seam still counts.
        let mut v2 = v.to_vec();
        v2.extend([[0.3, 0.3, -0.5], [0.3, 0.3, 0.5], [0.2, 0.6, 0.0]]);
        let mut t2 = t.to_vec();
        t2.push([7, 8, 9]);
        assert_eq!(self_intersecting_pairs(&v2, &t2, &[[1, 4], [2, 5]]).unwrap(), vec![[0, 3]]);
        assert!(self_intersecting_pairs(&v, &t, &[[1, 40]]).is_err());
    }

    #[test]
    fn strain_energy_and_seam_gap() {
        let p = [[0.0, 0.0, 0.0], [1.1, 0.0, 0.0], [0.0, 0.9, 0.0]];
        let s = edge_strain(&p, &[[0, 1], [0, 2]], &[1.0, 1.0]).unwrap();
        assert!((s.max - 0.1).abs() < 1e-6 && (s.mean - 0.1).abs() < 1e-6);
        assert!(edge_strain(&p, &[[0, 3]], &[1.0]).is_err());
        assert!(edge_strain(&p, &[[0, 1]], &[0.0]).is_err());
        let e = kinetic_energy(&[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]], &[2.0, 0.5]).unwrap();
        assert!((e - 2.0).abs() < 1e-12);
        let e2 = kinetic_energy_soa(&[1.0, 0.0], &[0.0, 2.0], &[0.0, 0.0], &[2.0, 0.5]).unwrap();
        assert_eq!(e, e2);
        assert!(kinetic_energy(&[[0.0; 3]], &[]).is_err());
        assert!((max_seam_gap(&p, &[[1, 2], [0, 1]]).unwrap() - (1.21f32 + 0.81).sqrt()).abs() < 1e-6);
        assert!(max_seam_gap(&p, &[[1, 9]]).is_err());
    }

    #[test]
    fn on_body_share_and_centroid() {
        let (v, t) = icosphere(3, 1.0);
        let body = ClosedMesh::new(&v, &t).unwrap();
        // On the surface, 9 cm out, 9 cm in, 11 cm out, far below.
        let pts = [[0.0, 0.0, 1.0], [1.09, 0.0, 0.0], [0.0, 0.91, 0.0], [0.0, 0.0, -1.11], [0.0, -5.0, 0.0]];
        assert!((on_body_fraction(&pts, &body, ON_BODY_DISTANCE) - 0.6).abs() < 1e-6);
        assert!((on_body_fraction(&pts, &body, 0.2) - 0.8).abs() < 1e-6);
        assert_eq!(on_body_fraction(&[], &body, ON_BODY_DISTANCE), 0.0);
        let c = centroid(&pts);
        assert!((c[1] - (0.91 - 5.0) / 5.0).abs() < 1e-6, "{c:?}");
        assert_eq!(centroid(&[]), [0.0; 3]);
    }

    /// The top is the mean of the highest twentieth against gravity (two of forty points here),
    /// whichever way up; without gravity the centroid.
    #[test]
    fn the_top_is_the_highest_twentieth() {
        let pts: Vec<[f32; 3]> = (0..40).map(|i| [i as f32 * 0.1, -(i as f32), 0.5]).collect();
        // Up is +y: the two highest are points 0 and 1.
        assert_eq!(top(&pts, [0.0, 9.8, 0.0]), [0.05, -0.5, 0.5]);
        // Up is -y (gravity along +y): points 38 and 39.
        assert_eq!(top(&pts, [0.0, -1.0, 0.0]), [3.85, -38.5, 0.5]);
        assert_eq!(top(&pts, [0.0; 3]), centroid(&pts));
        assert_eq!(top(&pts[..1], [0.0, 1.0, 0.0]), pts[0]);
        assert_eq!(top(&[], [0.0, 1.0, 0.0]), [0.0; 3]);
    }

    #[test]
    fn penetration_of_points_in_a_sphere() {
        let (v, t) = icosphere(3, 1.0);
        let pen = penetration(&[[0.0, 0.0, 0.5], [0.0, 0.2, 0.0], [2.0, 0.0, 0.0]], &v, &t).unwrap();
        assert_eq!(pen.count, 2);
        assert!((pen.max_depth - 0.8).abs() < 0.01, "{}", pen.max_depth);
    }
}
