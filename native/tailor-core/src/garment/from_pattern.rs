//! A [`Garment`] from a read [`Pattern`]: every piece triangulated at one resolution, each
//! piece keeping the pattern's placement, and the pattern's stitches turned into seams.

use std::path::Path;

use super::build::triangulate_all;
use super::stitches::stitch_seam;
use crate::error::Result;
use crate::garment_file::{Garment, GarmentPiece};
use crate::pattern::{read_pattern, Pattern, Placement, ReadOptions};
use crate::seam::SeamMode;
use crate::triangulate::{PieceMesh, TriangulateOptions};

/// Builds a garment from `pattern`, every piece meshed with `options`. Returns the garment and
/// its piece meshes (so callers need not triangulate twice). A stitch's seam is in
/// [`SeamMode::Equal`] when its two sides have the same vertex count at this resolution,
/// [`SeamMode::Unequal`] otherwise. The pattern's source and size go into `settings`
/// (`"pattern_source"`, `"pattern_size"`).
pub fn garment_from_pattern(pattern: &Pattern, options: &TriangulateOptions) -> Result<(Garment, Vec<PieceMesh>)> {
    let mut garment = Garment::default();
    for piece in &pattern.pieces {
        garment.pieces.push(GarmentPiece {
            source: piece.clone(),
            options: options.clone(),
            placement: piece.placement.clone(),
            bend: None,
        });
    }
    let meshes = triangulate_all(&garment)?;
    let placements: Vec<Option<Placement>> = pattern.pieces.iter().map(|p| p.placement.clone()).collect();
    for (i, stitch) in pattern.stitches.iter().enumerate() {
        let mut seam = stitch_seam(i, stitch, &pattern.pieces, &placements, SeamMode::Unequal)?;
        let r = seam.resolve(&meshes)?;
        if r.a.len() == r.b.len() {
            seam.mode = SeamMode::Equal;
        }
        garment.seams.push(seam);
    }
    garment.settings.insert("pattern_source".into(), serde_json::Value::String(pattern.source.clone()));
    if let Some(size) = &pattern.size {
        garment.settings.insert("pattern_size".into(), serde_json::Value::String(size.clone()));
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
