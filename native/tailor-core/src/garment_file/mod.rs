//! The versioned garment file: everything needed to rebuild a sewn garment.
//!
//! A garment is saved as two files side by side: `NAME.json`, a readable manifest (format
//! name, version, pieces with their source outline, resolution, placement and bend, the
//! resolution-independent seams, named settings), and `NAME.bin`, a binary sidecar holding the
//! large per-particle arrays the manifest points into (see [`codec`]). Meshes are not stored:
//! triangulation is deterministic, so a piece's source and options rebuild its mesh, and seams
//! are stored by rest positions so they survive a change of resolution.
//!
//! Versioning: the manifest carries `version`; this build writes [`VERSION`] and reads any
//! version from 1 to [`VERSION`], refusing newer files with [`TailorError::Unsupported`].

pub mod codec;
mod model;

pub use codec::{decode, encode, FORMAT, VERSION};
pub use model::{Garment, GarmentPiece, ParticleParam, ParticleValues};

use std::path::{Path, PathBuf};

use crate::error::{Result, TailorError};

/// The sidecar path that goes with a manifest path (`x.json` → `x.bin`, otherwise `x` → `x.bin`).
pub fn sidecar_path(manifest: &Path) -> PathBuf {
    match manifest.extension() {
        Some(e) if e == "json" => manifest.with_extension("bin"),
        _ => {
            let mut s = manifest.as_os_str().to_owned();
            s.push(".bin");
            PathBuf::from(s)
        }
    }
}

/// Writes `garment` to `manifest` and its sidecar (see [`sidecar_path`]).
pub fn save(garment: &Garment, manifest: &Path) -> Result<()> {
    let bin_path = sidecar_path(manifest);
    let bin_name = bin_path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let (json, bin) = encode(garment, &bin_name)?;
    // Sidecar first: a manifest on disk always points at a complete sidecar.
    std::fs::write(&bin_path, bin).map_err(|e| TailorError::io(bin_path.display().to_string(), e))?;
    std::fs::write(manifest, json).map_err(|e| TailorError::io(manifest.display().to_string(), e))
}

/// Reads a garment saved by [`save`].
pub fn load(manifest: &Path) -> Result<Garment> {
    let label = manifest.display().to_string();
    let json = std::fs::read_to_string(manifest).map_err(|e| TailorError::io(&label, e))?;
    let name = codec::sidecar_name(&json, &label)?;
    let bin_path = manifest.parent().unwrap_or(Path::new("")).join(name);
    let bin = std::fs::read(&bin_path).map_err(|e| TailorError::io(bin_path.display().to_string(), e))?;
    decode(&json, &bin, &label)
}
