//! Host side of `resolve_mesh.wgsl` (end-of-substep mesh penetrations and friction),
//! composed as `common + collide_common + mesh_query + resolve_mesh`.

use super::Buffers;

pub const SOURCE: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("collide_common.wgsl"),
    include_str!("mesh_query.wgsl"),
    include_str!("resolve_mesh.wgsl")
);
pub const ENTRY: &str = "main";
pub const WORKGROUP: u32 = 64;

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = vec![
        (0, &b.params),
        (1, &b.state),
        (2, &b.x),
        (3, &b.x_start),
        (4, &b.v),
        (5, &b.contacts),
        (6, &b.fdata),
        (7, &b.particles),
    ];
    e.extend(super::mesh_query::entries(b));
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn resolve_mesh_wgsl_validates() {
        let m = validate_wgsl("resolve_mesh", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
    }
}
