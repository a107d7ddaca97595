//! Rust mirrors of the structs in `collide_common.wgsl` (the GPU spatial hash and the mesh
//! colliders' layout), and a Rust port of its bucket function, checked against the CPU's
//! Eq. 1 so both backends file a cell in the same bucket.

use bytemuck::{Pod, Zeroable};

/// Source of the collision declarations, prepended after `common.wgsl` to the collision
/// stages (so each of them is validated as `common + collide_common + stage`).
pub const COLLIDE_WGSL: &str = include_str!("collide_common.wgsl");

/// Most mesh colliders the GPU path takes (the uniform array's length); more fall back to
/// the CPU with a warning.
pub const MAX_MESHES: usize = 8;

/// Insertion rules as `MeshInfo::rule` encodes them.
pub const RULE_PAPER: u32 = 0;
pub const RULE_PAPER_OR_PLANE: u32 = 1;
pub const RULE_AABB: u32 = 2;

/// Mirror of WGSL `MeshInfo` (48 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct MeshInfo {
    pub cell: f32,
    pub vert_off: u32,
    pub n_verts: u32,
    pub tri_off: u32,
    pub n_tris: u32,
    pub bucket_off: u32,
    pub mask: u32,
    pub rule: u32,
    pub moving: u32,
    pub static_friction: f32,
    pub kinetic_friction: f32,
    pub _pad0: u32,
}

/// Mirror of WGSL `Meshes` (uniform, 16 + 8 × 48 = 400 bytes): rewritten every frame.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Meshes {
    pub inv_dt: f32,
    pub entries_off: u32,
    pub _pad1: u32,
    pub _pad2: u32,
    pub m: [MeshInfo; MAX_MESHES],
}

/// Mirror of WGSL `TableInfo` (uniform, 16 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct TableInfo {
    pub n_buckets: u32,
    pub n_entries: u32,
    pub _pad0: u32,
    pub _pad1: u32,
}

/// The WGSL `bucket_of`, line for line in u32 arithmetic (see its comment there).
pub fn gpu_bucket_of(c: [i32; 3], mask: u32) -> u32 {
    use crate::collision::hash::{P1, P2, P3};
    let mut h = (c[0] as u32).wrapping_mul(P1 as u32)
        ^ (c[1] as u32).wrapping_mul(P2 as u32)
        ^ (c[2] as u32).wrapping_mul(P3 as u32);
    let neg = (c[0] < 0) != ((c[1] < 0) != (c[2] < 0));
    if neg {
        h = 0u32.wrapping_sub(h);
    }
    h & mask
}

/// Entries of a table sized for `primitives` primitives: the CPU's choice, the next power of
/// two at least twice the primitives (`SpatialHash::build_with`).
pub fn buckets_for(primitives: usize) -> usize {
    (2 * primitives).max(2).next_power_of_two()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::hash::bucket_of;
    use crate::gpu::common::{assert_struct_size, validate_wgsl, COMMON_WGSL};
    use crate::test_util::Rng;

    #[test]
    fn collide_common_validates_and_matches_the_rust_layout() {
        let src = format!("{COMMON_WGSL}{COLLIDE_WGSL}");
        let m = validate_wgsl("collide_common", &src).unwrap();
        assert_struct_size(&m, "MeshInfo", std::mem::size_of::<MeshInfo>());
        assert_struct_size(&m, "Meshes", std::mem::size_of::<Meshes>());
        assert_struct_size(&m, "TableInfo", std::mem::size_of::<TableInfo>());
        assert!(COLLIDE_WGSL.contains(&format!("MAX_MESHES: u32 = {MAX_MESHES}u;")));
        let pad = crate::solver::collide::collider_filing::PAD;
        assert!(COLLIDE_WGSL.contains(&format!("PAD: f32 = {pad:?};")), "the CPU's triangle pad is {pad}");
    }

    #[test]
    fn gpu_bucket_equals_the_cpu_eq1_for_every_cell_a_scene_reaches() {
        let mut rng = Rng::new(5);
        for mask in [1u32, 1023, (1 << 20) - 1, (1 << 26) - 1] {
            for k in 0..20_000 {
                // Small cells (near the origin, signs mixed) and far ones up to ±1e9.
                let span = if k % 2 == 0 { 50.0 } else { 1e9 };
                let c = [0, 1, 2].map(|_| ((rng.f32() * 2.0 - 1.0) * span) as i32);
                let cpu = bucket_of(c.map(|v| v as i64), mask as u64) as u32;
                assert_eq!(gpu_bucket_of(c, mask), cpu, "cell {c:?}, mask {mask}");
            }
        }
        for c in [[0, 0, 0], [-1, 0, 0], [0, -1, 0], [-1, -1, -1], [1_000_000_000, -1_000_000_000, 7]] {
            assert_eq!(gpu_bucket_of(c, 4095), bucket_of(c.map(|v| v as i64), 4095) as u32, "cell {c:?}");
        }
    }
}
