//! Uploading a simulation to the GPU: what the GPU cannot run (refused before any work), the
//! collider hash's capacity for a frame, and the upload itself: the model packed into the
//! index and float buffers (sections addressed by `Params`), the per-particle and per-collider
//! data, the seams' closing state and the moving state, into buffers reused while they fit.

use bytemuck::Zeroable;

use super::buffers::{Buffers, Capacities};
use super::collide_common::{self, buckets_for, MeshInfo, Meshes, TableInfo, MAX_MESHES};
use super::common::{
    Collider, Contact, Params, StepState, KIND_CAPSULE, KIND_PLANE, KIND_SPHERE, PARTICLE_PINNED, PARTICLE_SEWN,
};
use super::gauss_seidel::ColourRange;
use super::pipelines::BindGroups;
use super::predict::Particle;
use super::{attach, close_seams, phase_to_gpu, project_triangles, GpuFailure, GpuSolver, Uploaded};
use crate::collision::InsertionRule;
use crate::solver::collide::collider_filing::PAD;
use crate::solver::collide::mesh_collider::MeshCollider;
use crate::solver::model::settings::Method;
use crate::solver::model::SEAM_PAIRS_SET;
use crate::solver::SelfContacts;
use crate::solver::SolverView;

impl GpuSolver {
    /// Why `sim` cannot run on the GPU yet, if it cannot (call after `gpu_view`).
    pub(super) fn unsupported(view: &SolverView<'_>) -> Option<String> {
        if view.settings.method == Method::Jacobi {
            return Some("the Jacobi method".into());
        }
        let own = view.collide.self_settings;
        if own.enabled && own.contacts == SelfContacts::Triangles {
            return Some("triangle self-contacts (CPU only)".into());
        }
        // One dimension of dispatches covers 65535 workgroups of 64.
        let m = view.model;
        const DISPATCH: usize = 65_535 * 64;
        if view.x.len() > DISPATCH || m.triangles.len() > DISPATCH || m.slots.curved.len() > DISPATCH {
            return Some(format!("more than {DISPATCH} particles or triangles"));
        }
        let meshes = &view.collide.meshes;
        if meshes.len() > MAX_MESHES {
            return Some(format!("more than {MAX_MESHES} mesh colliders ({})", meshes.len()));
        }
        let tris: usize = meshes.iter().map(|m| m.tris.len()).sum();
        let verts: usize = meshes.iter().map(|m| m.next.len()).sum();
        let buckets: usize = meshes.iter().map(|m| buckets_for(m.tris.len())).sum();
        if tris > DISPATCH || verts > DISPATCH || buckets > DISPATCH || buckets_for(view.x.len()) > DISPATCH {
            return Some(format!("more than {DISPATCH} collider vertices, triangles or hash buckets"));
        }
        None
    }

    /// Upper bound on the insertions of the colliders' hash at any substep of the coming
    /// frame: per triangle, the cells of its padded AABB, whose extent along each axis is at
    /// most the larger of its extents at the frame's two ends (linear interpolation).
    pub(super) fn mesh_entry_bound(meshes: &[MeshCollider]) -> usize {
        let mut total = 0usize;
        for m in meshes {
            let l = m.cell;
            for t in &m.tris {
                let mut cells = 1usize;
                for k in 0..3 {
                    let mut e = 0.0f32;
                    for p in [&m.prev, &m.next, &m.cur] {
                        let v = t.map(|i| p[i as usize][k]);
                        e = e.max(v[0].max(v[1]).max(v[2]) - v[0].min(v[1]).min(v[2]));
                    }
                    // An interval of length e covers at most floor(e/l) + 2 cells; the margin
                    // covers rounding of the padded bounds.
                    cells *= ((e + 2.0 * PAD * l) / l * (1.0 + 1e-4)) as usize + 2;
                }
                total += cells;
            }
        }
        total
    }

    /// Uploads the model and state (reusing buffers that are large enough).
    pub(super) fn upload(&mut self, view: &SolverView<'_>) -> Result<(), GpuFailure> {
        if let Some(why) = Self::unsupported(view) {
            return Err(GpuFailure::Unsupported(why));
        }
        let m = view.model;
        let n = m.n();
        let nt = m.triangles.len();
        let sp = &m.seam_pairs;
        let mat = &m.matrix32;
        let lay = &m.slots;

        // Packed index data, sections in the order of `Params`.
        let mut idx: Vec<u32> = Vec::new();
        let base = |idx: &mut Vec<u32>, data: &[u32]| {
            let b = idx.len() as u32;
            idx.extend_from_slice(data);
            b
        };
        let mut p = Params::zeroed();
        p.mat_off = base(&mut idx, &mat.offsets);
        p.mat_cols = base(&mut idx, &mat.cols);
        p.slot_off = base(&mut idx, &lay.particle_offsets);
        p.slot_idx = base(&mut idx, &lay.particle_slots);
        let tv: Vec<u32> = m.triangles.verts.iter().flatten().copied().collect();
        p.tri_verts = base(&mut idx, &tv);
        p.seam_off = base(&mut idx, &sp.offsets);
        p.seam_verts = base(&mut idx, &sp.verts);
        let mut colours = Vec::with_capacity(m.colouring.groups.len());
        let order: Vec<u32> = m.colouring.groups.iter().flatten().copied().collect();
        let mut start = 0u32;
        for g in &m.colouring.groups {
            colours.push(ColourRange { start, count: g.len() as u32, _pad0: 0, _pad1: 0 });
            start += g.len() as u32;
        }
        p.order = base(&mut idx, &order);
        // Curved stencils as one compressed-row set, in slot order.
        let (mut c_off, mut c_verts, mut c_coefs, mut c_wr) = (vec![0u32], Vec::new(), Vec::new(), Vec::new());
        for &(set_id, st) in &lay.curved {
            let set = m.stencil_set(set_id);
            let st = st as usize;
            for t in set.range(st) {
                c_verts.push(set.verts[t]);
                c_coefs.push(set.coefs[t]);
            }
            c_off.push(c_verts.len() as u32);
            c_wr.extend_from_slice(&[set.weights[st], set.rest[st]]);
        }
        // Each seam pair's closing state; its rest length lives in its curved stencil, if any.
        let mut pair_state: Vec<close_seams::PairState> = (0..sp.len())
            .map(|s| {
                let left = view.closing_left.get(s).copied().unwrap_or(0.0);
                let gap0 = view.closing_gap0.get(s).copied().unwrap_or(0.0);
                [gap0, left, f32::from_bits(close_seams::NOT_CURVED), sp.rest[s]]
            })
            .collect();
        for (c, &(set_id, st)) in lay.curved.iter().enumerate() {
            if set_id == SEAM_PAIRS_SET {
                pair_state[st as usize][2] = f32::from_bits(c as u32);
            }
        }
        p.curved_off = base(&mut idx, &c_off);
        p.curved_verts = base(&mut idx, &c_verts);

        // Mesh colliders: global triangle vertices and levels, per-collider layout.
        let col = view.collide;
        let mut meshes = Meshes::zeroed();
        let (mut tri_idx, mut tri_levels, mut mesh_vert_off) = (Vec::new(), Vec::new(), Vec::new());
        let (mut voff, mut toff, mut boff) = (0u32, 0u32, 0u32);
        for (c, mc) in col.meshes.iter().enumerate() {
            let nb = buckets_for(mc.tris.len()) as u32;
            meshes.m[c] = MeshInfo {
                cell: mc.cell,
                vert_off: voff,
                n_verts: mc.next.len() as u32,
                tri_off: toff,
                n_tris: mc.tris.len() as u32,
                bucket_off: boff,
                mask: nb - 1,
                rule: match mc.opts.rule {
                    InsertionRule::Paper => collide_common::RULE_PAPER,
                    InsertionRule::PaperOrPlane => collide_common::RULE_PAPER_OR_PLANE,
                    InsertionRule::Aabb => collide_common::RULE_AABB,
                },
                moving: mc.moving as u32,
                static_friction: mc.opts.static_friction,
                kinetic_friction: mc.opts.kinetic_friction,
                _pad0: 0,
            };
            mesh_vert_off.push(voff);
            tri_idx.extend(mc.tris.iter().flat_map(|t| t.map(|v| v + voff)));
            tri_levels.extend(mc.tri_level.iter().map(|&l| l as u32));
            voff += mc.next.len() as u32;
            toff += mc.tris.len() as u32;
            boff += nb;
        }
        let (n_mesh_verts, n_mesh_tris, mesh_buckets) = (voff as usize, toff as usize, boff as usize);
        // Collider attachments: each bound triangle's vertices as global `mverts` indices.
        let attachments: Vec<attach::Attachment> = m
            .collider_attachments
            .iter()
            .map(|a| {
                let c = a.collider as usize;
                let tri = col.meshes[c].tris[a.triangle as usize];
                attach::Attachment {
                    particle: a.particle,
                    verts: tri.map(|v| v + mesh_vert_off[c]),
                    bary: a.bary,
                    weight: a.weight,
                    local: a.local,
                    last: a.target,
                    ..Default::default()
                }
            })
            .collect();
        let mesh_entries = if col.meshes.is_empty() { 0 } else { Self::mesh_entry_bound(&col.meshes) * 5 / 4 };
        meshes.entries_off = boff + 1;
        p.n_meshes = col.meshes.len() as u32;
        p.n_mesh_verts = voff;
        p.n_mesh_tris = toff;
        p.mesh_tris = base(&mut idx, &tri_idx);
        p.tri_levels = base(&mut idx, &tri_levels);
        let levels: Vec<u32> = col.levels.iter().map(|&l| l as u32).collect();
        p.particle_levels = base(&mut idx, &levels);
        let pinned: Vec<u32> = m.pinned.iter().map(|&b| b as u32).collect();
        p.pinned = base(&mut idx, &pinned);
        // Self-collision: the CPU's exclusion set (it skips the pass when that cannot be built).
        let excl = if col.self_settings.enabled {
            crate::solver::collide::self_collide::build_exclusions(m, view.self_radius).ok()
        } else {
            None
        };
        let self_enabled = excl.is_some();
        if let Some(ex) = &excl {
            let (off, nbr) = ex.csr();
            p.excl_off = base(&mut idx, off);
            p.excl_nbr = base(&mut idx, nbr);
        }
        let self_buckets = if self_enabled { buckets_for(n) } else { 0 };
        p.self_enabled = self_enabled as u32;
        p.self_radius = view.self_radius;
        p.self_cell = view.self_cell;
        p.self_mu_s = col.self_settings.static_friction;
        p.self_mu_k = col.self_settings.kinetic_friction;
        p.self_mask = self_buckets.max(1) as u32 - 1;

        // The two-level step's coarse grid, when the CPU's step would run it.
        let coarse = view.coarse.map(|c| c.gpu_layout());
        let n_coarse = coarse.as_ref().map_or(0, |c| c.diag0.len());
        if let Some(c) = &coarse {
            p.n_coarse = n_coarse as u32;
            p.coarse_iterations = crate::solver::stages::coarse::COARSE_CG_ITERATIONS as u32;
            p.coarse_agg = base(&mut idx, c.agg);
            p.coarse_member_off = base(&mut idx, &c.member_offsets);
            p.coarse_members = base(&mut idx, &c.members);
            p.coarse_off = base(&mut idx, c.offsets);
            p.coarse_cols = base(&mut idx, c.cols);
        }

        let mut fdata: Vec<f32> = Vec::new();
        let fbase = |f: &mut Vec<f32>, data: &[f32]| {
            let b = f.len() as u32;
            f.extend_from_slice(data);
            b
        };
        if let Some(c) = &coarse {
            p.coarse_vals = fbase(&mut fdata, c.vals);
            p.coarse_diag0 = fbase(&mut fdata, c.diag0);
        }
        p.mat_vals = fbase(&mut fdata, &mat.vals);
        p.diag = fbase(&mut fdata, view.diag);
        let mut td = Vec::with_capacity(nt * project_triangles::TRI_FLOATS);
        for t in 0..nt {
            let g = m.triangles.g[t];
            td.extend_from_slice(&[g[0][0], g[0][1], g[1][0], g[1][1], g[2][0], g[2][1]]);
            td.push(m.triangles.w_stretch[t]);
            td.push(m.triangles.w_shear[t]);
            td.push(m.triangles.w_stretch_v[t]);
        }
        p.tri_data = fbase(&mut fdata, &td);
        p.seam_coefs = fbase(&mut fdata, &sp.coefs);
        p.curved_coefs = fbase(&mut fdata, &c_coefs);
        p.curved_wr = fbase(&mut fdata, &c_wr);
        if let Some((fs, fk)) = &col.friction {
            let pairs: Vec<f32> = fs.iter().zip(fk).flat_map(|(&a, &b)| [a, b]).collect();
            p.has_friction = 1;
            p.friction = fbase(&mut fdata, &pairs);
        }
        p.n_curved = lay.curved.len() as u32;
        let colliders: Vec<Collider> = view
            .colliders
            .iter()
            .map(|c| {
                let (kind, p0, p1, radius) = match c.shape {
                    crate::solver::Shape::Plane { point, normal } => (KIND_PLANE, point, normal, 0.0),
                    crate::solver::Shape::Sphere { center, radius } => (KIND_SPHERE, center, [0.0; 3], radius),
                    crate::solver::Shape::Capsule { a, b, radius } => (KIND_CAPSULE, a, b, radius),
                };
                Collider {
                    p0,
                    radius,
                    p1,
                    kind,
                    static_friction: c.static_friction,
                    kinetic_friction: c.kinetic_friction,
                    _pad0: 0,
                    _pad1: 0,
                }
            })
            .collect();
        p.n_colliders = colliders.len() as u32;
        p.thickness = view.thickness;

        let s = view.settings;
        let h = view.h;
        p.gravity = s.gravity;
        p.h = h;
        p.inv_h = 1.0 / h;
        p.inv_h2 = 1.0 / (h * h);
        p.rho = view.rho;
        p.n = n as u32;
        p.n_tris = nt as u32;
        p.n_seam_pairs = sp.len() as u32;
        p.delay = s.chebyshev.delay;
        p.ramp_enabled = s.ramp.enabled as u32;
        p.air_damping = s.air_damping;
        p.closing_damping = s.ramp.closing_damping;
        p.gap_threshold = s.ramp.gap_threshold;
        p.closed_fraction = s.ramp.closed_fraction;
        p.release_time = s.ramp.release_time;
        p.has_seams = (!sp.is_empty()) as u32;
        p.substeps = s.substeps;
        p.iterations = s.iterations;
        p.release_gap = s.ramp.release_gap;
        p.closing_gravity = s.ramp.closing_gravity;
        p.closing_speed = s.ramp.closing_speed;
        let closing_scheduled = view.seams_closing && !sp.is_empty();
        p.closing_scheduled = closing_scheduled as u32;

        let need = Capacities {
            n,
            slots: lay.total,
            idx: idx.len(),
            fdata: fdata.len(),
            colours: colours.len(),
            colliders: colliders.len(),
            mesh_verts: n_mesh_verts,
            mesh_tris: n_mesh_tris,
            mesh_buckets,
            mesh_entries,
            self_buckets,
            attachments: attachments.len(),
            seam_pairs: sp.len(),
            coarse: n_coarse,
        };
        let stride = self.ctx.device.limits().min_uniform_buffer_offset_alignment.max(16) as u64;
        let realloc = self.buffers.as_ref().is_none_or(|b| !b.caps.fits(&need));
        if realloc {
            self.buffers = Some(Buffers::new(&self.ctx.device, need, stride));
            self.binds = None;
        }
        let b = self.buffers.as_ref().ok_or_else(|| GpuFailure::Device("buffers missing".into()))?;
        let q = &self.ctx.queue;
        let vec4 = |s: &crate::solver::Vec3Soa| -> Vec<[f32; 4]> {
            (0..s.len()).map(|i| [s.x[i], s.y[i], s.z[i], 0.0]).collect()
        };
        let sewn = &m.sewn;
        let particles: Vec<Particle> = (0..n)
            .map(|i| Particle {
                b_const: m.b_const.get(i).to_array(),
                mass: m.mass[i],
                pin_target: view.pin_target.get(i).to_array(),
                flags: if m.pinned[i] { PARTICLE_PINNED } else { 0 } | if sewn[i] { PARTICLE_SEWN } else { 0 },
            })
            .collect();
        let (phase, elapsed) = phase_to_gpu(view.ramp.phase);
        // The early stop's floor, as `Simulation::prepare` computes it (from the full gravity,
        // also while the ramp holds it).
        let g2 = view.settings.gravity.iter().map(|&g| (g as f64).powi(2)).sum::<f64>();
        let weight_norm = (0..n).filter(|&i| !m.pinned[i]).map(|i| (m.mass[i] as f64).powi(2) * g2).sum::<f64>().sqrt();
        let (stall_on, (stall_best, stall_since)) = (view.ramp.stall.is_some(), view.ramp.stall.unwrap_or_default());
        let state = StepState {
            omega: 1.0,
            phase,
            elapsed,
            tolerance: view.settings.tolerance,
            weight_norm: weight_norm as f32,
            closing: view.seams_closing as u32,
            stall_on: stall_on as u32,
            stall_best,
            stall_since,
            ..StepState::zeroed()
        };
        q.write_buffer(&b.params, 0, bytemuck::bytes_of(&p));
        q.write_buffer(&b.state, 0, bytemuck::bytes_of(&state));
        q.write_buffer(&b.particles, 0, bytemuck::cast_slice(&particles));
        q.write_buffer(&b.x, 0, bytemuck::cast_slice(&vec4(view.x)));
        q.write_buffer(&b.v, 0, bytemuck::cast_slice(&vec4(view.v)));
        // Pinned particles are in no colour, so their update norms must read zero.
        q.write_buffer(&b.norms, 0, bytemuck::cast_slice(&vec![[0.0f32; 2]; n]));
        let no_contact = Contact { collider: u32::MAX, ..Contact::zeroed() };
        q.write_buffer(&b.contacts, 0, bytemuck::cast_slice(&vec![no_contact; n]));
        if !colliders.is_empty() {
            q.write_buffer(&b.colliders, 0, bytemuck::cast_slice(&colliders));
        }
        if !idx.is_empty() {
            q.write_buffer(&b.idx, 0, bytemuck::cast_slice(&idx));
        }
        if !fdata.is_empty() {
            q.write_buffer(&b.fdata, 0, bytemuck::cast_slice(&fdata));
        }
        if n_mesh_verts > 0 {
            // Sections: previous, next, this substep's positions, velocities, then normals.
            let mut mv = vec![[0.0f32; 4]; 4 * n_mesh_verts];
            let v4 = |p: [f32; 3]| [p[0], p[1], p[2], 0.0];
            for (c, mc) in col.meshes.iter().enumerate() {
                let o = mesh_vert_off[c] as usize;
                for (k, v) in mc.next.iter().enumerate() {
                    mv[o + k] = v4(mc.prev[k]);
                    mv[n_mesh_verts + o + k] = v4(*v);
                    mv[2 * n_mesh_verts + o + k] = v4(mc.cur[k]);
                    mv[3 * n_mesh_verts + o + k] = v4(mc.vel[k].into());
                }
            }
            q.write_buffer(&b.mverts, 0, bytemuck::cast_slice(&mv));
            q.write_buffer(&b.mcounts, 0, bytemuck::cast_slice(&vec![0u32; mesh_buckets]));
        }
        let table = |n_buckets: usize, n_entries: usize| TableInfo {
            n_buckets: n_buckets as u32,
            n_entries: n_entries as u32,
            ..Default::default()
        };
        q.write_buffer(&b.mesh_table_info, 0, bytemuck::bytes_of(&table(mesh_buckets, mesh_entries)));
        q.write_buffer(&b.self_table_info, 0, bytemuck::bytes_of(&table(self_buckets, n)));
        q.write_buffer(&b.meshes, 0, bytemuck::bytes_of(&meshes));
        let info = attach::AttachInfo { n: attachments.len() as u32, ..Default::default() };
        q.write_buffer(&b.attach_info, 0, bytemuck::bytes_of(&info));
        if !attachments.is_empty() {
            q.write_buffer(&b.attachments, 0, bytemuck::cast_slice(&attachments));
        }
        if !pair_state.is_empty() {
            q.write_buffer(&b.closing, 0, bytemuck::cast_slice(&pair_state));
        }
        if self_enabled {
            q.write_buffer(&b.scounts, 0, bytemuck::cast_slice(&vec![0u32; self_buckets]));
        }
        q.write_buffer(&b.sdelta, 0, bytemuck::cast_slice(&vec![[0.0f32; 4]; n]));
        let mut cbytes = vec![0u8; colours.len().max(1) * stride as usize];
        for (c, r) in colours.iter().enumerate() {
            let o = c * stride as usize;
            cbytes[o..o + 16].copy_from_slice(bytemuck::bytes_of(r));
        }
        q.write_buffer(&b.colours, 0, &cbytes);

        // Bind groups depend on the buffers and on the colour count only.
        let rebind = self.binds.as_ref().is_none_or(|g| g.gauss_seidel.len() != colours.len());
        if rebind {
            self.binds = Some(BindGroups::new(&self.ctx.device, &self.ctx.pipelines, b, colours.len(), stride));
        }
        self.uploaded = Some(Uploaded {
            n,
            n_tris: nt,
            n_curved: lay.curved.len(),
            n_colliders: colliders.len(),
            n_meshes: col.meshes.len(),
            n_mesh_verts,
            n_mesh_tris,
            mesh_buckets,
            mesh_vert_off,
            meshes,
            self_enabled,
            self_buckets,
            n_attach: attachments.len(),
            early_stop: s.tolerance > 0.0,
            closing_scheduled,
            n_seam_pairs: sp.len(),
            colours,
            h,
            rho: view.rho,
            method: s.method,
            n_coarse,
        });
        self.dirty = false;
        self.mesh_hash_valid = false;
        Ok(())
    }
}
