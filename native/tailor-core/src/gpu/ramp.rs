//! Host side of `ramp.wgsl` (seam gaps and the seam-closing ramp, on the GPU).

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("ramp.wgsl"));
pub const ENTRY: &str = "main";

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.idx), (3, &b.fdata), (4, &b.x), (5, &b.contacts), (6, &b.sdelta)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn ramp_wgsl_validates() {
        let m = validate_wgsl("ramp", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
