//! The local step: project every non-linear constraint and write its right-hand-side
//! contributions `w·Aᵀp` into its slots (see `model::SlotLayout`). Embarrassingly parallel:
//! each constraint writes only its own slots. Slots are `Vec3A` (16 bytes) so that the global
//! sweep gathers each with one aligned load.

use glam::Vec3A;
use rayon::prelude::*;

use super::constraints::{stencil, triangle};
use super::model::Model;
use super::soa::Vec3Soa;

/// Fills `slots` from positions `x`.
pub(crate) fn project_all(model: &Model, x: &Vec3Soa, slots: &mut [Vec3A]) {
    let tris = &model.triangles;
    let (tri_slots, curved_slots) = slots.split_at_mut(3 * tris.len());
    tri_slots.par_chunks_mut(3).with_min_len(512).enumerate().for_each(|(t, out)| {
        let v = tris.verts[t];
        let xs = [x.get(v[0] as usize), x.get(v[1] as usize), x.get(v[2] as usize)];
        let c = triangle::rhs_contributions(&tris.g[t], xs, tris.w_stretch[t], tris.w_shear[t]);
        for (o, c) in out.iter_mut().zip(c) {
            *o = c.into();
        }
    });
    let layout = &model.slots;
    if layout.curved.is_empty() {
        return;
    }
    let base0 = 3 * tris.len();
    // Curved stencils own consecutive runs of slots: split the tail into those runs.
    let mut runs: Vec<(&mut [Vec3A], (u8, u32))> = Vec::with_capacity(layout.curved.len());
    let mut rest = curved_slots;
    for (c, &id) in layout.curved.iter().enumerate() {
        let end = layout.curved.get(c + 1).map(|_| layout.curved_base[c + 1] as usize).unwrap_or(layout.total) - base0;
        let start = layout.curved_base[c] as usize - base0;
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(end - start);
        runs.push((head, id));
        rest = tail;
    }
    runs.into_par_iter().with_min_len(256).for_each(|(out, (set_id, s))| {
        let set = if set_id == 0 { &model.bending } else { &model.seam_hinges };
        let s = s as usize;
        let v = set.vector(s, x);
        let p = stencil::project(v, set.rest[s]) * set.weights[s];
        for (o, t) in out.iter_mut().zip(set.range(s)) {
            *o = (p * set.coefs[t]).into();
        }
    });
}
