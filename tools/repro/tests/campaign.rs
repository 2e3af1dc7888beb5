//! A seeded campaign of hostile inputs to the `repro` binary: random
//! option sets (sizes at and beyond their limits, non-finite and extreme
//! floats, malformed numbers) and random damage to valid shard files
//! (lines deleted, doubled, swapped or inserted, files cut short, bytes
//! flipped, numbers changed, plans and files swapped with those of
//! another seed, files renamed, added or removed), with or without the
//! checksum recomputed afterwards.
//!
//! Every case must end (a generous bound turns a hang into a failure),
//! with exit status 0, 1 (a typed error) or 2 (a usage error from the
//! option parser), never a panic or a signal; a refusal says why on
//! stderr. A success must leave tables whose statistics are finite and
//! non-negative, whose hit counts are at most M and probabilities within
//! [0, 1]. A shard file damaged without recomputing its checksum is never
//! merged; an undamaged set merges into the tables of one process.
//!
//! The generator is SplitMix64 from a fixed seed, so the cases are the
//! same on every run; the counts of cases and outcomes are printed
//! (`cargo test --test campaign -- --nocapture`).

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Option sets tried.
const FLAG_CASES: usize = 300;
/// Damaged shard sets tried.
const SHARD_CASES: usize = 1200;
/// A case still running after this long is a hang: every case is a run of
/// at most a few thousand chain-steps, or a refusal before any run. The
/// bound only turns a hang into a failure (no assertion depends on speed).
const HANG: Duration = Duration::from_secs(120);

/// SplitMix64: the campaign's generator.
struct Gen(u64);

impl Gen {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (n > 0; the bias of the modulo is irrelevant).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

/// Runs the binary with `args`, `--out dir` and `--quiet`, or fails the
/// test if it has not ended within [`HANG`].
fn repro(args: &[String], dir: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(args)
        .arg("--out")
        .arg(dir)
        .arg("--quiet")
        // Errors without a backtrace: capturing one (RUST_BACKTRACE=1 in
        // the environment) costs more than the whole case.
        .env("RUST_BACKTRACE", "0")
        .env("RUST_LIB_BACKTRACE", "0")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if started.elapsed() > HANG {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("{args:?}: still running after {HANG:?}: a hang");
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// The outcome of one case: `Ok(())` for exit 0, else the refusal's kind
/// (for the counts). Fails the test on a panic, a signal, another exit
/// status or a refusal without a message.
fn outcome(args: &[String], out: &Output) -> Result<(), String> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?}: a panic: {stderr}");
    match out.status.code() {
        Some(0) => Ok(()),
        Some(1) => {
            assert!(stderr.starts_with("Error: "), "{args:?}: {stderr}");
            Err(kind(&stderr))
        }
        Some(2) => {
            assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
            Err("option parser".to_string())
        }
        other => panic!("{args:?}: exit {other:?} (a signal or a crash): {stderr}"),
    }
}

/// A short name for a refusal: its innermost cause, without the file,
/// line numbers and values.
fn kind(stderr: &str) -> String {
    let cause = stderr
        .lines()
        .take_while(|l| !l.starts_with("Stack backtrace"))
        .filter(|l| !l.trim().is_empty())
        .last()
        .unwrap_or("")
        .trim();
    let cause = cause.split(".txt: ").last().unwrap_or(cause);
    if cause.contains("`: expected ") {
        return "a line out of place or malformed".to_string();
    }
    let words: Vec<&str> = cause
        .split([' ', ':', '`', '(', ','])
        .filter(|w| !w.is_empty() && !w.bytes().any(|b| b.is_ascii_digit()))
        .take(5)
        .collect();
    words.join(" ")
}

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

/// The rows of a CSV file as maps from column to value.
fn csv(path: &Path) -> Vec<BTreeMap<String, String>> {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = fields(lines.next().unwrap());
    lines
        .map(|l| header.iter().cloned().zip(fields(l)).collect())
        .collect()
}

fn num(row: &BTreeMap<String, String>, column: &str) -> f64 {
    row[column]
        .parse()
        .unwrap_or_else(|_| panic!("{column} = `{}` is not a number", row[column]))
}

/// Every table of a successful run: statistics finite and `>= 0`, hit
/// counts within `0..=M`, probabilities their ratio to M, in `[0, 1]`.
fn check_tables(what: &str, dir: &Path) {
    let mut seen = 0;
    for entry in fs::read_dir(dir).unwrap() {
        let sub = entry.unwrap().path();
        let summary = sub.join("summary.csv");
        if !summary.exists() {
            continue;
        }
        seen += 1;
        for row in csv(&summary) {
            for col in ["mean", "median", "sd", "sd_population", "se", "min", "max"] {
                let v = num(&row, col);
                assert!(v.is_finite() && v >= 0.0, "{what}: {col} = {v}");
            }
            assert!(num(&row, "M") >= 1.0, "{what}");
            assert!(num(&row, "min") <= num(&row, "max"), "{what}");
        }
        let curves = sub.join("curves.csv");
        if curves.exists() {
            for row in csv(&curves) {
                let (hits, m, p) = (num(&row, "hits"), num(&row, "M"), num(&row, "probability"));
                assert!((0.0..=m).contains(&hits), "{what}: {hits} hits of {m}");
                assert!((0.0..=1.0).contains(&p) && p == hits / m, "{what}: p = {p}");
            }
        }
    }
    assert!(seen > 0, "{what}: exit 0 without tables");
}

/// The tables of a protocol's directory (not the metadata, the cost
/// table or the shard files): name and bytes.
fn tables(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_str().unwrap();
            name != "meta.txt" && name != "cost.md" && !name.starts_with("shard-")
        })
        .map(|p| {
            let name = p.file_name().unwrap().to_str().unwrap().to_owned();
            (name, fs::read(&p).unwrap())
        })
        .collect();
    out.sort();
    out
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// One random option set: a protocol at `--quick` size made smaller
/// still, then one to four options with values drawn from lists of
/// ordinary, extreme and malformed ones.
fn flag_case(g: &mut Gen) -> Vec<String> {
    let protocol = *g.pick(&["e1", "t1", "e2", "e3", "e4", "e5", "t2", "t3"]);
    let anneals = matches!(protocol, "e5" | "t2" | "t3");
    let big = u64::MAX.to_string();
    let nan_inf = ["NaN", "inf", "-inf", "1e308", "-1e308", "1e-310", "0", "-1"];
    let mut options: Vec<(&str, Vec<String>)> = vec![
        (
            "--m",
            strings(&["1", "2", "3", "0", "-1", "x", "4294967296", &big]),
        ),
        ("--n", strings(&["1", "2", "5", "0", "1099511627776", &big])),
        (
            "--k",
            strings(&["1", "5", "20", "60", "0", "9007199254740993", &big]),
        ),
        ("--stride", strings(&["1", "3", "7", "0", "1000", &big])),
        (
            "--h",
            [&["0.01", "0.1", "40", "2.5"][..], &nan_inf[..]]
                .concat()
                .into_iter()
                .map(String::from)
                .collect(),
        ),
        (
            if anneals { "--a-high" } else { "--a" },
            [&["1", "4", "1e300"][..], &nan_inf[..]]
                .concat()
                .into_iter()
                .map(String::from)
                .collect(),
        ),
        ("--a-low", strings(&["0.1", "2", "NaN", "0", "1e308"])),
        (
            "--eps",
            [&["1", "0.5,3"][..], &nan_inf[..]]
                .concat()
                .into_iter()
                .map(String::from)
                .collect(),
        ),
        (
            "--start-centre",
            strings(&["3", "1e150", "-1e300", "1e308", "NaN", "inf"]),
        ),
        (
            "--start-var",
            strings(&["10", "0", "-1", "NaN", "1e300", "1e308", "inf"]),
        ),
        (
            "--start-point",
            strings(&["1", "0", "1e150", "1e308", "NaN", "-inf"]),
        ),
        ("--curve-every", strings(&["1", "7", "0", "1000", &big])),
        (
            "--checkpoints",
            strings(&["5", "1,5", "5,1", "0", "3,3", &big]),
        ),
        ("--d", strings(&["1", "2", "3", "10", "100", "0"])),
        (
            "--sampler",
            strings(&["hrla", "ula", "ola", "ula,ola", "xyz"]),
        ),
        (
            "--peer-sd",
            strings(&["0.25", "0", "NaN", "1e308", "1e-300", "inf"]),
        ),
        ("--peers", strings(&["sa", "csa,fsa", "smc-sa", "nope"])),
        ("--seed", strings(&["0", "7", &big, "-3"])),
        ("--threads", strings(&["1", "2"])),
    ];
    // T3's options elsewhere, and a_low at constant a, are refused every
    // time: tried in one case of ten only.
    let peers = protocol == "t3" || g.chance(10);
    let low = anneals || g.chance(10);
    options.retain(|(f, _)| (peers || !f.starts_with("--peer")) && (low || *f != "--a-low"));
    let mut args = vec![protocol.to_string(), "--quick".to_string()];
    let mut chosen: Vec<&str> = Vec::new();
    for _ in 0..1 + g.below(4) {
        let (flag, values) = g.pick(&options);
        if chosen.contains(flag) {
            continue;
        }
        chosen.push(*flag);
        args.push(flag.to_string());
        // Half the time one of the first two values, ordinary ones, so
        // that enough cases run to have their tables checked.
        let value = if g.chance(50) {
            &values[g.below(2)]
        } else {
            g.pick(values)
        };
        args.push(value.clone());
    }
    // Small unless the case chose the size: at most a few thousand
    // chain-steps a configuration.
    for (flag, value) in [("--m", "2"), ("--n", "3"), ("--k", "20")] {
        if !chosen.contains(&flag) {
            args.extend([flag.to_string(), value.to_string()]);
        }
    }
    args
}

#[test]
fn hostile_options_never_crash_hang_or_write_bad_tables() {
    let mut g = Gen(0x0005_eed0_f0b7_1045);
    let tmp = tempfile::tempdir().unwrap();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let (mut ok, mut round_trips) = (0, 0);
    for case in 0..FLAG_CASES {
        let args = flag_case(&mut g);
        let dir = tmp.path().join(format!("f{case}"));
        match outcome(&args, &repro(&args, &dir)) {
            Ok(()) => {
                ok += 1;
                check_tables(&format!("{args:?}"), &dir);
                // One success in three: the same options as two shards
                // merge into the same tables.
                if case % 3 == 0 {
                    round_trips += 1;
                    let sharded = tmp.path().join(format!("s{case}"));
                    for part in ["0/2", "1/2"] {
                        let mut a = args.clone();
                        a.extend(["--shard".to_string(), part.to_string()]);
                        outcome(&a, &repro(&a, &sharded)).unwrap();
                    }
                    let mut a = args.clone();
                    a.push("--merge".to_string());
                    outcome(&a, &repro(&a, &sharded)).unwrap();
                    let id = &args[0];
                    assert_eq!(tables(&dir.join(id)), tables(&sharded.join(id)), "{args:?}");
                }
            }
            Err(kind) => {
                assert!(
                    !dir.exists()
                        || fs::read_dir(&dir).unwrap().all(|e| {
                            // A refused protocol writes nothing.
                            !e.unwrap().path().join("summary.csv").exists()
                        }),
                    "{args:?}: refused after writing tables"
                );
                *counts.entry(kind).or_default() += 1;
            }
        }
    }
    println!(
        "option sets: {FLAG_CASES} cases, {ok} ran ({round_trips} also as two shards merged), refusals by kind:"
    );
    for (kind, n) in &counts {
        println!("  {n:4}  {kind}");
    }
    assert!(
        ok > FLAG_CASES / 10 && ok < FLAG_CASES,
        "a campaign that tests little: {ok} ran"
    );
}

/// A valid set of shards of one plan: its options, shard count and
/// directory, and the same shards of the plan with another seed.
struct Fixture {
    args: Vec<String>,
    id: &'static str,
    count: usize,
    clean: PathBuf,
    foreign: PathBuf,
    tables: Vec<(String, Vec<u8>)>,
}

fn fixture(root: &Path, id: &'static str, args: &[&str], count: usize) -> Fixture {
    let args = strings(args);
    let clean = root.join(format!("{id}-clean"));
    let foreign = root.join(format!("{id}-foreign"));
    for (dir, seed) in [(&clean, "2025"), (&foreign, "7")] {
        for i in 0..count {
            let mut a = args.clone();
            a.extend(strings(&[
                "--seed",
                seed,
                "--shard",
                &format!("{i}/{count}"),
            ]));
            outcome(&a, &repro(&a, dir)).unwrap();
        }
    }
    let single = root.join(format!("{id}-single"));
    outcome(&args, &repro(&args, &single)).unwrap();
    let tables = tables(&single.join(id));
    Fixture {
        args,
        id,
        count,
        clean,
        foreign,
        tables,
    }
}

fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The file with its checksum line (the last line starting `checksum `)
/// recomputed over everything before it, or appended if none is left.
fn reseal(bytes: &[u8]) -> Vec<u8> {
    let text = String::from_utf8_lossy(bytes).into_owned();
    let head = match text.rfind("\nchecksum ") {
        Some(i) => text[..=i].to_string(),
        None if text.ends_with('\n') => text,
        None => format!("{text}\n"),
    };
    format!("{head}checksum fnv1a64 {:016x}\n", fnv1a64(head.as_bytes())).into_bytes()
}

/// Numbers a damaged field may become.
const NUMBERS: [&str; 18] = [
    "0",
    "1",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-1",
    "+5",
    "7ff8000000000000",
    "7ff0000000000000",
    "fff0000000000000",
    "8000000000000001",
    "0000000000000001",
    "3ff0000000000000",
    "7fefffffffffffff",
    "3f",
    "3ff00000000000000",
    "1e3",
];

/// One random damage to the lines or bytes of `text`.
fn damage(g: &mut Gen, bytes: &mut Vec<u8>, foreign: &[u8]) -> &'static str {
    let text = String::from_utf8_lossy(bytes).into_owned();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    if lines.is_empty() {
        lines.push(String::new());
    }
    let n = lines.len();
    let what = match g.below(16) {
        0 => {
            lines.remove(g.below(n));
            "delete a line"
        }
        1 => {
            let i = g.below(n);
            let l = lines[i].clone();
            lines.insert(g.below(n), l);
            "duplicate a line"
        }
        2 => {
            let (i, j) = (g.below(n), g.below(n));
            lines.swap(i, j);
            "swap two lines"
        }
        3 => {
            bytes.truncate(g.below(bytes.len() + 1));
            return "truncate";
        }
        4 => {
            if !bytes.is_empty() {
                let i = g.below(bytes.len());
                bytes[i] = g.next() as u8;
            }
            return "flip a byte";
        }
        5..=9 => {
            // Mostly a value of the results (counters, running bests),
            // past the line's key and configuration.
            let results: Vec<usize> = (0..n)
                .filter(|&i| {
                    let l = &lines[i];
                    [
                        "diverged ",
                        "evaluations ",
                        "counts ",
                        "run ",
                        "chain-steps ",
                    ]
                    .iter()
                    .any(|k| l.starts_with(k))
                })
                .collect();
            let i = if !results.is_empty() && g.chance(70) {
                *g.pick(&results)
            } else {
                g.below(n)
            };
            let mut f: Vec<String> = lines[i].split(' ').map(String::from).collect();
            let j = if f.len() > 2 && g.chance(80) {
                2 + g.below(f.len() - 2)
            } else {
                g.below(f.len())
            };
            f[j] = g.pick(&NUMBERS).to_string();
            lines[i] = f.join(" ");
            "change a number"
        }
        10 => {
            // Another seed's plan lines in place of this file's.
            let theirs: Vec<String> = String::from_utf8_lossy(foreign)
                .lines()
                .filter(|l| l.starts_with("plan "))
                .map(String::from)
                .collect();
            let at = lines
                .iter()
                .position(|l| l.starts_with("plan "))
                .unwrap_or(0);
            lines.retain(|l| !l.starts_with("plan "));
            for (k, l) in theirs.into_iter().enumerate() {
                lines.insert((at + k).min(lines.len()), l);
            }
            "swap the plan"
        }
        11 => {
            let junk = *g.pick(&[
                "",
                "run 0 0 3ff0000000000000",
                "plan seed 2025",
                "garbage \u{fffd}",
                "checksum fnv1a64 0",
            ]);
            lines.insert(g.below(n + 1), junk.to_string());
            "insert a line"
        }
        12 => {
            bytes.extend_from_slice(b"extra line after the checksum\n");
            return "append after the checksum";
        }
        13 | 14 => {
            // Every running best of the file one extreme value: valid if
            // finite and >= 0, and then drawn and summarised.
            let v = *g.pick(&[
                "7fefffffffffffff",
                "7fe8000000000000",
                "0000000000000001",
                "0000000000000000",
                "7ff0000000000000",
                "3ff0000000000000",
            ]);
            for l in lines.iter_mut().filter(|l| l.starts_with("run ")) {
                let f: Vec<&str> = l.split(' ').collect();
                let n = f.len().saturating_sub(3);
                *l = format!("{} {}", f[..f.len().min(3)].join(" "), vec![v; n].join(" "));
            }
            "set every running best to one value"
        }
        _ => {
            *bytes = match g.below(3) {
                0 => Vec::new(),
                1 => (0..4096).map(|_| g.next() as u8).collect(),
                _ => vec![b'a'; 8 << 20],
            };
            return "replace the file";
        }
    };
    let mut out = lines.join("\n");
    out.push('\n');
    *bytes = out.into_bytes();
    what
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for e in fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            copy_dir(&p, &to.join(p.file_name().unwrap()));
        } else {
            fs::copy(&p, to.join(p.file_name().unwrap())).unwrap();
        }
    }
}

#[test]
fn damaged_shards_are_never_merged_into_bad_tables() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    let fixtures = [
        fixture(
            root,
            "e1",
            &["e1", "--quick", "--m", "3", "--k", "30", "--a", "1,4"],
            2,
        ),
        fixture(
            root,
            "t1",
            &["t1", "--quick", "--m", "3", "--h", "0.01,0.1"],
            3,
        ),
        fixture(
            root,
            "t3",
            &[
                "t3", "--quick", "--m", "2", "--a-high", "4", "--peers", "sa,csa",
            ],
            2,
        ),
    ];
    let mut g = Gen(0xda_4a9e_5a2d);
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    let (mut merged, mut resealed_merged) = (0, 0);
    for case in 0..SHARD_CASES {
        let f = g.pick(&fixtures);
        let dir = root.join(format!("c{case}"));
        copy_dir(&f.clean, &dir);
        let sub = dir.join(f.id);
        let mut damaged = false;
        let reseal_after = g.chance(50);
        let mut what = Vec::new();
        for _ in 0..1 + g.below(3) {
            let i = g.below(f.count);
            let name = format!("shard-{i}-of-{}.txt", f.count);
            let file = sub.join(&name);
            let foreign_file = f.foreign.join(f.id).join(&name);
            match g.below(20) {
                // Whole files: another seed's, renamed, added, removed.
                0 => {
                    fs::copy(&foreign_file, &file).unwrap();
                    what.push("another seed's file");
                }
                1 => {
                    let other = sub.join(format!("shard-{i}-of-{}.txt", f.count + 1));
                    if file.exists() {
                        fs::rename(&file, &other).unwrap();
                    }
                    what.push("rename a file");
                }
                2 => {
                    if file.exists() {
                        fs::remove_file(&file).unwrap();
                    }
                    what.push("remove a file");
                }
                3 => {
                    let j = (i + 1) % f.count;
                    let other = sub.join(format!("shard-{j}-of-{}.txt", f.count));
                    if file.exists() {
                        fs::copy(&file, &other).unwrap();
                    }
                    what.push("copy a file over another");
                }
                _ => {
                    let Ok(mut bytes) = fs::read(&file) else {
                        continue;
                    };
                    let foreign = fs::read(&foreign_file).unwrap();
                    what.push(damage(&mut g, &mut bytes, &foreign));
                    if reseal_after {
                        bytes = reseal(&bytes);
                    }
                    fs::write(&file, bytes).unwrap();
                }
            }
            damaged = true;
        }
        for w in &what {
            *kinds.entry(w).or_default() += 1;
        }
        // Unchanged bytes (a damage that undid itself) merge as before.
        let unchanged = (0..f.count).all(|i| {
            let name = format!("shard-{i}-of-{}.txt", f.count);
            fs::read(sub.join(&name)).ok() == fs::read(f.clean.join(f.id).join(&name)).ok()
        }) && fs::read_dir(&sub).unwrap().count() == f.count;
        let mut args = f.args.clone();
        args.push("--merge".to_string());
        match outcome(&args, &repro(&args, &dir)) {
            Ok(()) => {
                merged += 1;
                let label = format!("{args:?} after {what:?}");
                check_tables(&label, &dir);
                if unchanged {
                    assert_eq!(tables(&sub), f.tables, "{label}");
                } else {
                    // Only a damage whose checksum was recomputed can be
                    // read, and then only as another valid shard.
                    assert!(
                        reseal_after && damaged,
                        "{label}: a damaged shard was merged"
                    );
                    resealed_merged += 1;
                }
            }
            Err(kind) => {
                assert!(!unchanged, "{args:?}: intact shards refused: {kind}");
                assert!(
                    !sub.join("summary.csv").exists(),
                    "{args:?}: tables written"
                );
                *counts.entry(kind).or_default() += 1;
            }
        }
        fs::remove_dir_all(&dir).unwrap();
    }
    println!(
        "shard sets: {SHARD_CASES} cases, {merged} merged ({resealed_merged} of them damaged and resealed), refusals by kind:"
    );
    for (kind, n) in &counts {
        println!("  {n:4}  {kind}");
    }
    println!("damages applied:");
    for (kind, n) in &kinds {
        println!("  {n:4}  {kind}");
    }
    assert!(merged < SHARD_CASES / 2, "{merged} of {SHARD_CASES} merged");
}
