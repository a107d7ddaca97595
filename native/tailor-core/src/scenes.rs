//! Procedural scenes used by tests, benchmarks and the headless demo: flat rectangles, a tube
//! of two rectangles sewn along both sides (the simplest real garment), and closed collider
//! meshes (icosphere, box).

use glam::Vec3;

use crate::error::{Result, TailorError};
use crate::mesh::ClothMesh;
use crate::solver::Seam;

/// A rectangular grid in the pattern plane: `nx × ny` cells of `width × height` metres, the
/// cells split along alternating diagonals so the mesh has no preferred shear direction.
/// Returns rest coordinates (origin at the lower-left corner) and triangles (CCW).
pub fn rectangle(width: f32, height: f32, nx: usize, ny: usize) -> (Vec<[f32; 2]>, Vec<[u32; 3]>) {
    let mut rest = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            rest.push([width * i as f32 / nx as f32, height * j as f32 / ny as f32]);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            } else {
                tris.push([a, b, d]);
                tris.push([b, c, d]);
            }
        }
    }
    (rest, tris)
}

/// Vertex indices of a rectangle grid's column `i` from bottom to top.
pub fn grid_column(nx: usize, ny: usize, i: usize) -> Vec<u32> {
    (0..=ny).map(|j| (j * (nx + 1) + i) as u32).collect()
}

/// The most grid cells a procedural panel may have (two million: about the triangulation's
/// vertex budget, and far above any test or benchmark scene).
const MAX_SCENE_CELLS: f64 = 2.0e6;

/// A tube of two rectangular panels (front and back) sewn along both vertical sides.
pub struct SewnTube {
    pub mesh: ClothMesh,
    pub seams: Vec<Seam>,
    /// Vertices per panel.
    pub panel_vertices: usize,
}

/// Builds a tube: two `width × height` panels with cells of about `edge` metres, hung
/// vertically (z up) facing each other `gap` metres apart around the z axis, bottom at
/// `bottom_z`. The front panel's left side is sewn to the back panel's left side, and the
/// right sides likewise, so the seams start `gap` apart and close in simulation.
pub fn sewn_tube(width: f32, height: f32, edge: f32, gap: f32, bottom_z: f32, seam_stiffness: f32) -> Result<SewnTube> {
    // Checked before anything is allocated: `edge` 0 or 1e-6 asked for a grid of 1e11 cells
    // (or an infinite one) and the process died in the allocator.
    for (name, v) in [("width", width), ("height", height), ("edge", edge)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(TailorError::setting(name, v, "must be a positive length in metres"));
        }
    }
    for (name, v) in [("gap", gap), ("bottom", bottom_z), ("seam_stiffness", seam_stiffness)] {
        if !v.is_finite() {
            return Err(TailorError::setting(name, v, "must be a finite number"));
        }
    }
    let cells = (width as f64 / edge as f64).round().max(2.0) * (height as f64 / edge as f64).round().max(2.0);
    if cells > MAX_SCENE_CELLS {
        return Err(TailorError::setting(
            "edge",
            edge,
            format!("{width} x {height} m panels would get {cells:.0} cells each (at most {MAX_SCENE_CELLS:.0})"),
        ));
    }
    let nx = ((width / edge).round() as usize).max(2);
    let ny = ((height / edge).round() as usize).max(2);
    let (rest, tris) = rectangle(width, height, nx, ny);
    let nv = rest.len();
    let mut positions = Vec::with_capacity(2 * nv);
    let mut all_rest = Vec::with_capacity(2 * nv);
    let mut triangles = Vec::with_capacity(2 * tris.len());
    // Front panel at y = −gap/2, x from −w/2 to w/2; back panel mirrored at y = +gap/2, so that
    // both panels' outside faces point away from the axis.
    for (panel, side) in [(0u32, -1.0f32), (1, 1.0)] {
        for r in &rest {
            let x = if panel == 0 { r[0] - width / 2.0 } else { width / 2.0 - r[0] };
            positions.push([x, side * gap / 2.0, bottom_z + r[1]]);
            // Keep the pieces apart in the pattern plane too.
            all_rest.push([r[0] + panel as f32 * (width + 0.1), r[1]]);
        }
        for t in &tris {
            triangles.push(t.map(|v| v + panel * nv as u32));
        }
    }
    let mesh = ClothMesh::new(positions, all_rest, triangles)?;
    let left_front = grid_column(nx, ny, 0);
    let right_front = grid_column(nx, ny, nx);
    // The back panel is mirrored in x: its column nx sits at x = −w/2 (the left side).
    let off = |c: Vec<u32>| c.into_iter().map(|v| v + nv as u32).collect::<Vec<_>>();
    let left_back = off(grid_column(nx, ny, nx));
    let right_back = off(grid_column(nx, ny, 0));
    let bend = 1e-5;
    let seams = vec![
        Seam::one_to_one("left side", &left_front, &left_back, seam_stiffness, bend)?,
        Seam::one_to_one("right side", &right_front, &right_back, seam_stiffness, bend)?,
    ];
    Ok(SewnTube { mesh, seams, panel_vertices: nv })
}

/// The sewn tube of the benchmarks: cells of `edge` metres, square panels sized so that the two
/// panels together have close to `particles` particles, starting 2 cm apart with their bottom
/// at z = 0 (seams of 1000 N/m).
pub fn sewn_tube_of(particles: usize, edge: f32) -> Result<SewnTube> {
    let side = ((particles as f32 / 2.0).sqrt() - 1.0).max(2.0) * edge;
    sewn_tube(side, side, edge, 0.02, 0.0, 1000.0)
}

/// A hanging sheet: a square of side `size` with close to `particles` particles, lying flat
/// (z = `height`) and pinned at the two corners of one edge, so that it swings down and
/// settles hanging. Returns the mesh and the pinned particles.
pub fn hanging_sheet(particles: usize, size: f32, height: f32) -> Result<(ClothMesh, Vec<u32>)> {
    let n = ((particles as f32).sqrt() - 1.0).round().max(2.0) as usize;
    let (rest, tris) = rectangle(size, size, n, n);
    let positions = rest.iter().map(|r| [r[0] - size / 2.0, r[1] - size / 2.0, height]).collect();
    let pins = vec![(n * (n + 1)) as u32, ((n + 1) * (n + 1) - 1) as u32];
    Ok((ClothMesh::new(positions, rest, tris)?, pins))
}

/// Two square layers of `side` metres with `n × n` cells each, stacked `spacing` apart along
/// `up` (a unit axis) with their centre at `centre`: a layered garment for self-collision.
pub fn two_layers(centre: [f32; 3], up: [f32; 3], side: f32, n: usize, spacing: f32) -> Result<ClothMesh> {
    let (rest, tris) = rectangle(side, side, n, n);
    let up = Vec3::from(up).normalize();
    let u = up.any_orthonormal_vector();
    let w = up.cross(u);
    let c = Vec3::from(centre);
    let mut pos = Vec::with_capacity(2 * rest.len());
    let mut all_rest = Vec::with_capacity(2 * rest.len());
    for layer in 0..2 {
        for r in &rest {
            let p = c + u * (r[0] - 0.5 * side) + w * (r[1] - 0.5 * side) + up * (layer as f32 * spacing);
            pos.push(p.into());
            all_rest.push([r[0] + layer as f32 * (side + 0.1), r[1]]);
        }
    }
    let k = rest.len() as u32;
    let all_tris = tris.iter().copied().chain(tris.iter().map(|t| t.map(|v| v + k))).collect();
    ClothMesh::new(pos, all_rest, all_tris)
}

/// Subdivided icosahedron on a sphere of `radius`, outward winding: `10·4^k + 2` vertices.
pub fn icosphere(subdiv: u32, radius: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from(*p).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdiv {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        let mut nf = Vec::with_capacity(f.len() * 4);
        for &[a, b, c] in &f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            nf.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = nf;
    }
    (v.iter().map(|p| (*p * radius).into()).collect(), f)
}

/// Axis-aligned box `[lo, hi]`, 12 outward triangles.
pub fn box_mesh(lo: [f32; 3], hi: [f32; 3]) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = (0..8).map(|i| [[lo[0], hi[0]][i & 1], [lo[1], hi[1]][(i >> 1) & 1], [lo[2], hi[2]][i >> 2]]).collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3], // z = lo
        [4, 5, 6],
        [5, 7, 6], // z = hi
        [0, 1, 4],
        [1, 5, 4], // y = lo
        [2, 6, 3],
        [3, 6, 7], // y = hi
        [0, 4, 2],
        [2, 4, 6], // x = lo
        [1, 3, 5],
        [3, 7, 5], // x = hi
    ];
    (v, t)
}
