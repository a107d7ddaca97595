//! Run time against error: how fast each method gets how close to the exact implicit step, on
//! frozen states of four scenes, and the quality of whole animations in each quality preset.
//!
//! `cargo run --release -p tailor-core --example accuracy -- [--out DIR] [--sizes 1000,10000,100000]
//! [--only steps|animations|candidates] [--frames N]` (what `make bench-error` runs, before plotting).
//!
//! **Steps** (`DIR/steps.json`, `DIR/steps.csv`): each scene is advanced with the default
//! settings to its frozen states (early, during seam closing or swinging, settled); at each, one
//! substep's problem (prediction and contacts frozen) is solved by Jacobi, coloured
//! Gauss-Seidel, Gauss-Seidel with Chebyshev, the same with the two-level step's coarse
//! correction after every sweep (`two_level`) and the reference solver
//! ([`Simulation::measure_methods`]), recording after sampled iterations the solver wall time
//! and the relative objective error, relative residual and distance to the reference.
//!
//! **Animations** (`DIR/animations.json`): each scene runs `--frames` frames (default 90, at 30
//! fps) in the presets `preview`, the default settings and `final`; per frame the step's wall
//! time, every 10th frame the quality metrics (seam gap, penetrations of the body, strain,
//! kinetic energy, self-intersections).
//!
//! Scenes: a hanging sheet (pinned at two corners), the sewn tube (seams 20 cm apart), a
//! two-layer cloth with self-collision falling on the walking body, and the GarmentCode shirt on
//! the walking body. The body scenes need the shared data (`../shared/data` or
//! `$TAILOR_SHARED_DATA`) and are skipped without it.

mod common;

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use common::*;
use serde_json::{json, Value};
use tailor_core::scenes::{hanging_sheet, sewn_tube, two_layers};
use tailor_core::solver::{
    ColliderId, Fabric, MeshColliderOptions, Method, MethodRun, MethodsMeasurement, ReferenceOptions,
    SelfCollisionSettings, Simulation, SolverSettings, StepStats,
};

const DT: f32 = 1.0 / 30.0;

/// A scene being stepped, with its body (collider, rest vertices) when it has one.
struct Runner {
    sim: Simulation,
    body: Option<(ColliderId, Vec<[f32; 3]>)>,
    frame: usize,
}

impl Runner {
    fn step(&mut self) -> StepStats {
        self.frame += 1;
        if let Some((id, rest)) = &self.body {
            self.sim.set_collider_positions(*id, &walk(rest, self.frame as f32 * DT)).unwrap();
        }
        self.sim.step(DT).unwrap()
    }

    fn advance_to(&mut self, frame: usize) {
        while self.frame < frame {
            self.step();
        }
    }

    fn metrics(&self) -> Value {
        let q = self.sim.metrics(self.body.as_ref().map(|b| b.0)).unwrap();
        json!({
            "seam_gap_m": q.seam_gap, "penetration_count": q.penetration_count,
            "penetration_max_m": q.penetration_max_depth, "strain_max": q.strain_max,
            "strain_mean": q.strain_mean, "kinetic_energy_j": q.kinetic_energy,
            "self_intersections": q.self_intersections,
        })
    }
}

/// The scenes by name at about `n` particles, in `settings`; `None` when the body is absent.
fn build(name: &str, n: usize, settings: SolverSettings) -> Option<Runner> {
    let body = || {
        let (v, t) = mean_body()?;
        Some((v, t))
    };
    let with_body = |mut sim: Simulation, self_on: bool| {
        let (v, t) = body()?;
        let id = sim.add_mesh_collider(&walk(&v, 0.0), &t, MeshColliderOptions::default()).unwrap();
        sim.set_self_collision(SelfCollisionSettings { enabled: self_on, ..Default::default() }).unwrap();
        Some(Runner { sim, body: Some((id, v)), frame: 0 })
    };
    match name {
        "sheet" => {
            let (mesh, pins) = hanging_sheet(n, 1.0, 1.0).unwrap();
            let mut sim = Simulation::new(mesh, Fabric::default(), settings).unwrap();
            sim.pin(&pins, None).unwrap();
            Some(Runner { sim, body: None, frame: 0 })
        }
        "tube" => {
            let edge = 0.01;
            let side = ((n as f32 / 2.0).sqrt() - 1.0) * edge;
            let tube = sewn_tube(side, side, edge, 0.2, 0.0, 1000.0).unwrap();
            let mut sim = Simulation::new(tube.mesh, Fabric::default(), settings).unwrap();
            for s in tube.seams {
                sim.add_seam(s).unwrap();
            }
            Some(Runner { sim, body: None, frame: 0 })
        }
        "layers-body" => {
            let (v, _) = body()?;
            let (lo, hi) = bounds(&v);
            // Centred over the shoulders, 20 cm below the top of the head, Y up.
            let centre = [0.5 * (lo[0] + hi[0]), hi[1] - 0.2, 0.5 * (lo[2] + hi[2])];
            let cells = ((n as f32 / 2.0).sqrt() - 1.0).round() as usize;
            let mesh = two_layers(centre, [0.0, 1.0, 0.0], 0.7, cells, 0.03).unwrap();
            let sim =
                Simulation::new(mesh, Fabric::default(), SolverSettings { gravity: GRAVITY_Y, ..settings }).unwrap();
            with_body(sim, true)
        }
        "shirt-walk" => {
            body()?;
            with_body(shirt(shirt_edge(n), settings), false)
        }
        "shirt-walk-self" => {
            body()?;
            with_body(shirt(shirt_edge(n), settings), true)
        }
        _ => unreachable!("{name}"),
    }
}

/// Frozen states of each scene: (label, frame).
fn states(scene: &str, n: usize) -> Vec<(&'static str, usize)> {
    let big = n > 50_000;
    match scene {
        "sheet" if big => vec![("early", 1)],
        "sheet" => vec![("early", 1), ("swinging", 10), ("settled", 90)],
        "tube" if big => vec![("closing", 6)],
        "tube" => vec![("early", 1), ("closing", 6), ("settled", 60)],
        "layers-body" => vec![("early", 1), ("landing", 10), ("settled", 60)],
        _ => vec![("early", 1), ("closing", 10), ("settled", 60)],
    }
}

/// Iterations of each method per size, and of the reference: the reference is the slow part
/// (a direct solve per iteration, hundreds to thousands of iterations), so it is capped and its
/// own residual is reported beside the figures.
fn budgets(n: usize) -> ([MethodRun; 4], ReferenceOptions) {
    let (j, c, r) = if n < 5_000 {
        (8000, 2000, 5000)
    } else if n < 50_000 {
        (2000, 800, 400)
    } else {
        (300, 200, 150)
    };
    let run = |method, iterations, two_level| MethodRun { method, iterations, two_level };
    let methods = [
        run(Method::Jacobi, j, false),
        run(Method::GaussSeidel, j, false),
        run(Method::Chebyshev, c, false),
        run(Method::Chebyshev, c, true),
    ];
    (methods, ReferenceOptions { max_iterations: r, ..Default::default() })
}

/// Iterations kept: the first 10, then 20 per decade.
fn keep(k: u32) -> bool {
    k <= 10 || ((k as f64).log10() * 20.0).floor() != (((k - 1) as f64).log10() * 20.0).floor()
}

fn method_name(m: Method, two_level: bool) -> &'static str {
    match (m, two_level) {
        (_, true) => "two_level",
        (Method::Jacobi, _) => "jacobi",
        (Method::GaussSeidel, _) => "gauss_seidel",
        (Method::Chebyshev, _) => "chebyshev",
    }
}

fn records_json(records: &[tailor_core::solver::IterationRecord]) -> Value {
    Value::Array(
        records
            .iter()
            .map(|r| {
                let m = r.measures;
                json!([r.iteration, r.seconds, m.objective_rel, m.residual_rel, m.distance_rel, m.distance_max])
            })
            .collect(),
    )
}

fn steps(sizes: &[usize], csv: &mut impl Write) -> Vec<Value> {
    let mut out = Vec::new();
    writeln!(
        csv,
        "scene,particles,state,frame,method,iteration,seconds,objective_rel,residual_rel,distance_rel,distance_max_m"
    )
    .unwrap();
    let scenes: Vec<(&str, usize)> = sizes
        .iter()
        .flat_map(|&n| {
            let mut v = vec![("sheet", n), ("tube", n)];
            if n <= 10_000 {
                v.push(("shirt-walk", n));
            }
            if n == 10_000 {
                v.push(("layers-body", n));
            }
            v
        })
        .collect();
    for (scene, n) in scenes {
        let Some(mut run) = build(scene, n, SolverSettings::default()) else {
            println!("{scene}: the shared body is absent: skipped");
            continue;
        };
        let particles = run.sim.num_particles();
        let (methods, ro) = budgets(particles);
        for (state, frame) in states(scene, particles) {
            let t0 = Instant::now();
            run.advance_to(frame);
            let advance = t0.elapsed().as_secs_f64();
            let t1 = Instant::now();
            let m: MethodsMeasurement = run.sim.measure_methods(DT, &methods, ro, &keep).unwrap();
            let gap = run.sim.seam_gaps().0;
            let r = m.reference;
            println!(
                "{scene:>12} {particles:>6} {state:>9} (frame {frame:>3}, seam gap {:6.1} mm): reference {} its, \
                 {:.2} s, last change {:.1e} m, gradient {:.1e}; measured in {:.1} s (advance {:.1} s)",
                gap * 1e3,
                r.iterations,
                r.seconds,
                r.last_change,
                r.gradient_rel,
                t1.elapsed().as_secs_f64(),
                advance
            );
            let mut runs = vec![("reference", &m.reference_records)];
            for s in &m.methods {
                runs.push((method_name(s.method, s.two_level), &s.records));
            }
            for (name, recs) in &runs {
                for rec in recs.iter() {
                    let e = rec.measures;
                    writeln!(
                        csv,
                        "{scene},{particles},{state},{frame},{name},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
                        rec.iteration, rec.seconds, e.objective_rel, e.residual_rel, e.distance_rel, e.distance_max
                    )
                    .unwrap();
                }
                let last = recs.last().unwrap();
                println!(
                    "    {name:>12}: {:>5} its {:8.4} s -> objective {:.1e} residual {:.1e} distance {:.1e} ({:.2e} m)",
                    last.iteration,
                    last.seconds,
                    last.measures.objective_rel,
                    last.measures.residual_rel,
                    last.measures.distance_rel,
                    last.measures.distance_max
                );
            }
            out.push(json!({
                "scene": scene, "particles": particles, "state": state, "frame": frame, "seam_gap_m": gap,
                "reference": {"iterations": r.iterations, "seconds": r.seconds, "last_change_m": r.last_change,
                              "gradient_rel": r.gradient_rel, "envelope": r.envelope},
                "columns": ["iteration", "seconds", "objective_rel", "residual_rel", "distance_rel", "distance_max_m"],
                "runs": runs.iter().map(|(name, recs)| json!({"method": name, "records": records_json(recs)})).collect::<Vec<_>>(),
            }));
        }
    }
    out
}

fn preset(name: &str) -> SolverSettings {
    match name {
        "default" => SolverSettings::default(),
        p => SolverSettings::preset(p).unwrap(),
    }
}

fn animations(frames: usize) -> Vec<Value> {
    let mut out = Vec::new();
    for (scene, n) in [("tube", 10_000), ("shirt-walk", 1_000), ("shirt-walk-self", 10_000)] {
        for p in ["preview", "default", "final"] {
            let Some(mut run) = build(scene, n, preset(p)) else {
                println!("{scene}: the shared body is absent: skipped");
                break;
            };
            let mut ms = Vec::with_capacity(frames);
            let mut its = 0u64;
            let mut metrics = Vec::new();
            for f in 1..=frames {
                let t0 = Instant::now();
                let s = run.step();
                ms.push(t0.elapsed().as_secs_f64() * 1e3);
                its += s.iterations as u64;
                if f % 10 == 0 || f == frames {
                    let mut m = run.metrics();
                    m["frame"] = json!(f);
                    metrics.push(m);
                }
            }
            let last = metrics.last().unwrap().clone();
            let settled: Vec<&Value> =
                metrics.iter().filter(|m| m["frame"].as_u64().unwrap() as usize > frames / 2).collect();
            let max_of = |k: &str| settled.iter().map(|m| m[k].as_f64().unwrap()).fold(0.0f64, f64::max);
            let s = preset(p);
            let row = json!({
                "scene": scene, "particles": run.sim.num_particles(), "preset": p,
                "substeps": s.substeps, "iterations": s.iterations, "tolerance": s.tolerance,
                "frames": frames, "ms_median": median(&ms), "ms_mean": ms.iter().sum::<f64>() / frames as f64,
                "iterations_per_substep": its as f64 / (frames as f64 * s.substeps as f64),
                "seam_gap_max_second_half_m": max_of("seam_gap_m"),
                "penetration_count_max_second_half": max_of("penetration_count"),
                "penetration_max_second_half_m": max_of("penetration_max_m"),
                "strain_max_second_half": max_of("strain_max"),
                "last": last, "samples": metrics, "ms": ms,
            });
            println!(
                "{scene:>15} {:>6} {p:>8}: {:7.1} ms/frame median ({:5.1} fps), {:4.1} it/substep | 2nd half: seam gap \
                 {:6.2} mm, penetrations {} (max {:.2} mm), strain max {:.3} | last: KE {:.2e} J, strain mean {:.4}, \
                 self-intersections {}",
                row["particles"],
                row["ms_median"].as_f64().unwrap(),
                1e3 / row["ms_median"].as_f64().unwrap(),
                row["iterations_per_substep"].as_f64().unwrap(),
                row["seam_gap_max_second_half_m"].as_f64().unwrap() * 1e3,
                row["penetration_count_max_second_half"],
                row["penetration_max_second_half_m"].as_f64().unwrap() * 1e3,
                row["strain_max_second_half"].as_f64().unwrap(),
                last["kinetic_energy_j"].as_f64().unwrap(),
                last["strain_mean"].as_f64().unwrap(),
                last["self_intersections"],
            );
            out.push(row);
        }
    }
    out
}

/// The preset candidates on the shirt walking (1k particles, 60 frames): the sweep the presets
/// were chosen from (`--only candidates`).
fn candidates() -> Vec<Value> {
    let mut out = Vec::new();
    for (s, i, tol) in [
        (2u32, 10u32, 1e-2f32),
        (3, 10, 1e-2),
        (4, 10, 1e-2),
        (3, 15, 1e-2),
        (4, 20, 0.0),
        (6, 30, 1e-4),
        (8, 15, 1e-4),
        (8, 20, 1e-4),
    ] {
        let settings = SolverSettings { substeps: s, iterations: i, tolerance: tol, ..Default::default() };
        let Some(mut run) = build("shirt-walk", 1_000, settings) else {
            println!("shirt-walk: the shared body is absent: skipped");
            break;
        };
        let (mut pen, mut depth, mut strain, mut gap) = (0u64, 0.0f64, 0.0f64, 0.0f64);
        let mut ms = Vec::new();
        for f in 1..=60 {
            let t0 = Instant::now();
            run.step();
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
            if f > 30 && f % 5 == 0 {
                let q = run.metrics();
                pen = pen.max(q["penetration_count"].as_u64().unwrap());
                depth = depth.max(q["penetration_max_m"].as_f64().unwrap());
                strain = strain.max(q["strain_max"].as_f64().unwrap());
                gap = gap.max(q["seam_gap_m"].as_f64().unwrap());
            }
        }
        println!(
            "{s} x {i}, tolerance {tol:e}: {:.1} ms/frame median | frames 31-60: seam gap {:.2} mm, penetrations \
             {pen} ({:.1} mm), strain max {strain:.3}",
            median(&ms),
            gap * 1e3,
            depth * 1e3
        );
        out.push(json!({"substeps": s, "iterations": i, "tolerance": tol, "ms_median": median(&ms),
            "seam_gap_max_m": gap, "penetration_count_max": pen, "penetration_max_m": depth, "strain_max": strain}));
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let opt = |k: &str| args.iter().position(|a| a == k).and_then(|i| args.get(i + 1)).cloned();
    let out = PathBuf::from(opt("--out").unwrap_or_else(|| "out/bench".into()));
    let sizes: Vec<usize> = opt("--sizes")
        .unwrap_or_else(|| "1000,10000,100000".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let only = opt("--only").unwrap_or_default();
    let frames: usize = opt("--frames").and_then(|s| s.parse().ok()).unwrap_or(90);
    std::fs::create_dir_all(&out).unwrap();
    let start = Instant::now();
    let header = json!({
        "machine": machine(),
        "command": args.join(" "),
        "date_utc": std::process::Command::new("date").args(["-u", "+%Y-%m-%d %H:%M"]).output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string()).unwrap_or_default(),
    });
    println!("{}", header["machine"]);
    if only.is_empty() || only == "steps" {
        let mut csv = std::io::BufWriter::new(std::fs::File::create(out.join("steps.csv")).unwrap());
        let s = steps(&sizes, &mut csv);
        let doc = json!({"header": header, "machine_after": machine(), "steps": s});
        std::fs::write(out.join("steps.json"), serde_json::to_string(&doc).unwrap()).unwrap();
    }
    if only == "candidates" {
        let c = candidates();
        let doc = json!({"header": header, "machine_after": machine(), "candidates": c});
        std::fs::write(out.join("candidates.json"), serde_json::to_string(&doc).unwrap()).unwrap();
    }
    if only.is_empty() || only == "animations" {
        let a = animations(frames);
        let doc = json!({"header": header, "machine_after": machine(), "animations": a});
        std::fs::write(out.join("animations.json"), serde_json::to_string(&doc).unwrap()).unwrap();
    }
    println!("done in {:.0} s; {}", start.elapsed().as_secs_f64(), machine());
}
