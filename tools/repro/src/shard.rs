//! A shard's runs on disk, and their merge: how a protocol runs as many
//! processes (a SLURM job array, `tools/repro/slurm/`), one
//! [`Shard`] each, and becomes one result.
//!
//! `repro ID --shard i/n` writes `OUT/id/shard-i-of-n.txt` instead of the
//! tables; `repro ID --merge` (with the same options) reads the `n` files,
//! checks that they are the shards of the same plan and seed, one each,
//! and writes the tables a single process would have written, byte for
//! byte (the metadata, and T3's `cost.md`, add the shards' wall times up).
//!
//! The file is text, one record a line: floats as the hexadecimal bits of
//! the `f64`, so a merge loses nothing.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::error::ReproError;
use crate::exec::{Part, Shard};
use crate::protocol::Plan;

const MAGIC: &str = "hrla-repro shard 1";

/// A fingerprint of everything that decides a plan's runs (FNV-1a of its
/// debug form): shards of different options never merge.
pub fn fingerprint(plan: &Plan, seed: u64) -> u64 {
    let text = format!("{plan:?} seed {seed}");
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Where shard `shard` of the plan's protocol goes under `out`.
pub fn path(out: &Path, plan: &Plan, shard: Shard) -> PathBuf {
    out.join(plan.id.name().to_lowercase())
        .join(format!("shard-{}-of-{}.txt", shard.index, shard.count))
}

/// Writes a shard's runs; returns the file.
pub fn write(
    out: &Path,
    plan: &Plan,
    seed: u64,
    shard: Shard,
    part: &Part,
    threads: usize,
) -> Result<PathBuf, ReproError> {
    let mut text = String::new();
    let _ = writeln!(text, "{MAGIC}");
    let _ = writeln!(text, "protocol {}", plan.id.name());
    let _ = writeln!(text, "plan {:016x}", fingerprint(plan, seed));
    let _ = writeln!(text, "shard {shard}");
    let _ = writeln!(text, "wall-ns {}", part.wall.as_nanos());
    let _ = writeln!(text, "chain-steps {}", part.chain_steps);
    let _ = writeln!(text, "threads {threads}");
    for c in 0..plan.configs.len() {
        let _ = writeln!(text, "diverged {c} {}", part.diverged[c]);
        let _ = writeln!(text, "evaluations {c} {}", part.evaluations[c]);
        let _ = writeln!(text, "run-wall-ns {c} {}", part.run_wall[c].as_nanos());
        let counts: Vec<String> = part.counts[c].iter().map(u32::to_string).collect();
        let _ = writeln!(text, "counts {c} {}", counts.join(" "));
        for (run, values) in &part.values[c] {
            let bits: Vec<String> = values
                .iter()
                .map(|v| format!("{:016x}", v.to_bits()))
                .collect();
            let _ = writeln!(text, "run {c} {run} {}", bits.join(" "));
        }
    }
    let file = path(out, plan, shard);
    if let Some(dir) = file.parent() {
        fs::create_dir_all(dir).map_err(|source| ReproError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    fs::write(&file, text).map_err(|source| ReproError::Io {
        path: file.clone(),
        source,
    })?;
    Ok(file)
}

/// A shard file read back.
struct ShardFile {
    shard: Shard,
    threads: usize,
    part: Part,
}

fn corrupt(file: &Path, what: &str) -> ReproError {
    ReproError::Usage(format!("{}: {what}", file.display()))
}

fn read_one(file: &Path, plan: &Plan, seed: u64) -> Result<ShardFile, ReproError> {
    let text = fs::read_to_string(file).map_err(|source| ReproError::Io {
        path: file.to_path_buf(),
        source,
    })?;
    let mut lines = text.lines();
    if lines.next() != Some(MAGIC) {
        return Err(corrupt(file, "not a shard file of this version"));
    }
    let mut part = Part::empty(plan);
    let (mut shard, mut threads) = (None, 0);
    let want = format!("{:016x}", fingerprint(plan, seed));
    let mut runs = 0;
    for line in lines {
        let mut f = line.split_whitespace();
        let key = f.next().unwrap_or("");
        let mut next = || f.next().ok_or_else(|| corrupt(file, line));
        let bad = || corrupt(file, line);
        match key {
            "protocol" => {
                if next()? != plan.id.name() {
                    return Err(corrupt(file, "a shard of another protocol"));
                }
            }
            "plan" => {
                if next()? != want {
                    return Err(corrupt(
                        file,
                        "a shard of other options or another seed than this merge's",
                    ));
                }
            }
            "shard" => shard = Some(next()?.parse::<Shard>()?),
            "wall-ns" => {
                part.wall = Duration::from_nanos(next()?.parse().map_err(|_| bad())?);
            }
            "chain-steps" => part.chain_steps = next()?.parse().map_err(|_| bad())?,
            "threads" => threads = next()?.parse().map_err(|_| bad())?,
            "diverged" | "evaluations" | "run-wall-ns" | "counts" | "run" => {
                let c: usize = next()?.parse().map_err(|_| bad())?;
                if c >= plan.configs.len() {
                    return Err(bad());
                }
                let rest: Vec<&str> = f.collect();
                let first = rest.first().copied().ok_or_else(bad);
                match key {
                    "diverged" => part.diverged[c] = first?.parse().map_err(|_| bad())?,
                    "evaluations" => {
                        part.evaluations[c] = first?.parse().map_err(|_| bad())?;
                    }
                    "run-wall-ns" => {
                        let ns = first?.parse().map_err(|_| bad())?;
                        part.run_wall[c] = Duration::from_nanos(ns);
                    }
                    "counts" => {
                        let counts: Vec<u32> = rest
                            .iter()
                            .map(|v| v.parse().map_err(|_| bad()))
                            .collect::<Result<_, _>>()?;
                        if counts.len() != part.counts[c].len() {
                            return Err(bad());
                        }
                        part.counts[c] = counts;
                    }
                    _ => {
                        let (run, values) = rest.split_first().ok_or_else(bad)?;
                        let values: Vec<f64> = values
                            .iter()
                            .map(|v| {
                                u64::from_str_radix(v, 16)
                                    .map(f64::from_bits)
                                    .map_err(|_| bad())
                            })
                            .collect::<Result<_, _>>()?;
                        if values.len() != plan.configs[c].checkpoints.len() {
                            return Err(bad());
                        }
                        part.values[c].push((run.parse().map_err(|_| bad())?, values));
                        runs += 1;
                    }
                }
            }
            _ => return Err(bad()),
        }
    }
    let shard = shard.ok_or_else(|| corrupt(file, "no shard line"))?;
    if runs != shard.tasks(plan).len() {
        return Err(corrupt(file, "runs missing"));
    }
    Ok(ShardFile {
        shard,
        threads,
        part,
    })
}

/// Every shard of the plan under `out`, merged: the part, and the most
/// threads a shard ran on. Errors unless the directory holds exactly the
/// shards `0..n` of one `n`, all of this plan and seed.
pub fn merge(out: &Path, plan: &Plan, seed: u64) -> Result<(Part, usize), ReproError> {
    let dir = out.join(plan.id.name().to_lowercase());
    let entries = fs::read_dir(&dir).map_err(|source| ReproError::Io {
        path: dir.clone(),
        source,
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("shard-") && n.ends_with(".txt"))
        })
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(ReproError::Usage(format!(
            "no shard files in {} to merge",
            dir.display()
        )));
    }
    let shards = files
        .iter()
        .map(|f| read_one(f, plan, seed))
        .collect::<Result<Vec<_>, _>>()?;
    let count = shards[0].shard.count;
    let mut seen = vec![false; count];
    for s in &shards {
        if s.shard.count != count || std::mem::replace(&mut seen[s.shard.index], true) {
            return Err(ReproError::Usage(format!(
                "{}: shards of different counts, or one shard twice",
                dir.display()
            )));
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(ReproError::Usage(format!(
            "{}: shard {missing}/{count} is missing",
            dir.display()
        )));
    }
    let threads = shards.iter().map(|s| s.threads).max().unwrap_or(0);
    let part = shards
        .into_iter()
        .fold(Part::empty(plan), |acc, s| acc.merge(s.part));
    Ok((part, threads))
}
