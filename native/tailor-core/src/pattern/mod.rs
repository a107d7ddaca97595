//! 2D sewing patterns: pieces as closed outlines in metres, read from pattern files.
//!
//! The readers (DXF, SVG, GarmentCode JSON) each produce a [`Pattern`]; triangulation and
//! seams work on [`Piece`]s and know nothing of the file they came from. [`read_pattern`] picks
//! the reader from the extension, or from the content when the extension says nothing.

pub mod cut;
pub mod dxf;
pub mod flatten;
pub mod garmentcode;
pub mod outline;
pub mod svg;
mod types;
pub mod unfold;
mod units;

pub use types::*;
pub use units::Units;

use crate::error::{Result, TailorError};
use std::path::Path;

/// Largest pattern file accepted; real ones are well under a few MB.
const MAX_FILE_BYTES: u64 = 256 << 20;

/// How to read a pattern file.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOptions {
    /// Size to import from a graded file; `None` = the sample size (see [`dxf::aama`]).
    pub size: Option<String>,
    /// Units to use instead of those the file declares: DXF coordinates, the SVG user unit,
    /// GarmentCode vertex coordinates.
    pub units_override: Option<Units>,
    /// Curve flattening chord tolerance in metres.
    pub tolerance_m: f64,
    /// Mirror a piece drawn as a half across its mirror line (a piece cut on the fold; AAMA
    /// layer 6) into the whole piece ([`unfold`]). Default true.
    pub unfold: bool,
    /// Import each piece as many times as the file says to cut it (AAMA `Quantity:`): a pair
    /// as the piece and its mirror image, a piece cut 0 times left out ([`cut`]). Default true;
    /// false imports every piece once, as drawn.
    pub quantities: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions { size: None, units_override: None, tolerance_m: 0.0005, unfold: true, quantities: true }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Dxf,
    Svg,
    GarmentCode,
}

fn sniff(path: &Path, bytes: &[u8]) -> Option<Format> {
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("dxf") => return Some(Format::Dxf),
        Some("svg") => return Some(Format::Svg),
        Some("json") => return Some(Format::GarmentCode),
        _ => {}
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    let t = head.trim_start_matches('\u{feff}').trim_start();
    if t.starts_with('{') {
        Some(Format::GarmentCode)
    } else if t.starts_with('<') && head.contains("<svg") {
        Some(Format::Svg)
    } else if t.starts_with('0') || bytes.starts_with(b"AutoCAD Binary DXF") {
        Some(Format::Dxf)
    } else {
        None
    }
}

fn load(path: &Path) -> Result<(String, Vec<u8>)> {
    let file = path.display().to_string();
    let bytes = crate::files::read_input(path, MAX_FILE_BYTES)?;
    Ok((file, bytes))
}

fn check_options(options: &ReadOptions) -> Result<()> {
    // Below a micrometre the segment caps in `flatten` would decide the result, not the user.
    if !(options.tolerance_m.is_finite() && options.tolerance_m >= 1e-6 && options.tolerance_m <= 0.1) {
        return Err(TailorError::setting("tolerance_m", options.tolerance_m, "must be between 1e-6 and 0.1 metres"));
    }
    Ok(())
}

/// Reads a pattern from in-memory bytes; `path` names the file in errors and picks the format.
pub fn read_pattern_bytes(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<Pattern> {
    check_options(options)?;
    let file = path.display().to_string();
    match sniff(path, bytes) {
        Some(Format::Dxf) => dxf::read(&file, bytes, options),
        Some(Format::Svg) => svg::read(&file, bytes, options),
        Some(Format::GarmentCode) => garmentcode::read(&file, bytes, options),
        None => Err(TailorError::Unsupported {
            file,
            entity: "file".into(),
            reason: "not a DXF, SVG or GarmentCode JSON pattern".into(),
        }),
    }
}

/// Reads the pattern file at `path` (DXF, SVG or GarmentCode JSON) into metres.
pub fn read_pattern(path: &Path, options: &ReadOptions) -> Result<Pattern> {
    let (_, bytes) = load(path)?;
    read_pattern_bytes(path, &bytes, options)
}

/// The sizes a graded pattern file offers, in file order (empty when it is not graded).
pub fn list_sizes(path: &Path) -> Result<Vec<String>> {
    let (file, bytes) = load(path)?;
    match sniff(path, &bytes) {
        Some(Format::Dxf) => dxf::sizes(&file, &bytes),
        Some(_) => Ok(Vec::new()),
        None => Err(TailorError::Unsupported {
            file,
            entity: "file".into(),
            reason: "not a DXF, SVG or GarmentCode JSON pattern".into(),
        }),
    }
}
