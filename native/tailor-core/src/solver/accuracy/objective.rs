//! The objective one implicit step minimises, and its gradient, for the error measures.
//!
//! ```text
//! E(x) = Σᵢ mᵢ/(2h²)·‖xᵢ − yᵢ‖² + Σ_c w_c/2·‖A_c x − P_c(A_c x)‖² + Σ contacts wᵢ/2·‖xᵢ − tᵢ‖²
//! ∇E(x)ᵢ = Dᵢ·xᵢ + Σⱼ Lᵢⱼ·xⱼ − (mᵢ/h²·yᵢ + b_constᵢ + Σ slotsᵢ(x)) + wᵢ·(xᵢ − tᵢ)
//! ```
//!
//! over the free (unpinned) particles, with the contacts of the step frozen. Projections are
//! evaluated with the solver's f32 kernels and summed in f64, which puts the floor of every
//! relative measure near 1e-6.

use glam::Vec3;

use crate::solver::model::constraints::triangle;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::simulation::Simulation;
use crate::solver::stages::local::project_all;

impl Simulation {
    /// `E(x)` of the current step problem (after `predict`).
    pub(crate) fn objective(&self, x: &Vec3Soa) -> f64 {
        let m = &self.model;
        let inv_h2 = 1.0 / (self.h_prepared as f64 * self.h_prepared as f64);
        let mut e = 0.0f64;
        for i in 0..m.n() {
            if !m.pinned[i] {
                e += 0.5 * m.mass[i] as f64 * inv_h2 * (x.get(i) - self.y.get(i)).length_squared() as f64;
                let w = self.contacts.weight[i];
                if w > 0.0 {
                    e += 0.5 * w as f64 * (x.get(i) - self.contacts.target.get(i)).length_squared() as f64;
                }
            }
        }
        let t = &m.triangles;
        for k in 0..t.len() {
            let v = t.verts[k];
            let xs = [0, 1, 2].map(|j| x.get(v[j] as usize).into());
            e += triangle::energy(&t.g[k], xs, [t.w_stretch[k], t.w_stretch_v[k]], t.w_shear[k]);
        }
        for set in [&m.bending, &m.seam_pairs, &m.seam_hinges] {
            e += (0..set.len()).map(|s| set.energy(s, x)).sum::<f64>();
        }
        for a in &m.attachments {
            e += 0.5 * a.weight as f64 * (x.get(a.particle as usize) - Vec3::from(a.target)).length_squared() as f64;
        }
        for a in &m.collider_attachments {
            e += 0.5 * a.weight as f64 * (x.get(a.particle as usize) - Vec3::from(a.target)).length_squared() as f64;
        }
        e
    }

    /// `‖∇E(x)‖` over the free particles (uses the slot buffer as scratch).
    pub(crate) fn gradient_norm(&mut self, x: &Vec3Soa) -> f64 {
        let mut slots = std::mem::take(&mut self.slots);
        project_all(&self.model, x, &mut slots);
        let m = &self.model;
        let a = &m.matrix32;
        let mut g2 = 0.0f64;
        for i in 0..m.n() {
            if m.pinned[i] {
                continue;
            }
            let mut g = [0.0f64; 3];
            let xi = x.get(i);
            let mut r = self.rhs_fixed.get(i);
            for s in m.slots.particle_offsets[i]..m.slots.particle_offsets[i + 1] {
                r += Vec3::from(slots[m.slots.particle_slots[s as usize] as usize]);
            }
            for d in 0..3 {
                g[d] = self.diag[i] as f64 * xi[d] as f64 - r[d] as f64;
            }
            for k in a.offsets[i] as usize..a.offsets[i + 1] as usize {
                let xj = x.get(a.cols[k] as usize);
                for d in 0..3 {
                    g[d] += a.vals[k] as f64 * xj[d] as f64;
                }
            }
            let w = self.contacts.weight[i];
            if w > 0.0 {
                let t = self.contacts.target.get(i);
                for d in 0..3 {
                    g[d] += w as f64 * (xi[d] - t[d]) as f64;
                }
            }
            g2 += g.iter().map(|v| v * v).sum::<f64>();
        }
        self.slots = slots;
        g2.sqrt()
    }
}
