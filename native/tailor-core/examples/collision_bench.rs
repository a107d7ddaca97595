//! Collision stage timings on a character: a two-layer cloth (2 × 71² = 10 082 particles)
//! falling on the shoulders of the GarmentCode mean body (47 500 triangles), the body
//! swaying, and what each of the scene's collision skips saves.
//!
//! `cargo run --release -p tailor-core --example collision_bench [body.obj] [frames] [case filter]`
//!
//! Prints per-frame milliseconds of each solver stage and of the collision work inside
//! them (hash = collider interpolation and hash builds, contacts = particle-vs-cell tests in
//! the local steps, self = self-collision passes after each iteration, resolve = end of
//! substep penetration resolve and friction), then the same scene with one skip disabled.

use std::time::Instant;

use glam::Vec3;
use tailor_core::io::obj::read_obj;
use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::rectangle;
use tailor_core::solver::{
    CollisionSkips, Fabric, MeshColliderOptions, SelfCollisionSettings, Simulation, SolverSettings, Stage, StepStats,
};

const DT: f32 = 1.0 / 30.0;

#[derive(Clone, Copy)]
struct Scene {
    body: bool,
    moving: bool,
    self_on: bool,
    skips: CollisionSkips,
}

fn two_layers(centre: Vec3) -> ClothMesh {
    let (w, n) = (0.7f32, 70usize);
    let (rest, tris) = rectangle(w, w, n, n);
    let mut pos = Vec::new();
    let mut all_rest = Vec::new();
    for (layer, dz) in [(0, 0.0f32), (1, 0.03)] {
        for r in &rest {
            pos.push([centre.x + r[0] - 0.5 * w, centre.y + r[1] - 0.5 * w, centre.z + dz]);
            all_rest.push([r[0] + layer as f32 * (w + 0.1), r[1]]);
        }
    }
    let k = rest.len() as u32;
    let all_tris = tris.iter().copied().chain(tris.iter().map(|t| t.map(|v| v + k))).collect();
    ClothMesh::new(pos, all_rest, all_tris).unwrap()
}

/// Runs `frames` measured frames after `warm` frames; returns per-frame averages of the
/// stage timings (ms) and the last step's statistics.
fn run(body: &(Vec<[f32; 3]>, Vec<[u32; 3]>), scene: Scene, warm: usize, frames: usize) -> ([f64; 9], StepStats, u64) {
    let (bv, bt) = body;
    let top = bv.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
    // Shoulders are about 0.25 m below the top of the head; start the cloth just above them.
    let centre = Vec3::new(0.0, 0.0, top - 0.2);
    let settings = SolverSettings::default();
    let mut sim = Simulation::new(two_layers(centre), Fabric::default(), settings).unwrap();
    sim.set_self_collision(SelfCollisionSettings { enabled: scene.self_on, ..Default::default() }).unwrap();
    sim.set_collision_skips(scene.skips);
    let id =
        if scene.body { Some(sim.add_mesh_collider(bv, bt, MeshColliderOptions::default()).unwrap()) } else { None };
    let mut acc = [0.0f64; 9];
    let mut last = StepStats::default();
    let t_all = Instant::now();
    for f in 0..warm + frames {
        if let (Some(id), true) = (id, scene.moving) {
            // Sway: a slow rotation about the vertical axis, up to 10 degrees.
            let a = 0.17 * (f as f32 * 0.2).sin();
            let q = glam::Quat::from_rotation_z(a);
            let moved: Vec<[f32; 3]> = bv.iter().map(|p| (q * Vec3::from(*p)).into()).collect();
            sim.set_collider_positions(id, &moved).unwrap();
        }
        let t0 = Instant::now();
        let s = sim.step(DT).unwrap();
        let wall = t0.elapsed().as_secs_f64();
        if f >= warm {
            let t = &s.timings;
            let c = &s.collision;
            let v = [
                wall,
                t[Stage::Prediction],
                t[Stage::Local],
                t[Stage::Global],
                t[Stage::Damping],
                c.hash_seconds,
                c.contact_seconds,
                c.self_seconds,
                c.resolve_seconds,
            ];
            for (a, x) in acc.iter_mut().zip(v) {
                *a += x * 1e3 / frames as f64;
            }
        }
        last = s;
    }
    let _ = t_all;
    (acc, last, sim.state_hash())
}

fn print_row(name: &str, t: &[f64; 9], s: &StepStats) {
    let solve = t[2] + t[3] - t[6] - t[7];
    println!(
        "{name:<34} {:>8.1} | pred {:>6.1} local {:>6.1} global {:>6.1} damp {:>6.1} | hash {:>6.2} contacts {:>6.2} self {:>7.2} resolve {:>5.2} solve {:>7.1} | rebuilds {} reuses {} kept {} culled {} contacts {} pairs {} self searches {}",
        t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8], solve,
        s.collision.rebuilds, s.collision.reuses, s.collision.triangles_kept, s.collision.triangles_culled,
        s.collision.mesh_contacts, s.collision.self_pairs, s.collision.self_searches
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path =
        args.get(1).cloned().unwrap_or_else(|| "/work/shared/data/bodies/garmentcode-mean-all/mean_all.obj".into());
    let frames: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let obj = read_obj(&path).unwrap();
    // The body is Y-up; the solver's gravity is −Z: (x, y, z) → (x, −z, y).
    let bv: Vec<[f32; 3]> = obj.positions.iter().map(|p| [p[0], -p[2], p[1]]).collect();
    let body = (bv, obj.triangles);
    println!(
        "body: {} vertices, {} triangles; cloth: 2 layers × 71² = 10082 particles; {} threads; per frame (4 substeps × 20 iterations), ms, mean of {frames} frames after 10 warm-up",
        body.0.len(),
        body.1.len(),
        rayon::current_num_threads()
    );
    let all = CollisionSkips::default();
    let base = Scene { body: true, moving: true, self_on: true, skips: all };
    let cases = [
        ("moving body, all skips", base),
        ("moving body, no culling", Scene { skips: CollisionSkips { cull_far_triangles: false, ..all }, ..base }),
        ("still body, all skips", Scene { moving: false, ..base }),
        (
            "still body, no reuse",
            Scene { moving: false, skips: CollisionSkips { reuse_collider_hashes: false, ..all }, ..base },
        ),
        (
            "still body, no reuse, no culling",
            Scene {
                moving: false,
                skips: CollisionSkips { reuse_collider_hashes: false, cull_far_triangles: false, ..all },
                ..base
            },
        ),
        (
            "moving body, self search every pass",
            Scene { skips: CollisionSkips { reuse_self_pairs: false, ..all }, ..base },
        ),
        (
            "moving body, no mesh broad phase",
            Scene { skips: CollisionSkips { mesh_broad_phase: false, ..all }, ..base },
        ),
        ("moving body, self-collision off", Scene { self_on: false, ..base }),
        (
            "moving body, self off, no mesh broad phase",
            Scene { self_on: false, skips: CollisionSkips { mesh_broad_phase: false, ..all }, ..base },
        ),
        ("no body (no collider hash)", Scene { body: false, ..base }),
    ];
    let only = args.get(3).cloned().unwrap_or_default();
    for (name, scene) in cases.into_iter().filter(|(n, _)| n.contains(only.as_str())) {
        let (t, s, hash) = run(&body, scene, 10, frames);
        print_row(name, &t, &s);
        println!("{name:<34} state hash {hash:016x}");
    }
}
