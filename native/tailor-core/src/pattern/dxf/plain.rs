//! Plain DXF drawings: every closed outline (LWPOLYLINE, POLYLINE, SPLINE, CIRCLE, ELLIPSE, or
//! a chain of LINEs and ARCs meeting end to end) in ENTITIES is a piece; an outline inside
//! another is its hole; open chains inside a piece become its internal lines. INSERTs are
//! expanded with their position, scale and rotation (nested to a fixed depth). A piece is
//! named by a TEXT placed inside it, else by its layer when that is not `0`, else `piece N`.
//! Units come from `$INSUNITS`, else millimetres.

use super::document::{Document, Entity};
use super::geometry::{self, describe};
use crate::error::{Result, TailorError};
use crate::pattern::outline::{self, dist};
use crate::pattern::{Pattern, Piece, Point2, ReadOptions, Units};

const MAX_INSERT_DEPTH: usize = 8;
const CORNER_TURN_DEG: f64 = 30.0;

#[derive(Clone, Copy)]
struct Affine([f64; 6]);

impl Affine {
    const IDENTITY: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    fn apply(&self, p: Point2) -> Point2 {
        let m = self.0;
        [m[0] * p[0] + m[2] * p[1] + m[4], m[1] * p[0] + m[3] * p[1] + m[5]]
    }
    fn then(&self, outer: &Affine) -> Affine {
        let (a, b) = (self.0, outer.0);
        Affine([
            b[0] * a[0] + b[2] * a[1],
            b[1] * a[0] + b[3] * a[1],
            b[0] * a[2] + b[2] * a[3],
            b[1] * a[2] + b[3] * a[3],
            b[0] * a[4] + b[2] * a[5] + b[4],
            b[1] * a[4] + b[3] * a[5] + b[5],
        ])
    }
}

/// What [`collect`] gathers, and the fixed inputs it needs on the way down INSERTs.
struct Collected<'a> {
    file: &'a str,
    doc: &'a Document,
    /// Flattening tolerance in file units.
    tol: f64,
    paths: Vec<(Vec<Point2>, bool, String)>,
    texts: Vec<(Point2, String)>,
    budget: usize,
}

fn collect(ents: &[Entity], ctx: &str, m: Affine, depth: usize, out: &mut Collected) -> Result<()> {
    let (file, doc, tol) = (out.file, out.doc, out.tol);
    for e in ents {
        // Expanding many nested INSERTs could multiply geometry without bound.
        if out.budget == 0 {
            return Err(TailorError::parse(
                file,
                describe(ctx, e),
                "too many entities or points after expanding INSERTs",
            ));
        }
        out.budget -= 1;
        if e.kind == "INSERT" {
            let name = e.get(2).unwrap_or("");
            let Some(block) = doc.block(name) else {
                return Err(TailorError::parse(file, describe(ctx, e), format!("INSERT of unknown block {name:?}")));
            };
            if depth >= MAX_INSERT_DEPTH {
                return Err(TailorError::parse(file, describe(ctx, e), "INSERTs nested too deep (or recursive)"));
            }
            let (sx, sy) = (e.num(41).unwrap_or(1.0), e.num(42).unwrap_or(1.0));
            let rot = e.num(50).unwrap_or(0.0).to_radians();
            let (s, c) = rot.sin_cos();
            let local = Affine([c * sx, s * sx, -s * sy, c * sy, e.num(10).unwrap_or(0.0), e.num(20).unwrap_or(0.0)]);
            let bctx = format!("BLOCK {name:?}");
            collect(&block.entities, &bctx, local.then(&m), depth + 1, out)?;
            continue;
        }
        if let Some(t) = e.text() {
            if let (Some(x), Some(y)) = (e.num(10), e.num(20)) {
                out.texts.push((m.apply([x, y]), t.trim().to_string()));
            }
            continue;
        }
        if let Some(p) = geometry::path(file, ctx, e, tol)? {
            out.budget = out.budget.checked_sub(p.points.len()).ok_or_else(|| TailorError::Unsupported {
                file: file.into(),
                entity: describe(ctx, e),
                reason: "too many points in the file".into(),
            })?;
            out.paths.push((p.points.iter().map(|q| m.apply(*q)).collect(), p.closed, e.layer().to_string()));
        }
    }
    Ok(())
}

pub fn read(file: &str, doc: &Document, opts: &ReadOptions) -> Result<Pattern> {
    let units = opts
        .units_override
        .or_else(|| doc.header_num("$INSUNITS").and_then(|c| Units::from_insunits(c as i64)))
        .unwrap_or(Units::Millimetres);
    let scale = units.metres();
    let mut c = Collected {
        file,
        doc,
        tol: opts.tolerance_m / scale,
        paths: Vec::new(),
        texts: Vec::new(),
        budget: outline::MAX_POINTS,
    };
    collect(&doc.entities, "ENTITIES", Affine::IDENTITY, 0, &mut c)?;
    let sc = |p: &Point2| [p[0] * scale, p[1] * scale];
    let eps = 1e-5_f64.max(opts.tolerance_m * 0.1);
    let mut loops: Vec<(Vec<Point2>, String)> = Vec::new();
    let mut open = Vec::new();
    let mut open_layers = Vec::new();
    for (pts, closed, layer) in &c.paths {
        let pts: Vec<Point2> = pts.iter().map(sc).collect();
        if *closed {
            loops.push((pts, layer.clone()));
        } else {
            open_layers.push(layer.clone());
            open.push(pts);
        }
    }
    let mut lines = Vec::new();
    for (chain, closed) in outline::chain(open, eps) {
        if closed {
            loops.push((chain, open_layers.first().cloned().unwrap_or_default()));
        } else {
            lines.push(chain);
        }
    }
    for l in &mut loops {
        outline::dedup_closed(&mut l.0, 1e-9);
    }
    loops.retain(|l| l.0.len() >= 3 && outline::signed_area(&l.0).abs() > 0.0);
    if loops.is_empty() {
        return Err(TailorError::parse(
            file,
            "ENTITIES",
            "no closed outline (closed polyline, circle, spline or chain of lines)",
        ));
    }
    if loops.len() > outline::MAX_LOOPS {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: "ENTITIES".into(),
            reason: "too many closed outlines".into(),
        });
    }
    let layers: Vec<(Vec<Point2>, String)> = loops.clone();
    let nested = outline::nest(loops.into_iter().map(|l| l.0).collect());
    let texts: Vec<(Point2, String)> = c.texts.iter().map(|(p, t)| (sc(p), t.clone())).collect();
    let mut pieces = Vec::new();
    for (i, (mut out, holes)) in nested.into_iter().enumerate() {
        let layer = layers
            .iter()
            .find(|l| l.0.len() == out.len() && l.0.iter().any(|p| dist(*p, out[0]) == 0.0))
            .map(|l| l.1.clone());
        let name = texts
            .iter()
            .find(|(p, t)| {
                !t.is_empty() && outline::contains(&out, *p) && !holes.iter().any(|h| outline::contains(h, *p))
            })
            .map(|(_, t)| t.clone())
            .or(layer.filter(|l| l != "0" && !l.is_empty()))
            .unwrap_or_else(|| format!("piece {}", i + 1));
        let internal: Vec<Vec<Point2>> = lines.iter().filter(|l| outline::contains(&out, l[0])).cloned().collect();
        outline::dedup_closed(&mut out, 1e-9);
        let fixed = outline::sharp_corners(&out, CORNER_TURN_DEG);
        pieces.push(Piece {
            name,
            outline: out,
            fixed_vertices: fixed,
            holes,
            internal_lines: internal,
            notches: Vec::new(),
            grain: None,
            placement: None,
            edges: Vec::new(),
        });
    }
    Ok(Pattern { source: file.to_string(), pieces, stitches: Vec::new(), sizes: Vec::new(), size: None })
}
