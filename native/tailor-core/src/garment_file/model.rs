//! The in-memory garment that the file stores.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::setup::GarmentSetup;
use crate::bend::BendParams;
use crate::pattern::{Piece, Placement};
use crate::seam::Seam;
use crate::triangulate::TriangulateOptions;

/// One piece: where it came from and how it is meshed, placed and bent. The mesh itself is not
/// stored: triangulation is deterministic, so `source` + `options` rebuild it exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GarmentPiece {
    /// The pattern piece (outline, holes, lines, notches, spans) as imported.
    pub source: Piece,
    /// Triangulation settings, including the resolution (target edge length).
    pub options: TriangulateOptions,
    /// 3D placement (overrides `source.placement` when both are present).
    pub placement: Option<Placement>,
    /// Bend applied after placement.
    pub bend: Option<BendParams>,
}

impl GarmentPiece {
    /// Where the piece is placed: its own placement, else its pattern piece's.
    pub fn placement_in_effect(&self) -> Option<&Placement> {
        self.placement.as_ref().or(self.source.placement.as_ref())
    }
}

/// Values of a painted per-particle parameter (paper Sec. 5: binary, integer, float).
#[derive(Debug, Clone, PartialEq)]
pub enum ParticleValues {
    F32(Vec<f32>),
    I32(Vec<i32>),
    Bool(Vec<bool>),
    /// Three floats per vertex (the piece's placed positions).
    Vec3(Vec<[f32; 3]>),
}

impl ParticleValues {
    pub fn len(&self) -> usize {
        match self {
            ParticleValues::F32(v) => v.len(),
            ParticleValues::I32(v) => v.len(),
            ParticleValues::Bool(v) => v.len(),
            ParticleValues::Vec3(v) => v.len(),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A per-particle parameter of one piece (friction, mass scale, collision level, …), one value
/// per vertex of the piece's mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleParam {
    pub name: String,
    pub piece: usize,
    pub values: ParticleValues,
}

/// A whole garment: pieces, seams, its typed setup (fabric per piece, pins, collision), painted
/// parameters, and free-form settings (other tools' data, kept as JSON values by name).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Garment {
    pub pieces: Vec<GarmentPiece>,
    pub seams: Vec<Seam>,
    pub setup: GarmentSetup,
    pub particle_params: Vec<ParticleParam>,
    pub settings: BTreeMap<String, serde_json::Value>,
}
