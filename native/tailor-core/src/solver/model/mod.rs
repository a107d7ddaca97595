//! The simulated system: particles' masses, constraints, and what is derived from their topology
//! (the global matrix, the colouring, the layout of right-hand-side contributions).
//!
//! Derived structures are rebuilt lazily, only when the constraint topology or weights change
//! (seams, pins or attachments added, stiffness edited): never in the per-substep loop.
//!
//! This folder holds the solver's data, what is simulated and with which settings, apart from
//! the stages that run on it:
//!
//! * [`Model`] (this file): masses, constraints and the derived global system;
//! * [`constraints`]: the constraint kernels of the Projective Dynamics objective;
//! * [`system`]: the sparse symmetric matrix `Σ w AᵀA` (f64, and its f32 copy the sweeps read);
//! * [`colouring`]: the randomized graph colouring the parallel Gauss-Seidel sweeps follow;
//! * [`soa`]: the structure-of-arrays vectors every stage works on;
//! * [`settings`]: the fabric, the solver's settings and the presets, with validation.

pub mod colouring;
pub mod constraints;
pub mod settings;
pub mod soa;
pub mod system;

use crate::error::{Result, TailorError};
use crate::mesh::ClothMesh;

use self::colouring::{colour_graph, Colouring};
use self::constraints::bending::{hinge_weights, HingeTriangle};
use self::constraints::seam::BoundaryEdges;
use self::constraints::triangle::strain_coefficients;
use self::constraints::{Attachment, ColliderAttachment, Seam, StencilSet, TriangleSet};
use self::settings::{bend_at_angle, Fabric};
use self::soa::{vec_bytes, Vec3Soa};
use self::system::{SparseSym, SparseSym32};

/// The slot-layout id of the seam pairs' stencil set ([`Model::stencil_set`]).
pub const SEAM_PAIRS_SET: u8 = 2;

/// Where each constraint's right-hand-side contribution lands: triangles own slots `3t..3t+3`;
/// stencils with a non-zero rest length ("curved": their projection is not constant) own one
/// slot per term after those. Each particle sums its slots (compressed rows).
#[derive(Debug, Clone, Default)]
pub struct SlotLayout {
    /// `(set, stencil)` of each curved stencil: set 0 = bending, 1 = seam hinges, 2 = seam pairs
    /// still closing (see [`Model::stencil_set`]).
    pub curved: Vec<(u8, u32)>,
    pub curved_base: Vec<u32>,
    pub total: usize,
    pub particle_offsets: Vec<u32>,
    pub particle_slots: Vec<u32>,
}

/// The Gauss-Seidel sweep's view of the matrix and slot rows, in sweep order: the particles of
/// colour 0, then colour 1, and so on, each followed by its off-diagonal row and its slot list
/// stored contiguously in that order. A colour's rows are thus one contiguous stretch of memory
/// instead of every `colours`-th row of the particle-ordered matrix, which the hardware
/// prefetcher streams; this matters once the model no longer fits in cache (about 100k
/// particles). Entries keep their order within a row, so the sums are unchanged.
#[derive(Debug, Clone, Default)]
pub struct SweepRows {
    /// Sweep positions of colour `c`: `group_start[c]..group_start[c + 1]`.
    pub group_start: Vec<u32>,
    /// Particle at each sweep position.
    pub particle: Vec<u32>,
    /// Off-diagonal entries of the row at sweep position `p`: `row_offsets[p]..row_offsets[p+1]`.
    pub row_offsets: Vec<u32>,
    pub cols: Vec<u32>,
    pub vals: Vec<f32>,
    /// Slots summed by the particle at sweep position `p`: `slot_offsets[p]..slot_offsets[p+1]`.
    pub slot_offsets: Vec<u32>,
    pub slot_index: Vec<u32>,
}

impl SweepRows {
    fn new(matrix: &SparseSym32, colouring: &Colouring, slots: &SlotLayout) -> Self {
        let mut r =
            SweepRows { group_start: vec![0], row_offsets: vec![0], slot_offsets: vec![0], ..Default::default() };
        let m = colouring.groups.iter().map(Vec::len).sum();
        r.particle.reserve_exact(m);
        r.row_offsets.reserve_exact(m);
        r.slot_offsets.reserve_exact(m);
        let nnz = colouring
            .groups
            .iter()
            .flatten()
            .map(|&i| (matrix.offsets[i as usize + 1] - matrix.offsets[i as usize]) as usize)
            .sum();
        let ns = colouring
            .groups
            .iter()
            .flatten()
            .map(|&i| (slots.particle_offsets[i as usize + 1] - slots.particle_offsets[i as usize]) as usize)
            .sum();
        r.cols.reserve_exact(nnz);
        r.vals.reserve_exact(nnz);
        r.slot_index.reserve_exact(ns);
        for g in &colouring.groups {
            for &i in g {
                let i = i as usize;
                let (a, b) = (matrix.offsets[i] as usize, matrix.offsets[i + 1] as usize);
                r.cols.extend_from_slice(&matrix.cols[a..b]);
                r.vals.extend_from_slice(&matrix.vals[a..b]);
                let (a, b) = (slots.particle_offsets[i] as usize, slots.particle_offsets[i + 1] as usize);
                r.slot_index.extend_from_slice(&slots.particle_slots[a..b]);
                r.particle.push(i as u32);
                r.row_offsets.push(r.cols.len() as u32);
                r.slot_offsets.push(r.slot_index.len() as u32);
            }
            r.group_start.push(r.particle.len() as u32);
        }
        r
    }

    /// Heap bytes of the rows.
    pub fn memory_bytes(&self) -> usize {
        vec_bytes(&self.group_start)
            + vec_bytes(&self.particle)
            + vec_bytes(&self.row_offsets)
            + vec_bytes(&self.cols)
            + vec_bytes(&self.vals)
            + vec_bytes(&self.slot_offsets)
            + vec_bytes(&self.slot_index)
    }
}

impl SlotLayout {
    /// Heap bytes of the layout.
    pub fn memory_bytes(&self) -> usize {
        vec_bytes(&self.curved)
            + vec_bytes(&self.curved_base)
            + vec_bytes(&self.particle_offsets)
            + vec_bytes(&self.particle_slots)
    }
}

/// Everything about the system that is not the moving state.
#[derive(Debug, Clone)]
pub struct Model {
    pub mesh: ClothMesh,
    pub fabric: Fabric,
    /// Lumped mass per particle before scaling: density × a third of adjacent rest areas, kg.
    pub base_mass: Vec<f32>,
    pub mass_scale: Vec<f32>,
    pub mass: Vec<f32>,
    pub triangles: TriangleSet,
    pub bending: StencilSet,
    pub seams: Vec<Seam>,
    pub seam_pairs: StencilSet,
    pub seam_hinges: StencilSet,
    pub attachments: Vec<Attachment>,
    /// Attachments to points riding on mesh colliders (targets set every substep).
    pub collider_attachments: Vec<ColliderAttachment>,
    pub pinned: Vec<bool>,
    /// Whether each particle is on a seam (a vertex of some sewn pair's stencil).
    pub sewn: Vec<bool>,
    /// Per triangle, the angle of the fabric's `u` axis from the pattern's x axis, radians (0:
    /// the pattern's axes are the fabric's; `set_triangle_grain`).
    pub grain: Vec<f32>,
    // Derived, rebuilt when `dirty`.
    pub dirty: bool,
    /// Times the matrix, colouring and slot layout were rebuilt (they are kept while the
    /// topology, pins and stiffness do not change).
    pub rebuilds: u32,
    pub matrix32: SparseSym32,
    pub colouring: Colouring,
    pub slots: SlotLayout,
    pub sweep: SweepRows,
    pub b_const: Vec3Soa,
}

impl Model {
    pub fn new(mesh: ClothMesh, fabric: Fabric) -> Result<Self> {
        fabric.validate()?;
        let n = mesh.num_vertices();
        let mut base_mass = vec![0.0f64; n];
        let mut triangles = TriangleSet::default();
        let rest = mesh.rest();
        let r = |v: u32| [rest[v as usize][0] as f64, rest[v as usize][1] as f64];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let area = mesh.rest_area(t);
            let g = strain_coefficients(r(tri[0]), r(tri[1]), r(tri[2])).ok_or_else(|| {
                TailorError::DegenerateTriangle { triangle: t, reason: "its rest shape is degenerate".into() }
            })?;
            triangles.verts.push(*tri);
            triangles.g.push(g);
            let [su, sv] = fabric.stretch_uv();
            triangles.w_stretch.push((su as f64 * area) as f32);
            triangles.w_stretch_v.push((sv as f64 * area) as f32);
            triangles.w_shear.push((fabric.shear as f64 * area) as f32);
            for &v in tri {
                base_mass[v as usize] += fabric.density as f64 * area / 3.0;
            }
        }
        let mut bending = StencilSet::default();
        let directions = fabric.bend_directions();
        for (terms, area, _) in hinge_stencils(&mesh) {
            let bend = if fabric.is_isotropic() {
                fabric.bend as f64
            } else {
                bend_at_angle(directions, hinge_edge_angle(&mesh, &terms))
            };
            bending.push(&terms, bending_weight(bend, area), 0.0);
        }
        // Built by pushing: drop the growth slack (up to half the capacity) kept for the
        // lifetime of the simulation.
        triangles.shrink_to_fit();
        bending.shrink_to_fit();
        let base_mass: Vec<f32> = base_mass.into_iter().map(|m| m as f32).collect();
        for (i, &m) in base_mass.iter().enumerate() {
            if !(m > 0.0 && m.is_finite()) {
                // A vertex in no triangle has no area, hence no mass.
                return Err(TailorError::InvalidMass { particle: i, mass: m });
            }
        }
        Ok(Self {
            mass: base_mass.clone(),
            mass_scale: vec![1.0; n],
            base_mass,
            triangles,
            bending,
            seams: Vec::new(),
            seam_pairs: StencilSet::default(),
            seam_hinges: StencilSet::default(),
            attachments: Vec::new(),
            collider_attachments: Vec::new(),
            pinned: vec![false; n],
            sewn: vec![false; n],
            grain: vec![0.0; mesh.num_triangles()],
            dirty: true,
            rebuilds: 0,
            matrix32: SparseSym32::default(),
            colouring: Colouring::default(),
            slots: SlotLayout::default(),
            sweep: SweepRows::default(),
            b_const: Vec3Soa::zeros(n),
            mesh,
            fabric,
        })
    }

    pub fn n(&self) -> usize {
        self.mass.len()
    }

    /// The heap size of the model in bytes: the sum of the capacities of every `Vec` it owns
    /// (mesh, masses, constraints, seams, both matrices, colouring, slot layout, `b_const`).
    /// Fixed-size fields and allocator overhead are not counted.
    pub fn memory_bytes(&self) -> usize {
        let seams: usize =
            vec_bytes(&self.seams) + self.seams.iter().map(|s| vec_bytes(&s.pairs) + s.name.capacity()).sum::<usize>();
        self.mesh.memory_bytes()
            + vec_bytes(&self.base_mass)
            + vec_bytes(&self.mass_scale)
            + vec_bytes(&self.mass)
            + self.triangles.memory_bytes()
            + self.bending.memory_bytes()
            + seams
            + self.seam_pairs.memory_bytes()
            + self.seam_hinges.memory_bytes()
            + vec_bytes(&self.attachments)
            + vec_bytes(&self.collider_attachments)
            + vec_bytes(&self.pinned)
            + vec_bytes(&self.sewn)
            + vec_bytes(&self.grain)
            + self.matrix32.memory_bytes()
            + self.colouring.memory_bytes()
            + self.slots.memory_bytes()
            + self.sweep.memory_bytes()
            + self.b_const.memory_bytes()
    }

    /// Scales each particle's mass (painted mass maps); scales must be positive and finite.
    pub fn set_mass_scale(&mut self, scale: &[f32]) -> Result<()> {
        if scale.len() != self.n() {
            return Err(TailorError::shape("mass scale", format!("{} values for {} particles", scale.len(), self.n())));
        }
        for (i, &s) in scale.iter().enumerate() {
            if !(s > 0.0 && s.is_finite()) {
                return Err(TailorError::InvalidMass { particle: i, mass: s * self.base_mass[i] });
            }
        }
        self.mass_scale.copy_from_slice(scale);
        for ((m, &b), &s) in self.mass.iter_mut().zip(&self.base_mass).zip(scale) {
            *m = b * s;
        }
        Ok(())
    }

    /// Per-triangle stretch and shear stiffness (N/m), the same along `u` and `v`.
    pub fn set_triangle_stiffness(&mut self, stretch: &[f32], shear: &[f32]) -> Result<()> {
        self.set_triangle_stiffness_uv(stretch, stretch, shear)
    }

    /// Per-triangle stretch stiffness along `u` and along `v`, and shear stiffness (N/m).
    pub fn set_triangle_stiffness_uv(&mut self, stretch: &[f32], stretch_v: &[f32], shear: &[f32]) -> Result<()> {
        let m = self.triangles.len();
        if stretch.len() != m || stretch_v.len() != m || shear.len() != m {
            return Err(TailorError::shape(
                "triangle stiffness",
                format!(
                    "{} stretch, {} stretch_v and {} shear values for {m} triangles",
                    stretch.len(),
                    stretch_v.len(),
                    shear.len()
                ),
            ));
        }
        for t in 0..m {
            for (name, k) in [("stretch", stretch[t]), ("stretch_v", stretch_v[t]), ("shear", shear[t])] {
                if !(k >= 0.0 && k.is_finite()) {
                    return Err(TailorError::shape(
                        "triangle stiffness",
                        format!("triangle {t}: {name} {k} is invalid"),
                    ));
                }
            }
            // In f64 as `new` computes them: the same stiffness gives the same weights.
            let area = self.mesh.rest_area(t);
            self.triangles.w_stretch[t] = (stretch[t] as f64 * area) as f32;
            self.triangles.w_stretch_v[t] = (stretch_v[t] as f64 * area) as f32;
            self.triangles.w_shear[t] = (shear[t] as f64 * area) as f32;
        }
        self.dirty = true;
        Ok(())
    }

    /// Per-triangle bending stiffness (N·m): the hinge across each interior edge takes the mean
    /// of its two triangles' values, so a hinge between two fabrics (pieces are separate meshes,
    /// so only painted values meet inside one) bends as their average.
    pub fn set_triangle_bending(&mut self, bend: &[f32]) -> Result<()> {
        let m = self.triangles.len();
        if bend.len() != m {
            return Err(TailorError::shape("triangle bending", format!("{} values for {m} triangles", bend.len())));
        }
        if let Some((t, k)) = bend.iter().enumerate().find(|(_, k)| !(**k >= 0.0 && k.is_finite())) {
            return Err(TailorError::shape("triangle bending", format!("triangle {t}: bend {k} is invalid")));
        }
        // The same hinges in the same order as `new` built the stencils from.
        let weights: Vec<f32> = hinge_stencils(&self.mesh)
            .map(|(_, area, [t0, t1])| {
                bending_weight(0.5 * (bend[t0 as usize] as f64 + bend[t1 as usize] as f64), area)
            })
            .collect();
        debug_assert_eq!(weights.len(), self.bending.len());
        self.bending.weights.copy_from_slice(&weights);
        self.dirty = true;
        Ok(())
    }

    /// Per-triangle fabric orientation: `angle[t]` is the angle of the fabric's `u` axis from
    /// the pattern's x axis, radians. The triangle's strain coefficients are those of its rest
    /// shape turned by `−angle`, so that the columns of `F` are the images of the fabric's `u` and
    /// `v` (the stretch along each, the shear between them), and its hinges' directions are read
    /// from `u` ([`set_triangle_bending_directional`](Self::set_triangle_bending_directional),
    /// called after this). An angle of 0 gives the coefficients [`new`](Self::new) computed, bit
    /// for bit. A turn by a multiple of 180° changes nothing (both columns change sign).
    pub fn set_triangle_grain(&mut self, angle: &[f32]) -> Result<()> {
        let m = self.triangles.len();
        if angle.len() != m {
            return Err(TailorError::shape("triangle grain", format!("{} angles for {m} triangles", angle.len())));
        }
        if let Some((t, a)) = angle.iter().enumerate().find(|(_, a)| !a.is_finite()) {
            return Err(TailorError::shape("triangle grain", format!("triangle {t}: angle {a} is not finite")));
        }
        let rest = self.mesh.rest();
        for (t, tri) in self.mesh.triangles().iter().enumerate() {
            let (s, c) = (-angle[t] as f64).sin_cos();
            let r = |v: u32| {
                let [x, y] = [rest[v as usize][0] as f64, rest[v as usize][1] as f64];
                if angle[t] == 0.0 {
                    [x, y]
                } else {
                    [c * x - s * y, s * x + c * y]
                }
            };
            self.triangles.g[t] = strain_coefficients(r(tri[0]), r(tri[1]), r(tri[2])).ok_or_else(|| {
                TailorError::DegenerateTriangle { triangle: t, reason: "its rest shape is degenerate".into() }
            })?;
        }
        self.grain.copy_from_slice(angle);
        self.dirty = true;
        Ok(())
    }

    /// Per-triangle bending stiffness by direction (N·m, `[u, bias, v]` as
    /// [`Fabric::bend_directions`]): each hinge takes the mean of its two triangles' values at
    /// its edge's direction in the pattern ([`bend_at_angle`]). A triangle whose three values
    /// are equal bends as [`set_triangle_bending`](Self::set_triangle_bending) gives it.
    pub fn set_triangle_bending_directional(&mut self, bend: &[[f32; 3]]) -> Result<()> {
        let m = self.triangles.len();
        if bend.len() != m {
            return Err(TailorError::shape("triangle bending", format!("{} values for {m} triangles", bend.len())));
        }
        if let Some((t, k)) = bend.iter().enumerate().find(|(_, k)| !k.iter().all(|k| *k >= 0.0 && k.is_finite())) {
            return Err(TailorError::shape("triangle bending", format!("triangle {t}: bend {k:?} is invalid")));
        }
        let weights: Vec<f32> = hinge_stencils(&self.mesh)
            .map(|(terms, area, [t0, t1])| {
                let angle = hinge_edge_angle(&self.mesh, &terms);
                let at = |t: u32| {
                    let b = bend[t as usize];
                    if b[0] == b[1] && b[1] == b[2] {
                        b[0] as f64
                    } else {
                        // The edge's angle from the fabric's u axis in this triangle.
                        bend_at_angle(b, angle - self.grain[t as usize] as f64)
                    }
                };
                bending_weight(0.5 * (at(t0) + at(t1)), area)
            })
            .collect();
        debug_assert_eq!(weights.len(), self.bending.len());
        self.bending.weights.copy_from_slice(&weights);
        self.dirty = true;
        Ok(())
    }

    /// Bending rest shape from a 3D pose (keeps creases and pre-shaped folds); `None` = flat.
    pub fn set_bending_rest(&mut self, pose: Option<&Vec3Soa>) {
        match pose {
            Some(p) => {
                self.bending.set_rest_from(p);
                self.seam_hinges.set_rest_from(p);
            }
            None => {
                self.bending.rest.iter_mut().for_each(|r| *r = 0.0);
                self.seam_hinges.rest.iter_mut().for_each(|r| *r = 0.0);
            }
        }
        self.dirty = true;
    }

    /// Adds a seam (validated against this mesh). Returns the number of hinges it created.
    pub fn add_seam(&mut self, seam: Seam) -> Result<usize> {
        seam.validate(self.n())?;
        let first = self.seam_pairs.verts.len();
        seam.push_pairs(&mut self.seam_pairs);
        for &v in &self.seam_pairs.verts[first..] {
            self.sewn[v as usize] = true;
        }
        let boundary = BoundaryEdges::new(&self.mesh);
        let hinges = seam.push_hinges(&self.mesh, &boundary, &mut self.seam_hinges);
        self.seams.push(seam);
        self.dirty = true;
        Ok(hinges)
    }

    pub fn add_attachment(&mut self, a: Attachment) -> Result<()> {
        let n = self.n();
        if a.particle as usize >= n {
            return Err(TailorError::index("attachment", a.particle as i64, n, "particles"));
        }
        if !(a.weight > 0.0 && a.weight.is_finite()) || a.target.iter().any(|c| !c.is_finite()) {
            return Err(TailorError::shape(
                "attachment",
                format!(
                    "particle {}: weight {} and target {:?} must be finite (weight > 0)",
                    a.particle, a.weight, a.target
                ),
            ));
        }
        self.attachments.push(a);
        self.dirty = true;
        Ok(())
    }

    /// Updates attachment targets without touching the matrix (animated attachments).
    pub fn set_attachment_targets(&mut self, targets: &[[f32; 3]]) -> Result<()> {
        if targets.len() != self.attachments.len() {
            return Err(TailorError::shape(
                "attachment targets",
                format!("{} targets for {} attachments", targets.len(), self.attachments.len()),
            ));
        }
        crate::mesh::check_finite3("attachment targets", targets)?;
        for (a, t) in self.attachments.iter_mut().zip(targets) {
            a.target = *t;
        }
        self.update_b_const();
        Ok(())
    }

    fn update_b_const(&mut self) {
        self.b_const = Vec3Soa::zeros(self.n());
        for a in &self.attachments {
            let i = a.particle as usize;
            let t = glam::Vec3::from(a.target) * a.weight;
            self.b_const.set(i, self.b_const.get(i) + t);
        }
    }

    /// Assembles the constant matrix `L` in f64 (the reference solver's; the real-time solver
    /// keeps only [`Model::matrix32`], which saves about 130 bytes per particle).
    pub fn assemble_matrix(&self) -> SparseSym {
        SparseSym::assemble(
            self.n(),
            &self.triangles,
            &[&self.bending, &self.seam_pairs, &self.seam_hinges],
            self.attachments
                .iter()
                .map(|a| (a.particle, a.weight))
                .chain(self.collider_attachments.iter().map(|a| (a.particle, a.weight))),
        )
    }

    /// The stencil set with a slot-layout id (0 bending, 1 seam hinges, 2 seam pairs).
    pub fn stencil_set(&self, id: u8) -> &StencilSet {
        match id {
            0 => &self.bending,
            1 => &self.seam_hinges,
            _ => &self.seam_pairs,
        }
    }

    /// Rebuilds the matrix, colouring and slot layout if anything changed.
    pub fn rebuild_if_dirty(&mut self, seed: u64) {
        if !self.dirty {
            return;
        }
        // The f64 matrix is not kept: only the reference solver needs it, and assembles its own.
        let matrix = self.assemble_matrix();
        self.matrix32 = matrix.to_f32();
        drop(matrix);
        let mut colouring = colour_graph(&self.matrix32.offsets, &self.matrix32.cols, seed);
        // Pinned particles are not unknowns: drop them from the sweep.
        for g in &mut colouring.groups {
            g.retain(|&i| !self.pinned[i as usize]);
        }
        colouring.groups.retain(|g| !g.is_empty());
        self.colouring = colouring;
        self.slots = self.slot_layout();
        self.sweep = SweepRows::new(&self.matrix32, &self.colouring, &self.slots);
        self.update_b_const();
        self.dirty = false;
        self.rebuilds += 1;
    }

    fn slot_layout(&self) -> SlotLayout {
        let n = self.n();
        let mut curved = Vec::new();
        let mut curved_base = Vec::new();
        let mut total = 3 * self.triangles.len();
        for (set_id, set) in [(0u8, &self.bending), (1u8, &self.seam_hinges), (SEAM_PAIRS_SET, &self.seam_pairs)] {
            for s in 0..set.len() {
                if set.rest[s] != 0.0 {
                    curved.push((set_id, s as u32));
                    curved_base.push(total as u32);
                    total += set.range(s).len();
                }
            }
        }
        // Owner particle of every slot, then compressed rows by particle.
        let mut owner = vec![0u32; total];
        for (t, v) in self.triangles.verts.iter().enumerate() {
            owner[3 * t..3 * t + 3].copy_from_slice(v);
        }
        for (c, &(set_id, s)) in curved.iter().enumerate() {
            let set = self.stencil_set(set_id);
            for (k, t) in set.range(s as usize).enumerate() {
                owner[curved_base[c] as usize + k] = set.verts[t];
            }
        }
        let mut particle_offsets = vec![0u32; n + 1];
        for &o in &owner {
            particle_offsets[o as usize + 1] += 1;
        }
        for i in 0..n {
            particle_offsets[i + 1] += particle_offsets[i];
        }
        let mut fill = particle_offsets.clone();
        let mut particle_slots = vec![0u32; total];
        for (slot, &o) in owner.iter().enumerate() {
            particle_slots[fill[o as usize] as usize] = slot as u32;
            fill[o as usize] += 1;
        }
        SlotLayout { curved, curved_base, total, particle_offsets, particle_slots }
    }
}

/// The bending stencil of each interior edge with a non-degenerate hinge, in topology order:
/// its four `(vertex, coefficient)` terms, the hinge's rest area and its two triangles.
pub(crate) fn hinge_stencils(mesh: &ClothMesh) -> impl Iterator<Item = ([(u32, f32); 4], f64, [u32; 2])> + '_ {
    let rest = mesh.rest();
    let r = move |v: u32| [rest[v as usize][0] as f64, rest[v as usize][1] as f64];
    mesh.topology().hinges.iter().filter_map(move |h| {
        let [e0, e1, o0, o1] = h.vertices;
        let t0 = HingeTriangle { e0: r(e0), e1: r(e1), o: r(o0) };
        let t1 = HingeTriangle { e0: r(e0), e1: r(e1), o: r(o1) };
        hinge_weights(&t0, &t1).map(|(k, area)| {
            ([(e0, k[0] as f32), (e1, k[1] as f32), (o0, k[2] as f32), (o1, k[3] as f32)], area, h.triangles)
        })
    })
}

/// A hinge's stencil weight for bending stiffness `bend` (N·m) over rest area `area` (the
/// quadratic bending energy's 3k/A).
/// The direction of a hinge's edge in the pattern, radians from the x axis (`u`): its stencil's
/// first two terms are the edge's ends ([`hinge_stencils`]).
fn hinge_edge_angle(mesh: &ClothMesh, terms: &[(u32, f32); 4]) -> f64 {
    let rest = mesh.rest();
    let (a, b) = (rest[terms[0].0 as usize], rest[terms[1].0 as usize]);
    ((b[1] - a[1]) as f64).atan2((b[0] - a[0]) as f64)
}

pub(crate) fn bending_weight(bend: f64, area: f64) -> f32 {
    (3.0 * bend / area) as f32
}
