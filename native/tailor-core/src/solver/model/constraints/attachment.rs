//! Soft attachments: `w/2·‖xᵢ − t‖²` pulls particle `i` towards a target `t` with weight `w`
//! (N/m). Linear, so it adds `w` to the system diagonal and `w·t` to the right-hand side.
//! Hard pins are not constraints: a pinned particle is removed from the unknowns and held at
//! its target.

/// One soft attachment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attachment {
    pub particle: u32,
    pub target: [f32; 3],
    pub weight: f32,
}

/// A soft attachment whose target rides on a mesh collider (a pinned waistband on a walking
/// body): the same energy `w/2·‖xᵢ − t‖²`, with `t` recomputed every substep from the
/// collider's positions of that substep (see `solver/simulation/attach.rs`):
///
/// `t = Σₖ bₖ·vₖ + F·o`, where `v₀, v₁, v₂` are the bound triangle's vertices, `b` the
/// barycentric coordinates of the surface point nearest the particle when it was attached,
/// `F = [ê, n̂, n̂ × ê]` the triangle's orthonormal frame (first edge, face normal) and `o` the
/// particle's offset from that surface point in that frame, measured at attach time. The weight
/// is on the system diagonal like a fixed attachment's; only `w·t` on the right-hand side moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColliderAttachment {
    pub particle: u32,
    /// Mesh collider index (`ColliderId.0`).
    pub collider: u32,
    pub triangle: u32,
    pub bary: [f32; 3],
    /// Offset from the surface point in the triangle's frame `(ê, n̂, n̂ × ê)`, metres.
    pub local: [f32; 3],
    pub weight: f32,
    /// Target of the current substep.
    pub target: [f32; 3],
}
