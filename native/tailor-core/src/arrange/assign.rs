//! Which place a piece goes on, from its name, and its shape where the name says nothing: a
//! first guess for a whole pattern, which the artist corrects piece by piece.
//!
//! The name is split into lower-case words at anything not a letter or digit
//! (`left_sleeve_b` → `left`, `sleeve`, `b`), and the words are read as GarmentCode and
//! drafting systems write them:
//!
//! * the part: `sleeve` (or `arm`, or a drafting system's `sl`, `slv` or a word ending in `sl`,
//!   as AccuMark's `TEESL`) → an arm; `pant`, `trouser`, `leg`, `short` → a leg; `skirt`,
//!   `waistband`, `wb`, `waist` → the waist (a waistband more than 2.5 times as long as wide
//!   is a band: its length goes round the body, [`Along::Shortest`]; a skirt's piece hangs
//!   along it however narrow, a gored skirt's panel); `collar`, `neck`, or a
//!   drafting system's `co` or a word ending in `co` (`TEECO`) → the neck (a band goes round
//!   it); `cuff` → an arm (a leg with a leg's word: `pant_r_cuff`), at the end of its sleeve
//!   ([`suggest_all`]: the longest side of the arm's other pieces), a band round it; `hood` →
//!   the head (a half on its side of the head, turned 90 degrees from the face; a whole hood at
//!   the back); anything else → the torso;
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
//! waistband and leg), and are left out before the names are read (when what follows still names
//! a part somewhere and the first word is not a part: `skirt_front`, `skirt_back` keep their
//! `skirt`). Three or more panels numbered on one place with no side in their names (a gored
//! skirt's `skirt_panel_0` …) go round it evenly in number order.

use super::place::{Along, Side};

/// Where [`suggest`] puts a piece.
#[derive(Debug, Clone, PartialEq)]
pub struct Suggestion {
    /// The place's name (one of [`super::PLACE_NAMES`]).
    pub place: &'static str,
    pub side: Side,
    pub around_deg: f64,
    pub along: Along,
    /// How far along the place's axis from its origin the piece starts, metres (a cuff at the
    /// end of its sleeve; 0 for most pieces).
    pub offset: f64,
}

fn words(name: &str) -> Vec<String> {
    name.split(|c: char| !c.is_ascii_alphanumeric()).filter(|w| !w.is_empty()).map(str::to_ascii_lowercase).collect()
}

/// The place for a piece called `name` with 2D outline or rest points `shape` (metres).
pub fn suggest(name: &str, shape: &[[f32; 2]]) -> Suggestion {
    suggest_words(&words(name), shape)
}

/// The suggestion for a piece the artist put on `place` (one of [`super::PLACE_NAMES`]): its
/// own suggestion where that is the place, else that place read as the name reads it there (a
/// back half at the back of a limb, the waist or the neck, turned 180 degrees; on the head a
/// half on its side) and, on a limb, no half side and its longest direction along it;
/// elsewhere the suggestion's side and its vertical, or for a band its shortest.
pub fn suggest_on(name: &str, shape: &[[f32; 2]], place: &str) -> crate::error::Result<Suggestion> {
    let s = suggest(name, shape);
    let Some(&place) = super::PLACE_NAMES.iter().find(|&&p| p == place) else {
        return Err(crate::error::TailorError::setting(
            "place",
            place,
            format!("must be one of {}", super::PLACE_NAMES.join(", ")),
        ));
    };
    if place == s.place {
        return Ok(s);
    }
    let limb = place.ends_with("_arm") || place.ends_with("_leg");
    let c = cues(&words(name));
    let around_deg = match place {
        "torso_front" | "torso_back" => 0.0,
        "head" => hood_turn(half_of(&c)),
        _ if c.back && !c.front => 180.0,
        _ => 0.0,
    };
    let along = if limb {
        Along::Longest
    } else if band(shape) {
        Along::Shortest
    } else {
        Along::Vertical
    };
    let side = if limb || place == "head" { Side::Centre } else { s.side };
    Ok(Suggestion { place, side, around_deg, along, offset: 0.0 })
}

/// [`suggest`] for every piece of a pattern (name and shape), the style's name left out: the
/// words all the names start with, when the first of them is not a part and what follows still
/// names a part in some piece (`ORILEG WB` before `WB` and `LL R`; not `skirt` before `front`
/// and `back`, nor `pant` before `f_r` and `r_cuff_f`: there the first word is the part).
pub fn suggest_all(pieces: &[(&str, &[[f32; 2]])]) -> Vec<Suggestion> {
    let all: Vec<Vec<String>> = pieces.iter().map(|(n, _)| words(n)).collect();
    let shortest = all.iter().map(Vec::len).min().unwrap_or(0);
    let mut prefix = 0;
    while all.len() >= 2 && prefix < shortest && all.iter().all(|w| w[prefix] == all[0][prefix]) {
        prefix += 1;
    }
    let style = prefix < shortest
        && prefix > 0
        && !names_a_part(&all[0][0])
        && all.iter().any(|w| w[prefix..].iter().any(|x| names_a_part(x)));
    if !style {
        prefix = 0;
    }
    let mut out: Vec<Suggestion> =
        all.iter().zip(pieces).map(|(w, (_, shape))| suggest_words(&w[prefix..], shape)).collect();
    spread_numbered(&all, &mut out);
    cuffs_at_the_end(&all, pieces, &mut out);
    out
}

/// A cuff starts where its sleeve ends: at the longest side of the other pieces on its arm.
fn cuffs_at_the_end(all: &[Vec<String>], pieces: &[(&str, &[[f32; 2]])], out: &mut [Suggestion]) {
    let cuff: Vec<bool> = all.iter().map(|w| w.iter().any(|x| is_cuff(x))).collect();
    for i in (0..out.len()).filter(|&i| cuff[i]) {
        let sleeve = (0..out.len())
            .filter(|&j| !cuff[j] && out[j].place == out[i].place)
            .map(|j| sides(pieces[j].1).0 as f64)
            .fold(0.0, f64::max);
        out[i].offset = sleeve;
    }
}

/// Panels numbered round one place (a gored skirt's `skirt_panel_0` … `skirt_panel_4`), their
/// names saying no side: three or more with the same words before the number go round the axis
/// in number order, evenly, the first in front and each next towards the character's left (as
/// GarmentCode lays them), so that the seam between one and the next is short.
fn spread_numbered(all: &[Vec<String>], out: &mut [Suggestion]) {
    use std::collections::BTreeMap;
    /// Place and the words before the number.
    type Group<'a> = (&'a str, &'a [String]);
    let mut groups: BTreeMap<Group, Vec<(u64, usize)>> = BTreeMap::new();
    for (i, w) in all.iter().enumerate() {
        let Some((last, stem)) = w.split_last() else { continue };
        let Ok(number) = last.parse::<u64>() else { continue };
        let c = cues(stem);
        if c.front || c.back || c.left || c.right || out[i].side != Side::Centre || out[i].around_deg != 0.0 {
            continue;
        }
        groups.entry((out[i].place, stem)).or_default().push((number, i));
    }
    for mut members in groups.into_values().filter(|m| m.len() >= 3) {
        members.sort_unstable();
        let n = members.len() as f64;
        for (k, &(_, i)) in members.iter().enumerate() {
            // Round the axis towards the character's left is a negative turn (`around_deg`).
            let turn = -360.0 * k as f64 / n;
            out[i].around_deg = if turn <= -180.0 { turn + 360.0 } else { turn };
        }
    }
}

fn is_sleeve(x: &str) -> bool {
    x.contains("sleeve") || matches!(x, "arm" | "arms" | "slv") || (x.ends_with("sl") && x.len() <= 6)
}

fn is_leg(x: &str) -> bool {
    x.starts_with("pant") || x.starts_with("trouser") || matches!(x, "leg" | "legs") || x.starts_with("short")
}

fn is_waist(x: &str) -> bool {
    x.starts_with("skirt") || x.starts_with("waist") || x == "wb"
}

fn is_collar(x: &str) -> bool {
    x.starts_with("collar") || x.starts_with("neck") || (x.ends_with("co") && x.len() <= 6)
}

fn is_hood(x: &str) -> bool {
    x.starts_with("hood")
}

fn is_cuff(x: &str) -> bool {
    x.starts_with("cuff")
}

fn is_torso(x: &str) -> bool {
    x.contains("torso") || x.contains("bodice")
}

/// Whether the word says which part of the body a piece is for.
fn names_a_part(x: &str) -> bool {
    is_sleeve(x) || is_leg(x) || is_waist(x) || is_collar(x) || is_hood(x) || is_torso(x) || is_cuff(x)
}

/// What a name says of the piece's side of the body.
struct Cues {
    front: bool,
    back: bool,
    left: bool,
    right: bool,
}

fn cues(w: &[String]) -> Cues {
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
    Cues { front, back, left, right }
}

/// The half of the body a name says: left, right, or neither (or both).
fn half_of(c: &Cues) -> Side {
    match (c.left, c.right) {
        (true, false) => Side::Left,
        (false, true) => Side::Right,
        _ => Side::Centre,
    }
}

/// A hood's turn round the head: a half covers its side of the head (GarmentCode draws it seen
/// from that side), from the face to the seam at the back; a whole hood is centred at the back.
fn hood_turn(half: Side) -> f64 {
    match half {
        Side::Left => 90.0,
        Side::Right => -90.0,
        Side::Centre => 180.0,
    }
}

fn suggest_words(w: &[String], shape: &[[f32; 2]]) -> Suggestion {
    let any = |f: &dyn Fn(&str) -> bool| w.iter().any(|x| f(x));
    let c = cues(w);
    let (front, back) = (c.front, c.back);
    let (sleeve, leg, waist) = (any(&is_sleeve), any(&is_leg), any(&is_waist));
    let (collar, hood) = (any(&is_collar), any(&is_hood));
    let around_deg = if back && !front { 180.0 } else { 0.0 };
    let half = half_of(&c);
    let limb = |l: &'static str, r: &'static str| Suggestion {
        place: if half == Side::Right { r } else { l },
        side: Side::Centre,
        around_deg,
        along: Along::Longest,
        offset: 0.0,
    };
    // A whole leg: its middle on the outside (the character's left of the left leg).
    let whole_leg = |s: Suggestion| {
        let outside = if s.place == "right_leg" { 90.0 } else { -90.0 };
        Suggestion { around_deg: if front || back { s.around_deg } else { outside }, ..s }
    };
    if any(&is_cuff) {
        // At the end of the sleeve ([`suggest_all`] sets how far), a band round the arm.
        let along = if band(shape) { Along::Shortest } else { Along::Longest };
        let on = if leg { limb("left_leg", "right_leg") } else { limb("left_arm", "right_arm") };
        return Suggestion { along, ..on };
    }
    if sleeve {
        return limb("left_arm", "right_arm");
    }
    if leg {
        return whole_leg(limb("left_leg", "right_leg"));
    }
    if hood {
        let around_deg = hood_turn(half);
        return Suggestion { place: "head", side: Side::Centre, around_deg, along: Along::Vertical, offset: 0.0 };
    }
    if collar {
        let along = if band(shape) { Along::Shortest } else { Along::Vertical };
        return Suggestion { place: "neck", side: half, around_deg, along, offset: 0.0 };
    }
    if waist {
        // A skirt's piece hangs along the body however narrow (a gored skirt's fifteen panels,
        // 12 cm by 70: taken for bands, they went round the waist and the skirt never closed);
        // only a waistband's goes round it.
        let skirt = any(&|x: &str| x.starts_with("skirt")) && !any(&|x: &str| x.starts_with("waist") || x == "wb");
        let along = if band(shape) && !skirt { Along::Shortest } else { Along::Vertical };
        return Suggestion { place: "waist", side: half, around_deg, along, offset: 0.0 };
    }
    let named_torso = front || back || any(&is_torso);
    if !named_torso && long_and_narrow(shape) {
        return whole_leg(limb("left_leg", "right_leg"));
    }
    let place = if back && !front { "torso_back" } else { "torso_front" };
    Suggestion { place, side: half, around_deg: 0.0, along: Along::Vertical, offset: 0.0 }
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
    long > 2.5 * short
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

    /// Collars go round the neck, hoods on the head.
    #[test]
    fn collars_and_hoods_go_up_from_the_neck() {
        let rib = suggest("REGULAR TEECO", &[[0.0, 0.0], [0.04, 0.39]]);
        assert_eq!((rib.place, rib.along), ("neck", Along::Shortest));
        assert_eq!(suggest("collar_stand", &[[0.0, 0.0], [0.45, 0.05]]).place, "neck");
        assert_eq!(s("left_hood"), ("head", Side::Centre, 90.0));
        assert_eq!(s("right_hood"), ("head", Side::Centre, -90.0));
        assert_eq!(s("HOOD"), ("head", Side::Centre, 180.0));
    }

    /// A place the artist chose keeps the suggestion's turn; a limb takes the longest direction
    /// and no side, a band its shortest; an unknown place is an error naming the places.
    #[test]
    fn a_chosen_place_keeps_what_still_applies() {
        let rib = suggest_on("RIB", &[[0.0, 0.0], [0.04, 0.39]], "neck").unwrap();
        assert_eq!((rib.place, rib.along), ("neck", Along::Shortest));
        let half = suggest_on("left_btorso", &[[0.0, 0.0], [0.25, 0.5]], "right_arm").unwrap();
        assert_eq!(
            (half.place, half.side, half.around_deg, half.along),
            ("right_arm", Side::Centre, 180.0, Along::Longest)
        );
        let same = suggest_on("left_btorso", &[[0.0, 0.0], [0.25, 0.5]], "torso_front").unwrap();
        assert_eq!((same.side, same.along), (Side::Left, Along::Vertical));
        let err = suggest_on("x", &[[0.0, 0.0], [0.25, 0.5]], "hand").unwrap_err().to_string();
        assert!(err.contains("hand") && err.contains("torso_front"), "{err}");
    }

    /// A waist piece much longer than wide is a band, its length round the body; a skirt's
    /// panel as narrow hangs along it.
    #[test]
    fn a_band_goes_round_the_waist() {
        let band = suggest("WB", &[[0.0, 0.0], [0.05, 0.7]]);
        assert_eq!((band.place, band.along), ("waist", Along::Shortest));
        let panel = suggest("skirt_panel_3", &[[0.0, 0.0], [0.12, 0.7]]);
        assert_eq!((panel.place, panel.along), ("waist", Along::Vertical));
        let skirt_band = suggest("skirt_waistband", &[[0.0, 0.0], [0.7, 0.05]]);
        assert_eq!((skirt_band.place, skirt_band.along), ("waist", Along::Shortest));
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
        // A gored skirt's numbered panels go round the waist in order, from the front.
        let names: Vec<String> = (0..5).map(|k| format!("skirt_panel_{k}")).collect();
        let panels: Vec<(&str, &[[f32; 2]])> = names.iter().map(|n| (n.as_str(), leg)).collect();
        let turns: Vec<f64> = suggest_all(&panels).iter().map(|s| s.around_deg).collect();
        assert_eq!(turns, [0.0, -72.0, -144.0, 144.0, 72.0]);
        // A cuff starts at the end of its sleeve (0.6 m), a band round the arm.
        let sleeve: &[[f32; 2]] = &[[0.0, 0.0], [0.6, 0.4]];
        let cuff: &[[f32; 2]] = &[[0.0, 0.0], [0.12, 0.04]];
        let got = suggest_all(&[("left_sleeve_f", sleeve), ("sl_left_cuff_f", cuff), ("right_sleeve_f", sleeve)]);
        assert_eq!((got[1].place, got[1].along, got[1].offset), ("left_arm", Along::Shortest, sleeve[1][0] as f64));
        assert_eq!(got[0].offset, 0.0);
        let trousers: &[[f32; 2]] = &[[0.0, 0.0], [0.4, 1.0]];
        let got = suggest_all(&[("pant_f_r", trousers), ("pant_r_cuff_f", cuff)]);
        assert_eq!((got[1].place, got[1].offset), ("right_leg", 1.0));
        // GarmentCode's two-panel skirt: `skirt` is the part, not a style's name.
        let skirt = suggest_all(&[("skirt_front", leg), ("skirt_back", leg)]);
        assert_eq!((skirt[0].place, skirt[1].place), ("waist", "waist"));
        assert_eq!(skirt[1].around_deg, 180.0);
    }
}
