//! Host side of `finish.wgsl` (velocity update and air damping).

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("finish.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![
        (0, &b.params),
        (1, &b.state),
        (2, &b.x),
        (3, &b.x_start),
        (4, &b.v),
        (5, &b.contacts),
        (6, &b.colliders),
        (7, &b.particles),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn finish_wgsl_validates() {
        let m = validate_wgsl("finish", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
