//! Host side of `predict.wgsl` (the prediction stage).

use bytemuck::{Pod, Zeroable};

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("predict.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

/// Mirror of WGSL `Particle` (32 bytes): each `vec3<f32>` is followed by a 4-byte scalar,
/// which fills the vec3's 16-byte slot, so the Rust `[f32; 3]` + scalar layout matches.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Particle {
    pub b_const: [f32; 3],
    pub mass: f32,
    pub pin_target: [f32; 3],
    pub pinned: u32,
}

/// The buffers behind each `@binding` of the entry point (must list exactly the used ones).
pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![
        (0, &b.params),
        (1, &b.state),
        (2, &b.particles),
        (3, &b.x),
        (4, &b.v),
        (5, &b.x_start),
        (6, &b.rhs),
        (7, &b.prev),
        (8, &b.cur),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::{assert_struct_size, validate_wgsl};

    #[test]
    fn predict_wgsl_validates_and_matches_the_rust_layout() {
        let m = validate_wgsl("predict", SOURCE).unwrap();
        assert_struct_size(&m, "Particle", std::mem::size_of::<Particle>());
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
