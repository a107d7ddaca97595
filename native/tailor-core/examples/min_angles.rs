//! Per-file minimum triangle angle of imported patterns, the figures in docs/user-guide.md
//! ("Meshing quality").
//!
//! ```text
//! cargo run -p tailor-core --release --example min_angles -- [--edge H]... PATH...
//! ```
//!
//! Each PATH is a pattern file (DXF, SVG, GarmentCode JSON) or a folder searched recursively for
//! them. Every file is imported as [`garment_from_pattern`] does at each edge length (0.02 and
//! 0.01 m unless `--edge` is given) and one line is printed per file and edge length: the
//! smallest triangle angle of any piece, the piece it is in, the smallest angle the mesher is
//! excused from (the sharpest input corner of that piece, see
//! [`TriangulateOptions::min_angle_deg`]), and how many import warnings the file gave. A line
//! starting `BELOW` is a triangle under the stated minimum that no input corner explains.
//!
//! With `--all-lines` every piece is meshed with all of its internal lines
//! ([`triangulate_piece`] directly), without the import's dropping of lines that leave a sliver
//! (`garment::from_pattern`): the mesher's own figures on the lines as drawn.

use std::path::{Path, PathBuf};

use tailor_core::garment::{garment_from_pattern, import_warnings};
use tailor_core::garment_file::{Garment, GarmentPiece};
use tailor_core::pattern::{read_pattern, ReadOptions};
use tailor_core::triangulate::{triangulate_piece, TriangulateOptions};

fn collect(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_dir() {
        let mut entries: Vec<PathBuf> =
            std::fs::read_dir(path).map(|d| d.flatten().map(|e| e.path()).collect()).unwrap_or_default();
        entries.sort();
        for e in entries {
            collect(&e, out);
        }
        return;
    }
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("").to_ascii_lowercase();
    // GarmentCode's own drawings (`*_pattern.svg`) are not patterns; its JSON beside them is.
    let drawing = name.ends_with("_pattern.svg");
    if name.ends_with(".dxf") || (name.ends_with(".svg") && !drawing) || name.ends_with("specification.json") {
        out.push(path.to_path_buf());
    }
}

fn main() {
    let mut edges = Vec::new();
    let mut files = Vec::new();
    let mut all_lines = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--all-lines" {
            all_lines = true;
        } else if a == "--edge" {
            edges.push(args.next().and_then(|v| v.parse::<f64>().ok()).expect("--edge takes a length in metres"));
        } else {
            collect(Path::new(&a), &mut files);
        }
    }
    if edges.is_empty() {
        edges = vec![0.02, 0.01];
    }
    let mut worst = vec![(f64::INFINITY, String::new()); edges.len()];
    let mut below = 0;
    for file in &files {
        let pattern = match read_pattern(file, &ReadOptions::default()) {
            Ok(p) => p,
            Err(e) => {
                println!("{}: not read: {e}", file.display());
                continue;
            }
        };
        for (k, &h) in edges.iter().enumerate() {
            let options = TriangulateOptions::new(h);
            let t = std::time::Instant::now();
            let imported =
                if all_lines { with_all_lines(&pattern, &options) } else { garment_from_pattern(&pattern, &options) };
            let (garment, meshes) = match imported {
                Ok(g) => g,
                Err(e) => {
                    println!("{} h={h}: FAILED: {e}", file.display());
                    continue;
                }
            };
            if std::env::var_os("MIN_ANGLES_DEBUG").is_some() {
                for w in import_warnings(&garment) {
                    println!("    warning: {w}");
                }
            }
            let (mut min, mut piece, mut excused) = (f64::INFINITY, String::new(), 180.0);
            for (m, gp) in meshes.iter().zip(&garment.pieces) {
                let q = &m.quality;
                if q.min_angle_deg < min {
                    min = q.min_angle_deg;
                    piece = m.name.clone();
                    excused = tailor_core::triangulate::sharpest_input_corner_deg(&gp.source, &options);
                }
                let bad = tailor_core::triangulate::unexcused_angles(m, &gp.source, &options);
                if !bad.is_empty() {
                    below += 1;
                    println!("BELOW {} h={h} piece {}: {:?}", file.display(), m.name, &bad[..bad.len().min(5)]);
                    if std::env::var_os("MIN_ANGLES_DEBUG").is_some() {
                        for &(t, a) in bad.iter().take(5) {
                            let p = m.triangles[t].map(|v| m.rest[v as usize]);
                            let d = |i: usize, j: usize| ((p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]) as f64) / h;
                            let on = m.triangles[t].map(|v| m.contour.contains(&v));
                            println!(
                                "    tri {t} angle {a:.2}: edges/h {:.4} {:.4} {:.4}, on contour {on:?}, at {:?}",
                                d(0, 1),
                                d(1, 2),
                                d(2, 0),
                                p[0]
                            );
                        }
                    }
                }
            }
            if min < worst[k].0 {
                worst[k] = (min, format!("{} ({piece})", file.display()));
            }
            println!(
                "{} h={h}: {} pieces, {} triangles, min angle {min:.2} deg in {piece} (its sharpest input corner {excused:.2} deg), {} warnings, {:.2} s",
                file.display(),
                meshes.len(),
                meshes.iter().map(|m| m.triangles.len()).sum::<usize>(),
                import_warnings(&garment).len(),
                t.elapsed().as_secs_f64()
            );
        }
    }
    for (k, &h) in edges.iter().enumerate() {
        println!("h={h}: {} files, lowest min angle {:.2} deg in {}", files.len(), worst[k].0, worst[k].1);
    }
    println!("{below} piece meshes with an angle below the minimum that no input corner explains");
}

/// Every piece of `pattern` meshed with all its internal lines (`--all-lines`), as a garment
/// without seams.
fn with_all_lines(
    pattern: &tailor_core::pattern::Pattern,
    options: &TriangulateOptions,
) -> tailor_core::error::Result<(Garment, Vec<tailor_core::triangulate::PieceMesh>)> {
    let mut garment = Garment::default();
    let mut meshes = Vec::new();
    for p in &pattern.pieces {
        meshes.push(triangulate_piece(p, options)?);
        garment.pieces.push(GarmentPiece {
            placement: p.placement.clone(),
            source: p.clone(),
            options: options.clone(),
            bend: None,
        });
    }
    Ok((garment, meshes))
}
