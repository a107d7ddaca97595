//! The welded garment: the sewn pieces as one mesh, for export (OBJ, glTF, other DCCs).
//!
//! The solver keeps every piece as its own mesh and holds the seams closed with springs; a
//! renderer or another DCC wants one surface. [`weld`] merges the pieces along their seams:
//!
//! 1. **Seam points.** Each side of each sewn pair is a vertex, or a point strictly inside a
//!    triangle edge (unequal seams pair by arc length, so a vertex of one side lands inside an
//!    edge of the other). Such a point becomes a new vertex of its edge ([`points`]).
//! 2. **Splitting.** Every triangle with points on its edges is cut at them ([`split`]), so the
//!    triangles on both sides of a seam meet at the same vertices: no T-junction remains, the
//!    seam is watertight whatever the two sides' vertex counts.
//! 3. **Merging.** The two points of every pair are joined (union-find over vertices and
//!    inserted points); each class becomes one welded vertex at the mean of its members (on a
//!    closed seam they coincide to the seam gap, so this is the solved position).
//! 4. **Clean-up.** A triangle two of whose corners fell into one class (a dart's tip sewn
//!    shut) has no area left and is dropped, and counted.
//! 5. **Winding.** Pieces sewn with opposite windings would flip the normals across their seam;
//!    whole pieces are flipped so every seam edge is wound consistently ([`orient`]).
//!
//! Every welded vertex is a fixed weighted sum of input vertices, so any frame of the pieces
//! (a PC2 cache) welds with [`WeldedMesh::apply`], and per-corner attributes (UVs) carry over
//! with [`WeldedMesh::apply_corners`] through each corner's barycentric coordinates in the input
//! triangle it was cut from. [`WeldStats`] says what was merged, inserted and dropped, and how
//! many boundary, non-manifold or inconsistently wound edges the result has.

mod orient;
mod points;
mod split;

use std::collections::HashMap;

use crate::error::{Result, TailorError};
use crate::garment::SolverInput;
use crate::mesh::union_find::UnionFind;
use crate::solver::Seam;
use points::{classify, edge_set, EdgePoints, Point};
use split::Corner;

/// What the weld did, and the shape of its result.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WeldStats {
    pub input_vertices: usize,
    pub input_triangles: usize,
    /// Vertices and inserted seam points absorbed into another (each pair of two distinct
    /// points merges one).
    pub merged: usize,
    /// Seam points inside an edge that became vertices.
    pub inserted_points: usize,
    /// Vertices added at the centroid of triangles cut on two or three edges.
    pub centroids: usize,
    /// Input triangles cut at seam points.
    pub split_triangles: usize,
    /// Triangles dropped because two of their corners merged.
    pub collapsed_triangles: usize,
    /// Edges of the welded mesh with one triangle (its open border).
    pub boundary_edges: usize,
    /// Edges with more than two triangles (three pieces sewn along one line).
    pub non_manifold_edges: usize,
    /// Pieces (connected parts of the input) whose triangles were reversed to wind like the
    /// pieces they are sewn to.
    pub flipped_pieces: usize,
    /// Edges whose two triangles still run along it the same way after the pieces were
    /// flipped (only seams that no flip satisfies, such as a Möbius strip).
    pub misoriented_edges: usize,
}

/// The garment as one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct WeldedMesh {
    pub positions: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Input vertex → welded vertex.
    pub vertex_map: Vec<u32>,
    /// Welded triangle → the input triangle it was cut from.
    pub triangle_source: Vec<u32>,
    /// Per welded triangle, each corner's barycentric coordinates in its source triangle.
    pub corner_weights: Vec<[[f32; 3]; 3]>,
    /// Welded vertex `i` = Σ `source_weights[k]`·input[`source_vertices[k]`] over
    /// `k ∈ source_offsets[i]..source_offsets[i+1]`.
    pub source_offsets: Vec<u32>,
    pub source_vertices: Vec<u32>,
    pub source_weights: Vec<f32>,
    pub stats: WeldStats,
}

fn check_positions(context: &str, positions: &[[f32; 3]]) -> Result<()> {
    for (i, p) in positions.iter().enumerate() {
        if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
            return Err(TailorError::NonFinite { context: context.into(), what: "vertex", index: i, value });
        }
    }
    Ok(())
}

fn check_triangles(triangles: &[[u32; 3]], n: usize) -> Result<()> {
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri {
            if v as usize >= n {
                return Err(TailorError::index(format!("weld: triangle {t}"), v as i64, n, "vertices"));
            }
        }
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            return Err(TailorError::DegenerateTriangle { triangle: t, reason: format!("repeats a vertex ({tri:?})") });
        }
    }
    Ok(())
}

/// Welds the pieces of a garment (`positions` and `triangles` of all pieces together, as the
/// solver holds them) along `seams` (the solver's weighted seam pairs). See the module docs.
pub fn weld(positions: &[[f32; 3]], triangles: &[[u32; 3]], seams: &[Seam]) -> Result<WeldedMesh> {
    let n = positions.len();
    if n == 0 || triangles.is_empty() {
        return Err(TailorError::EmptyMesh { what: format!("weld: {n} vertices, {} triangles", triangles.len()) });
    }
    if n >= u32::MAX as usize / 2 {
        return Err(TailorError::shape("weld", format!("{n} vertices is too many")));
    }
    check_positions("weld: positions", positions)?;
    check_triangles(triangles, n)?;

    // 1. Seam points: vertices, or new nodes on edges; every pair's two nodes joined.
    let edges = edge_set(triangles);
    let mut uf = UnionFind::new(n);
    let mut on_edges = EdgePoints::default();
    let mut extra_sources: Vec<[(u32, f32); 3]> = Vec::new(); // nodes n.. as input vertices
    for seam in seams {
        for (k, (a, b)) in seam.pairs.iter().enumerate() {
            let mut node = |p, side| -> Result<u32> {
                Ok(match classify(p, n, &seam.name, k, side)? {
                    Point::Vertex(v) => v,
                    Point::Edge { lo, hi, t } => {
                        if !edges.contains(&(lo, hi)) {
                            return Err(TailorError::InvalidSeam {
                                seam: seam.name.clone(),
                                reason: format!(
                                    "pair {k} side {side}: vertices {lo} and {hi} are not the ends of a triangle edge"
                                ),
                            });
                        }
                        let (node, fresh) = on_edges.insert(lo, hi, t, || uf.push());
                        if fresh {
                            extra_sources.push([(lo, 1.0 - t), (hi, t), (lo, 0.0)]);
                        }
                        node
                    }
                })
            };
            let (na, nb) = (node(a, 'A')?, node(b, 'B')?);
            uf.union(na, nb);
        }
    }
    let inserted_points = extra_sources.len();
    on_edges.sort();

    // 2. Cut the triangles at the points on their edges.
    let mut pieces: Vec<(u32, [Corner; 3])> = Vec::with_capacity(triangles.len());
    let mut split_triangles = 0;
    for (t, &tri) in triangles.iter().enumerate() {
        let pts = [0, 1, 2].map(|k| on_edges.on(tri[k], tri[(k + 1) % 3]));
        if pts.iter().any(|p| !p.is_empty()) {
            split_triangles += 1;
        }
        let centroid = || {
            let third = 1.0 / 3.0;
            extra_sources.push([(tri[0], third), (tri[1], third), (tri[2], third)]);
            uf.push()
        };
        pieces.extend(split::split(tri, pts, centroid).into_iter().map(|c| (t as u32, c)));
    }
    let centroids = extra_sources.len() - inserted_points;

    // 3. One welded vertex per class, numbered in order of first node.
    let nodes = uf.len();
    let mut welded_of_root: HashMap<u32, u32> = HashMap::new();
    let mut node_welded = Vec::with_capacity(nodes);
    let mut class_size: Vec<u32> = Vec::new();
    for v in 0..nodes as u32 {
        let root = uf.find(v);
        let next = welded_of_root.len() as u32;
        let w = *welded_of_root.entry(root).or_insert(next);
        if w as usize == class_size.len() {
            class_size.push(0);
        }
        class_size[w as usize] += 1;
        node_welded.push(w);
    }
    let welded_count = class_size.len();
    let mut sources: Vec<Vec<(u32, f32)>> = vec![Vec::new(); welded_count];
    for (node, &w) in node_welded.iter().enumerate() {
        let share = 1.0 / class_size[w as usize] as f32;
        let list = &mut sources[w as usize];
        if node < n {
            list.push((node as u32, share));
        } else {
            list.extend(extra_sources[node - n].iter().filter(|s| s.1 != 0.0).map(|&(v, x)| (v, x * share)));
        }
    }
    let (mut source_offsets, mut source_vertices, mut source_weights) = (vec![0u32], Vec::new(), Vec::new());
    for mut list in sources {
        list.sort_by_key(|s| s.0);
        let start = source_vertices.len();
        for (v, x) in list {
            if source_vertices.len() > start && *source_vertices.last().expect("non-empty") == v {
                *source_weights.last_mut().expect("non-empty") += x;
            } else {
                source_vertices.push(v);
                source_weights.push(x);
            }
        }
        source_offsets.push(source_vertices.len() as u32);
    }

    // 4. Welded triangles; those with two corners in one class are gone.
    let (mut out_tris, mut triangle_source, mut corner_weights) = (Vec::new(), Vec::new(), Vec::new());
    let mut collapsed_triangles = 0;
    let (component, components) = orient::components(triangles, n);
    let mut out_piece = Vec::new();
    for (src, c) in pieces {
        let tri = c.map(|c| node_welded[c.node as usize]);
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            collapsed_triangles += 1;
            continue;
        }
        out_tris.push(tri);
        out_piece.push(component[src as usize]);
        triangle_source.push(src);
        corner_weights.push(c.map(|c| c.bary));
    }

    let flipped_pieces = orient::orient(&mut out_tris, &mut corner_weights, &out_piece, components);

    let merged =
        n + inserted_points - node_welded[..n + inserted_points].iter().collect::<std::collections::HashSet<_>>().len();
    let mut mesh = WeldedMesh {
        positions: Vec::new(),
        triangles: out_tris,
        vertex_map: node_welded[..n].to_vec(),
        triangle_source,
        corner_weights,
        source_offsets,
        source_vertices,
        source_weights,
        stats: WeldStats {
            input_vertices: n,
            input_triangles: triangles.len(),
            merged,
            inserted_points,
            centroids,
            split_triangles,
            collapsed_triangles,
            flipped_pieces,
            ..WeldStats::default()
        },
    };
    mesh.positions = mesh.apply(positions)?;
    census(&mesh.triangles, &mut mesh.stats);
    Ok(mesh)
}

/// Boundary, non-manifold and inconsistently wound edges of `triangles`.
fn census(triangles: &[[u32; 3]], stats: &mut WeldStats) {
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::with_capacity(triangles.len() * 2);
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = edges.entry(points::key(a, b)).or_insert((0, 0));
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    for &(count, winding) in edges.values() {
        match count {
            1 => stats.boundary_edges += 1,
            2 if winding != 0 => stats.misoriented_edges += 1,
            c if c > 2 => stats.non_manifold_edges += 1,
            _ => {}
        }
    }
}

impl WeldedMesh {
    pub fn num_vertices(&self) -> usize {
        self.source_offsets.len() - 1
    }

    /// Welds one frame of the input vertices (a baked frame, a PC2 frame): `frame` has one
    /// position per input vertex; the result one per welded vertex.
    pub fn apply(&self, frame: &[[f32; 3]]) -> Result<Vec<[f32; 3]>> {
        if frame.len() != self.stats.input_vertices {
            return Err(TailorError::shape(
                "weld: frame",
                format!(
                    "{} positions, but the welded garment was made from {} vertices",
                    frame.len(),
                    self.stats.input_vertices
                ),
            ));
        }
        check_positions("weld: frame", frame)?;
        Ok(self
            .source_offsets
            .windows(2)
            .map(|r| {
                let mut p = [0.0f64; 3];
                for k in r[0] as usize..r[1] as usize {
                    let (v, w) = (self.source_vertices[k] as usize, self.source_weights[k] as f64);
                    for (o, &x) in p.iter_mut().zip(&frame[v]) {
                        *o += w * x as f64;
                    }
                }
                p.map(|x| x as f32)
            })
            .collect())
    }

    /// Carries a per-corner attribute (UVs, colours) of the input triangles over: `values` has
    /// `width` floats per input corner (`3 × input triangles` corners, in triangle order); the
    /// result has `width` per welded corner, interpolated at the corner's place in its source
    /// triangle (a corner that is an input vertex keeps that corner's value exactly).
    pub fn apply_corners(&self, values: &[f32], width: usize) -> Result<Vec<f32>> {
        let corners = 3 * self.stats.input_triangles;
        if width == 0 || values.len() != corners * width {
            return Err(TailorError::shape(
                "weld: corner values",
                format!("{} values, expected {corners} corners × {width}", values.len()),
            ));
        }
        let mut out = Vec::with_capacity(3 * self.triangles.len() * width);
        for (&src, bary) in self.triangle_source.iter().zip(&self.corner_weights) {
            for b in bary {
                for d in 0..width {
                    let at = |k: usize| values[(3 * src as usize + k) * width + d] as f64;
                    out.push((b[0] as f64 * at(0) + b[1] as f64 * at(1) + b[2] as f64 * at(2)) as f32);
                }
            }
        }
        Ok(out)
    }
}

/// Welds a garment as the solver sees it ([`SolverInput`], e.g. from
/// [`build_simulation`](crate::garment::build_simulation)) at `positions` (one per particle,
/// e.g. the simulation's current ones), or as placed when `None`.
pub fn weld_garment(input: &SolverInput, positions: Option<&[[f32; 3]]>) -> Result<WeldedMesh> {
    let mesh = &input.sewn.mesh;
    let positions = positions.unwrap_or(mesh.positions());
    if positions.len() != mesh.num_vertices() {
        return Err(TailorError::shape(
            "weld: positions",
            format!("{} positions for a garment of {} particles", positions.len(), mesh.num_vertices()),
        ));
    }
    weld(positions, mesh.triangles(), &input.seams)
}
