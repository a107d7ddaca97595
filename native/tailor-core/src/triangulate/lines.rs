//! Internal lines and notches as CAD exports really draw them.
//!
//! A CAD export rarely ends an internal line exactly on the outline: CLO's DXF had line ends a
//! fraction of a micrometre from an outline vertex (a pin beside a pin: 0.001° slivers) and
//! lines overshooting the outline by 0.03-1.2 mm, or starting 7 mm outside it. Before meshing:
//!
//! * **Snap.** An internal line's end (or a notch) within the *snap tolerance*
//!   [`snap_tolerance`] `= max(h/4, 3 mm)` of the outline or a hole is moved onto it; and if an
//!   *anchor* lies within that tolerance too it is moved onto the anchor exactly. Anchors are
//!   the outline's and holes' own pins (fixed vertices, stitch span ends, vertices turning by
//!   `corner_turn_deg`), and the line ends and notches already snapped, so two pins never sit a
//!   sliver apart.
//! * **Clip.** What is then still outside the piece (or inside a hole) is cut off at the
//!   outline; the parts inside are kept as lines of their own (each then snapped as above),
//!   and a warning names the piece, the line and how far it left.
//! * **Drop.** Only a line with nothing left inside (no part longer than the tolerance) is
//!   dropped, with a warning.
//! * **Join** (mesher 2 on, see [`TriangulateOptions::mesher`]). A line's end within
//!   [`join_tolerance`] of another line's vertex (an end or a corner) is moved onto it: the
//!   legging waistband's DXF draws a box as four lines whose corners miss each other by
//!   2.5-9 µm, which left 0.01° slivers no refinement can open (its floor is `h / 1024`).
//!
//! * **Cross** (mesher 3 on). Lines crossing each other (a sleeve's grain line over its
//!   balance lines), or a line ending on another's middle, are cut where they meet, so the
//!   meeting point is every line's end and one vertex of the mesh before refinement. Split
//!   after refinement (mesher 2), the crossing landed a few micrometres from the points
//!   refinement had already put on each line: the men's tee's sleeves kept triangles of
//!   1e-9 m², which the solver refuses.
//!
//! Snapping alone is silent: it moves points by less than the tolerance, under a quarter of a
//! triangle. The result is a piece whose line ends lie on the outline to rounding, which the
//! rest of the triangulation attaches exactly.

use super::options::TriangulateOptions;
use super::resample::{arc_lengths, dist, inside, project, segment_projection, sharp_vertices};
use crate::pattern::{Piece, Point2};

/// Distance within which an internal line's end or a notch is snapped onto the outline or a
/// hole, and onto a pin there: a quarter of the edge length `h`, and at least 3 mm.
pub fn snap_tolerance(h: f64) -> f64 {
    (0.25 * h).max(0.003)
}

/// Distance within which an internal line's end is joined onto another line's vertex (mesher 2
/// on): the distance under which triangulation merges pins anyway, a thousandth of `h` and at
/// least a micrometre; far below any drawn feature, above a CAD export's rounding.
pub fn join_tolerance(h: f64) -> f64 {
    (1e-3 * h).max(1e-6)
}

/// Joins line ends within `tol` of a vertex of another line: ends and vertices so linked
/// (transitively) form a group, and every end in a group moves onto the group's first inner
/// vertex (a vertex that is not an end; inner vertices never move), else onto its first end in
/// line order; repeated points this leaves are dropped. Groups rather than nearest neighbours,
/// so that a box corner where three ends meet a few micrometres apart becomes one point
/// whatever the order of the lines.
fn join_line_ends(lines: &mut [Vec<Point2>], tol: f64) {
    // Every vertex as (line, index); union-find over them.
    let ids: Vec<(usize, usize)> =
        lines.iter().enumerate().flat_map(|(k, l)| (0..l.len()).map(move |j| (k, j))).collect();
    let at = |i: usize| lines[ids[i].0][ids[i].1];
    let is_end = |i: usize| ids[i].1 == 0 || ids[i].1 + 1 == lines[ids[i].0].len();
    let mut parent: Vec<usize> = (0..ids.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for i in (0..ids.len()).filter(|&i| is_end(i)) {
        for j in 0..ids.len() {
            if ids[j].0 != ids[i].0 && dist(at(i), at(j)) <= tol {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    // The point each group's ends move to: its first inner vertex, else its first end.
    let mut target: Vec<Option<Point2>> = vec![None; ids.len()];
    for pass_inner in [true, false] {
        for i in 0..ids.len() {
            let r = root(&mut parent, i);
            if target[r].is_none() && is_end(i) != pass_inner {
                target[r] = Some(at(i));
            }
        }
    }
    let moves: Vec<(usize, usize, Point2)> = (0..ids.len())
        .filter(|&i| is_end(i))
        .filter_map(|i| target[root(&mut parent, i)].map(|q| (ids[i].0, ids[i].1, q)))
        .collect();
    for (k, j, q) in moves {
        lines[k][j] = q;
    }
    for l in lines.iter_mut() {
        l.dedup_by(|b, a| dist(*a, *b) <= 1e-12);
    }
}

/// Every line cut where another crosses it or ends on it (see the module): the meeting point
/// is computed once and becomes an end of each part, so the parts share it exactly. A meeting
/// within `tol` of a line's own vertex uses that vertex. `origin` follows the parts.
fn cut_at_crossings(lines: Vec<Vec<Point2>>, origin: Vec<usize>, tol: f64) -> (Vec<Vec<Point2>>, Vec<usize>) {
    // Per line, per segment: the (parameter, point) cuts on it.
    let mut cuts: Vec<Vec<Vec<(f64, Point2)>>> = lines.iter().map(|l| vec![Vec::new(); l.len() - 1]).collect();
    // Snapped to a vertex of either line within `tol`, else the crossing itself.
    let snap = |p: Point2, a: &[Point2], b: &[Point2]| -> Point2 {
        a.iter().chain(b).copied().find(|&v| dist(v, p) <= tol).unwrap_or(p)
    };
    for i in 0..lines.len() {
        for j in i + 1..lines.len() {
            for si in 0..lines[i].len() - 1 {
                for sj in 0..lines[j].len() - 1 {
                    let (a, b) = (lines[i][si], lines[i][si + 1]);
                    let (c, d) = (lines[j][sj], lines[j][sj + 1]);
                    let Some(t) = crossing(a, b, c, d) else { continue };
                    let p = snap([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])], &lines[i], &lines[j]);
                    for (k, s, q0, q1) in [(i, si, a, b), (j, sj, c, d)] {
                        // Inside the segment a new point; at its end a cut there unless that is
                        // the line's own end.
                        let n = lines[k].len();
                        if dist(p, q0) > tol && dist(p, q1) > tol {
                            let len = dist(q0, q1).max(f64::MIN_POSITIVE);
                            cuts[k][s].push((dist(q0, p) / len, p));
                        } else if dist(p, q1) <= tol && s + 2 < n {
                            cuts[k][s].push((1.0, q1));
                        } else if dist(p, q0) <= tol && s > 0 {
                            cuts[k][s].push((0.0, q0));
                        }
                    }
                }
            }
        }
    }
    let (mut out, mut out_origin) = (Vec::new(), Vec::new());
    for ((line, line_cuts), o) in lines.into_iter().zip(cuts).zip(origin) {
        let mut part = vec![line[0]];
        for (s, mut on) in line_cuts.into_iter().enumerate() {
            on.sort_by(|x, y| x.0.total_cmp(&y.0));
            for (_, p) in on {
                if dist(*part.last().expect("a part has a point"), p) > 1e-12 {
                    part.push(p);
                }
                if part.len() >= 2 {
                    out.push(std::mem::replace(&mut part, vec![p]));
                    out_origin.push(o);
                }
            }
            let next = line[s + 1];
            if dist(*part.last().expect("a part has a point"), next) > 1e-12 {
                part.push(next);
            }
        }
        if part.len() >= 2 {
            out.push(part);
            out_origin.push(o);
        }
    }
    (out, out_origin)
}

/// A closed loop (outline or hole) with its pins as points.
struct Loop<'a> {
    pts: &'a [Point2],
    cum: Vec<f64>,
    anchors: Vec<Point2>,
}

impl Loop<'_> {
    /// The nearest point of the loop to `p` and its distance.
    fn nearest(&self, p: Point2) -> (Point2, f64) {
        let (s, d) = project(self.pts, &self.cum, true, p);
        (super::resample::point_at(self.pts, &self.cum, true, s), d)
    }
}

/// The piece with its internal lines snapped, clipped and (only when nothing is left) dropped,
/// and its notches snapped, as the module docs say; the index in `piece` of each line of the
/// result (a clipped line may give several); and a warning per line clipped or dropped.
pub(crate) fn attach_lines(piece: &Piece, options: &TriangulateOptions) -> (Piece, Vec<usize>, Vec<String>) {
    let tol = snap_tolerance(options.edge_length);
    let mut warnings = Vec::new();
    fn loop_of<'a>(pts: &'a [Point2], mut pins: Vec<usize>, turn_deg: f64) -> Loop<'a> {
        pins.extend(sharp_vertices(pts, true, turn_deg));
        pins.sort_unstable();
        pins.dedup();
        let anchors = pins.into_iter().filter(|&i| i < pts.len()).map(|i| pts[i]).collect();
        Loop { pts, cum: arc_lengths(pts, true), anchors }
    }
    let turn = options.corner_turn_deg;
    let mut outline_pins = piece.fixed_vertices.clone();
    outline_pins.extend(piece.edges.iter().flat_map(|e| [e.start, e.end]));
    let mut loops = vec![loop_of(&piece.outline, outline_pins, turn)];
    loops.extend(piece.holes.iter().map(|h| loop_of(h, Vec::new(), turn)));
    let in_piece = |p: Point2| inside(&piece.outline, p) && !piece.holes.iter().any(|h| inside(h, p));

    // Snaps `p` onto the nearest loop (and an anchor there) when within `tol`; the anchor list
    // of that loop grows by the snapped point.
    let snap = |p: Point2, loops: &mut Vec<Loop<'_>>| -> Option<Point2> {
        let (k, (q, d)) = loops.iter().map(|l| l.nearest(p)).enumerate().min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?;
        if d > tol {
            return None;
        }
        let l = &mut loops[k];
        let anchor =
            l.anchors.iter().copied().filter(|&a| dist(a, q) <= tol).min_by(|a, b| dist(*a, q).total_cmp(&dist(*b, q)));
        let snapped = anchor.unwrap_or(q);
        if anchor.is_none() {
            l.anchors.push(snapped);
        }
        Some(snapped)
    };

    let mut out = piece.clone();
    out.notches = piece
        .notches
        .iter()
        .map(|&p| {
            // Notches farther than h/2 are left where they are (the mesh ignores them).
            let near = loops[0].nearest(p).1 <= 0.5 * options.edge_length;
            if near {
                snap(p, &mut loops).unwrap_or(p)
            } else {
                p
            }
        })
        .collect();

    let (mut lines, mut origin) = (Vec::new(), Vec::new());
    for (k, line) in piece.internal_lines.iter().enumerate() {
        let mut pts: Vec<Point2> = Vec::with_capacity(line.len());
        for &p in line {
            if pts.last().is_none_or(|&q| dist(p, q) > 1e-12) {
                pts.push(p);
            }
        }
        if pts.len() < 2 {
            warnings.push(format!("piece {}: internal line {k} dropped: it has no length", piece.name));
            continue;
        }
        // Ends within the tolerance move onto the outline first, so an overshoot is not a
        // clip.
        let n = pts.len();
        for j in [0, n - 1] {
            if let Some(q) = snap(pts[j], &mut loops) {
                pts[j] = q;
            }
        }
        let (parts, left) = inside_parts(&pts, piece, &in_piece, 0.05 * tol);
        if !left {
            lines.push(pts);
            origin.push(k);
            continue;
        }
        let outside = pts
            .iter()
            .filter(|&&p| !in_piece(p))
            .map(|&p| loops.iter().map(|l| l.nearest(p).1).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max);
        let kept: Vec<Vec<Point2>> = parts.into_iter().filter(|p| polyline_length(p) > tol).collect();
        if kept.is_empty() {
            warnings.push(format!(
                "piece {}: internal line {k} dropped: no part of it longer than {:.1} mm lies inside the piece",
                piece.name,
                tol * 1e3
            ));
            continue;
        }
        let how = if outside > 0.0 {
            format!("leaves the piece (by up to {:.1} mm); clipped at the outline", outside * 1e3)
        } else {
            "runs along the outline or a hole; cut off there".to_string()
        };
        let into = if kept.len() > 1 { format!(" into {} lines", kept.len()) } else { String::new() };
        warnings.push(format!("piece {}: internal line {k} {how}{into}", piece.name));
        for mut part in kept {
            let n = part.len();
            for j in [0, n - 1] {
                if let Some(q) = snap(part[j], &mut loops) {
                    part[j] = q;
                }
            }
            lines.push(part);
            origin.push(k);
        }
    }
    if options.mesher >= 2 {
        join_line_ends(&mut lines, join_tolerance(options.edge_length));
        // A line shorter than the tolerance that joining folded onto one point goes.
        let keep: Vec<bool> = lines.iter().map(|l| l.len() >= 2).collect();
        let mut it = keep.iter();
        origin.retain(|_| *it.next().unwrap_or(&true));
        lines.retain(|l| l.len() >= 2);
    }
    if options.mesher >= 3 {
        (lines, origin) = cut_at_crossings(lines, origin, join_tolerance(options.edge_length));
    }
    out.internal_lines = lines;
    (out, origin, warnings)
}

fn polyline_length(p: &[Point2]) -> f64 {
    p.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// The parts of polyline `pts` strictly inside the piece, cut where it crosses the outline or a
/// hole or runs along one, and whether any of it is outside or along the outline.
/// A stretch within `along` of the outline counts as running along it.
fn inside_parts(
    pts: &[Point2],
    piece: &Piece,
    in_piece: &dyn Fn(Point2) -> bool,
    along: f64,
) -> (Vec<Vec<Point2>>, bool) {
    let loops: Vec<&Vec<Point2>> = std::iter::once(&piece.outline).chain(&piece.holes).collect();
    let on_loop = |p: Point2| {
        loops.iter().any(|lp| {
            let m = lp.len();
            (0..m).any(|i| segment_projection(lp[i], lp[(i + 1) % m], p).1 <= along)
        })
    };
    let mut parts: Vec<Vec<Point2>> = Vec::new();
    let mut current: Vec<Point2> = Vec::new();
    let mut left = false;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let mut ts = vec![0.0, 1.0];
        for lp in &loops {
            let m = lp.len();
            for i in 0..m {
                if let Some(t) = crossing(a, b, lp[i], lp[(i + 1) % m]) {
                    ts.push(t);
                }
            }
        }
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|y, x| (*y - *x).abs() < 1e-12);
        let at = |t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        for s in ts.windows(2) {
            let (p0, p1) = (at(s[0]), at(s[1]));
            if dist(p0, p1) < 1e-12 {
                continue;
            }
            let mid = at(0.5 * (s[0] + s[1]));
            if in_piece(mid) && !on_loop(mid) {
                if current.is_empty() {
                    current.push(p0);
                }
                current.push(p1);
            } else {
                left = true;
                if !current.is_empty() {
                    parts.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if current.len() >= 2 {
        parts.push(current);
    }
    // A part touching the outline at one of its inner points is cut there too.
    let mut out = Vec::new();
    for part in parts {
        let mut cur = vec![part[0]];
        for (j, &p) in part.iter().enumerate().skip(1) {
            cur.push(p);
            if j + 1 < part.len() && on_loop(p) {
                left = true;
                out.push(std::mem::replace(&mut cur, vec![p]));
            }
        }
        out.push(cur);
    }
    out.retain(|p| p.len() >= 2);
    (out, left)
}

/// Parameter along `ab` where it meets segment `cd` (touching included), if it does.
fn crossing(a: Point2, b: Point2, c: Point2, d: Point2) -> Option<f64> {
    let r = [b[0] - a[0], b[1] - a[1]];
    let s = [d[0] - c[0], d[1] - c[1]];
    let den = r[0] * s[1] - r[1] * s[0];
    let scale = (r[0].hypot(r[1]) * s[0].hypot(s[1])).max(f64::MIN_POSITIVE);
    if den.abs() <= 1e-12 * scale {
        // Parallel: an end of cd on ab counts (a line running along the outline is cut there).
        let (t, dd) = segment_projection(a, b, c);
        return (dd < 1e-12).then_some(t);
    }
    let q = [c[0] - a[0], c[1] - a[1]];
    let t = (q[0] * s[1] - q[1] * s[0]) / den;
    let u = (q[0] * r[1] - q[1] * r[0]) / den;
    let e = 1e-12;
    ((-e..=1.0 + e).contains(&t) && (-e..=1.0 + e).contains(&u)).then_some(t.clamp(0.0, 1.0))
}
