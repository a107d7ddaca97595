//! Host side of `contacts.wgsl` (contact detection against analytic and mesh colliders).
//! The stage is composed as `common + collide_common + mesh_query + contacts`.

use super::Buffers;

pub const SOURCE: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("collide_common.wgsl"),
    include_str!("mesh_query.wgsl"),
    include_str!("contacts.wgsl")
);
pub const ENTRY: &str = "detect";
pub const WORKGROUP: u32 = 64;

pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = vec![
        (0, &b.params),
        (1, &b.state),
        (2, &b.fdata),
        (3, &b.x),
        (4, &b.particles),
        (5, &b.colliders),
        (6, &b.contacts),
    ];
    e.extend(super::mesh_query::entries(b));
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;
    use crate::solver::collide::contacts::CONTACT_WEIGHT_FACTOR;

    #[test]
    fn contacts_wgsl_validates_and_uses_the_cpu_weight_factor() {
        let m = validate_wgsl("contacts", SOURCE).unwrap();
        assert!(m.entry_points.iter().any(|e| e.name == ENTRY));
        assert!(SOURCE.contains(&format!("CONTACT_WEIGHT_FACTOR: f32 = {CONTACT_WEIGHT_FACTOR:?};")));
    }
}
