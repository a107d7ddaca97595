//! Contacts and collisions in the solver, in one place: the cloth against analytic shapes
//! ([`contacts`]: planes, spheres, capsules, with [`shape_check`] on their input), against
//! animated characters ([`mesh_collider`], its hash filed by [`collider_filing`], its
//! iterations' tests spared by [`mesh_broad_phase`]) and against itself: spheres
//! ([`self_collide`], Nylén et al. 2020, section 6) or particles against triangles
//! ([`self_triangles`] with the kernel [`point_triangle`], issue 23); the rule that switches collisions off by level ([`levels`]); and the
//! collision state a simulation owns ([`Collisions`]).
//!
//! The geometric kernels (the spatial hash, closest points, intersection tests) are solver-free
//! and live in [`crate::collision`], where the quality metrics and the GPU backend use them too.
//! The hooks that run these parts inside a substep, and the public API that adds colliders to
//! a simulation, are in `simulation/colliders.rs` (with attachments to colliders and the
//! closing hold beside it): this module never imports the simulation, so there is no cycle.
//!
//! The skips the scene decides (no hash without mesh colliders, no self pass when off, hash
//! reuse for a still collider and one filing a frame for a moving one, culling of triangles far from the cloth) are switchable in Rust
//! only, through [`CollisionSkips`], so benchmarks and tests can measure and compare them.

pub(crate) mod collider_filing;
pub mod contacts;
pub mod levels;
pub(crate) mod mesh_broad_phase;
pub(crate) mod mesh_collider;
pub(crate) mod occupancy;
pub mod point_triangle;
pub(crate) mod self_collide;
pub(crate) mod self_movers;
pub(crate) mod self_triangle_movers;
pub(crate) mod self_triangles;
pub(crate) mod shape_check;

pub use contacts::{ImplicitCollider, Shape};
pub use mesh_collider::{ColliderId, MeshColliderOptions};
pub use self_collide::{SelfCollisionSettings, SelfContacts};

use self::mesh_collider::MeshCollider;
use self::self_collide::SelfCollide;
use self::self_triangles::SelfTriangles;
use crate::solver::stats::CollisionStats;

/// Marks a `ContactSet::collider` entry as mesh collider `c & !MESH_CONTACT`.
pub(crate) const MESH_CONTACT: u32 = 1 << 31;

/// Optimisations the scene switches (all on by default); turning one off must not change
/// results, only time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CollisionSkips {
    /// Keep a still collider's hash across substeps and frames, and file a moving one once for
    /// the substeps of a frame (`MeshCollider::prepare`).
    pub reuse_collider_hashes: bool,
    /// Leave collider triangles far from the cloth out of the hash.
    pub cull_far_triangles: bool,
    /// Search self-collision pairs with a margin and keep the list while particles move
    /// less than half of it (see `self_collide.rs`).
    pub reuse_self_pairs: bool,
    /// Skip or shorten a particle's mesh-collider test in an iteration while it stays within
    /// the radius its last test found (`mesh_broad_phase.rs`).
    pub mesh_broad_phase: bool,
}

impl Default for CollisionSkips {
    fn default() -> Self {
        Self { reuse_collider_hashes: true, cull_far_triangles: true, reuse_self_pairs: true, mesh_broad_phase: true }
    }
}

/// Collision state of a simulation.
#[derive(Debug, Default)]
pub(crate) struct Collisions {
    /// Each contact's push against the cloth this substep ([`Simulation::contact_pushes`]).
    pub(crate) pushes: Vec<f32>,
    /// The iterations' broad phase against the mesh colliders (`mesh_broad_phase.rs`): per
    /// particle, what its last test in this substep leaves for the next iterations.
    pub(crate) reuse: Vec<mesh_broad_phase::Reuse>,
    pub(crate) meshes: Vec<MeshCollider>,
    pub(crate) levels: Vec<i32>,
    pub(crate) friction: Option<(Vec<f32>, Vec<f32>)>,
    pub self_settings: SelfCollisionSettings,
    pub(crate) self_state: SelfCollide,
    pub(crate) self_triangles: SelfTriangles,
    pub skips: CollisionSkips,
    /// Mesh contact of each particle: (triangle, barycentrics) on collider `ContactSet::collider`.
    pub(crate) contact_tri: Vec<u32>,
    pub(crate) contact_bary: Vec<[f32; 3]>,
    pub(crate) alpha: f32,
    /// Fractions of the frame at the ends of this substep and of the later ones (a moving
    /// collider's hash serves them all, `MeshCollider::prepare`).
    pub(crate) alphas_left: Vec<f32>,
    frame_dt: f32,
    pub stats: CollisionStats,
    /// Another backend began this frame (`begin_frame`) and then handed it to the CPU: the
    /// CPU step must not begin it again.
    pub(crate) frame_begun: bool,
    /// Particles the body holds while seams close (`simulation/closing_hold.rs`), and whether this
    /// closing phase has placed them.
    pub(crate) holds: Vec<u32>,
    pub(crate) holds_placed: bool,
}

impl Collisions {
    pub fn new(n: usize) -> Self {
        Self { levels: vec![0; n], contact_tri: vec![0; n], contact_bary: vec![[0.0; 3]; n], ..Default::default() }
    }

    /// Called once per `step(dt)`, before the substeps.
    pub fn begin_frame(&mut self, dt: f32) {
        self.frame_dt = dt;
        for m in &mut self.meshes {
            m.begin_frame(dt);
        }
    }

    /// After a frame run on another backend: colliders at their frame-end positions.
    #[cfg(feature = "gpu")]
    pub fn end_frame_elsewhere(&mut self) {
        for m in &mut self.meshes {
            m.end_frame_elsewhere();
        }
    }

    /// Called before substep `k` of `count`.
    pub fn set_substep(&mut self, k: u32, count: u32) {
        self.alpha = (k + 1) as f32 / count as f32;
        self.alphas_left.clear();
        self.alphas_left.extend((k + 1..=count).map(|j| j as f32 / count as f32));
    }

    pub fn take_stats(&mut self) -> CollisionStats {
        std::mem::take(&mut self.stats)
    }

    /// Whether some mesh collider moves during the current frame (after `begin_frame`).
    pub fn any_collider_moving(&self) -> bool {
        self.meshes.iter().any(|m| m.moving)
    }

    pub fn invalidate_topology(&mut self) {
        self.self_state.invalidate();
        self.self_triangles.invalidate();
    }

    /// Heap bytes of the per-particle collision state: contact pushes, the broad phase's
    /// shortlists, levels, friction, the mesh contacts and the self-collision pass's
    /// per-particle buffers. Not counted: the colliders' own meshes and hashes (they grow with
    /// the body, not the garment) and the self-collision pair finder.
    pub fn particle_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        let friction = self.friction.as_ref().map_or(0, |(a, b)| vec_bytes(a) + vec_bytes(b));
        vec_bytes(&self.pushes)
            + vec_bytes(&self.reuse)
            + vec_bytes(&self.levels)
            + friction
            + vec_bytes(&self.contact_tri)
            + vec_bytes(&self.contact_bary)
            + self.self_state.particle_bytes()
            + self.self_triangles.particle_bytes()
    }

    pub(crate) fn particle_friction(&self, i: usize, default: (f32, f32)) -> (f32, f32) {
        match &self.friction {
            Some((s, k)) => (s[i], k[i]),
            None => default,
        }
    }
}
