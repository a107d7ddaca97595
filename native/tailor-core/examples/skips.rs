//! What each of the scene's skips saves, and that it changes nothing visible: every
//! comparison runs the same scene twice, with the skip and without, stepping the two
//! simulations alternately frame by frame (so both see the same machine load), and reports
//! the median step time of each, the largest distance between their particles, and their
//! quality metrics at the end.
//!
//! `cargo run --release -p tailor-core --example skips -- [--only NAME]`
//!
//! Skips: sleeping at rest (`solver/sleep.rs`), early termination at the tolerance, keeping
//! the matrix and colouring while the topology does not change, keeping a still collider's
//! hash, culling collider triangles far from the cloth, the iterations' broad phase against
//! mesh colliders (`collide/mesh_broad_phase.rs`). The body scenes need the shared data
//! and are skipped without it.

mod common;

use std::time::Instant;

use common::*;
use tailor_core::scenes::{box_mesh, hanging_sheet, sewn_tube_of};
use tailor_core::solver::{
    ColliderId, CollisionSkips, Fabric, MeshColliderOptions, QualityMetrics, Simulation, SolverSettings,
};

const DT: f32 = 1.0 / 30.0;

/// A simulation and the collider it drives (rest positions, moving or not).
struct Run {
    sim: Simulation,
    body: Option<(ColliderId, Vec<[f32; 3]>, bool)>,
    ms: Vec<f64>,
    iterations: u64,
    asleep: u32,
}

impl Run {
    fn new(sim: Simulation) -> Self {
        Self { sim, body: None, ms: Vec::new(), iterations: 0, asleep: 0 }
    }

    fn step(&mut self, f: usize, measured: bool) {
        if let Some((id, rest, true)) = &self.body {
            self.sim.set_collider_positions(*id, &walk(rest, (f + 1) as f32 * DT)).unwrap();
        }
        let t0 = Instant::now();
        let s = self.sim.step(DT).unwrap();
        if measured {
            self.ms.push(t0.elapsed().as_secs_f64() * 1e3);
            self.iterations += s.iterations as u64;
            self.asleep += s.asleep as u32;
        }
    }

    fn metrics(&self) -> QualityMetrics {
        self.sim.metrics(self.body.as_ref().map(|b| b.0)).unwrap()
    }
}

fn max_distance(a: &Simulation, b: &Simulation) -> f32 {
    let (p, q) = (a.positions().to_aos(), b.positions().to_aos());
    p.iter()
        .zip(&q)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
        .fold(0.0, f32::max)
}

/// Steps `with` and `without` alternately for `frames` frames, measuring from `from` on, and
/// prints one comparison row.
fn compare(name: &str, mut with: Run, mut without: Run, frames: usize, from: usize) {
    for f in 0..frames {
        // Alternate which goes first, so neither always runs on a warm cache.
        if f % 2 == 0 {
            with.step(f, f >= from);
            without.step(f, f >= from);
        } else {
            without.step(f, f >= from);
            with.step(f, f >= from);
        }
    }
    let (a, b) = (median(&with.ms), median(&without.ms));
    let (qa, qb) = (with.metrics(), without.metrics());
    let n = (frames - from) as f64;
    println!(
        "| {name} | {} | {frames} (from {from}) | {a:.2} | {b:.2} | {:.2} | {:.1} / {:.1} | {:.2e} | {:.2} / {:.2} | {} ({:.1}) / {} ({:.1}) | {:.3} / {:.3} | {} |",
        with.sim.num_particles(),
        b / a,
        with.iterations as f64 / n,
        without.iterations as f64 / n,
        max_distance(&with.sim, &without.sim),
        qa.seam_gap * 1e3,
        qb.seam_gap * 1e3,
        qa.penetration_count,
        qa.penetration_max_depth * 1e3,
        qb.penetration_count,
        qb.penetration_max_depth * 1e3,
        qa.strain_max,
        qb.strain_max,
        with.asleep,
    );
}

/// A sheet of about `n` particles dropped from 2 cm onto a table (a box mesh collider).
fn on_table(n: usize, settings: SolverSettings) -> Run {
    let (mesh, _) = hanging_sheet(n, 1.0, 0.02).unwrap();
    let mut sim = Simulation::new(mesh, Fabric::default(), settings).unwrap();
    let (v, t) = box_mesh([-0.8, -0.8, -0.1], [0.8, 0.8, 0.0]);
    let id = sim.add_mesh_collider(&v, &t, MeshColliderOptions::default()).unwrap();
    sim.set_collider_friction(id, 0.8, 0.6).unwrap();
    let mut r = Run::new(sim);
    r.body = Some((id, v, false));
    r
}

/// The GarmentCode shirt on the mean body, walking or still.
fn shirt_on_body(n: usize, moving: bool, settings: SolverSettings) -> Option<Run> {
    let (v, t) = mean_body()?;
    let mut sim = shirt(shirt_edge(n), settings);
    let id = sim.add_mesh_collider(&walk(&v, 0.0), &t, MeshColliderOptions::default()).unwrap();
    let mut r = Run::new(sim);
    r.body = Some((id, v, moving));
    Some(r)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let only = args.iter().position(|a| a == "--only").and_then(|i| args.get(i + 1)).cloned().unwrap_or_default();
    let run = |name: &str| name.contains(only.as_str());
    println!("{}", machine());
    println!(
        "| skip | particles | frames | ms/frame with | ms/frame without | speed-up | it/frame with / without | \
         max distance, m | seam gap, mm | penetrations (deepest, mm) | strain max | frames asleep |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let d = SolverSettings::default;
    let no_sleep = |mut r: Run| {
        r.sim.set_sleeping(false);
        r
    };
    if run("sleep: sheet on a table") {
        compare("sleep: sheet on a table", on_table(10_000, d()), no_sleep(on_table(10_000, d())), 120, 60);
    }
    if run("sleep: shirt on the still body") {
        if let (Some(a), Some(b)) = (shirt_on_body(1_000, false, d()), shirt_on_body(1_000, false, d())) {
            compare("sleep: shirt on the still body", a, no_sleep(b), 240, 120);
        }
    }
    let tol = |t: f32| SolverSettings { tolerance: t, ..d() };
    if run("early stop 1e-2: sheet on a table") {
        compare(
            "early stop 1e-2: sheet on a table",
            no_sleep(on_table(10_000, tol(1e-2))),
            no_sleep(on_table(10_000, d())),
            90,
            0,
        );
    }
    if run("early stop 1e-2: shirt, walking body") {
        if let (Some(a), Some(b)) = (shirt_on_body(1_000, true, tol(1e-2)), shirt_on_body(1_000, true, d())) {
            compare("early stop 1e-2: shirt, walking body", a, b, 90, 0);
        }
    }
    if run("matrix and colouring kept: tube") {
        // Without: pin and unpin a particle before every frame, which marks the topology dirty
        // and rebuilds the matrix, colouring and Chebyshev's ρ for the same topology.
        let tube = |n| {
            let t = sewn_tube_of(n, 0.01).unwrap();
            let mut sim = Simulation::new(t.mesh, Fabric::default(), d()).unwrap();
            for s in t.seams {
                sim.add_seam(s).unwrap();
            }
            sim
        };
        let mut forced = Run::new(tube(10_000));
        let kept = Run::new(tube(10_000));
        let mut frames = 0;
        let rebuild = |r: &mut Run| {
            r.sim.pin(&[0], None).unwrap();
            r.sim.unpin(&[0]).unwrap();
        };
        // The comparison steps both; the forced one is dirtied before each of its frames.
        let mut with = kept;
        for f in 0..40 {
            rebuild(&mut forced);
            let m = f >= 10;
            if f % 2 == 0 {
                with.step(f, m);
                forced.step(f, m);
            } else {
                forced.step(f, m);
                with.step(f, m);
            }
            frames += 1;
        }
        let (a, b) = (median(&with.ms), median(&forced.ms));
        println!(
            "| matrix and colouring kept: tube | {} | {frames} (from 10) | {a:.2} | {b:.2} | {:.2} | 80 / 80 | {:.2e} | \
             {:.2} / {:.2} | | {:.3} / {:.3} | 0 |",
            with.sim.num_particles(),
            b / a,
            max_distance(&with.sim, &forced.sim),
            with.metrics().seam_gap * 1e3,
            forced.metrics().seam_gap * 1e3,
            with.metrics().strain_max,
            forced.metrics().strain_max
        );
    }
    for (name, moving, skips) in [
        (
            "still collider's hash kept: shirt, still body",
            false,
            CollisionSkips { reuse_collider_hashes: false, ..Default::default() },
        ),
        (
            "far triangles culled: shirt, walking body",
            true,
            CollisionSkips { cull_far_triangles: false, ..Default::default() },
        ),
        (
            "mesh broad phase: shirt, walking body",
            true,
            CollisionSkips { mesh_broad_phase: false, ..Default::default() },
        ),
    ] {
        if !run(name) {
            continue;
        }
        if let (Some(a), Some(mut b)) = (shirt_on_body(10_000, moving, d()), shirt_on_body(10_000, moving, d())) {
            b.sim.set_collision_skips(skips);
            compare(name, a, b, 20, 5);
        }
    }
    println!("{}", machine());
}
