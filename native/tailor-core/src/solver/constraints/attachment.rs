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
