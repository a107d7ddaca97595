//! Scenes shared by the benchmark examples (`accuracy`, `stress`): the shared sample body
//! with a procedural walk, and the GarmentCode shirt sized to it. Everything here is Y-up,
//! like the body file and the shirt's placements; the procedural scenes of
//! `tailor_core::scenes` are Z-up.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::{Quat, Vec3};
use tailor_core::garment::{build_simulation, read_garment, BuildOptions};
use tailor_core::io::obj::read_obj;
use tailor_core::pattern::ReadOptions;
use tailor_core::solver::{Fabric, Simulation, SolverSettings};
use tailor_core::triangulate::TriangulateOptions;

/// Gravity of the Y-up scenes.
pub const GRAVITY_Y: [f32; 3] = [0.0, -9.81, 0.0];

/// The repository's `shared/data` (beside the checkout), or `$TAILOR_SHARED_DATA`.
pub fn shared_data() -> PathBuf {
    std::env::var_os("TAILOR_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"))
}

/// The GarmentCode mean body (Y-up, 47 500 triangles), or `None` when the shared data is absent.
pub fn mean_body() -> Option<(Vec<[f32; 3]>, Vec<[u32; 3]>)> {
    let obj = read_obj(shared_data().join("bodies/garmentcode-mean-all/mean_all.obj")).ok()?;
    Some((obj.positions, obj.triangles))
}

/// A procedural in-place walk (a treadmill) of a rigid body at time `t`: the vertical bob of
/// the steps (2.5 cm at 2 Hz), the sway of the hips (2 cm sideways at 1 Hz) and the turn of
/// the torso (±6° about the vertical at 1 Hz), about the body's vertical axis through `pivot`.
pub fn walk_pose(t: f32, pivot: Vec3) -> impl Fn(&[f32; 3]) -> [f32; 3] {
    use std::f32::consts::TAU;
    let q = Quat::from_rotation_y(0.105 * (TAU * t).sin());
    let offset = Vec3::new(0.02 * (TAU * t).sin(), 0.025 * (2.0 * TAU * t).sin().abs(), 0.0);
    move |p| (q * (Vec3::from(*p) - pivot) + pivot + offset).into()
}

/// The body's vertices posed by [`walk_pose`] at time `t`.
pub fn walk(body: &[[f32; 3]], t: f32) -> Vec<[f32; 3]> {
    let (lo, hi) = bounds(body);
    let pivot = Vec3::new(0.5 * (lo[0] + hi[0]), 0.0, 0.5 * (lo[2] + hi[2]));
    let f = walk_pose(t, pivot);
    body.iter().map(f).collect()
}

pub fn bounds(p: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for q in p {
        for d in 0..3 {
            lo[d] = lo[d].min(q[d]);
            hi[d] = hi[d].max(q[d]);
        }
    }
    (lo, hi)
}

/// The GarmentCode shirt of the test data, meshed at `edge` metres and sewn, in its placement
/// around the mean body (Y-up, 4 mm thickness).
pub fn shirt(edge: f64, settings: SolverSettings) -> Simulation {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/garmentcode/shirt_mean_specification.json");
    let (_, garment, _) = read_garment(&path, &ReadOptions::default(), &TriangulateOptions::new(edge)).unwrap();
    let settings = SolverSettings { gravity: GRAVITY_Y, ..settings };
    let (mut sim, _) = build_simulation(&garment, Fabric::default(), settings, &BuildOptions::default()).unwrap();
    sim.set_thickness(0.004).unwrap();
    sim
}

/// Shirt edge length for about `particles` particles (1 027 at 3 cm).
pub fn shirt_edge(particles: usize) -> f64 {
    0.03 * (1027.0 / particles as f64).sqrt()
}

/// Median of `v` (NaN when empty).
pub fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    s[s.len() / 2]
}

/// `uptime`'s load averages and the CPU model, for the reports.
pub fn machine() -> String {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_default();
    format!(
        "{} × {cpu}, {} rayon threads, load average {}",
        std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
        rayon::current_num_threads(),
        load.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    )
}
