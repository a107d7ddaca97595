//! CPU vs GPU frame time against particle count, with or without collisions, plus the fixed
//! cost of a frame's dispatches. Prints a Markdown table (paste it into `docs/benchmarks.md`).
//!
//! ```text
//! cargo run --release -p tailor-core --features gpu --example gpu_bench -- [options] [sizes…]
//!   sizes            particle counts (default 1000 10000 100000 1000000)
//!   --collisions     a cloth dropped on an animated sphere mesh (5120 triangles, moving every
//!                    frame, so its hash is rebuilt every substep) with self-collision on;
//!                    default: a cloth hanging from its top edge, no collisions
//!   --no-self        with --collisions: self-collision off (splits the two costs)
//!   --budget S       seconds of timed frames per measurement (default 3; at least 1 frame)
//!   --cpu-only / --gpu-only
//!   --kernels        after the table, a profile: each kernel's GPU time in one frame (a
//!                    timestamp after every dispatch), per size
//! ```
//!
//! `ns/p·it` is frame time over particles × substeps × iterations. "empty frame" runs as many
//! one-workgroup dispatches as a frame of that scene records (`GpuSolver::dispatches_per_frame`)
//! with nothing to do: the fixed cost of a frame on that adapter, reported separately. The
//! stage columns are prediction / local / global / damping in ms per frame: the CPU's stage
//! timers, and on the GPU its timestamp queries over a few more frames with stage timing on
//! (`-` where the adapter has none; the GPU ms/frame is measured with it off).

use std::time::Instant;

use tailor_core::gpu::{GpuOptions, GpuSolver};
use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::{icosphere, rectangle};
use tailor_core::solver::{
    ColliderId, Fabric, MeshColliderOptions, SelfCollisionSettings, Simulation, SolverSettings, StageTimings, STAGES,
};

const DT: f32 = 1.0 / 30.0;
const SPHERE_R: f32 = 0.3;

struct Options {
    sizes: Vec<usize>,
    collisions: bool,
    self_collision: bool,
    budget: f64,
    cpu: bool,
    gpu: bool,
    kernels: bool,
}

fn options() -> Options {
    let mut o = Options {
        sizes: Vec::new(),
        collisions: false,
        self_collision: true,
        budget: 3.0,
        cpu: true,
        gpu: true,
        kernels: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--collisions" => o.collisions = true,
            "--no-self" => o.self_collision = false,
            "--cpu-only" => o.gpu = false,
            "--gpu-only" => o.cpu = false,
            "--kernels" => o.kernels = true,
            "--budget" => o.budget = args.next().and_then(|s| s.parse().ok()).expect("--budget SECONDS"),
            n => o.sizes.push(n.parse().unwrap_or_else(|_| panic!("unknown argument {n}"))),
        }
    }
    if o.sizes.is_empty() {
        o.sizes = vec![1_000, 10_000, 100_000, 1_000_000];
    }
    o
}

/// A 1 m square cloth of about `n` particles: hanging from its top edge, or (with
/// collisions) lying just above an icosphere body with self-collision on.
fn scene(n: usize, collisions: bool, self_collision: bool) -> Simulation {
    let side = ((n as f64).sqrt().round() as usize).max(2) - 1;
    let (rest, tris) = rectangle(1.0, 1.0, side, side);
    let pos: Vec<[f32; 3]> = if collisions {
        rest.iter().map(|r| [r[0] - 0.5, r[1] - 0.5, SPHERE_R + 0.01]).collect()
    } else {
        rest.iter().map(|r| [r[0], 0.0, r[1]]).collect()
    };
    let mesh = ClothMesh::new(pos, rest, tris).expect("a valid rectangle");
    let mut sim = Simulation::new(mesh, Fabric::default(), SolverSettings::default()).expect("valid settings");
    if collisions {
        let (v, t) = icosphere(4, SPHERE_R);
        sim.add_mesh_collider(&v, &t, MeshColliderOptions::default()).expect("a valid sphere");
        let s = SelfCollisionSettings { enabled: self_collision, ..Default::default() };
        sim.set_self_collision(s).expect("valid");
    } else {
        let top: Vec<u32> = (0..=side).map(|i| (side * (side + 1) + i) as u32).collect();
        sim.pin(&top, None).expect("valid pins");
    }
    sim
}

/// The body bobs by ±5 mm so that its hash is rebuilt every substep, as for an animated
/// character.
fn animate(sim: &mut Simulation, frame: usize) {
    if sim.num_mesh_colliders() == 0 {
        return;
    }
    let (v, _) = icosphere(4, SPHERE_R);
    let dz = 0.005 * (frame as f32 * 0.7).sin();
    let moved: Vec<[f32; 3]> = v.iter().map(|p| [p[0], p[1], p[2] + dz]).collect();
    sim.set_collider_positions(ColliderId(0), &moved).expect("same vertex count");
}

/// Mean seconds per frame over at least one frame and about `budget` seconds, after one
/// warm-up frame (rebuilds, uploads, pipeline caches).
/// Mean wall time per frame and mean time per stage (the step's own timings: on the GPU from
/// timestamp queries where the adapter has them), over the frames after the first.
fn time_frames(budget: f64, mut frame: impl FnMut(usize) -> StageTimings) -> (f64, [f64; 4]) {
    frame(0);
    let t0 = Instant::now();
    let mut frames = 0;
    let mut stages = [0.0f64; 4];
    while frames == 0 || (t0.elapsed().as_secs_f64() < budget && frames < 30) {
        let t = frame(frames + 1);
        for (k, s) in STAGES.iter().enumerate() {
            stages[k] += t[*s];
        }
        frames += 1;
    }
    (t0.elapsed().as_secs_f64() / frames as f64, stages.map(|t| t / frames as f64))
}

/// `a / b / c / d` ms: prediction, local, global, damping.
fn stage_ms(t: &[f64; 4]) -> String {
    if t.iter().any(|v| v.is_nan()) {
        return "-".into();
    }
    t.iter().map(|v| format!("{:.1}", v * 1e3)).collect::<Vec<_>>().join(" / ")
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

fn main() {
    let o = options();
    let mut gpu = if o.gpu {
        match GpuSolver::new(GpuOptions::default()) {
            Ok(g) => Some(g),
            Err(e) => {
                println!("no GPU: {e}");
                None
            }
        }
    } else {
        None
    };
    if let Some(g) = &gpu {
        let i = g.adapter_info();
        println!("adapter: {} ({:?}, {:?}, driver {} {})", i.name, i.backend, i.device_type, i.driver, i.driver_info);
    }
    let s = SolverSettings::default();
    println!(
        "scene: {}; {} substeps × {} iterations per frame (dt = 1/30 s); rayon threads {}; load average {}",
        if o.collisions && o.self_collision {
            "cloth on an animated 5120-triangle sphere mesh, self-collision on"
        } else if o.collisions {
            "cloth on an animated 5120-triangle sphere mesh, self-collision off"
        } else {
            "hanging cloth, no collisions"
        },
        s.substeps,
        s.iterations,
        rayon::current_num_threads(),
        load_average()
    );
    println!();
    println!(
        "| particles | colours | CPU ms/frame | CPU ns/p·it | GPU ms/frame | GPU ns/p·it | empty frame ms | dispatches | CPU/GPU | CPU stages ms | GPU stages ms |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|");
    // Per size: its particle count and each kernel's ms in one profiled frame.
    let mut profiles: Vec<(usize, Vec<(&'static str, f64)>)> = Vec::new();
    for &n in &o.sizes {
        let mut probe = scene(n, o.collisions, o.self_collision);
        let n = probe.num_particles();
        let colours = probe.colour_count();
        let work = (n as f64) * s.substeps as f64 * s.iterations as f64;
        let (mut cpu_t, mut cpu_stages) = (f64::NAN, [f64::NAN; 4]);
        if o.cpu {
            let mut cpu = scene(n, o.collisions, o.self_collision);
            (cpu_t, cpu_stages) = time_frames(o.budget, |f| {
                animate(&mut cpu, f);
                cpu.step(DT).expect("a stable CPU step").timings
            });
        }
        let (mut gpu_t, mut gpu_stages, mut empty, mut dispatches) = (f64::NAN, [f64::NAN; 4], f64::NAN, 0);
        if let Some(g) = &mut gpu {
            let mut sim = scene(n, o.collisions, o.self_collision);
            let (mut ok, mut last) = (true, 0);
            let (t, _) = time_frames(o.budget, |f| {
                last = f;
                if ok {
                    animate(&mut sim, f);
                    match g.step(&mut sim, DT) {
                        Ok(st) => return st.timings,
                        Err(e) => {
                            println!("GPU step failed: {e}");
                            ok = false;
                        }
                    }
                }
                StageTimings::default()
            });
            if ok {
                gpu_t = t;
                // The stage split from a few more frames with timestamps on (they cost the
                // frame some per cent, so the frame time above is measured without them).
                if g.set_stage_timing(true) {
                    gpu_stages = time_frames(o.budget / 4.0, |f| {
                        animate(&mut sim, last + 1 + f);
                        g.step(&mut sim, DT).map(|st| st.timings).unwrap_or_default()
                    })
                    .1;
                }
                g.set_stage_timing(false);
                if o.kernels && g.set_kernel_timing(true) {
                    // The median frame of five, each kernel's time from the same frame.
                    let mut frames: Vec<Vec<(&'static str, f64)>> = (0..5)
                        .map(|f| {
                            animate(&mut sim, last + 100 + f);
                            let _ = g.step(&mut sim, DT);
                            g.kernel_times().to_vec()
                        })
                        .collect();
                    frames.sort_by(|a, b| total(a).total_cmp(&total(b)));
                    profiles.push((n, frames.swap_remove(2)));
                }
                g.set_kernel_timing(false);
                dispatches = g.dispatches_per_frame(s.substeps, s.iterations);
                let _ = g.sync_velocities(&mut sim);
                empty = (0..3)
                    .filter_map(|_| g.dispatch_overhead(s.substeps, s.iterations).ok())
                    .fold(f64::INFINITY, f64::min);
            }
            g.mark_dirty();
        }
        println!(
            "| {n} | {colours} | {:.1} | {:.0} | {:.1} | {:.0} | {:.1} | {dispatches} | {:.2} | {} | {} |",
            cpu_t * 1e3,
            cpu_t * 1e9 / work,
            gpu_t * 1e3,
            gpu_t * 1e9 / work,
            empty * 1e3,
            cpu_t / gpu_t,
            stage_ms(&cpu_stages),
            stage_ms(&gpu_stages)
        );
    }
    println!();
    print_profiles(&profiles);
    println!("load average at the end: {}", load_average());
}

fn total(kernels: &[(&'static str, f64)]) -> f64 {
    kernels.iter().map(|k| k.1).sum()
}

/// The profiles as one table: a row per kernel, a column per size (ms in one frame and the
/// share of that frame's profiled time).
fn print_profiles(profiles: &[(usize, Vec<(&'static str, f64)>)]) {
    if profiles.is_empty() {
        return;
    }
    println!("Profile: each kernel's GPU time in one frame (median of five profiled frames; a timestamp after every dispatch, so the total exceeds a plain frame's):");
    println!();
    let head: Vec<String> = profiles.iter().map(|(n, _)| format!("{n} particles, ms (share)")).collect();
    println!("| kernel | {} |", head.join(" | "));
    println!("|---|{}", "---:|".repeat(profiles.len()));
    let mut names: Vec<&'static str> = Vec::new();
    for (_, p) in profiles {
        for (k, _) in p {
            if !names.contains(k) {
                names.push(k);
            }
        }
    }
    for name in names.iter().chain(std::iter::once(&"total")) {
        let cells: Vec<String> = profiles
            .iter()
            .map(|(_, p)| {
                let all = total(p);
                let t = if *name == "total" { all } else { p.iter().find(|k| k.0 == *name).map_or(0.0, |k| k.1) };
                format!("{:.2} ({:.0} %)", t * 1e3, 100.0 * t / all.max(1e-12))
            })
            .collect();
        println!("| {name} | {} |", cells.join(" | "));
    }
    println!();
}
