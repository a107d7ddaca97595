//! Triangulation of a pattern [`Piece`] into an isotropic triangle mesh at a target edge length.
//!
//! The target edge length `h` is the artist's resolution knob (the paper's "polygonal
//! resolution", Sec. 4): silk wants small `h`, denim a larger one. The stages:
//!
//! 1. [`resample`]: the outline, each hole and each internal line are resampled at `h` by arc
//!    length between *pins*: the piece's fixed vertices, the ends of its named edges (stitch
//!    spans), notches, vertices where the outline turns by at least `corner_turn_deg`, and the
//!    points where an internal line meets the outline. Pins stay vertices, so corners and
//!    notches survive any resolution and boundary spacing is even (`d / round(d / h)`).
//! 2. [`fill`]: the interior is seeded with an equilateral lattice of side `h`.
//! 3. [`cdt`]: a constrained Delaunay triangulation of all of it, refined (Ruppert/Chew, via
//!    `spade`) to a minimum angle (default 28°) and a maximum area.
//! 4. [`contour`]: the outer contour is read back from the final triangles (refinement may
//!    have split an outline segment) and every pin is mapped to its contour position.
//!
//! The mesh is a flat 2D rest shape in the piece's own frame (metres); seams refer to it
//! through [`PieceMesh::contour`] positions.

mod cdt;
mod contour;
mod fill;
mod quality;
pub(crate) mod resample;

pub use quality::MeshQuality;

use serde::{Deserialize, Serialize};

use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Point2};
use resample::{arc_lengths, project, resample, sharp_vertices, signed_area, Resampled};

/// Settings of [`triangulate_piece`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TriangulateOptions {
    /// Target edge length `h`, metres (the resolution).
    pub edge_length: f64,
    /// Minimum triangle angle refinement enforces, degrees (at most 33; input angles smaller
    /// than this between outline segments cannot be improved).
    pub min_angle_deg: f64,
    /// Outline, hole and internal-line vertices where the direction turns by at least this many
    /// degrees are kept as vertices (so a 90° corner of an unmarked outline stays sharp).
    pub corner_turn_deg: f64,
    /// Largest triangle area allowed, as a multiple of the equilateral area `(√3/4) h²`.
    pub max_area_factor: f64,
    /// Lattice seeds closer than this multiple of `h` to a constraint are dropped.
    pub lattice_margin: f64,
}

impl TriangulateOptions {
    /// Defaults for a target edge length `h` (metres).
    pub fn new(edge_length: f64) -> Self {
        Self { edge_length, min_angle_deg: 28.0, corner_turn_deg: 30.0, max_area_factor: 1.5, lattice_margin: 0.6 }
    }

    fn validate(&self) -> Result<()> {
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

/// A triangulated piece: the flat rest mesh plus its outer contour, the unit of sewing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PieceMesh {
    pub name: String,
    /// Target edge length it was built with, metres.
    pub edge_length: f64,
    /// 2D rest coordinates, metres, in the piece's frame.
    pub rest: Vec<[f32; 2]>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The outer boundary loop, counter-clockwise, as vertex indices; `contour[0]` lies on the
    /// piece's first pin (its first fixed vertex, or outline point 0 when there is none).
    pub contour: Vec<u32>,
    /// Arc length along the contour from `contour[0]` to each contour vertex, metres.
    pub contour_param: Vec<f64>,
    /// Total contour length, metres.
    pub contour_length: f64,
    /// Contour positions of the corners: fixed vertices and vertices turning by at least
    /// `corner_turn_deg`, ascending.
    pub corners: Vec<usize>,
    /// Contour position of each `Piece::fixed_vertices` entry.
    pub fixed_map: Vec<usize>,
    /// Contour positions `[start, end]` of each `Piece::edges` span.
    pub span_map: Vec<[usize; 2]>,
    /// Contour position of each notch (None when it is farther than `h/2` from the outline).
    pub notch_map: Vec<Option<usize>>,
    /// Contour position nearest (by arc length) to each `Piece::outline` point; exact for pins.
    pub outline_map: Vec<usize>,
    pub quality: MeshQuality,
}

impl PieceMesh {
    /// Rest position of contour position `i` (wrapping).
    pub fn contour_point(&self, i: usize) -> [f32; 2] {
        self.rest[self.contour[i % self.contour.len()] as usize]
    }

    /// Contour position of a vertex, if it is on the contour.
    pub fn contour_position(&self, vertex: u32) -> Option<usize> {
        self.contour.iter().position(|&v| v == vertex)
    }
}

/// Where an internal line's end sits: free inside, or on the outline / a hole at arc length s.
#[derive(Clone, Copy)]
enum Attach {
    Free,
    Outline(f64),
    Hole(usize, f64),
}

/// Triangulates `piece` at `options.edge_length`. See the module docs for the stages.
pub fn triangulate_piece(piece: &Piece, options: &TriangulateOptions) -> Result<PieceMesh> {
    options.validate()?;
    validate_piece(piece)?;
    let h = options.edge_length;
    let eps = 1e-9;
    let snap = (1e-3 * h).max(1e-6);
    let outline = &piece.outline;
    let m = outline.len();
    let cum = arc_lengths(outline, true);

    let mut pins = Vec::new();
    for &i in &piece.fixed_vertices {
        if i >= m {
            return Err(TailorError::index(
                format!("piece {} fixed vertex", piece.name),
                i as i64,
                m,
                "outline points",
            ));
        }
        pins.push(cum[i]);
    }
    for (k, span) in piece.edges.iter().enumerate() {
        for i in [span.start, span.end] {
            if i >= m {
                return Err(TailorError::index(
                    format!("piece {} edge {k}", piece.name),
                    i as i64,
                    m,
                    "outline points",
                ));
            }
            pins.push(cum[i]);
        }
    }
    let sharp = sharp_vertices(outline, true, options.corner_turn_deg);
    pins.extend(sharp.iter().map(|&i| cum[i]));
    let notch_s: Vec<Option<f64>> = piece
        .notches
        .iter()
        .map(|&p| {
            let (s, d) = project(outline, &cum, true, p);
            (d <= 0.5 * h).then_some(s)
        })
        .collect();
    pins.extend(notch_s.iter().flatten());

    let hole_cums: Vec<Vec<f64>> = piece.holes.iter().map(|hl| arc_lengths(hl, true)).collect();
    let mut hole_pins: Vec<Vec<f64>> = piece
        .holes
        .iter()
        .zip(&hole_cums)
        .map(|(hl, c)| sharp_vertices(hl, true, options.corner_turn_deg).iter().map(|&i| c[i]).collect())
        .collect();
    let attach = |p: Point2| -> Attach {
        let (s, d) = project(outline, &cum, true, p);
        if d <= snap {
            return Attach::Outline(s);
        }
        for (k, hl) in piece.holes.iter().enumerate() {
            let (s, d) = project(hl, &hole_cums[k], true, p);
            if d <= snap {
                return Attach::Hole(k, s);
            }
        }
        Attach::Free
    };
    let line_ends: Vec<[Attach; 2]> =
        piece.internal_lines.iter().map(|l| [attach(l[0]), attach(l[l.len() - 1])]).collect();
    check_lines_inside(piece, &line_ends, snap)?;
    for ends in &line_ends {
        for a in ends {
            match *a {
                Attach::Outline(s) => pins.push(s),
                Attach::Hole(k, s) => hole_pins[k].push(s),
                Attach::Free => {}
            }
        }
    }

    let r_out = resample(outline, true, pins, h, eps);
    let r_holes: Vec<Resampled> =
        piece.holes.iter().zip(hole_pins).map(|(hl, p)| resample(hl, true, p, h, eps)).collect();

    // Constraint points: outline first (so outline point j is vertex j), then holes, then lines.
    let mut points: Vec<Point2> = r_out.points.clone();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut line_edges: Vec<[usize; 2]> = Vec::new();
    push_loop(&mut edges, 0, r_out.points.len());
    let mut hole_start = Vec::new();
    for r in &r_holes {
        hole_start.push(points.len());
        push_loop(&mut edges, points.len(), r.points.len());
        points.extend_from_slice(&r.points);
    }
    for (line, ends) in piece.internal_lines.iter().zip(&line_ends) {
        let lp = sharp_vertices(line, false, options.corner_turn_deg);
        let lc = arc_lengths(line, false);
        let r = resample(line, false, lp.iter().map(|&i| lc[i]).collect(), h, eps);
        let mut ids = Vec::with_capacity(r.points.len());
        for (j, &p) in r.points.iter().enumerate() {
            let end = if j == 0 {
                Some(ends[0])
            } else if j + 1 == r.points.len() {
                Some(ends[1])
            } else {
                None
            };
            let id = match end {
                Some(Attach::Outline(s)) => pin_point(&r_out, s),
                Some(Attach::Hole(k, s)) => hole_start[k] + pin_point(&r_holes[k], s),
                _ => {
                    points.push(p);
                    points.len() - 1
                }
            };
            ids.push(id);
        }
        for w in ids.windows(2) {
            if w[0] != w[1] {
                line_edges.push([w[0], w[1]]);
            }
        }
    }

    let segments: Vec<[Point2; 2]> = edges.iter().chain(&line_edges).map(|&[a, b]| [points[a], points[b]]).collect();
    let hole_polys: Vec<Vec<Point2>> = r_holes.iter().map(|r| r.points.clone()).collect();
    points.extend(fill::lattice_points(&r_out.points, &hole_polys, &segments, h, options.lattice_margin));

    let raw = cdt::triangulate(cdt::CdtInput {
        piece: &piece.name,
        points,
        loop_edges: edges,
        line_edges,
        outline: &r_out.points,
        holes: &hole_polys,
        h,
        min_angle_deg: options.min_angle_deg,
        area_factor: options.max_area_factor,
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
    let outline_map = (0..m)
        .map(|i| {
            let nearest = (0..r_out.params.len())
                .min_by(|&a, &b| circ(r_out.params[a], cum[i], total).total_cmp(&circ(r_out.params[b], cum[i], total)))
                .unwrap_or(0);
            pos_of_vertex(nearest)
        })
        .collect::<Vec<usize>>();
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
    })
}

/// Internal lines must stay inside the piece: every point not snapped to the outline or a hole
/// strictly inside, and no segment crossing the outline or a hole.
fn check_lines_inside(piece: &Piece, ends: &[[Attach; 2]], snap: f64) -> Result<()> {
    let loops: Vec<&Vec<Point2>> = std::iter::once(&piece.outline).chain(&piece.holes).collect();
    for (k, line) in piece.internal_lines.iter().enumerate() {
        let err = |what: &str| TailorError::shape(format!("piece {}", piece.name), format!("internal line {k} {what}"));
        for (j, &p) in line.iter().enumerate() {
            let snapped = (j == 0 && !matches!(ends[k][0], Attach::Free))
                || (j + 1 == line.len() && !matches!(ends[k][1], Attach::Free));
            let inside_piece =
                resample::inside(&piece.outline, p) && !piece.holes.iter().any(|h| resample::inside(h, p));
            if !snapped && !inside_piece {
                return Err(err(&format!("leaves the piece at point {j} ({:.4}, {:.4})", p[0], p[1])));
            }
        }
        for w in line.windows(2) {
            for lp in &loops {
                for i in 0..lp.len() {
                    if segments_cross(w[0], w[1], lp[i], lp[(i + 1) % lp.len()], snap) {
                        return Err(err("crosses the outline or a hole"));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Proper crossing of segments ab and cd: each strictly separates the other's ends by more
/// than `tol` (so touching at an end is not a crossing).
fn segments_cross(a: Point2, b: Point2, c: Point2, d: Point2, tol: f64) -> bool {
    let side = |p: Point2, q: Point2, r: Point2| {
        let l = resample::dist(p, q).max(f64::MIN_POSITIVE);
        ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / l
    };
    let opposite = |x: f64, y: f64| (x > tol && y < -tol) || (x < -tol && y > tol);
    opposite(side(a, b, c), side(a, b, d)) && opposite(side(c, d, a), side(c, d, b))
}

fn push_loop(edges: &mut Vec<[usize; 2]>, start: usize, n: usize) {
    for i in 0..n {
        edges.push([start + i, start + (i + 1) % n]);
    }
}

/// Index (in `r.points`) of the pin nearest arc length `s`.
fn pin_point(r: &Resampled, s: f64) -> usize {
    let k = (0..r.pins.len()).min_by(|&a, &b| (r.pins[a] - s).abs().total_cmp(&(r.pins[b] - s).abs())).unwrap_or(0);
    r.pin_points[k]
}

fn circ(a: f64, b: f64, total: f64) -> f64 {
    let d = (a - b).abs();
    d.min(total - d)
}

fn validate_piece(piece: &Piece) -> Result<()> {
    let ctx = format!("piece {}", piece.name);
    let check = |what: &'static str, pts: &[Point2]| -> Result<()> {
        for (i, p) in pts.iter().enumerate() {
            for &c in p {
                if !c.is_finite() {
                    return Err(TailorError::NonFinite { context: ctx.clone(), what, index: i, value: c as f32 });
                }
            }
        }
        Ok(())
    };
    if piece.outline.len() < 3 {
        return Err(TailorError::shape(ctx, format!("the outline has {} points (3 at least)", piece.outline.len())));
    }
    check("outline point", &piece.outline)?;
    if signed_area(&piece.outline) <= 0.0 {
        return Err(TailorError::shape(ctx, "the outline is clockwise or has no area (it must be counter-clockwise)"));
    }
    for (k, hl) in piece.holes.iter().enumerate() {
        if hl.len() < 3 {
            return Err(TailorError::shape(ctx, format!("hole {k} has {} points (3 at least)", hl.len())));
        }
        check("hole point", hl)?;
        if let Some(j) = hl.iter().position(|&p| !resample::inside(&piece.outline, p)) {
            return Err(TailorError::shape(ctx, format!("hole {k} point {j} is outside the outline")));
        }
    }
    for (k, l) in piece.internal_lines.iter().enumerate() {
        if l.len() < 2 {
            return Err(TailorError::shape(ctx, format!("internal line {k} has {} points (2 at least)", l.len())));
        }
        check("internal line point", l)?;
    }
    check("notch", &piece.notches)?;
    Ok(())
}
