//! Host side of `project_stencils.wgsl` (the local step for curved bending and seam hinges).

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("project_stencils.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.idx), (3, &b.fdata), (4, &b.x), (5, &b.slots)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn project_stencils_wgsl_validates() {
        let m = validate_wgsl("project_stencils", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
