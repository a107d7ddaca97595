//! A [`Garment`] from a read [`Pattern`]: every piece triangulated at one resolution, each
//! piece keeping the pattern's placement, and the pattern's stitches turned into seams.
//!
//! Real CAD exports often carry internal lines (grain, mirror or construction lines) that end
//! a hair off the outline, overshoot it or poke out of the piece. Triangulation itself snaps
//! line ends and notches near the outline onto it and clips lines that leave the piece
//! ([`snap_tolerance`](crate::triangulate::snap_tolerance)), with a warning per line clipped or
//! dropped ([`PieceMesh::warnings`]). What still cannot be meshed (lines crossing each other)
//! is the last resort here: a piece that fails *with* internal lines (or whose lines leave a
//! triangle under 1°) but succeeds without them keeps, line by line in file order, each line
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

/// Below this angle (degrees) a triangle along an internal line is a sliver the solver may
/// refuse as degenerate in f32: the lines are then treated as failing (and dropped by the
/// retry below). Pieces without lines are meshed as they are.
const LINE_SLIVER_DEG: f64 = 1.0;

/// [`triangulate_piece`], refusing a mesh whose internal lines left a sliver.
fn triangulate_checked(piece: &Piece, options: &TriangulateOptions) -> Result<PieceMesh> {
    let m = triangulate_piece(piece, options)?;
    if !piece.internal_lines.is_empty() && m.quality.min_angle_deg < LINE_SLIVER_DEG {
        return Err(crate::error::TailorError::shape(
            format!("piece {}", piece.name),
            format!("its internal lines leave a {:.3}° triangle", m.quality.min_angle_deg),
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
    let e = match triangulate_checked(piece, options) {
        Ok(m) => {
            let w = m.warnings.clone();
            return Ok((piece.clone(), m, w));
        }
        Err(e) if !piece.internal_lines.is_empty() => e,
        Err(e) => return Err(e),
    };
    let all = piece.internal_lines.len();
    // Nothing to salvage if the piece fails even without lines.
    let bare = with_lines(piece, &[]);
    let bare_mesh = triangulate_piece(&bare, options).map_err(|_| e.clone())?;
    // Greedily: each line in turn is kept if the piece still meshes with it and those kept.
    let mut good: Vec<usize> = Vec::new();
    let mut best: Option<PieceMesh> = None;
    for k in 0..all {
        let mut trial = good.clone();
        trial.push(k);
        if let Ok(m) = triangulate_checked(&with_lines(piece, &trial), options) {
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
