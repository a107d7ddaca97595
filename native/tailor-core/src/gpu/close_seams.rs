//! Host side of `close_seams.wgsl` (the seams' closing schedule, on the GPU).

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("close_seams.wgsl"));
pub const ENTRY: &str = "main";

/// One seam pair's closing state as `close_seams.wgsl` keeps it: the gap when sewn, the
/// schedule left, the pair's curved-stencil index (bits; [`NOT_CURVED`] when its rest length
/// lives in no stencil) and its rest length.
pub type PairState = [f32; 4];

/// The curved-stencil index of a pair whose rest length was 0 when the slots were laid out.
pub const NOT_CURVED: u32 = u32::MAX;

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.idx), (3, &b.fdata), (4, &b.x), (5, &b.closing)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn close_seams_wgsl_validates() {
        let m = validate_wgsl("close_seams", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
