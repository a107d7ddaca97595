//! DXF group-code tokenizer: the ASCII file is a flat list of (code, value) line pairs.
//!
//! Written by hand rather than taken from the `dxf` crate (0.6.2, evaluated on the AccuMark
//! and CLO test files): it reads the AccuMark files, but on CLO's R10 export it returns the
//! boundary POLYLINE's VERTEXes as loose entities with no polyline, and it costs minutes of
//! compile time (chrono, image, a code-generating build script). Pattern files use a tiny
//! ASCII subset that a page of code reads.

use crate::error::{Result, TailorError};

/// One group: its code, its value (trimmed) and the 1-based line of the code.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub code: i32,
    pub value: String,
    pub line: usize,
}

/// Splits `text` into groups. A code line that is not an integer is an error naming its line;
/// a dangling code at the very end (a truncated file) is dropped.
pub fn tokenize(file: &str, bytes: &[u8]) -> Result<Vec<Group>> {
    if bytes.starts_with(b"AutoCAD Binary DXF") {
        return Err(TailorError::Unsupported {
            file: file.into(),
            entity: "file".into(),
            reason: "binary DXF; export the pattern as ASCII DXF".into(),
        });
    }
    // Old exports are Latin-1 or the Windows code page; a lossy decode keeps piece names readable
    // enough and can never fail.
    let text = String::from_utf8_lossy(bytes);
    let mut lines = text.lines().enumerate();
    let mut groups = Vec::with_capacity(text.len() / 16);
    while let Some((i, code_line)) = lines.next() {
        let code_text = code_line.trim();
        if code_text.is_empty() && groups.is_empty() {
            continue;
        }
        let code: i32 = code_text.parse().map_err(|_| {
            TailorError::parse(
                file,
                format!("group code at line {}", i + 1),
                format!("expected an integer, found {code_text:?}"),
            )
        })?;
        let Some((_, value)) = lines.next() else { break };
        groups.push(Group { code, value: value.trim().to_string(), line: i + 1 });
    }
    Ok(groups)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_lines_and_reports_bad_codes() {
        let g = tokenize("t.dxf", b"  0\r\nSECTION\r\n  2\r\nHEADER\r\n  0").unwrap();
        assert_eq!(g.len(), 2);
        assert_eq!((g[1].code, g[1].value.as_str(), g[1].line), (2, "HEADER", 3));
        let e = tokenize("t.dxf", b"0\nSECTION\nxx\nfoo\n").unwrap_err().to_string();
        assert!(e.contains("t.dxf") && e.contains("line 3"), "{e}");
    }
}
