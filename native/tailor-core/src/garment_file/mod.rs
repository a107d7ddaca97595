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
//! Version 2 added the typed `setup` ([`setup`]) and three-float arrays (`f32x3`, the placed
//! positions); a version-1 file's setup, kept in its settings under `tailor_sample`, is read
//! into the typed setup ([`migrate`]).

pub mod codec;
mod migrate;
mod model;
pub mod setup;

pub use codec::{decode, encode, FORMAT, VERSION};
pub use model::{Garment, GarmentPiece, ParticleParam, ParticleValues};
pub use setup::GarmentSetup;

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

/// Writes `garment` to `manifest` and its sidecar (see [`sidecar_path`]). The manifest is the
/// file the caller named; the sidecar is not, so an existing file there that is not a Tailor
/// sidecar (`import x.svg -o notes.json` beside an unrelated `notes.bin`) is left alone and
/// the save refused.
pub fn save(garment: &Garment, manifest: &Path) -> Result<()> {
    let bin_path = sidecar_path(manifest);
    let bin_name = bin_path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    check_sidecar_replaceable(&bin_path)?;
    let (json, bin) = encode(garment, &bin_name)?;
    // Sidecar first: a manifest on disk always points at a complete sidecar.
    std::fs::write(&bin_path, bin).map_err(|e| TailorError::io(bin_path.display().to_string(), e))?;
    std::fs::write(manifest, json).map_err(|e| TailorError::io(manifest.display().to_string(), e))
}

/// Whether the file at `bin_path` may be replaced by a sidecar: it does not exist, or it is a
/// Tailor sidecar (starts with the sidecar's magic bytes).
fn check_sidecar_replaceable(bin_path: &Path) -> Result<()> {
    let meta = match std::fs::symlink_metadata(bin_path) {
        Ok(m) => m,
        Err(_) => return Ok(()),
    };
    let mut head = [0u8; 8];
    let ours = meta.is_file()
        && std::fs::File::open(bin_path).and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head)).is_ok()
        && head == *codec::MAGIC;
    if ours {
        Ok(())
    } else {
        Err(TailorError::Io {
            path: bin_path.display().to_string(),
            reason: "exists and is not a Tailor garment sidecar; refusing to replace it (choose another name)".into(),
        })
    }
}

/// The largest manifest [`load`] reads; manifests of real garments are a few megabytes.
const MAX_MANIFEST_BYTES: u64 = 256 << 20;

/// Reads a garment saved by [`save`]. The sidecar must be a regular file in the manifest's
/// folder (no symbolic link out of it) of exactly the size the manifest records, checked
/// before it is read.
pub fn load(manifest: &Path) -> Result<Garment> {
    let label = manifest.display().to_string();
    let json = crate::files::read_input_text(manifest, MAX_MANIFEST_BYTES)?;
    let (name, bytes) = codec::sidecar_ref(&json, &label)?;
    let limit = bytes.min(crate::files::MAX_INPUT_BYTES);
    let bin = crate::files::read_beside(manifest, &name, &format!("sidecar {name}"), limit).map_err(|e| match e {
        TailorError::Io { path, reason } if reason.contains("larger than") => TailorError::parse(
            &label,
            format!("sidecar {name}"),
            format!("{path} is larger than the {bytes} bytes the manifest records"),
        ),
        e => e,
    })?;
    decode(&json, &bin, &label)
}
