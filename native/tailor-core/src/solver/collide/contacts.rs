//! Per-particle contact constraints and analytic colliders.
//!
//! A contact is a temporary inequality constraint `w/2·‖xᵢ − pᵢ‖²` whose projection `pᵢ` is
//! the closest point outside the collider (its surface pushed out by the thickness). It only
//! touches the diagonal of the global system, so contacts can change every iteration without
//! touching the colouring. The weight is a multiple of the particle's own diagonal, so one
//! Gauss-Seidel update removes most of a penetration whatever the particle's mass or stiffness.
//!
//! Analytic colliders (plane, sphere, capsule) serve scenes and tests that need no mesh; mesh
//! colliders of an animated character write into the same [`ContactSet`].

use glam::Vec3;
use rayon::prelude::*;

use crate::solver::model::soa::Vec3Soa;

/// An analytic collider with Coulomb friction coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitCollider {
    pub shape: Shape,
    /// Static friction coefficient μs (tangential motion stops while ‖Δv_t‖ ≤ μs·‖Δv_n‖).
    pub static_friction: f32,
    /// Kinetic friction coefficient μk.
    pub kinetic_friction: f32,
}

/// Collider shapes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Half-space below the plane through `point` with outward `normal`.
    Plane {
        point: [f32; 3],
        normal: [f32; 3],
    },
    Sphere {
        center: [f32; 3],
        radius: f32,
    },
    /// Segment `a`–`b` swept by a sphere (a cylinder with round caps).
    Capsule {
        a: [f32; 3],
        b: [f32; 3],
        radius: f32,
    },
}

impl Shape {
    /// Signed distance and outward unit normal at `p`.
    #[inline]
    pub fn distance(&self, p: Vec3) -> (f32, Vec3) {
        match *self {
            Shape::Plane { point, normal } => {
                let n = Vec3::from(normal).normalize_or(Vec3::Z);
                ((p - Vec3::from(point)).dot(n), n)
            }
            Shape::Sphere { center, radius } => sphere(p, Vec3::from(center), radius),
            Shape::Capsule { a, b, radius } => {
                let (a, b) = (Vec3::from(a), Vec3::from(b));
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared().max(1e-20)).clamp(0.0, 1.0);
                sphere(p, a + ab * t, radius)
            }
        }
    }
}

fn sphere(p: Vec3, c: Vec3, r: f32) -> (f32, Vec3) {
    let d = p - c;
    let l = d.length();
    let n = if l > 1e-12 { d / l } else { Vec3::Z };
    (l - r, n)
}

/// This substep's contacts: weight (0 = none), target and normal per particle.
#[derive(Debug, Clone, Default)]
pub struct ContactSet {
    pub weight: Vec<f32>,
    pub target: Vec3Soa,
    pub normal: Vec3Soa,
    /// Index of the collider each particle touched (for its friction), or u32::MAX.
    pub collider: Vec<u32>,
}

/// Contact weight as a multiple of the particle's diagonal.
pub const CONTACT_WEIGHT_FACTOR: f32 = 20.0;

impl ContactSet {
    pub fn resize(&mut self, n: usize) {
        self.weight = vec![0.0; n];
        self.target = Vec3Soa::zeros(n);
        self.normal = Vec3Soa::zeros(n);
        self.collider = vec![u32::MAX; n];
    }

    /// Heap bytes of the per-particle contact arrays.
    pub fn memory_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.weight) + self.target.memory_bytes() + self.normal.memory_bytes() + vec_bytes(&self.collider)
    }

    pub fn count(&self) -> usize {
        self.weight.iter().filter(|&&w| w > 0.0).count()
    }

    /// Detects contacts of every particle against the colliders at positions `x`; `diag` is
    /// each particle's system diagonal (`m/h² + Lᵢᵢ`), `pinned` particles never collide.
    pub fn detect(
        &mut self,
        colliders: &[ImplicitCollider],
        thickness: f32,
        x: &Vec3Soa,
        diag: &[f32],
        pinned: &[bool],
    ) {
        if colliders.is_empty() {
            return;
        }
        let n = x.len();
        let found: Vec<(f32, Vec3, Vec3, u32)> = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|i| {
                if pinned[i] {
                    return (0.0, Vec3::ZERO, Vec3::ZERO, u32::MAX);
                }
                let p = x.get(i);
                let mut best = (0.0, Vec3::ZERO, Vec3::ZERO, u32::MAX);
                let mut deepest = f32::INFINITY;
                for (c, col) in colliders.iter().enumerate() {
                    let (d, nrm) = col.shape.distance(p);
                    if d < thickness && d < deepest {
                        deepest = d;
                        best = (CONTACT_WEIGHT_FACTOR * diag[i], p + nrm * (thickness - d), nrm, c as u32);
                    }
                }
                best
            })
            .collect();
        for (i, (w, t, nrm, c)) in found.into_iter().enumerate() {
            self.weight[i] = w;
            self.collider[i] = c;
            if w > 0.0 {
                self.target.set(i, t);
                self.normal.set(i, nrm);
            }
        }
    }

    /// Clears every contact.
    pub fn clear(&mut self) {
        self.weight.iter_mut().for_each(|w| *w = 0.0);
        self.collider.iter_mut().for_each(|c| *c = u32::MAX);
    }
}

/// Pushes particles still inside a collider out to its surface plus thickness (after the
/// iterations, so that no substep ends inside), returning how many moved.
pub fn resolve_penetrations(colliders: &[ImplicitCollider], thickness: f32, x: &mut Vec3Soa, pinned: &[bool]) -> usize {
    let mut moved = 0;
    for (i, &pin) in pinned.iter().enumerate() {
        if pin {
            continue;
        }
        let mut p = x.get(i);
        let mut touched = false;
        for col in colliders {
            let (d, n) = col.shape.distance(p);
            if d < thickness {
                p += n * (thickness - d);
                touched = true;
            }
        }
        if touched {
            x.set(i, p);
            moved += 1;
        }
    }
    moved
}

/// Coulomb friction on a particle's velocity `v` after a contact that changed its normal
/// velocity by `dvn` (≥ 0): the tangential part stops if it is under `μs·dvn`, else it loses
/// `μk·dvn` of its magnitude.
#[inline]
pub fn coulomb(v: Vec3, n: Vec3, dvn: f32, mu_s: f32, mu_k: f32) -> Vec3 {
    let vn = n * v.dot(n);
    let vt = v - vn;
    let lt = vt.length();
    if lt <= mu_s * dvn {
        vn
    } else {
        vn + vt * (1.0 - mu_k * dvn / lt).max(0.0)
    }
}
