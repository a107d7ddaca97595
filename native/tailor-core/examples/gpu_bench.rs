//! CPU vs GPU frame time on a hanging cloth at about 1k, 10k and 100k particles, plus the
//! fixed cost of a frame's dispatches.
//!
//! `cargo run --release -p tailor-core --features gpu --example gpu_bench [sizes…]`
//! (sizes are particle counts, default `1000 10000 100000`). Records belong in `docs/gpu.md`.

use std::time::Instant;

use tailor_core::gpu::{GpuOptions, GpuSolver};
use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::rectangle;
use tailor_core::solver::{Fabric, Simulation, SolverSettings};

const DT: f32 = 1.0 / 30.0;

/// A square cloth of about `n` particles hanging from its top edge (1 m wide).
fn cloth(n: usize) -> Simulation {
    let side = ((n as f64).sqrt().round() as usize).max(2) - 1;
    let (rest, tris) = rectangle(1.0, 1.0, side, side);
    let pos: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], 0.0, r[1]]).collect();
    let mesh = ClothMesh::new(pos, rest, tris).expect("a valid rectangle");
    let mut sim = Simulation::new(mesh, Fabric::default(), SolverSettings::default()).expect("valid settings");
    let top: Vec<u32> = (0..=side).map(|i| (side * (side + 1) + i) as u32).collect();
    sim.pin(&top, None).expect("valid pins");
    sim
}

/// Mean seconds per frame over at least one frame and about `budget` seconds.
fn time_frames(budget: f64, mut frame: impl FnMut()) -> (f64, usize) {
    frame(); // warm-up: rebuilds, uploads, pipeline caches
    let t0 = Instant::now();
    let mut frames = 0;
    while frames == 0 || (t0.elapsed().as_secs_f64() < budget && frames < 30) {
        frame();
        frames += 1;
    }
    (t0.elapsed().as_secs_f64() / frames as f64, frames)
}

fn main() {
    let sizes: Vec<usize> = {
        let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
        if args.is_empty() {
            vec![1_000, 10_000, 100_000]
        } else {
            args
        }
    };
    let mut gpu = match GpuSolver::new(GpuOptions::default()) {
        Ok(g) => Some(g),
        Err(e) => {
            println!("no GPU: {e}");
            None
        }
    };
    if let Some(g) = &gpu {
        let i = g.adapter_info();
        println!("adapter: {} ({:?}, {:?}, driver {} {})", i.name, i.backend, i.device_type, i.driver, i.driver_info);
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    let s = SolverSettings::default();
    println!("settings: {} substeps × {} iterations per frame (dt = 1/30 s)", s.substeps, s.iterations);
    println!(
        "{:>8} {:>7} {:>12} {:>12} {:>12} {:>12} {:>14}",
        "n", "colours", "cpu ms/frame", "cpu ns/p·it", "gpu ms/frame", "gpu ns/p·it", "gpu empty ms"
    );
    for &n in &sizes {
        let mut cpu = cloth(n);
        let n = cpu.num_particles();
        let work = (n as f64) * s.substeps as f64 * s.iterations as f64;
        let (cpu_t, _) = time_frames(3.0, || {
            cpu.step(DT).expect("a stable CPU step");
        });
        let colours = cpu.colour_count();
        let (mut gpu_t, mut empty) = (f64::NAN, f64::NAN);
        if let Some(g) = &mut gpu {
            let mut sim = cloth(n);
            let mut ok = true;
            let (t, _) = time_frames(3.0, || {
                if ok {
                    if let Err(e) = g.step(&mut sim, DT) {
                        println!("GPU step failed: {e}");
                        ok = false;
                    }
                }
            });
            if ok {
                gpu_t = t;
                let _ = g.sync_velocities(&mut sim);
                empty = (0..3)
                    .filter_map(|_| g.dispatch_overhead(s.substeps, s.iterations, colours).ok())
                    .fold(f64::INFINITY, f64::min);
            }
            g.mark_dirty();
        }
        println!(
            "{:>8} {:>7} {:>12.2} {:>12.2} {:>12.2} {:>12.2} {:>14.2}",
            n,
            colours,
            cpu_t * 1e3,
            cpu_t * 1e9 / work,
            gpu_t * 1e3,
            gpu_t * 1e9 / work,
            empty * 1e3
        );
    }
}
