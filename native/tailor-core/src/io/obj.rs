//! Wavefront OBJ reader: `v` positions and `f` polygons (fan-triangulated); normals, texture
//! coordinates, groups and materials are ignored. Face corners may be `i`, `i/t`, `i//n` or
//! `i/t/n`, with negative indices counting back from the last vertex read.

use std::path::Path;

use super::{read_bytes, TriMesh};
use crate::error::{Result, TailorError};

/// Reads an OBJ file.
pub fn read_obj(path: impl AsRef<Path>) -> Result<TriMesh> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = read_bytes(path)?;
    let text = String::from_utf8_lossy(&bytes);
    parse_obj(&text, &name)
}

/// Parses OBJ text; `file` names the source in errors.
pub fn parse_obj(text: &str, file: &str) -> Result<TriMesh> {
    let mut mesh = TriMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut tokens = line.split_whitespace();
        let entity = || format!("line {}", n + 1);
        match tokens.next() {
            Some("v") => {
                let mut p = [0.0f32; 3];
                for c in p.iter_mut() {
                    let tok = tokens
                        .next()
                        .ok_or_else(|| TailorError::parse(file, entity(), "vertex with fewer than 3 coordinates"))?;
                    *c = tok
                        .parse::<f32>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| TailorError::parse(file, entity(), format!("bad coordinate {tok:?}")))?;
                }
                mesh.positions.push(p);
            }
            Some("f") => {
                corners.clear();
                for tok in tokens {
                    let idx = tok.split('/').next().unwrap_or("");
                    let i: i64 = idx
                        .parse()
                        .map_err(|_| TailorError::parse(file, entity(), format!("bad face corner {tok:?}")))?;
                    let nv = mesh.positions.len() as i64;
                    let abs = if i > 0 { i - 1 } else { nv + i };
                    if i == 0 || abs < 0 || abs > u32::MAX as i64 {
                        return Err(TailorError::parse(
                            file,
                            entity(),
                            format!("face index {i} is invalid ({nv} vertices so far)"),
                        ));
                    }
                    corners.push(abs as u32);
                }
                if corners.len() < 3 {
                    return Err(TailorError::parse(file, entity(), format!("face with {} corners", corners.len())));
                }
                for k in 1..corners.len() - 1 {
                    mesh.triangles.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    mesh.validate(file)?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::data_dir;

    #[test]
    fn parses_polygons_and_index_forms() {
        let text = "# cube corner\nv 0 0 0\nv 1 0 0\nv 1 1 0 # comment\nv 0 1 0\nvn 0 0 1\n\
                    f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4//1 -2//1 -1//1\ng g\nusemtl m\n";
        let m = parse_obj(text, "t.obj").unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
    }

    #[test]
    fn errors_name_file_line_and_reason() {
        let e = parse_obj("v 0 0 0\nv 1 0\n", "bad.obj").unwrap_err();
        assert_eq!(e.to_string(), "bad.obj: line 2: vertex with fewer than 3 coordinates");
        let e = parse_obj("v 0 0 0\nf 1 2 x\n", "bad.obj").unwrap_err();
        assert!(e.to_string().starts_with("bad.obj: line 2: bad face corner"), "{e}");
        let e = parse_obj("v 0 0 0\nf 1 2 3\n", "bad.obj").unwrap_err();
        assert!(matches!(e, TailorError::Parse { ref entity, .. } if entity == "triangle 0"), "{e}");
        let e = parse_obj("v 0 0 0\nf -2 1 1\n", "bad.obj").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        let e = read_obj("/nonexistent/x.obj").unwrap_err();
        assert!(matches!(e, TailorError::Io { .. }), "{e}");
    }

    #[test]
    fn reads_the_garmentcode_body() {
        let Some(dir) = data_dir() else { return };
        let path = dir.join("bodies/garmentcode-mean-all/mean_all.obj");
        if !path.exists() {
            return;
        }
        let m = read_obj(&path).unwrap();
        assert_eq!(m.positions.len(), 23_752);
        assert_eq!(m.triangles.len(), 47_500);
        let (lo, hi) = m.bounds().unwrap();
        let height = hi[1] - lo[1];
        assert!((height - 1.72).abs() < 0.02, "height {height}");
    }
}
