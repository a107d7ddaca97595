//! Host side of `ramp.wgsl` (seam gaps and the seam-closing ramp's state machine, on the GPU).

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

    /// The stall watch's constants are the CPU's.
    #[test]
    fn ramp_wgsl_stalls_as_the_cpu_does() {
        use crate::solver::stages::damping::{STALL_SHRINK, STALL_TIME};
        for (name, v) in [("STALL_TIME", STALL_TIME), ("STALL_SHRINK", STALL_SHRINK)] {
            let line = format!("const {name}: f32 = {v:?};");
            assert!(SOURCE.contains(&line), "ramp.wgsl lacks `{line}`");
        }
    }
}
