//! Finding the places on a humanoid body from its shape alone (no armature): 200 planes across
//! the up axis cut the mesh into loops ([`super::slices`]), and the body's parts are read off
//! how the loops split and join, which holds for any standing character in a rest, A or T pose
//! whatever its proportions:
//!
//! * **Crotch**: going up from the feet, the first plane where a loop contains the point midway
//!   between the legs (the legs are two loops below it, the hips one above).
//! * **Torso**: from the crotch up, the loop containing the previous plane's torso centroid,
//!   tracked up to the top of the head.
//! * **Armpits**: the top of the first run of planes, up from the crotch, where loops lie beside
//!   the torso on both sides (the hands and arms of an A pose, hanging apart from it; ears, higher
//!   up, are loops beside the head too); for a T pose, where none hang apart, the first plane where
//!   the torso's loop widens by more than half (the arms joining it).
//! * **Chest**: the torso's half-width a few planes below the armpits; it separates the shoulders
//!   from the arms above the armpits.
//! * **Neck**: above the armpits, the first plane where the torso is narrower than 0.6 of the
//!   chest (0.35 on the GarmentCode body, shoulders 0.58 with the arms, neck 0.16).
//! * **Waist**: the torso's loop of least perimeter between the crotch and the armpits.
//! * **Axes**: the torso's is the least-squares line through its loops' centroids from the
//!   crotch to the armpits, a leg's through the centroids of its loop (the one nearest the middle
//!   on its side: hands hang beside the thighs in an A pose) from above the feet to the crotch,
//!   an arm's the principal axis of its surface points (the loops beside the torso, and above the
//!   armpits what lies beyond the chest), which holds from an A pose to a T pose.
//!
//! The front is the caller's, or the horizontal direction of least spread (the arms span the
//! other), pointed to where the feet reach (toes forward of the heels).

use rayon::prelude::*;

use super::reach::Reach;
use super::slices::{slice, Loop};
use super::{add, cross, dot, scale, sub, unit, Place, V3};
use crate::error::{Result, TailorError};

/// Planes across the up axis (8.6 mm apart on a 1.72 m body).
const LEVELS: usize = 200;

/// The body's frame: unit up, front (across up) and left (`up × front`, the character's left).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyFrame {
    pub up: V3,
    pub front: V3,
    pub left: V3,
}

/// The sections of the body: per plane its height and loops, in the frame's coordinates.
struct Sections {
    frame: BodyFrame,
    bottom: f64,
    step: f64,
    loops: Vec<Vec<Loop>>,
    /// The lateral middle of the body.
    middle: f64,
}

impl Sections {
    fn height(&self, k: usize) -> f64 {
        self.bottom + (k as f64 + 0.5) * self.step
    }

    /// World point of plane `k`'s `(lateral, front)` point `p`.
    fn world(&self, k: usize, p: [f64; 2]) -> V3 {
        self.world_at(self.height(k), p)
    }

    fn world_at(&self, h: f64, p: [f64; 2]) -> V3 {
        let f = &self.frame;
        add(add(scale(f.left, p[0]), scale(f.front, p[1])), scale(f.up, h))
    }
}

/// The places on `vertices`/`triangles` (a closed humanoid body, standing along `up`, facing
/// `front` when given), in the order of [`super::PLACE_NAMES`].
pub fn body_places(vertices: &[[f32; 3]], triangles: &[[u32; 3]], up: V3, front: Option<V3>) -> Result<Vec<Place>> {
    check_mesh(vertices, triangles)?;
    let frame = body_frame(vertices, up, front)?;
    let s = sections(vertices, triangles, frame);
    let parts = Parts::find(&s)?;
    Ok(parts.places(&s))
}

fn check_mesh(vertices: &[[f32; 3]], triangles: &[[u32; 3]]) -> Result<()> {
    if vertices.is_empty() {
        return Err(TailorError::EmptyMesh { what: "the body has no vertices".into() });
    }
    if triangles.is_empty() {
        return Err(TailorError::EmptyMesh { what: "the body has no triangles".into() });
    }
    for (i, v) in vertices.iter().enumerate() {
        if let Some(&c) = v.iter().find(|c| !c.is_finite()) {
            return Err(TailorError::NonFinite { context: "body".into(), what: "vertex", index: i, value: c });
        }
    }
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
            return Err(TailorError::index(format!("body triangle {t}"), i as i64, vertices.len(), "vertices"));
        }
    }
    Ok(())
}

/// Up as given; front as given (made perpendicular to up) or found (see the module docs).
fn body_frame(vertices: &[[f32; 3]], up: V3, front: Option<V3>) -> Result<BodyFrame> {
    let up =
        unit(up).ok_or_else(|| TailorError::setting("up", format!("{up:?}"), "must be a non-zero finite vector"))?;
    let front = match front {
        Some(f) => unit(sub(f, scale(up, dot(f, up))))
            .ok_or_else(|| TailorError::setting("front", format!("{f:?}"), "must be a finite vector not along up"))?,
        None => found_front(vertices, up),
    };
    Ok(BodyFrame { up, front, left: cross(up, front) })
}

fn found_front(vertices: &[[f32; 3]], up: V3) -> V3 {
    let seed = if up[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let a = unit(sub(seed, scale(up, dot(seed, up)))).unwrap_or([0.0, 0.0, 1.0]);
    let b = cross(up, a);
    let pts: Vec<[f64; 3]> = vertices
        .iter()
        .map(|v| {
            let v = v.map(f64::from);
            [dot(v, a), dot(v, b), dot(v, up)]
        })
        .collect();
    let n = pts.len() as f64;
    let (ma, mb) = (pts.iter().map(|p| p[0]).sum::<f64>() / n, pts.iter().map(|p| p[1]).sum::<f64>() / n);
    let (mut saa, mut sab, mut sbb) = (0.0, 0.0, 0.0);
    for p in &pts {
        let (x, y) = (p[0] - ma, p[1] - mb);
        (saa, sab, sbb) = (saa + x * x, sab + x * y, sbb + y * y);
    }
    // The eigenvector of the smaller eigenvalue of [[saa, sab], [sab, sbb]]: least spread.
    let half_angle = 0.5 * f64::atan2(2.0 * sab, saa - sbb); // direction of most spread
    let (c, s) = (half_angle.cos(), half_angle.sin());
    let least = add(scale(a, -s), scale(b, c));
    // Toes reach further forward than the shins above them.
    let lo = pts.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
    let hi = pts.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max);
    let band = |from: f64, to: f64| {
        let sel: Vec<f64> = pts
            .iter()
            .filter(|p| (lo + from * (hi - lo)..lo + to * (hi - lo)).contains(&p[2]))
            .map(|p| p[0] * (-s) + p[1] * c)
            .collect();
        sel.iter().sum::<f64>() / sel.len().max(1) as f64
    };
    if band(0.0, 0.03) >= band(0.08, 0.12) {
        least
    } else {
        scale(least, -1.0)
    }
}

fn sections(vertices: &[[f32; 3]], triangles: &[[u32; 3]], frame: BodyFrame) -> Sections {
    let v64: Vec<V3> = vertices.iter().map(|v| v.map(f64::from)).collect();
    let height: Vec<f64> = v64.iter().map(|&v| dot(v, frame.up)).collect();
    let flat: Vec<[f64; 2]> = v64.iter().map(|&v| [dot(v, frame.left), dot(v, frame.front)]).collect();
    let bottom = height.iter().copied().fold(f64::INFINITY, f64::min);
    let top = height.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let step = (top - bottom) / LEVELS as f64;
    let loops = (0..LEVELS)
        .into_par_iter()
        .map(|k| slice(&height, &flat, triangles, bottom + (k as f64 + 0.5) * step))
        .collect();
    let lo = flat.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    let hi = flat.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
    Sections { frame, bottom, step, loops, middle: 0.5 * (lo + hi) }
}

/// A straight axis `p(h) = (a + b·h)` in `(lateral, front)` as a function of height.
#[derive(Debug, Clone, Copy)]
struct Line {
    a: [f64; 2],
    b: [f64; 2],
}

impl Line {
    /// Least squares through `(h, point)`; `None` with fewer than two heights.
    fn fit(points: &[(f64, [f64; 2])]) -> Option<Line> {
        let n = points.len() as f64;
        if points.len() < 2 {
            return None;
        }
        let mh = points.iter().map(|p| p.0).sum::<f64>() / n;
        let m = [0, 1].map(|k| points.iter().map(|p| p.1[k]).sum::<f64>() / n);
        let shh: f64 = points.iter().map(|p| (p.0 - mh).powi(2)).sum();
        if shh.is_nan() || shh <= 0.0 {
            return None;
        }
        let b = [0, 1].map(|k| points.iter().map(|p| (p.0 - mh) * (p.1[k] - m[k])).sum::<f64>() / shh);
        Some(Line { a: [m[0] - b[0] * mh, m[1] - b[1] * mh], b })
    }

    fn at(&self, h: f64) -> [f64; 2] {
        [self.a[0] + self.b[0] * h, self.a[1] + self.b[1] * h]
    }
}

/// The parts found on the sections (plane indices and the torso's loop per plane).
struct Parts {
    crotch: usize,
    armpit: usize,
    neck: usize,
    waist: usize,
    /// The torso's loop on each plane from the crotch up (`None` above the head).
    torso: Vec<Option<usize>>,
    chest_half: f64,
    torso_axis: Line,
    legs: [(Line, Vec<V3>); 2],
    arms: [(V3, V3, Vec<V3>); 2],
}

/// Left (+1) and right (−1), in that order.
const SIDES: [f64; 2] = [1.0, -1.0];

impl Parts {
    fn find(s: &Sections) -> Result<Parts> {
        let crotch = find_crotch(s)?;
        let torso = track_torso(s, crotch);
        let top = torso.iter().rposition(Option::is_some).unwrap_or(crotch);
        if top < crotch + LEVELS / 10 {
            return Err(TailorError::not_a_body("torso", "no torso above the crotch: is up the body's up?"));
        }
        let loop_of = |k: usize| torso[k].map(|i| &s.loops[k][i]);
        let beside = |k: usize, side: f64| -> Vec<&Loop> { side_loops(s, k, torso[k], side) };
        // The top of the first run of planes with loops on both sides (hands, then arms), a
        // gap of a plane or two allowed: higher up, ears are loops beside the head.
        let both = |k: usize| !beside(k, 1.0).is_empty() && !beside(k, -1.0).is_empty();
        let armpit = (crotch..=top)
            .find(|&k| both(k))
            .map(|first| {
                let mut last = first;
                while let Some(next) = (last + 1..=(last + 3).min(top)).find(|&k| both(k)) {
                    last = next;
                }
                last
            })
            .or_else(|| {
                // A T pose: the arms join the torso where its loop widens by more than half.
                (crotch + 2..=top).find(|&k| {
                    let (w, below) = (loop_of(k).map_or(0.0, Loop::width), loop_of(k - 2).map_or(0.0, Loop::width));
                    w > 1.5 * below
                })
            })
            .ok_or_else(|| TailorError::not_a_body("arms", "nothing beside the torso, nor where its width jumps"))?;
        let chest_level = armpit.saturating_sub(3).max(crotch);
        let chest =
            loop_of(chest_level).ok_or_else(|| TailorError::not_a_body("chest", "no torso below the armpits"))?;
        let chest_half = f64::max(chest.hi[0] - s.middle, s.middle - chest.lo[0]);
        let neck = (armpit + 1..=top)
            .find(|&k| loop_of(k).is_some_and(|l| l.width() < 0.6 * 2.0 * chest_half))
            .ok_or_else(|| TailorError::not_a_body("neck", "the torso never narrows above the armpits"))?;
        let span = armpit - crotch;
        let waist = (crotch + span * 15 / 100..=armpit - span * 30 / 100)
            .filter_map(|k| loop_of(k).map(|l| (k, l.perimeter)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
            .ok_or_else(|| TailorError::not_a_body("waist", "no torso between the crotch and the armpits"))?;
        let centroids: Vec<(f64, [f64; 2])> =
            (crotch..=armpit).filter_map(|k| loop_of(k).map(|l| (s.height(k), l.centroid))).collect();
        let torso_axis =
            Line::fit(&centroids).ok_or_else(|| TailorError::not_a_body("torso", "too short to give an axis"))?;
        let [left_leg, right_leg] = SIDES.map(|side| find_leg(s, crotch, side));
        let legs = [left_leg?, right_leg?];
        let arm_of = |side: f64| {
            let mut pts: Vec<V3> = Vec::new();
            for k in crotch..=armpit {
                for l in beside(k, side) {
                    pts.extend(l.points.iter().map(|&p| s.world(k, p)));
                }
            }
            // Above the armpits the arm is part of the torso's loop: what lies beyond the chest.
            for k in armpit + 1..neck {
                if let Some(l) = loop_of(k) {
                    let out = l.points.iter().filter(|p| (p[0] - s.middle) * side > 1.1 * chest_half);
                    pts.extend(out.map(|&p| s.world(k, p)));
                }
            }
            arm_axis(s, &pts, side, chest_half).map(|(o, d)| (o, d, pts))
        };
        let arms = [arm_of(1.0)?, arm_of(-1.0)?];
        Ok(Parts { crotch, armpit, neck, waist, torso, chest_half, torso_axis, legs, arms })
    }

    /// The torso's surface (clear of the arms above the armpits) and the legs below it.
    fn torso_samples(&self, s: &Sections) -> Vec<V3> {
        let mut pts = Vec::new();
        for k in self.crotch..self.neck {
            if let Some(i) = self.torso[k] {
                let keep = |p: &&[f64; 2]| k <= self.armpit || (p[0] - s.middle).abs() <= 1.1 * self.chest_half;
                pts.extend(s.loops[k][i].points.iter().filter(keep).map(|&p| s.world(k, p)));
            }
        }
        for (_, leg) in &self.legs {
            pts.extend(leg.iter().copied());
        }
        pts
    }

    fn places(&self, s: &Sections) -> Vec<Place> {
        let f = s.frame;
        let down_along = |line: &Line| {
            let d = add(add(scale(f.left, line.b[0]), scale(f.front, line.b[1])), f.up);
            scale(unit(d).unwrap_or(f.up), -1.0)
        };
        let torso_dir = down_along(&self.torso_axis);
        let at = |line: &Line, k: usize| s.world(k, line.at(s.height(k)));
        let torso_pts = self.torso_samples(s);
        let neck = at(&self.torso_axis, self.neck);
        let waist = at(&self.torso_axis, self.waist);
        // Up from the neck's base: the neck and head, and the shoulders just under it (a collar
        // or a hood's edge rests there).
        let head_pts: Vec<V3> = (self.neck.saturating_sub(3)..self.torso.len())
            .filter_map(|k| self.torso[k].map(|i| (k, i)))
            .flat_map(|(k, i)| {
                let keep = move |p: &&[f64; 2]| k >= self.neck || (p[0] - s.middle).abs() <= self.chest_half;
                s.loops[k][i].points.iter().filter(keep).map(move |&p| s.world(k, p))
            })
            .collect();
        let neck_place = make_place(s, "neck", neck, scale(torso_dir, -1.0), f.front, &head_pts);
        // The head is the same axis under another name (hoods; the artist sees which is which).
        let head_place = Place { name: "head".into(), ..neck_place.clone() };
        let mut places = vec![
            make_place(s, "torso_front", neck, torso_dir, f.front, &torso_pts),
            make_place(s, "torso_back", neck, torso_dir, scale(f.front, -1.0), &torso_pts),
            make_place(s, "waist", waist, torso_dir, f.front, &torso_pts),
            neck_place,
            head_place,
        ];
        for ((origin, axis, pts), name) in self.arms.iter().zip(["left_arm", "right_arm"]) {
            let mut place = make_place(s, name, *origin, *axis, f.front, pts);
            // An arm hanging at an angle meets the torso under it: a sleeve rolled round the arm
            // from the shoulder would cut the chest's side. The place starts where a cylinder of
            // twice the arm's radius and 3 cm more clears the torso.
            let clear = 2.0 * place.radius + 0.03;
            let start = torso_pts
                .iter()
                .filter_map(|&p| {
                    let r = sub(p, place.origin);
                    let along = dot(r, place.axis);
                    (along > -clear && dot(r, r) - along * along < clear * clear).then_some(along + 0.01)
                })
                .fold(0.0f64, f64::max);
            let shifted = add(place.origin, scale(place.axis, start));
            place = make_place(s, name, shifted, *axis, f.front, pts);
            // What the sleeve must clear includes the torso beside the arm (and behind its
            // root, within a clearance of it).
            let mut all = pts.clone();
            all.extend(torso_pts.iter().filter(|&&p| dot(sub(p, shifted), place.axis) >= -0.03));
            place.reach = Reach::from_samples(&all, place.origin, place.axis, place.facing, s.step);
            places.push(place);
        }
        for (((line, pts), side), name) in self.legs.iter().zip(SIDES).zip(["left_leg", "right_leg"]) {
            // A leg's place hangs from the waist, so trousers start where they are worn; its
            // radius is the leg's, and what it clears includes the hips (the other leg too).
            let mut place = make_place(s, name, at(line, self.waist), down_along(line), f.front, pts);
            let mut all = pts.clone();
            for k in self.crotch..=self.waist {
                if let Some(i) = self.torso[k] {
                    all.extend(s.loops[k][i].points.iter().map(|&p| s.world(k, p)));
                }
            }
            all.extend(&self.legs[if side > 0.0 { 1 } else { 0 }].1);
            place.reach = Reach::from_samples(&all, place.origin, place.axis, place.facing, s.step);
            places.push(place);
        }
        places
    }
}

/// A place on the axis from `origin` along `axis`, facing `facing` made perpendicular to it (or
/// up, for an axis along the front), clearing `samples`.
fn make_place(s: &Sections, name: &str, origin: V3, axis: V3, facing: V3, samples: &[V3]) -> Place {
    let f = s.frame;
    let across = |v: V3| unit(sub(v, scale(axis, dot(v, axis))));
    let facing = across(facing).or_else(|| across(f.up)).unwrap_or(f.left);
    let (mut length, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for &p in samples {
        let r = sub(p, origin);
        let along = dot(r, axis);
        length = length.max(along);
        if along >= 0.0 {
            sum += (dot(r, r) - along * along).max(0.0).sqrt();
            n += 1;
        }
    }
    Place {
        name: name.to_string(),
        origin,
        axis,
        facing,
        left: f.left,
        up: f.up,
        length,
        radius: if n > 0 { sum / n as f64 } else { 0.0 },
        reach: Reach::from_samples(samples, origin, axis, facing, s.step),
    }
}

fn find_crotch(s: &Sections) -> Result<usize> {
    for k in LEVELS / 10..LEVELS * 7 / 10 {
        let loops = &s.loops[k];
        let total: f64 = loops.iter().map(|l| l.perimeter).sum();
        if total <= 0.0 || s.loops[k - 1].len() < 2 {
            continue;
        }
        let front = loops.iter().map(|l| l.perimeter * l.centroid[1]).sum::<f64>() / total;
        if loops.iter().any(|l| l.contains([s.middle, front])) {
            return Ok(k);
        }
    }
    Err(TailorError::not_a_body(
        "legs",
        "no crotch between 10% and 70% of the height (no two legs joining): is up the body's up?",
    ))
}

/// The torso's loop per plane from the crotch up: the largest containing the previous one's
/// centroid.
fn track_torso(s: &Sections, crotch: usize) -> Vec<Option<usize>> {
    let mut torso = vec![None; LEVELS];
    let loops = &s.loops[crotch];
    let total: f64 = loops.iter().map(|l| l.perimeter).sum();
    let front = loops.iter().map(|l| l.perimeter * l.centroid[1]).sum::<f64>() / total.max(1e-300);
    let mut at = [s.middle, front];
    for (k, slot) in torso.iter_mut().enumerate().skip(crotch) {
        let found = s.loops[k]
            .iter()
            .enumerate()
            .filter(|(_, l)| l.contains(at))
            .max_by(|a, b| a.1.perimeter.total_cmp(&b.1.perimeter))
            .map(|(i, _)| i);
        match found {
            Some(i) => {
                *slot = Some(i);
                at = s.loops[k][i].centroid;
            }
            None => break,
        }
    }
    torso
}

/// Loops on plane `k` beside the torso's loop `torso` on `side` (arms, hands).
fn side_loops(s: &Sections, k: usize, torso: Option<usize>, side: f64) -> Vec<&Loop> {
    let Some(t) = torso else { return Vec::new() };
    let tl = &s.loops[k][t];
    s.loops[k]
        .iter()
        .enumerate()
        .filter(|&(i, l)| {
            i != t
                && !tl.contains(l.centroid)
                && if side > 0.0 { l.centroid[0] > tl.hi[0] } else { l.centroid[0] < tl.lo[0] }
        })
        .map(|(_, l)| l)
        .collect()
}

/// A leg's axis (through the centroids of the loop nearest the middle on `side`, from above the
/// feet to the crotch) and its surface points (every plane below the crotch, feet included).
fn find_leg(s: &Sections, crotch: usize, side: f64) -> Result<(Line, Vec<V3>)> {
    let mut centroids = Vec::new();
    let mut pts = Vec::new();
    for k in 0..crotch {
        let leg = s.loops[k]
            .iter()
            .filter(|l| (l.centroid[0] - s.middle) * side > 0.0)
            .min_by(|a, b| (a.centroid[0] - s.middle).abs().total_cmp(&(b.centroid[0] - s.middle).abs()));
        if let Some(l) = leg {
            pts.extend(l.points.iter().map(|&p| s.world(k, p)));
            if k >= LEVELS * 6 / 100 && k + 2 < crotch {
                centroids.push((s.height(k), l.centroid));
            }
        }
    }
    let name = if side > 0.0 { "left leg" } else { "right leg" };
    let line =
        Line::fit(&centroids).ok_or_else(|| TailorError::not_a_body(name, "no loop on its side below the crotch"))?;
    Ok((line, pts))
}

/// An arm's root (on its axis, where it leaves the chest's side) and unit direction (out
/// along it), from its surface points: the principal axis through their mean.
fn arm_axis(s: &Sections, pts: &[V3], side: f64, chest_half: f64) -> Result<(V3, V3)> {
    let name = if side > 0.0 { "left arm" } else { "right arm" };
    if pts.len() < 10 {
        return Err(TailorError::not_a_body(name, "too few points beside the torso"));
    }
    let n = pts.len() as f64;
    let mean = [0, 1, 2].map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / n);
    let mut cov = [[0.0; 3]; 3];
    for p in pts {
        let d = sub(*p, mean);
        for i in 0..3 {
            for j in 0..3 {
                cov[i][j] += d[i] * d[j];
            }
        }
    }
    // Power iteration from the lateral direction (an arm is longer than it is thick).
    let f = s.frame;
    let mut dir = scale(f.left, side);
    for _ in 0..100 {
        let next = [0, 1, 2].map(|i| dot(cov[i], dir));
        dir = unit(next).ok_or_else(|| TailorError::not_a_body(name, "its points lie on one spot"))?;
    }
    let lateral = dot(dir, f.left) * side;
    if lateral < 0.0 || (lateral.abs() < 0.2 && dot(dir, f.up) > 0.0) {
        dir = scale(dir, -1.0);
    }
    let lateral = dot(dir, f.left) * side;
    let middle = scale(f.left, s.middle);
    let root_along = if lateral > 0.3 {
        // Where the axis leaves the chest's side.
        let offset = (dot(sub(mean, middle), f.left) * side - chest_half) / lateral;
        -offset
    } else {
        pts.iter().map(|p| dot(sub(*p, mean), dir)).fold(f64::INFINITY, f64::min)
    };
    Ok((add(mean, scale(dir, root_along)), dir))
}

#[cfg(test)]
mod tests {
    use super::super::test_body::mean_body;
    use super::*;

    fn places() -> Vec<Place> {
        let (v, t) = mean_body();
        body_places(v, t, [0.0, 1.0, 0.0], None).unwrap()
    }

    fn by_name<'a>(places: &'a [Place], name: &str) -> &'a Place {
        places.iter().find(|p| p.name == name).unwrap()
    }

    /// On the GarmentCode body (Y up, facing +z, its left +x, 1.72 m): the places are where its
    /// parts are. Measured: see docs/architecture.md, "Arrangement round the body".
    #[test]
    fn the_places_of_the_garmentcode_body_are_where_its_parts_are() {
        let (v, _) = mean_body();
        let places = places();
        for p in &places {
            eprintln!(
                "{:12} origin {:+.3?} axis {:+.2?} facing {:+.2?} length {:.3} radius {:.3}",
                p.name, p.origin, p.axis, p.facing, p.length, p.radius
            );
        }
        let names: Vec<&str> = places.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, super::super::PLACE_NAMES);
        let front = by_name(&places, "torso_front");
        // The front found from the feet is +z, so the character's left is +x.
        assert!(front.facing[2] > 0.95 && front.left[0] > 0.99, "{front:?}");
        assert!(by_name(&places, "torso_back").facing[2] < -0.95);
        // The torso's axis at chest height (1.2 m) within 2 cm of the middle of the body's
        // vertices there (between the arms).
        let chest: Vec<&[f32; 3]> = v.iter().filter(|p| (p[1] - 1.2).abs() < 0.01 && p[0].abs() < 0.2).collect();
        let mid = [0, 2].map(|k| chest.iter().map(|p| p[k] as f64).sum::<f64>() / chest.len() as f64);
        let t = (1.2 - front.origin[1]) / front.axis[1];
        let axis_at = add(front.origin, scale(front.axis, t));
        assert!((axis_at[0] - mid[0]).hypot(axis_at[2] - mid[1]) < 0.02, "{axis_at:?} vs {mid:?}");
        // Down the torso, from the neck's base (1.40-1.48 m on this body).
        assert!(front.axis[1] < -0.99 && (1.40..1.48).contains(&front.origin[1]), "{front:?}");
        assert!((0.10..0.20).contains(&front.radius), "{}", front.radius);
        let waist = by_name(&places, "waist");
        assert!((0.95..1.15).contains(&waist.origin[1]), "{waist:?}");
        // The neck and head: up from the neck's base; in the 5 cm above it the neck, the top of
        // the shoulders and the chin reach 11-13 cm from the axis (the neck alone 7.5 cm).
        for name in ["neck", "head"] {
            let p = by_name(&places, name);
            assert!(p.axis[1] > 0.99 && p.origin == front.origin && p.facing[2] > 0.95, "{p:?}");
            assert!((0.2..0.35).contains(&p.length), "{name}: the head is {} m tall", p.length);
            let neck = p.reach.max_in(0.0, 0.05, -std::f64::consts::PI, std::f64::consts::PI);
            assert!((0.06..0.14).contains(&neck), "{name}: the neck reaches {neck} m");
        }
        for (name, side) in [("left_arm", 1.0), ("right_arm", -1.0)] {
            let arm = by_name(&places, name);
            // Out to its side and down (an A pose, about 45 degrees), from beside the chest.
            assert!(arm.axis[0] * side > 0.6 && arm.axis[1] < -0.5, "{arm:?}");
            assert!((0.12..0.30).contains(&(arm.origin[0] * side)) && (1.25..1.45).contains(&arm.origin[1]), "{arm:?}");
            assert!((0.45..0.75).contains(&arm.length) && (0.02..0.07).contains(&arm.radius), "{arm:?}");
        }
        for (name, side) in [("left_leg", 1.0), ("right_leg", -1.0)] {
            let leg = by_name(&places, name);
            assert!(leg.axis[1] < -0.98 && (leg.origin[1] - waist.origin[1]).abs() < 0.01, "{leg:?}");
            // At the knee (0.5 m) the axis is 8-14 cm to its side.
            let t = (0.5 - leg.origin[1]) / leg.axis[1];
            let x = (leg.origin[0] + leg.axis[0] * t) * side;
            assert!((0.08..0.14).contains(&x), "{name}: {x}");
            assert!((0.04..0.09).contains(&leg.radius), "{leg:?}");
        }
    }

    /// The same body turned to Z up (Blender's frame) gives the same places turned.
    #[test]
    fn the_places_turn_with_the_body() {
        let (v, t) = mean_body();
        let turned: Vec<[f32; 3]> = v.iter().map(|p| [p[0], -p[2], p[1]]).collect();
        let a = places();
        let b = body_places(&turned, t, [0.0, 0.0, 1.0], None).unwrap();
        for (p, q) in a.iter().zip(&b) {
            let back = |v: V3| [v[0], v[2], -v[1]];
            for (x, y) in [(p.origin, back(q.origin)), (p.axis, back(q.axis)), (p.facing, back(q.facing))] {
                assert!(x.iter().zip(&y).all(|(a, b)| (a - b).abs() < 2e-3), "{}: {x:?} vs {y:?}", p.name);
            }
            assert!((p.radius - q.radius).abs() < 1e-3);
        }
    }

    #[test]
    fn bad_bodies_are_errors_naming_what() {
        let (v, t) = mean_body();
        let up = [0.0, 1.0, 0.0];
        assert!(matches!(body_places(&[], t, up, None), Err(TailorError::EmptyMesh { .. })));
        assert!(matches!(body_places(v, &[], up, None), Err(TailorError::EmptyMesh { .. })));
        let mut nan = v.clone();
        nan[7][1] = f32::NAN;
        assert!(matches!(body_places(&nan, t, up, None), Err(TailorError::NonFinite { index: 7, .. })));
        let mut bad = t.clone();
        bad[3][2] = 1 << 30;
        assert!(matches!(body_places(v, &bad, up, None), Err(TailorError::IndexOutOfRange { .. })));
        assert!(matches!(body_places(v, t, [0.0; 3], None), Err(TailorError::InvalidSetting { name: "up", .. })));
        // Lying down (up along the front): no legs joining where a standing body's do.
        let e = body_places(v, t, [0.0, 0.0, 1.0], None).unwrap_err();
        assert!(matches!(e, TailorError::NotABody { .. }), "{e}");
        // A sphere is not a humanoid.
        let (sv, st) = crate::scenes::icosphere(3, 0.5);
        let e = body_places(&sv, &st, up, None).unwrap_err();
        assert!(matches!(e, TailorError::NotABody { .. }), "{e}");
    }
}
