//! Hostile inputs to the `repro` binary: shard files that were edited,
//! truncated, taken from another run or filled with impossible numbers,
//! and options far beyond what a plan can hold. Each must end in a typed
//! error (exit status 1, a message on stderr, never a panic or an abort),
//! before anything is run or written, and never in tables.
//!
//! Edited shard files are resealed (their checksum line recomputed, see
//! [`reseal`]) so that the check under test is the one that refuses them,
//! not the checksum.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How long a refused command may take before it is called a hang. Every
/// refusal here comes before any run starts; the bound only turns a hang
/// into a failure instead of a blocked test suite, and is far above what
/// any machine needs (no assertion depends on speed).
const HANG: Duration = Duration::from_secs(120);

/// Runs the binary with `args`, `--out dir` and `--quiet`, killing it if it
/// has not ended within [`HANG`].
fn repro(args: &[&str], dir: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(args)
        .arg("--out")
        .arg(dir)
        .arg("--quiet")
        // Errors without a backtrace: capturing one (RUST_BACKTRACE=1 in
        // the environment) costs more than the whole case.
        .env("RUST_BACKTRACE", "0")
        .env("RUST_LIB_BACKTRACE", "0")
        .stdout(Stdio::piped())
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
            let out = child.wait_with_output().unwrap();
            panic!(
                "{args:?} did not end within {HANG:?}; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn ok(args: &[&str], dir: &Path) {
    let out = repro(args, dir);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The command was refused with a typed error: exit status 1 (what `main`
/// returns for an error; a panic exits with 101, an abort by a signal),
/// no panic message, and `words` in the message on stderr.
fn refused(args: &[&str], dir: &Path, words: &[&str]) -> String {
    let out = repro(args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: expected a typed error, got {:?}; stderr: {stderr}",
        out.status
    );
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    for w in words {
        assert!(
            stderr.contains(w),
            "{args:?}: `{w}` not in the message: {stderr}"
        );
    }
    stderr
}

/// FNV-1a, 64 bits, as the shard format documents it.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// `text` with its last line, when it is a `checksum` line, recomputed
/// over everything before it, as a writer that meant these lines would
/// have written it. A file of a format without a checksum is unchanged.
fn reseal(text: &str) -> String {
    let body = text.strip_suffix('\n').unwrap_or(text);
    match body.rfind('\n') {
        Some(i) if body[i + 1..].starts_with("checksum ") => {
            let head = &text[..=i];
            format!("{head}checksum fnv1a64 {:016x}\n", fnv1a64(head.as_bytes()))
        }
        _ => text.to_string(),
    }
}

fn shard_file(dir: &Path, protocol: &str, i: usize, n: usize) -> PathBuf {
    dir.join(protocol).join(format!("shard-{i}-of-{n}.txt"))
}

/// Rewrites every line of a shard file that `edit` changes (`None`
/// deletes it), then reseals the file.
fn edit_lines(file: &Path, edit: impl Fn(&str) -> Option<String>) {
    let text = fs::read_to_string(file).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        if let Some(l) = edit(line) {
            out.push_str(&l);
            out.push('\n');
        }
    }
    fs::write(file, reseal(&out)).unwrap();
}

/// Shards `0..n` of `args` written under `dir`.
fn shards(args: &[&str], n: usize, dir: &Path) {
    for i in 0..n {
        let part = format!("{i}/{n}");
        let mut a = args.to_vec();
        a.extend(["--shard", &part]);
        ok(&a, dir);
    }
}

const T1: &[&str] = &["t1", "--quick", "--m", "3"];
const E1: &[&str] = &["e1", "--quick", "--m", "3", "--k", "30"];

/// A shard run with another seed whose plan line was deleted is not merged
/// into the tables of this seed.
#[test]
fn a_shard_of_another_seed_without_its_plan_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, other) = (tmp.path().join("a"), tmp.path().join("b"));
    shards(T1, 3, &dir);
    let mut seven = T1.to_vec();
    seven.extend(["--seed", "7"]);
    shards(&seven, 3, &other);
    let foreign = shard_file(&other, "t1", 1, 3);
    edit_lines(&foreign, |l| {
        (!l.starts_with("plan")).then(|| l.to_string())
    });
    fs::copy(&foreign, shard_file(&dir, "t1", 1, 3)).unwrap();
    refused(
        &[T1, &["--merge"]].concat(),
        &dir,
        &["shard-1-of-3.txt", "plan"],
    );
    assert!(!dir.join("t1").join("summary.csv").exists());
    // With its plan, the seed is named.
    shards(&seven, 3, &other);
    fs::copy(shard_file(&other, "t1", 1, 3), shard_file(&dir, "t1", 1, 3)).unwrap();
    refused(
        &[T1, &["--merge"]].concat(),
        &dir,
        &["other options or another seed", "seed"],
    );
}

/// A shard whose text ends inside its last value (a copy cut short) is
/// refused, not read as a shorter number.
#[test]
fn a_shard_truncated_inside_a_value_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    shards(T1, 2, dir);
    let file = shard_file(dir, "t1", 1, 2);
    let text = fs::read_to_string(&file).unwrap();
    let last_run = text.rfind("\nrun ").unwrap() + 1;
    let end = last_run + text[last_run..].find('\n').unwrap();
    fs::write(&file, &text[..end - 5]).unwrap();
    refused(
        &[T1, &["--merge"]].concat(),
        dir,
        &["shard-1-of-2.txt", "truncated"],
    );
    assert!(!dir.join("t1").join("summary.csv").exists());
}

/// One flipped byte in a value is caught by the checksum.
#[test]
fn a_shard_with_a_flipped_byte_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    shards(T1, 2, dir);
    let file = shard_file(dir, "t1", 0, 2);
    let mut bytes = fs::read(&file).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    // The fifth hex digit of the first value: still a valid number.
    let at = text.find("\nrun ").unwrap() + 1;
    let value = at + text[at..].match_indices(' ').nth(2).unwrap().0 + 1;
    bytes[value + 4] = if bytes[value + 4] == b'1' { b'2' } else { b'1' };
    fs::write(&file, bytes).unwrap();
    refused(
        &[T1, &["--merge"]].concat(),
        dir,
        &["shard-0-of-2.txt", "checksum"],
    );
}

/// NaN running bests are not merged (they would be tables of NaN).
#[test]
fn a_shard_with_nan_values_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    shards(T1, 2, dir);
    edit_lines(&shard_file(dir, "t1", 0, 2), |l| {
        Some(if l.starts_with("run 0 ") {
            let mut f: Vec<&str> = l.split(' ').collect();
            f[3] = "7ff8000000000000";
            f.join(" ")
        } else {
            l.to_string()
        })
    });
    refused(
        &[T1, &["--merge"]].concat(),
        dir,
        &["shard-0-of-2.txt", "NaN"],
    );
    assert!(!dir.join("t1").join("summary.csv").exists());
}

/// A hit count larger than the runs it counts (a probability of 250) is
/// refused.
#[test]
fn a_shard_with_counts_above_m_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    shards(E1, 2, dir);
    edit_lines(&shard_file(dir, "e1", 1, 2), |l| {
        Some(if l.starts_with("counts 0 ") {
            let n = l.split(' ').count() - 2;
            format!("counts 0 {}", vec!["750"; n].join(" "))
        } else {
            l.to_string()
        })
    });
    refused(
        &[E1, &["--merge"]].concat(),
        dir,
        &["shard-1-of-2.txt", "count"],
    );
    assert!(!dir.join("e1").join("curves.csv").exists());
}

/// Counters at the top of their type in two shards are refused, not
/// wrapped (release) or a panic (debug).
#[test]
fn counters_that_would_overflow_are_refused() {
    for (key, value) in [
        ("counts 0 ", u64::from(u32::MAX)),
        ("evaluations 0 ", u64::MAX),
    ] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        shards(E1, 2, dir);
        for i in 0..2 {
            edit_lines(&shard_file(dir, "e1", i, 2), |l| {
                Some(if l.starts_with(key) {
                    let n = l.split(' ').count() - 2;
                    format!("{key}{}", vec![value.to_string(); n].join(" "))
                } else {
                    l.to_string()
                })
            });
        }
        refused(&[E1, &["--merge"]].concat(), dir, &["shard-0-of-2.txt"]);
        assert!(!dir.join("e1").join("curves.csv").exists(), "{key}");
    }
}

/// Running bests at the ends of the positive floats are a valid (if
/// absurd) shard: the merge writes finite statistics and T3's log-scale
/// figure instead of drawing it without end. Every running best f64::MAX
/// in both shards, or the smallest subnormal in one of them beside
/// ordinary values in the other.
#[test]
fn running_bests_at_the_ends_of_the_floats_merge_into_finite_tables() {
    for (value, shards_edited) in [("7fefffffffffffff", 2), ("0000000000000001", 1)] {
        let tmp = tempfile::tempdir().unwrap();
        extreme_running_bests(tmp.path(), value, shards_edited);
    }
}

fn extreme_running_bests(dir: &Path, value: &str, shards_edited: usize) {
    let t3 = [
        "t3", "--quick", "--m", "2", "--a-high", "4", "--peers", "sa",
    ];
    shards(&t3, 2, dir);
    for i in 0..shards_edited {
        edit_lines(&shard_file(dir, "t3", i, 2), |l| {
            Some(if l.starts_with("run ") {
                let f: Vec<&str> = l.split(' ').collect();
                let all = vec![value; f.len() - 3];
                format!("{} {}", f[..3].join(" "), all.join(" "))
            } else {
                l.to_string()
            })
        });
    }
    ok(&[&t3[..], &["--merge"]].concat(), dir);
    let summary = fs::read_to_string(dir.join("t3").join("summary.csv")).unwrap();
    for row in summary.lines().skip(1) {
        let f: Vec<&str> = row.rsplit(',').collect();
        // max, min, se, sd_population, sd, median, mean (from the right,
        // after diverged_chains).
        for v in &f[1..8] {
            let v: f64 = v.parse().unwrap();
            assert!(v.is_finite() && v >= 0.0, "{row}");
        }
    }
    assert!(dir.join("t3").join("t3.svg").exists());
}

/// A stride longer than the run leaves no iterate for the running best:
/// refused, naming the option, instead of tables of inf and NaN.
#[test]
fn a_stride_beyond_the_checkpoints_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let max = u64::MAX.to_string();
    refused(
        &["t1", "--quick", "--stride", &max],
        tmp.path(),
        &["--stride"],
    );
    refused(
        &["t1", "--quick", "--stride", "281"],
        tmp.path(),
        &["--stride"],
    );
    refused(
        &["t3", "--quick", "--a-high", "4", "--stride", "2"],
        tmp.path(),
        &["--stride"],
    );
    assert!(!tmp.path().join("t1").exists());
}

/// A run whose chains all diverge at once has no running best: the
/// protocol fails instead of writing tables of inf and NaN.
#[test]
fn a_run_without_a_finite_running_best_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "t1",
        "--quick",
        "--sampler",
        "ola",
        "--h",
        "1e300",
        "--m",
        "2",
        "--n",
        "3",
        "--k",
        "20",
        "--stride",
        "1",
    ];
    refused(&args, tmp.path(), &["OLA", "run 0", "not finite"]);
    assert!(!tmp.path().join("t1").join("summary.csv").exists());
}

/// M, N or K at the top of `u64` (or beyond what the machine can hold) is
/// refused before anything runs, naming the option, rather than aborting,
/// panicking or running without end.
#[test]
fn sizes_beyond_the_limits_are_refused_naming_the_option() {
    let tmp = tempfile::tempdir().unwrap();
    let max = u64::MAX.to_string();
    for (flag, value, extra) in [
        ("--m", max.as_str(), &[][..]),
        ("--n", max.as_str(), &[][..]),
        ("--k", max.as_str(), &[][..]),
        // One chain, one run: without a bound, a run without end.
        ("--k", max.as_str(), &["--n", "1", "--m", "1"][..]),
        ("--k", "9007199254740993", &["--n", "1", "--m", "1"][..]),
        // Fits in the counters, not in any machine's memory.
        ("--n", "1099511627776", &["--k", "100", "--m", "1"][..]),
        ("--m", "4294967296", &["--k", "100", "--n", "1"][..]),
    ] {
        let mut args = vec!["t1", "--quick", flag, value];
        args.extend(extra);
        refused(&args, tmp.path(), &[flag]);
        let mut shard = args.clone();
        shard.extend(["--shard", "0/2"]);
        refused(&shard, tmp.path(), &[flag]);
    }
    assert!(!tmp.path().join("t1").exists());
    // The curve grid of every iterate of a long run does not fit either.
    refused(
        &[
            "e1",
            "--quick",
            "--a",
            "1",
            "--k",
            "4503599627370496",
            "--n",
            "1",
            "--m",
            "1",
            "--curve-every",
            "1",
        ],
        tmp.path(),
        &["--curve-every"],
    );
    assert!(!tmp.path().join("e1").exists());
}

/// `--threads` beyond 8 per core is refused before any thread starts, on
/// either backend: 100 000 threads are never spawned one by one first.
#[test]
fn too_many_threads_are_refused_before_any_starts() {
    let tmp = tempfile::tempdir().unwrap();
    for backend in ["cpu", "gpu"] {
        let args = ["--backend", backend, "--threads", "100000", "t1", "--quick"];
        let started = std::time::Instant::now();
        refused(&args, tmp.path(), &["--threads", "100000", "per core"]);
        // Spawning them one by one took minutes.
        assert!(started.elapsed() < Duration::from_secs(30), "{backend}");
    }
    assert!(!tmp.path().join("t1").exists());
}

/// A start the tool cannot draw is refused by its option and the value
/// given, before anything runs: a variance that is negative or not finite
/// on any backend, and on the GPU (whose starts are drawn in f32) one
/// whose square root, the standard deviation, is beyond f32.
#[test]
fn a_start_is_refused_by_its_option_and_value() {
    let tmp = tempfile::tempdir().unwrap();
    for (value, shown) in [("-1", "got -1"), ("inf", "got inf")] {
        let arg = format!("--start-var={value}");
        refused(
            &["t1", "--quick", &arg],
            tmp.path(),
            &["--start-var", shown],
        );
    }
    refused(
        &["t1", "--quick", "--start-point", "nan"],
        tmp.path(),
        &["--start-point", "got NaN"],
    );
    // Before any adapter is looked for: the same refusal with none.
    refused(
        &["--backend", "gpu", "t1", "--quick", "--start-var", "1e300"],
        tmp.path(),
        &["--start-var", "1e300", "f32"],
    );
    assert!(!tmp.path().join("t1").exists());
}
