//! Rust mirrors of the structs in `common.wgsl`, and the shader-source assembly every stage uses.

use bytemuck::{Pod, Zeroable};

/// Source of the shared declarations, prepended to every stage's shader.
pub const COMMON_WGSL: &str = include_str!("common.wgsl");

/// Ramp phases as the shaders encode them.
pub const PHASE_CLOSING: u32 = 0;
pub const PHASE_RELEASING: u32 = 1;
pub const PHASE_DONE: u32 = 2;

/// Mirror of WGSL `Params` (uniform; 288 bytes). `gravity` is a `vec3<f32>` (16-byte aligned,
/// 12 bytes) followed by `h`, so no padding is needed there; the size is a multiple of 16.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Params {
    pub gravity: [f32; 3],
    pub h: f32,
    pub inv_h: f32,
    pub inv_h2: f32,
    pub rho: f32,
    pub n: u32,
    pub n_tris: u32,
    pub n_seam_pairs: u32,
    pub delay: u32,
    pub ramp_enabled: u32,
    pub air_damping: f32,
    pub closing_damping: f32,
    pub gap_threshold: f32,
    pub closed_fraction: f32,
    pub release_time: f32,
    pub has_seams: u32,
    pub mat_off: u32,
    pub mat_cols: u32,
    pub slot_off: u32,
    pub slot_idx: u32,
    pub tri_verts: u32,
    pub seam_off: u32,
    pub seam_verts: u32,
    pub order: u32,
    pub mat_vals: u32,
    pub diag: u32,
    pub tri_data: u32,
    pub seam_coefs: u32,
    pub n_curved: u32,
    pub curved_off: u32,
    pub curved_verts: u32,
    pub curved_coefs: u32,
    pub curved_wr: u32,
    pub n_colliders: u32,
    pub thickness: f32,
    pub substeps: u32,
    pub n_meshes: u32,
    pub n_mesh_verts: u32,
    pub n_mesh_tris: u32,
    pub mesh_tris: u32,
    pub tri_levels: u32,
    pub particle_levels: u32,
    pub pinned: u32,
    pub has_friction: u32,
    pub friction: u32,
    pub self_enabled: u32,
    pub self_radius: f32,
    pub self_cell: f32,
    pub self_mu_s: f32,
    pub self_mu_k: f32,
    pub self_mask: u32,
    pub excl_off: u32,
    pub excl_nbr: u32,
    /// Iterations per substep: the last one is a plain sweep (`Chebyshev::omega`).
    pub iterations: u32,
    pub release_gap: f32,
    pub closing_gravity: f32,
    pub closing_speed: f32,
    /// Pairs were on their closing schedule at upload: `close_seams` runs every substep.
    pub closing_scheduled: u32,
    /// The two-level step's coarse grid (`coarse.wgsl`): aggregates (0: off), CG iterations,
    /// and its sections of `idx` and `fdata`.
    pub n_coarse: u32,
    pub coarse_iterations: u32,
    pub coarse_agg: u32,
    pub coarse_member_off: u32,
    pub coarse_members: u32,
    pub coarse_off: u32,
    pub coarse_cols: u32,
    pub coarse_vals: u32,
    pub coarse_diag0: u32,
    pub _pad_coarse: [u32; 3],
}

/// Mirror of WGSL `StepState` (storage; 104 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct StepState {
    pub omega: f32,
    pub last_delta: f32,
    pub started: u32,
    pub k: u32,
    pub r0: f32,
    pub residual: f32,
    pub phase: u32,
    pub elapsed: f32,
    pub gap_max: f32,
    pub closed_fraction: f32,
    /// Particles in contact after the last substep's iterations.
    pub contacts: u32,
    /// Substep of the frame being run (the ramp stage wraps it to 0 after the last).
    pub substep: u32,
    /// Particles touching a mesh collider after the last substep.
    pub mesh_contacts: u32,
    /// Overlapping cloth pairs of the last self-collision pass.
    pub self_pairs: u32,
    /// Early stop: the substep has converged, iteration stages do nothing (set by `gate`).
    pub done: u32,
    /// Set by `reduce_omega` when the residual is under `tolerance` (see `common.wgsl`).
    pub stop: u32,
    pub tolerance: f32,
    /// ‖m·g‖ over the free particles, the residual's floor in the early-stop test.
    pub weight_norm: f32,
    /// Iterations run in the frame.
    pub iterations_run: u32,
    /// The fastest particle's speed after the frame's last substep (f32 bits; atomic in WGSL).
    pub max_speed_bits: u32,
    /// Some seam pair still has closing schedule left.
    pub closing: u32,
    /// The ramp's stall watch: on, the smallest widest gap so far (m), seconds since it shrank.
    pub stall_on: u32,
    pub stall_best: f32,
    pub stall_since: f32,
    /// The substep's first sweep's update norm, and whether an update outgrew it `RUNAWAY` times (then plain
    /// sweeps to the substep's end: `Chebyshev::omega`).
    pub first_delta: f32,
    pub diverging: u32,
}

/// Mirror of WGSL `Particle` (32 bytes): each `vec3<f32>` is followed by a 4-byte scalar,
/// which fills the vec3's 16-byte slot, so the Rust `[f32; 3]` + scalar layout matches.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Particle {
    pub b_const: [f32; 3],
    pub mass: f32,
    pub pin_target: [f32; 3],
    /// [`PARTICLE_PINNED`] | [`PARTICLE_SEWN`].
    pub flags: u32,
}

/// `Particle::flags`: the particle is a hard pin (removed from the unknowns).
pub const PARTICLE_PINNED: u32 = 1;
/// `Particle::flags`: the particle is on a seam (`Model::sewn`).
pub const PARTICLE_SEWN: u32 = 2;

/// Collider kinds as `Collider::kind` encodes them.
pub const KIND_PLANE: u32 = 0;
pub const KIND_SPHERE: u32 = 1;
pub const KIND_CAPSULE: u32 = 2;

/// Mirror of WGSL `Collider` (48 bytes): each `vec3<f32>` is followed by a scalar that fills
/// its 16-byte slot; explicit tail padding to the 16-byte struct alignment.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Collider {
    pub p0: [f32; 3],
    pub radius: f32,
    pub p1: [f32; 3],
    pub kind: u32,
    pub static_friction: f32,
    pub kinetic_friction: f32,
    pub _pad0: u32,
    pub _pad1: u32,
}

/// Mirror of WGSL `Contact` (48 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Contact {
    pub target_pos: [f32; 3],
    pub weight: f32,
    pub normal: [f32; 3],
    pub collider: u32,
    pub bary: [f32; 3],
    pub tri: u32,
}

/// Parses and validates a WGSL source with naga (no GPU needed); the error names the stage.
pub fn validate_wgsl(name: &str, src: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(src).map_err(|e| format!("{name}: {}", e.emit_to_string(src)))?;
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .map_err(|e| format!("{name}: {e:?}"))?;
    Ok(module)
}

/// Checks that a WGSL struct has the size of its Rust mirror (catches padding mistakes).
#[cfg(test)]
pub(crate) fn assert_struct_size(module: &naga::Module, name: &str, rust_size: usize) {
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("struct {name} not found"));
    let size = ty.1.inner.size(module.to_ctx()) as usize;
    assert_eq!(size, rust_size, "WGSL {name} is {size} bytes, the Rust mirror {rust_size}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_wgsl_validates_and_matches_the_rust_layout() {
        let m = validate_wgsl("common", COMMON_WGSL).unwrap();
        assert_struct_size(&m, "Params", std::mem::size_of::<Params>());
        assert_struct_size(&m, "StepState", std::mem::size_of::<StepState>());
        assert_struct_size(&m, "Collider", std::mem::size_of::<Collider>());
        assert_struct_size(&m, "Contact", std::mem::size_of::<Contact>());
        assert_eq!(std::mem::size_of::<Params>() % 16, 0);
    }
}
