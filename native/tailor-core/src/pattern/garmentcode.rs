//! GarmentCode pattern specifications (JSON, MIT, github.com/maria-korosteleva/GarmentCode).
//!
//! `pattern.panels` maps a panel name to 2D `vertices` (units given by
//! `properties.units_in_meter`, 100 = cm), `edges` whose `endpoints` index the vertices and
//! whose optional `curvature` bends them, and a 3D `translation` and `rotation` (XYZ Euler
//! degrees) that place the panel around the body. `pattern.stitches` pairs panel edges.
//!
//! Curvature follows pygarment: with e = end − start and p = e rotated +90°, a relative
//! control point (u, v) is start + u·e + v·p (`curvature_coords: "absolute"` in older files
//! gives control points as is). `quadratic` has one, `cubic` two; the oldest files write a
//! bare `[u, v]` quadratic control point. `circle` is `[radius, large_arc, right]`: the arc of
//! that radius through both ends, the larger of the two when `large_arc`, bulging to the right
//! of the edge direction when `right` (the SVG arc with sweep = !right in a y-down frame).
//!
//! Panels come in `panel_order` when the file has it, else in name order. Each edge becomes an
//! [`OutlineSpan`] of the flattened outline, so `Piece::edges[i]` is GarmentCode edge `i`. An
//! outline the file lists clockwise (GarmentCode does this for panels facing backwards) is
//! reversed to counter-clockwise: each span then runs from the file edge's end vertex to its
//! start vertex, and `Placement::flipped` records the reversal.
//!
//! A stitch `[{panel, edge}, {panel, edge}]` sews the two edges in opposite senses of the
//! file's vertex order, A's start to B's end: two panels seen from their right side walk a
//! shared edge in opposite senses (pygarment's box mesh: `swap`, the default). A third element
//! `"right_wrong"` sews them in the same sense. After the reader turns clockwise panels round,
//! B is walked clockwise ([`Stitch::b_clockwise`]) when both panels or neither were turned,
//! and the other way when exactly one was (or the stitch is right-to-wrong). Choosing by the
//! pieces' 3D placement instead (the nearer pairing of the two edges) gets it wrong where a
//! placement puts the edges crosswise: the hoody's hood stands beside the head with its
//! neckline's back corner nearer the shoulder than the centre back, and sewn that way the
//! hood gathered the whole back neckline into a bunch at the nape.

use super::{flatten, outline, OutlineSpan, Pattern, Piece, Placement, Point2, ReadOptions, Stitch, StitchSide};
use crate::error::{Result, TailorError};
use serde_json::Value;
use std::f64::consts::PI;

const CORNER_TURN_DEG: f64 = 30.0;
const MAX_EDGES: usize = 100_000;

struct Ctx<'a> {
    file: &'a str,
    relative: bool,
    /// Flattening tolerance in file units.
    tol: f64,
    /// Points still allowed (see [`outline::MAX_POINTS`]).
    budget: std::cell::Cell<usize>,
}

fn f(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

fn pt(v: &Value) -> Option<Point2> {
    let a = v.as_array()?;
    if a.len() < 2 {
        return None;
    }
    Some([f(&a[0])?, f(&a[1])?])
}

fn vec3(v: Option<&Value>) -> Option<[f64; 3]> {
    let a = v?.as_array()?;
    if a.len() != 3 {
        return None;
    }
    Some([f(&a[0])?, f(&a[1])?, f(&a[2])?])
}

pub fn read(file: &str, bytes: &[u8], opts: &ReadOptions) -> Result<Pattern> {
    let root: Value = serde_json::from_slice(bytes).map_err(|e| TailorError::parse(file, "JSON", e.to_string()))?;
    let pattern = root.get("pattern").ok_or_else(|| TailorError::parse(file, "JSON", "no \"pattern\" object"))?;
    let panels = pattern
        .get("panels")
        .and_then(Value::as_object)
        .ok_or_else(|| TailorError::parse(file, "pattern", "no \"panels\" object"))?;
    let props = root.get("properties");
    let units_in_meter = props.and_then(|p| p.get("units_in_meter")).and_then(f).unwrap_or(100.0);
    if units_in_meter.is_nan() || units_in_meter <= 0.0 {
        return Err(TailorError::parse(file, "properties.units_in_meter", "must be positive"));
    }
    let scale = match opts.units_override {
        Some(u) => u.metres(),
        None => 1.0 / units_in_meter,
    };
    let relative = props.and_then(|p| p.get("curvature_coords")).and_then(Value::as_str) != Some("absolute");
    let ctx = Ctx { file, relative, tol: opts.tolerance_m / scale, budget: outline::MAX_POINTS.into() };

    let mut order: Vec<String> = match pattern.get("panel_order").and_then(Value::as_array) {
        Some(list) => {
            list.iter().filter_map(|v| v.as_str().map(str::to_string)).filter(|n| panels.contains_key(n)).collect()
        }
        None => Vec::new(),
    };
    let mut rest: Vec<String> = panels.keys().filter(|k| !order.contains(k)).cloned().collect();
    rest.sort();
    order.extend(rest);

    let mut pieces = Vec::with_capacity(order.len());
    let mut turned = Vec::with_capacity(order.len());
    for name in &order {
        let (piece, flipped) = panel(&ctx, name, &panels[name], scale)?;
        pieces.push(piece);
        turned.push(flipped);
    }
    let stitches = match pattern.get("stitches") {
        None => Vec::new(),
        Some(s) => {
            let list = s.as_array().ok_or_else(|| TailorError::parse(file, "pattern.stitches", "is not a list"))?;
            list.iter().enumerate().map(|(i, s)| stitch(&ctx, i, s, &order, &pieces, &turned)).collect::<Result<_>>()?
        }
    };
    Ok(Pattern { source: file.to_string(), pieces, stitches, sizes: Vec::new(), size: None })
}

/// Stitch `i`; `turned[p]` says whether piece `p`'s outline was reversed on reading.
fn stitch(ctx: &Ctx, i: usize, s: &Value, order: &[String], pieces: &[Piece], turned: &[bool]) -> Result<Stitch> {
    let err = |reason: String| TailorError::parse(ctx.file, format!("stitch {i}"), reason);
    let list = s.as_array().map(Vec::as_slice);
    let (sides, right_wrong) = match list {
        Some([a, b]) => ([a, b], false),
        Some([a, b, Value::String(t)]) if t == "right_wrong" => ([a, b], true),
        _ => return Err(err("is not a pair of {panel, edge} (optionally followed by \"right_wrong\")".into())),
    };
    let side = |v: &Value| -> Result<StitchSide> {
        let name = v.get("panel").and_then(Value::as_str).ok_or_else(|| err("a side has no \"panel\" name".into()))?;
        let piece =
            order.iter().position(|n| n == name).ok_or_else(|| err(format!("panel {name:?} does not exist")))?;
        let edge = v.get("edge").and_then(Value::as_u64).ok_or_else(|| err(format!("panel {name:?}: no edge index")))?
            as usize;
        if edge >= pieces[piece].edges.len() {
            return Err(err(format!("panel {name:?} edge {edge}: the panel has {} edges", pieces[piece].edges.len())));
        }
        Ok(StitchSide { piece, edge })
    };
    let (a, b) = (side(sides[0])?, side(sides[1])?);
    let b_clockwise = (turned[a.piece] == turned[b.piece]) != right_wrong;
    Ok(Stitch { a, b, b_clockwise })
}

/// The panel as a piece, and whether its outline was listed clockwise (and turned round).
fn panel(ctx: &Ctx, name: &str, p: &Value, scale: f64) -> Result<(Piece, bool)> {
    let who = format!("panel {name:?}");
    let err = |entity: &str, reason: String| TailorError::parse(ctx.file, entity, reason);
    let verts: Vec<Point2> = p
        .get("vertices")
        .and_then(Value::as_array)
        .ok_or_else(|| err(&who, "no \"vertices\" list".into()))?
        .iter()
        .enumerate()
        .map(|(i, v)| pt(v).ok_or_else(|| err(&format!("{who} vertex {i}"), "is not a pair of finite numbers".into())))
        .collect::<Result<_>>()?;
    let edges = p.get("edges").and_then(Value::as_array).ok_or_else(|| err(&who, "no \"edges\" list".into()))?;
    if edges.len() < 2 || edges.len() > MAX_EDGES {
        return Err(err(&who, format!("{} edges cannot enclose a panel", edges.len())));
    }
    let mut pts: Vec<Point2> = Vec::new();
    let mut starts = Vec::with_capacity(edges.len());
    let mut prev_end = None;
    for (i, e) in edges.iter().enumerate() {
        let ename = format!("{who} edge {i}");
        let ends = e.get("endpoints").and_then(Value::as_array).filter(|a| a.len() == 2);
        let ends = ends.ok_or_else(|| err(&ename, "no \"endpoints\" pair".into()))?;
        let idx = |v: &Value| {
            v.as_u64().map(|x| x as usize).filter(|x| *x < verts.len()).ok_or_else(|| {
                err(&ename, format!("endpoint {v} is not a vertex index (the panel has {} vertices)", verts.len()))
            })
        };
        let (a, b) = (idx(&ends[0])?, idx(&ends[1])?);
        if prev_end.is_some_and(|pe| pe != a) {
            return Err(err(&ename, "does not start where the previous edge ends (edges must form one loop)".into()));
        }
        prev_end = Some(b);
        starts.push(pts.len());
        pts.push(verts[a]);
        edge_points(ctx, &ename, verts[a], verts[b], e.get("curvature"), &mut pts)?;
        pts.pop(); // the end is the next edge's start
        if pts.len() > ctx.budget.get() {
            return Err(TailorError::Unsupported {
                file: ctx.file.into(),
                entity: ename,
                reason: "too many points in the file".into(),
            });
        }
    }
    let first = edges[0].get("endpoints").and_then(|a| a.get(0)).and_then(Value::as_u64);
    if prev_end.map(|x| x as u64) != first {
        return Err(err(
            &format!("{who} edge {}", edges.len() - 1),
            "does not end where edge 0 starts (open loop)".into(),
        ));
    }
    let n = pts.len();
    ctx.budget.set(ctx.budget.get() - n);
    if n < 3 || !outline::all_finite(&pts) {
        return Err(err(&who, "outline has fewer than 3 points or non-finite coordinates".into()));
    }
    let mut pts: Vec<Point2> = pts.iter().map(|q| [q[0] * scale, q[1] * scale]).collect();
    let mut spans: Vec<OutlineSpan> = (0..starts.len())
        .map(|i| OutlineSpan { start: starts[i], end: starts.get(i + 1).copied().unwrap_or(0) })
        .collect();
    let area = outline::signed_area(&pts);
    if area.is_nan() || area == 0.0 {
        return Err(err(&who, "outline has no area".into()));
    }
    let flipped = area < 0.0;
    if flipped {
        // Keep vertex 0 at index 0: new[k] = old[(n - k) % n].
        let old = pts.clone();
        for (k, q) in pts.iter_mut().enumerate() {
            *q = old[(n - k) % n];
        }
        let map = |j: usize| (n - j) % n;
        for s in &mut spans {
            *s = OutlineSpan { start: map(s.end), end: map(s.start) };
        }
    }
    let mut fixed: Vec<usize> = spans.iter().flat_map(|s| [s.start, s.end]).collect();
    fixed.extend(outline::sharp_corners(&pts, CORNER_TURN_DEG));
    fixed.sort_unstable();
    fixed.dedup();
    let translation = vec3(p.get("translation")).map(|t| [t[0] * scale, t[1] * scale, t[2] * scale]);
    let rotation = vec3(p.get("rotation"));
    let placement = match (translation, rotation) {
        (None, None) => None,
        (t, r) => Some(Placement { translation: t.unwrap_or([0.0; 3]), rotation_deg: r.unwrap_or([0.0; 3]), flipped }),
    };
    let piece = Piece {
        name: name.to_string(),
        outline: pts,
        fixed_vertices: fixed,
        holes: Vec::new(),
        internal_lines: Vec::new(),
        notches: Vec::new(),
        grain: None,
        placement,
        edges: spans,
    };
    Ok((piece, flipped))
}

/// Appends the points of one edge after `s`, ending with `e`.
fn edge_points(ctx: &Ctx, who: &str, s: Point2, e: Point2, curv: Option<&Value>, out: &mut Vec<Point2>) -> Result<()> {
    let bad = |reason: &str| TailorError::parse(ctx.file, who, reason.to_string());
    let abs = |c: Point2| {
        if ctx.relative {
            let (ex, ey) = (e[0] - s[0], e[1] - s[1]);
            [s[0] + c[0] * ex - c[1] * ey, s[1] + c[0] * ey + c[1] * ex]
        } else {
            c
        }
    };
    let Some(curv) = curv.filter(|c| !c.is_null()) else {
        out.push(e);
        return Ok(());
    };
    if let Some(c) = pt(curv) {
        flatten::quadratic(s, abs(c), e, ctx.tol, out);
        return Ok(());
    }
    let kind = curv.get("type").and_then(Value::as_str).ok_or_else(|| bad("curvature has no \"type\""))?;
    let params = curv.get("params").and_then(Value::as_array).ok_or_else(|| bad("curvature has no \"params\" list"))?;
    match kind {
        "quadratic" => {
            let c = params.first().and_then(pt).ok_or_else(|| bad("quadratic curvature needs one control point"))?;
            flatten::quadratic(s, abs(c), e, ctx.tol, out);
        }
        "cubic" => {
            let (c1, c2) = match (params.first().and_then(pt), params.get(1).and_then(pt)) {
                (Some(a), Some(b)) => (a, b),
                _ => return Err(bad("cubic curvature needs two control points")),
            };
            flatten::cubic(s, abs(c1), abs(c2), e, ctx.tol, out);
        }
        "circle" => {
            let r = params.first().and_then(f).ok_or_else(|| bad("circle curvature needs a radius"))?;
            let flag = |i: usize| {
                params.get(i).map(|v| v.as_f64().map(|x| x != 0.0).or(v.as_bool()).unwrap_or(false)).unwrap_or(false)
            };
            circle(s, e, r, flag(1), flag(2), ctx.tol, out).map_err(|r| bad(&r))?;
        }
        other => {
            return Err(TailorError::Unsupported {
                file: ctx.file.into(),
                entity: who.into(),
                reason: format!("curvature type {other:?}"),
            })
        }
    }
    Ok(())
}

/// The circle arc of radius `r` from `s` to `e` (see the module docs for the flags).
fn circle(
    s: Point2,
    e: Point2,
    r: f64,
    large: bool,
    right: bool,
    tol: f64,
    out: &mut Vec<Point2>,
) -> Result<(), String> {
    let chord = outline::dist(s, e);
    if r.is_nan() || r <= 0.0 || chord == 0.0 {
        return Err(format!("circle arc radius {r} with chord {chord} is degenerate"));
    }
    // pygarment treats a radius within rounding of half the chord as a half circle.
    if r < chord / 2.0 * (1.0 - 1e-6) {
        return Err(format!("circle arc radius {r} is shorter than half the chord {}", chord / 2.0));
    }
    let r = r.max(chord / 2.0);
    let c = (r * r - chord * chord / 4.0).max(0.0).sqrt();
    let (ux, uy) = ((e[0] - s[0]) / chord, (e[1] - s[1]) / chord);
    // Unit normal towards the bulge: right of the direction when `right`.
    let d = if right { [uy, -ux] } else { [-uy, ux] };
    let k = if large { c } else { -c };
    let mid = [(s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0];
    let center = [mid[0] + d[0] * k, mid[1] + d[1] * k];
    let half = (chord / (2.0 * r)).clamp(-1.0, 1.0).asin();
    let theta = if large { 2.0 * PI - 2.0 * half } else { 2.0 * half };
    // Bulging right of the direction of travel means turning counter-clockwise.
    let sweep = if right { theta } else { -theta };
    let a0 = (s[1] - center[1]).atan2(s[0] - center[0]);
    let before = out.len();
    flatten::arc(center, r, a0, sweep, tol, out);
    if out.len() > before {
        let last = out.len() - 1;
        out[last] = e;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_bulges_to_the_right() {
        let mut out = Vec::new();
        circle([0.0, 0.0], [2.0, 0.0], 1.0, false, true, 1e-6, &mut out).unwrap();
        // Travelling +x, right is −y: a half circle below the chord.
        assert!(out.iter().all(|p| p[1] <= 1e-9));
        assert!(out.iter().any(|p| p[1] < -0.99));
        let mut l = Vec::new();
        circle([0.0, 0.0], [2.0, 0.0], 2.0, true, false, 1e-6, &mut l).unwrap();
        assert!(l.iter().all(|p| (p[0] - 1.0).hypot(p[1] - 3f64.sqrt()) - 2.0 < 1e-9));
        assert!(l.iter().any(|p| p[1] > 3.0));
    }
}
