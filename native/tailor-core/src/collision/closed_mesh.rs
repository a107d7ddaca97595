//! Inside/outside and distance queries against a closed triangle mesh (the body), used by the
//! penetration metric.
//!
//! **Inside test: ray parity.** A point is inside a closed mesh iff a ray from it crosses the
//! surface an odd number of times. The ray goes along `+x`, so a triangle is crossed when the
//! point's `(y, z)` lies in the triangle's `(y, z)` projection and the plane's `x` there is
//! larger than the point's. Triangles are binned on a uniform 2D grid over `(y, z)` so a ray
//! only tests the triangles of its bin.
//!
//! Robustness: the 2D inclusion uses the edge functions `e(a, b, p) = (b − a) ⊥ (p − a)` in
//! `f64`, which are exact in sign for `f32` input (differences of `f32` are exact in `f64`,
//! products of two of them too). Each projected triangle is made counter-clockwise, and a point
//! exactly on an edge line is decided as if it were moved by an infinitesimal `(ε, ε²)`
//! (simulation of simplicity): `e = 0` counts as inside iff `d_z < 0 || (d_z = 0 && d_y > 0)`
//! for the edge direction `d = b − a`. Two triangles sharing an edge on opposite sides of it
//! traverse it in opposite directions, so exactly one of them owns the point; a ray through a
//! shared edge or vertex is therefore counted once, and one grazing a silhouette zero or two
//! times, never leaving the parity wrong. Triangles edge-on to the ray are skipped.
//!
//! **Distance: ring search.** Triangles are filed in every hash cell their AABB overlaps. The
//! search visits shells of cells at Chebyshev distance `r = 0, 1, 2, …` around the point's
//! cell; a triangle not yet seen lies in cells at distance `> r`, hence at least `r·l` away, so
//! the search stops as soon as the best distance found is `≤ r·l`.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

use glam::{DVec2, Vec3};
use rayon::prelude::*;

use super::collider_hash::{ColliderHash, InsertionRule};
use super::geometry::closest_point_on_triangle;
use super::hash::Cell;
use crate::error::{Result, TailorError};

/// A closed mesh prepared for inside and distance queries.
#[derive(Debug)]
pub struct ClosedMesh {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    // 2D (y, z) grid for the rays, CSR.
    lo: [f32; 2],
    inv_side: f32,
    dims: [usize; 2],
    bin_starts: Vec<u32>,
    bin_items: Vec<u32>,
    // 3D hash for distances, built on the first distance query: the penetration metric asks
    // only for the points found inside, usually none, and the build over a 47k-triangle body
    // was most of the metric's time per frame.
    hash: OnceLock<ColliderHash>,
    cell: f32,
    cell_lo: Cell,
    cell_hi: Cell,
    // Bounding box of the vertices.
    bounds: [Vec3; 2],
}

/// A cell side for conservative (every AABB cell) hashing: the mean triangle AABB extent, but
/// at least 1/16 of the largest one so no triangle spans more than 17³ cells.
pub fn aabb_cell_size(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> f32 {
    let mut sum = 0.0f64;
    let mut max = 0.0f32;
    for t in triangles {
        let v = t.map(|i| Vec3::from(vertices[i as usize]));
        let e = (v[0].max(v[1]).max(v[2]) - v[0].min(v[1]).min(v[2])).max_element();
        sum += e as f64;
        max = max.max(e);
    }
    let mean = (sum / triangles.len().max(1) as f64) as f32;
    mean.max(max / 16.0).max(1e-6)
}

impl ClosedMesh {
    /// Validates the mesh (non-empty, indices in range, finite) and builds both accelerators.
    pub fn new(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> Result<Self> {
        if triangles.is_empty() {
            return Err(TailorError::EmptyMesh { what: "the closed mesh has no triangles".into() });
        }
        let cell = {
            // Validate indices before anything indexes with them.
            let n = vertices.len();
            for (t, tri) in triangles.iter().enumerate() {
                if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
                    return Err(TailorError::index(format!("closed mesh triangle {t}"), v as i64, n, "vertices"));
                }
            }
            aabb_cell_size(vertices, triangles)
        };
        // Checked now, so the build on first use cannot fail.
        ColliderHash::check(vertices, triangles, cell)?;

        let (mut lo3, mut hi3) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for v in vertices {
            lo3 = lo3.min(Vec3::from(*v));
            hi3 = hi3.max(Vec3::from(*v));
        }
        let res = ((triangles.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let side = ((hi3.y - lo3.y).max(hi3.z - lo3.z) / res as f32).max(1e-6);
        let inv_side = 1.0 / side;
        let dims = [
            (((hi3.y - lo3.y) * inv_side) as usize + 1).min(res + 1),
            (((hi3.z - lo3.z) * inv_side) as usize + 1).min(res + 1),
        ];
        let lo = [lo3.y, lo3.z];
        let bin = |y: f32, z: f32| {
            let by = (((y - lo[0]) * inv_side) as usize).min(dims[0] - 1);
            let bz = (((z - lo[1]) * inv_side) as usize).min(dims[1] - 1);
            (by, bz)
        };
        let ranges: Vec<((usize, usize), (usize, usize))> = triangles
            .iter()
            .map(|t| {
                let v = t.map(|i| vertices[i as usize]);
                let (ymin, ymax) = (v[0][1].min(v[1][1]).min(v[2][1]), v[0][1].max(v[1][1]).max(v[2][1]));
                let (zmin, zmax) = (v[0][2].min(v[1][2]).min(v[2][2]), v[0][2].max(v[1][2]).max(v[2][2]));
                (bin(ymin, zmin), bin(ymax, zmax))
            })
            .collect();
        let mut bin_starts = vec![0u32; dims[0] * dims[1] + 1];
        for &((y0, z0), (y1, z1)) in &ranges {
            for bz in z0..=z1 {
                for by in y0..=y1 {
                    bin_starts[bz * dims[0] + by + 1] += 1;
                }
            }
        }
        for i in 1..bin_starts.len() {
            bin_starts[i] += bin_starts[i - 1];
        }
        let mut fill = bin_starts.clone();
        let mut bin_items = vec![0u32; *bin_starts.last().unwrap() as usize];
        for (t, &((y0, z0), (y1, z1))) in ranges.iter().enumerate() {
            for bz in z0..=z1 {
                for by in y0..=y1 {
                    let slot = &mut fill[bz * dims[0] + by];
                    bin_items[*slot as usize] = t as u32;
                    *slot += 1;
                }
            }
        }
        let l = cell;
        let cell_lo = super::hash::cell_of(lo3.into(), l);
        let cell_hi = super::hash::cell_of(hi3.into(), l);
        Ok(Self {
            vertices: vertices.to_vec(),
            triangles: triangles.to_vec(),
            lo,
            inv_side,
            dims,
            bin_starts,
            bin_items,
            hash: OnceLock::new(),
            cell,
            cell_lo,
            cell_hi,
            bounds: [lo3, hi3],
        })
    }

    /// The distance hash, built on first use (its input was checked in [`ClosedMesh::new`]).
    ///
    /// The build is parallel. Reached first from inside a parallel loop (a rayon worker), it
    /// must not run on that loop's workers: the others wait here for it, and this thread, while
    /// waiting for the build's own jobs, could take a job of the loop that needs this very hash
    /// (a deadlock, seen from 8 threads up: `tailor simulate` hung at its first frame on a
    /// 16-core machine). There it is built on a thread outside every pool, in a one-thread pool
    /// of its own, and waited for without taking work; [`ClosedMesh::prepare_queries`] before
    /// a parallel loop keeps the build parallel.
    fn distance_hash(&self) -> &ColliderHash {
        self.hash.get_or_init(|| {
            if rayon::current_thread_index().is_none() {
                return self.build_distance_hash();
            }
            std::thread::scope(|s| {
                s.spawn(|| match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
                    Ok(pool) => pool.install(|| self.build_distance_hash()),
                    Err(_) => self.build_distance_hash(),
                })
                .join()
                .unwrap_or_else(|e| std::panic::resume_unwind(e))
            })
        })
    }

    fn build_distance_hash(&self) -> ColliderHash {
        let mut h = ColliderHash::new();
        // `check` passed on this input in `new`: the build files every triangle.
        let built = h.build_checked(&self.vertices, &self.triangles, self.cell, InsertionRule::Aabb);
        debug_assert!(built.is_ok(), "{built:?}");
        h
    }

    /// Builds the distance hash now, if no query has yet: before queries in a parallel loop,
    /// so that the build runs in parallel (a first query from inside the loop builds it on one
    /// thread, see `distance_hash`).
    pub fn prepare_queries(&self) {
        let _ = self.distance_hash();
    }

    /// Whether `p` is inside (ray parity along `+x`). Points exactly on the surface may go
    /// either way.
    pub fn contains(&self, p: [f32; 3]) -> bool {
        let (fy, fz) = ((p[1] - self.lo[0]) * self.inv_side, (p[2] - self.lo[1]) * self.inv_side);
        if !(fy >= 0.0 && fz >= 0.0) || fy as usize >= self.dims[0] || fz as usize >= self.dims[1] {
            return false;
        }
        let b = fz as usize * self.dims[0] + fy as usize;
        let q = DVec2::new(p[1] as f64, p[2] as f64);
        let mut crossings = 0u32;
        for &t in &self.bin_items[self.bin_starts[b] as usize..self.bin_starts[b + 1] as usize] {
            let v = self.triangles[t as usize].map(|i| self.vertices[i as usize]);
            let mut a = DVec2::new(v[0][1] as f64, v[0][2] as f64);
            let mut bb = DVec2::new(v[1][1] as f64, v[1][2] as f64);
            let c = DVec2::new(v[2][1] as f64, v[2][2] as f64);
            let (mut xa, mut xb, xc) = (v[0][0] as f64, v[1][0] as f64, v[2][0] as f64);
            let area = (bb - a).perp_dot(c - a);
            if area == 0.0 {
                continue; // edge-on to the ray
            }
            if area < 0.0 {
                std::mem::swap(&mut a, &mut bb);
                std::mem::swap(&mut xa, &mut xb);
            }
            let (Some(wc), Some(wa), Some(wb)) = (owned(a, bb, q), owned(bb, c, q), owned(c, a, q)) else {
                continue;
            };
            let x = (wa * xa + wb * xb + wc * xc) / area.abs();
            if x > p[0] as f64 {
                crossings += 1;
            }
        }
        crossings % 2 == 1
    }

    /// Distance from `p` to the surface and the nearest triangle.
    pub fn distance(&self, p: [f32; 3]) -> (f32, u32) {
        self.distance_unless_below(p, -1.0)
    }

    /// [`ClosedMesh::distance`], except that the search may stop, returning any distance
    /// `≤ floor`, as soon as it knows the true distance is at most `floor`.
    fn distance_unless_below(&self, p: [f32; 3], floor: f32) -> (f32, u32) {
        let pv = Vec3::from(p);
        let l = self.cell;
        let c = self.distance_hash().hash().cell_of(p);
        // Beyond this shell radius every cell of the mesh's bounding box has been visited.
        let r_max =
            (0..3).map(|k| (c[k] - self.cell_lo[k]).abs().max((self.cell_hi[k] - c[k]).abs())).max().unwrap_or(0);
        let mut best = (f32::INFINITY, 0u32);
        let visit_one = |t: u32, best: &mut (f32, u32)| {
            let [a, b, cc] = self.triangles[t as usize].map(|i| Vec3::from(self.vertices[i as usize]));
            let d = closest_point_on_triangle(pv, a, b, cc).0.distance(pv);
            if d < best.0 || (d == best.0 && t < best.1) {
                *best = (d, t);
            }
        };
        let visit = |cell: Cell, best: &mut (f32, u32)| {
            for t in self.distance_hash().hash().query_cell(cell) {
                visit_one(t, best);
            }
        };
        // Shells grow as r²: past a few times the triangle count in visited cells (a point
        // far from, or deep inside, a coarse mesh) testing every triangle is cheaper.
        let budget = 4 * self.triangles.len() as i64 + 27;
        for r in 0..=r_max {
            if (2 * r + 1).saturating_pow(3) > budget {
                let mut best = (f32::INFINITY, 0u32);
                for t in 0..self.triangles.len() as u32 {
                    visit_one(t, &mut best);
                }
                return best;
            }
            for dz in -r..=r {
                for dy in -r..=r {
                    if dz.abs() == r || dy.abs() == r {
                        for dx in -r..=r {
                            visit([c[0] + dx, c[1] + dy, c[2] + dz], &mut best);
                        }
                    } else {
                        visit([c[0] - r, c[1] + dy, c[2] + dz], &mut best);
                        if r > 0 {
                            visit([c[0] + r, c[1] + dy, c[2] + dz], &mut best);
                        }
                    }
                }
            }
            if best.0 <= r as f32 * l || best.0 <= floor {
                break;
            }
        }
        best
    }

    /// Whether the surface comes within `within` metres of `p` (`within` ≥ 0).
    ///
    /// The ring search of [`ClosedMesh::distance`] bounded by the question: a point farther
    /// than `within` from the mesh's bounding box is answered at once, and after shell `r`
    /// every triangle not yet seen is more than `r·l` away, so no shell beyond
    /// `⌈within / l⌉` is visited. Cheap for points far from the body (a garment that fell).
    pub fn is_within(&self, p: [f32; 3], within: f32) -> bool {
        let pv = Vec3::from(p);
        if !pv.is_finite() || within.is_nan() || within < 0.0 {
            return false;
        }
        let outside = (self.bounds[0] - pv).max(pv - self.bounds[1]).max(Vec3::ZERO);
        if outside.length() > within {
            return false;
        }
        let l = self.cell;
        let c = self.distance_hash().hash().cell_of(p);
        let near = |t: u32| {
            let [a, b, cc] = self.triangles[t as usize].map(|i| Vec3::from(self.vertices[i as usize]));
            closest_point_on_triangle(pv, a, b, cc).0.distance(pv) <= within
        };
        let r_end = ((within / l).ceil() as i64).min(1 << 20);
        if (2 * r_end + 1).saturating_pow(3) > 4 * self.triangles.len() as i64 + 27 {
            return (0..self.triangles.len() as u32).any(near);
        }
        let query = |dx: i64, dy: i64, dz: i64| {
            self.distance_hash().hash().query_cell([c[0] + dx, c[1] + dy, c[2] + dz]).any(near)
        };
        for r in 0..=r_end {
            for dz in -r..=r {
                for dy in -r..=r {
                    let hit = if dz.abs() == r || dy.abs() == r {
                        (-r..=r).any(|dx| query(dx, dy, dz))
                    } else {
                        query(-r, dy, dz) || (r > 0 && query(r, dy, dz))
                    };
                    if hit {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// How many of `points` are within `within` metres of the surface: [`ClosedMesh::is_within`]'s
    /// count, mostly decided by the vertices ([`super::near_surface`]), in parallel.
    pub fn count_within(&self, points: &[[f32; 3]], within: f32) -> usize {
        super::near_surface::count_within(self, points, within)
    }

    /// The mesh's vertices.
    pub fn vertices(&self) -> &[[f32; 3]] {
        &self.vertices
    }

    /// The mesh's triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The area-weighted centroid of the surface (the mean vertex when it has no area).
    pub fn surface_centroid(&self) -> [f32; 3] {
        let (mut sum, mut area) = (glam::DVec3::ZERO, 0.0f64);
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| Vec3::from(self.vertices[i as usize]).as_dvec3());
            let w = 0.5 * (b - a).cross(c - a).length();
            sum += w * (a + b + c) / 3.0;
            area += w;
        }
        if area > 0.0 {
            return (sum / area).as_vec3().into();
        }
        let n = self.vertices.len().max(1) as f64;
        (self.vertices.iter().map(|v| Vec3::from(*v).as_dvec3()).sum::<glam::DVec3>() / n).as_vec3().into()
    }

    /// Number of points inside and the largest distance of an inside point to the surface.
    pub fn penetration(&self, points: &[[f32; 3]]) -> Penetration {
        let inside: Vec<[f32; 3]> = points.par_iter().copied().filter(|&p| self.contains(p)).collect();
        if inside.is_empty() {
            return Penetration::default();
        }
        // The distance queries below run in parallel: the hash first (`prepare_queries`).
        self.prepare_queries();
        // Only the deepest point matters: a search may stop once it cannot beat the deepest
        // found so far (positive f32 bits order like the floats).
        let deepest = AtomicU32::new(0);
        let max_depth = inside
            .par_iter()
            .map(|&p| {
                let floor = f32::from_bits(deepest.load(Ordering::Relaxed));
                let d = self.distance_unless_below(p, floor).0;
                deepest.fetch_max(d.to_bits(), Ordering::Relaxed);
                d
            })
            .reduce(|| 0.0, f32::max);
        Penetration { count: inside.len(), max_depth }
    }
}

/// Edge function of `q` against edge `ab` of a counter-clockwise triangle, `None` when `q` is
/// outside that edge's half-plane (ties broken by the `(ε, ε²)` perturbation of the module
/// docs).
#[inline]
fn owned(a: DVec2, b: DVec2, q: DVec2) -> Option<f64> {
    let d = b - a;
    let e = d.perp_dot(q - a);
    if e > 0.0 || (e == 0.0 && (d.y < 0.0 || (d.y == 0.0 && d.x > 0.0))) {
        Some(e)
    } else {
        None
    }
}

/// Points inside a closed mesh.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Penetration {
    /// How many points are inside.
    pub count: usize,
    /// Largest distance from an inside point to the surface (0 when none is inside).
    pub max_depth: f32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{box_mesh, icosphere, Rng};

    /// A fresh mesh's first queries, from a pool of many threads (more than this machine has
    /// cores, as on a 16-core workstation): they answer instead of deadlocking on the lazy
    /// hash build (which hung `tailor simulate` at its first frame on a 16-core machine).
    #[test]
    fn first_queries_from_many_threads_do_not_deadlock() {
        // As many triangles as a character (its hash build splits across the workers).
        let (v, t) = icosphere(6, 1.0);
        // Inside, near the surface (a garment's few points through the body).
        let points: Vec<[f32; 3]> = (0..20_000)
            .map(|i| {
                let (z, a) = (i as f32 / 20_000.0 * 1.8 - 0.9, i as f32 * 2.399);
                let r = (0.95f32 * 0.95 - z * z).max(0.0).sqrt();
                [r * a.cos(), r * a.sin(), z]
            })
            .collect();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(16).build().unwrap();
            let answers: Vec<(usize, usize, usize)> = (0..2)
                .map(|_| {
                    let mesh = ClosedMesh::new(&v, &t).unwrap();
                    let count = pool.install(|| mesh.penetration(&points)).count;
                    let mesh = ClosedMesh::new(&v, &t).unwrap();
                    // An unbounded distance takes the exact test, point by point in parallel.
                    let near = pool.install(|| mesh.count_within(&points[..2000], f32::INFINITY));
                    // A first query from inside someone else's parallel loop (the closing holds'),
                    // on fresh meshes: the deadlock needed a worker to steal part of the build.
                    let close = (0..10)
                        .map(|_| {
                            let mesh = ClosedMesh::new(&v, &t).unwrap();
                            pool.install(|| points.par_iter().filter(|&&p| mesh.distance(p).0 < 0.1).count())
                        })
                        .min()
                        .unwrap();
                    (count, near, close)
                })
                .collect();
            let _ = tx.send(answers);
        });
        let answers = rx.recv_timeout(std::time::Duration::from_secs(60)).expect("the queries deadlocked");
        assert!(answers.iter().all(|&a| a == (20_000, 2000, 20_000)), "{answers:?}");
    }

    #[test]
    fn inside_and_depth_for_a_sphere_and_a_box() {
        let (v, t) = icosphere(3, 1.0);
        let sphere = ClosedMesh::new(&v, &t).unwrap();
        let mut rng = Rng::new(5);
        let mut points = Vec::new();
        let mut want = 0;
        let mut want_depth = 0.0f32;
        for _ in 0..3000 {
            let p = rng.vec3(1.3);
            let r = p.length();
            // Stay clear of the band between the inscribed polyhedron and the sphere.
            if (0.99..1.01).contains(&r) {
                continue;
            }
            if r < 1.0 {
                want += 1;
                want_depth = want_depth.max(1.0 - r);
            }
            points.push(p.into());
        }
        let pen = sphere.penetration(&points);
        assert_eq!(pen.count, want);
        // The polyhedron is inscribed in the sphere: depths are smaller by up to the sag.
        assert!((pen.max_depth - want_depth).abs() < 0.01, "{} vs {want_depth}", pen.max_depth);
        assert!((sphere.distance([0.0, 0.0, 0.0]).0 - 1.0).abs() < 0.01);
        // Far away (brute-force fallback) and absurdly far: still answered, quickly.
        assert!((sphere.distance([10.0, 0.0, 0.0]).0 - 9.0).abs() < 1e-4);
        assert!(sphere.distance([3e30, 0.0, 0.0]).0 > 1e30);
        assert!(!sphere.contains([f32::NAN, 0.0, 0.0]));

        // A box, with points on grid lines that hit its edges and vertices exactly.
        let (v, t) = box_mesh([-1.0, -1.0, -1.0], [1.0, 2.0, 3.0]);
        let bx = ClosedMesh::new(&v, &t).unwrap();
        let mut count = 0;
        let mut pts = Vec::new();
        for &y in &[-2.0f32, -1.0, -0.5, 0.0, 1.0, 2.0, 2.5] {
            for &z in &[-1.5f32, -1.0, 0.0, 1.0, 2.9, 3.0, 4.0] {
                for &x in &[-3.0f32, -0.5, 0.0, 0.5, 3.0] {
                    pts.push([x, y, z]);
                    let strictly = y > -1.0 && y < 2.0 && z > -1.0 && z < 3.0 && x > -1.0 && x < 1.0;
                    let outside =
                        !(-1.0..=2.0).contains(&y) || !(-1.0..=3.0).contains(&z) || !(-1.0..=1.0).contains(&x);
                    if strictly {
                        count += 1;
                    }
                    if strictly || outside {
                        assert_eq!(bx.contains([x, y, z]), strictly, "{x} {y} {z}");
                    }
                }
            }
        }
        let inside: Vec<[f32; 3]> = pts.iter().copied().filter(|p| bx.contains(*p)).collect();
        assert!(inside.len() >= count);
        let pen = bx.penetration(&[[0.0, 0.5, 1.0], [0.5, 0.0, 0.0], [5.0, 0.0, 0.0]]);
        assert_eq!(pen.count, 2);
        assert!((pen.max_depth - 1.0).abs() < 1e-6, "{}", pen.max_depth);
    }

    #[test]
    fn within_agrees_with_the_distance() {
        let (v, t) = icosphere(3, 0.3);
        let sphere = ClosedMesh::new(&v, &t).unwrap();
        let mut rng = Rng::new(11);
        for k in 0..4000 {
            let p: [f32; 3] = (rng.vec3(0.8) * if k % 4 == 0 { 10.0 } else { 1.0 }).into();
            let d = sphere.distance(p).0;
            for within in [0.0, 0.01, 0.05, 0.2, 3.0] {
                // Points within rounding of the limit may go either way.
                if (d - within).abs() > 1e-5 {
                    assert_eq!(sphere.is_within(p, within), d <= within, "{p:?} at {d} within {within}");
                }
            }
        }
        assert!(!sphere.is_within([f32::NAN, 0.0, 0.0], 1.0) && !sphere.is_within([0.0; 3], f32::NAN));
        assert_eq!(sphere.count_within(&[[0.0, 0.31, 0.0], [0.0, 0.0, 0.0], [0.0, -2.0, 0.0]], 0.05), 1);
        // The surface centroid: the sphere's centre; a box's, whatever its vertex order.
        let c = Vec3::from(sphere.surface_centroid());
        assert!(c.length() < 1e-5, "{c}");
        let (v, t) = box_mesh([0.0, 1.0, 2.0], [2.0, 2.0, 4.0]);
        let c = Vec3::from(ClosedMesh::new(&v, &t).unwrap().surface_centroid());
        assert!((c - Vec3::new(1.0, 1.5, 3.0)).length() < 1e-5, "{c}");
    }

    #[test]
    fn rays_through_shared_edges_and_vertices_count_once() {
        // Points whose +x ray passes exactly through vertices and edges of the sphere.
        let (v, t) = icosphere(2, 1.0);
        let sphere = ClosedMesh::new(&v, &t).unwrap();
        for p in &v {
            let q = [p[0] * 0.5 - 0.3, p[1], p[2]];
            let want = Vec3::from(q).length() < 0.95;
            if want || Vec3::from(q).length() > 1.05 {
                assert_eq!(sphere.contains(q), want, "{q:?}");
            }
        }
    }
}
