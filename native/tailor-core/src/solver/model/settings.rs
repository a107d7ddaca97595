//! Solver settings and fabric parameters, with validation.
//!
//! Units: metres, kilograms, seconds. Stretch and shear stiffness are membrane stiffnesses in
//! N/m (energy per unit rest area per unit strain²); bending stiffness is in N·m (J); seam
//! stiffness is a spring constant in N/m per sewn pair; air damping is a rate in 1/s.

use crate::error::{Result, TailorError};

/// The global-step method (the real-time path uses [`Method::Chebyshev`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Jacobi iterations (parallel, order independent), under-relaxed by `jacobi_relaxation`.
    Jacobi,
    /// Gauss-Seidel over the graph colouring, parallel within a colour (Vivace).
    GaussSeidel,
    /// Gauss-Seidel accelerated by Chebyshev semi-iteration (Wang 2015), the default.
    Chebyshev,
}

/// Default collision thickness: the distance kept between the cloth and colliders, metres.
/// Every simulation starts with it; a garment's setup records its own (default this one).
pub const DEFAULT_THICKNESS: f32 = 0.004;

/// Per-material parameters, applied to every triangle/hinge unless overridden per element.
/// Stored by name in a garment file's setup (the four isotropic fields required there; the
/// anisotropic ones only where the fabric has them).
///
/// **Directions.** A piece's fabric axes are its pattern's: `u` along the pattern's x axis, `v`
/// along its y axis, the bias at 45° between them (an anisotropic piece's turned so that `v`
/// lies along its grain line: `garment::setup::fabric_grain`, `Model::set_triangle_grain`). An
/// isotropic fabric (every `Option` `None`) behaves the same along all of them. An anisotropic one (woven and knit fabrics: the library's
/// denim is 4.8 times stiffer along `v` than along `u`) gives `stretch_v`, and the bending of a
/// hinge follows its edge's direction in the pattern (as ARCSim's measured model does: Wang et
/// al. 2011): `bend` for an edge along `u`, `bend_bias` at 45°, `bend_v` along `v`, linear in the
/// angle between them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fabric {
    /// Area density, kg/m² (cotton shirting is about 0.1-0.2).
    pub density: f32,
    /// Stretch stiffness along `u` (and along `v` unless `stretch_v` says otherwise), N/m.
    pub stretch: f32,
    /// Shear stiffness (resistance to the `u` and `v` axes losing orthogonality), N/m.
    pub shear: f32,
    /// Bending stiffness of the quadratic hinge model, N·m (of a hinge whose edge runs along `u`,
    /// and of every hinge unless `bend_bias`/`bend_v` say otherwise): its energy is 3 times the
    /// continuum `½·B·κ²` of a rigidity `B = bend`, so a fabric of flexural rigidity `B` has
    /// `bend = B/3` ([`crate::fabrics::HINGE_ENERGY_PER_RIGIDITY`], measured there; the library
    /// converts).
    pub bend: f32,
    /// Stretch stiffness along `v`, N/m (`None`: as `stretch`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch_v: Option<f32>,
    /// Bending stiffness of a hinge whose edge runs on the bias (45°), N·m (`None`: the mean of
    /// `bend` and the `v` value).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend_bias: Option<f32>,
    /// Bending stiffness of a hinge whose edge runs along `v`, N·m (`None`: as `bend`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend_v: Option<f32>,
}

impl Default for Fabric {
    fn default() -> Self {
        Self { density: 0.15, stretch: 600.0, shear: 60.0, bend: 2e-5, stretch_v: None, bend_bias: None, bend_v: None }
    }
}

impl Fabric {
    /// An isotropic fabric of these four values.
    pub const fn isotropic(density: f32, stretch: f32, shear: f32, bend: f32) -> Self {
        Self { density, stretch, shear, bend, stretch_v: None, bend_bias: None, bend_v: None }
    }

    pub fn validate(&self) -> Result<()> {
        positive("fabric.density", self.density)?;
        non_negative("fabric.stretch", self.stretch)?;
        non_negative("fabric.shear", self.shear)?;
        non_negative("fabric.bend", self.bend)?;
        for (name, v) in
            [("fabric.stretch_v", self.stretch_v), ("fabric.bend_bias", self.bend_bias), ("fabric.bend_v", self.bend_v)]
        {
            if let Some(v) = v {
                non_negative(name, v)?;
            }
        }
        if self.stretch.min(self.stretch_uv()[1]) + self.shear <= 0.0 {
            return Err(TailorError::setting(
                "fabric.stretch",
                self.stretch,
                "stretch + shear must be positive along u and v",
            ));
        }
        Ok(())
    }

    /// Whether the fabric is the same in every direction (no anisotropic value differs).
    pub fn is_isotropic(&self) -> bool {
        self.stretch_uv()[0] == self.stretch_uv()[1] && {
            let [u, b, v] = self.bend_directions();
            u == b && b == v
        }
    }

    /// The stretch stiffness along `u` and along `v`, N/m.
    pub fn stretch_uv(&self) -> [f32; 2] {
        [self.stretch, self.stretch_v.unwrap_or(self.stretch)]
    }

    /// The bending stiffness of a hinge whose edge runs along `u`, on the bias and along `v`.
    pub fn bend_directions(&self) -> [f32; 3] {
        let v = self.bend_v.unwrap_or(self.bend);
        [self.bend, self.bend_bias.unwrap_or(0.5 * (self.bend + v)), v]
    }
}

/// The bending stiffness of a hinge whose edge runs at `angle` radians from the pattern's x axis
/// (`u`), for the stiffnesses `[u, bias, v]`: linear in the angle folded into 0-90°, through the
/// bias at 45° (ARCSim's interpolation of its measured bending rows).
pub fn bend_at_angle(bend: [f32; 3], angle: f64) -> f64 {
    let a = angle.rem_euclid(std::f64::consts::PI);
    let folded = if a > std::f64::consts::FRAC_PI_2 { std::f64::consts::PI - a } else { a };
    let t = folded / std::f64::consts::FRAC_PI_4; // 0 along u, 1 on the bias, 2 along v
    let [u, b, v] = bend.map(|x| x as f64);
    if t <= 1.0 {
        u + (b - u) * t
    } else {
        b + (v - b) * (t - 1.0).min(1.0)
    }
}

/// The seam-closing damping ramp of the paper (section 4, "Seam simulation").
///
/// While fewer than `closed_fraction` of the seam pairs are within `gap_threshold`, air damping
/// is raised to `closing_damping`; once that many have met, damping returns linearly to the
/// base value over `release_time` seconds and stays there (until seams are added again).
/// While seams close, gravity is scaled by `closing_gravity` (see there).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamRamp {
    pub enabled: bool,
    /// Air damping while seams close, 1/s.
    pub closing_damping: f32,
    /// A pair counts as met when its gap is under this, metres.
    pub gap_threshold: f32,
    /// Fraction of pairs that must have met to start the release, 0..=1.
    pub closed_fraction: f32,
    /// ...and the widest pair must be within this, metres (see `damping`: a few pairs still
    /// far apart hold the release back; a seam that stops closing releases it after a while).
    pub release_gap: f32,
    /// Duration of the linear return to the base damping, seconds.
    pub release_time: f32,
    /// Speed at which the widest seam pair is drawn together, m/s (0 = at once). Each pair's
    /// rest length starts at its gap and shrinks every substep, so seams close over time
    /// instead of in one implicit step, which would drag cloth through the body and stretch
    /// it (the abrupt start the paper damps). Every pair shrinks in proportion to its gap, so
    /// all meet together, the garment contracting round the body as one shell: at one speed
    /// for all, short seams (an armhole, 18 cm on the GarmentCode shirt) closed long before
    /// long ones (its shoulders, 45 cm), and the sleeves, sewn on and pulled under the arms,
    /// dragged the still-open shoulder seams down under the arms: 386 % edge strain while
    /// closing and the shirt fell off. All together: 9 % strain, shoulder seams over the
    /// shoulders.
    pub closing_speed: f32,
    /// Factor on gravity while seams close (phase `Closing`), 0..=1; full gravity from the
    /// release on. The paper raises air damping so that a garment assembles where it was
    /// placed, but damping only bounds the fall speed (`g/c`, 0.8 m/s at 12/s; quasi-statically
    /// `g·h²` per substep whatever `c`), and panels placed around a body touch it nowhere that
    /// holds them: under full gravity every sample garment falls ~0.6 m in the ~1 s its seams
    /// take to close (the GarmentCode shirt ends 1.9 m down, on the floor). With 0 (the
    /// default) the panels stay where they were placed until they are sewn and gravity drapes
    /// the closed garment onto the body.
    pub closing_gravity: f32,
    /// Stiffness, N/m per particle, with which the body holds the cloth near it while seams
    /// close (phase `Closing`; 0 = no hold). When closing starts, every particle within
    /// `closing_hold_distance` of a mesh collider's surface is attached to it (as a painted pin
    /// rides on the body, `simulation/attach.rs`); the holds go when the ramp releases. Why: with
    /// gravity held, nothing but the solver's arbitrary split decides which side of a seam
    /// moves, and a heavy part placed away from the body drags the part that fits it: the
    /// tiers of a GarmentCode tiered skirt, laid flat in rings round its waistband, dragged the
    /// waistband 30 cm down past the hips while their seams closed and the skirt fell (its
    /// centroid 55 cm down after 2 s); held, the cloth that sits on the body stays and the rest
    /// comes to it (10 cm, on the hips). Weak beside a seam (1e4), so seams still close and
    /// pieces still slide into place; it only breaks the tie.
    pub closing_hold: f32,
    /// Cloth within this distance of a mesh collider's surface, metres, is held while seams
    /// close (see `closing_hold`).
    pub closing_hold_distance: f32,
}

impl Default for SeamRamp {
    fn default() -> Self {
        Self {
            enabled: true,
            closing_damping: 12.0,
            gap_threshold: 2e-3,
            closed_fraction: 0.95,
            release_gap: 0.01,
            release_time: 0.5,
            closing_speed: 0.5,
            closing_gravity: 0.0,
            closing_hold: 100.0,
            closing_hold_distance: 0.05,
        }
    }
}

/// Chebyshev acceleration parameters (see `stages/chebyshev.rs` for the spectral-radius rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChebyshevSettings {
    /// Plain Gauss-Seidel iterations at the start of each substep before acceleration starts;
    /// they also measure the spectral radius. At least 3.
    pub delay: u32,
    /// A fixed spectral radius; `None` estimates it automatically.
    pub rho: Option<f32>,
    /// Factor applied to the estimated radius (under-estimating is safe, over-estimating is not).
    pub safety: f32,
    /// Upper clamp of the radius used.
    pub max_rho: f32,
}

impl Default for ChebyshevSettings {
    fn default() -> Self {
        Self { delay: 4, rho: None, safety: 1.0, max_rho: 0.995 }
    }
}

/// Everything that controls a step.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverSettings {
    /// Substeps per call to `step(dt)`.
    pub substeps: u32,
    /// Local/global iterations per substep (the maximum when `tolerance` stops early).
    pub iterations: u32,
    /// Stop a substep's iterations when the residual (the force the last sweep corrected, N)
    /// falls under this fraction of the larger of its first value and the cloth's weight
    /// `‖M·g‖` (0 disables).
    pub tolerance: f32,
    pub method: Method,
    /// Gravity, m/s².
    pub gravity: [f32; 3],
    /// Base air damping, 1/s (velocities decay as exp(-damping · t)).
    pub air_damping: f32,
    pub ramp: SeamRamp,
    pub chebyshev: ChebyshevSettings,
    /// Under-relaxation of [`Method::Jacobi`] (plain Jacobi need not converge on bending stencils).
    pub jacobi_relaxation: f32,
    /// Seed of the randomized graph colouring (the result is deterministic for a seed).
    pub colouring_seed: u64,
    /// The two-level global step (`stages/coarse.rs`): every few sweeps, the error's smooth
    /// part is solved for on a coarse grid of particle aggregates, so that bending and the
    /// garment's large-scale stretch converge at the resolutions garments are meshed at. CPU
    /// only: a GPU frame with it runs on the CPU. Not applied while self-collision is on (its
    /// pass and the correction work against each other: measured on the layered outfit).
    pub two_level: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            substeps: 4,
            iterations: 20,
            tolerance: 0.0,
            method: Method::Chebyshev,
            gravity: [0.0, 0.0, -9.81],
            air_damping: 0.2,
            ramp: SeamRamp::default(),
            chebyshev: ChebyshevSettings::default(),
            jacobi_relaxation: 0.66,
            colouring_seed: 0x7a11_0c0d,
            two_level: false,
        }
    }
}

/// Names of the quality presets, fastest first (see [`SolverSettings::preset`]).
pub const PRESETS: [&str; 2] = ["preview", "final"];

impl SolverSettings {
    /// A quality preset: the default settings with the substeps, iterations and tolerance
    /// chosen from the run-time-against-error benchmark (`make bench-error`, `docs/accuracy.md`).
    ///
    /// * `"preview"`: 4 substeps × at most 10 iterations, stopping at 1e-2: the cheapest
    ///   setting measured that keeps the walking shirt out of the body (2 × 10 and 3 × 10 let
    ///   particles 16 to 22 mm into it);
    /// * `"final"`: 8 substeps × 15 iterations, no early stop: what every bake, sample and
    ///   drape-suite figure is measured at (the add-on's Final, `tailor simulate`'s default).
    ///   8 × 20 stopping at 1e-4 measured better on the walking shirt (strain 0.35 against
    ///   0.44, seam gap 2.2 mm against 3.1) at 1.6 times the cost; a solver that converges is
    ///   issue 28's, not a preset's.
    pub fn preset(name: &str) -> Result<Self> {
        let (substeps, iterations, tolerance) = match name {
            "preview" => (4, 10, 1e-2),
            "final" => (8, 15, 0.0),
            other => {
                return Err(TailorError::setting("preset", other, format!("expected one of {PRESETS:?}")));
            }
        };
        Ok(Self { substeps, iterations, tolerance, ..Self::default() })
    }

    pub fn validate(&self) -> Result<()> {
        if self.substeps == 0 {
            return Err(TailorError::setting("substeps", self.substeps, "must be at least 1"));
        }
        if self.iterations == 0 {
            return Err(TailorError::setting("iterations", self.iterations, "must be at least 1"));
        }
        non_negative("tolerance", self.tolerance)?;
        for g in self.gravity {
            finite("gravity", g)?;
        }
        non_negative("air_damping", self.air_damping)?;
        non_negative("ramp.closing_damping", self.ramp.closing_damping)?;
        non_negative("ramp.gap_threshold", self.ramp.gap_threshold)?;
        non_negative("ramp.release_gap", self.ramp.release_gap)?;
        non_negative("ramp.release_time", self.ramp.release_time)?;
        non_negative("ramp.closing_speed", self.ramp.closing_speed)?;
        if !(self.ramp.closing_hold.is_finite() && self.ramp.closing_hold >= 0.0) {
            return Err(TailorError::setting("ramp.closing_hold", self.ramp.closing_hold, "must be finite and >= 0"));
        }
        if !(self.ramp.closing_hold_distance.is_finite() && self.ramp.closing_hold_distance >= 0.0) {
            return Err(TailorError::setting(
                "ramp.closing_hold_distance",
                self.ramp.closing_hold_distance,
                "must be finite and >= 0",
            ));
        }
        if !(0.0..=1.0).contains(&self.ramp.closing_gravity) {
            return Err(TailorError::setting("ramp.closing_gravity", self.ramp.closing_gravity, "must be in 0..=1"));
        }
        if !(0.0..=1.0).contains(&self.ramp.closed_fraction) {
            return Err(TailorError::setting("ramp.closed_fraction", self.ramp.closed_fraction, "must be in 0..=1"));
        }
        if self.chebyshev.delay < 3 {
            return Err(TailorError::setting("chebyshev.delay", self.chebyshev.delay, "must be at least 3"));
        }
        if let Some(r) = self.chebyshev.rho {
            if !(0.0..1.0).contains(&r) {
                return Err(TailorError::setting("chebyshev.rho", r, "must be in [0, 1)"));
            }
        }
        if !(0.0..=1.0).contains(&self.chebyshev.safety) || !(0.0..1.0).contains(&self.chebyshev.max_rho) {
            return Err(TailorError::setting(
                "chebyshev.safety",
                self.chebyshev.safety,
                "safety in 0..=1, max_rho < 1",
            ));
        }
        if !(self.jacobi_relaxation > 0.0 && self.jacobi_relaxation <= 1.0) {
            return Err(TailorError::setting("jacobi_relaxation", self.jacobi_relaxation, "must be in (0, 1]"));
        }
        Ok(())
    }
}

fn finite(name: &'static str, v: f32) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(TailorError::setting(name, v, "must be finite"))
    }
}

pub(crate) fn non_negative(name: &'static str, v: f32) -> Result<()> {
    finite(name, v)?;
    if v < 0.0 {
        return Err(TailorError::setting(name, v, "must not be negative"));
    }
    Ok(())
}

pub(crate) fn positive(name: &'static str, v: f32) -> Result<()> {
    finite(name, v)?;
    if v <= 0.0 {
        return Err(TailorError::setting(name, v, "must be positive"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid_and_ordered_by_cost() {
        let p: Vec<SolverSettings> = PRESETS.iter().map(|n| SolverSettings::preset(n).unwrap()).collect();
        for s in &p {
            s.validate().unwrap();
        }
        assert!(p[0].tolerance > 0.0, "preview stops at its tolerance");
        let work = |s: &SolverSettings| s.substeps * s.iterations;
        assert!(work(&p[0]) < work(&p[1]) && p[0].tolerance > p[1].tolerance);
        let err = SolverSettings::preset("fast").unwrap_err().to_string();
        assert!(err.contains("preset") && err.contains("preview"), "{err}");
    }
}
