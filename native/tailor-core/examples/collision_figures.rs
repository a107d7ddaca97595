//! Prints the collision figures quoted in reviews: hash build times (1 thread vs all) and
//! the quality metrics on the shared sample bodies.
//!
//! `cargo run --release -p tailor-core --example collision_figures [shared/data]`

use std::path::PathBuf;
use std::time::Instant;

use tailor_core::collision::collider_hash::{ColliderHash, InsertionRule};
use tailor_core::collision::{SelfCollision, SpatialHash};
use tailor_core::io::{gltf::GltfScene, obj::read_obj, TriMesh};
use tailor_core::quality::metrics::{count_self_intersections, penetration};

struct Rng(u64);
impl Rng {
    fn f32(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Median and minimum wall time of `runs` calls, in milliseconds, after two warm-up calls
/// (the minimum is the better figure on a shared machine).
fn time_ms(runs: usize, mut f: impl FnMut()) -> (f64, f64) {
    f();
    f();
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(|a, b| a.total_cmp(b));
    (t[runs / 2], t[0])
}

fn in_pool<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

fn mean_edge(m: &TriMesh) -> f32 {
    let mut s = 0.0f64;
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (m.positions[t[k] as usize], m.positions[t[(k + 1) % 3] as usize]);
            s += ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt() as f64;
        }
    }
    (s / (3 * m.triangles.len()) as f64) as f32
}

fn signed_volume(m: &TriMesh) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize].map(|x| x as f64));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

fn main() {
    let all = rayon::current_num_threads();
    println!("threads available: {all}");
    for n in [10_000usize, 100_000] {
        // Cloth-like density: n particles on a 1 m² sheet folded into a box, cell = spacing.
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
        for _ in 0..n {
            x.push(rng.f32());
            y.push(rng.f32());
            z.push(rng.f32() * 0.05);
        }
        let l = 1.0 / (n as f32).sqrt();
        for threads in [1, all] {
            let (build, pairs, npairs) = in_pool(threads, || {
                let mut h = SpatialHash::new();
                let build = time_ms(21, || h.build_points(&x, &y, &z, l).unwrap());
                let mut sc = SelfCollision::new();
                let mut np = 0;
                let pairs = time_ms(11, || np = sc.find_pairs(&x, &y, &z, 0.5 * l, l, |_, _| false).unwrap().len());
                (build, pairs, np)
            });
            println!(
                "points {n:>7}: {threads:>2} thread(s): hash build {:7.3} ms (min {:7.3}), self-collision \
                 pairs (build + query, r = l/2) {:7.3} ms (min {:7.3}), {npairs} pairs",
                build.0, build.1, pairs.0, pairs.1
            );
        }
    }

    let data = std::env::args().nth(1).map(PathBuf::from).unwrap_or_else(|| PathBuf::from("../shared/data"));
    let body_path = data.join("bodies/garmentcode-mean-all/mean_all.obj");
    if let Ok(body) = read_obj(&body_path) {
        let (lo, hi) = body.bounds().unwrap();
        let l = mean_edge(&body);
        println!(
            "mean_all.obj: {} vertices, {} triangles, height {:.3} m, mean edge {:.4} m, signed volume {:.4} m³",
            body.positions.len(),
            body.triangles.len(),
            hi[1] - lo[1],
            l,
            signed_volume(&body)
        );
        for threads in [1, all] {
            in_pool(threads, || {
                let mut ch = ColliderHash::new();
                for (rule, name) in [(InsertionRule::Paper, "paper"), (InsertionRule::PaperOrPlane, "paper+plane")] {
                    let (med, min) = time_ms(11, || ch.build(&body.positions, &body.triangles, l, rule).unwrap());
                    println!(
                        "  collider hash ({name}, l = mean edge), {threads:>2} thread(s): {med:.3} ms (min {min:.3}), \
                         {} insertions, fullest bucket {}",
                        ch.hash().num_entries(),
                        ch.hash().max_bucket_len()
                    );
                }
            });
        }
        let s = Instant::now();
        let si = count_self_intersections(&body.positions, &body.triangles).unwrap();
        println!("  self-intersections: {si} ({:.1} ms)", s.elapsed().as_secs_f64() * 1e3);
        // Grid points over the bounding box: the inside count estimates the volume.
        let step = 0.01f32;
        let mut pts = Vec::new();
        let mut px = lo[0];
        while px < hi[0] {
            let mut py = lo[1];
            while py < hi[1] {
                let mut pz = lo[2];
                while pz < hi[2] {
                    pts.push([px + 0.5 * step, py + 0.5 * step, pz + 0.5 * step]);
                    pz += step;
                }
                py += step;
            }
            px += step;
        }
        let s = Instant::now();
        let pen = penetration(&pts, &body.positions, &body.triangles).unwrap();
        println!(
            "  penetration of a 1 cm grid ({} points): {} inside (volume {:.4} m³), max depth {:.4} m ({:.1} ms)",
            pts.len(),
            pen.count,
            pen.count as f64 * (step as f64).powi(3),
            pen.max_depth,
            s.elapsed().as_secs_f64() * 1e3
        );
    } else {
        println!("{} not found: body figures skipped", body_path.display());
    }

    let cesium = data.join("bodies/khronos-cesiumman/CesiumMan.glb");
    if let Ok(scene) = GltfScene::load(&cesium) {
        let dur = scene.animations()[0].duration;
        let mut p = Vec::new();
        let (ms, _) = time_ms(21, || scene.positions_at(Some(0), 0.37 * dur, &mut p).unwrap());
        println!(
            "CesiumMan.glb: {} vertices, animation {:.3} s, skinning one pose {ms:.3} ms",
            scene.num_vertices(),
            dur
        );
        for k in 0..=4 {
            let t = dur * k as f32 / 4.0;
            let m = scene.mesh_at(Some(0), t).unwrap();
            let (lo, hi) = m.bounds().unwrap();
            let si = count_self_intersections(&m.positions, &m.triangles).unwrap();
            println!("  t = {t:.3} s: height {:.3} m, self-intersections {si}", hi[1] - lo[1]);
        }
    }
}
