//! End-to-end tests of the `repro` binary, each into a temporary directory.
//! `repro all --quick`: every protocol's outputs exist and are well formed
//! (CSV columns and row counts, numbers parse, probabilities in [0, 1], SVG
//! is XML with one captioned panel per tolerance or listed pair, metadata
//! with the right chain-step count). A bad option fails before anything is
//! written, and the thread count does not change a byte of the outputs.

use std::collections::HashSet;
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use hrla_repro::output::{CURVE_COLUMNS, SUMMARY_COLUMNS};
use hrla_repro::protocol::{Overrides, ProtocolId, plan};
use hrla_repro::stats::grid_points;

/// Splits a CSV line of this tool's output (quoted fields have no quotes
/// inside).
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
}

fn read_csv(path: &Path, columns: &[&str]) -> Vec<Vec<String>> {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(
        lines.next().map(fields).unwrap(),
        columns,
        "{}",
        path.display()
    );
    lines
        .map(|l| {
            let f = fields(l);
            assert_eq!(f.len(), columns.len(), "{}: `{l}`", path.display());
            f
        })
        .collect()
}

/// Runs the binary with `args` and `--out dir`; stdout and stderr are
/// captured, and stderr is shown when a run that should succeed fails.
fn repro(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(args)
        .arg("--out")
        .arg(dir)
        .output()
        .unwrap()
}

fn assert_success(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every text of an SVG figure, trimmed.
fn svg_texts(doc: &roxmltree::Document) -> HashSet<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect()
}

fn num(row: &[String], columns: &[&str], name: &str) -> f64 {
    let i = columns.iter().position(|c| *c == name).unwrap();
    row[i]
        .parse()
        .unwrap_or_else(|_| panic!("column {name}: `{}` is not a number", row[i]))
}

#[test]
fn quick_all_writes_well_formed_outputs() {
    let dir = tempfile::tempdir().unwrap();
    assert_success(&repro(&["all", "--quick", "--quiet"], dir.path()));
    for id in ProtocolId::ALL {
        let p = plan(id, &Overrides::default(), true).unwrap();
        let sub = dir.path().join(id.name().to_lowercase());

        let rows = read_csv(&sub.join("summary.csv"), &SUMMARY_COLUMNS);
        let checkpoints: usize = p.configs.iter().map(|c| c.checkpoints.len()).sum();
        assert_eq!(rows.len(), checkpoints, "{}", id.name());
        for row in &rows {
            for col in ["mean", "median", "sd", "se", "min", "max"] {
                let v = num(row, &SUMMARY_COLUMNS, col);
                assert!(v.is_finite() && v >= 0.0, "{} {col} = {v}", id.name());
            }
            assert_eq!(num(row, &SUMMARY_COLUMNS, "M"), p.runs as f64);
            let (mean, min, max) = (
                num(row, &SUMMARY_COLUMNS, "mean"),
                num(row, &SUMMARY_COLUMNS, "min"),
                num(row, &SUMMARY_COLUMNS, "max"),
            );
            assert!(min <= mean && mean <= max);
        }

        let md = fs::read_to_string(sub.join("summary.md")).unwrap();
        assert_eq!(
            md.lines().filter(|l| l.starts_with('|')).count(),
            checkpoints + 2
        );

        let meta = fs::read_to_string(sub.join("meta.txt")).unwrap();
        assert!(meta.contains(&format!("chain-steps: {}\n", p.chain_steps())));
        let wall: f64 = meta
            .lines()
            .find_map(|l| l.strip_prefix("wall seconds: "))
            .unwrap()
            .parse()
            .unwrap();
        assert!(wall >= 0.0);

        if id.is_table() {
            assert!(!sub.join("curves.csv").exists());
            continue;
        }
        let curves = read_csv(&sub.join("curves.csv"), &CURVE_COLUMNS);
        let expected: usize = p
            .configs
            .iter()
            .map(|c| c.eps.len() * grid_points(c.steps, c.curve_every))
            .sum();
        assert_eq!(curves.len(), expected, "{}", id.name());
        for row in &curves {
            let prob = num(row, &CURVE_COLUMNS, "probability");
            let hits = num(row, &CURVE_COLUMNS, "hits");
            assert!((0.0..=1.0).contains(&prob));
            assert_eq!(prob, hits / p.runs as f64);
        }

        let svg_path = sub.join(format!("{}.svg", id.name().to_lowercase()));
        let svg = fs::read_to_string(&svg_path).unwrap();
        let doc = roxmltree::Document::parse(&svg)
            .unwrap_or_else(|e| panic!("{}: {e}", svg_path.display()));
        assert_eq!(doc.root_element().tag_name().name(), "svg");
        let texts = svg_texts(&doc);
        for panel in &p.panels {
            assert!(
                texts.contains(&panel.title),
                "{}: no panel `{}`",
                id.name(),
                panel.title
            );
        }
        // One polyline per (panel, curve) at least.
        let lines = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .count();
        assert!(lines >= p.panels.len(), "{}: {lines} polylines", id.name());
    }
}

#[test]
fn bad_options_fail_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let out = repro(&["e5", "--quick", "--quiet", "--a", "3"], dir.path());
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--a-high"));
    assert!(!dir.path().join("e5").exists());
}

/// End to end through the binary: one worker thread and two give the same
/// tables and curves, byte for byte.
#[test]
fn outputs_do_not_depend_on_the_thread_count() {
    let run = |threads: &str| {
        let dir = tempfile::tempdir().unwrap();
        let args = ["e2", "--quick", "--quiet", "--threads", threads];
        assert_success(&repro(&args, dir.path()));
        let read = |f: &str| fs::read_to_string(dir.path().join("e2").join(f)).unwrap();
        (read("summary.csv"), read("curves.csv"), read("e2.svg"))
    };
    assert_eq!(run("1"), run("2"));
}

/// T3 runs the four peers beside HRLA: its comparison table has a row per
/// configuration and checkpoint with the copied figures beside the peers
/// from (1, ..., 1), its cost table a row per configuration, and its
/// figure one captioned panel per checkpoint.
#[test]
fn t3_runs_the_peers_beside_hrla() {
    let dir = tempfile::tempdir().unwrap();
    let out = repro(&["t3", "--quick", "--a-high", "4"], dir.path());
    assert_success(&out);
    let sub = dir.path().join("t3");
    let comparison = fs::read_to_string(sub.join("comparison.md")).unwrap();
    let rows: Vec<&str> = comparison
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| method"))
        .collect();
    // (HRLA + 4 peers) x 2 starts x 2 checkpoints (k = 1 and 10).
    assert_eq!(rows.len(), 5 * 2 * 2);
    for peer in ["SA", "FSA", "SMC-SA", "CSA"] {
        let from_one = format!("| {peer} (1,...,1) |");
        assert_eq!(
            rows.iter().filter(|r| r.starts_with(&from_one)).count(),
            2,
            "{peer}"
        );
    }
    // The quick run reads k = 1 and 10: the paper has no figure there.
    assert!(rows.iter().all(|r| r.contains("| - | - |")));
    let cost = fs::read_to_string(sub.join("cost.md")).unwrap();
    assert_eq!(cost.lines().filter(|l| l.starts_with("| SA ")).count(), 2);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("| CSA N(3·1, 10 I) |"));
    let svg = fs::read_to_string(sub.join("t3.svg")).unwrap();
    let texts = svg_texts(&roxmltree::Document::parse(&svg).unwrap());
    for caption in [
        "k = 1",
        "k = 10",
        "CSA (1,...,1)",
        "HRLA a_high=4 (1,...,1)",
    ] {
        assert!(texts.contains(caption), "no `{caption}` in the figure");
    }
    let refused = repro(&["e1", "--quick", "--peers", "sa"], dir.path());
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("apply to T3"));
}
