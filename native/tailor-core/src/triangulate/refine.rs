//! Minimum-angle refinement once every constraint is in (Ruppert/Chew, after `spade`'s own).
//!
//! `spade`'s refinement runs before the internal lines are added (see `cdt`), leaves triangles
//! under a hundredth of the target area alone (tiny outline features), skips a skinny triangle
//! whose circumcentre falls outside the piece, and skips every triangle whose shortest edge
//! joins two segments meeting at a sharp input corner, so a corner's whole wedge stays skinny,
//! not only the angle at the corner. This pass repairs all of that on the final constrained
//! triangulation:
//!
//! * A triangle inside the piece is *bad* when one of its angles is below `θ_min` and that angle
//!   is not *excused*: an angle whose two sides are both constraint segments is an input corner
//!   (outline, hole or internal-line segments, or pieces of them) and no refinement can open it.
//! * For a bad triangle the candidate is Üngör's off-centre (the circumcentre, or nearer on the
//!   bisector of the shortest edge for a skinny triangle). Walking from the triangle to it, the
//!   first constraint segment crossed (it is outside the piece or beyond an internal line) is
//!   split; otherwise a constraint segment on the boundary of the cavity it would open that it
//!   sees under more than `180° − 2 θ_min` (the diametral lens) is split; otherwise it is
//!   inserted. When the segment to split is an edge of the bad triangle and the vertex opposite
//!   is free (not on a constraint), that vertex is removed instead (a bounded number of times).
//!   Outline and hole segments are split only with `TriangulateOptions::refine_contour`.
//! * A segment is split at its midpoint, except one with an end at a sharp input corner (two
//!   constraint segments meeting below 60°): that one is split at a distance `h·2^k` from the
//!   corner (the power of two nearest half its length), Ruppert's concentric shells, so both
//!   legs of the corner get vertices at the same distances and the triangle at the corner is
//!   isosceles with only the corner's own angle small.
//!
//! Splitting adds contour vertices (the contour is read back from the triangles afterwards) but
//! never moves or removes one. Refinement stops at a vertex budget and never splits below
//! `h / 1024`; reaching either clears `refinement_complete`. Everything is deterministic (a
//! first-in first-out queue of faces in triangulation order).

use std::collections::VecDeque;

use spade::handles::{FixedFaceHandle, FixedUndirectedEdgeHandle, FixedVertexHandle, InnerTag};
use spade::{ConstrainedDelaunayTriangulation, Point2 as SPoint, Triangulation};

use crate::pattern::Point2;

type Cdt = ConstrainedDelaunayTriangulation<SPoint<f64>>;

/// Corners sharper than this (degrees) are split by concentric shells.
const SHELL_BELOW_DEG: f64 = 60.0;

/// The off-centre sees its triangle's shortest edge under θ_min plus this (degrees), so the new
/// triangle is not itself borderline.
const OFF_CENTRE_MARGIN: f64 = 2.0;

pub(crate) struct RefineInput<'a> {
    /// Vertices below this index are input vertices (constraint points and lattice seeds).
    pub n_in: usize,
    /// Vertices below this index are constraint points (outline, holes, internal lines).
    pub n_constraint: usize,
    pub outline: &'a [Point2],
    pub holes: &'a [Vec<Point2>],
    pub h: f64,
    pub min_angle_deg: f64,
}

fn orient(a: SPoint<f64>, b: SPoint<f64>, c: SPoint<f64>) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

fn d2(a: SPoint<f64>, b: SPoint<f64>) -> f64 {
    (a.x - b.x).powi(2) + (a.y - b.y).powi(2)
}

enum Walk {
    /// The point lies in (or on the boundary of) this face, reached without crossing a segment.
    Inside(FixedFaceHandle<InnerTag>),
    /// The first constraint segment crossed on the way.
    Crossed(FixedUndirectedEdgeHandle),
    Stuck,
}

/// Straight walk from `s` (inside face `start`) to `c`.
fn walk(cdt: &Cdt, start: FixedFaceHandle<InnerTag>, s: SPoint<f64>, c: SPoint<f64>) -> Walk {
    let mut f = start;
    for _ in 0..1_000_000 {
        let face = cdt.face(f);
        let mut next = None;
        for e in face.adjacent_edges() {
            let [a, b] = e.positions();
            if orient(a, b, c) < 0.0 {
                let (oa, ob) = (orient(s, c, a), orient(s, c, b));
                if (oa <= 0.0 && ob >= 0.0) || (oa >= 0.0 && ob <= 0.0) {
                    next = Some(e);
                    break;
                }
            }
        }
        let Some(e) = next else { return Walk::Inside(f) };
        if e.is_constraint_edge() {
            return Walk::Crossed(e.fix().as_undirected());
        }
        match e.rev().face().as_inner() {
            Some(g) => f = g.fix(),
            None => return Walk::Stuck,
        }
    }
    Walk::Stuck
}

/// A constraint segment on the boundary of the cavity inserting `c` would open (the faces whose
/// circumcircle contains `c`, from face `f0` on, not across segments) whose diametral circle
/// contains `c`.
fn encroached(
    cdt: &Cdt,
    f0: FixedFaceHandle<InnerTag>,
    c: SPoint<f64>,
    cos_lens: f64,
) -> Option<FixedUndirectedEdgeHandle> {
    let mut stack = vec![f0];
    // A set, not a list: the cavity of a point near long thin triangles holds thousands of
    // faces, and `contains` on a list made this quadratic (a fuzzed GarmentCode pattern of a
    // million vertices took 2.5 minutes). Same faces, same order.
    let mut seen = std::collections::HashSet::from([f0.index()]);
    while let Some(f) = stack.pop() {
        for e in cdt.face(f).adjacent_edges() {
            if e.is_constraint_edge() {
                let [a, b] = e.positions();
                let (u, v) = ([a.x - c.x, a.y - c.y], [b.x - c.x, b.y - c.y]);
                let (nu, nv) = ((u[0] * u[0] + u[1] * u[1]).sqrt(), (v[0] * v[0] + v[1] * v[1]).sqrt());
                if u[0] * v[0] + u[1] * v[1] < cos_lens * nu * nv {
                    return Some(e.fix().as_undirected());
                }
                continue;
            }
            if let Some(g) = e.rev().face().as_inner() {
                let (centre, r2) = g.circumcircle();
                if !seen.contains(&g.fix().index()) && d2(centre, c) < r2 {
                    seen.insert(g.fix().index());
                    stack.push(g.fix());
                }
            }
        }
    }
    None
}

/// The most faces that removals of free vertices may requeue in all: each removal renumbers
/// handles and so requeues every face, and a fuzzed collar 264 m long spent 10 s of CPU on
/// that. Ordinary pieces stay far below it (they remove a handful); past it, an encroached
/// segment is split instead, as when `max_removals` runs out.
const REQUEUE_WORK: usize = 5_000_000;

/// Input vertices where two constraint segments meet below [`SHELL_BELOW_DEG`].
fn sharp_vertices(cdt: &Cdt, n_in: usize) -> Vec<bool> {
    let mut sharp = vec![false; n_in];
    for (i, s) in sharp.iter_mut().enumerate() {
        let v = cdt.vertex(FixedVertexHandle::from_index(i));
        let p = v.position();
        let mut dirs: Vec<f64> = v
            .out_edges()
            .filter(|e| e.is_constraint_edge())
            .map(|e| {
                let q = e.to().position();
                (q.y - p.y).atan2(q.x - p.x)
            })
            .collect();
        if dirs.len() < 2 {
            continue;
        }
        dirs.sort_by(f64::total_cmp);
        let n = dirs.len();
        let min_gap = (0..n)
            .map(|k| if k + 1 < n { dirs[k + 1] - dirs[k] } else { dirs[0] + std::f64::consts::TAU - dirs[n - 1] })
            .fold(f64::INFINITY, f64::min);
        *s = min_gap.to_degrees() < SHELL_BELOW_DEG;
    }
    sharp
}

/// Refines `cdt` as the module docs say. Returns false when it stopped at its budget.
pub(crate) fn refine(cdt: &mut Cdt, input: &RefineInput<'_>) -> bool {
    let h = input.h;
    let limit = input.min_angle_deg.to_radians();
    // A point sees a segment under more than 180° - 2 θ_min inside its diametral lens.
    let cos_lens = (std::f64::consts::PI - 2.0 * limit).cos();
    let min_len2 = (h / 1024.0).powi(2);
    // Per vertex (kept in step with spade's swap-removal): a sharp input corner.
    let mut sharp = sharp_vertices(cdt, input.n_in.min(cdt.num_vertices()));
    sharp.resize(cdt.num_vertices(), false);
    let (mut removals, max_removals) = (0usize, 100 + cdt.num_vertices() / 20);
    // Faces requeued by removals so far (see REQUEUE_WORK).
    let mut requeued = 0usize;
    // Indexed once: a plain even-odd test per candidate is quadratic on long pieces.
    let region = super::region::Region::new(input.outline, input.holes, h);
    let budget = cdt.num_vertices() + 2000;
    let mut added = 0usize;
    let mut complete = true;

    let mut queue: VecDeque<FixedFaceHandle<InnerTag>> = cdt.fixed_inner_faces().collect();
    let mut queued = vec![false; cdt.num_all_faces()];
    for f in &queue {
        queued[f.index()] = true;
    }
    let push = |queue: &mut VecDeque<_>, queued: &mut Vec<bool>, f: FixedFaceHandle<InnerTag>| {
        if queued.len() <= f.index() {
            queued.resize(f.index() + 1, false);
        }
        if !queued[f.index()] {
            queued[f.index()] = true;
            queue.push_back(f);
        }
    };
    let push_around = |cdt: &Cdt, queue: &mut VecDeque<_>, queued: &mut Vec<bool>, v: FixedVertexHandle| {
        let faces: Vec<_> = cdt.vertex(v).out_edges().filter_map(|e| e.face().as_inner().map(|f| f.fix())).collect();
        for f in faces {
            push(queue, queued, f);
        }
    };

    while let Some(fh) = queue.pop_front() {
        queued[fh.index()] = false;
        let face = cdt.face(fh);
        let p = face.positions();
        let edges = face.adjacent_edges();
        // Edge k runs from vertex k to vertex k + 1; the angle at vertex k lies between edges
        // k - 1 and k.
        let fixed = edges.map(|e| e.is_constraint_edge());
        let und = edges.map(|e| e.fix().as_undirected());
        let verts = face.vertices().map(|v| v.fix());
        let l2 = [d2(p[0], p[1]), d2(p[1], p[2]), d2(p[2], p[0])];
        let mut bad = false;
        for k in 0..3 {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (u, v) = ([b.x - a.x, b.y - a.y], [c.x - a.x, c.y - a.y]);
            let ang = (u[0] * v[1] - u[1] * v[0]).abs().atan2(u[0] * v[0] + u[1] * v[1]);
            if ang < limit && !(fixed[k] && fixed[(k + 2) % 3]) {
                bad = true;
            }
        }
        if !bad {
            continue;
        }
        let s = SPoint::new((p[0].x + p[1].x + p[2].x) / 3.0, (p[0].y + p[1].y + p[2].y) / 3.0);
        if !region.contains([s.x, s.y]) {
            continue;
        }
        if l2.iter().copied().fold(f64::INFINITY, f64::min) < min_len2 {
            complete = false;
            continue;
        }
        if added >= budget {
            complete = false;
            break;
        }
        let c = off_centre(p, face.circumcenter(), limit + OFF_CENTRE_MARGIN.to_radians());
        let hint = face.vertices()[0].fix();
        let split = match walk(cdt, fh, s, c) {
            Walk::Stuck => continue,
            Walk::Crossed(e) => Some(e),
            Walk::Inside(fc) => encroached(cdt, fc, c, cos_lens),
        };
        match split {
            Some(e) => {
                // A free vertex (a lattice seed or one of spade's, not on a constraint) too near
                // a segment of this triangle goes, rather than the segment being split (which
                // would add a contour vertex a seam may count on).
                if let Some(k) = (0..3).find(|&k| und[k] == e) {
                    let opp = verts[(k + 2) % 3];
                    let free = removals < max_removals
                        && requeued + cdt.num_inner_faces() <= REQUEUE_WORK
                        && opp.index() >= input.n_constraint
                        && !cdt.vertex(opp).out_edges().any(|e| e.is_constraint_edge());
                    if free {
                        cdt.remove(opp);
                        removals += 1;
                        requeued += cdt.num_inner_faces();
                        sharp.swap_remove(opp.index());
                        // Removal renumbers handles: visit every face again.
                        queue.clear();
                        queued.iter_mut().for_each(|q| *q = false);
                        for f in cdt.fixed_inner_faces().collect::<Vec<_>>() {
                            push(&mut queue, &mut queued, f);
                        }
                        continue;
                    }
                }
                let [a, b] = cdt.undirected_edge(e).vertices().map(|v| v.fix());
                let (pa, pb) = (cdt.vertex(a).position(), cdt.vertex(b).position());
                let len2 = d2(pa, pb);
                if len2 < 4.0 * min_len2 {
                    complete = false;
                    continue;
                }
                let len = len2.sqrt();
                let is_sharp = |v: FixedVertexHandle| sharp.get(v.index()).copied().unwrap_or(false);
                let t = match (is_sharp(a), is_sharp(b)) {
                    (true, false) => shell(len, h),
                    (false, true) => 1.0 - shell(len, h),
                    _ => 0.5,
                };
                let q = SPoint::new(pa.x + t * (pb.x - pa.x), pa.y + t * (pb.y - pa.y));
                cdt.remove_constraint_edge(e);
                let n_before = cdt.num_vertices();
                let Ok(v) = cdt.insert_with_hint(q, a) else {
                    cdt.add_constraint(a, b);
                    continue;
                };
                if v.index() < n_before {
                    // Coincides with a vertex already there (cannot happen on a proper segment).
                    cdt.add_constraint(a, b);
                    continue;
                }
                added += 1;
                sharp.resize(cdt.num_vertices(), false);
                for (x, y) in [(a, v), (v, b)] {
                    if cdt.can_add_constraint(x, y) {
                        cdt.add_constraint(x, y);
                    } else {
                        cdt.add_constraint_and_split(x, y, |p| p);
                    }
                }
                for w in [v, a, b] {
                    push_around(cdt, &mut queue, &mut queued, w);
                }
                push(&mut queue, &mut queued, fh);
            }
            None => {
                let n_before = cdt.num_vertices();
                let Ok(v) = cdt.insert_with_hint(c, hint) else { continue };
                if v.index() < n_before {
                    continue;
                }
                added += 1;
                sharp.resize(cdt.num_vertices(), false);
                push_around(cdt, &mut queue, &mut queued, v);
            }
        }
    }
    complete
}

/// Üngör's off-centre of triangle `p`: the point on the bisector of its shortest edge, on the
/// triangle's side, that sees that edge under `apex`, when it is nearer than the circumcentre
/// `cc` (which it is for a skinny triangle); else the circumcentre.
fn off_centre(p: [SPoint<f64>; 3], cc: SPoint<f64>, apex: f64) -> SPoint<f64> {
    let l2 = [d2(p[0], p[1]), d2(p[1], p[2]), d2(p[2], p[0])];
    let k = (0..3).min_by(|&i, &j| l2[i].total_cmp(&l2[j])).unwrap_or(0);
    let (a, b) = (p[k], p[(k + 1) % 3]);
    let mid = SPoint::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
    let half = 0.5 * l2[k].sqrt();
    let d = half / (0.5 * apex).tan();
    let (dc2, n) = (d2(mid, cc), [-(b.y - a.y), b.x - a.x]);
    if d * d >= dc2 || half == 0.0 {
        return cc;
    }
    // Towards the third vertex.
    let side = if orient(a, b, p[(k + 2) % 3]) >= 0.0 { 1.0 } else { -1.0 };
    let s = side * d / (2.0 * half);
    SPoint::new(mid.x + s * n[0], mid.y + s * n[1])
}

/// Where to split a segment of length `len` with a sharp corner at its start (as a fraction
/// from the corner): at the power of two times `h` nearest half its length.
fn shell(len: f64, h: f64) -> f64 {
    let d = h * (0.5 * len / h).log2().round().exp2();
    (d / len).clamp(0.25, 0.75)
}
