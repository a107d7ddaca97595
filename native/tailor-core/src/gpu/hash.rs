//! Host side of `hash.wgsl`: the generic scan and per-bucket sort of a GPU hash build, bound
//! once for the collider table and once for the particle table. Composed as
//! `common + collide_common + hash`.

pub const SOURCE: &str =
    concat!(include_str!("common.wgsl"), include_str!("collide_common.wgsl"), include_str!("hash.wgsl"));
pub const SCAN_ENTRY: &str = "scan";
pub const SORT_ENTRY: &str = "sort";
pub const WORKGROUP: u32 = 64;

/// Bindings of either entry for one table: its `TableInfo`, counts and table buffers.
pub fn entries<'a>(
    info: &'a wgpu::Buffer,
    counts: &'a wgpu::Buffer,
    table: &'a wgpu::Buffer,
) -> Vec<(u32, &'a wgpu::Buffer)> {
    vec![(2, info), (3, counts), (4, table)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn hash_wgsl_validates() {
        let m = validate_wgsl("hash", SOURCE).unwrap();
        for e in [SCAN_ENTRY, SORT_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
