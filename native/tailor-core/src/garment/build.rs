//! From a [`Garment`] to the solver: triangulate every piece, place it in 3D, bend it, sew all
//! pieces into one [`ClothMesh`](crate::mesh::ClothMesh), and turn each resolved seam's pairs
//! into a weighted [`solver::Seam`].
//!
//! Placement: a piece's own `placement` (or, failing that, its source's) as in
//! [`place_piece`](crate::placement::place_piece); pieces without one are laid side by side in
//! `z = 0`, `gap` metres apart ([`place_pieces`]). The bend, if any, is applied after
//! placement. Stiffness: a garment seam's `stiffness` and `bend_stiffness` are *factors* on
//! [`BuildOptions::seam_stiffness`] (N/m) and [`BuildOptions::seam_bend_stiffness`], so that a
//! stored garment stays meaningful if the solver's units are retuned. The solver derives the
//! hinges across each seam itself from consecutive pairs.

use rayon::prelude::*;

use crate::bend::bend_piece;
use crate::error::Result;
use crate::garment_file::Garment;
use crate::pattern::Piece;
use crate::placement::place_pieces;
use crate::seam::{sew, SewnGarment, WeightedPoint};
use crate::solver::{self, Fabric, SeamPoint, Simulation, SolverSettings};
use crate::triangulate::{triangulate_piece, PieceMesh};

/// How a garment becomes solver input.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildOptions {
    /// Gap between pieces laid side by side (pieces without a placement), metres.
    pub gap: f64,
    /// Seam spring constant for a seam of stiffness factor 1, N/m.
    pub seam_stiffness: f32,
    /// Bending stiffness across a seam of bend factor 1.
    pub seam_bend_stiffness: f32,
}

/// Default seam spring constant of a garment's seams, N/m per sewn pair.
///
/// A closed seam carries the tension of the cloth across it, so its gap is that tension over
/// this constant: the GarmentCode shirt on its body (8 substeps x 15 iterations) settles at
/// 3.1 mm with 1e3 N/m and 0.5 mm with 1e4 N/m (0.3 mm at 30 iterations), at the same cost
/// per frame (measured with `python -m tailor simulate`, docs/benchmarks.md). Ten times the
/// stretch of the default fabric's edge springs keeps seams stiffer than the cloth they join.
pub const DEFAULT_SEAM_STIFFNESS: f32 = 1.0e4;

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions { gap: 0.05, seam_stiffness: DEFAULT_SEAM_STIFFNESS, seam_bend_stiffness: 1e-5 }
    }
}

/// Everything the solver is built from, kept for callers that need the piece layout.
#[derive(Debug, Clone)]
pub struct SolverInput {
    /// The piece meshes, in garment order.
    pub meshes: Vec<PieceMesh>,
    /// The sewn cloth (positions placed and bent), pairs in cloth indices, piece offsets.
    pub sewn: SewnGarment,
    /// One solver seam per garment seam, in garment order.
    pub seams: Vec<solver::Seam>,
}

/// Triangulates every piece of `garment` with its own options (in parallel; deterministic).
pub fn triangulate_all(garment: &Garment) -> Result<Vec<PieceMesh>> {
    garment.pieces.par_iter().map(|p| triangulate_piece(&p.source, &p.options)).collect()
}

fn seam_point(p: WeightedPoint) -> SeamPoint {
    SeamPoint { verts: [p[0].0, p[1].0], weights: [p[0].1, p[1].1] }
}

/// Places, bends and sews `meshes` (the garment's piece meshes, e.g. from [`triangulate_all`]).
pub fn solver_input(garment: &Garment, meshes: Vec<PieceMesh>, options: &BuildOptions) -> Result<SolverInput> {
    let pieces: Vec<Piece> = garment
        .pieces
        .iter()
        .map(|gp| {
            let mut p = gp.source.clone();
            p.placement = gp.placement.clone().or(p.placement);
            p
        })
        .collect();
    let mut positions = place_pieces(&pieces, &meshes, options.gap)?;
    for ((gp, mesh), pos) in garment.pieces.iter().zip(&meshes).zip(positions.iter_mut()) {
        if let Some(bend) = &gp.bend {
            bend_piece(pos, &mesh.rest, bend)?;
        }
    }
    let sewn = sew(&meshes, &positions, &garment.seams)?;
    let mut seams: Vec<solver::Seam> = garment
        .seams
        .iter()
        .map(|s| solver::Seam {
            name: s.name.clone(),
            pairs: Vec::new(),
            stiffness: options.seam_stiffness * s.stiffness,
            bend_stiffness: options.seam_bend_stiffness * s.bend_stiffness,
        })
        .collect();
    for (pair, &k) in sewn.pairs.iter().zip(&sewn.pair_seam) {
        let (a, b) = (seam_point(pair.a), seam_point(pair.b));
        // A dart's tip is sewn to itself: a constraint with nothing to do, which the solver
        // refuses; leave it out.
        let same_vertex = |p: &SeamPoint| p.weights[1] == 0.0 || p.verts[0] == p.verts[1];
        if same_vertex(&a) && same_vertex(&b) && a.verts[0] == b.verts[0] {
            continue;
        }
        seams[k as usize].pairs.push((a, b));
    }
    Ok(SolverInput { meshes, sewn, seams })
}

/// A simulation of `garment` ready to step: the sewn cloth with every seam added.
pub fn build_simulation(
    garment: &Garment,
    fabric: Fabric,
    settings: SolverSettings,
    options: &BuildOptions,
) -> Result<(Simulation, SolverInput)> {
    let input = solver_input(garment, triangulate_all(garment)?, options)?;
    let mut sim = Simulation::new(input.sewn.mesh.clone(), fabric, settings)
        .map_err(|e| crate::seam::assemble::name_piece(e, &input.meshes))?;
    for seam in &input.seams {
        sim.add_seam(seam.clone())?;
    }
    Ok((sim, input))
}
