//! Sewing pieces into one cloth: the piece meshes concatenated into the solver's
//! [`ClothMesh`], and every seam's pairs and hinges shifted to the concatenated indices.

use super::model::Seam;
use super::pairs::{SeamHinge, SeamPair};
use crate::error::{Result, TailorError};
use crate::mesh::ClothMesh;
use crate::triangulate::PieceMesh;

/// The solver's view of a sewn garment.
#[derive(Debug, Clone)]
pub struct SewnGarment {
    pub mesh: ClothMesh,
    /// Index of each piece's first vertex in `mesh`.
    pub offsets: Vec<u32>,
    /// All seams' pairs, in `mesh` indices.
    pub pairs: Vec<SeamPair>,
    /// The seam (index into the seam list) of each pair, for per-seam stiffness.
    pub pair_seam: Vec<u32>,
    /// All seams' hinges, in `mesh` indices.
    pub hinges: Vec<SeamHinge>,
    /// The seam of each hinge.
    pub hinge_seam: Vec<u32>,
}

/// Concatenates `meshes` (with their current 3D `positions`, one list per piece) and resolves
/// `seams` on them.
pub fn sew(meshes: &[PieceMesh], positions: &[Vec<[f32; 3]>], seams: &[Seam]) -> Result<SewnGarment> {
    if meshes.len() != positions.len() {
        return Err(TailorError::shape(
            "sew",
            format!("{} meshes but {} position lists", meshes.len(), positions.len()),
        ));
    }
    let (mut pos, mut rest, mut tris, mut offsets) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (m, p) in meshes.iter().zip(positions) {
        if p.len() != m.rest.len() {
            return Err(TailorError::shape(
                format!("piece {}", m.name),
                format!("{} positions for {} vertices", p.len(), m.rest.len()),
            ));
        }
        let off = u32::try_from(pos.len()).map_err(|_| TailorError::shape("sew", "more than 2³² vertices"))?;
        offsets.push(off);
        pos.extend_from_slice(p);
        rest.extend_from_slice(&m.rest);
        tris.extend(m.triangles.iter().map(|t| t.map(|v| v + off)));
    }
    let mesh = ClothMesh::new(pos, rest, tris).map_err(|e| name_piece(e, meshes))?;
    let mut out = SewnGarment {
        mesh,
        offsets,
        pairs: Vec::new(),
        pair_seam: Vec::new(),
        hinges: Vec::new(),
        hinge_seam: Vec::new(),
    };
    for (k, seam) in seams.iter().enumerate() {
        let r = seam.resolve(meshes)?;
        let (ma, mb) = (&meshes[r.piece_a], &meshes[r.piece_b]);
        let (oa, ob) = (out.offsets[r.piece_a], out.offsets[r.piece_b]);
        let pairs = r.pairs(ma, mb)?;
        out.pair_seam.extend(std::iter::repeat_n(k as u32, pairs.len()));
        out.pairs.extend(pairs.into_iter().map(|p| p.offset(oa, ob)));
        let hinges = r.hinges(ma, mb)?;
        out.hinge_seam.extend(std::iter::repeat_n(k as u32, hinges.len()));
        out.hinges.extend(hinges.into_iter().map(|h| h.offset(oa, ob)));
    }
    Ok(out)
}

/// A [`TailorError::DegenerateTriangle`] about the sewn cloth (triangles of `meshes` in order)
/// with the piece and its own triangle index added to the reason; other errors unchanged.
pub fn name_piece(e: TailorError, meshes: &[PieceMesh]) -> TailorError {
    match e {
        TailorError::DegenerateTriangle { triangle, reason } => {
            let mut first = 0;
            for m in meshes {
                if triangle < first + m.triangles.len() {
                    let local = triangle - first;
                    return TailorError::DegenerateTriangle {
                        triangle,
                        reason: format!("{reason} (triangle {local} of piece {})", m.name),
                    };
                }
                first += m.triangles.len();
            }
            TailorError::DegenerateTriangle { triangle, reason }
        }
        other => other,
    }
}
