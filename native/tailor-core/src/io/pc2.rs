//! Point Cache 2 (`.pc2`, Blender's and 3ds Max's vertex animation cache).
//!
//! Layout, little-endian: `char[12] "POINTCACHE2\0"`, `i32 version = 1`, `i32 num_points`,
//! `f32 start_frame`, `f32 sample_rate` (frames between samples), `i32 num_samples`, then
//! `num_samples × num_points × (f32 x, y, z)`.
//!
//! Writing is atomic: the cache is written to a temporary file next to the target and renamed
//! over it only once complete, so a reader (Blender's Mesh Cache modifier) never sees a
//! half-written file and a crash leaves the previous cache intact.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::read_bytes;
use crate::error::{Result, TailorError};

const MAGIC: &[u8; 12] = b"POINTCACHE2\0";
const HEADER_LEN: usize = 32;

/// A whole point cache in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCache {
    pub start_frame: f32,
    pub sample_rate: f32,
    pub num_points: usize,
    /// One `Vec` of `num_points` positions per sample.
    pub frames: Vec<Vec<[f32; 3]>>,
}

/// Reads a `.pc2` file, checking the header against the file length.
pub fn read_pc2(path: impl AsRef<Path>) -> Result<PointCache> {
    let path = path.as_ref();
    parse_pc2(&read_bytes(path)?, &path.display().to_string())
}

/// Parses `.pc2` bytes; `file` names the source in errors.
pub fn parse_pc2(b: &[u8], file: &str) -> Result<PointCache> {
    let err = |reason: String| TailorError::parse(file, "header", reason);
    if b.len() < HEADER_LEN || &b[..12] != MAGIC {
        return Err(err("not a Point Cache 2 file (no POINTCACHE2 magic)".into()));
    }
    let i32_at = |o: usize| i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    let f32_at = |o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    let version = i32_at(12);
    if version != 1 {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: "header".into(),
            reason: format!("version {version}"),
        });
    }
    let (num_points, num_samples) = (i32_at(16), i32_at(28));
    if num_points < 0 || num_samples < 0 {
        return Err(err(format!("negative count: {num_points} points, {num_samples} samples")));
    }
    let (np, ns) = (num_points as usize, num_samples as usize);
    let expected = HEADER_LEN as u128 + 12 * np as u128 * ns as u128;
    // Up to one frame past the count is a frame that a stream (`pc2_stream.rs`) was appending
    // when its writer stopped (killed, crashed): the samples counted are whole, and read.
    let (len, frame) = (b.len() as u128, 12 * np as u128);
    if len < expected || len > expected + frame {
        return Err(err(format!("{np} points × {ns} samples need {expected} bytes but the file has {}", b.len())));
    }
    let b = &b[..expected as usize];
    let floats: Vec<f32> =
        b[HEADER_LEN..].chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let frames = (0..ns)
        .map(|s| {
            (0..np)
                .map(|p| {
                    let o = 3 * (s * np + p);
                    [floats[o], floats[o + 1], floats[o + 2]]
                })
                .collect()
        })
        .collect();
    Ok(PointCache { start_frame: f32_at(20), sample_rate: f32_at(24), num_points: np, frames })
}

/// Writes a whole cache atomically.
pub fn write_pc2(path: impl AsRef<Path>, cache: &PointCache) -> Result<()> {
    let mut w = Pc2Writer::create(path, cache.num_points, cache.start_frame, cache.sample_rate)?;
    for f in &cache.frames {
        w.push_frame(f)?;
    }
    w.finish()
}

/// Streams frames to a cache as they are simulated; the file appears (atomically) on
/// [`Pc2Writer::finish`]. Dropping the writer without finishing removes the temporary file.
#[derive(Debug)]
pub struct Pc2Writer {
    target: PathBuf,
    temp: PathBuf,
    out: Option<BufWriter<File>>,
    num_points: usize,
    num_samples: usize,
}

impl Pc2Writer {
    /// Starts a cache of `num_points` points; `sample_rate` is the frame step between samples.
    pub fn create(path: impl AsRef<Path>, num_points: usize, start_frame: f32, sample_rate: f32) -> Result<Self> {
        let target = path.as_ref().to_path_buf();
        let name = target.display().to_string();
        if num_points > i32::MAX as usize {
            return Err(TailorError::shape(name, format!("{num_points} points do not fit a PC2 header")));
        }
        let file_name = target
            .file_name()
            .ok_or_else(|| TailorError::Io { path: name.clone(), reason: "not a file path".into() })?;
        let mut temp_name = std::ffi::OsString::from(".");
        temp_name.push(file_name);
        temp_name.push(format!(".{}.tmp", std::process::id()));
        let temp = target.with_file_name(temp_name);
        let file = File::create(&temp).map_err(|e| TailorError::io(temp.display().to_string(), e))?;
        let mut w = Self { target, temp, out: Some(BufWriter::new(file)), num_points, num_samples: 0 };
        let mut header = Vec::with_capacity(HEADER_LEN);
        header.extend_from_slice(MAGIC);
        header.extend(1i32.to_le_bytes());
        header.extend((num_points as i32).to_le_bytes());
        header.extend(start_frame.to_le_bytes());
        header.extend(sample_rate.to_le_bytes());
        header.extend(0i32.to_le_bytes()); // patched by finish()
        w.write(&header)?;
        Ok(w)
    }

    /// Appends one sample.
    pub fn push_frame(&mut self, points: &[[f32; 3]]) -> Result<()> {
        self.check_len(points.len())?;
        for p in points {
            self.write(&xyz_bytes(p[0], p[1], p[2]))?;
        }
        self.num_samples += 1;
        Ok(())
    }

    /// Appends one sample given as structure-of-arrays (the solver's layout).
    pub fn push_frame_soa(&mut self, x: &[f32], y: &[f32], z: &[f32]) -> Result<()> {
        self.check_len(x.len())?;
        self.check_len(y.len())?;
        self.check_len(z.len())?;
        for i in 0..x.len() {
            self.write(&xyz_bytes(x[i], y[i], z[i]))?;
        }
        self.num_samples += 1;
        Ok(())
    }

    /// Samples written so far.
    pub fn num_samples(&self) -> usize {
        self.num_samples
    }

    /// Patches the sample count, flushes to disk and renames the file into place.
    pub fn finish(mut self) -> Result<()> {
        let temp_name = self.temp.display().to_string();
        let io = |e: std::io::Error| TailorError::io(temp_name.clone(), e);
        let mut file =
            self.out.take().expect("writer present until finish").into_inner().map_err(|e| io(e.into_error()))?;
        file.seek(SeekFrom::Start(28)).map_err(io)?;
        file.write_all(&(self.num_samples as i32).to_le_bytes()).map_err(io)?;
        file.sync_all().map_err(io)?;
        drop(file);
        std::fs::rename(&self.temp, &self.target).map_err(|e| TailorError::io(self.target.display().to_string(), e))
    }

    fn check_len(&self, n: usize) -> Result<()> {
        if n != self.num_points {
            return Err(TailorError::shape(
                self.target.display().to_string(),
                format!("frame {} has {n} points, the cache {}", self.num_samples, self.num_points),
            ));
        }
        Ok(())
    }

    fn write(&mut self, bytes: &[u8]) -> Result<()> {
        let out = self.out.as_mut().expect("writer present until finish");
        out.write_all(bytes).map_err(|e| TailorError::io(self.temp.display().to_string(), e))
    }
}

fn xyz_bytes(x: f32, y: f32, z: f32) -> [u8; 12] {
    let mut b = [0u8; 12];
    b[..4].copy_from_slice(&x.to_le_bytes());
    b[4..8].copy_from_slice(&y.to_le_bytes());
    b[8..].copy_from_slice(&z.to_le_bytes());
    b
}

impl Drop for Pc2Writer {
    fn drop(&mut self) {
        if self.out.take().is_some() {
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::temp_dir;

    #[test]
    fn round_trip_and_atomic_replacement() {
        let dir = temp_dir("pc2");
        let path = dir.join("cloth.pc2");
        let cache = PointCache {
            start_frame: 1.0,
            sample_rate: 1.0,
            num_points: 3,
            frames: (0..4).map(|f| (0..3).map(|p| [f as f32, p as f32, 0.5 * (f * p) as f32]).collect()).collect(),
        };
        write_pc2(&path, &cache).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), 32 + 4 * 3 * 12);
        assert_eq!(read_pc2(&path).unwrap(), cache);

        // A writer dropped half-way leaves the previous cache untouched and no temp file.
        let mut w = Pc2Writer::create(&path, 3, 0.0, 0.5).unwrap();
        w.push_frame_soa(&[9.0; 3], &[9.0; 3], &[9.0; 3]).unwrap();
        assert!(w.push_frame(&[[0.0; 3]; 2]).is_err());
        drop(w);
        assert_eq!(read_pc2(&path).unwrap(), cache);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);

        let whole = std::fs::read(&path).unwrap();
        let mut bytes = whole.clone();
        bytes.pop();
        let e = parse_pc2(&bytes, "cut.pc2").unwrap_err();
        assert!(e.to_string().starts_with("cut.pc2: header: 3 points × 4 samples need"), "{e}");
        // A frame being appended when its writer stopped (up to one frame past the count) is
        // not read; more than that is an error.
        let mut bytes = whole;
        bytes.extend([1u8; 36]);
        assert_eq!(parse_pc2(&bytes, "appended.pc2").unwrap(), cache);
        bytes.push(1);
        assert!(parse_pc2(&bytes, "long.pc2").is_err());
        let e = parse_pc2(b"POINTCACHE3\0", "x.pc2").unwrap_err();
        assert!(e.to_string().contains("magic"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
