//! Error measures of a step: how far an iterate is from the exact solution of the implicit
//! step, as a function of iterations and wall time.
//!
//! For iterate `xₖ`, initial guess `x₀` (the inertial prediction) and reference `x*`:
//!
//! * relative objective error `(E(xₖ) − E(x*)) / (E(x₀) − E(x*))`;
//! * relative residual `‖∇E(xₖ)‖ / ‖∇E(x₀)‖`;
//! * distance to the reference `‖xₖ − x*‖ / ‖x₀ − x*‖`, and its largest particle distance in
//!   metres.
//!
//! [`Simulation::measure_step`] freezes one substep's problem (prediction and contacts), solves
//! it with the reference solver, then runs the chosen method iteration by iteration, timing only
//! the iterations, and restores the simulation afterwards: measuring changes nothing. A method
//! may run with the two-level step's coarse correction after every sweep ([`MethodRun`]), as
//! `SolverSettings::two_level` runs it.

use std::time::Instant;

use crate::error::{Result, TailorError};
use crate::solver::accuracy::reference::ReferenceInfo;
use crate::solver::model::settings::Method;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::simulation::Simulation;
use crate::solver::stages::coarse::CoarseLevel;
use crate::solver::stages::StageTimings;

/// The three error measures of one iterate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorMeasures {
    pub objective_rel: f64,
    pub residual_rel: f64,
    pub distance_rel: f64,
    /// Largest distance of a particle to the reference, metres.
    pub distance_max: f64,
}

/// Measures after one iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// 1-based iteration count.
    pub iteration: u32,
    /// Solver wall time up to and including this iteration, seconds (measuring excluded).
    pub seconds: f64,
    pub measures: ErrorMeasures,
}

/// A measured step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepMeasurement {
    pub method: Method,
    /// Run with the two-level step's coarse correction after every sweep.
    pub two_level: bool,
    pub reference: ReferenceInfo,
    pub records: Vec<IterationRecord>,
}

/// One method to measure: `iterations` of `method`, with the two-level step's coarse
/// correction after every sweep when `two_level` (its coarse grid built from the frozen
/// substep's matrix before the clock starts, as a substep's preparation builds it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodRun {
    pub method: Method,
    pub iterations: u32,
    pub two_level: bool,
}

impl From<(Method, u32)> for MethodRun {
    fn from((method, iterations): (Method, u32)) -> Self {
        MethodRun { method, iterations, two_level: false }
    }
}

/// Limits of the reference solve.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceOptions {
    pub max_iterations: u32,
    /// Stop when no particle moves more than this in an iteration, metres. Positions are f32,
    /// so values much below 1e-7 m (the spacing of f32 near 1 m) cannot be reached.
    pub tolerance_m: f64,
}

impl Default for ReferenceOptions {
    fn default() -> Self {
        Self { max_iterations: 5_000, tolerance_m: 1e-7 }
    }
}

impl Simulation {
    /// Measures `iterations` iterations of `method` on the next substep (of length
    /// `dt / substeps`) against the reference solution. The simulation is left unchanged.
    pub fn measure_step(
        &mut self,
        dt: f32,
        method: Method,
        iterations: u32,
        reference: ReferenceOptions,
    ) -> Result<StepMeasurement> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(TailorError::setting("dt", dt, "the time step must be positive and finite"));
        }
        if iterations == 0 {
            return Err(TailorError::setting("iterations", iterations, "must be at least 1"));
        }
        let saved = self.save_state();
        let result = self.measure_inner(dt / self.settings.substeps as f32, method, iterations, reference);
        self.restore_state(saved);
        result
    }

    fn measure_inner(
        &mut self,
        h: f32,
        method: Method,
        iterations: u32,
        ro: ReferenceOptions,
    ) -> Result<StepMeasurement> {
        let run = MethodRun { method, iterations, two_level: self.settings.two_level };
        let mut out = self.measure_frozen(h, &[run], ro, &|_| true, false)?;
        Ok(out.methods.remove(0))
    }

    /// Measures several methods on the same frozen substep against one reference solve, and
    /// the reference solver's own convergence (its iterates against its final solution, its
    /// time including the factorisation). Only the iterations `keep(k)` accepts (1-based) are
    /// recorded, plus the last of each run, so long runs can be sampled on a log scale.
    /// The simulation is left unchanged.
    pub fn measure_methods(
        &mut self,
        dt: f32,
        methods: &[MethodRun],
        reference: ReferenceOptions,
        keep: &dyn Fn(u32) -> bool,
    ) -> Result<MethodsMeasurement> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(TailorError::setting("dt", dt, "the time step must be positive and finite"));
        }
        if methods.iter().any(|r| r.iterations == 0) {
            return Err(TailorError::setting("iterations", 0, "must be at least 1"));
        }
        let saved = self.save_state();
        let result = self.measure_frozen(dt / self.settings.substeps as f32, methods, reference, keep, true);
        self.restore_state(saved);
        result
    }

    fn measure_frozen(
        &mut self,
        h: f32,
        methods: &[MethodRun],
        ro: ReferenceOptions,
        keep: &dyn Fn(u32) -> bool,
        record_reference: bool,
    ) -> Result<MethodsMeasurement> {
        self.prepare(h);
        self.predict(h);
        self.detect_contacts_now();
        let x0 = self.x.clone();
        let mut ref_iterates: Vec<(u32, f64, Vec3Soa)> = Vec::new();
        let (x_ref, reference) = {
            let mut observe = |k: u32, secs: f64, x: &Vec3Soa| {
                if record_reference && keep(k) {
                    ref_iterates.push((k, secs, x.clone()));
                }
            };
            self.reference_solve_observed(ro.max_iterations, ro.tolerance_m, &mut observe)?
        };
        if record_reference && ref_iterates.last().is_none_or(|r| r.0 != reference.iterations) {
            ref_iterates.push((reference.iterations, reference.seconds, x_ref.clone()));
        }
        let e_ref = self.objective(&x_ref);
        let e0 = self.objective(&x0);
        let g0 = self.gradient_norm(&x0).max(1e-300);
        let d0 = distance(&x0, &x_ref).0.max(1e-300);
        let g_ref = self.gradient_norm(&x_ref);
        let reference = ReferenceInfo { gradient_rel: g_ref / g0, ..reference };
        let measure = |this: &mut Self, iteration: u32, seconds: f64, x: &Vec3Soa| {
            let (dist, dmax) = distance(x, &x_ref);
            let measures = ErrorMeasures {
                objective_rel: (this.objective(x) - e_ref) / (e0 - e_ref).max(1e-300),
                residual_rel: this.gradient_norm(x) / g0,
                distance_rel: dist / d0,
                distance_max: dmax,
            };
            IterationRecord { iteration, seconds, measures }
        };
        let reference_records: Vec<IterationRecord> =
            ref_iterates.iter().map(|(k, t, x)| measure(self, *k, *t, x)).collect();
        drop(ref_iterates);

        let mut out = Vec::with_capacity(methods.len());
        // Each run has the coarse grid it asks for; the simulation's own is put back after.
        let own_coarse = self.coarse.take();
        for &MethodRun { method, iterations, two_level } in methods {
            self.coarse = two_level.then(|| {
                let mut c = CoarseLevel::build(&self.model.matrix32, &self.free);
                c.set_values(&self.model.matrix32, &self.diag);
                c
            });
            self.x.copy_from(&x0);
            let mut timings = StageTimings::default();
            let start = Instant::now();
            let mut excluded = 0.0f64;
            let mut measured: Vec<(u32, f64, Vec3Soa)> = Vec::new();
            self.iterate(method, iterations, 0.0, false, &mut timings, |k, x| {
                let t = Instant::now();
                if keep(k + 1) || k + 1 == iterations {
                    let elapsed = (t - start).as_secs_f64() - excluded;
                    measured.push((k + 1, elapsed, x.clone()));
                }
                excluded += t.elapsed().as_secs_f64();
            });
            let records = measured.iter().map(|(k, t, x)| measure(self, *k, *t, x)).collect();
            out.push(StepMeasurement { method, two_level, reference, records });
        }
        self.coarse = own_coarse;
        Ok(MethodsMeasurement { reference, reference_records, methods: out })
    }
}

/// Several methods measured on one frozen substep ([`Simulation::measure_methods`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MethodsMeasurement {
    pub reference: ReferenceInfo,
    /// The reference solver's own iterates against its solution.
    pub reference_records: Vec<IterationRecord>,
    pub methods: Vec<StepMeasurement>,
}

/// `‖a − b‖` over all particles and the largest per-particle distance.
fn distance(a: &Vec3Soa, b: &Vec3Soa) -> (f64, f64) {
    let mut sum = 0.0f64;
    let mut max = 0.0f64;
    for i in 0..a.len() {
        let d = (a.get(i) - b.get(i)).length_squared() as f64;
        sum += d;
        max = max.max(d);
    }
    (sum.sqrt(), max.sqrt())
}
