//! `Simulation.step_async`, `metrics_async` and `fit_maps_async`: a step (or the quality metrics,
//! which cost more than a step on the samples, or the fit maps) computed on a native thread that
//! never touches Python.
//!
//! Why not a Python thread calling `Simulation.step` (which releases the GIL while it solves)?
//! Inside Blender that thread still takes the GIL to enter and leave the call, and Blender with
//! Python 3.11 calls the C API without the GIL while one of its operators runs when another
//! thread holds it (`PyC_IsInterpreterActive` reads the interpreter's *global* current thread
//! state): two threads then allocate Python objects at once and Blender crashes, seen in the
//! Live window test (gdb: Blender's main thread in `PyDict_GetItemString` under
//! `bpy.ops.screen.screenshot_area`, the worker in `PyUnicode_New` building the step's
//! statistics). So the add-on's Live and modal bake keep every Python call on Blender's main
//! thread: `step_async` takes the solver out of the `Simulation` (which says busy meanwhile),
//! solves on a thread of its own, and the main thread collects the result with
//! [`Pending::finish`] once [`Pending::done`] says so, without waiting.

use std::sync::mpsc::{self, Receiver};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::engine::Solver;
use tailor_core::solver::{self as core, ColliderId, QualityMetrics, StepStats};

use crate::colliders::metrics_dict;
use crate::errors::to_py;
use crate::simulation::{stats_dict, Simulation};

/// The step's thread gets the stack a Python thread has (the solve ran there before), not
/// Rust's 2 MiB default.
const STACK_BYTES: usize = 8 << 20;

/// What runs on the thread.
pub enum Work {
    /// `frames` frames of `dt` seconds (`Simulation.step`), then, with `measure`, the metrics
    /// of the state reached (`measure: Some(collider)`): one trip to the thread for a frame.
    Step { dt: f32, frames: u32, measure: Option<Option<ColliderId>> },
    /// `Simulation.metrics(collider)`.
    Metrics(Option<ColliderId>),
    /// `Simulation.fit_maps(collider)`.
    FitMaps(Option<ColliderId>),
}

enum Done {
    Step(StepStats, Option<QualityMetrics>),
    Metrics(QualityMetrics),
    FitMaps(tailor_core::quality::fit_maps::FitMaps),
}

/// What the thread hands back: the solver (None if the work panicked: it is lost, as a panic
/// in `Simulation.step` loses it) and the result or the error, with the wall time.
struct Outcome {
    solver: Option<Solver>,
    result: Result<Done, tailor_core::TailorError>,
    /// Seconds the step's frames took (the measurement after them not included), or the
    /// measurement's.
    wall_s: f64,
}

/// A step or a measurement running on a native thread (`Simulation.step_async`,
/// `Simulation.metrics_async`). `done()` asks without waiting, `wait(timeout)` waits with the
/// GIL released, `finish()` returns what the synchronous call would have (a step's statistics
/// plus `wall_s`, and `metrics` when asked for; the metrics dict) and gives the solver back to the simulation, or raises the
/// call's error (a diverged step was rolled back, as `step`'s is). Until `finish` the
/// simulation says busy.
#[pyclass(module = "tailor")]
pub struct Pending {
    sim: Py<Simulation>,
    /// Behind a mutex only so that the object is `Sync` (pyo3 asks); the GIL serialises it.
    rx: Mutex<Receiver<Outcome>>,
    outcome: Option<Outcome>,
    finished: bool,
}

impl Pending {
    /// Moves the thread's outcome in if it arrived within `timeout` (None: no wait).
    fn receive(&mut self, py: Python<'_>, timeout: Option<Duration>) -> bool {
        if self.outcome.is_some() || self.finished {
            return true;
        }
        let got = match timeout {
            None => self.rx.lock().ok().and_then(|rx| rx.try_recv().ok()),
            Some(t) => {
                let rx = &self.rx;
                py.detach(|| rx.lock().ok().and_then(|rx| rx.recv_timeout(t).ok()))
            }
        };
        self.outcome = got;
        self.outcome.is_some()
    }
}

/// Starts `work` on a native thread, the solver taken out of `slf`.
pub fn start(slf: &Bound<'_, Simulation>, work: Work) -> PyResult<Pending> {
    let mut solver = Simulation::take_solver(slf)?;
    let (tx, rx) = mpsc::channel();
    let spawned = std::thread::Builder::new().name("tailor-solve".into()).stack_size(STACK_BYTES).spawn(move || {
        let t0 = Instant::now();
        let mut wall_s = 0.0;
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match work {
            Work::Step { dt, frames, measure } => {
                let mut last = StepStats::default();
                for _ in 0..frames.max(1) {
                    last = solver.step(dt)?;
                }
                wall_s = t0.elapsed().as_secs_f64();
                let metrics = measure.map(|collider| solver.metrics(collider)).transpose()?;
                Ok(Done::Step(last, metrics))
            }
            Work::Metrics(collider) => {
                let m = solver.metrics(collider).map(Done::Metrics);
                wall_s = t0.elapsed().as_secs_f64();
                m
            }
            Work::FitMaps(collider) => {
                let m = solver.fit_maps(collider).map(Done::FitMaps);
                wall_s = t0.elapsed().as_secs_f64();
                m
            }
        }));
        let outcome = match run {
            Ok(result) => Outcome { solver: Some(solver), result, wall_s },
            Err(payload) => Outcome {
                solver: None,
                result: Err(tailor_core::TailorError::Internal { reason: crate::errors::panic_reason(&payload) }),
                wall_s,
            },
        };
        // A receiver dropped without `finish` (the handle discarded): the solver goes with it.
        let _ = tx.send(outcome);
    });
    match spawned {
        Ok(_) => Ok(Pending { sim: slf.clone().unbind(), rx: Mutex::new(rx), outcome: None, finished: false }),
        Err(e) => Err(to_py(tailor_core::TailorError::Internal { reason: format!("no thread to solve on: {e}") })),
    }
}

#[pymethods]
impl Pending {
    /// True once the work has ended (done or failed): `finish` then returns at once.
    fn done(&mut self, py: Python<'_>) -> PyResult<bool> {
        crate::errors::guard(|| Ok(self.receive(py, None)))
    }

    /// Waits up to `timeout` seconds (None: until it ends) with the GIL released; True if the
    /// work has ended.
    #[pyo3(signature = (timeout=None))]
    fn wait(&mut self, py: Python<'_>, timeout: Option<f64>) -> PyResult<bool> {
        crate::errors::guard(|| {
            // NaN or negative: no wait; beyond what a Duration holds: until it ends.
            let t = match timeout {
                Some(s) if s.is_nan() || s <= 0.0 => Duration::ZERO,
                Some(s) => Duration::try_from_secs_f64(s).unwrap_or(Duration::MAX),
                None => Duration::MAX,
            };
            Ok(self.receive(py, Some(t)))
        })
    }

    /// What the synchronous call returns (a step's statistics with `wall_s`, the seconds it
    /// solved, and `metrics` when asked for; the metrics dict), waiting for it first if needed; the simulation is usable
    /// again afterwards. Raises the call's error (`SimulationError` for a diverged step, rolled
    /// back). Once only.
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            if self.finished {
                return Err(to_py(tailor_core::TailorError::Busy { what: "this call was already finished".into() }));
            }
            if !self.receive(py, Some(Duration::MAX)) {
                return Err(to_py(tailor_core::TailorError::Internal {
                    reason: "the solver's thread ended without a result".into(),
                }));
            }
            let outcome = self.outcome.take().expect("received above");
            self.finished = true;
            let mut adapter = None;
            if let Some(solver) = outcome.solver {
                if matches!(&outcome.result, Ok(Done::Step(s, _)) if s.backend == core::ActiveBackend::Gpu) {
                    adapter = solver.adapter();
                }
                Simulation::put_back(self.sim.bind(py), solver)?;
            }
            match outcome.result.map_err(to_py)? {
                Done::Step(stats, metrics) => {
                    let d = stats_dict(py, &stats, adapter)?;
                    d.set_item("wall_s", outcome.wall_s)?;
                    if let Some(m) = metrics {
                        d.set_item("metrics", metrics_dict(py, &m)?)?;
                    }
                    Ok(d)
                }
                Done::Metrics(m) => metrics_dict(py, &m),
                Done::FitMaps(m) => crate::simulation::fit_maps_dict(py, m),
            }
        })
    }
}
