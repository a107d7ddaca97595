//! A PC2 cache written frame by frame into its own path, a valid cache after every frame.
//!
//! [`super::pc2::Pc2Writer`] writes beside the target and renames at the end: a reader never
//! sees half a file, but a bake that crashes or is killed loses every frame. A long bake (the
//! command line's, a render farm's) wants the opposite: every frame solved kept on disk as it
//! comes, so that a crash loses at most the frame in progress and the bake can resume. So each
//! frame's samples are written after the last one and only then is the header's sample count
//! raised to include it: at any moment the header counts whole frames only. A crash inside a
//! frame leaves up to one frame of bytes past the count, which readers skip
//! ([`super::pc2::read_pc2`] too) and [`Pc2Stream::resume`] cuts off. The data is flushed to the
//! operating system every frame (it survives the process, not a power cut: no `fsync` per
//! frame, which would cost more than a small garment's solve).

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::error::{Result, TailorError};

const MAGIC: &[u8; 12] = b"POINTCACHE2\0";
const HEADER_LEN: u64 = 32;
/// Offset of the header's sample count.
const COUNT_AT: u64 = 28;

/// A cache being written frame by frame (see the module docs).
#[derive(Debug)]
pub struct Pc2Stream {
    path: PathBuf,
    file: File,
    num_points: usize,
    num_samples: usize,
    start_frame: f32,
    sample_rate: f32,
}

impl Pc2Stream {
    /// A new cache of `num_points` points at `path` (replacing any file there), no frame yet.
    pub fn create(path: impl AsRef<Path>, num_points: usize, start_frame: f32, sample_rate: f32) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        if num_points > (i32::MAX as usize) / 3 {
            return Err(TailorError::shape(
                path.display().to_string(),
                format!("{num_points} points do not fit a PC2"),
            ));
        }
        let mut file = File::create(&path).map_err(|e| TailorError::io(path.display().to_string(), e))?;
        let mut header = Vec::with_capacity(HEADER_LEN as usize);
        header.extend_from_slice(MAGIC);
        header.extend(1i32.to_le_bytes());
        header.extend((num_points as i32).to_le_bytes());
        header.extend(start_frame.to_le_bytes());
        header.extend(sample_rate.to_le_bytes());
        header.extend(0i32.to_le_bytes());
        file.write_all(&header).map_err(|e| TailorError::io(path.display().to_string(), e))?;
        Ok(Self { path, file, num_points, num_samples: 0, start_frame, sample_rate })
    }

    /// Goes on with the cache at `path`: its header must hold `num_points` points; of its
    /// whole frames the first `keep` are kept (all when None) and anything after them (later
    /// frames, a frame cut by a crash) is cut off.
    pub fn resume(path: impl AsRef<Path>, num_points: usize, keep: Option<usize>) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        let name = path.display().to_string();
        let io = |e: std::io::Error| TailorError::io(name.clone(), e);
        let mut file = OpenOptions::new().read(true).write(true).open(&path).map_err(io)?;
        let mut h = [0u8; HEADER_LEN as usize];
        file.read_exact(&mut h)
            .map_err(|_| TailorError::parse(&name, "header", "shorter than a PC2 header (32 bytes)"))?;
        let i32_at = |o: usize| i32::from_le_bytes([h[o], h[o + 1], h[o + 2], h[o + 3]]);
        let f32_at = |o: usize| f32::from_le_bytes([h[o], h[o + 1], h[o + 2], h[o + 3]]);
        if &h[..12] != MAGIC || i32_at(12) != 1 {
            return Err(TailorError::parse(&name, "header", "not a version-1 Point Cache 2 file"));
        }
        if i32_at(16) != num_points as i32 {
            return Err(TailorError::shape(
                &name,
                format!("the cache holds {} points, the garment has {num_points}", i32_at(16)),
            ));
        }
        let frame_bytes = 12 * num_points as u64;
        let len = file.metadata().map_err(io)?.len();
        // Whole frames on disk, never more than the header counts (a frame it does not count
        // was cut by a crash, or not finished).
        let on_disk = (len.saturating_sub(HEADER_LEN) / frame_bytes.max(1)) as usize;
        let counted = (i32_at(28).max(0) as usize).min(on_disk);
        let samples = keep.map_or(counted, |k| k.min(counted));
        file.set_len(HEADER_LEN + samples as u64 * frame_bytes).map_err(io)?;
        let mut s =
            Self { path, file, num_points, num_samples: samples, start_frame: f32_at(20), sample_rate: f32_at(24) };
        s.write_count()?;
        Ok(s)
    }

    /// Appends one frame, then counts it in the header.
    pub fn push_frame(&mut self, points: &[[f32; 3]]) -> Result<()> {
        if points.len() != self.num_points {
            return Err(TailorError::shape(
                self.path.display().to_string(),
                format!("frame {} has {} points, the cache {}", self.num_samples, points.len(), self.num_points),
            ));
        }
        let mut bytes = Vec::with_capacity(12 * points.len());
        for p in points {
            for c in p {
                bytes.extend(c.to_le_bytes());
            }
        }
        let at = HEADER_LEN + self.num_samples as u64 * 12 * self.num_points as u64;
        let name = self.path.display().to_string();
        self.file.seek(SeekFrom::Start(at)).map_err(|e| TailorError::io(name.clone(), e))?;
        self.file.write_all(&bytes).map_err(|e| TailorError::io(name, e))?;
        self.num_samples += 1;
        self.write_count()
    }

    fn write_count(&mut self) -> Result<()> {
        let name = self.path.display().to_string();
        let io = |e: std::io::Error| TailorError::io(name.clone(), e);
        self.file.seek(SeekFrom::Start(COUNT_AT)).map_err(io)?;
        self.file.write_all(&(self.num_samples as i32).to_le_bytes()).map_err(io)?;
        self.file.flush().map_err(io)
    }

    /// Frames in the cache.
    pub fn num_samples(&self) -> usize {
        self.num_samples
    }

    /// The header's start frame and sample rate.
    pub fn timing(&self) -> (f32, f32) {
        (self.start_frame, self.sample_rate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::pc2::read_pc2;
    use crate::test_util::temp_dir;

    /// After every frame the file is a valid cache of the frames so far; a frame cut by a
    /// crash (bytes past the count) is dropped by `resume`, which can also go back to an
    /// earlier frame; a cache of another point count is refused.
    #[test]
    fn valid_after_every_frame_and_resumable_after_a_cut() {
        let dir = temp_dir("pc2-stream");
        let path = dir.join("bake.pc2");
        let frame = |f: usize| -> Vec<[f32; 3]> { (0..4).map(|p| [f as f32, p as f32, 0.5]).collect() };
        let mut s = Pc2Stream::create(&path, 4, 1.0, 1.0).unwrap();
        assert_eq!(read_pc2(&path).unwrap().frames.len(), 0);
        for f in 0..3 {
            s.push_frame(&frame(f)).unwrap();
            let c = read_pc2(&path).unwrap();
            assert_eq!(c.frames.len(), f + 1);
            assert_eq!(c.frames[f], frame(f));
            assert_eq!((c.start_frame, c.sample_rate), (1.0, 1.0));
        }
        assert!(s.push_frame(&frame(0)[..3]).is_err());
        drop(s);
        // A crash half-way through frame 3: its first bytes are on disk, the count is 3.
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&[7u8; 20]).unwrap();
        drop(f);
        assert_eq!(read_pc2(&path).unwrap().frames.len(), 3);
        let mut s = Pc2Stream::resume(&path, 4, None).unwrap();
        assert_eq!(s.num_samples(), 3);
        s.push_frame(&frame(3)).unwrap();
        let c = read_pc2(&path).unwrap();
        assert_eq!(c.frames, (0..4).map(frame).collect::<Vec<_>>());
        let s = Pc2Stream::resume(&path, 4, Some(2)).unwrap();
        assert_eq!((s.num_samples(), s.timing()), (2, (1.0, 1.0)));
        assert_eq!(read_pc2(&path).unwrap().frames.len(), 2);
        let e = Pc2Stream::resume(&path, 5, None).unwrap_err();
        assert!(e.to_string().contains("holds 4 points"), "{e}");
        std::fs::write(dir.join("x.pc2"), b"POINTCACHE2").unwrap();
        assert!(Pc2Stream::resume(dir.join("x.pc2"), 4, None).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
