//! The core's folders are layers: a module imports only the layers below it.
//!
//! Reads every `crate::…` and `super::…` path in the code of `src/` (comments and test-only
//! code left out) and checks, as documented in `src/lib.rs`, `src/solver/mod.rs` and
//! `docs/architecture.md`:
//!
//! * the pipeline's layers, `collision` < `quality` < `solver` < `gpu` < `engine`: the CPU
//!   solver imports neither the GPU backend nor the facade above both;
//! * inside the solver, `model` < `stages` < `stats` < `collide` < `sleep` < `simulation` <
//!   `accuracy`: the parts never import the simulation that runs them; code inside the solver
//!   names the submodule it uses, not the solver's re-exports, so that the order can be read;
//! * no cycle among the top-level modules of `src/`.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

const PIPELINE: &[&str] = &["collision", "quality", "solver", "gpu", "engine"];
const SOLVER: &[&str] = &["model", "stages", "stats", "collide", "sleep", "simulation", "accuracy"];

/// `(module of the file, path it uses)` for every path in the code of `src/`.
type Uses = Vec<(Vec<String>, Vec<String>)>;

fn module_of(rel: &Path) -> Vec<String> {
    let mut m: Vec<String> = rel.with_extension("").iter().map(|c| c.to_string_lossy().into_owned()).collect();
    if matches!(m.last().map(String::as_str), Some("mod" | "lib")) {
        m.pop();
    }
    m
}

fn ident_at(s: &str) -> Option<&str> {
    let end = s.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(s.len());
    (end > 0).then(|| &s[..end])
}

/// The absolute paths a file's code names (`module`: the file's module path).
fn uses_in(module: &[String], text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    // Depth of braces, and the depth at which each inline module (`mod x { … }`) opened.
    let (mut depth, mut inline): (usize, Vec<(usize, bool)>) = (0, Vec::new());
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let trimmed = code.trim_start();
        let word = trimmed.trim_start_matches("pub(crate) ").trim_start_matches("pub ");
        if let (Some(rest), true) = (word.strip_prefix("mod "), code.trim_end().ends_with('{')) {
            inline.push((depth, ident_at(rest) == Some("tests")));
        }
        let in_tests = inline.iter().any(|&(_, t)| t);
        let here: Vec<String> = module.iter().cloned().chain(inline.iter().map(|_| "inline".to_string())).collect();
        for (at, _) in code.match_indices("crate::").chain(code.match_indices("super::")) {
            if at > 0 && code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let mut rest = &code[at..];
            let mut path: Vec<String> = Vec::new();
            if let Some(r) = rest.strip_prefix("crate::") {
                rest = r;
            } else {
                path = here.clone();
                while let Some(r) = rest.strip_prefix("super::") {
                    path.pop();
                    rest = r;
                }
            }
            let mut names = vec![];
            if let Some(group) = rest.strip_prefix('{') {
                // `crate::{a::b, c}`: the first name of each item (one level is enough here).
                let group = &group[..group.find('}').unwrap_or(group.len())];
                names.extend(group.split(',').filter_map(|item| ident_at(item.trim())));
            } else {
                names.extend(ident_at(rest));
                let mut r = &rest[names.first().map_or(0, |n| n.len())..];
                while let Some(next) = r.strip_prefix("::").and_then(ident_at) {
                    names.push(next);
                    r = &r[2 + next.len()..];
                }
            }
            if !in_tests && !path.iter().any(|p| p == "inline") {
                if let Some((first, more)) = names.split_first() {
                    if rest.starts_with('{') {
                        for n in &names {
                            out.push(path.iter().cloned().chain([n.to_string()]).collect());
                        }
                    } else {
                        out.push(
                            path.iter()
                                .cloned()
                                .chain([first.to_string()])
                                .chain(more.iter().map(|s| s.to_string()))
                                .collect(),
                        );
                    }
                }
            }
        }
        for c in code.chars() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if inline.last().is_some_and(|&(d, _)| d == depth) {
                        inline.pop();
                    }
                }
                _ => {}
            }
        }
    }
    out
}

fn all_uses(src: &Path) -> Uses {
    let mut out = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let module = module_of(p.strip_prefix(src).unwrap());
                // Test-only files: their imports are not the library's layering.
                if matches!(module.last().map(String::as_str), Some("tests" | "test_util")) {
                    continue;
                }
                for u in uses_in(&module, &fs::read_to_string(&p).unwrap()) {
                    out.push((module.clone(), u));
                }
            }
        }
    }
    out
}

fn rank(order: &[&str], name: Option<&String>) -> Option<usize> {
    order.iter().position(|o| Some(*o) == name.map(String::as_str))
}

/// What breaks the documented layers, one line each.
fn violations(uses: &Uses) -> Vec<String> {
    let mut bad = BTreeSet::new();
    let mut graph: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for (from, to) in uses {
        let (Some(a), Some(b)) = (from.first(), to.first()) else { continue };
        if a != b {
            graph.entry(a).or_default().insert(b);
        }
        if let (Some(ra), Some(rb)) = (rank(PIPELINE, Some(a)), rank(PIPELINE, Some(b))) {
            if rb > ra {
                bad.insert(format!("{} uses {} (layer {b} is above {a})", from.join("::"), to.join("::")));
            }
        }
        if a == "solver" && b == "solver" {
            let (ra, rb) = (rank(SOLVER, from.get(1)), rank(SOLVER, to.get(1)));
            match (ra, rb) {
                (_, None) if to.len() > 1 => {
                    bad.insert(format!(
                        "{} uses {}: name the submodule, not a re-export",
                        from.join("::"),
                        to.join("::")
                    ));
                }
                (Some(ra), Some(rb)) if rb > ra => {
                    bad.insert(format!(
                        "{} uses {} (solver::{} is above solver::{})",
                        from.join("::"),
                        to.join("::"),
                        SOLVER[rb],
                        SOLVER[ra]
                    ));
                }
                _ => {}
            }
        }
    }
    // A cycle among the top-level modules: depth-first search for a back edge.
    fn visit<'a>(
        n: &'a str,
        g: &BTreeMap<&'a str, BTreeSet<&'a str>>,
        path: &mut Vec<&'a str>,
        done: &mut BTreeSet<&'a str>,
        bad: &mut BTreeSet<String>,
    ) {
        if let Some(i) = path.iter().position(|&p| p == n) {
            bad.insert(format!("cycle: {} -> {n}", path[i..].join(" -> ")));
            return;
        }
        if !done.insert(n) {
            return;
        }
        path.push(n);
        for &m in g.get(n).into_iter().flatten() {
            visit(m, g, path, done, bad);
        }
        path.pop();
    }
    let mut done = BTreeSet::new();
    for &n in graph.keys() {
        visit(n, &graph, &mut Vec::new(), &mut done, &mut bad);
    }
    bad.into_iter().collect()
}

#[test]
fn the_core_imports_only_the_layers_below() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let uses = all_uses(&src);
    assert!(uses.len() > 300, "only {} paths read: is the reader broken?", uses.len());
    let bad = violations(&uses);
    assert!(bad.is_empty(), "the layers of docs/architecture.md are broken:\n{}", bad.join("\n"));
}

/// The reader and the rules catch what they are for (so that the test above can fail).
#[test]
fn a_broken_layer_is_caught() {
    let m = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    let case = |file: &str, text: &str| -> Vec<String> {
        let uses: Uses = uses_in(&m(file), text).into_iter().map(|u| (m(file), u)).collect();
        violations(&uses)
    };
    // The CPU solver using the GPU backend or the facade.
    assert_eq!(case("solver::simulation", "use crate::gpu::GpuSolver;").len(), 1);
    assert_eq!(case("solver::stages::local", "    let s: crate::engine::Solver;").len(), 1);
    // A part of the solver importing the simulation, through `super::` too.
    assert_eq!(case("solver::collide", "use super::simulation::Simulation;").len(), 1);
    assert_eq!(case("solver::collide::levels", "use super::super::{simulation::Simulation, model};").len(), 1);
    // A re-export named inside the solver.
    assert_eq!(case("solver::stages", "use crate::solver::Simulation;").len(), 1);
    // A cycle between two top-level modules.
    let mut uses: Uses = vec![(m("mesh"), m("io::obj")), (m("io"), m("mesh::ClothMesh"))];
    assert_eq!(violations(&uses), ["cycle: io -> mesh -> io"]);
    uses.pop();
    assert!(violations(&uses).is_empty());
    // What is allowed: down the layers, comments, test modules.
    assert!(case("gpu", "use crate::solver::Simulation; // crate::engine::Solver").is_empty());
    assert!(case("solver::simulation", "use crate::solver::model::Model;\nuse super::stages::STAGES;").is_empty());
    assert!(case("collision::hash", "#[cfg(test)]\nmod tests {\n    use crate::solver::Simulation;\n}\n").is_empty());
    let after = "mod tests {\n    use super::*;\n}\nuse crate::gpu::X;\n";
    assert_eq!(case("solver::model", after).len(), 1, "the code after an inline module is read again");
}
