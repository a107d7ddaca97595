//! Host side of `chebyshev.wgsl`: the per-iteration reduction + ω update, and extrapolation.

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("chebyshev.wgsl"));
pub const REDUCE_ENTRY: &str = "reduce_omega";
pub const EXTRAPOLATE_ENTRY: &str = "extrapolate";
pub const GATE_ENTRY: &str = "gate";
pub const WORKGROUP: u32 = 64;

/// The early stop's gate: `state` only.
pub fn gate_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(1, &b.state)]
}

pub fn reduce_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.norms)]
}

pub fn extrapolate_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (3, &b.x), (4, &b.prev), (5, &b.cur)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn chebyshev_wgsl_validates() {
        let m = validate_wgsl("chebyshev", SOURCE).unwrap();
        for e in [REDUCE_ENTRY, EXTRAPOLATE_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
