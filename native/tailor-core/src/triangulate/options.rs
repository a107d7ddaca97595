//! Settings of the triangulation.

use serde::{Deserialize, Serialize};

use crate::error::{Result, TailorError};

/// Settings of [`triangulate_piece`](super::triangulate_piece).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TriangulateOptions {
    /// Target edge length `h`, metres (the resolution).
    pub edge_length: f64,
    /// Minimum triangle angle refinement aims for, degrees (at most 33). The exception is an
    /// *input corner* sharper than this: a point where outline, hole or internal-line segments
    /// meet at a smaller angle inside the piece; a triangle's angle at such a point may be as
    /// small as the corner's ([`unexcused_angles`](super::unexcused_angles) lists every other
    /// angle below it; `examples/min_angles.rs` prints them per file, docs/user-guide.md has
    /// the figures, and where it does not hold yet).
    pub min_angle_deg: f64,
    /// Outline, hole and internal-line vertices where the direction turns by at least this many
    /// degrees are kept as vertices (so a 90° corner of an unmarked outline stays sharp).
    pub corner_turn_deg: f64,
    /// Largest triangle area allowed, as a multiple of the equilateral area `(√3/4) h²`.
    pub max_area_factor: f64,
    /// Lattice seeds closer than this multiple of `h` to a constraint are dropped.
    pub lattice_margin: f64,
    /// Which mesher made the piece's mesh (see [`MESHER_VERSION`]). A mesh must be remade
    /// exactly as it was saved: a garment file's per-particle parameters and one-to-one seams,
    /// and a .blend's piece meshes, count its vertices. A file written before the field
    /// existed reads 1.
    #[serde(default = "first_mesher")]
    pub mesher: u32,
}

/// The mesher new meshes are made with.
/// - 1: spade's Ruppert/Chew refinement only (min angles down to about 10° beside internal
///   lines and tiny outline features);
/// - 2: then our own pass (`refine`) once every constraint is in, outline and hole segments
///   split where needed, so only an input corner's own angle stays below the minimum;
/// - 3: internal lines cut where they cross or meet before meshing (`lines`), not split by
///   the triangulation afterwards beside points refinement had put on them (tiny triangles).
pub const MESHER_VERSION: u32 = 3;

fn first_mesher() -> u32 {
    1
}

impl TriangulateOptions {
    /// Defaults for a target edge length `h` (metres).
    pub fn new(edge_length: f64) -> Self {
        Self {
            edge_length,
            min_angle_deg: 28.0,
            corner_turn_deg: 30.0,
            max_area_factor: 1.5,
            lattice_margin: 0.6,
            mesher: MESHER_VERSION,
        }
    }

    pub(crate) fn validate(&self) -> Result<()> {
        if !(self.edge_length.is_finite() && self.edge_length > 1e-5) {
            return Err(TailorError::setting("edge_length", self.edge_length, "must be a length above 0.01 mm"));
        }
        if !(self.min_angle_deg >= 0.0 && self.min_angle_deg <= 33.0) {
            return Err(TailorError::setting(
                "min_angle_deg",
                self.min_angle_deg,
                "must be in [0, 33] (Delaunay refinement does not terminate above)",
            ));
        }
        if !(1..=MESHER_VERSION).contains(&self.mesher) {
            return Err(TailorError::setting(
                "mesher",
                self.mesher,
                format!("must be a mesher this build knows (1 to {MESHER_VERSION})"),
            ));
        }
        if !(self.corner_turn_deg > 0.0 && self.corner_turn_deg <= 180.0) {
            return Err(TailorError::setting("corner_turn_deg", self.corner_turn_deg, "must be in (0, 180]"));
        }
        if !(self.max_area_factor.is_finite() && self.max_area_factor >= 0.5) {
            return Err(TailorError::setting("max_area_factor", self.max_area_factor, "must be at least 0.5"));
        }
        if !(self.lattice_margin.is_finite() && (0.2..=1.0).contains(&self.lattice_margin)) {
            return Err(TailorError::setting("lattice_margin", self.lattice_margin, "must be in [0.2, 1]"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_saved_before_the_mesher_field_read_the_first_mesher() {
        let o: TriangulateOptions = serde_json::from_str(
            r#"{"edge_length":0.02,"min_angle_deg":28.0,"corner_turn_deg":30.0,"max_area_factor":1.5,"lattice_margin":0.6}"#,
        )
        .unwrap();
        assert_eq!(o.mesher, 1);
        assert_eq!(TriangulateOptions::new(0.02).mesher, MESHER_VERSION);
        let future = TriangulateOptions { mesher: MESHER_VERSION + 1, ..TriangulateOptions::new(0.02) };
        assert!(future.validate().unwrap_err().to_string().contains("mesher"));
    }
}
