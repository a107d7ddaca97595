//! A flat piece put on a place: turned, set facing the body, rolled round it.
//!
//! # Method
//!
//! 1. **Turn.** The pattern is drawn as the body is seen from the front (x to the character's
//!    left, y up; see the module docs of [`super`]). The place's axis seen the same way is the 2D
//!    direction `d₂ = (axis·left, axis·up)`. The piece's own direction along it is its y
//!    ([`Along::Vertical`]: torso, waist) or the longer side of its bounding box
//!    ([`Along::Longest`]: sleeves, legs) or the shorter ([`Along::Shortest`]: a waistband or a
//!    cuff, whose length goes round the body), signed to agree with `d₂`; the piece turns in its
//!    plane by the angle between them (0 for a torso piece; 40 degrees for a GarmentCode
//!    sleeve drawn level on an A-pose arm). A limb's piece drawn across the limb's direction
//!    (more than 60 degrees off it either way: a marker lays sleeves and legs along the fabric's
//!    grain, whatever the body) could turn either way; it turns so that its wider end, the cap
//!    of a sleeve or the top of a leg, is the root. A torso or waist piece whose grain line
//!    lies across the drawing was laid on its side the same way: its x goes along the body,
//!    its narrower end (the shoulders, a skirt's waist) at the root. Its end nearest the root
//!    (the top of a bodice, the cap of a sleeve) then starts at the place's origin, `offset`
//!    further along.
//! 2. **Set.** Across the axis, the piece's line at [`Side`] (its middle, or for a half its edge
//!    on the centre line) goes over the place's facing, turned by `around_deg` about the axis
//!    (180: the back of an arm); the piece lies in the plane across the facing at distance `R`
//!    from the axis, its x towards the character's left.
//! 3. **Roll.** [`crate::bend`]'s isometric roll (`BendMode::Roll`) with radius `R` about the
//!    place's axis, both ways from that line: the cylinder it rolls onto is tangent to the plane
//!    on the line and centred on the axis, so every point ends at `R` from the axis and every
//!    length along the piece is kept (edges shorten by their chord, `ℓ(ℓ/R)²/24`).
//! 4. **Clear.** `R` is the smallest radius at which the piece clears the body by the clearance:
//!    the part's reach ([`super::Reach`]) over the piece's span along the axis and the sector
//!    it covers once rolled (its width over `R`), each widened by the clearance, plus the
//!    clearance. A larger `R` narrows the
//!    sector, so that the reach needed only falls as `R` grows: bisection finds the smallest.

use super::{add, cross, dot, scale, unit, Place};
use crate::bend::{bend_piece, BendMode, BendParams, SymmetryLine};
use crate::error::{Result, TailorError};

/// Which of the piece's directions runs along the place's axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Along {
    /// Its y, up as drawn: torso and waist pieces.
    Vertical,
    /// The longer side of its bounding box: sleeves, trouser legs.
    Longest,
    /// The shorter side of its bounding box, so that its length goes round the axis: a
    /// waistband, a cuff.
    Shortest,
}

/// Where the piece lies across the place's centre line (the facing), seen from the front.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Centred on it: a whole front, a sleeve's half.
    Centre,
    /// A half on the character's left of it (its right edge on the line): `left_ftorso`.
    Left,
    /// A half on the character's right of it.
    Right,
}

/// How [`place_piece`] puts a piece on a place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaceOptions {
    /// Distance kept from the body, metres.
    pub clearance: f64,
    pub side: Side,
    /// Turn of the facing about the axis, degrees (180: the back of an arm or a leg).
    pub around_deg: f64,
    pub along: Along,
    /// How far along the axis from the place's origin the piece's root end starts, metres.
    pub offset: f64,
    /// The least radius to roll onto, metres (0: none): the larger of two halves' radii, so
    /// that the halves of a sleeve or a bodice lie on one cylinder.
    pub min_radius: f64,
    /// The piece's grain line (a direction in its pattern frame), when it has one. A torso or
    /// waist piece ([`Along::Vertical`]) whose grain lies within 30 degrees of the pattern's x
    /// was laid sideways by a marker (the grain runs down the body): its x, not its y, goes
    /// along the body, its narrower end (the shoulders, a skirt's waist) at the root.
    pub grain: Option<[f64; 2]>,
}

impl PlaceOptions {
    /// 3 cm off the body, centred, facing the place's way, from its origin, the piece's axis
    /// by the place's kind (vertical on the torso and waist, longest on the limbs).
    pub fn for_place(place: &Place) -> Self {
        let limb = place.name.ends_with("_arm") || place.name.ends_with("_leg");
        PlaceOptions {
            clearance: 0.03,
            side: Side::Centre,
            around_deg: 0.0,
            along: if limb { Along::Longest } else { Along::Vertical },
            offset: 0.0,
            min_radius: 0.0,
            grain: None,
        }
    }
}

/// A piece placed by [`place_piece`].
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// 3D positions, one per rest point.
    pub positions: Vec<[f32; 3]>,
    /// Radius of the cylinder the piece lies on (reach plus clearance), metres.
    pub radius: f64,
    /// The roll that wrapped it (its flat placement is `positions` before this bend).
    pub bend: BendParams,
}

/// Puts the flat piece `rest` (its 2D pattern points, metres) on `place` (see the module docs).
pub fn place_piece(rest: &[[f32; 2]], place: &Place, options: &PlaceOptions) -> Result<Placed> {
    check(rest, place, options)?;
    let axis = unit(place.axis)
        .ok_or_else(|| TailorError::setting("place.axis", format!("{:?}", place.axis), "must be non-zero"))?;
    // 1. Turn: the piece's along direction onto the axis as seen from the front.
    let d2 = [dot(axis, place.left), dot(axis, place.up)];
    let dn = d2[0].hypot(d2[1]);
    if dn.is_nan() || dn <= 0.2 {
        return Err(TailorError::setting(
            "place.axis",
            format!("{axis:?}"),
            "points too far to the front or back to lay a pattern drawn from the front along it",
        ));
    }
    let d2 = [d2[0] / dn, d2[1] / dn];
    let (lo, hi) = bounds(rest);
    let a2 = match options.along {
        Along::Vertical => [0.0, 1.0],
        Along::Longest if hi[0] - lo[0] > hi[1] - lo[1] => [1.0, 0.0],
        Along::Longest => [0.0, 1.0],
        Along::Shortest if hi[0] - lo[0] > hi[1] - lo[1] => [0.0, 1.0],
        Along::Shortest => [1.0, 0.0],
    };
    let sideways = options.along == Along::Vertical && options.grain.is_some_and(laid_sideways);
    let a2 = if sideways { [1.0, 0.0] } else { a2 };
    let agree = a2[0] * d2[0] + a2[1] * d2[1];
    let across_limb = options.along == Along::Longest && agree.abs() < 0.5;
    // The root is the end with the smaller coordinate along `a2 · sign`: a piece laid on its
    // side roots its narrower end (a hem is wide), a limb's piece drawn across it its wider one.
    let high_first = if sideways || across_limb { wider_end_is_high(rest, a2) == across_limb } else { agree < 0.0 };
    let sign = if high_first { -1.0 } else { 1.0 };
    let a2 = [a2[0] * sign, a2[1] * sign];
    let turn = f64::atan2(a2[0] * d2[1] - a2[1] * d2[0], a2[0] * d2[0] + a2[1] * d2[1]);
    let (st, ct) = turn.sin_cos();
    // Across, seen from the front: the perpendicular towards the character's left (or up).
    let n2 = [d2[1], -d2[0]];
    let n2 = if n2[0] < -1e-9 || (n2[0].abs() <= 1e-9 && n2[1] < 0.0) { [-n2[0], -n2[1]] } else { n2 };
    let coords: Vec<(f64, f64)> = rest
        .iter()
        .map(|r| {
            let (x, y) = (r[0] as f64, r[1] as f64);
            let q = [ct * x - st * y, st * x + ct * y];
            (q[0] * d2[0] + q[1] * d2[1], q[0] * n2[0] + q[1] * n2[1])
        })
        .collect();
    let root = coords.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let length = coords.iter().map(|c| c.0).fold(f64::NEG_INFINITY, f64::max) - root;
    let (b_lo, b_hi) = coords.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| (l.min(c.1), h.max(c.1)));
    let anchor = match options.side {
        Side::Centre => 0.5 * (b_lo + b_hi),
        Side::Left => b_lo,
        Side::Right => b_hi,
    };
    // 2. Set: the facing turned about the axis, and across it the front view's n₂.
    let turn_about = options.around_deg.to_radians();
    let side_dir = cross(axis, place.facing);
    let facing = add(scale(place.facing, turn_about.cos()), scale(side_dir, turn_about.sin()));
    let across = cross(axis, facing);
    let n3 = add(scale(place.left, n2[0]), scale(place.up, n2[1]));
    let (across, sense) = if dot(across, n3) < 0.0 { (scale(across, -1.0), -1.0) } else { (across, 1.0) };
    // 4. Clear: the smallest radius whose sector the body does not reach into.
    let span = (options.offset, options.offset + length);
    let need = |r: f64| {
        // Angles from the place's facing, right-handed about the axis: `across` is `sense`
        // times the direction of growing angle at the facing.
        let (t0, t1) = ((b_lo - anchor) / r, (b_hi - anchor) / r);
        let (t0, t1) = if sense > 0.0 { (t0, t1) } else { (-t1, -t0) };
        // Surface within the clearance of the piece's ends and sides counts too.
        let (c, wide) = (options.clearance, options.clearance / r);
        place.reach.max_in(span.0 - c, span.1 + c, turn_about + t0 - wide, turn_about + t1 + wide) + c
    };
    let floor = (place.radius * 0.5 + options.clearance).max(options.min_radius).max(1e-3);
    // Clearing all round is enough whatever the sector.
    let (c, pi) = (options.clearance, std::f64::consts::PI);
    let ceiling = (place.reach.max_in(span.0 - c, span.1 + c, -pi, pi) + c).max(floor);
    let radius = if need(floor) <= floor {
        floor
    } else {
        let (mut lo_r, mut hi_r) = (floor, ceiling.max(floor * 1.000001));
        for _ in 0..40 {
            let mid = 0.5 * (lo_r + hi_r);
            if need(mid) <= mid {
                hi_r = mid;
            } else {
                lo_r = mid;
            }
        }
        hi_r
    };
    let base = add(place.origin, scale(facing, radius));
    let mut positions: Vec<[f32; 3]> = coords
        .iter()
        .map(|&(a, b)| {
            let p = add(base, add(scale(axis, options.offset + a - root), scale(across, b - anchor)));
            p.map(|c| c as f32)
        })
        .collect();
    // 3. Roll, from the line at the anchor (in the rest frame: turned back).
    let line_point = [anchor * n2[0], anchor * n2[1]];
    let bend = BendParams {
        axis_point: place.origin,
        axis_direction: axis,
        angle_deg: 90.0,
        symmetry: Some(SymmetryLine {
            point: [ct * line_point[0] + st * line_point[1], -st * line_point[0] + ct * line_point[1]],
            direction: a2,
        }),
        threshold: 0.0,
        radius: Some(radius),
        mode: BendMode::Roll,
        taper_deg: 0.0,
    };
    bend_piece(&mut positions, rest, &bend)?;
    Ok(Placed { positions, radius, bend })
}

/// A grain line within 30 degrees of the pattern's x (a marker's piece laid on its side).
fn laid_sideways(grain: [f64; 2]) -> bool {
    let n = grain[0].hypot(grain[1]);
    n > 0.0 && grain[0].abs() / n > 30f64.to_radians().cos()
}

/// Whether the piece is wider across `dir` (a unit axis of the pattern) at its high end along
/// `dir` than at its low end: the extents across of the points in each end's fifth.
fn wider_end_is_high(rest: &[[f32; 2]], dir: [f64; 2]) -> bool {
    let along = |r: &[f32; 2]| r[0] as f64 * dir[0] + r[1] as f64 * dir[1];
    let across = |r: &[f32; 2]| -(r[0] as f64) * dir[1] + r[1] as f64 * dir[0];
    let (lo, hi) = rest.iter().map(along).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| (l.min(a), h.max(a)));
    let fifth = 0.2 * (hi - lo);
    let width = |near: &dyn Fn(f64) -> bool| {
        let (l, h) = rest
            .iter()
            .filter(|r| near(along(r)))
            .map(across)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| (l.min(a), h.max(a)));
        if h >= l {
            h - l
        } else {
            0.0
        }
    };
    width(&|a| a >= hi - fifth) > width(&|a| a <= lo + fifth)
}

fn bounds(rest: &[[f32; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for r in rest {
        for k in 0..2 {
            lo[k] = lo[k].min(r[k] as f64);
            hi[k] = hi[k].max(r[k] as f64);
        }
    }
    (lo, hi)
}

fn check(rest: &[[f32; 2]], place: &Place, options: &PlaceOptions) -> Result<()> {
    if rest.len() < 3 {
        return Err(TailorError::EmptyMesh {
            what: format!("a piece to place needs 3 points or more, not {}", rest.len()),
        });
    }
    for (i, r) in rest.iter().enumerate() {
        if let Some(&c) = r.iter().find(|c| !c.is_finite()) {
            return Err(TailorError::NonFinite {
                context: "piece to place".into(),
                what: "rest point",
                index: i,
                value: c,
            });
        }
    }
    let (lo, hi) = bounds(rest);
    if !(hi[0] - lo[0] > 1e-6 && hi[1] - lo[1] > 1e-6) {
        return Err(TailorError::shape("piece to place", "its rest points lie on a line"));
    }
    if !(options.clearance.is_finite() && options.clearance >= 0.0) {
        return Err(TailorError::setting("clearance", options.clearance, "must be a distance of 0 or more"));
    }
    if !options.around_deg.is_finite() {
        return Err(TailorError::setting("around_deg", options.around_deg, "must be finite"));
    }
    if !(options.min_radius.is_finite() && options.min_radius >= 0.0) {
        return Err(TailorError::setting("min_radius", options.min_radius, "must be a distance of 0 or more"));
    }
    if !options.offset.is_finite() {
        return Err(TailorError::setting("offset", options.offset, "must be finite"));
    }
    let vectors = [place.origin, place.axis, place.facing, place.left, place.up];
    if vectors.iter().flatten().any(|c| !c.is_finite())
        || !(place.radius.is_finite() && place.radius >= 0.0)
        || place.reach.values.iter().any(|v| !v.is_finite())
        || place.reach.step.is_nan()
        || place.reach.step <= 0.0
    {
        return Err(TailorError::setting("place", &place.name, "has a non-finite vector, radius or reach"));
    }
    let facing_across =
        dot(place.facing, place.axis).abs() < 1e-3 && (dot(place.facing, place.facing) - 1.0).abs() < 1e-3;
    if !facing_across {
        return Err(TailorError::setting(
            "place.facing",
            format!("{:?}", place.facing),
            "must be a unit vector across the axis",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::body::body_places;
    use super::super::sub;
    use super::super::test_body::mean_body;
    use super::*;
    use crate::collision::closed_mesh::ClosedMesh;

    fn places() -> &'static Vec<Place> {
        static P: std::sync::OnceLock<Vec<Place>> = std::sync::OnceLock::new();
        P.get_or_init(|| {
            let (v, t) = mean_body();
            body_places(v, t, [0.0, 1.0, 0.0], None).unwrap()
        })
    }

    fn place(name: &str) -> &'static Place {
        places().iter().find(|p| p.name == name).unwrap()
    }

    /// A grid of `nx × ny` points over `w × h` (5 mm apart for the sizes used) starting at
    /// `(x0, y0)`, and its edges.
    fn grid(x0: f32, y0: f32, w: f32, h: f32, nx: usize, ny: usize) -> (Vec<[f32; 2]>, Vec<[usize; 2]>) {
        let mut rest = Vec::new();
        let mut edges = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                rest.push([x0 + w * i as f32 / (nx - 1) as f32, y0 + h * j as f32 / (ny - 1) as f32]);
                let v = j * nx + i;
                if i + 1 < nx {
                    edges.push([v, v + 1]);
                }
                if j + 1 < ny {
                    edges.push([v, v + nx]);
                }
                if i + 1 < nx && j + 1 < ny {
                    edges.push([v, v + nx + 1]);
                }
            }
        }
        (rest, edges)
    }

    fn len3(p: &[[f32; 3]], e: [usize; 2]) -> f64 {
        (0..3).map(|k| (p[e[0]][k] as f64 - p[e[1]][k] as f64).powi(2)).sum::<f64>().sqrt()
    }

    fn len2(p: &[[f32; 2]], e: [usize; 2]) -> f64 {
        (0..2).map(|k| (p[e[0]][k] as f64 - p[e[1]][k] as f64).powi(2)).sum::<f64>().sqrt()
    }

    /// Pieces of a shirt's size on the torso's front and back (whole and halves) and on each
    /// arm (front and back halves): every edge keeps its length within 0.1 %, no point is
    /// inside the body, and every point is at least the clearance from it (less the chord of
    /// a 5 mm grid's sag, well under a millimetre).
    #[test]
    fn placed_pieces_keep_their_lengths_and_clear_the_body() {
        let (v, t) = mean_body();
        let body = ClosedMesh::new(v, t).unwrap();
        let clearance = 0.03;
        type Case = (&'static str, Side, f64, (Vec<[f32; 2]>, Vec<[usize; 2]>));
        let cases: Vec<Case> = vec![
            ("torso_front", Side::Centre, 0.0, grid(-0.25, 0.0, 0.5, 0.45, 101, 91)),
            ("torso_front", Side::Left, 0.0, grid(0.0, 0.0, 0.28, 0.45, 57, 91)),
            ("torso_back", Side::Right, 0.0, grid(-0.26, 0.0, 0.26, 0.45, 53, 91)),
            ("left_arm", Side::Centre, 0.0, grid(-0.31, -0.21, 0.31, 0.21, 63, 43)),
            ("right_arm", Side::Centre, 180.0, grid(0.0, -0.21, 0.31, 0.21, 63, 43)),
            ("left_leg", Side::Centre, 0.0, grid(-0.12, -0.9, 0.24, 0.9, 25, 91)),
            ("waist", Side::Centre, 180.0, grid(-0.3, -0.5, 0.6, 0.5, 61, 51)),
        ];
        for (name, side, around, (rest, edges)) in cases {
            let p = place(name);
            let options = PlaceOptions { side, around_deg: around, clearance, ..PlaceOptions::for_place(p) };
            let placed = place_piece(&rest, p, &options).unwrap();
            let pos = &placed.positions;
            let worst =
                edges.iter().map(|&e| (len3(pos, e) - len2(&rest, e)).abs() / len2(&rest, e)).fold(0.0, f64::max);
            let pen = body.penetration(pos);
            let nearest = pos.iter().map(|&q| body.distance(q).0).fold(f32::INFINITY, f32::min);
            eprintln!(
                "{name} {side:?} {around}: radius {:.3}, worst edge change {:.2e}, inside {}, nearest {:.4}",
                placed.radius, worst, pen.count, nearest
            );
            assert!(worst < 1e-3, "{name}: an edge changed by {worst}");
            assert_eq!(pen.count, 0, "{name}: {pen:?}");
            assert!(nearest as f64 >= clearance - 1e-3, "{name}: {nearest}");
            // Wrapped round, not flat: the piece's points are all at the radius from the axis.
            for q in pos.iter().step_by(97) {
                let r = sub(q.map(f64::from), p.origin);
                let d = (dot(r, r) - dot(r, p.axis).powi(2)).sqrt();
                assert!((d - placed.radius).abs() < 1e-3, "{name}: {d} vs {}", placed.radius);
            }
        }
    }

    /// A half goes on its side of the centre line, its inner edge on the line: the left front
    /// half of a shirt ends on the character's left (+x on this body), the right on its right,
    /// both in front; the top of the pieces at the neck's base.
    #[test]
    fn halves_go_on_their_sides() {
        let p = place("torso_front");
        let (left, _) = grid(0.0, 0.0, 0.28, 0.45, 15, 10);
        let (right, _) = grid(-0.28, 0.0, 0.28, 0.45, 15, 10);
        let a = place_piece(&left, p, &PlaceOptions { side: Side::Left, ..PlaceOptions::for_place(p) }).unwrap();
        let b = place_piece(&right, p, &PlaceOptions { side: Side::Right, ..PlaceOptions::for_place(p) }).unwrap();
        let middle = p.origin[0] as f32 + p.facing[0] as f32 * a.radius as f32;
        let (lo, hi) = (
            a.positions.iter().map(|q| q[0]).fold(f32::MAX, f32::min),
            b.positions.iter().map(|q| q[0]).fold(f32::MIN, f32::max),
        );
        assert!(lo > middle - 5e-3 && hi < middle + 5e-3, "{lo} {hi} {middle}");
        // Inner edges (rest x = 0) meet on the centre line in front.
        let inner = |rest: &[[f32; 2]], pos: &[[f32; 3]]| -> Vec<[f32; 3]> {
            rest.iter().zip(pos).filter(|(r, _)| r[0] == 0.0).map(|(_, q)| *q).collect()
        };
        for (qa, qb) in inner(&left, &a.positions).iter().zip(inner(&right, &b.positions)) {
            // Each half has the radius its own side needs (2 mm apart here).
            assert!((qa[0] - qb[0]).abs() < 5e-3 && qa[2] > 0.1 && (qa[1] - qb[1]).abs() < 1e-3, "{qa:?} {qb:?}");
        }
        let top = a.positions.iter().map(|q| q[1]).fold(f32::MIN, f32::max);
        assert!((top as f64 - p.origin[1]).abs() < 0.01, "{top}");
    }

    /// A sleeve drawn level (GarmentCode's: the cap at x = -0.31 for the left arm) goes cap
    /// first from the shoulder down the arm.
    #[test]
    fn a_sleeve_goes_cap_first_down_the_arm() {
        let p = place("left_arm");
        let (rest, _) = grid(-0.31, -0.21, 0.31, 0.21, 32, 22);
        let placed = place_piece(&rest, p, &PlaceOptions::for_place(p)).unwrap();
        let along = |q: [f32; 3]| dot(sub(q.map(f64::from), p.origin), p.axis);
        let (cap, cuff) = (along(placed.positions[0]), along(placed.positions[31]));
        assert!(cap.abs() < 0.01 && (cuff - 0.31).abs() < 0.01, "{cap} {cuff}");
    }

    /// A tapered leg drawn across the leg (a marker's: hem at x = 0, 0.2 m wide, top at
    /// x = 0.9, 0.5 m wide), on either leg and either way round: its wide top goes at the hip,
    /// whatever the leg's slight lean (the left and right legs lean opposite ways, which turned
    /// one of a pair upside down before the wider end decided).
    #[test]
    fn a_leg_drawn_across_goes_wide_end_up() {
        let taper = |flip: bool| -> Vec<[f32; 2]> {
            let (rest, _) = grid(0.0, -0.5, 0.9, 1.0, 46, 21);
            rest.into_iter()
                .filter_map(|[x, y]| {
                    let half = 0.1 + 0.15 * x / 0.9;
                    let x = if flip { 0.9 - x } else { x };
                    (y.abs() <= half + 1e-6).then_some([x, y])
                })
                .collect()
        };
        for name in ["left_leg", "right_leg"] {
            let p = place(name);
            for flip in [false, true] {
                let rest = taper(flip);
                let placed = place_piece(&rest, p, &PlaceOptions::for_place(p)).unwrap();
                let along = |q: [f32; 3]| dot(sub(q.map(f64::from), p.origin), p.axis);
                let top = if flip { 0.0 } else { 0.9 };
                let ends = rest.iter().zip(&placed.positions).filter(|(r, _)| (r[0] - top).abs() < 1e-4);
                let worst = ends.map(|(_, q)| along(*q).abs()).fold(0.0, f64::max);
                assert!(worst < 0.01, "{name} flip {flip}: the wide end is {worst} m down the leg");
            }
        }
    }

    /// A waistband (0.05 × 0.7 m, drawn upright as a marker lays it) on the waist with
    /// [`Along::Shortest`]: its length goes round the waist (every point at the radius, the
    /// band 5 cm tall), not down the legs.
    #[test]
    fn a_band_goes_round() {
        let p = place("waist");
        let (rest, edges) = grid(0.0, 0.0, 0.05, 0.7, 6, 71);
        let options = PlaceOptions { along: Along::Shortest, ..PlaceOptions::for_place(p) };
        let placed = place_piece(&rest, p, &options).unwrap();
        let along = |q: &[f32; 3]| dot(sub(q.map(f64::from), p.origin), p.axis);
        let (lo, hi) = placed.positions.iter().map(along).fold((f64::MAX, f64::MIN), |(l, h), a| (l.min(a), h.max(a)));
        assert!((hi - lo - 0.05).abs() < 1e-3, "the band spans {} m of the axis", hi - lo);
        let worst = edges
            .iter()
            .map(|&e| (len3(&placed.positions, e) - len2(&rest, e)).abs() / len2(&rest, e))
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "an edge changed by {worst}");
        // Round the axis: 0.7 m of arc at the radius.
        assert!(0.7 / placed.radius > 2.0, "covers {} rad", 0.7 / placed.radius);
    }

    /// A bodice a marker laid on its side (hem at x = 0, 0.5 m wide; shoulders at x = 0.6,
    /// 0.36 m wide; grain line along x): with its grain it goes shoulders up, 0.6 m down the
    /// torso from the neck's base; without, as drawn (its y up: 0.5 m down). Either way round
    /// in the drawing the same. A grain line drawn upright (or on the bias) changes nothing.
    #[test]
    fn a_piece_laid_on_its_side_goes_up_its_grain() {
        let p = place("torso_front");
        let along = |q: &[f32; 3]| dot(sub(q.map(f64::from), p.origin), p.axis);
        let bodice = |flip: bool| -> Vec<[f32; 2]> {
            let (rest, _) = grid(0.0, -0.25, 0.6, 0.5, 31, 26);
            rest.into_iter()
                .filter_map(|[x, y]| {
                    let half = 0.25 - 0.07 * x / 0.6;
                    (y.abs() <= half + 1e-6).then_some([if flip { 0.6 - x } else { x }, y])
                })
                .collect()
        };
        for flip in [false, true] {
            let rest = bodice(flip);
            let with = PlaceOptions { grain: Some([1.0, 0.0]), ..PlaceOptions::for_place(p) };
            let placed = place_piece(&rest, p, &with).unwrap();
            let span = placed.positions.iter().map(along).fold(f64::MIN, f64::max);
            assert!((span - 0.6).abs() < 0.01, "flip {flip}: spans {span} m of the torso");
            let shoulders_x = if flip { 0.0 } else { 0.6 };
            let shoulders = rest.iter().zip(&placed.positions).filter(|(r, _)| (r[0] - shoulders_x).abs() < 1e-4);
            let worst = shoulders.map(|(_, q)| along(q)).fold(0.0, f64::max);
            assert!(worst < 0.01, "flip {flip}: the shoulders are {worst} m down");
            let without = place_piece(&rest, p, &PlaceOptions::for_place(p)).unwrap();
            let span = without.positions.iter().map(along).fold(f64::MIN, f64::max);
            assert!((span - 0.5).abs() < 0.01, "as drawn it spans {span} m");
            for upright in [[0.0, 1.0], [1.0, 1.0]] {
                let o = PlaceOptions { grain: Some(upright), ..PlaceOptions::for_place(p) };
                assert_eq!(place_piece(&rest, p, &o).unwrap().positions, without.positions);
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let p = place("torso_front");
        let o = PlaceOptions::for_place(p);
        let (rest, _) = grid(0.0, 0.0, 0.2, 0.2, 4, 4);
        assert!(matches!(place_piece(&rest[..2], p, &o), Err(TailorError::EmptyMesh { .. })));
        let mut nan = rest.clone();
        nan[5][0] = f32::NAN;
        assert!(matches!(place_piece(&nan, p, &o), Err(TailorError::NonFinite { index: 5, .. })));
        let line: Vec<[f32; 2]> = (0..5).map(|i| [i as f32, 0.0]).collect();
        assert!(matches!(place_piece(&line, p, &o), Err(TailorError::ShapeMismatch { .. })));
        let bad = PlaceOptions { clearance: -1.0, ..o };
        assert!(matches!(place_piece(&rest, p, &bad), Err(TailorError::InvalidSetting { name: "clearance", .. })));
        let mut q = p.clone();
        q.radius = f64::NAN;
        assert!(matches!(place_piece(&rest, &q, &o), Err(TailorError::InvalidSetting { .. })));
        let mut q = p.clone();
        q.axis = q.facing;
        assert!(place_piece(&rest, &q, &o).is_err());
    }
}
