//! The cloth mesh the solver simulates.
//!
//! A [`ClothMesh`] is one or more triangulated pattern pieces concatenated: each vertex has a
//! 3D position (where the piece was placed around the body) and a 2D rest position (its place
//! in the flat pattern, metres). Stretch and shear are measured against the 2D rest shape, so a
//! garment keeps the true dimensions of its pattern however it was placed or bent.
//!
//! Construction validates everything the solver later relies on and names the offending
//! element: no empty mesh, indices in range, finite coordinates, no degenerate rest triangle,
//! manifold edges.

mod topology;
pub(crate) mod union_find;

pub use topology::{Hinge, Topology};

use crate::error::{Result, TailorError};

/// Twice the smallest rest-triangle area accepted, in m² (a 0.1 mm right triangle).
const MIN_DOUBLE_AREA: f64 = 1e-8;

/// A validated triangle mesh with a 2D rest shape.
#[derive(Debug, Clone)]
pub struct ClothMesh {
    positions: Vec<[f32; 3]>,
    rest: Vec<[f32; 2]>,
    triangles: Vec<[u32; 3]>,
    topology: Topology,
}

impl ClothMesh {
    /// Heap bytes of the mesh: positions, rest shape, triangles, edges and hinges.
    pub fn memory_bytes(&self) -> usize {
        fn b<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        b(&self.positions) + b(&self.rest) + b(&self.triangles) + b(&self.topology.edges) + b(&self.topology.hinges)
    }

    /// Builds and validates a mesh. `positions` are the initial 3D positions (metres), `rest`
    /// the 2D pattern coordinates (metres), `triangles` index both.
    pub fn new(positions: Vec<[f32; 3]>, rest: Vec<[f32; 2]>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        if positions.is_empty() {
            return Err(TailorError::EmptyMesh { what: "the mesh has no vertices".into() });
        }
        if triangles.is_empty() {
            return Err(TailorError::EmptyMesh { what: "the mesh has no triangles".into() });
        }
        if rest.len() != positions.len() {
            return Err(TailorError::shape(
                "cloth mesh",
                format!("{} rest (2D) coordinates for {} vertices", rest.len(), positions.len()),
            ));
        }
        check_finite3("cloth mesh positions", &positions)?;
        for (i, r) in rest.iter().enumerate() {
            for &c in r {
                if !c.is_finite() {
                    return Err(TailorError::NonFinite {
                        context: "cloth mesh rest coordinates".into(),
                        what: "vertex",
                        index: i,
                        value: c,
                    });
                }
            }
        }
        let n = positions.len();
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                if v as usize >= n {
                    return Err(TailorError::index(format!("triangle {t}"), v as i64, n, "vertices"));
                }
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(TailorError::DegenerateTriangle {
                    triangle: t,
                    reason: format!("it repeats a vertex {tri:?}"),
                });
            }
            let da = double_area_2d(rest[tri[0] as usize], rest[tri[1] as usize], rest[tri[2] as usize]);
            if da.abs() < MIN_DOUBLE_AREA {
                return Err(TailorError::DegenerateTriangle {
                    triangle: t,
                    reason: format!("its rest (2D pattern) area is {:.3e} m²", da.abs() * 0.5),
                });
            }
        }
        let topology = Topology::build(&triangles, &rest)?;
        Ok(Self { positions, rest, triangles, topology })
    }

    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }
    pub fn rest(&self) -> &[[f32; 2]] {
        &self.rest
    }
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Rest (pattern) area of triangle `t`, m².
    pub fn rest_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.triangles[t];
        0.5 * double_area_2d(self.rest[a as usize], self.rest[b as usize], self.rest[c as usize]).abs()
    }

    /// Mean rest edge length, metres (the default self-collision cell size).
    pub fn mean_edge_length(&self) -> f64 {
        let e = &self.topology.edges;
        let sum: f64 = e.iter().map(|&[a, b]| dist2(self.rest[a as usize], self.rest[b as usize])).sum();
        sum / e.len().max(1) as f64
    }
}

/// Rejects NaN or infinite coordinates, naming the first offending element.
pub fn check_finite3(context: &str, points: &[[f32; 3]]) -> Result<()> {
    for (i, p) in points.iter().enumerate() {
        for &c in p {
            if !c.is_finite() {
                return Err(TailorError::NonFinite { context: context.into(), what: "vertex", index: i, value: c });
            }
        }
    }
    Ok(())
}

/// Signed twice-area of a 2D triangle (positive when counter-clockwise), in f64.
pub fn double_area_2d(a: [f32; 2], b: [f32; 2], c: [f32; 2]) -> f64 {
    let (ax, ay) = (a[0] as f64, a[1] as f64);
    (b[0] as f64 - ax) * (c[1] as f64 - ay) - (b[1] as f64 - ay) * (c[0] as f64 - ax)
}

fn dist2(a: [f32; 2], b: [f32; 2]) -> f64 {
    let dx = a[0] as f64 - b[0] as f64;
    let dy = a[1] as f64 - b[1] as f64;
    (dx * dx + dy * dy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    type MeshParts = (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[u32; 3]>);

    fn quad() -> MeshParts {
        let rest = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let pos = rest.iter().map(|r: &[f32; 2]| [r[0], r[1], 0.0]).collect();
        (pos, rest, vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn builds_topology_of_a_quad() {
        let (p, r, t) = quad();
        let m = ClothMesh::new(p, r, t).unwrap();
        assert_eq!(m.topology().edges.len(), 5);
        assert_eq!(m.topology().hinges.len(), 1);
        assert_eq!(m.topology().boundary_edges, 4);
        assert!((m.rest_area(0) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_input_naming_the_element() {
        let (p, r, _) = quad();
        let e = ClothMesh::new(p.clone(), r.clone(), vec![[0, 1, 7]]).unwrap_err();
        assert!(matches!(e, TailorError::IndexOutOfRange { index: 7, .. }), "{e}");
        let e = ClothMesh::new(p.clone(), r.clone(), vec![[0, 1, 1]]).unwrap_err();
        assert!(matches!(e, TailorError::DegenerateTriangle { triangle: 0, .. }), "{e}");
        let mut r2 = r.clone();
        r2[2] = [2.0, 0.0];
        let e = ClothMesh::new(p.clone(), r2, vec![[0, 1, 2]]).unwrap_err();
        assert!(matches!(e, TailorError::DegenerateTriangle { triangle: 0, .. }), "{e}");
        let mut p2 = p.clone();
        p2[3][1] = f32::NAN;
        let e = ClothMesh::new(p2, r.clone(), vec![[0, 1, 2]]).unwrap_err();
        assert!(matches!(e, TailorError::NonFinite { index: 3, .. }), "{e}");
        let e = ClothMesh::new(vec![], vec![], vec![]).unwrap_err();
        assert!(matches!(e, TailorError::EmptyMesh { .. }), "{e}");
        let e = ClothMesh::new(p, r, vec![]).unwrap_err();
        assert!(matches!(e, TailorError::EmptyMesh { .. }), "{e}");
    }

    #[test]
    fn rejects_non_manifold_edges() {
        let rest = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, -1.0], [1.0, 1.0]];
        let pos = rest.iter().map(|r: &[f32; 2]| [r[0], r[1], 0.0]).collect();
        let e = ClothMesh::new(pos, rest, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap_err();
        assert!(matches!(e, TailorError::NonManifold { a: 0, b: 1, count: 3 }), "{e}");
    }
}
