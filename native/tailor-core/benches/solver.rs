//! Solver benchmark: the cost of a step of the CPU solver for garments of about 1k, 10k and
//! 100k particles, on one thread and on all threads.
//!
//! Scene: `scenes::sewn_tube` with a fixed edge of 1 cm (`--edge`) and square panels sized so
//! that the two panels together have close to the requested particle count; panels start 2 cm
//! apart and hang free under gravity (no colliders). Settings: `SolverSettings::default()`,
//! 30 fps (`dt = 1/30 s`). After a warm-up (the colouring is built and the seams close), the
//! measured steps alternate between the thread pools, so that every thread count sees the same
//! machine load; every figure is the median over the measured steps.
//!
//! Figures per (size, threads):
//! * `ns/p-it`: (local + global time of a step) / (particles × iterations of the step);
//! * `ms/sub`: all four stages of a step / substeps; `ms/frame`: wall time of `step(1/30)`;
//! * `cpu-ms/fr`: CPU time of all the process's threads during that step (Linux only): on a
//!   shared machine, wall time includes time the cores ran other processes, this does not
//!   (it does include rayon workers spinning while they wait);
//! * the stage split per substep (prediction, local, global, damping), ms;
//! * colours of the particle graph; `B/p`: `Simulation::memory_bytes()` / particles.
//!
//! Usage: `cargo bench -p tailor-core --bench solver -- [--sizes 1000,10000,100000]
//! [--threads 1,2] [--steps N] [--warmup N] [--edge M]`. Unknown flags (such as `--bench`,
//! which cargo passes) are ignored. The last line printed is one JSON object with everything.

use std::time::Instant;

use tailor_core::scenes::sewn_tube;
use tailor_core::solver::{Fabric, Simulation, SolverSettings, Stage, StepStats};

struct Args {
    sizes: Vec<usize>,
    threads: Vec<usize>,
    /// Measured steps; `None` = 20, or 6 from 50k particles up.
    steps: Option<usize>,
    /// Warm-up frames; `None` = 15, or 8 from 50k particles up.
    warmup: Option<usize>,
    edge: f32,
}

fn parse_list(s: &str) -> Vec<usize> {
    s.split(',').filter_map(|t| t.trim().parse().ok()).collect()
}

fn parse_args() -> Args {
    let all = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let mut a = Args {
        sizes: vec![1_000, 10_000, 100_000],
        threads: if all > 1 { vec![1, all] } else { vec![1] },
        steps: None,
        warmup: None,
        edge: 0.01,
    };
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < argv.len() {
        let next = argv.get(i + 1).map(String::as_str).unwrap_or("");
        let used = match argv[i].as_str() {
            "--sizes" => {
                a.sizes = parse_list(next);
                true
            }
            "--threads" => {
                a.threads = parse_list(next);
                true
            }
            "--steps" => {
                a.steps = next.parse().ok();
                true
            }
            "--warmup" => {
                a.warmup = next.parse().ok();
                true
            }
            "--edge" => {
                a.edge = next.parse().unwrap_or(a.edge);
                true
            }
            _ => false, // `--bench` and anything else: ignored
        };
        i += if used { 2 } else { 1 };
    }
    a
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// CPU time consumed so far by all threads of this process, seconds (Linux
/// `/proc/self/task/*/schedstat`; 0 elsewhere). On a loaded machine this is the figure that
/// does not count the time other processes had the cores.
fn process_cpu_seconds() -> f64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else { return 0.0 };
    let mut ns = 0u64;
    for e in dir.flatten() {
        if let Ok(s) = std::fs::read_to_string(e.path().join("schedstat")) {
            ns += s.split_whitespace().next().and_then(|v| v.parse::<u64>().ok()).unwrap_or(0);
        }
    }
    ns as f64 * 1e-9
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// A sewn tube of about `target` particles at edge `edge`: two square panels of
/// `(nx+1)²` vertices each, `nx = round(√(target/2)) − 1`.
fn build(target: usize, edge: f32) -> Simulation {
    let nx = (((target as f64 / 2.0).sqrt().round() as usize).max(3)) - 1;
    let side = nx as f32 * edge;
    let tube = sewn_tube(side, side, edge, 0.02, 0.0, 2000.0).expect("tube");
    let mut sim = Simulation::new(tube.mesh, Fabric::default(), SolverSettings::default()).expect("simulation");
    for s in tube.seams {
        sim.add_seam(s).expect("seam");
    }
    sim
}

/// Per-step samples of one (size, threads) configuration.
#[derive(Default)]
struct Samples {
    ns_per_pit: Vec<f64>,
    ms_substep: Vec<f64>,
    ms_frame: Vec<f64>,
    cpu_ms_frame: Vec<f64>,
    pred: Vec<f64>,
    local: Vec<f64>,
    global: Vec<f64>,
    damping: Vec<f64>,
    iterations: Vec<f64>,
}

impl Samples {
    fn push(&mut self, st: &StepStats, wall: f64, cpu: f64, n: usize) {
        let t = &st.timings;
        let sub = st.substeps as f64;
        self.ns_per_pit.push((t[Stage::Local] + t[Stage::Global]) * 1e9 / (n as f64 * st.iterations as f64));
        self.ms_substep.push(t.total() * 1e3 / sub);
        self.ms_frame.push(wall * 1e3);
        self.cpu_ms_frame.push(cpu * 1e3);
        self.pred.push(t[Stage::Prediction] * 1e3 / sub);
        self.local.push(t[Stage::Local] * 1e3 / sub);
        self.global.push(t[Stage::Global] * 1e3 / sub);
        self.damping.push(t[Stage::Damping] * 1e3 / sub);
        self.iterations.push(st.iterations as f64);
    }
}

fn main() {
    let args = parse_args();
    let dt = 1.0 / 30.0;
    let model = cpu_model();
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let pools: Vec<(usize, rayon::ThreadPool)> = args
        .threads
        .iter()
        .map(|&k| (k, rayon::ThreadPoolBuilder::new().num_threads(k).build().expect("thread pool")))
        .collect();
    let s = SolverSettings::default();
    println!(
        "solver benchmark: {model}, {cores} logical CPUs; sewn tube, edge {} m; {} substeps x {} iterations, \
         {:?}, dt 1/30 s",
        args.edge, s.substeps, s.iterations, s.method
    );
    println!(
        "{:>8} {:>3} {:>8} {:>8} {:>9} {:>9} {:>7} {:>7} {:>7} {:>7} {:>4} {:>6} {:>6}",
        "parts",
        "thr",
        "ns/p-it",
        "ms/sub",
        "ms/frame",
        "cpu-ms/fr",
        "pred",
        "local",
        "global",
        "damp",
        "col",
        "B/p",
        "closed"
    );
    let mut json_rows = Vec::new();
    for &target in &args.sizes {
        let big = target >= 50_000;
        let steps = args.steps.unwrap_or(if big { 6 } else { 20 });
        let warmup = args.warmup.unwrap_or(if big { 8 } else { 15 });
        let mut sim = build(target, args.edge);
        let n = sim.num_particles();
        let mut last = None;
        for _ in 0..warmup {
            last = Some(pools.last().unwrap().1.install(|| sim.step(dt)).expect("warm-up step"));
        }
        let mut samples: Vec<Samples> = pools.iter().map(|_| Samples::default()).collect();
        for _ in 0..steps {
            for ((_, pool), smp) in pools.iter().zip(samples.iter_mut()) {
                let (c0, t0) = (process_cpu_seconds(), Instant::now());
                let st = pool.install(|| sim.step(dt)).expect("step");
                let wall = t0.elapsed().as_secs_f64();
                smp.push(&st, wall, process_cpu_seconds() - c0, n);
                last = Some(st);
            }
        }
        let last = last.expect("at least one step");
        let bytes = sim.memory_bytes();
        for ((k, _), smp) in pools.iter().zip(samples) {
            let m = |v: &Vec<f64>| median(v.clone());
            let row = (
                m(&smp.ns_per_pit),
                m(&smp.ms_substep),
                m(&smp.ms_frame),
                m(&smp.pred),
                m(&smp.local),
                m(&smp.global),
                m(&smp.damping),
                m(&smp.cpu_ms_frame),
            );
            println!(
                "{:>8} {:>3} {:>8.1} {:>8.3} {:>9.2} {:>9.2} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>4} {:>6.0} {:>6.2}",
                n,
                k,
                row.0,
                row.1,
                row.2,
                row.7,
                row.3,
                row.4,
                row.5,
                row.6,
                last.colours,
                bytes as f64 / n as f64,
                last.seam_closed_fraction
            );
            json_rows.push(serde_json::json!({
                "particles": n,
                "threads": k,
                "steps": steps,
                "warmup": warmup,
                "ns_per_particle_iteration": row.0,
                "ms_per_substep": row.1,
                "ms_per_frame": row.2,
                "cpu_ms_per_frame": row.7,
                "ms_prediction": row.3,
                "ms_local": row.4,
                "ms_global": row.5,
                "ms_damping": row.6,
                "iterations_per_step": m(&smp.iterations),
                "colours": last.colours,
                "memory_bytes": bytes,
                "bytes_per_particle": bytes as f64 / n as f64,
                "seam_closed_fraction": last.seam_closed_fraction,
            }));
        }
    }
    let out = serde_json::json!({
        "bench": "solver",
        "cpu": model,
        "logical_cpus": cores,
        "edge_m": args.edge,
        "substeps": s.substeps,
        "iterations": s.iterations,
        "dt": dt,
        "results": json_rows,
    });
    println!("{out}");
}
