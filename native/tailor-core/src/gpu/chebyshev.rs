//! Host side of `chebyshev.wgsl`: the per-iteration reduction + ω update, and extrapolation.

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("chebyshev.wgsl"));
pub const REDUCE_PARTIAL_ENTRY: &str = "reduce_partial";
pub const REDUCE_ENTRY: &str = "reduce_omega";
pub const EXTRAPOLATE_ENTRY: &str = "extrapolate";
pub const GATE_ENTRY: &str = "gate";
pub const WORKGROUP: u32 = 64;

/// The early stop's gate: `state` only.
pub fn gate_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(1, &b.state)]
}

/// `REDUCE` in `chebyshev.wgsl`: threads a workgroup, and partial sums.
pub const REDUCE: usize = 256;

/// Workgroups of `reduce_partial` for `n` particles: enough that each thread sums a few
/// (16 at most below a million), at most `REDUCE` (the slots of `partials`).
pub fn reduce_groups(n: usize) -> u32 {
    n.div_ceil(REDUCE * 16).clamp(1, REDUCE) as u32
}

pub fn reduce_partial_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.norms), (6, &b.partials)]
}

pub fn reduce_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (6, &b.partials)]
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
        assert!(SOURCE.contains(&format!("const REDUCE: u32 = {REDUCE}u;")));
        assert_eq!(
            (reduce_groups(0), reduce_groups(4096), reduce_groups(4097), reduce_groups(1 << 30)),
            (1, 1, 2, 256)
        );
        for e in [REDUCE_PARTIAL_ENTRY, REDUCE_ENTRY, EXTRAPOLATE_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
