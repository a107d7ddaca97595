//! Host side of `gauss_seidel.wgsl`: one dispatch per colour over that colour's particles.

use bytemuck::{Pod, Zeroable};

use super::Buffers;

pub const SOURCE: &str =
    concat!(include_str!("common.wgsl"), include_str!("row.wgsl"), include_str!("gauss_seidel.wgsl"));
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

/// Mirror of WGSL `ColourRange` (16 bytes): where a colour's particles sit in the packed
/// `order` section. One per colour, each at its own uniform-offset-aligned place.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct ColourRange {
    pub start: u32,
    pub count: u32,
    pub _pad0: u32,
    pub _pad1: u32,
}

/// Entries except binding 2 (the colour's range), which differs per colour's bind group.
pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![
        (0, &b.params),
        (1, &b.state),
        (3, &b.idx),
        (4, &b.fdata),
        (5, &b.x),
        (6, &b.rhs),
        (7, &b.slots),
        (8, &b.norms),
        (9, &b.contacts),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::{assert_struct_size, validate_wgsl};

    #[test]
    fn gauss_seidel_wgsl_validates_and_matches_the_rust_layout() {
        let m = validate_wgsl("gauss_seidel", SOURCE).unwrap();
        assert_struct_size(&m, "ColourRange", std::mem::size_of::<ColourRange>());
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
