//! The body holds the cloth while seams close (`SeamRamp::closing_hold`).
//!
//! When the ramp's closing phase starts, every free particle within `closing_hold_distance` of
//! a mesh collider's surface (not pinned, not already attached) is attached to that collider
//! with stiffness `closing_hold` (`attach.rs`: it rides on the body's triangle nearest to it);
//! when the phase ends (the seams have met, by measured gaps, or stalled) the holds go, and
//! only friction and the garment's shape keep it on the body.
//!
//! Why: with gravity held while seams close, the only forces are the seams', which are equal
//! and opposite; which side of a seam moves, and so where the garment ends up, is left to the
//! solver's arbitrary split. A heavy part placed away from the body then drags the part that
//! fits it: the tiers of a GarmentCode tiered skirt, laid flat in rings round its waistband,
//! dragged the waistband 30 cm down past the hips and the skirt fell. A person dressing holds
//! the waistband at the waist; here the body does. The hold is weak beside a seam (100 N/m
//! against 1e4), so a held piece still slides where its seams pull it; it only decides the
//! tie, for the cloth that already sits on the body. Cloth farther out (a sleeve round an arm,
//! a skirt's hem) is not held and comes to it.

use rayon::prelude::*;

use crate::collision::ClosedMesh;
use crate::error::{Result, TailorError};
use crate::solver::collide::ColliderId;
use crate::solver::simulation::Simulation;

impl Simulation {
    /// Places the holds when the closing phase is on and has none yet; removes them once it
    /// has ended. Called at the start and at the end of every step.
    pub(crate) fn update_closing_holds(&mut self) -> Result<()> {
        if !self.closing_holds_due() {
            return Ok(());
        }
        self.release_closing_holds();
        if self.holding() {
            self.collide.holds_placed = true;
            self.place_closing_holds()?;
        }
        Ok(())
    }

    /// Whether [`update_closing_holds`](Self::update_closing_holds) would place or release
    /// holds now (an edit of the model: another backend brings its velocities down first).
    pub(crate) fn closing_holds_due(&self) -> bool {
        let holding = self.holding();
        (holding && !self.collide.holds_placed && !self.collide.meshes.is_empty())
            || (!holding && !self.collide.holds.is_empty())
    }

    /// The closing phase is on and the body holds the cloth in it.
    fn holding(&self) -> bool {
        self.ramp_closing() && self.settings.ramp.closing_hold > 0.0
    }

    /// The particles the body holds now (empty outside the closing phase).
    pub fn closing_holds(&self) -> &[u32] {
        &self.collide.holds
    }

    fn place_closing_holds(&mut self) -> Result<()> {
        let n = self.num_particles();
        let (within, stiffness) = (self.settings.ramp.closing_hold_distance, self.settings.ramp.closing_hold);
        let mut taken = self.model.pinned.clone();
        for a in &self.model.collider_attachments {
            taken[a.particle as usize] = true;
        }
        let x = self.x.to_aos();
        for id in 0..self.collide.meshes.len() {
            let m = &self.collide.meshes[id];
            // A collider that is not a valid closed mesh answers no distance query: it holds
            // nothing (contacts still work on it).
            let Ok(body) = ClosedMesh::new(&m.cur, &m.tris) else { continue };
            // Its distance hash built before the parallel loop, in parallel (`prepare_queries`).
            body.prepare_queries();
            let near: Vec<u32> = (0..n as u32)
                .into_par_iter()
                .filter(|&i| !taken[i as usize] && body.is_within(x[i as usize], within))
                .collect();
            if near.is_empty() {
                continue;
            }
            // A collider whose triangles all have zero area gives nothing to ride on: it holds
            // nothing, and the step goes on (any other error is a bug and is reported).
            match self.attach_to_collider(&near, ColliderId(id as u32), stiffness) {
                Ok(()) => {}
                Err(TailorError::EmptyMesh { .. }) => continue,
                Err(e) => return Err(e),
            }
            near.iter().for_each(|&i| taken[i as usize] = true);
            self.collide.holds.extend_from_slice(&near);
        }
        Ok(())
    }

    fn release_closing_holds(&mut self) {
        if self.collide.holds.is_empty() {
            return;
        }
        let mut held = vec![false; self.num_particles()];
        std::mem::take(&mut self.collide.holds).iter().for_each(|&p| held[p as usize] = true);
        self.model.collider_attachments.retain(|a| !held[a.particle as usize]);
        self.model.dirty = true;
    }
}
