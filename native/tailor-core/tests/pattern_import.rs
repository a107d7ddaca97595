//! Pattern import tests: piece counts and outline lengths checked against lengths computed
//! independently here (raw DXF vertices, analytic SVG shapes, finely sampled GarmentCode
//! curves). Tests on the shared third-party data skip when `../shared/data` is absent.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use tailor_core::pattern::{list_sizes, outline, read_pattern, Pattern, ReadOptions, Units};
use tailor_core::TailorError;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(rel)
}

fn shared(rel: &str) -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/patterns");
    if root.is_dir() {
        Some(root.join(rel))
    } else {
        eprintln!("note: {} is absent, skipping", root.display());
        None
    }
}

fn read(p: &Path) -> Pattern {
    read_pattern(p, &ReadOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn close(got: f64, want: f64, rel: f64, what: &str) {
    assert!((got - want).abs() <= rel * want.abs(), "{what}: got {got}, want {want} (±{:.2} %)", rel * 100.0);
}

fn check_invariants(p: &Pattern) {
    for pc in &p.pieces {
        assert!(pc.outline.len() >= 3, "{}", pc.name);
        assert!(outline::signed_area(&pc.outline) > 0.0, "{} is not CCW", pc.name);
        for h in &pc.holes {
            assert!(outline::signed_area(h) < 0.0, "a hole of {} is not CW", pc.name);
        }
        assert!(pc.fixed_vertices.iter().all(|&i| i < pc.outline.len()));
        assert!(pc.fixed_vertices.windows(2).all(|w| w[0] < w[1]));
        for s in &pc.edges {
            assert!(s.start < pc.outline.len() && s.end < pc.outline.len());
        }
    }
}

// ---------------------------------------------------------------- DXF, independent scan

/// Per block of the sample size (or `size`): (piece name, boundary length in file units),
/// from a line-by-line scan that sums the raw VERTEX/LINE coordinates on layer 1.
fn scan_dxf(path: &Path, size: Option<&str>) -> (Vec<(String, f64)>, f64) {
    let text = String::from_utf8_lossy(&std::fs::read(path).unwrap()).to_string();
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let pairs: Vec<(&str, &str)> = lines.chunks(2).filter(|c| c.len() == 2).map(|c| (c[0], c[1])).collect();
    let value_after = |key: &str| {
        pairs.iter().find_map(|(c, v)| {
            (*c == "1" && v.to_lowercase().starts_with(key)).then(|| v.split_once(':').unwrap().1.trim().to_string())
        })
    };
    let units = match value_after("units:").as_deref().map(str::to_uppercase).as_deref() {
        Some("ENGLISH") => 0.0254,
        Some("METRIC") => 0.001,
        _ => panic!("no units"),
    };
    let want = size.map(str::to_string).or_else(|| value_after("sample size:")).unwrap();
    let mut out = Vec::new();
    let (mut in_block, mut name, mut bsize, mut len) = (false, String::new(), String::new(), 0.0);
    let (mut kind, mut layer) = ("", "");
    let mut poly: Vec<[f64; 2]> = Vec::new();
    let mut closed = false;
    let mut cur = [f64::NAN, f64::NAN, f64::NAN, f64::NAN];
    let mut poly_layer = "";
    let flush_entity = |kind: &str, layer: &str, cur: &[f64; 4], poly: &mut Vec<[f64; 2]>, len: &mut f64| {
        if layer == "1" && kind == "VERTEX" {
            poly.push([cur[0], cur[1]]);
        }
        if layer == "1" && kind == "LINE" {
            *len += (cur[2] - cur[0]).hypot(cur[3] - cur[1]);
        }
    };
    let poly_len = |poly: &[[f64; 2]], closed: bool| {
        let mut l: f64 = poly.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum();
        if closed && poly.len() > 2 {
            l += (poly[0][0] - poly[poly.len() - 1][0]).hypot(poly[0][1] - poly[poly.len() - 1][1]);
        }
        l
    };
    for (c, v) in pairs {
        match c {
            "0" => {
                flush_entity(kind, layer, &cur, &mut poly, &mut len);
                if v == "SEQEND" {
                    if poly_layer == "1" {
                        len += poly_len(&poly, closed);
                    }
                    poly.clear();
                }
                if v == "POLYLINE" {
                    closed = false;
                }
                if v == "BLOCK" {
                    in_block = true;
                    (name, bsize, len) = (String::new(), String::new(), 0.0);
                }
                if v == "ENDBLK" && in_block {
                    in_block = false;
                    if bsize.eq_ignore_ascii_case(&want) {
                        out.push((name.clone(), len));
                    }
                }
                kind = v;
                layer = "";
                cur = [f64::NAN; 4];
            }
            "8" => {
                layer = v;
                if kind == "POLYLINE" {
                    poly_layer = v;
                }
            }
            "70" if kind == "POLYLINE" => closed = v.parse::<i32>().unwrap() & 1 == 1,
            "10" => cur[0] = v.parse().unwrap(),
            "20" => cur[1] = v.parse().unwrap(),
            "11" => cur[2] = v.parse().unwrap(),
            "21" => cur[3] = v.parse().unwrap(),
            "42" => panic!("the scan does not handle bulges"),
            "1" => {
                let l = v.to_lowercase();
                if l.starts_with("piece name:") {
                    name = v.split_once(':').unwrap().1.trim().to_string();
                } else if l.starts_with("size:") {
                    bsize = v.split_once(':').unwrap().1.trim().to_string();
                }
            }
            _ => {}
        }
    }
    (out, units)
}

fn check_dxf_against_scan(file: &str, pieces: usize) {
    let Some(path) = shared(&format!("astm-parser-dxf/{file}")) else { return };
    let t = std::time::Instant::now();
    // As drawn: the scan measures each drawn boundary once (a piece cut on the fold is its half).
    let p = read_pattern(&path, &ReadOptions { unfold: false, quantities: false, ..Default::default() }).unwrap();
    let took = t.elapsed();
    check_invariants(&p);
    assert_eq!(p.pieces.len(), pieces, "{file}: {:?}", p.pieces.iter().map(|x| &x.name).collect::<Vec<_>>());
    let (scan, units) = scan_dxf(&path, None);
    assert_eq!(scan.len(), pieces);
    for (name, len) in scan {
        let pc = p.pieces.iter().find(|x| x.name == name).unwrap_or_else(|| panic!("{file}: no piece {name}"));
        let got = outline::perimeter(&pc.outline);
        println!("{file} size {:?} {name}: reader {got:.5} m, scan {:.5} m ({took:?})", p.size, len * units);
        close(got, len * units, 0.005, &format!("{file} {name}"));
        assert!(pc.grain.is_some(), "{name} has no grain line");
        assert!(pc.fixed_vertices.len() >= 3, "{name} has {} fixed vertices", pc.fixed_vertices.len());
        // Notches on the boundary became fixed outline vertices.
        for q in &pc.notches {
            let i = pc.outline.iter().position(|v| outline::dist(*v, *q) < 1e-9);
            assert!(
                i.is_some_and(|i| pc.fixed_vertices.contains(&i)),
                "{file} {name}: notch {q:?} is not a fixed vertex"
            );
        }
    }
}

#[test]
fn wm_slim_tank_imports_front_and_back_at_sample_size() {
    check_dxf_against_scan("WM_SLIM_TANK.DXF", 2);
    let Some(path) = shared("astm-parser-dxf/WM_SLIM_TANK.DXF") else { return };
    let p = read(&path);
    assert_eq!(p.size.as_deref(), Some("36"));
    assert_eq!(p.sizes.len(), 14);
    assert_eq!(list_sizes(&path).unwrap(), p.sizes);
    let names: Vec<&str> = p.pieces.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["TANK_SR_BK", "TANK_SR_FR"]);
    // Every size reads, and the graded pieces grow with the size.
    let per = |s: &str| {
        let o = ReadOptions { size: Some(s.into()), unfold: false, ..Default::default() };
        let p = read_pattern(&path, &o).unwrap();
        assert_eq!(p.size.as_deref(), Some(s));
        outline::perimeter(&p.pieces[0].outline)
    };
    assert!(per("26") < per("36") && per("36") < per("52"));
    let (scan, units) = scan_dxf(&path, Some("52"));
    close(per("52"), scan[0].1 * units, 0.005, "size 52");
    // Both pieces are drawn as halves cut on the fold: read whole, twice the area.
    let drawn = read_pattern(&path, &ReadOptions { unfold: false, ..Default::default() }).unwrap();
    for (w, d) in p.pieces.iter().zip(&drawn.pieces) {
        let (aw, ad) = (outline::signed_area(&w.outline).abs(), outline::signed_area(&d.outline).abs());
        close(aw, 2.0 * ad, 1e-4, &format!("{} unfolded", w.name));
    }
}

#[test]
fn men_classic_tee_has_seven_pieces() {
    check_dxf_against_scan("MEN_CLASSIC_TEE.DXF", 7);
}

#[test]
fn orilegwb_is_metric_leg_and_waistband() {
    check_dxf_against_scan("ORILEGWB_AAMA.DXF", 2);
}

/// The shared files cut as their `Quantity:` says: the legging's leg twice (a left and a right
/// leg, mirror images), its waistband once; the tee's front, back and collar rib once, the
/// two-piece sleeve's halves twice each, and the one-piece sleeve and the collar shell (cut 0
/// times: alternatives) left out.
#[test]
fn the_shared_patterns_are_cut_as_their_quantities_say() {
    let names = |p: &Pattern| p.pieces.iter().map(|x| x.name.clone()).collect::<Vec<_>>();
    if let Some(path) = shared("astm-parser-dxf/ORILEGWB_AAMA.DXF") {
        let p = read(&path);
        check_invariants(&p);
        assert_eq!(names(&p), ["ORILEG WB WB", "ORILEG WB LL R", "ORILEG WB LL L"]);
        let (r, l) = (&p.pieces[1], &p.pieces[2]);
        close(outline::signed_area(&l.outline), outline::signed_area(&r.outline), 1e-12, "the pair's areas");
        assert_eq!(r.notches.len(), l.notches.len());
    }
    if let Some(path) = shared("astm-parser-dxf/MEN_CLASSIC_TEE.DXF") {
        let p = read(&path);
        check_invariants(&p);
        let want = [
            "REGULAR TEEFR",
            "REGULAR TEEBK",
            "REGULAR TEECO",
            "REGULAR TEESL BK R",
            "REGULAR TEESL BK L",
            "REGULAR TEESL FR R",
            "REGULAR TEESL FR L",
        ];
        assert_eq!(names(&p), want);
    }
}

/// The men's tee meshes at 2 and 3 cm with no tiny triangle: its sleeves' grain line crosses
/// three balance lines, which mesher 2 split after refinement beside points already on them
/// (triangles of 1e-9 m², which the solver refuses); mesher 3 cuts the lines first.
#[test]
fn the_tees_crossing_lines_leave_no_tiny_triangle() {
    use tailor_core::triangulate::TriangulateOptions;
    let Some(path) = shared("astm-parser-dxf/MEN_CLASSIC_TEE.DXF") else { return };
    for h in [0.02, 0.03] {
        let eq = 3f64.sqrt() / 4.0 * h * h;
        // As the garment is built (lines that would leave a sliver dropped, with a warning).
        let (_, _, meshes) =
            tailor_core::garment::read_garment(&path, &ReadOptions::default(), &TriangulateOptions::new(h)).unwrap();
        for m in &meshes {
            let smallest = m
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| m.rest[i as usize].map(f64::from));
                    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(smallest > 1e-3 * eq, "{} at {h}: a triangle of {smallest:.2e} m²", m.name);
        }
    }
}

/// Cut quantities (`synthetic_cut.dxf`): SLEEVE (`Quantity: 2`) is read as a pair, the piece as
/// drawn and its mirror image across its bounding box's middle, notch and grain line mirrored
/// with it; PANEL once; ALT (0) left out; the L size, whose blocks carry no quantity, is cut as
/// the sample size's blocks say. With `quantities` off every piece is read once, as drawn.
#[test]
fn a_pair_is_read_as_the_piece_and_its_mirror() {
    let path = data("dxf/synthetic_cut.dxf");
    let names = |p: &Pattern| p.pieces.iter().map(|x| x.name.clone()).collect::<Vec<_>>();
    for size in ["M", "L"] {
        let p = read_pattern(&path, &ReadOptions { size: Some(size.into()), ..Default::default() }).unwrap();
        check_invariants(&p);
        assert_eq!(names(&p), ["SLEEVE R", "SLEEVE L", "PANEL"], "size {size}");
    }
    let p = read(&path);
    let (r, l) = (&p.pieces[0], &p.pieces[1]);
    // The mirror of x is 0.2 − x (the bounding box runs from 0 to 0.2 m).
    let img = |q: [f64; 2]| [0.2 - q[0], q[1]];
    for v in &r.outline {
        assert!(l.outline.iter().any(|w| outline::dist(*w, img(*v)) < 1e-9), "{v:?} has no image");
    }
    close(outline::signed_area(&l.outline), outline::signed_area(&r.outline), 1e-12, "area and orientation");
    assert_eq!(l.notches.len(), 1);
    assert!(outline::dist(l.notches[0], img(r.notches[0])) < 1e-9);
    let g = r.grain.unwrap();
    let lg = l.grain.expect("the mirror keeps the grain line");
    assert!(outline::dist(lg[0], img(g[0])) < 1e-9 && outline::dist(lg[1], img(g[1])) < 1e-9, "{lg:?}");
    let i = l.outline.iter().position(|v| outline::dist(*v, l.notches[0]) < 1e-9).expect("the notch is a vertex");
    assert!(l.fixed_vertices.contains(&i), "the mirrored notch is a fixed vertex");
    let drawn = read_pattern(&path, &ReadOptions { quantities: false, ..Default::default() }).unwrap();
    assert_eq!(names(&drawn), ["SLEEVE", "PANEL", "ALT"]);
    assert_eq!(drawn.pieces[0].outline, r.outline);
}

#[test]
fn clo_box_is_one_rectangle() {
    check_dxf_against_scan("clo-box.dxf", 1);
    let Some(path) = shared("astm-parser-dxf/clo-box.dxf") else { return };
    let p = read(&path);
    assert_eq!(p.pieces[0].fixed_vertices.len(), 4);
    assert_eq!(p.pieces[0].outline.len(), 4);
}

#[test]
fn unknown_size_lists_the_available_ones() {
    let path = data("dxf/synthetic_aama.dxf");
    let e = read_pattern(&path, &ReadOptions { size: Some("XXL".into()), ..Default::default() }).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, TailorError::Parse { .. }));
    assert!(msg.contains("synthetic_aama.dxf") && msg.contains("XXL") && msg.contains("S, M, L"), "{msg}");
}

#[test]
fn synthetic_aama_nest() {
    let path = data("dxf/synthetic_aama.dxf");
    let p = read(&path);
    check_invariants(&p);
    assert_eq!(p.sizes, ["S", "M", "L"]);
    assert_eq!(p.size.as_deref(), Some("M"));
    assert_eq!(p.pieces.len(), 2);
    let front = &p.pieces[0];
    assert_eq!(front.name, "FRONT");
    let front_len = (800.0 + 500.0 * 0.5f64.atan()) * 1e-3;
    close(outline::perimeter(&front.outline), front_len, 1e-3, "FRONT");
    // Bulge flattening stays within the 0.5 mm tolerance: every point is on or inside the arc.
    let center = [0.1, 0.3 - 0.075];
    let worst = front
        .outline
        .iter()
        .filter(|q| q[1] > 0.3 + 1e-9)
        .map(|q| 0.125 - (q[0] - center[0]).hypot(q[1] - center[1]))
        .fold(0.0f64, f64::max);
    assert!(worst <= 0.0005 + 1e-9, "arc chord error {worst}");
    assert_eq!(front.notches.len(), 2);
    assert_eq!(front.internal_lines.len(), 1);
    assert_eq!(front.grain, Some([[0.1, 0.05], [0.1, 0.25]]));
    // Corners and notches are fixed vertices.
    for q in [[0.0, 0.0], [0.2, 0.0], [0.2, 0.3], [0.0, 0.3], [0.1, 0.0], [0.2, 0.15]] {
        let i = front
            .outline
            .iter()
            .position(|v| outline::dist(*v, q) < 1e-9)
            .unwrap_or_else(|| panic!("{q:?} not a vertex"));
        assert!(front.fixed_vertices.contains(&i), "{q:?} not fixed");
    }
    let back_len = (360.0 + 2.0 * 40f64.hypot(280.0)) * 1e-3;
    close(outline::perimeter(&p.pieces[1].outline), back_len, 1e-9, "BACK");
    assert_eq!(p.pieces[1].holes.len(), 1, "layer 11 cutout");
    close(outline::perimeter(&p.pieces[1].holes[0]), 0.08, 1e-9, "cutout");
    // Other sizes and a units override.
    let l = read_pattern(&path, &ReadOptions { size: Some("l".into()), ..Default::default() }).unwrap();
    close(outline::perimeter(&l.pieces[1].outline), 1.1 * back_len, 1e-9, "BACK L");
    let cm =
        read_pattern(&path, &ReadOptions { units_override: Some(Units::Centimetres), ..Default::default() }).unwrap();
    close(outline::perimeter(&cm.pieces[1].outline), 10.0 * back_len, 1e-9, "BACK in cm");
}

#[test]
fn piece_name_and_size_from_insert_attribs() {
    let p = read(&data("dxf/synthetic_attrib.dxf"));
    assert_eq!(p.pieces.len(), 1);
    assert_eq!(p.pieces[0].name, "CUFF");
    assert_eq!(p.size.as_deref(), Some("10"));
    close(outline::perimeter(&p.pieces[0].outline), 12.0 * 0.0254, 1e-9, "cuff");
}

#[test]
fn synthetic_plain_dxf() {
    let fine = ReadOptions { tolerance_m: 1e-5, ..Default::default() };
    let p = read_pattern(&data("dxf/synthetic_plain.dxf"), &fine).unwrap();
    check_invariants(&p);
    assert_eq!(p.pieces.len(), 2);
    let sq = p.pieces.iter().find(|x| x.name == "PANEL").expect("square named by its layer");
    close(outline::perimeter(&sq.outline), 2.0, 1e-9, "square");
    assert_eq!(sq.holes.len(), 1);
    close(outline::perimeter(&sq.holes[0]), 2.0 * PI * 0.05, 1e-3, "circle hole");
    assert_eq!(sq.internal_lines.len(), 1, "the open spline");
    assert_eq!(sq.fixed_vertices.len(), 4);
    let d = p.pieces.iter().find(|x| x.name == "POCKET").expect("D named by its TEXT");
    close(outline::perimeter(&d.outline), 0.4 + 0.2 * PI, 1e-3, "D");
    assert_eq!(list_sizes(&data("dxf/synthetic_plain.dxf")).unwrap(), Vec::<String>::new());
}

#[test]
fn dxf_errors_name_file_entity_and_reason() {
    let text = std::fs::read_to_string(data("dxf/synthetic_aama.dxf")).unwrap();
    // Break the y of the first VERTEX of block FRONT_M.
    let at = text.find("FRONT_M").unwrap();
    let v = at + text[at..].find("VERTEX").unwrap();
    let y = v + text[v..].find(" 20\r\n").unwrap();
    let broken = format!("{}{}", &text[..y], &text[y..].replacen(" 20\r\n", " 20\r\nabc\r\n 99\r\n", 1));
    let e =
        tailor_core::pattern::read_pattern_bytes(Path::new("front.dxf"), broken.as_bytes(), &ReadOptions::default())
            .unwrap_err()
            .to_string();
    assert!(e.starts_with("front.dxf: BLOCK \"FRONT_M\" VERTEX at line"), "{e}");
    assert!(e.contains("group 20"), "{e}");
    let e = read_pattern(Path::new("/nonexistent/x.dxf"), &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, TailorError::Io { .. }));
}

// ---------------------------------------------------------------- SVG, analytic shapes

#[test]
fn svg_two_panel_skirt() {
    let p = read(&data("svg/skirt_two_panels.svg"));
    check_invariants(&p);
    let names: Vec<&str> = p.pieces.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["skirt front", "skirt back"]);
    let want = (800.0 * (150.0f64 / 400.0).asin() + 360.0 + 2.0 * 30f64.hypot(400.0)) * 1e-3;
    for pc in &p.pieces {
        close(outline::perimeter(&pc.outline), want, 1e-3, &pc.name);
        assert!(pc.fixed_vertices.len() >= 4);
    }
}

#[test]
fn svg_piece_with_hole() {
    // A fine tolerance, so that the chords of the small hole are within 0.1 % of the circle.
    let fine = ReadOptions { tolerance_m: 1e-5, ..Default::default() };
    let p = read_pattern(&data("svg/piece_with_hole.svg"), &fine).unwrap();
    check_invariants(&p);
    assert_eq!(p.pieces.len(), 1);
    let pc = &p.pieces[0];
    assert_eq!(pc.name, "pocket panel");
    close(outline::perimeter(&pc.outline), 0.9, 1e-9, "rect");
    close(outline::signed_area(&pc.outline), 0.05, 1e-9, "rect area");
    assert_eq!(pc.holes.len(), 1);
    close(outline::perimeter(&pc.holes[0]), 2.0 * PI * 0.03, 1e-3, "hole");
    assert_eq!(pc.internal_lines.len(), 1);
}

#[test]
fn svg_transforms_and_units() {
    let p = read(&data("svg/transforms_units.svg"));
    check_invariants(&p);
    let by = |n: &str| p.pieces.iter().find(|x| x.name == n).unwrap_or_else(|| panic!("no {n}"));
    let inch = 0.0254;
    close(outline::perimeter(&by("yoke").outline), 6.25 * inch, 1e-9, "yoke");
    close(outline::signed_area(&by("yoke").outline), (200.0 / 96.0) * (100.0 / 96.0) * inch * inch, 1e-9, "yoke area");
    close(outline::perimeter(&by("cuff").outline), 3.0 * inch, 1e-9, "cuff");
    let (a, b) = (1.0 * inch, 0.5 * inch);
    let ramanujan = PI * (3.0 * (a + b) - ((3.0 * a + b) * (a + 3.0 * b)).sqrt());
    let fine = ReadOptions { tolerance_m: 1e-5, ..Default::default() };
    let fine = read_pattern(&data("svg/transforms_units.svg"), &fine).unwrap();
    let patch = &fine.pieces.iter().find(|x| x.name == "patch").unwrap().outline;
    close(outline::perimeter(patch), ramanujan, 1e-3, "patch");
    // At the default tolerance every chord stays within 0.5 mm of the ellipse.
    let c = [700.0 / 96.0 * inch, -300.0 / 96.0 * inch];
    let q = &by("patch").outline;
    for i in 0..q.len() {
        let m = [(q[i][0] + q[(i + 1) % q.len()][0]) / 2.0 - c[0], (q[i][1] + q[(i + 1) % q.len()][1]) / 2.0 - c[1]];
        let r = (m[0] / a).hypot(m[1] / b);
        assert!((1.0 - r) * b <= 0.0005 + 1e-9, "chord {i} is {} m inside", (1.0 - r) * b);
    }
    assert!(by("collar").outline.len() > 10);
    // A units override redefines the user unit.
    let o = ReadOptions { units_override: Some(Units::Millimetres), ..Default::default() };
    let mm = read_pattern(&data("svg/transforms_units.svg"), &o).unwrap();
    close(outline::perimeter(&mm.pieces.iter().find(|x| x.name == "yoke").unwrap().outline), 0.6, 1e-9, "yoke mm");
}

// ---------------------------------------------------------------- GarmentCode, sampled curves

/// Independent edge lengths: Béziers by dense sampling, circle arcs analytically.
fn gc_edge_lengths(path: &Path) -> Vec<(String, Vec<f64>, [f64; 3])> {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let scale = 1.0 / v["properties"]["units_in_meter"].as_f64().unwrap();
    let mut out = Vec::new();
    for (name, panel) in v["pattern"]["panels"].as_object().unwrap() {
        let verts: Vec<[f64; 2]> = panel["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
            .collect();
        let mut lens = Vec::new();
        for e in panel["edges"].as_array().unwrap() {
            let (s, t) = (
                verts[e["endpoints"][0].as_u64().unwrap() as usize],
                verts[e["endpoints"][1].as_u64().unwrap() as usize],
            );
            let d = [t[0] - s[0], t[1] - s[1]];
            let chord = d[0].hypot(d[1]);
            let ctrl = |c: &serde_json::Value| {
                let (u, w) = (c[0].as_f64().unwrap(), c[1].as_f64().unwrap());
                [s[0] + u * d[0] - w * d[1], s[1] + u * d[1] + w * d[0]]
            };
            let len = match e.get("curvature") {
                None => chord,
                Some(c) => match c["type"].as_str().unwrap() {
                    "circle" => {
                        let r = c["params"][0].as_f64().unwrap();
                        let th = 2.0 * (chord / (2.0 * r)).min(1.0).asin();
                        r * if c["params"][1].as_f64().unwrap() != 0.0 { 2.0 * PI - th } else { th }
                    }
                    kind => {
                        let cs: Vec<[f64; 2]> = c["params"].as_array().unwrap().iter().map(ctrl).collect();
                        let bez = |tt: f64| -> [f64; 2] {
                            let mt = 1.0 - tt;
                            if kind == "quadratic" {
                                [0, 1].map(|k| mt * mt * s[k] + 2.0 * mt * tt * cs[0][k] + tt * tt * t[k])
                            } else {
                                [0, 1].map(|k| {
                                    mt * mt * mt * s[k]
                                        + 3.0 * mt * mt * tt * cs[0][k]
                                        + 3.0 * mt * tt * tt * cs[1][k]
                                        + tt * tt * tt * t[k]
                                })
                            }
                        };
                        let n = 20_000;
                        (0..n)
                            .map(|i| {
                                let (a, b) = (bez(i as f64 / n as f64), bez((i + 1) as f64 / n as f64));
                                (b[0] - a[0]).hypot(b[1] - a[1])
                            })
                            .sum()
                    }
                },
            };
            lens.push(len * scale);
        }
        let tr = &panel["translation"];
        out.push((name.clone(), lens, [0, 1, 2].map(|k| tr[k].as_f64().unwrap() * scale)));
    }
    out
}

fn span_length(outline: &[[f64; 2]], start: usize, end: usize) -> f64 {
    let n = outline.len();
    let mut i = start;
    let mut l = 0.0;
    while i != end {
        let j = (i + 1) % n;
        l += outline::dist(outline[i], outline[j]);
        i = j;
    }
    l
}

fn check_garmentcode(file: &str, panels: usize, stitches: usize) {
    let path = data(&format!("garmentcode/{file}"));
    let t = std::time::Instant::now();
    let p = read(&path);
    let took = t.elapsed();
    check_invariants(&p);
    assert_eq!(p.pieces.len(), panels, "{file} panels");
    assert_eq!(p.stitches.len(), stitches, "{file} stitches");
    let mut total = (0.0, 0.0);
    for (name, lens, tr) in gc_edge_lengths(&path) {
        let pc = p.pieces.iter().find(|x| x.name == name).unwrap();
        assert_eq!(pc.edges.len(), lens.len());
        for (i, (span, want)) in pc.edges.iter().zip(&lens).enumerate() {
            close(span_length(&pc.outline, span.start, span.end), *want, 0.005, &format!("{file} {name} edge {i}"));
        }
        let want: f64 = lens.iter().sum();
        close(outline::perimeter(&pc.outline), want, 0.005, &format!("{file} {name}"));
        total.0 += outline::perimeter(&pc.outline);
        total.1 += want;
        let pl = pc.placement.as_ref().unwrap();
        assert!(pl.translation.iter().zip(tr).all(|(a, b)| (a - b).abs() < 1e-12));
    }
    println!(
        "{file}: {panels} panels, {stitches} stitches, outline total {:.5} m, sampled {:.5} m ({took:?})",
        total.0, total.1
    );
    for s in &p.stitches {
        assert!(s.a.edge < p.pieces[s.a.piece].edges.len() && s.b.edge < p.pieces[s.b.piece].edges.len());
    }
}

#[test]
fn garmentcode_shirt() {
    check_garmentcode("shirt_mean_specification.json", 8, 18);
    let p = read(&data("garmentcode/shirt_mean_specification.json"));
    // panel_order is respected, and back panels (clockwise in the file) are flagged.
    assert_eq!(p.pieces[0].name, "right_sleeve_b");
    let bt = p.pieces.iter().find(|x| x.name == "left_btorso").unwrap();
    let ft = p.pieces.iter().find(|x| x.name == "left_ftorso").unwrap();
    assert!(bt.placement.as_ref().unwrap().flipped && !ft.placement.as_ref().unwrap().flipped);
    // Reversed spans still start at the file's edge-0 start vertex (vertex 0 stays at index 0).
    assert_eq!(bt.edges[0].end, 0);
    assert_eq!(ft.edges[0].start, 0);
}

#[test]
fn garmentcode_hoody() {
    check_garmentcode("hoody_mean_specification.json", 6, 12);
}

#[test]
fn garmentcode_pencil_dress() {
    check_garmentcode("dress_pencil_specification.json", 6, 23);
}

#[test]
fn garmentcode_jumpsuit() {
    check_garmentcode("js_mean_all_specification.json", 12, 57);
}

#[test]
fn garmentcode_flared_skirt() {
    check_garmentcode("flare_skirt_specification.json", 4, 6);
}

#[test]
fn garmentcode_shared_copies_match() {
    for f in ["shirt_mean_specification.json", "flare_skirt_specification.json"] {
        let Some(s) = shared(&format!("garmentcode/{f}")) else { return };
        assert_eq!(read(&s).pieces, read(&data(&format!("garmentcode/{f}"))).pieces);
    }
}

#[test]
fn garmentcode_errors_name_panel_and_edge() {
    let text = std::fs::read_to_string(data("garmentcode/flare_skirt_specification.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["pattern"]["panels"]["wb_back"]["edges"][3]["endpoints"][1] = 42.into();
    let e = tailor_core::pattern::read_pattern_bytes(
        Path::new("skirt.json"),
        v.to_string().as_bytes(),
        &ReadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("skirt.json: panel \"wb_back\" edge 3: endpoint 42"), "{e}");
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["pattern"]["stitches"][2][1]["panel"] = "nope".into();
    let e = tailor_core::pattern::read_pattern_bytes(
        Path::new("skirt.json"),
        v.to_string().as_bytes(),
        &ReadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("stitch 2") && e.contains("\"nope\""), "{e}");
}

#[test]
fn garmentcode_stitches_sew_right_side_to_right_side_unless_marked() {
    let text = std::fs::read_to_string(data("garmentcode/hoody_mean_specification.json")).unwrap();
    let parse = |v: &serde_json::Value| {
        tailor_core::pattern::read_pattern_bytes(
            Path::new("hoody.json"),
            v.to_string().as_bytes(),
            &ReadOptions::default(),
        )
    };
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let p = parse(&v).unwrap();
    let turned: Vec<bool> = p.pieces.iter().map(|q| q.placement.as_ref().unwrap().flipped).collect();
    assert!(turned.iter().any(|&t| t) && turned.iter().any(|&t| !t), "the hoody has panels listed both ways");
    for (i, s) in p.stitches.iter().enumerate() {
        // The file's vertex order runs the two edges opposite; counter-clockwise after reading,
        // that is B against A unless exactly one of the two panels was turned round.
        assert_eq!(s.b_clockwise, turned[s.a.piece] == turned[s.b.piece], "stitch {i}");
    }
    let mut marked = v.clone();
    marked["pattern"]["stitches"][1].as_array_mut().unwrap().push("right_wrong".into());
    let q = parse(&marked).unwrap();
    assert_eq!(q.stitches[1].b_clockwise, !p.stitches[1].b_clockwise);
    assert_eq!(q.stitches[0], p.stitches[0]);
    let mut bad = v;
    bad["pattern"]["stitches"][4].as_array_mut().unwrap().push("inside_out".into());
    let e = parse(&bad).unwrap_err().to_string();
    assert!(e.contains("stitch 4") && e.contains("right_wrong"), "{e}");
}

/// A piece cut on the fold (`synthetic_fold.dxf`: its right half drawn, a mirror line on the
/// fold) is read as the whole piece: twice the half's area, symmetric about the fold, its notch,
/// turn point and internal line copied across (the notch a fixed vertex on both sides); with
/// `unfold` off, as drawn.
#[test]
fn a_piece_cut_on_the_fold_is_read_whole() {
    let path = data("dxf/synthetic_fold.dxf");
    let whole = read(&path);
    check_invariants(&whole);
    let drawn = read_pattern(&path, &ReadOptions { unfold: false, ..Default::default() }).unwrap();
    let (w, d) = (&whole.pieces[0], &drawn.pieces[0]);
    assert_eq!(w.name, "YOKE");
    close(outline::signed_area(&d.outline).abs(), 0.0481, 1e-9, "the half");
    close(outline::signed_area(&w.outline).abs(), 0.0962, 1e-9, "the whole piece");
    // Symmetric about x = 0: every vertex has its mirror image.
    for p in &w.outline {
        assert!(
            w.outline.iter().any(|q| (q[0] + p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12),
            "{p:?} has no mirror"
        );
    }
    assert_eq!((d.notches.len(), w.notches.len()), (1, 2));
    assert_eq!((d.internal_lines.len(), w.internal_lines.len()), (1, 2));
    for q in &w.notches {
        let i = w.outline.iter().position(|v| outline::dist(*v, *q) < 1e-9).expect("a notch on the outline");
        assert!(w.fixed_vertices.contains(&i), "notch {q:?} is not fixed");
    }
    assert_eq!(w.grain, d.grain);
}
