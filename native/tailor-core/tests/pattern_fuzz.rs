//! Robustness: thousands of deterministic mutations (byte flips, truncations, line deletions,
//! duplications and swaps, numbers replaced by extreme values) of every fixture and of the
//! shared real files must each return `Ok` or `Err` quickly: no panic, no hang. Plus a few
//! hand-written adversarial inputs (recursive INSERTs, deep nesting, huge curves).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tailor_core::pattern::{read_pattern_bytes, Pattern, ReadOptions};

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        // xorshift64*
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn corpus() -> Vec<(String, Vec<u8>)> {
    let mut dirs: Vec<PathBuf> = ["dxf", "svg", "garmentcode"]
        .iter()
        .map(|d| Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(d))
        .collect();
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/patterns/astm-parser-dxf");
    if shared.is_dir() {
        dirs.push(shared);
    } else {
        eprintln!("note: shared DXF files absent, fuzzing the repository fixtures only");
    }
    let mut out = Vec::new();
    for d in dirs {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().path()).collect();
        entries.sort();
        for p in entries {
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            if matches!(ext.as_str(), "dxf" | "svg" | "json") {
                out.push((p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out
}

const NUMBERS: &[&str] = &["1e308", "-1e308", "NaN", "inf", "0", "-0", "1e-300", "99999999999", "-1", "3", "1e6", ""];
const BYTES: &[u8] = b"0-.e\n\r<>\"{}[],: /zZaA";

fn lines(b: &[u8]) -> Vec<Vec<u8>> {
    b.split(|c| *c == b'\n').map(<[u8]>::to_vec).collect()
}

fn mutate(rng: &mut Rng, src: &[u8]) -> (Vec<u8>, String) {
    let mut b = src.to_vec();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(4) {
        if b.is_empty() {
            break;
        }
        match rng.below(8) {
            0 => {
                let i = rng.below(b.len());
                b[i] ^= 1 << rng.below(8);
                what.push(format!("flip@{i}"));
            }
            1 => {
                let i = rng.below(b.len());
                b[i] = BYTES[rng.below(BYTES.len())];
                what.push(format!("byte@{i}"));
            }
            2 => {
                let i = rng.below(b.len());
                b.truncate(i);
                what.push(format!("truncate@{i}"));
            }
            3..=5 => {
                let mut l = lines(&b);
                let i = rng.below(l.len());
                let j = rng.below(l.len());
                match rng.below(3) {
                    0 => {
                        l.remove(i);
                        what.push(format!("delete line {i}"));
                    }
                    1 => {
                        let dup = l[i].clone();
                        l.insert(j, dup);
                        what.push(format!("duplicate line {i} at {j}"));
                    }
                    _ => {
                        l.swap(i, j);
                        what.push(format!("swap lines {i} {j}"));
                    }
                }
                b = l.join(&b'\n');
            }
            _ => {
                // Replace the number starting at a random digit with an extreme value.
                let start = rng.below(b.len());
                if let Some(off) = b[start..].iter().position(u8::is_ascii_digit) {
                    let s = start + off;
                    let e = s + b[s..].iter().take_while(|c| c.is_ascii_digit() || **c == b'.').count();
                    let n = NUMBERS[rng.below(NUMBERS.len())];
                    b.splice(s..e, n.bytes());
                    what.push(format!("number@{s}={n}"));
                }
            }
        }
    }
    (b, what.join(", "))
}

fn check_ok(p: &Pattern) {
    for pc in &p.pieces {
        assert!(pc.outline.len() >= 3);
        assert!(pc.outline.iter().chain(pc.holes.iter().flatten()).all(|q| q[0].is_finite() && q[1].is_finite()));
        assert!(pc.fixed_vertices.iter().all(|&i| i < pc.outline.len()));
        assert!(pc.edges.iter().all(|s| s.start < pc.outline.len() && s.end < pc.outline.len()));
    }
    for s in &p.stitches {
        assert!(s.a.piece < p.pieces.len() && s.b.piece < p.pieces.len());
    }
}

/// Runs one input, failing the test on a panic or when it takes longer than `limit`. The limits
/// are hang guards (a reader looping forever), set far above the milliseconds an input takes so
/// that a loaded CI machine cannot trip them; speed is not what this test checks.
fn run(name: &str, bytes: &[u8], opts: &ReadOptions, what: &str, limit: Duration) -> bool {
    let t = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| read_pattern_bytes(Path::new(name), bytes, opts).map(|p| check_ok(&p))));
    let took = t.elapsed();
    assert!(r.is_ok(), "panic on {name} mutated by [{what}]");
    assert!(took < limit, "{name} mutated by [{what}] took {took:?}");
    matches!(r, Ok(Ok(())))
}

#[test]
fn mutated_files_never_panic_or_hang() {
    let corpus = corpus();
    // TAILOR_FUZZ_CASES / TAILOR_FUZZ_SEED allow longer local runs with other seeds.
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let mut rng = Rng(env("TAILOR_FUZZ_SEED").unwrap_or(0x7A11_0E5E_ED5E_ED01) | 1);
    let cases = env("TAILOR_FUZZ_CASES").unwrap_or(4000) as usize;
    let start = Instant::now();
    let (mut ok, mut err) = (0, 0);
    for case in 0..cases {
        let (name, src) = &corpus[case % corpus.len()];
        let (bytes, what) = mutate(&mut rng, src);
        // Sometimes hide the extension so that content sniffing is exercised too.
        let name = if rng.below(8) == 0 { "pattern".to_string() } else { name.clone() };
        let opts = ReadOptions {
            size: if rng.below(4) == 0 { Some("M".into()) } else { None },
            units_override: None,
            tolerance_m: [5e-4, 1e-6, 0.1][rng.below(3)],
            unfold: rng.below(2) == 0,
            quantities: rng.below(2) == 0,
        };
        if env("TAILOR_FUZZ_DUMP") == Some(case as u64) {
            std::fs::write(std::env::temp_dir().join(format!("fuzz-case-{case}-{name}")), &bytes).unwrap();
        }
        if std::env::var("TAILOR_FUZZ_TRACE").is_ok() {
            eprintln!("case {case}: {name} [{what}] tol {}", opts.tolerance_m);
        }
        if run(&name, &bytes, &opts, &what, Duration::from_secs(30)) {
            ok += 1;
        } else {
            err += 1;
        }
    }
    let took = start.elapsed();
    println!("{cases} mutated cases over {} files: {ok} read, {err} rejected, {took:?}", corpus.len());
}

#[test]
fn adversarial_inputs_terminate() {
    let opts = ReadOptions { tolerance_m: 1e-6, ..Default::default() };
    let lim = Duration::from_secs(60);
    // A block that inserts itself.
    let rec = "0\nSECTION\n2\nBLOCKS\n0\nBLOCK\n2\nB\n0\nINSERT\n2\nB\n0\nLWPOLYLINE\n70\n1\n10\n0\n20\n0\n10\n1\n20\n0\n10\n1\n20\n1\n0\nENDBLK\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n0\nINSERT\n2\nB\n0\nENDSEC\n0\nEOF\n";
    assert!(!run("rec.dxf", rec.as_bytes(), &opts, "recursive insert", lim));
    // A huge circle at the finest tolerance, and a spline with a bogus knot vector.
    let big = "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n10\n0\n20\n0\n40\n1e300\n0\nSPLINE\n71\n3\n40\n0\n40\n1e308\n10\n0\n20\n0\n10\n1\n20\n1\n0\nENDSEC\n0\nEOF\n";
    run("big.dxf", big.as_bytes(), &opts, "huge circle", lim);
    // Many loose LINEs forming one long zigzag loop (chaining must stay fast).
    let mut many = String::from("0\nSECTION\n2\nENTITIES\n");
    let n = 20_000;
    let pt = |i: usize| if i == n { (0.0, -1.0) } else { (i as f64, (i % 2) as f64) };
    for i in 0..=n {
        let (a, b) = (pt(i), if i == n { pt(0) } else { pt(i + 1) });
        many += &format!("0\nLINE\n10\n{}\n20\n{}\n11\n{}\n21\n{}\n", a.0, a.1, b.0, b.1);
    }
    many += "0\nENDSEC\n0\nEOF\n";
    assert!(run("many.dxf", many.as_bytes(), &ReadOptions::default(), "20k lines", lim));
    // Deeply nested SVG groups and JSON arrays.
    let deep = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\">{}<rect width=\"1\" height=\"1\"/>{}</svg>",
        "<g>".repeat(5000),
        "</g>".repeat(5000)
    );
    run("deep.svg", deep.as_bytes(), &opts, "deep svg", lim);
    let deep = format!("{{\"pattern\":{}{}}}", "[".repeat(100_000), "]".repeat(100_000));
    assert!(!run("deep.json", deep.as_bytes(), &opts, "deep json", lim));
    // A path with a million segments.
    let long = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0{}Z\"/></svg>",
        " l 1 1 l -1 1".repeat(500_000)
    );
    run("long.svg", long.as_bytes(), &opts, "long path", lim);
    // GarmentCode: an arc radius shorter than half its chord, and an edge loop that never closes.
    let gc = r#"{"pattern":{"panels":{"p":{"vertices":[[0,0],[10,0],[10,10]],"edges":[{"endpoints":[0,1],"curvature":{"type":"circle","params":[1,0,1]}},{"endpoints":[1,2]},{"endpoints":[2,0]}]}},"stitches":[]}}"#;
    assert!(!run("gc.json", gc.as_bytes(), &opts, "short radius", lim));
}
