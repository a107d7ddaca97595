//! The fit maps of the current state ([`crate::quality::fit_maps`]): the strain map from the
//! pattern alone; with a mesh collider, the distance map and the pressure map, whose cloth forces
//! are the stretch and shear forces of the solver's own energy plus gravity.

use glam::{Vec3, Vec3A};

use super::Simulation;
use crate::collision::closed_mesh::ClosedMesh;
use crate::error::Result;
use crate::quality::fit_maps::{contact_pressure, signed_distances, vertex_areas, vertex_strain, FitMaps};
use crate::solver::collide::ColliderId;
use crate::solver::model::constraints::triangle;

/// Vertices this far beyond the collision thickness still count as pressed (the solver keeps
/// contacts at the thickness, give or take its tolerance).
const PRESSURE_BAND_MARGIN: f32 = 0.002;

impl Simulation {
    /// The fit maps of the current positions; `collider` (a closed mesh collider, at its current
    /// positions) adds the distance and pressure maps.
    pub fn fit_maps(&self, collider: Option<ColliderId>) -> Result<FitMaps> {
        let pos = self.positions().to_aos();
        let mesh = &self.model.mesh;
        let mut maps =
            FitMaps { strain: vertex_strain(&pos, mesh.rest(), mesh.triangles())?, distance: None, pressure: None };
        let Some(id) = collider else {
            return Ok(maps);
        };
        let m = self.mesh(id)?;
        let body = ClosedMesh::new(&m.cur, &m.tris)?;
        maps.distance = Some(signed_distances(&pos, &body));
        let areas = vertex_areas(mesh.rest(), mesh.triangles())?;
        maps.pressure = Some(contact_pressure(
            &pos,
            &self.cloth_forces(&pos),
            &areas,
            &body,
            self.thickness + PRESSURE_BAND_MARGIN,
        )?);
        Ok(maps)
    }

    /// Each particle's stretch and shear force (`−∂E/∂x` of the triangles' energy, the
    /// projections held: `f_k = Σⱼ g[k][j]·qⱼ − Σⱼ (w_sⱼ + w_sh)·g[k][j]·cⱼ`) plus its weight under
    /// the gravity in effect. Pinned particles get none (the pin holds them, not the body).
    fn cloth_forces(&self, pos: &[[f32; 3]]) -> Vec<Vec3> {
        let t = &self.model.triangles;
        let g_eff = Vec3::from(self.settings().gravity) * self.gravity_scale();
        let mut f: Vec<Vec3> = self.masses().iter().map(|&m| g_eff * m).collect();
        for k in 0..t.len() {
            let v = t.verts[k];
            let x = v.map(|i| Vec3A::from(pos[i as usize]));
            let (g, ws, wsh) = (&t.g[k], [t.w_stretch[k], t.w_stretch_v[k]], t.w_shear[k]);
            let rhs = triangle::rhs_contributions(g, x, ws, wsh);
            let c = triangle::columns(g, x);
            for (j, &i) in v.iter().enumerate() {
                let held = if ws[0] == ws[1] {
                    (c[0] * g[j][0] + c[1] * g[j][1]) * (ws[0] + wsh)
                } else {
                    c[0] * (g[j][0] * (ws[0] + wsh)) + c[1] * (g[j][1] * (ws[1] + wsh))
                };
                f[i as usize] += Vec3::from(rhs[j] - held);
            }
        }
        for (fi, &pinned) in f.iter_mut().zip(&self.model.pinned) {
            if pinned {
                *fi = Vec3::ZERO;
            }
        }
        f
    }
}
