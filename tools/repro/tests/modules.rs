//! The library's modules import one way: no chain of `crate::` paths leads
//! from a module back to itself (test modules included), so a lower module
//! never depends on a higher one.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

/// Each module of `src/` (a directory module is one module, its files
/// together) and the modules its code names through `crate::`, outside
/// comments.
fn imports() -> BTreeMap<String, Vec<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut text: BTreeMap<String, String> = BTreeMap::new();
    for entry in fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if name == "lib" || name == "main" {
            continue;
        }
        let files = if path.is_dir() {
            fs::read_dir(&path)
                .unwrap()
                .map(|f| fs::read_to_string(f.unwrap().path()).unwrap())
                .collect()
        } else {
            vec![fs::read_to_string(&path).unwrap()]
        };
        text.insert(name, files.concat());
    }
    let modules: Vec<String> = text.keys().cloned().collect();
    text.iter()
        .map(|(name, code)| {
            let code: String = code
                .lines()
                .filter(|l| !l.trim_start().starts_with("//"))
                .collect::<Vec<_>>()
                .join("\n");
            // The identifier after each `crate::`.
            let named: Vec<&str> = code
                .split("crate::")
                .skip(1)
                .map(|rest| {
                    let end = rest
                        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                        .unwrap_or(rest.len());
                    &rest[..end]
                })
                .collect();
            let uses = modules
                .iter()
                .filter(|m| *m != name && named.contains(&m.as_str()))
                .cloned()
                .collect();
            (name.clone(), uses)
        })
        .collect()
}

/// A cycle through `at`, if the graph has one reachable from it.
fn cycle(
    graph: &BTreeMap<String, Vec<String>>,
    at: &str,
    path: &mut Vec<String>,
    done: &mut Vec<String>,
) -> Option<Vec<String>> {
    if let Some(i) = path.iter().position(|m| m == at) {
        let mut found = path[i..].to_vec();
        found.push(at.to_string());
        return Some(found);
    }
    if done.iter().any(|m| m == at) {
        return None;
    }
    path.push(at.to_string());
    for next in &graph[at] {
        if let Some(c) = cycle(graph, next, path, done) {
            return Some(c);
        }
    }
    path.pop();
    done.push(at.to_string());
    None
}

#[test]
fn modules_import_one_way() {
    let graph = imports();
    // The walk sees the modules it should: the kernel's adapter is
    // imported, and the error type imports none above it.
    assert!(graph["engine"].contains(&"kernel".to_string()), "{graph:?}");
    assert!(graph["config"].contains(&"error".to_string()), "{graph:?}");
    let (mut path, mut done) = (Vec::new(), Vec::new());
    for module in graph.keys() {
        if let Some(c) = cycle(&graph, module, &mut path, &mut done) {
            panic!("an import cycle: {}", c.join(" -> "));
        }
    }
}
