//! Encoding: a JSON manifest plus a binary sidecar for the per-particle arrays.
//!
//! Sidecar layout: the 8-byte magic `TLRBIN\0\x01`, then each array little-endian (`f32`,
//! `i32`, or `u8` 0/1 for booleans), each starting at a multiple of 8 bytes. The manifest
//! records every array's dtype, byte offset and element count, and the sidecar's size and
//! FNV-1a 64-bit hash, so that a sidecar from another save is detected rather than misread.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::model::{Garment, GarmentPiece, ParticleParam, ParticleValues};
use super::setup::GarmentSetup;
use crate::error::{Result, TailorError};
use crate::seam::Seam;

/// The `format` field of every garment manifest.
pub const FORMAT: &str = "tailor-garment";
/// The version this build writes; it reads this version and older.
pub const VERSION: u32 = 2;
pub(crate) const MAGIC: &[u8; 8] = b"TLRBIN\0\x01";

#[derive(Serialize, Deserialize)]
struct Manifest {
    format: String,
    version: u32,
    sidecar: SidecarRef,
    pieces: Vec<GarmentPiece>,
    seams: Vec<Seam>,
    /// Absent in version 1 (its setup is in `settings`, see `migrate`).
    #[serde(default)]
    setup: Option<GarmentSetup>,
    particle_params: Vec<ArrayRef>,
    settings: BTreeMap<String, serde_json::Value>,
}

#[derive(Serialize, Deserialize)]
struct SidecarRef {
    file: String,
    bytes: u64,
    fnv1a64: String,
}

#[derive(Serialize, Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Dtype {
    F32,
    I32,
    Bool,
    /// Three little-endian f32 per element (`count` elements of 12 bytes).
    F32x3,
}

#[derive(Serialize, Deserialize)]
struct ArrayRef {
    name: String,
    piece: usize,
    dtype: Dtype,
    offset: u64,
    count: u64,
}

/// FNV-1a, 64 bit: a cheap fingerprint to pair a manifest with its sidecar.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// The manifest text and sidecar bytes of `garment`; `sidecar_file` is the sidecar's file name
/// as the manifest will refer to it.
pub fn encode(garment: &Garment, sidecar_file: &str) -> Result<(String, Vec<u8>)> {
    let mut bin = MAGIC.to_vec();
    let mut refs = Vec::with_capacity(garment.particle_params.len());
    for p in &garment.particle_params {
        while bin.len() % 8 != 0 {
            bin.push(0);
        }
        let offset = bin.len() as u64;
        let dtype = match &p.values {
            ParticleValues::F32(v) => {
                v.iter().for_each(|x| bin.extend_from_slice(&x.to_le_bytes()));
                Dtype::F32
            }
            ParticleValues::I32(v) => {
                v.iter().for_each(|x| bin.extend_from_slice(&x.to_le_bytes()));
                Dtype::I32
            }
            ParticleValues::Bool(v) => {
                bin.extend(v.iter().map(|&b| b as u8));
                Dtype::Bool
            }
            ParticleValues::Vec3(v) => {
                v.iter().flatten().for_each(|x| bin.extend_from_slice(&x.to_le_bytes()));
                Dtype::F32x3
            }
        };
        refs.push(ArrayRef { name: p.name.clone(), piece: p.piece, dtype, offset, count: p.values.len() as u64 });
    }
    let manifest = Manifest {
        format: FORMAT.into(),
        version: VERSION,
        sidecar: SidecarRef {
            file: sidecar_file.into(),
            bytes: bin.len() as u64,
            fnv1a64: format!("{:016x}", fnv1a64(&bin)),
        },
        pieces: garment.pieces.clone(),
        seams: garment.seams.clone(),
        setup: Some(garment.setup.clone()),
        particle_params: refs,
        settings: garment.settings.clone(),
    };
    let json = serde_json::to_string_pretty(&manifest)
        .map_err(|e| TailorError::parse(sidecar_file, "manifest", format!("cannot encode: {e}")))?;
    Ok((json, bin))
}

/// The sidecar file name a manifest names (checked to be a bare file name), without reading it.
pub fn sidecar_name(json: &str, file: &str) -> Result<String> {
    Ok(sidecar_ref(json, file)?.0)
}

/// The sidecar file name a manifest names (checked to be a bare file name) and the size it
/// records, so that a reader can refuse a bigger file before reading it.
pub fn sidecar_ref(json: &str, file: &str) -> Result<(String, u64)> {
    let m = parse_manifest(json, file)?;
    let name = m.sidecar.file;
    if name.is_empty() || name.contains(['/', '\\']) || name == "." || name == ".." {
        return Err(TailorError::parse(file, "sidecar", format!("{name:?} is not a plain file name")));
    }
    Ok((name, m.sidecar.bytes))
}

fn parse_manifest(json: &str, file: &str) -> Result<Manifest> {
    let head: serde_json::Value =
        serde_json::from_str(json).map_err(|e| TailorError::parse(file, "manifest", e.to_string()))?;
    if head.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
        return Err(TailorError::parse(file, "format", format!("not a Tailor garment (expected \"{FORMAT}\")")));
    }
    let version = head.get("version").and_then(|v| v.as_u64()).unwrap_or(0);
    if version == 0 || version > VERSION as u64 {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: "version".into(),
            reason: format!("garment file version {version}; this build reads versions 1 to {VERSION}"),
        });
    }
    serde_json::from_value(head).map_err(|e| TailorError::parse(file, "manifest", e.to_string()))
}

/// The garment of a manifest and its sidecar bytes; `file` names the manifest in errors.
pub fn decode(json: &str, bin: &[u8], file: &str) -> Result<Garment> {
    let m = parse_manifest(json, file)?;
    let side = &m.sidecar.file;
    if bin.len() as u64 != m.sidecar.bytes || format!("{:016x}", fnv1a64(bin)) != m.sidecar.fnv1a64 {
        return Err(TailorError::parse(
            file,
            format!("sidecar {side}"),
            "does not match the manifest (size or hash differ: saved separately or damaged)",
        ));
    }
    if bin.len() < MAGIC.len() || &bin[..MAGIC.len()] != MAGIC {
        return Err(TailorError::parse(file, format!("sidecar {side}"), "bad magic bytes"));
    }
    let mut params = Vec::with_capacity(m.particle_params.len());
    for r in &m.particle_params {
        let entity = format!("particle parameter {}", r.name);
        if r.piece >= m.pieces.len() {
            return Err(TailorError::parse(file, entity, format!("piece {} of {}", r.piece, m.pieces.len())));
        }
        let width = match r.dtype {
            Dtype::F32 | Dtype::I32 => 4,
            Dtype::Bool => 1,
            Dtype::F32x3 => 12,
        };
        let end = r.count.checked_mul(width).and_then(|n| n.checked_add(r.offset));
        let range = match end {
            Some(end) if r.offset % 8 == 0 && r.offset >= MAGIC.len() as u64 && end <= bin.len() as u64 => {
                r.offset as usize..end as usize
            }
            _ => return Err(TailorError::parse(file, entity, "array lies outside the sidecar or is misaligned")),
        };
        let bytes = &bin[range];
        let word = |c: &[u8]| [c[0], c[1], c[2], c[3]];
        let values = match r.dtype {
            Dtype::F32 => ParticleValues::F32(bytes.chunks_exact(4).map(|c| f32::from_le_bytes(word(c))).collect()),
            Dtype::I32 => ParticleValues::I32(bytes.chunks_exact(4).map(|c| i32::from_le_bytes(word(c))).collect()),
            Dtype::F32x3 => ParticleValues::Vec3(
                bytes.chunks_exact(12).map(|c| [0, 4, 8].map(|k| f32::from_le_bytes(word(&c[k..k + 4])))).collect(),
            ),
            Dtype::Bool => {
                if let Some(i) = bytes.iter().position(|&b| b > 1) {
                    return Err(TailorError::parse(file, entity, format!("boolean {i} is {}", bytes[i])));
                }
                ParticleValues::Bool(bytes.iter().map(|&b| b == 1).collect())
            }
        };
        params.push(ParticleParam { name: r.name.clone(), piece: r.piece, values });
    }
    let mut settings = m.settings;
    let setup = match m.setup {
        Some(setup) => setup,
        None => super::migrate::setup_of_v1(&mut settings, file)?,
    };
    setup.validate(m.pieces.len()).map_err(|e| TailorError::parse(file, "setup", e.to_string()))?;
    Ok(Garment { pieces: m.pieces, seams: m.seams, setup, particle_params: params, settings })
}
