//! Scenes shared by the `collision_*` tests: cloth grids, sphere, box and plane meshes.
#![allow(dead_code)]

use glam::Vec3;
use tailor_core::collision::ClosedMesh;
use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::rectangle;
use tailor_core::solver::{Fabric, Simulation, SolverSettings};

/// Positions, rest shape and triangles of a cloth.
pub type Grid = (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[u32; 3]>);

/// A horizontal `w × w` cloth of `n × n` cells centred at `(cx, cy)`, height `z`.
pub fn cloth_grid(w: f32, n: usize, cx: f32, cy: f32, z: f32) -> Grid {
    let (rest, tris) = rectangle(w, w, n, n);
    let pos = rest.iter().map(|r| [r[0] - 0.5 * w + cx, r[1] - 0.5 * w + cy, z]).collect();
    (pos, rest, tris)
}

pub fn sim_of(pos: Vec<[f32; 3]>, rest: Vec<[f32; 2]>, tris: Vec<[u32; 3]>, settings: SolverSettings) -> Simulation {
    let mesh = ClothMesh::new(pos, rest, tris).unwrap();
    let fabric = Fabric { density: 0.2, stretch: 60.0, shear: 60.0, bend: 1e-6 };
    Simulation::new(mesh, fabric, settings).unwrap()
}

/// Icosphere with outward triangles.
pub fn icosphere(subdiv: u32, r: f32, c: Vec3) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
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
        let mut nf = Vec::new();
        let mut m = |a: u32, b: u32, v: &mut Vec<Vec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        for &[a, b, c] in &f {
            let (ab, bc, ca) = (m(a, b, &mut v), m(b, c, &mut v), m(c, a, &mut v));
            nf.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = nf;
    }
    (v.iter().map(|p| (*p * r + c).into()).collect(), f)
}

/// Axis-aligned box of half-size `h` centred at `c`, 12 outward triangles.
pub fn box_mesh(h: f32, c: Vec3) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    for i in 0..8 {
        let s = Vec3::new(
            if i & 1 != 0 { 1.0 } else { -1.0 },
            if i & 2 != 0 { 1.0 } else { -1.0 },
            if i & 4 != 0 { 1.0 } else { -1.0 },
        );
        v.push((c + s * h).into());
    }
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut t = Vec::new();
    for [a, b, cc, d] in quads {
        t.push([a, b, cc]);
        t.push([a, cc, d]);
    }
    (v, t)
}

/// A `size × size` square of `n × n` cells through `origin`, spanned by unit vectors `u`, `w`
/// (normal `u × w`).
pub fn plane_mesh(size: f32, n: usize, origin: Vec3, u: Vec3, w: Vec3) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (a, b) = (size * (i as f32 / n as f32 - 0.5), size * (j as f32 / n as f32 - 0.5));
            v.push((origin + u * a + w * b).into());
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (v, t)
}

/// Deepest cloth particle inside the closed mesh, metres (0 when none is).
pub fn max_depth(sim: &Simulation, verts: &[[f32; 3]], tris: &[[u32; 3]]) -> f32 {
    let pen = ClosedMesh::new(verts, tris).unwrap().penetration(&sim.positions().to_aos());
    pen.max_depth
}
