//! DXF pattern files: a group-code [`tokenizer`], the section/block/entity [`document`],
//! entity [`geometry`] flattening, and two readers: [`aama`] for pattern-CAD exports (one
//! block per piece, meaning carried by layers) and [`plain`] for ordinary drawings.

pub mod aama;
pub mod document;
pub mod geometry;
pub mod plain;
pub mod tokenizer;

use super::{Pattern, ReadOptions};
use crate::error::Result;

fn parse(file: &str, bytes: &[u8]) -> Result<document::Document> {
    Ok(document::build(&tokenizer::tokenize(file, bytes)?))
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
