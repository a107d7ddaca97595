//! Scenes shared by the `collision_*` tests: cloth grids, sphere, box and plane meshes.
#![allow(dead_code)]

use glam::Vec3;
use tailor_core::collision::ClosedMesh;
use tailor_core::mesh::ClothMesh;
use tailor_core::scenes::{self, rectangle};
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
    let fabric = Fabric::isotropic(0.2, 60.0, 60.0, 1e-6);
    Simulation::new(mesh, fabric, settings).unwrap()
}

/// Icosphere of radius `r` centred at `c`, outward triangles.
pub fn icosphere(subdiv: u32, r: f32, c: Vec3) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (v, t) = scenes::icosphere(subdiv, r);
    (v.into_iter().map(|p| (Vec3::from(p) + c).into()).collect(), t)
}

/// Axis-aligned box of half-size `h` centred at `c`, 12 outward triangles.
pub fn box_mesh(h: f32, c: Vec3) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    scenes::box_mesh((c - h).into(), (c + h).into())
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
