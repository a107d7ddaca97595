//! Which place a piece goes on, from its name, and its shape where the name says nothing: a
//! first guess for a whole pattern, which the artist corrects piece by piece.
//!
//! The name is split into lower-case words at anything not a letter or digit
//! (`left_sleeve_b` → `left`, `sleeve`, `b`), and the words are read as GarmentCode and
//! drafting systems write them:
//!
//! * the part: `sleeve` (or `arm`, or a drafting system's `sl`, `slv` or a word ending in `sl`,
//!   as AccuMark's `TEESL`) → an arm; `pant`, `trouser`, `leg`, `short` → a leg; `skirt`,
//!   `waistband`, `wb`, `waist` → the waist (a waist piece more than three times as long as wide
//!   is a band: its length goes round the body, [`Along::Shortest`]); anything else → the torso;
//! * front or back: `front`, `f`, `fr`, a word starting `front` or `f…torso` (GarmentCode's
//!   `ftorso`), or ending in `fr` (`TEEFR`), for the front; the same with `back`, `b`, `bk` for the
//!   back (on a limb: its back half, turned 180 degrees round it);
//! * left or right: `left`, `l`, `lt` / `right`, `r`, `rt`, or a word starting with either: a
//!   half of the torso or waist goes on that side of the centre line, a sleeve or leg on that
//!   arm or leg.
//!
//! With no part in its name, a piece much longer than wide (over 0.6 m and twice its width) or
//! longer than 0.8 m is taken for a trouser leg, anything else for the torso's front.
//!
//! A leg piece named neither front nor back is a whole leg (a legging's): it goes round the leg
//! with its middle on the outside, turned 90 degrees from the front, so that its two long edges
//! meet on the inside as an inseam.
//!
//! Over a whole pattern ([`suggest_all`]), the words every piece's name starts with are the
//! style's name, not the part (`ORILEG WB WB`, `ORILEG WB LL R`: a legging with a waistband, its
//! waistband and leg), and are left out before the names are read.

use super::place::{Along, Side};

/// Where [`suggest`] puts a piece.
#[derive(Debug, Clone, PartialEq)]
pub struct Suggestion {
    /// The place's name (one of [`super::PLACE_NAMES`]).
    pub place: &'static str,
    pub side: Side,
    pub around_deg: f64,
    pub along: Along,
}

fn words(name: &str) -> Vec<String> {
    name.split(|c: char| !c.is_ascii_alphanumeric()).filter(|w| !w.is_empty()).map(str::to_ascii_lowercase).collect()
}

/// The place for a piece called `name` with 2D outline or rest points `shape` (metres).
pub fn suggest(name: &str, shape: &[[f32; 2]]) -> Suggestion {
    suggest_words(&words(name), shape)
}

/// [`suggest`] for every piece of a pattern (name and shape), the style's name, the words all
/// the names start with, left out (unless that would leave a piece no word).
pub fn suggest_all(pieces: &[(&str, &[[f32; 2]])]) -> Vec<Suggestion> {
    let all: Vec<Vec<String>> = pieces.iter().map(|(n, _)| words(n)).collect();
    let shortest = all.iter().map(Vec::len).min().unwrap_or(0);
    let mut prefix = 0;
    while all.len() >= 2 && prefix < shortest && all.iter().all(|w| w[prefix] == all[0][prefix]) {
        prefix += 1;
    }
    if prefix == shortest {
        prefix = 0;
    }
    all.iter().zip(pieces).map(|(w, (_, shape))| suggest_words(&w[prefix..], shape)).collect()
}

fn suggest_words(w: &[String], shape: &[[f32; 2]]) -> Suggestion {
    let any = |f: &dyn Fn(&str) -> bool| w.iter().any(|x| f(x));
    let front = any(&|x| {
        matches!(x, "front" | "f" | "fr" | "frt")
            || x.starts_with("front")
            || (x.starts_with('f') && x.ends_with("torso"))
            || (x.len() > 2 && x.ends_with("fr"))
    });
    let back = any(&|x| {
        matches!(x, "back" | "b" | "bk")
            || x.starts_with("back")
            || (x.starts_with('b') && x.ends_with("torso"))
            || (x.len() > 2 && x.ends_with("bk"))
    });
    let left = any(&|x| matches!(x, "l" | "lt") || x.starts_with("left"));
    let right = any(&|x| matches!(x, "r" | "rt") || x.starts_with("right"));
    let sleeve =
        any(&|x| x.contains("sleeve") || matches!(x, "arm" | "arms" | "slv") || (x.ends_with("sl") && x.len() <= 6));
    let leg = any(&|x| {
        x.starts_with("pant") || x.starts_with("trouser") || matches!(x, "leg" | "legs") || x.starts_with("short")
    });
    let waist = any(&|x| x.starts_with("skirt") || x.starts_with("waist") || x == "wb");
    let around_deg = if back && !front { 180.0 } else { 0.0 };
    let half = if left && !right {
        Side::Left
    } else if right && !left {
        Side::Right
    } else {
        Side::Centre
    };
    let limb = |l: &'static str, r: &'static str| Suggestion {
        place: if right && !left { r } else { l },
        side: Side::Centre,
        around_deg,
        along: Along::Longest,
    };
    // A whole leg: its middle on the outside (the character's left of the left leg).
    let whole_leg = |s: Suggestion| {
        let outside = if s.place == "right_leg" { 90.0 } else { -90.0 };
        Suggestion { around_deg: if front || back { s.around_deg } else { outside }, ..s }
    };
    if sleeve {
        return limb("left_arm", "right_arm");
    }
    if leg {
        return whole_leg(limb("left_leg", "right_leg"));
    }
    if waist {
        let along = if band(shape) { Along::Shortest } else { Along::Vertical };
        return Suggestion { place: "waist", side: half, around_deg, along };
    }
    let named_torso = front || back || any(&|x| x.contains("torso") || x.contains("bodice"));
    if !named_torso && long_and_narrow(shape) {
        return whole_leg(limb("left_leg", "right_leg"));
    }
    let place = if back && !front { "torso_back" } else { "torso_front" };
    Suggestion { place, side: half, around_deg: 0.0, along: Along::Vertical }
}

/// The sides of the shape's bounding box, longer first (zero for no points).
fn sides(shape: &[[f32; 2]]) -> (f32, f32) {
    if shape.is_empty() {
        return (0.0, 0.0);
    }
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in shape {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (a, b) = (hi[0] - lo[0], hi[1] - lo[1]);
    (a.max(b), a.min(b))
}

fn long_and_narrow(shape: &[[f32; 2]]) -> bool {
    let (long, short) = sides(shape);
    (long > 0.6 && long > 2.0 * short) || long > 0.8
}

fn band(shape: &[[f32; 2]]) -> bool {
    let (long, short) = sides(shape);
    long > 3.0 * short
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(name: &str) -> (&'static str, Side, f64) {
        let g = suggest(name, &[[0.0, 0.0], [0.3, 0.4]]);
        (g.place, g.side, g.around_deg)
    }

    /// Every piece name of the GarmentCode specifications the repository carries, and a few
    /// drafting-system names.
    #[test]
    fn names_say_the_place() {
        assert_eq!(s("left_ftorso"), ("torso_front", Side::Left, 0.0));
        assert_eq!(s("right_btorso"), ("torso_back", Side::Right, 0.0));
        assert_eq!(s("left_sleeve_f"), ("left_arm", Side::Centre, 0.0));
        assert_eq!(s("right_sleeve_b"), ("right_arm", Side::Centre, 180.0));
        assert_eq!(s("pant_b_l"), ("left_leg", Side::Centre, 180.0));
        assert_eq!(s("pant_f_r"), ("right_leg", Side::Centre, 0.0));
        assert_eq!(s("skirt_back"), ("waist", Side::Centre, 180.0));
        assert_eq!(s("wb_front"), ("waist", Side::Centre, 0.0));
        assert_eq!(s("REGULAR TEEFR"), ("torso_front", Side::Centre, 0.0));
        assert_eq!(s("TANK_SR_BK"), ("torso_back", Side::Centre, 0.0));
        assert_eq!(s("Back"), ("torso_back", Side::Centre, 0.0));
        // Nothing in the name: by shape.
        assert_eq!(suggest("PIECE 3", &[[0.0, 0.0], [0.25, 1.0]]).place, "left_leg");
        assert_eq!(suggest("PIECE 4", &[[0.0, 0.0], [0.5, 0.6]]).place, "torso_front");
        assert_eq!(suggest("PIECE 5", &[[0.0, 0.0], [0.95, 0.6]]).place, "left_leg", "longer than 0.8 m");
        // Drafting systems' sleeves.
        assert_eq!(s("REGULAR TEESL BK L"), ("left_arm", Side::Centre, 180.0));
        assert_eq!(s("SLV FR R"), ("right_arm", Side::Centre, 0.0));
        assert_eq!(s("SL"), ("left_arm", Side::Centre, 0.0));
        // A whole leg (neither front nor back) goes round the leg, its middle outside.
        assert_eq!(s("LEG L"), ("left_leg", Side::Centre, -90.0));
        assert_eq!(s("LEG R"), ("right_leg", Side::Centre, 90.0));
        assert_eq!(s("leg_front_r"), ("right_leg", Side::Centre, 0.0));
    }

    /// A waist piece much longer than wide is a band, its length round the body.
    #[test]
    fn a_band_goes_round_the_waist() {
        let band = suggest("WB", &[[0.0, 0.0], [0.05, 0.7]]);
        assert_eq!((band.place, band.along), ("waist", Along::Shortest));
        let panel = suggest("skirt_front", &[[0.0, 0.0], [0.6, 0.5]]);
        assert_eq!((panel.place, panel.along), ("waist", Along::Vertical));
    }

    /// Over a whole pattern, the style's name (the words every name starts with) is not read:
    /// the legging `ORILEG WB` has a waistband `ORILEG WB WB` and legs `ORILEG WB LL R`/`L`,
    /// which read alone would all be the waist (`wb`). A lone piece, or names that share
    /// nothing, read as they are.
    #[test]
    fn the_style_name_is_left_out() {
        let band: &[[f32; 2]] = &[[0.0, 0.0], [0.05, 0.87]];
        let leg: &[[f32; 2]] = &[[0.0, 0.0], [0.95, 0.6]];
        let got = suggest_all(&[("ORILEG WB WB", band), ("ORILEG WB LL R", leg), ("ORILEG WB LL L", leg)]);
        let read: Vec<(&str, Along, f64)> = got.iter().map(|s| (s.place, s.along, s.around_deg)).collect();
        assert_eq!(
            read,
            [("waist", Along::Shortest, 0.0), ("right_leg", Along::Longest, 90.0), ("left_leg", Along::Longest, -90.0)]
        );
        assert_eq!(suggest("ORILEG WB LL R", leg).place, "waist", "alone, the style's `wb` says waist");
        assert_eq!(suggest_all(&[("ORILEG WB LL R", leg)])[0].place, "waist");
        let gc = suggest_all(&[("left_ftorso", band), ("right_ftorso", band)]);
        assert_eq!((gc[0].side, gc[1].side), (Side::Left, Side::Right));
        let same = suggest_all(&[("SLEEVE", leg), ("SLEEVE", leg)]);
        assert_eq!(same[0].place, "left_arm", "names that are all style keep their words");
    }
}
