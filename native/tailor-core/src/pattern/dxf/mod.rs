//! DXF pattern files: a group-code [`tokenizer`], the section/block/entity [`document`],
//! entity [`geometry`] flattening, and two readers: [`aama`] for pattern-CAD exports (one
//! block per piece, meaning carried by layers) and [`plain`] for ordinary drawings.

pub mod aama;
pub mod document;
pub mod geometry;
pub mod plain;
pub mod tokenizer;

use super::{Pattern, ReadOptions};
use crate::error::{Result, TailorError};

/// Groups, refused unless the file ends with its `0 EOF` group: the units of an AAMA file sit
/// in a TEXT near the end of ENTITIES, so a truncated file read without this check came out in
/// inches, 25.4 times too big, with no error.
fn parse(file: &str, bytes: &[u8]) -> Result<document::Document> {
    let groups = tokenizer::tokenize(file, bytes)?;
    match groups.last() {
        Some(g) if g.code == 0 && g.value.eq_ignore_ascii_case("EOF") => Ok(document::build(&groups)),
        last => Err(TailorError::parse(
            file,
            "file",
            format!(
                "incomplete: no EOF group at the end (the file stops at line {}); it was cut short or is not a DXF",
                last.map_or(0, |g| g.line + 1)
            ),
        )),
    }
}

/// Reads a DXF pattern, choosing the AAMA/ASTM reader when blocks carry piece annotations.
pub fn read(file: &str, bytes: &[u8], opts: &ReadOptions) -> Result<Pattern> {
    let doc = parse(file, bytes)?;
    if aama::detect(&doc) {
        aama::read(file, &doc, opts)
    } else {
        plain::read(file, &doc, opts)
    }
}

/// The sizes a graded DXF offers (empty for a plain drawing).
pub fn sizes(file: &str, bytes: &[u8]) -> Result<Vec<String>> {
    let doc = parse(file, bytes)?;
    Ok(if aama::detect(&doc) { aama::sizes(&doc) } else { Vec::new() })
}
