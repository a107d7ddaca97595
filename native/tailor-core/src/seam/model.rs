//! The resolution-independent seam and its resolution against the current piece meshes.
//!
//! A [`Seam`] stores, for each side, the piece, the rest-frame (2D, metres) positions of its
//! two endpoints and its walking direction, never vertex indices. Resolving it against the
//! current [`PieceMesh`]es ([`Seam::resolve`]) finds the contour vertices nearest the
//! endpoints and walks the contour between them: this *is* the paper's remapping after a
//! change of resolution ("by comparing the positions of a1, an, b1 and bn in the original mesh
//! to their counterparts in the updated mesh, their indices (and the indices of the vertices
//! in between) are recomputed"). Endpoints usually sit on pins (corners, span ends), which
//! every resolution keeps as vertices, so they land exactly; elsewhere within half an edge.

use serde::{Deserialize, Serialize};

use super::paths::{nearest_contour_position, path_between, ContourPath, Direction};
use super::validate::validate_seam;
use crate::error::{Result, TailorError};
use crate::triangulate::PieceMesh;

/// How the two sides are paired.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SeamMode {
    /// The paper's one-to-one mapping: both sides must have the same vertex count.
    Equal,
    /// Arc-length pairing: every vertex of either side is sewn to the point at the same
    /// fraction of the other side's length (different resolutions, easing, gathering).
    Unequal,
}

/// One side of a seam, independent of the mesh resolution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeamSide {
    /// Index of the piece (into the garment's piece list).
    pub piece: usize,
    /// Rest (2D, piece frame, metres) position of the first endpoint.
    pub start: [f64; 2],
    /// Rest position of the last endpoint.
    pub end: [f64; 2],
    /// Direction walked along the contour from `start` to `end`.
    pub direction: Direction,
}

/// A seam between two contour runs, stored without vertex indices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Seam {
    pub name: String,
    pub a: SeamSide,
    pub b: SeamSide,
    pub mode: SeamMode,
    /// Stiffness of the zero-rest-length distance constraints (solver units).
    pub stiffness: f32,
    /// Stiffness of the hinge bending across the seam.
    pub bend_stiffness: f32,
}

/// A seam resolved against the current meshes: the two vertex paths.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedSeam {
    pub name: String,
    pub piece_a: usize,
    pub piece_b: usize,
    pub a: ContourPath,
    pub b: ContourPath,
    pub mode: SeamMode,
    /// Rest length of side A over side B (1 for a plain seam; > 1 when A is eased onto B).
    pub length_ratio: f64,
}

impl SeamSide {
    /// The side of an already picked path (at least one vertex, on `mesh`'s contour).
    pub fn from_path(piece: usize, mesh: &PieceMesh, path: &ContourPath) -> Result<Self> {
        let n = mesh.contour.len();
        if path.is_empty() || path.positions.iter().any(|&p| p >= n) {
            return Err(TailorError::shape(
                format!("piece {}", mesh.name),
                format!("a seam side needs contour positions below {n}, got {:?}", path.positions),
            ));
        }
        let p = |i: usize| {
            let q = mesh.contour_point(i);
            [q[0] as f64, q[1] as f64]
        };
        Ok(SeamSide { piece, start: p(path.first()), end: p(path.last()), direction: path.direction })
    }

    /// The contour path on `mesh` between the positions nearest `start` and `end`.
    pub fn resolve(&self, mesh: &PieceMesh) -> Result<ContourPath> {
        let f = |p: [f64; 2]| [p[0] as f32, p[1] as f32];
        let s = nearest_contour_position(mesh, f(self.start));
        let e = nearest_contour_position(mesh, f(self.end));
        path_between(mesh, s, e, self.direction)
    }
}

impl Seam {
    /// A seam from two picked paths (after the paper's five steps or a corner suggestion),
    /// validated.
    #[allow(clippy::too_many_arguments)]
    pub fn from_paths(
        name: &str,
        piece_a: usize,
        mesh_a: &PieceMesh,
        path_a: &ContourPath,
        piece_b: usize,
        mesh_b: &PieceMesh,
        path_b: &ContourPath,
        mode: SeamMode,
    ) -> Result<Seam> {
        validate_seam(name, mesh_a, path_a, mesh_b, path_b, piece_a == piece_b, mode)?;
        Ok(Seam {
            name: name.to_string(),
            a: SeamSide::from_path(piece_a, mesh_a, path_a)?,
            b: SeamSide::from_path(piece_b, mesh_b, path_b)?,
            mode,
            stiffness: 1.0,
            bend_stiffness: 1.0,
        })
    }

    /// Resolves (or, after a re-triangulation, remaps) the seam on `meshes` (indexed by piece).
    pub fn resolve(&self, meshes: &[PieceMesh]) -> Result<ResolvedSeam> {
        let get = |side: &SeamSide, label: &str| {
            meshes.get(side.piece).ok_or_else(|| TailorError::InvalidSeam {
                seam: self.name.clone(),
                reason: format!("side {label} refers to piece {} but there are {} pieces", side.piece, meshes.len()),
            })
        };
        let (ma, mb) = (get(&self.a, "A")?, get(&self.b, "B")?);
        for (side, label) in [(&self.a, "A"), (&self.b, "B")] {
            if side.start.iter().chain(&side.end).any(|c| !c.is_finite()) {
                return Err(TailorError::InvalidSeam {
                    seam: self.name.clone(),
                    reason: format!("side {label} has a non-finite endpoint"),
                });
            }
        }
        let (a, b) = (self.a.resolve(ma)?, self.b.resolve(mb)?);
        validate_seam(&self.name, ma, &a, mb, &b, self.a.piece == self.b.piece, self.mode)?;
        let length_ratio = a.length(ma) / b.length(mb).max(f64::MIN_POSITIVE);
        Ok(ResolvedSeam {
            name: self.name.clone(),
            piece_a: self.a.piece,
            piece_b: self.b.piece,
            a,
            b,
            mode: self.mode,
            length_ratio,
        })
    }
}

/// Remaps a path picked on `old` onto `new` (the same piece at another resolution) by the
/// positions of its endpoints; the vertices between are recomputed.
pub fn remap_path(old: &PieceMesh, path: &ContourPath, new: &PieceMesh) -> Result<ContourPath> {
    SeamSide::from_path(0, old, path)?.resolve(new)
}
