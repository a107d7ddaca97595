//! A [`Garment`] from a read [`Pattern`]: every piece triangulated at one resolution, each
//! piece keeping the pattern's placement, and the pattern's stitches turned into seams.
//!
//! Real CAD exports often carry internal lines (grain, mirror or construction lines) that end
//! a hair off the outline, overshoot it or poke out of the piece. Triangulation itself snaps
//! line ends and notches near the outline onto it and clips lines that leave the piece
//! ([`snap_tolerance`](crate::triangulate::snap_tolerance)), with a warning per line clipped or
//! dropped ([`PieceMesh::warnings`]). What still cannot be meshed (lines crossing each other)
//! is the last resort here: a piece that fails *with* internal lines (or whose lines leave a
//! triangle well under the piece's own smallest angle: [`LINE_ANGLE_SLACK_DEG`]) but succeeds
//! without them keeps, line by line in file order, each line
//! that still meshes together with the lines kept before it. Every warning is kept in
//! `settings["import_warnings"]` (a list of strings) so callers can show it.

use std::path::Path;

use rayon::prelude::*;
use serde_json::Value;

use super::stitches::stitch_seam;
use crate::error::Result;
use crate::garment_file::{Garment, GarmentPiece};
use crate::pattern::{read_pattern, Pattern, Piece, ReadOptions};
use crate::seam::SeamMode;
use crate::triangulate::{triangulate_piece, PieceMesh, TriangulateOptions};

/// Internal lines may not make a piece's mesh worse than it is without them: a mesh with lines
/// whose smallest angle is more than this many degrees under the smaller of the piece's own
/// (without lines) and the stated minimum (`TriangulateOptions::min_angle_deg`) is refused, and
/// the lines are kept one by one (below). A line that meets the outline at a grazing angle
/// leaves such a sliver wherever it is snapped: the women's tank DXF at 3 cm had an 8.5°
/// triangle beside a line (28.5° without it), and a 1° sliver may be refused by the solver as
/// degenerate in f32.
const LINE_ANGLE_SLACK_DEG: f64 = 2.0;

/// [`triangulate_piece`], refusing a mesh whose internal lines left a triangle more than
/// [`LINE_ANGLE_SLACK_DEG`] under `floor` (the piece's own minimum angle without lines, at most
/// the stated one).
fn triangulate_checked(piece: &Piece, options: &TriangulateOptions, floor: f64) -> Result<PieceMesh> {
    let m = triangulate_piece(piece, options)?;
    if !piece.internal_lines.is_empty() && m.quality.min_angle_deg < floor - LINE_ANGLE_SLACK_DEG {
        return Err(crate::error::TailorError::shape(
            format!("piece {}", piece.name),
            format!("its internal lines leave a {:.3}° triangle ({:.1}° without them)", m.quality.min_angle_deg, floor),
        ));
    }
    Ok(m)
}

fn with_lines(piece: &Piece, keep: &[usize]) -> Piece {
    let mut p = piece.clone();
    p.internal_lines = keep.iter().map(|&k| piece.internal_lines[k].clone()).collect();
    p
}

/// Triangulates `piece`; on failure keeps, line by line, only the internal lines that still
/// triangulate with those kept before them (none, at worst). Returns the piece as meshed, its mesh, and the triangulation's
/// warnings plus one when lines were dropped here.
fn mesh_piece(piece: &Piece, options: &TriangulateOptions) -> Result<(Piece, PieceMesh, Vec<String>)> {
    if piece.internal_lines.is_empty() {
        let m = triangulate_piece(piece, options)?;
        let w = m.warnings.clone();
        return Ok((piece.clone(), m, w));
    }
    let bare = with_lines(piece, &[]);
    let bare_mesh = triangulate_piece(&bare, options);
    let floor =
        bare_mesh.as_ref().map_or(options.min_angle_deg, |m| m.quality.min_angle_deg.min(options.min_angle_deg));
    let e = match triangulate_checked(piece, options, floor) {
        Ok(m) => {
            let w = m.warnings.clone();
            return Ok((piece.clone(), m, w));
        }
        Err(e) => e,
    };
    let all = piece.internal_lines.len();
    // Nothing to salvage if the piece fails even without lines.
    let bare_mesh = bare_mesh.map_err(|_| e.clone())?;
    // Greedily: each line in turn is kept if the piece still meshes with it and those kept.
    let mut good: Vec<usize> = Vec::new();
    let mut best: Option<PieceMesh> = None;
    for k in 0..all {
        let mut trial = good.clone();
        trial.push(k);
        if let Ok(m) = triangulate_checked(&with_lines(piece, &trial), options, floor) {
            good = trial;
            best = Some(m);
        }
    }
    let dropped: Vec<usize> = (0..all).filter(|k| !good.contains(k)).collect();
    if let Some(m) = best {
        let mut w = m.warnings.clone();
        w.push(format!("{e}; internal line(s) {dropped:?} of {all} dropped"));
        return Ok((with_lines(piece, &good), m, w));
    }
    let mut w = bare_mesh.warnings.clone();
    w.push(format!("{e}; imported without its {all} internal line(s)"));
    Ok((bare, bare_mesh, w))
}

/// Builds a garment from `pattern`, every piece meshed with `options`. Returns the garment and
/// its piece meshes (so callers need not triangulate twice). A stitch's seam is in
/// [`SeamMode::Equal`] when its two sides have the same vertex count at this resolution,
/// [`SeamMode::Unequal`] otherwise. The pattern's source and size go into `settings`
/// (`"pattern_source"`, `"pattern_size"`), with `"import_warnings"` when internal lines were
/// clipped or dropped (see the module docs).
pub fn garment_from_pattern(pattern: &Pattern, options: &TriangulateOptions) -> Result<(Garment, Vec<PieceMesh>)> {
    let meshed: Vec<(Piece, PieceMesh, Vec<String>)> =
        pattern.pieces.par_iter().map(|p| mesh_piece(p, options)).collect::<Result<_>>()?;
    let mut garment = Garment::default();
    let (mut meshes, mut warnings) = (Vec::with_capacity(meshed.len()), Vec::new());
    for (piece, mesh, warning) in meshed {
        garment.pieces.push(GarmentPiece {
            placement: piece.placement.clone(),
            source: piece,
            options: options.clone(),
            bend: None,
        });
        meshes.push(mesh);
        warnings.extend(warning.into_iter().map(Value::String));
    }
    for (i, stitch) in pattern.stitches.iter().enumerate() {
        let mut seam = stitch_seam(i, stitch, &pattern.pieces, SeamMode::Unequal)?;
        let r = seam.resolve(&meshes)?;
        if r.a.len() == r.b.len() {
            seam.mode = SeamMode::Equal;
        }
        garment.seams.push(seam);
    }
    garment.settings.insert("pattern_source".into(), Value::String(pattern.source.clone()));
    if let Some(size) = &pattern.size {
        garment.settings.insert("pattern_size".into(), Value::String(size.clone()));
    }
    if !warnings.is_empty() {
        garment.settings.insert("import_warnings".into(), Value::Array(warnings));
    }
    Ok((garment, meshes))
}

/// Reads the pattern file at `path` and builds its garment at `options`.
pub fn read_garment(
    path: &Path,
    read: &ReadOptions,
    options: &TriangulateOptions,
) -> Result<(Pattern, Garment, Vec<PieceMesh>)> {
    let pattern = read_pattern(path, read)?;
    let (garment, meshes) = garment_from_pattern(&pattern, options)?;
    Ok((pattern, garment, meshes))
}

/// The warnings [`garment_from_pattern`] recorded in `settings["import_warnings"]`.
pub fn import_warnings(garment: &Garment) -> Vec<String> {
    match garment.settings.get("import_warnings") {
        Some(Value::Array(v)) => v.iter().filter_map(|w| w.as_str().map(str::to_string)).collect(),
        _ => Vec::new(),
    }
}
