//! Constrained Delaunay triangulation and Ruppert/Chew refinement (via `spade`).
//!
//! Input: the resampled constraint vertices and segments (outline, holes, internal lines) and
//! the interior lattice seeds. Refinement inserts Steiner points until every triangle's
//! circumradius-to-shortest-edge ratio is at most `1 / (2 sin θ_min)` (so every angle is at
//! least `θ_min`, except at input angles smaller than that) and every area is at most
//! `area_factor · (√3/4) h²`. Refinement may split a constraint segment that a new point
//! encroaches; the contour is therefore read back from the final triangles, never assumed.
//!
//! Two phases, because spade's inside/outside flood fill (`exclude_outer_faces`) counts each
//! crossing of an *open* internal line as entering another layer and then treats the whole
//! interior as outside. Phase 1 triangulates and refines with only the closed loops (outline,
//! holes) as constraints and the internal-line points as plain vertices; phase 2 then adds the
//! internal-line segments as constraints. The points along a line are `h` apart and no lattice
//! seed lies within `0.6 h` of it, so those segments are (almost always) Delaunay edges already
//! and phase 2 flips little or nothing. Last, `refine` repairs the angles spade left, with every
//! constraint in.
//!
//! The kept triangles are those whose centroid lies inside the resampled outline and outside
//! every hole (even-odd test), and whose area is not a rounding-level sliver: resampled points
//! on a straight outline are collinear only up to rounding, and the zero-area triangles spade
//! builds between them and the convex hull must not count as inside.

use spade::handles::FixedVertexHandle;
use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2 as SPoint, RefinementParameters, Triangulation};

use super::region::Region;
use crate::error::{Result, TailorError};
use crate::pattern::Point2;

/// A raw triangulation: points (constraint points first, in input order) and CCW triangles.
pub(crate) struct RawMesh {
    pub points: Vec<Point2>,
    pub triangles: Vec<[u32; 3]>,
    pub refinement_complete: bool,
}

pub(crate) struct CdtInput<'a> {
    pub piece: &'a str,
    pub points: Vec<Point2>,
    /// The first `n_constraint` points are the constraints' (the rest are lattice seeds).
    pub n_constraint: usize,
    /// Segments of closed loops (outline, holes).
    pub loop_edges: Vec<[usize; 2]>,
    /// Segments of internal lines, added after refinement.
    pub line_edges: Vec<[usize; 2]>,
    pub outline: &'a [Point2],
    pub holes: &'a [Vec<Point2>],
    pub h: f64,
    pub min_angle_deg: f64,
    pub area_factor: f64,
    /// Which mesher (`TriangulateOptions::mesher`): 1 stops after spade's refinement.
    pub mesher: u32,
}

pub(crate) fn triangulate(input: CdtInput<'_>) -> Result<RawMesh> {
    let ctx = || format!("piece {}", input.piece);
    let n_in = input.points.len();
    let verts: Vec<SPoint<f64>> = input.points.iter().map(|p| SPoint::new(p[0], p[1])).collect();
    let mut conflict = None;
    // Bulk-loaded, or inserted in order for long thin pieces (`load`).
    let (mut cdt, order): (ConstrainedDelaunayTriangulation<SPoint<f64>>, _) =
        super::load::load_cdt(verts, input.loop_edges.clone(), input.n_constraint, |e| {
            conflict.get_or_insert(e);
        })
        .map_err(|e| TailorError::shape(ctx(), format!("triangulation failed: {e}")))?;
    let spade = |i: usize| order.as_ref().map_or(i, |o| o.spade(i));
    let crossing = |[a, b]: [usize; 2]| {
        let (pa, pb) = (input.points[a], input.points[b]);
        TailorError::shape(
            ctx(),
            format!(
                "the outline, holes and internal lines cross each other near ({:.4}, {:.4})-({:.4}, {:.4}) m",
                pa[0], pa[1], pb[0], pb[1]
            ),
        )
    };
    if let Some(e) = conflict {
        return Err(crossing(e));
    }
    if cdt.num_vertices() != n_in {
        return Err(TailorError::shape(ctx(), "two outline, hole or internal-line points coincide"));
    }
    let eq_area = 3f64.sqrt() / 4.0 * input.h * input.h;
    let params = RefinementParameters::<f64>::new()
        .with_angle_limit(AngleLimit::from_deg(input.min_angle_deg))
        .with_max_allowed_area(input.area_factor * eq_area)
        // Below a hundredth of the target area a triangle is an input feature, not a defect.
        .with_min_required_area(0.01 * eq_area)
        // Capped by the vertex budget too: a needle (a fuzzed shear of a circle) asked for
        // millions of Steiner points and took minutes; normal pieces add a few per cent.
        .with_max_additional_vertices((10 * n_in + 1000).min(super::checks::MAX_VERTICES as usize))
        .exclude_outer_faces(true);
    let result = cdt.refine(params);

    // Internal lines crossing each other (a grain line over a balance line) are split where
    // they cross; the crossing becomes a vertex.
    for &[a, b] in &input.line_edges {
        let (fa, fb) = (FixedVertexHandle::from_index(spade(a)), FixedVertexHandle::from_index(spade(b)));
        if cdt.can_add_constraint(fa, fb) {
            cdt.add_constraint(fa, fb);
        } else {
            cdt.add_constraint_and_split(fa, fb, |p| p);
        }
    }

    // Now that every constraint is in: the angles spade left (see `refine`); mesher 1 (files
    // saved before the pass existed) stops here, so their meshes come back as they were saved.
    let complete = input.mesher < 2
        || super::refine::refine(
            &mut cdt,
            &super::refine::RefineInput {
                n_in,
                n_constraint: input.n_constraint,
                outline: input.outline,
                holes: input.holes,
                h: input.h,
                min_angle_deg: input.min_angle_deg,
            },
        );

    let points: Vec<Point2> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
    let sliver = 1e-9 * eq_area;
    let mut triangles = Vec::with_capacity(cdt.num_inner_faces());
    let region = Region::new(input.outline, input.holes, input.h);
    for face in cdt.inner_faces() {
        let [a, b, c] = face.vertices().map(|v| v.fix().index() as u32);
        let (pa, pb, pc) = (points[a as usize], points[b as usize], points[c as usize]);
        let cross = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
        if cross.abs() * 0.5 <= sliver {
            continue;
        }
        let centroid = [(pa[0] + pb[0] + pc[0]) / 3.0, (pa[1] + pb[1] + pc[1]) / 3.0];
        if !region.contains(centroid) {
            continue;
        }
        triangles.push(if cross > 0.0 { [a, b, c] } else { [a, c, b] });
    }
    let (points, triangles) = match order {
        // Back to input numbering: input point i is vertex i, Steiner points after.
        Some(o) => {
            let mut renumbered = points.clone();
            for (k, p) in points.iter().enumerate() {
                renumbered[o.input(k)] = *p;
            }
            let triangles = triangles.into_iter().map(|t| t.map(|k| o.input(k as usize) as u32)).collect();
            (renumbered, triangles)
        }
        None => (points, triangles),
    };
    Ok(RawMesh { points, triangles, refinement_complete: result.refinement_complete && complete })
}
