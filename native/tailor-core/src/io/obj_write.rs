//! Wavefront OBJ writer: one triangle mesh per file, with texture coordinates per face corner
//! when given (an OBJ sequence, one file a frame, is what every DCC imports without a plug-in).
//!
//! `v x y z` per vertex, then `vt u v` per corner (a seam's two sides keep their own UVs, so
//! corners, not vertices, carry them), then `f a/ta b/tb c/tc` (1-based). Written to a
//! temporary file beside the target and renamed over it: a reader never sees half a file.
//! Floats are written with Rust's shortest round-trip formatting, so reading the file back gives
//! the very `f32` values written.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Result, TailorError};

/// Writes `positions` and `triangles` (and `corner_uvs`, one `[u, v]` per triangle corner in
/// triangle order, when given) to `path` atomically.
pub fn write_obj(
    path: impl AsRef<Path>,
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    corner_uvs: Option<&[[f32; 2]]>,
) -> Result<()> {
    let path = path.as_ref();
    let name = path.display().to_string();
    if let Some(&t) = triangles.iter().flatten().find(|&&v| v as usize >= positions.len()) {
        return Err(TailorError::index("OBJ triangle vertex", t as i64, positions.len(), "vertices"));
    }
    if let Some(uv) = corner_uvs {
        if uv.len() != 3 * triangles.len() {
            return Err(TailorError::shape(
                &name,
                format!("{} texture coordinates for {} triangle corners", uv.len(), 3 * triangles.len()),
            ));
        }
    }
    let file_name =
        path.file_name().ok_or_else(|| TailorError::Io { path: name.clone(), reason: "not a file path".into() })?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(file_name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    let temp = path.with_file_name(temp_name);
    let io = |e: std::io::Error| TailorError::io(temp.display().to_string(), e);
    let written = (|| {
        let mut w = BufWriter::new(File::create(&temp).map_err(io)?);
        writeln!(w, "# Tailor: {} vertices, {} triangles", positions.len(), triangles.len()).map_err(io)?;
        for p in positions {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2]).map_err(io)?;
        }
        if let Some(uv) = corner_uvs {
            for t in uv {
                writeln!(w, "vt {} {}", t[0], t[1]).map_err(io)?;
            }
        }
        for (k, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|v| v + 1);
            if corner_uvs.is_some() {
                let u = 3 * k as u32 + 1;
                writeln!(w, "f {a}/{u} {b}/{} {c}/{}", u + 1, u + 2).map_err(io)?;
            } else {
                writeln!(w, "f {a} {b} {c}").map_err(io)?;
            }
        }
        w.into_inner().map_err(|e| io(e.into_error()))?.sync_all().map_err(io)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temp);
        return Err(e);
    }
    std::fs::rename(&temp, path).map_err(|e| TailorError::io(name, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::obj::read_obj;
    use crate::test_util::temp_dir;

    /// The file reads back (by our reader) as the positions and triangles written, to the bit;
    /// its `vt` lines are the corners' UVs in order; bad input is refused and writes nothing.
    #[test]
    fn writes_what_reads_back() {
        let dir = temp_dir("obj-write");
        let path = dir.join("frame.0001.obj");
        let v = [[0.1f32, -2.5e-7, 3.0], [1.0 / 3.0, 0.0, 0.0], [0.0, 1.0, 1e-30], [7.0, 8.0, 9.0]];
        let t = [[0u32, 1, 2], [2, 1, 3]];
        let uv: Vec<[f32; 2]> = (0..6).map(|k| [k as f32 * 0.1, 1.0 - k as f32 * 0.1]).collect();
        write_obj(&path, &v, &t, Some(&uv)).unwrap();
        let m = read_obj(&path).unwrap();
        assert_eq!(m.positions, v.to_vec());
        assert_eq!(m.triangles, t.to_vec());
        let text = std::fs::read_to_string(&path).unwrap();
        let vts: Vec<&str> = text.lines().filter(|l| l.starts_with("vt ")).collect();
        assert_eq!(vts.len(), 6);
        assert_eq!(vts[4], format!("vt {} {}", uv[4][0], uv[4][1]));
        assert!(text.contains("f 3/4 2/5 4/6"), "{text}");
        write_obj(&path, &v, &t, None).unwrap();
        assert!(!std::fs::read_to_string(&path).unwrap().contains("vt "));
        assert!(write_obj(dir.join("bad.obj"), &v, &[[0, 1, 4]], None).is_err());
        assert!(write_obj(dir.join("bad.obj"), &v, &t, Some(&uv[..5])).is_err());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
