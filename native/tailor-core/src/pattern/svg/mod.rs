//! SVG sewing patterns.
//!
//! Every closed subpath of a `path`, `rect`, `circle`, `ellipse`, `polygon` or closed
//! `polyline` is an outline; open ones are internal lines of the piece they start in. Shapes
//! inside a `<g>` that has an `inkscape:label` or `id` (and is not an Inkscape layer) form one
//! piece named after the nearest such group (several outlines in it: `name 2`, `name 3`...); other outlines are pieces named by their own
//! `inkscape:label`, else `id`, else `piece N`. An outline inside another is its hole.
//! `transform`s are composed through nested groups; `<defs>`, `<use>`, clip paths, masks,
//! markers and text are ignored.
//!
//! Units: one user unit is `width / viewBox width` (and likewise for height; the smaller
//! scale wins, as `preserveAspectRatio="xMidYMid meet"` does), with `width`/`height` in mm,
//! cm, in, pt, pc or px (1/96 in; unitless = px). Without an absolute width and height a user
//! unit is a px. `ReadOptions::units_override` sets the size of one user unit directly. SVG's
//! y axis points down; pieces are flipped to y up.

mod path;

use super::outline;
use super::{Pattern, Piece, Point2, ReadOptions, Units};
use crate::error::{Result, TailorError};
use path::SubPath;
use roxmltree::Node;
use svgtypes::{Length, LengthUnit, Transform};

const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";
const MAX_DEPTH: usize = 256;
const CORNER_TURN_DEG: f64 = 30.0;

struct Item {
    points: Vec<Point2>,
    closed: bool,
    /// The element's own name (label or id).
    name: Option<String>,
    /// Index into the named groups, for shapes inside one.
    group: Option<usize>,
}

struct Ctx<'f> {
    file: &'f str,
    /// Metres per user unit.
    scale: f64,
    tol_m: f64,
    items: Vec<Item>,
    groups: Vec<String>,
    /// Points still allowed (see [`outline::MAX_POINTS`]).
    budget: usize,
}

fn length_m(l: Length) -> Option<f64> {
    let unit = match l.unit {
        LengthUnit::None | LengthUnit::Px => Units::Pixels.metres(),
        LengthUnit::Mm => Units::Millimetres.metres(),
        LengthUnit::Cm => Units::Centimetres.metres(),
        LengthUnit::In => Units::Inches.metres(),
        LengthUnit::Pt => Units::Points.metres(),
        LengthUnit::Pc => Units::Points.metres() * 12.0,
        _ => return None,
    };
    Some(l.number * unit).filter(|v| v.is_finite() && *v > 0.0)
}

fn user_unit_m(root: Node, opts: &ReadOptions) -> f64 {
    if let Some(u) = opts.units_override {
        return u.metres();
    }
    let dim = |a: &str| root.attribute(a).and_then(|v| v.parse::<Length>().ok()).and_then(length_m);
    let vb = root.attribute("viewBox").and_then(|v| v.parse::<svgtypes::ViewBox>().ok());
    let px = Units::Pixels.metres();
    match vb {
        Some(vb) => {
            let sx = dim("width").map(|w| w / vb.w);
            let sy = dim("height").map(|h| h / vb.h);
            match (sx, sy) {
                (Some(a), Some(b)) => a.min(b),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => px,
            }
        }
        None => px,
    }
}

fn name_of(n: Node) -> Option<String> {
    n.attribute((INKSCAPE_NS, "label"))
        .or_else(|| n.attribute("id"))
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
}

fn describe(n: Node) -> String {
    match n.attribute("id") {
        Some(id) => format!("<{} id={id:?}>", n.tag_name().name()),
        None => format!("<{}> at byte {}", n.tag_name().name(), n.range().start),
    }
}

fn num(ctx: &Ctx, n: Node, attr: &str) -> Result<Option<f64>> {
    match n.attribute(attr) {
        None => Ok(None),
        Some(v) => {
            let l = v
                .parse::<Length>()
                .map_err(|e| TailorError::parse(ctx.file, describe(n), format!("{attr}={v:?}: {e}")))?;
            if !matches!(l.unit, LengthUnit::None | LengthUnit::Px) || !l.number.is_finite() {
                return Err(TailorError::Unsupported {
                    file: ctx.file.into(),
                    entity: describe(n),
                    reason: format!("{attr}={v:?}: only plain numbers are supported in shape attributes"),
                });
            }
            Ok(Some(l.number))
        }
    }
}

fn mul(a: &Transform, b: &Transform) -> Transform {
    Transform::new(
        a.a * b.a + a.c * b.b,
        a.b * b.a + a.d * b.b,
        a.a * b.c + a.c * b.d,
        a.b * b.c + a.d * b.d,
        a.a * b.e + a.c * b.f + a.e,
        a.b * b.e + a.d * b.f + a.f,
    )
}

fn walk(ctx: &mut Ctx, n: Node, parent: &Transform, group: Option<usize>, depth: usize) -> Result<()> {
    if depth > MAX_DEPTH {
        return Err(TailorError::parse(ctx.file, describe(n), format!("elements nested more than {MAX_DEPTH} deep")));
    }
    let tag = n.tag_name().name();
    if matches!(
        tag,
        "defs" | "clipPath" | "mask" | "marker" | "pattern" | "symbol" | "metadata" | "text" | "style" | "use"
    ) {
        return Ok(());
    }
    let local = match n.attribute("transform") {
        Some(t) => t
            .parse::<Transform>()
            .map_err(|e| TailorError::parse(ctx.file, describe(n), format!("transform {t:?}: {e}")))?,
        None => Transform::default(),
    };
    let m = mul(parent, &local);
    // Flatten in user space with a tolerance that the transform's largest stretch (its
    // largest singular value) scales to at most `tol_m`.
    let (sq, det) = (m.a * m.a + m.b * m.b + m.c * m.c + m.d * m.d, m.a * m.d - m.b * m.c);
    let stretch = ((sq + (sq * sq - 4.0 * det * det).max(0.0).sqrt()) / 2.0).sqrt() * ctx.scale;
    if !(stretch.is_finite() && stretch > 0.0 && det != 0.0) {
        return Ok(());
    }
    let tol = ctx.tol_m / stretch;
    let subs: Vec<SubPath> = match tag {
        "g" | "svg" | "a" | "switch" => {
            let is_layer = n.attribute((INKSCAPE_NS, "groupmode")) == Some("layer");
            let g = if tag == "g" && !is_layer && depth > 0 {
                name_of(n).map(|nm| {
                    ctx.groups.push(nm);
                    ctx.groups.len() - 1
                })
            } else {
                None
            };
            // The nearest named group owns a shape, so a wrapper group around labelled pieces
            // does not swallow them.
            let g = g.or(group);
            for c in n.children().filter(|c| c.is_element()) {
                walk(ctx, c, &m, g, depth + 1)?;
            }
            return Ok(());
        }
        "path" => match n.attribute("d") {
            Some(d) => path::parse_path(d, tol).map_err(|e| TailorError::parse(ctx.file, describe(n), e))?,
            None => Vec::new(),
        },
        "rect" => {
            let (x, y) = (num(ctx, n, "x")?.unwrap_or(0.0), num(ctx, n, "y")?.unwrap_or(0.0));
            let (w, h) = (num(ctx, n, "width")?.unwrap_or(0.0), num(ctx, n, "height")?.unwrap_or(0.0));
            if w > 0.0 && h > 0.0 {
                vec![path::rect(x, y, w, h, num(ctx, n, "rx")?, num(ctx, n, "ry")?, tol)]
            } else {
                Vec::new()
            }
        }
        "circle" | "ellipse" => {
            let (cx, cy) = (num(ctx, n, "cx")?.unwrap_or(0.0), num(ctx, n, "cy")?.unwrap_or(0.0));
            let (rx, ry) = if tag == "circle" {
                let r = num(ctx, n, "r")?.unwrap_or(0.0);
                (r, r)
            } else {
                (num(ctx, n, "rx")?.unwrap_or(0.0), num(ctx, n, "ry")?.unwrap_or(0.0))
            };
            if rx > 0.0 && ry > 0.0 {
                vec![path::ellipse(cx, cy, rx, ry, tol)]
            } else {
                Vec::new()
            }
        }
        "polygon" | "polyline" => {
            let pts: Vec<Point2> =
                svgtypes::PointsParser::from(n.attribute("points").unwrap_or("")).map(|(x, y)| [x, y]).collect();
            let closed = tag == "polygon" || (pts.len() > 2 && pts.first() == pts.last());
            vec![SubPath { points: pts, closed }]
        }
        "line" => {
            let p = |a, b| -> Result<Point2> { Ok([num(ctx, n, a)?.unwrap_or(0.0), num(ctx, n, b)?.unwrap_or(0.0)]) };
            vec![SubPath { points: vec![p("x1", "y1")?, p("x2", "y2")?], closed: false }]
        }
        _ => Vec::new(),
    };
    let name = name_of(n);
    for s in subs {
        let pts: Vec<Point2> = s
            .points
            .iter()
            .map(|p| {
                let (x, y) = (m.a * p[0] + m.c * p[1] + m.e, m.b * p[0] + m.d * p[1] + m.f);
                [x * ctx.scale, -y * ctx.scale]
            })
            .collect();
        ctx.budget = ctx.budget.checked_sub(pts.len()).ok_or_else(|| TailorError::Unsupported {
            file: ctx.file.into(),
            entity: describe(n),
            reason: "too many points in the file".into(),
        })?;
        if !outline::all_finite(&pts) {
            return Err(TailorError::parse(ctx.file, describe(n), "non-finite coordinates"));
        }
        ctx.items.push(Item { points: pts, closed: s.closed, name: name.clone(), group });
    }
    Ok(())
}

pub fn read(file: &str, bytes: &[u8], opts: &ReadOptions) -> Result<Pattern> {
    let text = std::str::from_utf8(bytes).map_err(|e| TailorError::parse(file, "file", format!("not UTF-8: {e}")))?;
    let popts = roxmltree::ParsingOptions { allow_dtd: true, nodes_limit: 2_000_000, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(text, popts)
        .map_err(|e| TailorError::parse(file, "XML", e.to_string()))?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(TailorError::parse(file, format!("<{}>", root.tag_name().name()), "the root element is not <svg>"));
    }
    let mut ctx = Ctx {
        file,
        scale: user_unit_m(root, opts),
        tol_m: opts.tolerance_m,
        items: Vec::new(),
        groups: Vec::new(),
        budget: outline::MAX_POINTS,
    };
    walk(&mut ctx, root, &Transform::default(), None, 0)?;
    if ctx.items.iter().filter(|i| i.closed).count() > outline::MAX_LOOPS {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: "<svg>".into(),
            reason: "too many closed outlines".into(),
        });
    }
    let pieces = build_pieces(&mut ctx);
    if pieces.is_empty() {
        return Err(TailorError::parse(
            file,
            "<svg>",
            "no closed outline (closed path, rect, circle, ellipse or polygon)",
        ));
    }
    Ok(Pattern { source: file.to_string(), pieces, stitches: Vec::new(), sizes: Vec::new(), size: None })
}

fn build_pieces(ctx: &mut Ctx) -> Vec<Piece> {
    for it in &mut ctx.items {
        if it.closed {
            outline::dedup_closed(&mut it.points, 1e-12);
        }
    }
    let items = &ctx.items;
    let mut pieces: Vec<Piece> = Vec::new();
    let mut owners: Vec<Option<usize>> = Vec::new();
    let partitions: Vec<Option<usize>> = std::iter::once(None).chain((0..ctx.groups.len()).map(Some)).collect();
    for part in partitions {
        let idx: Vec<usize> = (0..items.len())
            .filter(|&i| items[i].group == part && items[i].closed && items[i].points.len() >= 3)
            .filter(|&i| outline::signed_area(&items[i].points).abs() > 0.0)
            .collect();
        let loops: Vec<Vec<Point2>> = idx.iter().map(|&i| items[i].points.clone()).collect();
        for (k, (o, hs)) in outline::nest_indices(&loops).into_iter().enumerate() {
            let name = match part {
                Some(g) if k == 0 => ctx.groups[g].clone(),
                Some(g) => format!("{} {}", ctx.groups[g], k + 1),
                None => items[idx[o]].name.clone().unwrap_or_else(|| format!("piece {}", pieces.len() + 1)),
            };
            let mut out = loops[o].clone();
            outline::orient(&mut out, true);
            let holes = hs
                .iter()
                .map(|&h| {
                    let mut hole = loops[h].clone();
                    outline::orient(&mut hole, false);
                    hole
                })
                .collect();
            let fixed = outline::sharp_corners(&out, CORNER_TURN_DEG);
            pieces.push(Piece {
                name,
                outline: out,
                fixed_vertices: fixed,
                holes,
                internal_lines: Vec::new(),
                notches: Vec::new(),
                grain: None,
                placement: None,
                edges: Vec::new(),
            });
            owners.push(part);
        }
    }
    for it in items.iter().filter(|it| !it.closed && it.points.len() >= 2) {
        let inside = |p: &Piece| outline::contains(&p.outline, it.points[0]);
        let target = (0..pieces.len())
            .find(|&i| owners[i] == it.group && inside(&pieces[i]))
            .or_else(|| pieces.iter().position(inside));
        if let Some(i) = target {
            pieces[i].internal_lines.push(it.points.clone());
        }
    }
    pieces
}
