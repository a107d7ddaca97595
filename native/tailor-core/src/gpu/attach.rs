//! Host side of `attach.wgsl`: particles riding on a mesh collider (painted pins on the
//! character, `Simulation::attach_to_collider`), their targets moved with the collider every
//! substep on the GPU as the CPU moves them (`solver/simulation/attach.rs`).

use bytemuck::{Pod, Zeroable};

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("attach.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

/// Mirror of WGSL `Attachment` (storage; 64 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct Attachment {
    pub particle: u32,
    /// Global vertex indices of the bound triangle in the `mverts` sections.
    pub verts: [u32; 3],
    pub bary: [f32; 3],
    pub weight: f32,
    pub local: [f32; 3],
    pub _pad0: f32,
    /// The last target (kept when the triangle has no area).
    pub last: [f32; 3],
    pub _pad1: f32,
}

/// Mirror of WGSL `AttachInfo` (uniform; the number of attachments).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct AttachInfo {
    pub n: u32,
    pub _pad: [u32; 3],
}

/// The buffers behind each `@binding` of the entry point (must list exactly the used ones).
pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (2, &b.attach_info), (3, &b.attachments), (4, &b.mverts), (6, &b.rhs)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::{assert_struct_size, validate_wgsl};

    #[test]
    fn attach_wgsl_validates_and_matches_the_rust_layout() {
        let m = validate_wgsl("attach", SOURCE).unwrap();
        assert_struct_size(&m, "Attachment", std::mem::size_of::<Attachment>());
        assert_struct_size(&m, "AttachInfo", std::mem::size_of::<AttachInfo>());
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
