//! Mesh and cache IO: OBJ, PLY (ASCII and binary little-endian), glTF 2.0 binary with skinned
//! animation, and Point Cache 2.
//!
//! Every loader returns a [`TriMesh`] (polygons fan-triangulated) or a
//! [`TailorError::Parse`]/[`TailorError::Unsupported`] naming the file, the entity (line,
//! element, accessor, node…) and the reason. Nothing panics on malformed input.

pub mod gltf;
pub mod obj;
pub mod obj_write;
pub mod pc2;
pub mod pc2_stream;
pub mod ply;

use std::path::Path;

use crate::error::{Result, TailorError};

/// A plain triangle mesh: positions (metres) and counter-clockwise triangles.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    pub positions: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Axis-aligned bounds `(min, max)`, `None` for no vertices.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            ([lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])], [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])])
        }))
    }

    /// Checks indices and coordinates, naming `file` and the offending element.
    pub fn validate(&self, file: &str) -> Result<()> {
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(TailorError::parse(
                    file,
                    format!("triangle {t}"),
                    format!("vertex index {v} is out of range (only {n} vertices)"),
                ));
            }
        }
        for (i, p) in self.positions.iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(TailorError::parse(file, format!("vertex {i}"), format!("non-finite coordinate {p:?}")));
            }
        }
        Ok(())
    }
}

/// Loads a mesh by extension: `.obj`, `.ply`, `.glb`/`.gltf` (the rest pose at time 0).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<TriMesh> {
    let path = path.as_ref();
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "obj" => obj::read_obj(path),
        "ply" => ply::read_ply(path),
        "glb" | "gltf" => gltf::GltfScene::load(path)?.mesh_at(None, 0.0),
        _ => Err(TailorError::Unsupported {
            file: path.display().to_string(),
            entity: "file".into(),
            reason: format!("unknown mesh extension {ext:?} (expected obj, ply, glb or gltf)"),
        }),
    }
}

/// Reads a whole mesh or cache file: a regular file, at most [`crate::files::MAX_INPUT_BYTES`].
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    crate::files::read_input(path, crate::files::MAX_INPUT_BYTES)
}
