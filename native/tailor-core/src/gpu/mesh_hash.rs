//! Host side of `mesh_hash.wgsl`: the mesh colliders' positions for the substep and the
//! per-triangle half of their hash build (`hash.rs` has the generic scan and sort),
//! composed as `common + collide_common + mesh_hash`.

use super::Buffers;

pub const SOURCE: &str =
    concat!(include_str!("common.wgsl"), include_str!("collide_common.wgsl"), include_str!("mesh_hash.wgsl"));
pub const LERP_ENTRY: &str = "lerp";
pub const COUNT_ENTRY: &str = "count";
pub const SCATTER_ENTRY: &str = "scatter";
pub const WORKGROUP: u32 = 64;

pub fn lerp_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state), (2, &b.meshes), (4, &b.mverts)]
}

pub fn count_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (2, &b.meshes), (3, &b.idx), (4, &b.mverts), (5, &b.mcounts)]
}

pub fn scatter_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (2, &b.meshes), (3, &b.idx), (4, &b.mverts), (5, &b.mcounts), (6, &b.mtable)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn mesh_hash_wgsl_validates() {
        let m = validate_wgsl("mesh_hash", SOURCE).unwrap();
        for e in [LERP_ENTRY, COUNT_ENTRY, SCATTER_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
