//! The local step: project every non-linear constraint and write its right-hand-side
//! contributions `w·Aᵀp` into its slots (see `model::SlotLayout`). Embarrassingly parallel:
//! each constraint writes only its own slots. Slots are `Vec3A` (16 bytes) so that the global
//! sweep gathers each with one aligned load.

use glam::{Vec3A, Vec4};
use rayon::prelude::*;

use crate::solver::model::constraints::{stencil, triangle};
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::Model;

/// Triangles per parallel task of the local step.
const TRI_BLOCK: usize = 512;

/// Fills `slots` from positions `x`.
pub(crate) fn project_all(model: &Model, x: &Vec3Soa, slots: &mut [Vec3A]) {
    let tris = &model.triangles;
    let (tri_slots, curved_slots) = slots.split_at_mut(3 * tris.len());
    // Blocks of triangles per task, each a plain loop over zipped slices: no per-triangle
    // rayon plumbing and, with the three coordinate slices cut to one length, one bounds
    // check per vertex instead of three.
    let n = x.len();
    let (xx, xy, xz) = (&x.x[..n], &x.y[..n], &x.z[..n]);
    let get = |i: u32| {
        let i = i as usize;
        Vec3A::new(xx[i], xy[i], xz[i])
    };
    tri_slots.par_chunks_mut(3 * TRI_BLOCK).enumerate().for_each(|(b, out)| {
        let r = b * TRI_BLOCK..b * TRI_BLOCK + out.len() / 3;
        let (verts, g, ws, wsv, wsh) = (
            &tris.verts[r.clone()],
            &tris.g[r.clone()],
            &tris.w_stretch[r.clone()],
            &tris.w_stretch_v[r.clone()],
            &tris.w_shear[r],
        );
        // Four triangles a pass, one a lane (`rhs_contributions_x4`); the block's last few alone.
        let quads = verts.len() / 4;
        for (q, out) in out[..12 * quads].chunks_exact_mut(12).enumerate() {
            let t = 4 * q;
            let lanes = |f: &dyn Fn(usize) -> f32| Vec4::new(f(t), f(t + 1), f(t + 2), f(t + 3));
            let x = [0, 1, 2].map(|k| [xx, xy, xz].map(|axis| lanes(&|i| axis[verts[i][k] as usize])));
            let gl = [0, 1, 2].map(|k| [0, 1].map(|j| lanes(&|i| g[i][k][j])));
            let w = [lanes(&|i| ws[i]), lanes(&|i| wsv[i])];
            let c = triangle::rhs_contributions_x4(&gl, &x, w, lanes(&|i| wsh[i]));
            for (o, c) in out.chunks_exact_mut(3).zip(c) {
                o.copy_from_slice(&c);
            }
        }
        for (t, out) in (4 * quads..verts.len()).zip(out[12 * quads..].chunks_exact_mut(3)) {
            let v = verts[t];
            out.copy_from_slice(&triangle::rhs_contributions(
                &g[t],
                [get(v[0]), get(v[1]), get(v[2])],
                [ws[t], wsv[t]],
                wsh[t],
            ));
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
        let set = model.stencil_set(set_id);
        let s = s as usize;
        let v = set.vector(s, x);
        let p = stencil::project(v, set.rest[s]) * set.weights[s];
        for (o, t) in out.iter_mut().zip(set.range(s)) {
            *o = (p * set.coefs[t]).into();
        }
    });
}
