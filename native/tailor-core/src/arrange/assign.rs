//! Which place a piece goes on, from its name, and its shape where the name says nothing: a
//! first guess for a whole pattern, which the artist corrects piece by piece.
//!
//! The name is split into lower-case words at anything not a letter or digit
//! (`left_sleeve_b` → `left`, `sleeve`, `b`), and the words are read as GarmentCode and
//! drafting systems write them:
//!
//! * the part: `sleeve` (or `arm`) → an arm; `pant`, `trouser`, `leg`, `short` → a leg;
//!   `skirt`, `waistband`, `wb`, `waist` → the waist; anything else → the torso;
//! * front or back: `front`, `f`, `fr`, a word starting `front` or `f…torso` (GarmentCode's
//!   `ftorso`), or ending in `fr` (`TEEFR`), for the front; the same with `back`, `b`, `bk` for the
//!   back (on a limb: its back half, turned 180 degrees round it);
//! * left or right: `left`, `l`, `lt` / `right`, `r`, `rt`, or a word starting with either: a
//!   half of the torso or waist goes on that side of the centre line, a sleeve or leg on that
//!   arm or leg.
//!
//! With no part in its name, a piece much longer than wide (over 0.6 m and twice its width)
//! is taken for a trouser leg, anything else for the torso's front.

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
    let w = words(name);
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
    let sleeve = any(&|x| x.contains("sleeve") || matches!(x, "arm" | "arms"));
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
    if sleeve {
        return limb("left_arm", "right_arm");
    }
    if leg {
        return limb("left_leg", "right_leg");
    }
    if waist {
        return Suggestion { place: "waist", side: half, around_deg, along: Along::Vertical };
    }
    let named_torso = front || back || any(&|x| x.contains("torso") || x.contains("bodice"));
    if !named_torso && long_and_narrow(shape) {
        return limb("left_leg", "right_leg");
    }
    let place = if back && !front { "torso_back" } else { "torso_front" };
    Suggestion { place, side: half, around_deg: 0.0, along: Along::Vertical }
}

fn long_and_narrow(shape: &[[f32; 2]]) -> bool {
    if shape.is_empty() {
        return false;
    }
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in shape {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (a, b) = (hi[0] - lo[0], hi[1] - lo[1]);
    let (long, short) = (a.max(b), a.min(b));
    long > 0.6 && long > 2.0 * short
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
    }
}
