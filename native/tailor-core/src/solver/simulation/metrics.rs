//! The quality of a simulation's current state, measured by [`crate::quality`].

use super::Simulation;
use crate::collision::closed_mesh::ClosedMesh;
use crate::error::Result;
use crate::quality::metrics::{
    centroid, edge_strain, kinetic_energy_soa, on_body_fraction, self_intersecting_pairs, top, ON_BODY_DISTANCE,
};
use crate::quality::QualityMetrics;
use crate::solver::collide::self_collide::seam_partners;
use crate::solver::collide::ColliderId;

impl Simulation {
    /// Every pair of vertices sewn together (`seam_partners`: each vertex of a seam point with a
    /// non-zero weight with each of the other side's): the welded garment's shared vertices, for
    /// the self-intersection count.
    fn sewn_vertices(&self) -> Vec<[u32; 2]> {
        let partners = seam_partners(&self.model);
        partners.iter().enumerate().flat_map(|(v, ps)| ps.iter().map(move |&p| [v as u32, p])).collect()
    }

    /// Quality of the current state; `collider` names a closed mesh collider for the
    /// penetration count (at its current positions).
    pub fn metrics(&self, collider: Option<ColliderId>) -> Result<QualityMetrics> {
        let pos = self.positions().to_aos();
        let mesh = &self.model.mesh;
        let mut q = QualityMetrics::default();
        if let Some(id) = collider {
            let m = self.mesh(id)?;
            let body = ClosedMesh::new(&m.cur, &m.tris)?;
            let pen = body.penetration(&pos);
            q.penetration_count = pen.count;
            q.penetration_max_depth = pen.max_depth;
            q.on_body_fraction = Some(on_body_fraction(&pos, &body, ON_BODY_DISTANCE));
            q.collider_centroid = Some(body.surface_centroid());
        }
        q.particles = pos.len();
        q.centroid = centroid(&pos);
        q.top = top(&pos, self.settings.gravity.map(|g| -g));
        q.seams_closing = self.seams_closing();
        q.self_intersections = self_intersecting_pairs(&pos, mesh.triangles(), &self.sewn_vertices())?.len();
        q.seam_gap = self.seam_gaps().0;
        let edges = &mesh.topology().edges;
        let rest = mesh.rest();
        let rest_len: Vec<f32> = edges
            .iter()
            .map(|&[a, b]| {
                let (p, r) = (rest[a as usize], rest[b as usize]);
                ((p[0] - r[0]).hypot(p[1] - r[1])).max(1e-12)
            })
            .collect();
        let s = edge_strain(&pos, edges, &rest_len)?;
        (q.strain_max, q.strain_mean) = (s.max, s.mean);
        let v = self.velocities();
        q.kinetic_energy = kinetic_energy_soa(&v.x, &v.y, &v.z, self.masses())?;
        Ok(q)
    }
}
