//! Triangulation of a pattern [`Piece`] into an isotropic triangle mesh at a target edge length.
//!
//! The target edge length `h` is the artist's resolution knob (the paper's "polygonal
//! resolution", Sec. 4): silk wants small `h`, denim a larger one. The stages:
//!
//! 0. `checks`: the piece is validated (counts, finite coordinates, counter-clockwise outline,
//!    holes inside it, a sane vertex budget); `lines`: internal-line ends and notches within
//!    [`snap_tolerance`] of the outline are snapped onto it (onto a pin there when one is that
//!    near), lines leaving the piece are clipped, and each clip or drop is a warning
//!    ([`PieceMesh::warnings`]).
//! 1. `pins` and `resample`: the outline, each hole and each internal line are resampled at
//!    `h` by arc length between *pins*: the piece's fixed vertices, the ends of its named edges
//!    (stitch spans), notches, vertices where the outline turns by at least `corner_turn_deg`,
//!    and the points where an internal line meets the outline. Pins stay vertices, so corners
//!    and notches survive any resolution and boundary spacing is even (`d / round(d / h)`).
//! 2. `constraints`: the CDT's vertices and segments; `fill`: the interior is seeded with an
//!    equilateral lattice of side `h`.
//! 3. `cdt`: a constrained Delaunay triangulation of all of it, refined (Ruppert/Chew, via
//!    `spade`) to a minimum angle (default 28°) and a maximum area; then `refine`, a pass of
//!    our own once the internal lines are in, repairs the angles spade leaves (tiny outline
//!    features, circumcentres outside the piece, a sharp corner's wedge, triangles beside
//!    lines), so only an input corner's own angle stays below the minimum.
//! 4. `contour`: the outer contour is read back from the final triangles (refinement may have
//!    split an outline segment) and every pin is mapped to its contour position.
//!
//! The result is deterministic (same piece and options, same mesh), which the garment file
//! relies on. The mesh is a flat 2D rest shape in the piece's own frame (metres); seams refer
//! to it through [`PieceMesh::contour`] positions. Measured on the test pieces: minimum angle
//! ≥ 28°, 98-99 % of edges within ±35 % of `h`, contour edges within 1 % of each other on a
//! straight or gently curved outline.

mod cdt;
mod checks;
mod constraints;
mod contour;
mod corners;
mod fill;
mod lines;
mod load;
mod options;
mod piece_mesh;
mod pins;
mod quality;
mod refine;
mod region;
pub(crate) mod resample;

pub use corners::{input_corners, sharpest_input_corner_deg, unexcused_angles, InputCorner};
pub use lines::snap_tolerance;
pub use options::{TriangulateOptions, MESHER_VERSION};
pub use piece_mesh::PieceMesh;
pub use quality::MeshQuality;

use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Point2};
use constraints::pin_point;
use resample::{resample, Resampled};

/// Triangulates `piece` at `options.edge_length`. See the module docs for the stages.
pub fn triangulate_piece(piece: &Piece, options: &TriangulateOptions) -> Result<PieceMesh> {
    options.validate()?;
    let h = options.edge_length;
    checks::validate_piece(piece, h)?;
    // Line ends and notches near the outline snapped onto it, lines leaving the piece clipped.
    let (attached, origin, warnings) = lines::attach_lines(piece, options);
    let piece = &attached;
    // Pins closer than eps merge; line ends within snap of the outline or a hole attach to it.
    let eps = 1e-9;
    let snap = (1e-3 * h).max(1e-6);
    let outline = &piece.outline;
    let m = outline.len();
    let pins = pins::gather(piece, options, snap, &origin)?;
    let (cum, sharp, notch_s, line_ends) = (&pins.cum, &pins.sharp, &pins.notches, &pins.line_ends);

    let r_out = resample(outline, true, pins.outline.clone(), h, eps);
    let r_holes: Vec<Resampled> =
        piece.holes.iter().zip(pins.holes.iter().cloned()).map(|(hl, p)| resample(hl, true, p, h, eps)).collect();

    let c = constraints::build(piece, &r_out, &r_holes, line_ends, h, options.corner_turn_deg, eps);
    let (mut points, edges, line_edges) = (c.points, c.loop_edges, c.line_edges);

    let segments: Vec<[Point2; 2]> = edges.iter().chain(&line_edges).map(|&[a, b]| [points[a], points[b]]).collect();
    let hole_polys: Vec<Vec<Point2>> = r_holes.iter().map(|r| r.points.clone()).collect();
    let n_constraint = points.len();
    points.extend(fill::lattice_points(&r_out.points, &hole_polys, &segments, h, options.lattice_margin));

    let raw = cdt::triangulate(cdt::CdtInput {
        piece: &piece.name,
        points,
        n_constraint,
        loop_edges: edges,
        line_edges,
        outline: &r_out.points,
        holes: &hole_polys,
        h,
        min_angle_deg: options.min_angle_deg,
        area_factor: options.max_area_factor,
        mesher: options.mesher,
    })?;
    let mut triangles = raw.triangles;
    if triangles.is_empty() {
        return Err(TailorError::EmptyMesh { what: format!("piece {} produced no triangles", piece.name) });
    }
    let (rest64, map) = contour::compact(&raw.points, &mut triangles);
    let contour = contour::boundary_loop(&piece.name, &triangles, rest64.len(), map[0])?;

    let mut contour_param = Vec::with_capacity(contour.len());
    let mut acc = 0.0;
    for i in 0..contour.len() {
        contour_param.push(acc);
        let (a, b) = (rest64[contour[i] as usize], rest64[contour[(i + 1) % contour.len()] as usize]);
        acc += resample::dist(a, b);
    }
    let mut pos_of = vec![usize::MAX; rest64.len()];
    for (i, &v) in contour.iter().enumerate() {
        pos_of[v as usize] = i;
    }
    // Outline point j of the resampled outline is raw vertex j.
    let pos_of_vertex = |raw: usize| pos_of.get(map[raw] as usize).copied().unwrap_or(usize::MAX);
    let pos_of_pin = |s: f64| pos_of_vertex(pin_point(&r_out, s));
    let fixed_map: Vec<usize> = piece.fixed_vertices.iter().map(|&i| pos_of_pin(cum[i])).collect();
    let span_map = piece.edges.iter().map(|e| [pos_of_pin(cum[e.start]), pos_of_pin(cum[e.end])]).collect();
    let notch_map = notch_s.iter().map(|s| s.map(pos_of_pin)).collect();
    let mut corners: Vec<usize> = sharp.iter().map(|&i| pos_of_pin(cum[i])).chain(fixed_map.iter().copied()).collect();
    corners.sort_unstable();
    corners.dedup();
    let total = cum[m];
    let mut order: Vec<usize> = (0..r_out.params.len()).collect();
    order.sort_by(|&a, &b| r_out.params[a].total_cmp(&r_out.params[b]).then(a.cmp(&b)));
    let outline_map =
        (0..m).map(|i| pos_of_vertex(nearest_param(&r_out.params, &order, cum[i], total))).collect::<Vec<usize>>();
    // Every outline sample is on the boundary unless the outline touches a hole or itself.
    if outline_map.iter().chain(&corners).any(|&p| p == usize::MAX) {
        return Err(TailorError::shape(
            format!("piece {}", piece.name),
            "an outline point is not on the mesh's outer contour (does a hole touch the outline?)",
        ));
    }

    let quality = quality::measure(&rest64, &triangles, &contour, h, raw.refinement_complete);
    Ok(PieceMesh {
        name: piece.name.clone(),
        edge_length: h,
        rest: rest64.iter().map(|p| [p[0] as f32, p[1] as f32]).collect(),
        triangles,
        contour,
        contour_param,
        contour_length: acc,
        corners,
        fixed_map,
        span_map,
        notch_map,
        outline_map,
        quality,
        warnings,
    })
}

/// The index of the parameter in `params` circularly nearest `s` (the smallest index among
/// equals), from `order`, the indices sorted by parameter: a binary search and its neighbours
/// plus both ends for the wrap, instead of a scan of every parameter per outline point
/// (quadratic for outlines of many points).
fn nearest_param(params: &[f64], order: &[usize], s: f64, total: f64) -> usize {
    let n = order.len();
    if n == 0 {
        return 0;
    }
    let k = order.partition_point(|&i| params[i] < s);
    [0, n - 1, k.min(n - 1), k.saturating_sub(1)]
        .into_iter()
        .map(|c| order[c])
        .min_by(|&a, &b| circ(params[a], s, total).total_cmp(&circ(params[b], s, total)).then(a.cmp(&b)))
        .unwrap_or(0)
}

fn circ(a: f64, b: f64, total: f64) -> f64 {
    let d = (a - b).abs();
    d.min(total - d)
}
