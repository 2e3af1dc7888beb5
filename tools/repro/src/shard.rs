//! A shard's runs on disk, and their merge: how a protocol runs as many
//! processes (a SLURM job array, `tools/repro/slurm/`), one
//! [`Shard`] each, and becomes one result.
//!
//! `repro ID --shard i/n` writes `OUT/id/shard-i-of-n.txt` instead of the
//! tables; `repro ID --merge` (with the same options) reads the `n` files,
//! checks each of them and that they are the shards `0..n` of the same
//! plan and seed, one each, and writes the tables a single process would
//! have written, byte for byte (the metadata, and T3's `cost.md`, add the
//! shards' wall times up).
//!
//! # Format
//!
//! Text, one record a line, fields separated by one space, in this order:
//!
//! ```text
//! hrla-repro shard 2
//! plan format 2                      the plan's fingerprint: every
//! plan tool hrla-repro 0.1.0         parameter that decides the results,
//! plan ...                           one line each (see `plan_lines`)
//! shard i/n
//! wall-ns W                          measured, summed by the merge
//! chain-steps S                      N K summed over the shard's runs
//! threads T                          worker threads, at least 1
//! diverged c D                       then, for each configuration c:
//! evaluations c E
//! run-wall-ns c W
//! counts c h0 h1 ...                 hits per tolerance and grid iterate
//! run c i v0 v1 ...                  one per run i of c in the shard, in
//!                                    order; the running best at each
//!                                    checkpoint as the 16 hexadecimal
//!                                    digits of the f64's bits (exact)
//! checksum fnv1a64 X                 FNV-1a (64 bits) of every byte before
//!                                    this line, 16 hexadecimal digits
//! ```
//!
//! A merge refuses ([`ReproError::Shard`], a [`ShardProblem`]) a file
//! larger than any shard of the plan, truncated (not ending with its
//! checksum line), whose checksum fails, whose plan lines differ from the
//! merge's own in any way, whose name and `shard` line disagree, that
//! lacks, repeats or reorders a line, whose numbers are out of range (a
//! hit count above the shard's runs of that configuration, evaluations or
//! diverged chains above what its runs can make, chain-steps other than
//! its runs', running bests not finite, below `U*` or increasing across
//! checkpoints), or whose counters overflow when added to the other
//! shards'.

use std::fmt::Write as _;
use std::fs;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::engine::U_STAR;
use crate::error::{ReproError, ShardProblem};
use crate::exec::Part;
use crate::gpu::Backend;
use crate::protocol::Plan;
use crate::split::Shard;
use crate::stats::check_running_best;

/// The first line of a shard file of this format.
pub const MAGIC: &str = "hrla-repro shard 2";

/// The version of the format, in [`MAGIC`] and in the plan lines.
const FORMAT: u32 = 2;

/// The checksum of the format: FNV-1a, 64 bits (offset basis
/// `0xcbf29ce484222325`, prime `0x100000001b3`). Every change of one byte
/// changes it; other damage goes unseen with probability 2^-64.
pub fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The plan's fingerprint as it is written in a shard file: one `plan`
/// line per parameter that decides the results. The format's version and
/// the tool's, the floating-point type and the potential, the protocol,
/// the base seed and `M`, every configuration in full (sampler, `d`, `h`,
/// `N`, `K`, temperature, start, stride, checkpoints, tolerances, curve
/// grid), the kernel's schedule and sampler settings (`alpha`, `beta`,
/// `b`, ...) or the peer's, and the figure's panels. Floats are written
/// as Rust's `Debug` does, which reads back to the same bits.
pub fn plan_lines(plan: &Plan, seed: u64, backend: Backend) -> Vec<String> {
    // Destructured, so that a field added to the plan is not forgotten here.
    let Plan {
        id,
        runs,
        configs,
        panels,
        series,
    } = plan;
    let mut lines = vec![
        format!("plan format {FORMAT}"),
        format!("plan tool hrla-repro {}", env!("CARGO_PKG_VERSION")),
        "plan dtype f64".to_string(),
    ];
    // A GPU's shards draw from another generator: never merged with the
    // CPU's (whose files carry no such line).
    if backend == Backend::Gpu {
        lines.push(format!("plan backend gpu {}", crate::gpu::GENERATOR));
    }
    lines.extend([
        format!("plan potential Rastrigin U* = {U_STAR:?}"),
        format!("plan protocol {}", id.name()),
        format!("plan seed {seed}"),
        format!("plan runs {runs}"),
        format!("plan configurations {}", configs.len()),
    ]);
    for (c, spec) in configs.iter().enumerate() {
        lines.push(format!("plan config {c} {spec:?}"));
        let settings = match spec.method.peer() {
            Some(peer) => format!("{peer:?}"),
            None => match spec.kernel_setup() {
                Ok((schedule, sampler)) => format!("{schedule:?} {sampler:?}"),
                Err(e) => format!("refused: {e}"),
            },
        };
        lines.push(format!("plan settings {c} {settings}"));
    }
    lines.push(format!("plan figure {panels:?} {series:?}"));
    lines
}

/// Where shard `shard` of the plan's protocol goes under `out`.
pub fn path(out: &Path, plan: &Plan, shard: Shard) -> PathBuf {
    out.join(plan.id.name().to_lowercase())
        .join(format!("shard-{}-of-{}.txt", shard.index, shard.count))
}

/// The text of a shard file (see the module's documentation).
pub fn text(
    plan: &Plan,
    seed: u64,
    backend: Backend,
    shard: Shard,
    part: &Part,
    threads: usize,
) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "{MAGIC}");
    for line in plan_lines(plan, seed, backend) {
        let _ = writeln!(text, "{line}");
    }
    let _ = writeln!(text, "shard {shard}");
    let _ = writeln!(text, "wall-ns {}", part.wall.as_nanos());
    let _ = writeln!(text, "chain-steps {}", part.chain_steps);
    let _ = writeln!(text, "threads {}", threads.max(1));
    for c in 0..plan.configs.len() {
        let _ = writeln!(text, "diverged {c} {}", part.diverged[c]);
        let _ = writeln!(text, "evaluations {c} {}", part.evaluations[c]);
        let _ = writeln!(text, "run-wall-ns {c} {}", part.run_wall[c].as_nanos());
        let counts: Vec<String> = part.counts[c].iter().map(u32::to_string).collect();
        let _ = writeln!(text, "counts {c} {}", counts.join(" "));
        let mut runs: Vec<&(usize, Vec<f64>)> = part.values[c].iter().collect();
        runs.sort_by_key(|(run, _)| *run);
        for (run, values) in runs {
            let bits: Vec<String> = values
                .iter()
                .map(|v| format!("{:016x}", v.to_bits()))
                .collect();
            let _ = writeln!(text, "run {c} {run} {}", bits.join(" "));
        }
    }
    let sum = checksum(text.as_bytes());
    let _ = writeln!(text, "checksum fnv1a64 {sum:016x}");
    text
}

/// Writes a shard's runs; returns the file.
pub fn write(
    out: &Path,
    plan: &Plan,
    seed: u64,
    backend: Backend,
    shard: Shard,
    part: &Part,
    threads: usize,
) -> Result<PathBuf, ReproError> {
    let file = path(out, plan, shard);
    if let Some(dir) = file.parent() {
        fs::create_dir_all(dir).map_err(ReproError::io(dir))?;
    }
    fs::write(&file, text(plan, seed, backend, shard, part, threads))
        .map_err(ReproError::io(&file))?;
    Ok(file)
}

fn shard_error(path: &Path, problem: ShardProblem) -> ReproError {
    ReproError::Shard {
        path: path.to_path_buf(),
        problem,
    }
}

/// At most 80 characters of `s`, for messages.
fn clip(s: &str) -> String {
    s.chars().take(80).collect()
}

/// The most bytes a shard of `plan` can take: every number at the most
/// digits of its type. A bound only, saturating.
fn most_bytes(plan: &Plan, seed: u64, backend: Backend) -> u64 {
    const NUMBER: u64 = 21; // a space and up to 20 digits
    let lines: u64 = plan_lines(plan, seed, backend)
        .iter()
        .map(|l| l.len() as u64 + 1)
        .sum();
    let mut most = lines + 512;
    for s in &plan.configs {
        let counts = s.count_len() as u64;
        let per_run = NUMBER * 3 + 17 * s.checkpoints.len() as u64;
        let runs = (plan.runs as u64).saturating_mul(per_run);
        most = most
            .saturating_add(4 * 3 * NUMBER + 64)
            .saturating_add(counts.saturating_mul(11))
            .saturating_add(runs);
    }
    most
}

/// The lines of a shard file's content, numbered from 1, read in order.
struct Lines<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    last: usize,
}

impl<'a> Lines<'a> {
    /// The next line, which must start with `key` (and the configuration
    /// `c`), as its line number and its other fields.
    fn keyed(
        &mut self,
        key: &str,
        c: Option<usize>,
    ) -> Result<(usize, Vec<&'a str>), ShardProblem> {
        let expected = || match c {
            Some(c) => format!("`{key} {c} ...`"),
            None => format!("`{key} ...`"),
        };
        let Some((i, line)) = self.lines.next() else {
            return Err(ShardProblem::Malformed {
                line: self.last + 1,
                text: String::new(),
                expected: expected(),
            });
        };
        self.last = i + 1;
        let mut fields = line.split(' ');
        let head_ok = fields.next() == Some(key)
            && c.is_none_or(|c| fields.next().and_then(number::<usize>) == Some(c));
        if !head_ok {
            return Err(self.malformed(line, &expected()));
        }
        Ok((i + 1, fields.collect()))
    }

    /// The next line, `key` and one number.
    fn one<T: std::str::FromStr>(
        &mut self,
        key: &str,
        c: Option<usize>,
    ) -> Result<(usize, T), ShardProblem> {
        let (line, fields) = self.keyed(key, c)?;
        match fields[..] {
            [v] => number(v)
                .map(|v| (line, v))
                .ok_or_else(|| self.malformed_at(line, key, "one number")),
            _ => Err(self.malformed_at(line, key, "one number")),
        }
    }

    fn malformed(&self, line: &str, expected: &str) -> ShardProblem {
        ShardProblem::Malformed {
            line: self.last,
            text: clip(line),
            expected: expected.to_string(),
        }
    }

    fn malformed_at(&self, line: usize, key: &str, what: &str) -> ShardProblem {
        ShardProblem::Malformed {
            line,
            text: key.to_string(),
            expected: format!("`{key}` with {what}"),
        }
    }
}

/// A decimal number, digits only (no sign, no spaces).
fn number<T: std::str::FromStr>(s: &str) -> Option<T> {
    if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

/// An `f64` as the 16 lowercase hexadecimal digits of its bits.
fn bits(s: &str) -> Option<f64> {
    if s.len() != 16 || !s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')) {
        return None;
    }
    u64::from_str_radix(s, 16).ok().map(f64::from_bits)
}

/// The checked content of a shard file: its bytes have the right size,
/// end with a checksum line that matches, and are text.
fn content(file: &Path, plan: &Plan, seed: u64, backend: Backend) -> Result<String, ReproError> {
    let io = ReproError::io(file);
    let most = most_bytes(plan, seed, backend);
    let handle = fs::File::open(file).map_err(io)?;
    let size = handle.metadata().map_err(io)?.len();
    let too_large = |bytes| shard_error(file, ShardProblem::TooLarge { bytes, most });
    if size > most {
        return Err(too_large(size));
    }
    let mut bytes = Vec::new();
    handle.take(most + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > most {
        return Err(too_large(bytes.len() as u64));
    }
    let first = bytes.split(|&b| b == b'\n').next().unwrap_or(&[]);
    if first != MAGIC.as_bytes() {
        let first = clip(&String::from_utf8_lossy(first));
        let magic = MAGIC;
        return Err(shard_error(file, ShardProblem::NotAShard { first, magic }));
    }
    let body = bytes
        .strip_suffix(b"\n")
        .ok_or_else(|| shard_error(file, ShardProblem::Truncated))?;
    let start = body.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let stored = body[start..]
        .strip_prefix(b"checksum fnv1a64 ")
        .ok_or_else(|| shard_error(file, ShardProblem::Truncated))?;
    let stored = String::from_utf8_lossy(stored).into_owned();
    let computed = checksum(&bytes[..start]);
    if stored != format!("{computed:016x}") {
        let stored = clip(&stored);
        return Err(shard_error(
            file,
            ShardProblem::Checksum { stored, computed },
        ));
    }
    bytes.truncate(start);
    String::from_utf8(bytes).map_err(|_| shard_error(file, ShardProblem::NotText))
}

/// A shard file read back and checked: its part and its thread count.
fn read_one(
    file: &Path,
    plan: &Plan,
    seed: u64,
    backend: Backend,
    named: Shard,
) -> Result<(Part, usize), ReproError> {
    let text = content(file, plan, seed, backend)?;
    parse(&text, plan, seed, backend, named).map_err(|problem| shard_error(file, problem))
}

/// The content of shard `named` of `plan` (its checksum line removed),
/// checked line by line.
fn parse(
    text: &str,
    plan: &Plan,
    seed: u64,
    backend: Backend,
    named: Shard,
) -> Result<(Part, usize), ShardProblem> {
    let mut lines = Lines {
        lines: text.lines().enumerate(),
        last: 0,
    };
    lines.keyed("hrla-repro", None)?;
    for merge in plan_lines(plan, seed, backend) {
        match lines.lines.next() {
            Some((i, shard)) if shard == merge => lines.last = i + 1,
            Some((_, shard)) if shard.starts_with("plan ") => {
                return Err(ShardProblem::PlanDiffers {
                    shard: clip(shard),
                    merge,
                });
            }
            _ => return Err(ShardProblem::PlanMissing { expected: merge }),
        }
    }
    let (line, fields) = lines.keyed("shard", None)?;
    let inside = match fields[..] {
        [s] => s.parse::<Shard>().ok(),
        _ => None,
    }
    .ok_or_else(|| lines.malformed_at(line, "shard", "i/n"))?;
    if inside != named {
        return Err(ShardProblem::Misnamed { named, inside });
    }
    let mut part = Part::empty(plan);
    part.wall = Duration::from_nanos(lines.one("wall-ns", None)?.1);
    let (line, chain_steps) = lines.one::<u64>("chain-steps", None)?;
    let tasks = plan.tasks(named);
    let expected = tasks.iter().try_fold(0u64, |sum, &(c, _)| {
        sum.checked_add(plan.configs[c].chain_steps())
    });
    if Some(chain_steps) != expected {
        return Err(ShardProblem::OutOfRange {
            line,
            what: format!(
                "{chain_steps} chain-steps, where the shard's runs make {}",
                expected.map_or("more than 2^64".to_string(), |e| e.to_string())
            ),
        });
    }
    part.chain_steps = chain_steps;
    let (line, threads) = lines.one::<usize>("threads", None)?;
    if threads == 0 {
        return Err(ShardProblem::OutOfRange {
            line,
            what: "0 threads".to_string(),
        });
    }
    for (c, spec) in plan.configs.iter().enumerate() {
        let runs: Vec<usize> = tasks.iter().filter(|t| t.0 == c).map(|t| t.1).collect();
        let n_runs = runs.len() as u64;
        let chains = spec.chains as u64;
        let over = |line, what: &str, value: u64, most: Option<u64>| {
            let most = most.unwrap_or(u64::MAX);
            (value > most).then(|| ShardProblem::OutOfRange {
                line,
                what: format!(
                    "{what} {value} of configuration {c}, more than its {n_runs} runs in this \
                     shard can make ({most})"
                ),
            })
        };
        let (line, diverged) = lines.one::<usize>("diverged", Some(c))?;
        if let Some(e) = over(
            line,
            "diverged chains",
            diverged as u64,
            n_runs.checked_mul(chains),
        ) {
            return Err(e);
        }
        part.diverged[c] = diverged;
        let (line, evaluations) = lines.one::<u64>("evaluations", Some(c))?;
        let most = spec
            .steps
            .checked_add(1)
            .and_then(|k| k.checked_mul(chains))
            .and_then(|per_run| per_run.checked_mul(n_runs));
        if let Some(e) = over(line, "evaluations", evaluations, most) {
            return Err(e);
        }
        part.evaluations[c] = evaluations;
        part.run_wall[c] = Duration::from_nanos(lines.one("run-wall-ns", Some(c))?.1);
        let (line, fields) = lines.keyed("counts", Some(c))?;
        if fields != [""] || spec.count_len() != 0 {
            if fields.len() != spec.count_len() {
                return Err(lines.malformed_at(
                    line,
                    "counts",
                    &format!("{} hit counts", spec.count_len()),
                ));
            }
            for (slot, field) in part.counts[c].iter_mut().zip(fields) {
                let hits = number::<u32>(field)
                    .ok_or_else(|| lines.malformed_at(line, "counts", "hit counts (u32)"))?;
                if let Some(e) = over(line, "hit count", u64::from(hits), Some(n_runs)) {
                    return Err(e);
                }
                *slot = hits;
            }
        }
        for run in runs {
            let (line, fields) = lines.keyed("run", Some(c))?;
            let bad = || {
                lines.malformed_at(
                    line,
                    "run",
                    &format!(
                        "run {run} of configuration {c} and {} values as 16 hex digits",
                        spec.checkpoints.len()
                    ),
                )
            };
            let (i, values) = fields.split_first().ok_or_else(bad)?;
            if number::<usize>(i) != Some(run) || values.len() != spec.checkpoints.len() {
                return Err(bad());
            }
            let values: Vec<f64> = values
                .iter()
                .map(|v| bits(v).ok_or_else(bad))
                .collect::<Result<_, _>>()?;
            check_running_best(&values, &spec.checkpoints, U_STAR)
                .map_err(|problem| ShardProblem::Value { line, run, problem })?;
            part.values[c].push((run, values));
        }
    }
    if let Some((i, extra)) = lines.lines.next() {
        return Err(ShardProblem::Malformed {
            line: i + 1,
            text: clip(extra),
            expected: "the checksum line".to_string(),
        });
    }
    Ok((part, threads))
}

/// The shard a file's name says, `shard-i-of-n.txt`.
fn shard_of_name(name: &str) -> Option<Shard> {
    let rest = name.strip_prefix("shard-")?.strip_suffix(".txt")?;
    let (i, n) = rest.split_once("-of-")?;
    let (index, count) = (number(i)?, number(n)?);
    (index < count).then_some(Shard { index, count })
}

/// Every shard of the plan under `out`, merged: the part, and the most
/// threads a shard ran on. Errors unless the directory holds exactly the
/// shards `0..n` of one `n`, each a valid shard of this plan and seed
/// (see the module's documentation), whose counters add up without
/// overflow, and the merged plan fits in the machine's memory.
pub fn merge(
    out: &Path,
    plan: &Plan,
    seed: u64,
    backend: Backend,
) -> Result<(Part, usize), ReproError> {
    crate::limits::check_memory(
        &plan.configs,
        plan.runs,
        None,
        crate::limits::machine_memory(),
    )?;
    let dir = out.join(plan.id.name().to_lowercase());
    let entries = fs::read_dir(&dir).map_err(ReproError::io(&dir))?;
    let mut files: Vec<(Shard, PathBuf)> = Vec::new();
    for entry in entries {
        let path = entry.map_err(ReproError::io(&dir))?.path();
        let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        if !(name.starts_with("shard-") && name.ends_with(".txt")) {
            continue;
        }
        let shard = shard_of_name(name).ok_or_else(|| shard_error(&path, ShardProblem::BadName))?;
        files.push((shard, path));
    }
    files.sort_by_key(|(s, _)| s.index);
    let first = files
        .first()
        .map(|f| f.0)
        .ok_or_else(|| shard_error(&dir, ShardProblem::NoShards))?;
    if let Some(&(other, _)) = files.iter().find(|(s, _)| s.count != first.count) {
        return Err(shard_error(&dir, ShardProblem::OtherCount { first, other }));
    }
    // The names are distinct and of one count, so indices are distinct:
    // the first index out of place is missing.
    if let Some(index) = (0..first.count).find(|&i| files.get(i).is_none_or(|f| f.0.index != i)) {
        let count = first.count;
        return Err(shard_error(&dir, ShardProblem::Missing { index, count }));
    }
    let mut whole = Part::empty(plan);
    let mut threads = 0;
    for (shard, file) in &files {
        let (part, t) = read_one(file, plan, seed, backend, *shard)?;
        threads = threads.max(t);
        whole = whole.merge(part).map_err(|e| match e {
            ReproError::Overflow(what) => shard_error(file, ShardProblem::Overflow(what)),
            other => other,
        })?;
    }
    Ok((whole, threads))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exec::run_shard;
    use crate::protocol::{Overrides, ProtocolId, plan};
    use indicatif::ProgressBar;

    fn e1() -> Plan {
        let o = Overrides {
            m: Some(3),
            k: Some(vec![20]),
            a: Some(vec![1.0, 4.0]),
            ..Overrides::default()
        };
        plan(ProtocolId::E1, &o, true).unwrap()
    }

    /// A shard written and parsed back is the part that was run, and the
    /// plan lines are all different for different seeds and options.
    #[test]
    fn a_shard_reads_back_exactly() {
        let p = e1();
        let shard = Shard { index: 1, count: 2 };
        let part = run_shard(&p, 9, shard, &ProgressBar::hidden()).unwrap();
        let text = text(&p, 9, Backend::Cpu, shard, &part, 3);
        let body = &text[..text.rfind("checksum").unwrap()];
        let (back, threads) = parse(body, &p, 9, Backend::Cpu, shard).unwrap();
        assert_eq!(threads, 3);
        assert_eq!(back.counts, part.counts);
        assert_eq!(back.values, part.values);
        assert_eq!(back.chain_steps, part.chain_steps);
        assert_eq!(back.evaluations, part.evaluations);
        assert!(matches!(
            parse(body, &p, 10, Backend::Cpu, shard),
            Err(ShardProblem::PlanDiffers { .. })
        ));
        assert!(matches!(
            parse(body, &p, 9, Backend::Cpu, Shard { index: 0, count: 2 }),
            Err(ShardProblem::Misnamed { .. })
        ));
        let mut other = p.clone();
        other.configs[1].h = 0.010000000000000002;
        assert!(matches!(
            parse(body, &other, 9, Backend::Cpu, shard),
            Err(ShardProblem::PlanDiffers { .. })
        ));
    }

    #[test]
    fn the_checksum_is_fnv1a_64() {
        // The reference values of FNV-1a 64.
        assert_eq!(checksum(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(checksum(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn shard_names() {
        assert_eq!(
            shard_of_name("shard-2-of-5.txt"),
            Some(Shard { index: 2, count: 5 })
        );
        for bad in [
            "shard-5-of-5.txt",
            "shard-x-of-2.txt",
            "shard-1-2.txt",
            "shard-+1-of-2.txt",
        ] {
            assert_eq!(shard_of_name(bad), None, "{bad}");
        }
    }
}
