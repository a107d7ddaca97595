//! Quality metrics: how good a simulated frame is, and the verdict on it.
//!
//! * [`metrics`]: the measures (penetration, self-intersections, strain, kinetic energy, the
//!   share of the cloth near the body and its centroid), computed on plain positions and
//!   meshes, with no solver state;
//! * [`QualityMetrics`]: one frame's figures, filled by
//!   [`Simulation::metrics`](crate::solver::Simulation::metrics);
//! * [`verdict`]: which of the result's own checks a frame fails, with a named reason.
//!
//! Its own module because both the solver (which measures) and the layers above it (the
//! Python module's `tailor.judge`, the bake loops) use it: it imports only the geometric
//! kernels of [`crate::collision`], never the solver.

pub mod fit_maps;
pub mod metrics;
pub mod verdict;

/// Quality of a simulated state (see [`metrics`]), as
/// [`Simulation::metrics`](crate::solver::Simulation::metrics) measures it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct QualityMetrics {
    /// Cloth particles inside the closed collider asked for (0 without one).
    pub penetration_count: usize,
    /// Deepest such particle, metres.
    pub penetration_max_depth: f32,
    /// Intersecting pairs of cloth triangles that share no vertex.
    pub self_intersections: usize,
    /// Largest sewn-pair distance, metres.
    pub seam_gap: f32,
    /// Max and mean `|ℓ/ℓ₀ − 1|` over the cloth edges (rest lengths from the 2D pattern).
    pub strain_max: f32,
    pub strain_mean: f32,
    /// `½ Σ m v²`, joules.
    pub kinetic_energy: f64,
    /// Number of cloth particles.
    pub particles: usize,
    /// Mean position of the cloth particles, metres.
    pub centroid: [f32; 3],
    /// Mean position of the cloth's highest twentieth against gravity ([`metrics::top`]): where
    /// a worn garment hangs from (a waist, shoulders), metres; the centroid without gravity.
    pub top: [f32; 3],
    /// Share of the cloth particles within [`ON_BODY_DISTANCE`](metrics::ON_BODY_DISTANCE) of the collider's surface
    /// (`None` without a collider).
    pub on_body_fraction: Option<f32>,
    /// Area-weighted centroid of the collider's surface (`None` without a collider): the
    /// body's own motion, which [`verdict::centroid_shift`] takes out of the cloth's.
    pub collider_centroid: Option<[f32; 3]>,
    /// Whether some seam is still closing ([`Simulation::seams_closing`](crate::solver::Simulation::seams_closing)): the garment is
    /// still being assembled.
    pub seams_closing: bool,
}
