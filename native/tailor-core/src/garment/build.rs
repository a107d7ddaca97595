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
use crate::garment_file::setup::maps;
use crate::garment_file::{Garment, ParticleValues};
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

pub use crate::garment_file::setup::{DEFAULT_SEAM_BEND_STIFFNESS, DEFAULT_SEAM_STIFFNESS};

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            gap: 0.05,
            seam_stiffness: DEFAULT_SEAM_STIFFNESS,
            seam_bend_stiffness: DEFAULT_SEAM_BEND_STIFFNESS,
        }
    }
}

impl BuildOptions {
    /// The options a garment's own setup asks for (its seam stiffness and bending).
    pub fn of(garment: &Garment) -> Self {
        BuildOptions {
            seam_stiffness: garment.setup.seam_stiffness,
            seam_bend_stiffness: garment.setup.seam_bend_stiffness,
            ..BuildOptions::default()
        }
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
            p.placement = gp.placement_in_effect().cloned();
            p
        })
        .collect();
    let mut positions = place_pieces(&pieces, &meshes, options.gap)?;
    for ((gp, mesh), pos) in garment.pieces.iter().zip(&meshes).zip(positions.iter_mut()) {
        if let Some(bend) = &gp.bend {
            bend_piece(pos, &mesh.rest, bend)?;
        }
    }
    // A piece stored as placed (hand edits and all, e.g. exported from Blender) is used as
    // stored, where it still fits its mesh.
    for p in garment.particle_params.iter().filter(|p| p.name == maps::POSITION) {
        if let (ParticleValues::Vec3(v), Some(pos)) = (&p.values, positions.get_mut(p.piece)) {
            if v.len() == pos.len() {
                pos.copy_from_slice(v);
            }
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

/// A simulation of `garment` configured by its setup ([`super::setup::apply_setup`]): built
/// with the setup's first fabric (or `fabric`, which then stands for every piece) and seam
/// stiffness, then fabric per piece, painted maps, pins, thickness and self-collision applied.
/// `ride`: a collider will be there for riding pins (see `apply_setup`).
pub fn build_configured(
    garment: &Garment,
    fabric: Option<Fabric>,
    settings: SolverSettings,
    options: &BuildOptions,
    ride: bool,
) -> Result<(Simulation, SolverInput, super::setup::Applied)> {
    garment.setup.validate(garment.pieces.len())?;
    let mut g;
    let garment = match fabric {
        Some(f) => {
            g = garment.clone();
            g.setup.fabrics = vec![f; g.pieces.len()];
            &g
        }
        None => garment,
    };
    let base = garment.setup.base_fabric();
    let (mut sim, input) = build_simulation(garment, base, settings, options)?;
    let applied = super::setup::apply_setup(&mut sim, garment, &layout_of(&input), ride)?;
    Ok((sim, input, applied))
}

/// Where each piece's particles and triangles lie in the sewn cloth.
pub fn layout_of(input: &SolverInput) -> super::setup::Layout {
    let layout = super::setup::Layout::of_meshes(&input.meshes);
    debug_assert_eq!(layout.offsets, input.sewn.offsets, "the sewn cloth concatenates the pieces");
    layout
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
