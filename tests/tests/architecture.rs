//! The kernel's module graph has no cycle: every `use crate::…` or
//! `use super::…` of a file in `core/src` points down a layered order
//! (`float` before `sampler`, a trait file before the files that implement
//! it, ...), so each module can be read knowing only the ones it imports.
//! A cycle would mean two modules that can only be understood together.
//!
//! The graph is read from the source text: a module is a file, an edge is a
//! path starting with `crate::` or `super::` outside comments and outside
//! `#[cfg(test)]` modules, and a parent's `pub use child::…` (a re-export
//! makes whoever imports it depend on the child).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, by module path (`sampler::hrla`).
fn modules(dir: &Path, prefix: &[String], out: &mut BTreeMap<String, PathBuf>) {
    for entry in fs::read_dir(dir).expect("readable source folder") {
        let path = entry.expect("entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            let mut p = prefix.to_vec();
            p.push(name);
            modules(&path, &p, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let mut p = prefix.to_vec();
            if name != "mod" && name != "lib" {
                p.push(name);
            }
            out.insert(p.join("::"), path);
        }
    }
}

/// The source without comments and without its `#[cfg(test)]` module.
fn code(src: &str) -> String {
    let src = match src.find("#[cfg(test)]\nmod tests") {
        Some(i) => &src[..i],
        None => src,
    };
    src.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The module a path names, resolved from module `current`: its longest
/// prefix that is a module.
fn target(current: &str, path: &str, mods: &BTreeMap<String, PathBuf>) -> Option<String> {
    let mut segs: Vec<&str> = path.split("::").collect();
    let mut base: Vec<&str> = if current.is_empty() {
        vec![]
    } else {
        current.split("::").collect()
    };
    match segs[0] {
        "crate" => base.clear(),
        "super" => {
            while segs.first() == Some(&"super") {
                base.pop();
                segs.remove(0);
            }
            return resolve(&base, &segs, mods);
        }
        _ => return None,
    }
    segs.remove(0);
    resolve(&base, &segs, mods)
}

fn resolve(base: &[&str], segs: &[&str], mods: &BTreeMap<String, PathBuf>) -> Option<String> {
    (0..=segs.len()).rev().find_map(|i| {
        let m: Vec<&str> = base.iter().chain(&segs[..i]).copied().collect();
        let m = m.join("::");
        mods.contains_key(&m).then_some(m)
    })
}

/// Edges of the graph: the paths each file uses, `use` groups expanded one
/// level (`use super::{a::X, b::Y}`).
fn edges(mods: &BTreeMap<String, PathBuf>) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph = BTreeMap::new();
    for (m, path) in mods {
        let src = code(&fs::read_to_string(path).expect("readable source"));
        let mut out = BTreeSet::new();
        let mut paths = Vec::new();
        for stmt in src.split(';') {
            // `a::B as C` names module `a` whatever the alias.
            let stmt: String = stmt
                .split(" as ")
                .enumerate()
                .map(|(i, part)| {
                    if i == 0 {
                        part
                    } else {
                        part.trim_start()
                            .split_once(|c: char| !(c.is_alphanumeric() || c == '_'))
                            .map_or("", |(_, rest)| rest)
                    }
                })
                .collect::<String>()
                .split_whitespace()
                .collect();
            let Some(i) = stmt.find("use") else { continue };
            let body = &stmt[i + 3..];
            let child = format!(
                "{m}{}{}",
                if m.is_empty() { "" } else { "::" },
                body.split("::").next().unwrap_or("")
            );
            if mods.contains_key(&child) && &child != m {
                // A re-export of a child module's items.
                out.insert(child);
                continue;
            }
            if !(body.starts_with("crate::") || body.starts_with("super::")) {
                continue;
            }
            match body.split_once("::{") {
                Some((head, rest)) => {
                    for item in rest.trim_end_matches('}').split(',') {
                        paths.push(format!("{head}::{item}"));
                    }
                }
                None => paths.push(body.to_string()),
            }
        }
        // Paths written out in the code, outside `use`.
        for word in src.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':')) {
            if word.starts_with("crate::") || word.starts_with("super::") {
                paths.push(word.to_string());
            }
        }
        for p in paths {
            if let Some(t) = target(m, &p, mods)
                && &t != m
            {
                out.insert(t);
            }
        }
        graph.insert(m.clone(), out);
    }
    graph
}

/// A cycle of the graph, if any (depth-first search).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        v: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(v.to_string(), 1);
        stack.push(v.to_string());
        for w in &graph[v] {
            match state.get(w.as_str()) {
                Some(1) => {
                    let i = stack.iter().position(|s| s == w).unwrap();
                    let mut cycle = stack[i..].to_vec();
                    cycle.push(w.clone());
                    return Some(cycle);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(w, graph, state, stack) {
                        return Some(c);
                    }
                }
            }
        }
        stack.pop();
        state.insert(v.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for v in graph.keys() {
        if !state.contains_key(v.as_str())
            && let Some(c) = visit(v, graph, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

/// Every module of the kernel, `core/src`.
fn kernel_modules() -> BTreeMap<String, PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/src");
    let mut mods = BTreeMap::new();
    modules(&root, &[], &mut mods);
    mods
}

#[test]
fn the_kernel_has_no_import_cycle() {
    let mods = kernel_modules();
    let graph = edges(&mods);
    // The reader must see the edges it is meant to: a sample of known ones.
    assert!(graph["sampler::hrla"].contains("sampler::traits"));
    assert!(graph["sampler::hrla"].contains("sampler::ou"));
    assert!(graph["float"].contains("normal"));
    assert!(graph["sampler"].contains("sampler::hrla"));
    assert!(graph["potential::rastrigin"].contains("lanes"));
    if let Some(cycle) = find_cycle(&graph) {
        panic!("import cycle: {}", cycle.join(" -> "));
    }
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    assert!(find_cycle(&graph).is_some());
}

/// The workspace's crates by package name, each with the workspace crates
/// it depends on (its `[dependencies]`, dev-dependencies left out: a test
/// may compare two crates).
fn crate_graph() -> BTreeMap<String, BTreeSet<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let manifest = fs::read_to_string(root.join("Cargo.toml")).expect("workspace manifest");
    let members = manifest
        .lines()
        .find(|l| l.starts_with("members"))
        .expect("a members list");
    let dirs: Vec<&str> = members.split('"').skip(1).step_by(2).collect();
    let mut names = BTreeMap::new();
    let mut deps = BTreeMap::new();
    for dir in &dirs {
        let text = fs::read_to_string(root.join(dir).join("Cargo.toml")).expect("crate manifest");
        let name = text
            .lines()
            .find_map(|l| l.strip_prefix("name = \""))
            .and_then(|l| l.strip_suffix('"'))
            .expect("a package name")
            .to_string();
        let mut section = "";
        let mut uses = BTreeSet::new();
        for line in text.lines() {
            if line.starts_with('[') {
                section = line;
            } else if section == "[dependencies]"
                && let Some((dep, _)) = line.split_once('=')
            {
                uses.insert(dep.trim().to_string());
            }
        }
        names.insert(name.clone(), ());
        deps.insert(name, uses);
    }
    deps.into_iter()
        .map(|(k, v)| {
            let v = v.into_iter().filter(|d| names.contains_key(d)).collect();
            (k, v)
        })
        .collect()
}

/// The run-time layer sits between the kernel and the front ends: every
/// front end depends on it, none on another front end, the layer on no
/// front end, and the crates' graph has no cycle.
#[test]
fn front_ends_depend_on_the_layer_not_on_each_other() {
    let graph = crate_graph();
    let front_ends = ["hrla-python", "hrla-wasm", "hrla-repro"];
    assert!(graph["hrla-dyn"].contains("hrla"));
    for f in front_ends {
        assert!(graph[f].contains("hrla-dyn"), "{f} does not use the layer");
        for other in front_ends {
            assert!(!graph[f].contains(other), "{f} depends on {other}");
            assert!(
                !graph["hrla-dyn"].contains(other),
                "the layer depends on {other}"
            );
        }
    }
    assert!(
        graph["hrla"].is_empty(),
        "the kernel depends on {:?}",
        graph["hrla"]
    );
    if let Some(cycle) = find_cycle(&graph) {
        panic!("crate cycle: {}", cycle.join(" -> "));
    }
}

/// The module graph of a crate's sources (`src` of the crate at `dir`).
fn crate_modules(dir: &str) -> BTreeMap<String, BTreeSet<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(dir)
        .join("src");
    let mut mods = BTreeMap::new();
    modules(&root, &[], &mut mods);
    edges(&mods)
}

/// Every other crate's modules are layered too, but for the circles named
/// in `known` (each a place where two modules would still share one idea).
#[test]
fn the_other_crates_have_no_import_cycle_but_the_known_ones() {
    // (crate folder, [from, to]): none left.
    let known: [(&str, [&str; 2]); 0] = [];
    let mut found = Vec::new();
    for dir in ["dyn", "gpu", "wasm", "python", "tools/repro", "threads"] {
        let mut graph = crate_modules(dir);
        // The crate root is its facade: modules import the items it
        // re-exports, and it imports every module.
        graph.remove("");
        for out in graph.values_mut() {
            out.remove("");
        }
        // Cut each known circle at one edge; any other cycle fails.
        for (_, [from, to]) in known.iter().filter(|(d, _)| *d == dir) {
            // `a::*`: every child of `a`.
            let children = from.strip_suffix("::*").map(|a| format!("{a}::"));
            for (m, out) in graph.iter_mut() {
                if m == from || children.as_ref().is_some_and(|c| m.starts_with(c.as_str())) {
                    out.remove(*to);
                }
            }
        }
        if let Some(cycle) = find_cycle(&graph) {
            found.push(format!("{dir}: {}", cycle.join(" -> ")));
        }
    }
    assert!(found.is_empty(), "import cycles: {found:#?}");
}

/// The product sources: every `.rs` file of the workspace's crates but
/// their tests, benchmarks and examples.
fn product_sources() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut out = Vec::new();
    for dir in [
        "core",
        "dyn",
        "gpu",
        "wasm",
        "python",
        "tools/repro",
        "threads",
    ] {
        let mut mods = BTreeMap::new();
        modules(&root.join(dir).join("src"), &[], &mut mods);
        for path in mods.into_values() {
            let text = fs::read_to_string(&path).expect("readable source");
            out.push((path, code(&text)));
        }
    }
    out
}

/// Algorithm 1's loop (stop rules, a step, the observer) is written once,
/// in the optimiser; the front ends drive it, they do not repeat it.
#[test]
fn the_run_loop_exists_once() {
    let loops: Vec<String> = product_sources()
        .into_iter()
        .filter(|(_, src)| {
            src.split("loop {").skip(1).any(|body| {
                let body = &body[..body.len().min(1_500)];
                body.contains(".termination()") || body.contains("self.termination()")
            })
        })
        .map(|(path, _)| path.display().to_string())
        .collect();
    assert_eq!(loops.len(), 1, "the run loop is written in {loops:?}");
    assert!(
        loops[0].ends_with("core/src/optimizer/algorithm.rs"),
        "{loops:?}"
    );
}

/// The twins of the run-time path are gone: one optimiser, one build,
/// one problem and two entry points for `Auto`, whose stopping rules are
/// the kernel's (a front end keeps none of its own).
#[test]
fn no_twin_of_the_optimiser() {
    for (path, src) in product_sources() {
        for twin in [
            "FlatOptimizer",
            "build_flat",
            "fn step_on(",
            "fn run_on(",
            "FlatProgress",
            "FlatAutoProgress",
            "FlatSolution",
            "minimize_flat",
            "fn minimize_from(",
        ] {
            assert!(!src.contains(twin), "{} still has {twin}", path.display());
        }
    }
}

/// Python's watch of a run keeps only what is Python's own (the time
/// limit, the callback, the progress line): the target, stall and round
/// limits are the kernel's rules, for `auto` as for the samplers. How a
/// budget is shared (a sampler's polish, `Auto`'s share before the
/// ensemble) is the layer's too (`hrla_dyn::budget`).
#[test]
fn python_keeps_no_stopping_rule_of_its_own() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let src = fs::read_to_string(root.join("python/hrla/_minimize.py")).expect("readable source");
    let start = src.find("class _Watch").expect("the watch");
    let end = src[start..]
        .find("\n\n\ndef ")
        .map_or(src.len(), |e| start + e);
    let watch = &src[start..end];
    for rule in ["self.target", "self.stall", "self.maxiter", "by_round"] {
        assert!(!watch.contains(rule), "_Watch still checks {rule}");
    }
    for share in ["ENSEMBLE_CALLS", "ENSEMBLE_GRADIENTS", "POLISH"] {
        assert!(!src.contains(share), "_minimize.py keeps {share}");
    }
    for rule in ["auto_share(", "split_budget("] {
        assert!(
            src.contains(rule),
            "_minimize.py does not ask the layer's {rule}"
        );
    }
}

/// The functions of `src` longer than `limit` lines, as `name (lines)`:
/// from a `fn` line to the first line after it that is its indentation
/// and a closing brace (rustfmt's layout), signatures included.
fn long_functions(src: &str, limit: usize) -> Vec<String> {
    let lines: Vec<&str> = src.lines().collect();
    let mut long = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let body = line.trim_start();
        let indent = line.len() - body.len();
        let Some(at) = body.find("fn ") else {
            continue;
        };
        // An item's head: a visibility, then `const`, each optional.
        let head = ["pub(crate) ", "pub(super) ", "pub "]
            .iter()
            .find_map(|v| body[..at].strip_prefix(v))
            .unwrap_or(&body[..at]);
        let is_item = head.is_empty() || head == "const ";
        if !is_item || body.ends_with(';') {
            continue;
        }
        let close = format!("{}}}", " ".repeat(indent));
        if let Some(end) = lines[i + 1..].iter().position(|l| l.trim_end() == close) {
            let n = end + 2;
            if n > limit {
                let name: String = body[at + 3..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                long.push(format!("{name} ({n})"));
            }
        }
    }
    long
}

/// No kernel function is over 80 lines: a longer one holds steps that
/// want names of their own (as `Auto`'s run is written, step by step).
#[test]
fn no_kernel_function_is_over_80_lines() {
    let mut long = Vec::new();
    for (module, path) in kernel_modules() {
        let src = code(&fs::read_to_string(&path).expect("readable source"));
        for f in long_functions(&src, 80) {
            long.push(format!("{module}::{f}"));
        }
    }
    assert!(long.is_empty(), "functions over 80 lines: {long:?}");
}

#[test]
fn the_length_guard_counts_a_function_from_fn_to_its_brace() {
    let body = "    let x = 1;\n".repeat(79);
    let src = format!("pub fn long() {{\n{body}}}\n\nfn short() {{\n}}\n");
    assert_eq!(long_functions(&src, 80), ["long (81)"]);
    assert!(long_functions(&src, 81).is_empty());
    let src = format!("    pub(super) const fn long() {{\n{body}    }}\n");
    assert_eq!(long_functions(&src, 80), ["long (81)"]);
}
