//! AAMA / ASTM D6673 pattern DXF (as written by Gerber AccuMark, Lectra, CLO ...).
//!
//! Each piece is one BLOCK (inserted once in ENTITIES). Inside a block the layer says what an
//! entity is: 1 boundary, 2 turn points, 4 notches (and 80–83, the T, castle, check and U
//! notches, drawn as lines from the boundary), 7 grain line, 8 internal lines, 11 internal
//! cutouts (holes), 6 mirror line (a piece drawn as a half, cut on the fold: mirrored into the
//! whole piece unless `ReadOptions::unfold` is off, `pattern::unfold`). Not used: 3 curve
//! points, 5 grade reference, 9/10 stripe and
//! plaid references, 13 drill holes, 14 sew lines, 84 validation curves. Annotation is TEXT or
//! ATTRIB `Key: value`: `Piece Name:` and `Size:` in each block (or in ATTRIBs of its INSERT),
//! `Quantity:` in each block (how many to cut: pairs mirrored, 0 left out, `pattern::cut`),
//! `Units:` (ENGLISH = inches, METRIC = millimetres) and `Sample Size:` in ENTITIES. Without
//! `Units:` or `$INSUNITS` a file is read as inches, AAMA's default ENGLISH.
//!
//! Fixed vertices are the layer-2 turn points and the notches (inserted into the outline when
//! they fall on an edge), plus every vertex where the outline turns by more than 30°: AccuMark
//! writes turn points and notches only in the sample-size blocks, so other sizes rely on the
//! angle rule.
//!
//! A graded nest has one block per piece per size. The size imported by default is the one
//! the file marks with `Sample Size:`; when nothing marks it, it is the middle size of the
//! list in file order (the lower middle for an even count), which is where graded rules put
//! the base size. Pieces keep their block coordinates: INSERT positions only lay the nest out
//! for the plotter and mean nothing to the garment.

use super::document::{Block, Document, Entity};
use super::geometry::{self, describe};
use crate::error::{Result, TailorError};
use crate::pattern::outline::{self, dist};
use crate::pattern::{cut, unfold, Pattern, Piece, Point2, ReadOptions, Units};

/// Outline vertices turning by more than this are corners (fixed vertices).
const CORNER_TURN_DEG: f64 = 30.0;

/// A `Key: value` annotation, key lower-cased.
fn annotation(e: &Entity) -> Option<(String, String)> {
    let t = e.text()?;
    let (k, v) = t.split_once(':')?;
    Some((k.trim().to_ascii_lowercase(), v.trim().to_string()))
}

fn annotations<'a>(entities: impl Iterator<Item = &'a Entity>, key: &str) -> Option<String> {
    entities.filter_map(annotation).find(|(k, _)| k == key).map(|(_, v)| v)
}

/// The annotation entities of a block: its own and the ATTRIBs of INSERTs of it.
fn block_notes<'a>(doc: &'a Document, b: &'a Block) -> impl Iterator<Item = &'a Entity> {
    let attribs = doc
        .entities
        .iter()
        .filter(move |e| e.kind == "INSERT" && e.get(2) == Some(b.name.as_str()))
        .flat_map(|e| &e.vertices);
    b.entities.iter().chain(attribs)
}

/// True when the document looks like an AAMA/ASTM pattern (a block names its piece).
pub fn detect(doc: &Document) -> bool {
    doc.blocks.iter().any(|b| block_notes(doc, b).filter_map(annotation).any(|(k, _)| k == "piece name"))
}

/// A block that holds a piece: it has boundary geometry on layer 1.
fn is_piece(b: &Block) -> bool {
    !b.name.starts_with('*') && b.entities.iter().any(|e| e.layer() == "1" && e.kind != "TEXT" && e.kind != "POINT")
}

fn block_size(doc: &Document, b: &Block) -> Option<String> {
    annotations(block_notes(doc, b), "size")
}

/// Sizes in file order, without repeats.
pub fn sizes(doc: &Document) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in doc.blocks.iter().filter(|b| is_piece(b)).filter_map(|b| block_size(doc, b)) {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}

/// The units the file declares, if any.
pub fn file_units(file: &str, doc: &Document) -> Result<Option<Units>> {
    let all = doc.entities.iter().chain(doc.blocks.iter().flat_map(|b| &b.entities));
    match annotations(all, "units") {
        Some(u) => Units::parse(&u)
            .map(Some)
            .ok_or_else(|| TailorError::parse(file, "ENTITIES TEXT \"Units:\"", format!("unknown units {u:?}"))),
        None => Ok(doc.header_num("$INSUNITS").and_then(|c| Units::from_insunits(c as i64))),
    }
}

pub fn read(file: &str, doc: &Document, opts: &ReadOptions) -> Result<Pattern> {
    let units = match opts.units_override {
        Some(u) => u,
        None => file_units(file, doc)?.unwrap_or(Units::Inches),
    };
    let sizes = sizes(doc);
    let size = if sizes.is_empty() {
        None
    } else if let Some(want) = &opts.size {
        let found = sizes.iter().find(|s| s.trim().eq_ignore_ascii_case(want.trim()));
        Some(found.cloned().ok_or_else(|| {
            TailorError::parse(
                file,
                "size",
                format!("size {want:?} is not in the file; available: {}", sizes.join(", ")),
            )
        })?)
    } else {
        let all = doc.entities.iter().chain(doc.blocks.iter().flat_map(|b| &b.entities));
        let sample =
            annotations(all, "sample size").and_then(|s| sizes.iter().find(|x| x.eq_ignore_ascii_case(&s)).cloned());
        Some(sample.unwrap_or_else(|| sizes[(sizes.len() - 1) / 2].clone()))
    };
    let (mut pieces, mut quantities) = (Vec::new(), Vec::new());
    let mut budget = outline::MAX_POINTS;
    for b in doc.blocks.iter().filter(|b| is_piece(b)) {
        let bs = block_size(doc, b);
        if bs.is_some() && bs != size {
            continue;
        }
        let name = annotations(block_notes(doc, b), "piece name").unwrap_or_else(|| b.name.clone());
        quantities.push(quantity(doc, &name));
        pieces.push(piece(file, b, name, units.metres(), opts, &mut budget)?);
    }
    if pieces.is_empty() {
        return Err(TailorError::parse(file, "BLOCKS", "no block has a boundary on layer 1"));
    }
    if opts.quantities {
        pieces = cut::cut(pieces, &quantities);
    }
    Ok(Pattern { source: file.to_string(), pieces, stitches: Vec::new(), sizes, size })
}

/// How many of the piece called `name` to cut. AccuMark writes `Quantity:` in the sample size's
/// block only, so any size's block of the same piece says it for all.
fn quantity(doc: &Document, name: &str) -> Option<u32> {
    doc.blocks.iter().filter(|b| is_piece(b)).find_map(|b| {
        let notes = || block_notes(doc, b);
        (annotations(notes(), "piece name").as_deref() == Some(name))
            .then(|| annotations(notes(), "quantity")?.parse::<u32>().ok())
            .flatten()
    })
}

fn scaled(p: Point2, s: f64) -> Point2 {
    [p[0] * s, p[1] * s]
}

fn piece(file: &str, b: &Block, name: String, scale: f64, opts: &ReadOptions, budget: &mut usize) -> Result<Piece> {
    let tol_m = opts.tolerance_m;
    let ctx = format!("BLOCK {:?}", b.name);
    let tol = tol_m / scale;
    let mut loops = Vec::new();
    let mut cutouts = Vec::new();
    let mut open = Vec::new();
    let (mut turns, mut notches, mut internal, mut grain) = (Vec::new(), Vec::new(), Vec::new(), None);
    let mut mirror: Option<[Point2; 2]> = None;
    for e in &b.entities {
        let layer = e.layer();
        if e.kind == "POINT" {
            let p = scaled([e.num(10).unwrap_or(f64::NAN), e.num(20).unwrap_or(f64::NAN)], scale);
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(TailorError::parse(file, describe(&ctx, e), "point without finite coordinates"));
            }
            match layer {
                "2" => turns.push(p),
                "4" => notches.push(p),
                _ => {}
            }
            continue;
        }
        if !matches!(layer, "1" | "4" | "6" | "7" | "8" | "11" | "80" | "81" | "82" | "83") {
            continue;
        }
        let Some(path) = geometry::path(file, &ctx, e, tol)? else { continue };
        *budget = budget.checked_sub(path.points.len()).ok_or_else(|| TailorError::Unsupported {
            file: file.into(),
            entity: describe(&ctx, e),
            reason: "too many points in the file".into(),
        })?;
        let pts: Vec<Point2> = path.points.iter().map(|p| scaled(*p, scale)).collect();
        match layer {
            "1" if path.closed => loops.push(pts),
            "1" => open.push(pts),
            // A slit notch is drawn as a short line starting on the boundary.
            "4" | "80" | "81" | "82" | "83" => notches.push(pts[0]),
            "11" if path.closed && pts.len() >= 3 => cutouts.push(pts),
            "6" if mirror.is_none() && pts.len() >= 2 => mirror = Some([pts[0], pts[pts.len() - 1]]),
            "7" if grain.is_none() && pts.len() >= 2 => grain = Some([pts[0], pts[pts.len() - 1]]),
            "8" => {
                let mut p = pts;
                if path.closed {
                    p.push(p[0]);
                }
                internal.push(p);
            }
            _ => {}
        }
    }
    // AccuMark splits the boundary into one open POLYLINE per run between turn points.
    let eps = 1e-5_f64.max(tol_m * 0.1);
    for (mut chain, closed) in outline::chain(open, eps) {
        let len: f64 = chain.windows(2).map(|w| dist(w[0], w[1])).sum();
        let gap = if chain.len() > 2 { dist(chain[0], chain[chain.len() - 1]) } else { f64::INFINITY };
        if closed {
            loops.push(chain);
        } else if gap <= (0.01 * len).max(0.002) {
            // Small drafting gap: close it.
            outline::dedup_closed(&mut chain, 0.0);
            loops.push(chain);
        } else if loops.is_empty() {
            return Err(TailorError::parse(
                file,
                format!("{ctx} layer 1"),
                format!("boundary does not close (gap of {:.1} mm between its ends)", gap * 1000.0),
            ));
        }
    }
    for l in &mut loops {
        outline::dedup_closed(l, 1e-9);
    }
    loops.retain(|l| l.len() >= 3 && outline::signed_area(l).abs() > 0.0);
    if loops.is_empty() {
        return Err(TailorError::parse(file, format!("{ctx} layer 1"), "boundary has no area"));
    }
    if loops.len() > outline::MAX_LOOPS {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: format!("{ctx} layer 1"),
            reason: "too many closed outlines".into(),
        });
    }
    let mut nested = outline::nest(loops);
    nested.sort_by(|a, b| outline::signed_area(&b.0).total_cmp(&outline::signed_area(&a.0)));
    let (mut outline_pts, mut holes) = nested.swap_remove(0);
    for mut c in cutouts {
        if outline::contains(&outline_pts, c[0]) && outline::signed_area(&c).abs() > 0.0 {
            outline::orient(&mut c, false);
            holes.push(c);
        }
    }

    let snap = 5e-4;
    if let (true, Some(line)) = (opts.unfold, mirror) {
        // A half cut on the fold: the whole piece (left as drawn where it cannot be read so).
        unfold::unfold(&mut outline_pts, &mut holes, &mut internal, &mut [&mut notches, &mut turns], line, snap);
    }
    let mut fixed_pts = Vec::new();
    for p in turns.iter().chain(&notches) {
        if outline::vertex_at(&mut outline_pts, *p, snap).is_some() {
            fixed_pts.push(*p);
        }
    }
    let mut fixed = outline::sharp_corners(&outline_pts, CORNER_TURN_DEG);
    for p in fixed_pts {
        if let Some(i) = outline_pts.iter().position(|q| dist(*q, p) <= snap) {
            fixed.push(i);
        }
    }
    fixed.sort_unstable();
    fixed.dedup();
    Ok(Piece {
        name,
        outline: outline_pts,
        fixed_vertices: fixed,
        holes,
        internal_lines: internal,
        notches,
        grain,
        placement: None,
        edges: Vec::new(),
    })
}
