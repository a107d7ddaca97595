//! Arrangement round the body (issue 25): named places on a humanoid character, found from the
//! shape of its mesh, and pieces dropped on them, facing the body at a stated clearance and
//! rolled round it, so that seams close over the body instead of through it (paper Sec. 4:
//! the artist places and bends pieces before the seams close).
//!
//! * [`slices`]: cross-sections of the body by planes across its up axis (exact loops).
//! * [`body`]: the places found from the cross-sections ([`body_places`]): the torso's front
//!   and back, the waist, the neck and the head (up from the neck's base: collars, hoods), each
//!   arm and each leg.
//! * [`reach`]: how far a part reaches from its place's axis, per span and sector, the
//!   surface a piece on the place must clear.
//! * [`place`]: a flat piece put on a place ([`place_piece`]): turned so the pattern's vertical
//!   (torso, waist) or longest (limbs) direction runs along the place's axis, set facing the
//!   body at its reach plus the clearance, and rolled round the axis with the isometric bend
//!   ([`crate::bend`], `BendMode::Roll`), so that no edge changes length.
//! * [`assign`]: which place a piece goes on, from its name and shape ([`suggest`]; over a
//!   whole pattern, [`suggest_all`]).
//!
//! Patterns are read in the convention of GarmentCode (and of most drafted patterns): a piece
//! is drawn as the body is seen from the front, its x towards the character's left and its y
//! up, back pieces included. That is what lets a pair of halves (`left_ftorso`,
//! `right_ftorso`) each go on its own side of the centre line.

mod assign;
mod body;
mod place;
mod reach;
mod slices;

pub use assign::{suggest, suggest_all, suggest_on, Suggestion};
pub use body::{body_places, BodyFrame};
pub use place::{place_piece, Along, PlaceOptions, Placed, Side};
pub use reach::Reach;

use serde::{Deserialize, Serialize};

pub(crate) type V3 = [f64; 3];

/// The places [`body_places`] finds, by name.
pub const PLACE_NAMES: [&str; 9] =
    ["torso_front", "torso_back", "waist", "neck", "head", "left_arm", "right_arm", "left_leg", "right_leg"];

/// A named place on the body where pieces are arranged: an axis through a body part with how
/// far the part reaches from it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Place {
    /// One of [`PLACE_NAMES`].
    pub name: String,
    /// The axis's root end (the neck's base for the torso, and for the neck and the head, whose
    /// axis points up; the waist for the waist and the legs, the shoulder for an arm): a
    /// piece's end nearest the root starts here.
    pub origin: V3,
    /// Unit direction of the axis, from the root towards the part's far end (down the torso and
    /// legs, out along an arm).
    pub axis: V3,
    /// Unit direction across the axis that a piece on this place faces (the body's front for
    /// the torso's front and the limbs, its back for the torso's back).
    pub facing: V3,
    /// The body's left and up (unit): the frame patterns are drawn in, seen from the front.
    pub left: V3,
    pub up: V3,
    /// How far the part extends along the axis from the origin, metres.
    pub length: f64,
    /// Mean distance of the part's surface from the axis, metres.
    pub radius: f64,
    /// The part's surface round the axis, which a placed piece clears.
    pub reach: Reach,
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a / |a|`, or `None` for a (near) zero or non-finite vector.
pub(crate) fn unit(a: V3) -> Option<V3> {
    let n = dot(a, a).sqrt();
    (n.is_finite() && n > 1e-12).then(|| scale(a, 1.0 / n))
}

#[cfg(test)]
pub(crate) mod test_body {
    //! The GarmentCode mean body (`sample_blends/sources/mean_all.obj`, MIT, Y up, metres),
    //! read once for every test of the module.
    use std::sync::OnceLock;

    use crate::io::read_mesh;

    pub type Mesh = (Vec<[f32; 3]>, Vec<[u32; 3]>);

    pub fn mean_body() -> &'static Mesh {
        static BODY: OnceLock<Mesh> = OnceLock::new();
        BODY.get_or_init(|| {
            let path =
                std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample_blends/sources/mean_all.obj");
            let m = read_mesh(&path).expect("the GarmentCode body in sample_blends/sources");
            (m.positions, m.triangles)
        })
    }
}
