//! Turns drawing entities (POLYLINE, LWPOLYLINE, LINE, ARC, CIRCLE, ELLIPSE, SPLINE) into
//! flattened polylines in file units. Both DXF readers use it; neither knows about bulges or
//! knot vectors.

use super::document::Entity;
use crate::error::{Result, TailorError};
use crate::pattern::{flatten, Point2};
use std::f64::consts::PI;

/// A flattened path in file units, with whether the entity was closed.
#[derive(Debug, Clone)]
pub struct Path {
    pub points: Vec<Point2>,
    pub closed: bool,
}

/// Where an entity is, for error messages: `BLOCK "FRONT-M" POLYLINE at line 1234`.
pub fn describe(ctx: &str, e: &Entity) -> String {
    format!("{ctx} {} at line {}", e.kind, e.line)
}

/// The largest coordinate or radius accepted, in the file's units (a kilometre in
/// micrometres): beyond it a value is damage, not a pattern. An arc of radius 1e308 made its
/// chain miss its neighbours and the piece disappeared without an error.
const MAX_COORD: f64 = 1e9;

fn coord(file: &str, ctx: &str, e: &Entity, code: i32) -> Result<f64> {
    let v = e.num(code).ok_or_else(|| {
        let reason = match e.get(code) {
            Some(v) => format!("group {code} is not a finite number ({v:?})"),
            None => format!("missing coordinate (group {code})"),
        };
        TailorError::parse(file, describe(ctx, e), reason)
    })?;
    if v.abs() > MAX_COORD {
        return Err(TailorError::parse(
            file,
            describe(ctx, e),
            format!("group {code} is {v:e}, beyond the {MAX_COORD:e} a pattern can use"),
        ));
    }
    Ok(v)
}

fn point(file: &str, ctx: &str, e: &Entity, cx: i32) -> Result<Point2> {
    Ok([coord(file, ctx, e, cx)?, coord(file, ctx, e, cx + 10)?])
}

/// The path drawn by `e`, or `None` for entities that draw no outline (TEXT, POINT, INSERT...).
pub fn path(file: &str, ctx: &str, e: &Entity, tol: f64) -> Result<Option<Path>> {
    let bad = |reason: &str| TailorError::parse(file, describe(ctx, e), reason.to_string());
    let path = match e.kind.as_str() {
        "POLYLINE" => {
            let flags = e.num(70).unwrap_or(0.0) as i64;
            if flags & (16 | 64) != 0 {
                return Err(TailorError::Unsupported {
                    file: file.into(),
                    entity: describe(ctx, e),
                    reason: "polygon mesh / polyface POLYLINE is not a 2D outline".into(),
                });
            }
            let mut verts = Vec::with_capacity(e.vertices.len());
            for v in &e.vertices {
                // Spline frame control points (flag 16) are not on the curve.
                if (v.num(70).unwrap_or(0.0) as i64) & 16 != 0 {
                    continue;
                }
                verts.push((point(file, ctx, v, 10)?, v.num(42).unwrap_or(0.0)));
            }
            bulged(verts, flags & 1 != 0, tol)
        }
        "LWPOLYLINE" => {
            let mut verts: Vec<(Point2, f64)> = Vec::new();
            let mut pending_x: Option<f64> = None;
            for (code, value) in &e.groups {
                let num = || value.parse::<f64>().ok().filter(|v| v.is_finite() && v.abs() <= MAX_COORD);
                match code {
                    10 => pending_x = Some(num().ok_or_else(|| bad(&format!("vertex x {value:?} is not a number")))?),
                    20 => {
                        let y = num().ok_or_else(|| bad(&format!("vertex y {value:?} is not a number")))?;
                        let x = pending_x.take().ok_or_else(|| bad("vertex y (group 20) without x (group 10)"))?;
                        verts.push(([x, y], 0.0));
                    }
                    42 => {
                        if let Some(last) = verts.last_mut() {
                            last.1 = num().unwrap_or(0.0);
                        }
                    }
                    _ => {}
                }
            }
            let closed = (e.num(70).unwrap_or(0.0) as i64) & 1 != 0;
            bulged(verts, closed, tol)
        }
        "LINE" => Path { points: vec![point(file, ctx, e, 10)?, point(file, ctx, e, 11)?], closed: false },
        "ARC" | "CIRCLE" => {
            let c = point(file, ctx, e, 10)?;
            let r = coord(file, ctx, e, 40)?;
            if r.is_nan() || r <= 0.0 {
                return Err(bad("radius (group 40) must be positive"));
            }
            let (a0, sweep, closed) = if e.kind == "CIRCLE" {
                (0.0, 2.0 * PI, true)
            } else {
                let a0 = coord(file, ctx, e, 50)?.to_radians();
                let sweep = ccw_sweep(coord(file, ctx, e, 51)?.to_radians() - a0);
                (a0, sweep, false)
            };
            let mut points = vec![[c[0] + r * a0.cos(), c[1] + r * a0.sin()]];
            flatten::arc(c, r, a0, sweep, tol, &mut points);
            if closed {
                points.pop();
            }
            Path { points, closed }
        }
        "ELLIPSE" => {
            let c = point(file, ctx, e, 10)?;
            let major = point(file, ctx, e, 11)?;
            let ratio = coord(file, ctx, e, 40)?;
            let (t0, t1) = (e.num(41).unwrap_or(0.0), e.num(42).unwrap_or(2.0 * PI));
            let sweep = ccw_sweep(t1 - t0);
            let rx = major[0].hypot(major[1]);
            let phi = major[1].atan2(major[0]);
            let mut points = Vec::new();
            let start = {
                let (x, y) = (rx * t0.cos(), rx * ratio * t0.sin());
                let (s, co) = phi.sin_cos();
                [c[0] + co * x - s * y, c[1] + s * x + co * y]
            };
            points.push(start);
            flatten::ellipse_arc(c, [rx, rx * ratio], phi, t0, sweep, tol, &mut points);
            let closed = (sweep - 2.0 * PI).abs() < 1e-9;
            if closed {
                points.pop();
            }
            Path { points, closed }
        }
        "SPLINE" => {
            let flags = e.num(70).unwrap_or(0.0) as i64;
            let degree = e.num(71).unwrap_or(3.0);
            let knots = e.nums(40);
            let (xs, ys) = (e.nums(10), e.nums(20));
            let ctrl: Vec<Point2> = xs.iter().zip(&ys).map(|(x, y)| [*x, *y]).collect();
            let points = if !ctrl.is_empty() {
                if !(1.0..=20.0).contains(&degree) {
                    return Err(bad(&format!("spline degree {degree} out of range")));
                }
                flatten::bspline(degree as usize, &knots, &ctrl, &e.nums(41), tol).ok_or_else(|| {
                    bad(&format!("{} knots do not fit {} control points of degree {degree}", knots.len(), ctrl.len()))
                })?
            } else {
                // Fit points only: the curve passes through them; their polyline is the best
                // we can do without re-solving the interpolation.
                let fit: Vec<Point2> = e.nums(11).iter().zip(&e.nums(21)).map(|(x, y)| [*x, *y]).collect();
                if fit.len() < 2 {
                    return Err(bad("spline has neither control points nor fit points"));
                }
                fit
            };
            Path { points, closed: flags & 1 != 0 }
        }
        _ => return Ok(None),
    };
    if path.points.is_empty() || !crate::pattern::outline::all_finite(&path.points) {
        return Err(bad("no usable vertices"));
    }
    Ok(Some(path))
}

/// A counter-clockwise sweep in (0, 2π] from an end-minus-start angle difference; equal angles
/// mean a full turn. (A `while sweep <= 0 { sweep += 2π }` never ends on an angle of −1e308.)
fn ccw_sweep(d: f64) -> f64 {
    let s = d.rem_euclid(2.0 * PI);
    if s > 0.0 && s.is_finite() {
        s
    } else {
        2.0 * PI
    }
}

/// Expands polyline vertices with bulges into points.
fn bulged(verts: Vec<(Point2, f64)>, closed: bool, tol: f64) -> Path {
    let n = verts.len();
    let mut points = Vec::with_capacity(n);
    if let Some(first) = verts.first() {
        points.push(first.0);
    }
    let segs = if closed { n } else { n.saturating_sub(1) };
    for i in 0..segs {
        let (p0, b) = verts[i];
        let p1 = verts[(i + 1) % n].0;
        flatten::bulge(p0, p1, b, tol, &mut points);
    }
    if closed && points.len() > 1 {
        points.pop();
    }
    Path { points, closed }
}
