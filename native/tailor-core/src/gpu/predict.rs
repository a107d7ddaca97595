//! Host side of `predict.wgsl` (the prediction stage).

use super::Buffers;

pub use super::common::Particle;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("predict.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

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
