//! A [`Garment`] from a read [`Pattern`]: every piece triangulated at one resolution, each
//! piece keeping the pattern's placement, and the pattern's stitches turned into seams.
//!
//! Real CAD exports often carry internal lines (grain, mirror or construction lines) that poke
//! out of the piece or duplicate outline points, which triangulation rightly refuses. Rather
//! than refusing the whole pattern, a piece that fails *with* internal lines but succeeds
//! without them keeps only the lines that triangulate on their own (each line is tried alone;
//! if the survivors still fail together, all lines are dropped), and what was dropped and why
//! is kept in `settings["import_warnings"]` (a list of strings) so callers can show it.

use std::path::Path;

use rayon::prelude::*;
use serde_json::Value;

use super::stitches::stitch_seam;
use crate::error::Result;
use crate::garment_file::{Garment, GarmentPiece};
use crate::pattern::{read_pattern, Pattern, Piece, ReadOptions};
use crate::seam::SeamMode;
use crate::triangulate::{triangulate_piece, PieceMesh, TriangulateOptions};

fn with_lines(piece: &Piece, keep: &[usize]) -> Piece {
    let mut p = piece.clone();
    p.internal_lines = keep.iter().map(|&k| piece.internal_lines[k].clone()).collect();
    p
}

/// Triangulates `piece`; on failure retries with only the internal lines that triangulate on
/// their own, then with none. Returns the piece as meshed, its mesh, and a warning when lines
/// were dropped.
fn mesh_piece(piece: &Piece, options: &TriangulateOptions) -> Result<(Piece, PieceMesh, Option<String>)> {
    let e = match triangulate_piece(piece, options) {
        Ok(m) => return Ok((piece.clone(), m, None)),
        Err(e) if !piece.internal_lines.is_empty() => e,
        Err(e) => return Err(e),
    };
    let all = piece.internal_lines.len();
    // Nothing to salvage if the piece fails even without lines.
    let bare = with_lines(piece, &[]);
    let bare_mesh = triangulate_piece(&bare, options).map_err(|_| e.clone())?;
    let good: Vec<usize> = (0..all).filter(|&k| triangulate_piece(&with_lines(piece, &[k]), options).is_ok()).collect();
    let dropped: Vec<usize> = (0..all).filter(|k| !good.contains(k)).collect();
    if !good.is_empty() {
        let kept = with_lines(piece, &good);
        if let Ok(m) = triangulate_piece(&kept, options) {
            let warning = format!("{e}; internal line(s) {dropped:?} of {all} dropped");
            return Ok((kept, m, Some(warning)));
        }
    }
    let warning = format!("{e}; imported without its {all} internal line(s)");
    Ok((bare, bare_mesh, Some(warning)))
}

/// Builds a garment from `pattern`, every piece meshed with `options`. Returns the garment and
/// its piece meshes (so callers need not triangulate twice). A stitch's seam is in
/// [`SeamMode::Equal`] when its two sides have the same vertex count at this resolution,
/// [`SeamMode::Unequal`] otherwise. The pattern's source and size go into `settings`
/// (`"pattern_source"`, `"pattern_size"`), with `"import_warnings"` when internal lines had
/// to be dropped (see the module docs).
pub fn garment_from_pattern(pattern: &Pattern, options: &TriangulateOptions) -> Result<(Garment, Vec<PieceMesh>)> {
    let meshed: Vec<(Piece, PieceMesh, Option<String>)> =
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
        warnings.extend(warning.map(Value::String));
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
