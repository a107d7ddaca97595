//! Host side of `self_collide.wgsl` (cloth-cloth spheres, per-particle gather), composed as
//! `common + collide_common + self_collide`.

use super::Buffers;

pub const SOURCE: &str =
    concat!(include_str!("common.wgsl"), include_str!("collide_common.wgsl"), include_str!("self_collide.wgsl"));
pub const COUNT_ENTRY: &str = "count";
pub const SCATTER_ENTRY: &str = "scatter";
pub const GATHER_ENTRY: &str = "gather";
pub const APPLY_ENTRY: &str = "apply";
pub const WORKGROUP: u32 = 64;

pub fn count_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.x), (7, &b.scounts), (11, &b.self_table_info)]
}

pub fn scatter_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.x), (7, &b.scounts), (8, &b.stable), (11, &b.self_table_info)]
}

pub fn gather_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![
        (0, &b.params),
        (1, &b.state),
        (2, &b.x),
        (3, &b.x_start),
        (4, &b.particles),
        (5, &b.idx),
        (6, &b.fdata),
        (8, &b.stable),
        (9, &b.sdelta),
        (11, &b.self_table_info),
    ]
}

pub fn apply_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.x), (9, &b.sdelta), (10, &b.cur)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn self_collide_wgsl_validates() {
        let m = validate_wgsl("self_collide", SOURCE).unwrap();
        for e in [COUNT_ENTRY, SCATTER_ENTRY, GATHER_ENTRY, APPLY_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
