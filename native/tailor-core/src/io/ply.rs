//! PLY reader: ASCII and binary little-endian (big-endian is refused as unsupported).
//!
//! The header declares elements and their properties; the `vertex` element must have `x`, `y`,
//! `z` properties (any numeric type) and the `face` element a list property (`vertex_indices`
//! or `vertex_index`, else the first list), whose polygons are fan-triangulated. Every other
//! element and property is read and discarded, so files with colours, normals, edges or
//! materials load too.

use std::path::Path;

use super::{read_bytes, TriMesh};
use crate::error::{Result, TailorError};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

#[derive(Debug, Clone)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads a PLY file.
pub fn read_ply(path: impl AsRef<Path>) -> Result<TriMesh> {
    let path = path.as_ref();
    parse_ply(&read_bytes(path)?, &path.display().to_string())
}

/// Parses PLY bytes; `file` names the source in errors.
pub fn parse_ply(bytes: &[u8], file: &str) -> Result<TriMesh> {
    let err = |entity: &str, reason: String| TailorError::parse(file, entity, reason);
    let (elements, binary, body) = parse_header(bytes, file)?;
    let mut mesh = TriMesh::default();
    let mut reader = Body { bytes: body, pos: 0, binary };
    for el in &elements {
        let is_vertex = el.name == "vertex";
        let is_face = el.name == "face";
        let xyz: Vec<Option<usize>> = el
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar(n, _) => ["x", "y", "z"].iter().position(|c| c == n),
                Property::List(..) => None,
            })
            .collect();
        let list_prop = el
            .properties
            .iter()
            .position(|p| matches!(p, Property::List(n, ..) if n == "vertex_indices" || n == "vertex_index"))
            .or_else(|| el.properties.iter().position(|p| matches!(p, Property::List(..))));
        if is_vertex && (0..3).any(|c| !xyz.contains(&Some(c))) {
            return Err(err("element vertex", "missing an x, y or z property".into()));
        }
        if is_face && list_prop.is_none() {
            return Err(err("element face", "no vertex index list property".into()));
        }
        let mut corners: Vec<u32> = Vec::new();
        for i in 0..el.count {
            let mut p = [0.0f32; 3];
            for (k, prop) in el.properties.iter().enumerate() {
                let entity = || format!("element {} {i}", el.name);
                match prop {
                    Property::Scalar(_, ty) => {
                        let v =
                            reader.value(*ty).ok_or_else(|| err(&entity(), "truncated or malformed value".into()))?;
                        if let Some(Some(c)) = xyz.get(k).filter(|_| is_vertex) {
                            p[*c] = v as f32;
                        }
                    }
                    Property::List(_, count_ty, item_ty) => {
                        let n =
                            reader.value(*count_ty).ok_or_else(|| err(&entity(), "truncated list length".into()))?;
                        if !(n >= 0.0 && n.fract() == 0.0 && n <= 1e6) {
                            return Err(err(&entity(), format!("bad list length {n}")));
                        }
                        let keep = is_face && Some(k) == list_prop;
                        corners.clear();
                        for _ in 0..n as usize {
                            let v = reader.value(*item_ty).ok_or_else(|| err(&entity(), "truncated list".into()))?;
                            if keep {
                                if !(v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as f64) {
                                    return Err(err(&entity(), format!("bad vertex index {v}")));
                                }
                                corners.push(v as u32);
                            }
                        }
                        if keep {
                            if corners.len() < 3 {
                                return Err(err(&entity(), format!("face with {} corners", corners.len())));
                            }
                            for c in 1..corners.len() - 1 {
                                mesh.triangles.push([corners[0], corners[c], corners[c + 1]]);
                            }
                        }
                    }
                }
            }
            if is_vertex {
                mesh.positions.push(p);
            }
        }
    }
    mesh.validate(file)?;
    Ok(mesh)
}

fn parse_header<'a>(bytes: &'a [u8], file: &str) -> Result<(Vec<Element>, bool, &'a [u8])> {
    let err = |entity: &str, reason: String| TailorError::parse(file, entity, reason);
    if !bytes.starts_with(b"ply") {
        return Err(err("header", "not a PLY file (no 'ply' magic)".into()));
    }
    let marker = b"end_header";
    let end = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or_else(|| err("header", "no end_header line".into()))?;
    let mut body_start = end + marker.len();
    while body_start < bytes.len() && bytes[body_start] != b'\n' {
        body_start += 1;
    }
    body_start = (body_start + 1).min(bytes.len());
    let header = String::from_utf8_lossy(&bytes[..end]);
    let mut binary = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in header.lines().enumerate() {
        let entity = format!("header line {}", n + 1);
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first().copied() {
            Some("format") => {
                binary = Some(match t.get(1).copied() {
                    Some("ascii") => false,
                    Some("binary_little_endian") => true,
                    Some(other) => {
                        return Err(TailorError::Unsupported {
                            file: file.into(),
                            entity,
                            reason: format!("PLY format {other} (only ascii and binary_little_endian)"),
                        })
                    }
                    None => return Err(err(&entity, "format without a value".into())),
                })
            }
            Some("element") => {
                let (Some(name), Some(count)) = (t.get(1), t.get(2).and_then(|c| c.parse::<usize>().ok())) else {
                    return Err(err(&entity, format!("bad element line {line:?}")));
                };
                elements.push(Element { name: name.to_string(), count, properties: Vec::new() });
            }
            Some("property") => {
                let el = elements.last_mut().ok_or_else(|| err(&entity, "property before any element".into()))?;
                let bad = || err(&entity, format!("bad property line {line:?}"));
                if t.get(1) == Some(&"list") {
                    let (Some(c), Some(i), Some(name)) =
                        (t.get(2).and_then(|s| Scalar::parse(s)), t.get(3).and_then(|s| Scalar::parse(s)), t.get(4))
                    else {
                        return Err(bad());
                    };
                    el.properties.push(Property::List(name.to_string(), c, i));
                } else {
                    let (Some(ty), Some(name)) = (t.get(1).and_then(|s| Scalar::parse(s)), t.get(2)) else {
                        return Err(bad());
                    };
                    el.properties.push(Property::Scalar(name.to_string(), ty));
                }
            }
            _ => {}
        }
    }
    let binary = binary.ok_or_else(|| err("header", "no format line".into()))?;
    Ok((elements, binary, &bytes[body_start..]))
}

/// Cursor over the body, yielding numbers as `f64` (exact for every PLY type but 64-bit).
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    binary: bool,
}

impl Body<'_> {
    fn value(&mut self, ty: Scalar) -> Option<f64> {
        if self.binary {
            let b = self.bytes.get(self.pos..self.pos + ty.size())?;
            self.pos += ty.size();
            Some(ty.read_le(b))
        } else {
            while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let start = self.pos;
            while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let tok = std::str::from_utf8(&self.bytes[start..self.pos]).ok()?;
            let v: f64 = tok.parse().ok()?;
            v.is_finite().then_some(v)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment quad and triangle\nelement vertex 5\n\
        property float x\nproperty float y\nproperty float z\nproperty uchar red\n\
        element face 2\nproperty list uchar int vertex_indices\nproperty float quality\n\
        element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
        0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0.5 0.5 1 7\n4 0 1 2 3 0.5\n3 0 1 4 1.0\n0 1\n";

    #[test]
    fn parses_ascii_with_extra_properties_and_elements() {
        let m = parse_ply(ASCII.as_bytes(), "a.ply").unwrap();
        assert_eq!(m.positions.len(), 5);
        assert_eq!(m.positions[4], [0.5, 0.5, 1.0]);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
    }

    #[test]
    fn parses_binary_little_endian() {
        let mut b = b"ply\r\nformat binary_little_endian 1.0\r\nelement vertex 4\r\nproperty double x\r\n\
            property float y\r\nproperty float z\r\nelement face 1\r\nproperty list uchar uint vertex_index\r\nend_header\r\n"
            .to_vec();
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 3.0]] {
            b.extend((p[0] as f64).to_le_bytes());
            b.extend(p[1].to_le_bytes());
            b.extend(p[2].to_le_bytes());
        }
        b.push(4);
        for i in [3u32, 2, 1, 0] {
            b.extend(i.to_le_bytes());
        }
        let m = parse_ply(&b, "b.ply").unwrap();
        assert_eq!(m.positions[3], [0.0, 2.0, 3.0]);
        assert_eq!(m.triangles, vec![[3, 2, 1], [3, 1, 0]]);
        // Truncated body.
        let e = parse_ply(&b[..b.len() - 2], "b.ply").unwrap_err();
        assert_eq!(e.to_string(), "b.ply: element face 0: truncated list");
    }

    #[test]
    fn corrupted_files_never_panic() {
        let mut rng = crate::test_util::Rng::new(23);
        for _ in 0..500 {
            let mut b = ASCII.as_bytes().to_vec();
            for _ in 0..1 + (rng.f32() * 3.0) as usize {
                let i = (rng.f32() * b.len() as f32) as usize % b.len();
                b[i] = (rng.next_u64() & 0xFF) as u8;
            }
            let _ = parse_ply(&b, "fuzz.ply");
            let cut = (rng.f32() * b.len() as f32) as usize;
            let _ = parse_ply(&b[..cut], "fuzz.ply");
        }
    }

    #[test]
    fn reports_bad_headers_and_indices() {
        let e = parse_ply(b"obj\n", "x.ply").unwrap_err();
        assert!(e.to_string().contains("not a PLY file"), "{e}");
        let e = parse_ply(b"ply\nformat binary_big_endian 1.0\nend_header\n", "x.ply").unwrap_err();
        assert!(matches!(e, TailorError::Unsupported { .. }), "{e}");
        let bad = ASCII.replace("4 0 1 2 3 0.5", "4 0 1 2 9 0.5");
        let e = parse_ply(bad.as_bytes(), "x.ply").unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        let bad = ASCII.replace("property float z\n", "");
        let e = parse_ply(bad.as_bytes(), "x.ply").unwrap_err();
        assert!(e.to_string().contains("element vertex"), "{e}");
    }
}
