//! One-vector constraints `v = Σₖ cₖ·x_{iₖ}` with a distance-like projection.
//!
//! The projection keeps the direction of `v` and sets its length to the rest value `r`:
//! `p = r·v/‖v‖` (and `p = 0` when `r = 0`). Energy `w/2·(‖v‖ − r)²`.
//!
//! * A **seam pair** is `v = x_a − x_b` (or weighted edge points on either side for seams of
//!   unequal counts) with `r = 0`: a zero-rest-length spring, purely quadratic.
//! * A **bending hinge** is Bergou's `v = Σ Kₖ xₖ` over the hinge's four vertices with weight
//!   `w = 3k/(A₀+A₁)`; `r = 0` for a flat rest shape (the quadratic model exactly), or the
//!   magnitude of `v` in a creased rest pose (then its magnitude is preserved, as in Projective
//!   Dynamics' bending constraint of Bouaziz et al. 2014).
//!
//! Constraints with `r = 0` have `p = 0`, so they only enter the constant system matrix and the
//! local step skips them.

use glam::Vec3;

use crate::solver::model::soa::Vec3Soa;

/// Stencil constraints in compressed rows: constraint `s` has terms `offsets[s]..offsets[s+1]`.
#[derive(Debug, Clone)]
pub struct StencilSet {
    pub offsets: Vec<u32>,
    pub verts: Vec<u32>,
    pub coefs: Vec<f32>,
    pub weights: Vec<f32>,
    pub rest: Vec<f32>,
}

impl Default for StencilSet {
    fn default() -> Self {
        Self { offsets: vec![0], verts: Vec::new(), coefs: Vec::new(), weights: Vec::new(), rest: Vec::new() }
    }
}

impl StencilSet {
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// Releases unused capacity (after building by [`StencilSet::push`]).
    pub fn shrink_to_fit(&mut self) {
        self.offsets.shrink_to_fit();
        self.verts.shrink_to_fit();
        self.coefs.shrink_to_fit();
        self.weights.shrink_to_fit();
        self.rest.shrink_to_fit();
    }

    /// Heap bytes of the compressed rows.
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.offsets)
            + vec_bytes(&self.verts)
            + vec_bytes(&self.coefs)
            + vec_bytes(&self.weights)
            + vec_bytes(&self.rest)
    }

    /// Appends a constraint; terms on the same vertex are merged.
    pub fn push(&mut self, terms: &[(u32, f32)], weight: f32, rest: f32) {
        let start = self.verts.len();
        for &(v, c) in terms {
            if let Some(k) = self.verts[start..].iter().position(|&u| u == v) {
                self.coefs[start + k] += c;
            } else {
                self.verts.push(v);
                self.coefs.push(c);
            }
        }
        self.offsets.push(self.verts.len() as u32);
        self.weights.push(weight);
        self.rest.push(rest);
    }

    #[inline(always)]
    pub fn range(&self, s: usize) -> std::ops::Range<usize> {
        self.offsets[s] as usize..self.offsets[s + 1] as usize
    }

    /// `v = Σ cₖ xₖ` of constraint `s`.
    #[inline(always)]
    pub fn vector(&self, s: usize, x: &Vec3Soa) -> Vec3 {
        let mut v = Vec3::ZERO;
        for t in self.range(s) {
            v += x.get(self.verts[t] as usize) * self.coefs[t];
        }
        v
    }

    /// Energy `w/2·‖v − p(v)‖²` of constraint `s` (f64 for the error measures).
    pub fn energy(&self, s: usize, x: &Vec3Soa) -> f64 {
        let v = self.vector(s, x);
        0.5 * self.weights[s] as f64 * (v - project(v, self.rest[s])).length_squared() as f64
    }

    /// Sets every constraint's rest magnitude from a pose (used for creased rest shapes).
    /// Magnitudes under [`FLAT_REST`] count as flat, so that rounding in a flat region does not
    /// turn linear constraints into projected ones.
    pub fn set_rest_from(&mut self, pose: &Vec3Soa) {
        for s in 0..self.len() {
            let r = self.vector(s, pose).length();
            self.rest[s] = if r < FLAT_REST { 0.0 } else { r };
        }
    }
}

/// Rest magnitudes below this (metres) are treated as exactly flat.
pub const FLAT_REST: f32 = 1e-6;

/// The projection `p = r·v/‖v‖` (zero when `r = 0` or `v = 0`).
#[inline(always)]
pub fn project(v: Vec3, rest: f32) -> Vec3 {
    if rest == 0.0 {
        return Vec3::ZERO;
    }
    let l = v.length();
    if l > 1e-12 {
        v * (rest / l)
    } else {
        Vec3::ZERO
    }
}
