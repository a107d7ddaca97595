//! `mesh_query.wgsl`: the particle-vs-cell test against the mesh colliders' hash, included by
//! the contact detection (`contacts`) and the end-of-substep resolve (`resolve_mesh`). It has
//! no entry point of its own; it is validated as part of those stages and alone here.

use super::Buffers;

pub const SOURCE: &str = include_str!("mesh_query.wgsl");

/// The bindings the query reserves (10-13) in the stages that include it.
pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(10, &b.meshes), (11, &b.idx), (12, &b.mverts), (13, &b.mtable)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::collide_common::COLLIDE_WGSL;
    use crate::gpu::common::{validate_wgsl, COMMON_WGSL};

    #[test]
    fn mesh_query_validates_with_its_prelude() {
        let src = format!("{COMMON_WGSL}{COLLIDE_WGSL}{SOURCE}");
        validate_wgsl("mesh_query", &src).unwrap();
    }
}
