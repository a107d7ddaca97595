//! Changing one piece's resolution: re-triangulate it and remap the seams.
//!
//! Seams store their endpoints by rest position, so resolving them on the new meshes *is* the
//! remapping (see [`crate::seam::model`]). What can change is the vertex count of a side: a
//! seam in [`SeamMode::Equal`] whose sides no longer match switches to
//! [`SeamMode::Unequal`] (arc-length pairing) instead of failing.

use super::build::triangulate_all;
use crate::error::{Result, TailorError};
use crate::garment_file::Garment;
use crate::seam::SeamMode;
use crate::triangulate::PieceMesh;

/// Sets piece `piece`'s target edge length to `edge_length` metres, re-triangulates, and
/// remaps every seam. Returns the new meshes of all pieces. On error the garment is unchanged.
pub fn set_resolution(garment: &mut Garment, piece: usize, edge_length: f64) -> Result<Vec<PieceMesh>> {
    let n = garment.pieces.len();
    let p = garment
        .pieces
        .get(piece)
        .ok_or_else(|| TailorError::setting("piece", piece, format!("must be a piece index below {n}")))?;
    let mut next = garment.clone();
    let mut options = p.options.clone();
    options.edge_length = edge_length;
    // A piece meshed again gets today's mesher (its old vertices are gone either way).
    options.mesher = crate::triangulate::MESHER_VERSION;
    next.pieces[piece].options = options;
    let meshes = triangulate_all(&next)?;
    for seam in &mut next.seams {
        if seam.mode == SeamMode::Equal && (seam.a.piece == piece || seam.b.piece == piece) {
            seam.mode = SeamMode::Unequal;
            let r = seam.resolve(&meshes)?;
            if r.a.len() == r.b.len() {
                seam.mode = SeamMode::Equal;
            }
        }
        seam.resolve(&meshes)?;
    }
    *garment = next;
    Ok(meshes)
}
