//! `repro`: runs the paper's experimental protocols with the hrla kernel
//! and writes their tables and figures. See `repro --help`.
//!
//! This file owns the command line (subcommands and global options), the
//! progress bar and what is printed on stdout; planning, running and
//! writing are the library's.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use hrla_repro::compare::{comparison_markdown, cost_markdown, has_peers};
use hrla_repro::exec::{Part, ProtocolResult, execute, finish, run_shard};
use hrla_repro::gpu::{Backend, GpuBackend};
use hrla_repro::output::{summary_markdown, write_all};
use hrla_repro::protocol::{Overrides, Plan, ProtocolId, plan};
use hrla_repro::split::Shard;
use hrla_repro::{limits, shard};

/// Reproduce the experiments of "Global Optimization Algorithm through
/// High-Resolution Sampling" (spec section 7) with the hrla kernel.
///
/// Each protocol writes into `OUT/ID/`: summary.csv and summary.md (running
/// best at K, or at each checkpoint: mean, median, sample SD, SE over the M runs), meta.txt (wall
/// time, chain-steps, command), and for E1-E5 curves.csv and `ID.svg` (the
/// empirical probability that the best chain at iterate k is within eps of
/// U*). Run i of every configuration is seeded with seed ^ splitmix64(i),
/// and chain c of that run draws from its own generator,
/// Xoshiro256PlusPlus::seed_from_u64(chain_seed(seed ^ splitmix64(i), c)),
/// so results do not depend on the thread count.
#[derive(Debug, Parser)]
#[command(name = "repro", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Output directory.
    #[arg(long, global = true, default_value = "repro-out")]
    out: PathBuf,
    /// Base seed of the runs.
    #[arg(long, global = true, default_value_t = 2025)]
    seed: u64,
    /// Smoke-test size: M = 4 runs and K divided by 50 (explicit options win).
    #[arg(long, global = true)]
    quick: bool,
    /// No progress bar and no tables on stdout; errors still go to stderr.
    #[arg(long, global = true)]
    quiet: bool,
    /// Worker threads of runs on the CPU (0: one per core), at most 8 per
    /// core; runs on the GPU and a merge start none.
    #[arg(long, global = true, default_value_t = 0)]
    threads: usize,
    /// Run only shard i of n (runs i, i + n, ... of every protocol, in plan
    /// order) and write OUT/ID/shard-i-of-n.txt instead of the tables: one
    /// task of a job array (tools/repro/slurm/).
    #[arg(long, global = true, value_name = "i/n", conflicts_with = "merge")]
    shard: Option<Shard>,
    /// Merge the shard files under OUT/ID/ (written with the same options)
    /// and write the tables, the same bytes as one process would. Refuses
    /// any file that is not an intact shard of this plan and seed: its
    /// checksum, plan, names, numbers and ranges are checked.
    #[arg(long, global = true)]
    merge: bool,
    /// Where the chains run: cpu, or gpu (any wgpu adapter with f64:
    /// Vulkan, Metal, DX12, or a software Vulkan such as lavapipe). The
    /// GPU's chains draw from xoshiro128++ with the same run and chain
    /// seeds: the same statistics, other draws. Not for T3's peers. A
    /// merge takes the backend its shards ran on.
    #[arg(long, global = true, value_enum, default_value_t = Backend::Cpu)]
    backend: Backend,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// E1: empirical probability vs k, HRLA, a = 1..4, eps = 1..6.
    E1(Overrides),
    /// T1: running best for h = 0.001, 0.01, 0.1 and a = 1..4, stride 100.
    T1(Overrides),
    /// E2: OLA vs ULA vs HRLA at a = 2..5; panels (a=4, eps=2), (a=3, eps=4).
    E2(Overrides),
    /// E3: long runs, K = 100000, a = 4..8, eps = 1..6.
    E3(Overrides),
    /// E4: d = 10 (eps = 2) against d = 20 (eps = 4), a = 1..4.
    E4(Overrides),
    /// E5: linear annealing from 0.1 to a_high = 4, 12, 20, 40; eps = 0.25..2.
    E5(Overrides),
    /// T2: fixed effort N K = 140000, (N, K) from (1, 140000) to (10000, 14), annealing.
    T2(Overrides),
    /// T3: N = 250, M = 50, K = 500 read at k = 50 and 500, a_high = 1..6, from (1,...,1) and N(3·1, 10 I);
    /// beside HRLA, the peers SA, FSA, SMC-SA and CSA with the same N, K, M and seeds.
    T3(Overrides),
    /// Every protocol with its defaults, in the order E1, T1, E2, E3, E4, E5, T2, T3.
    All(AllArgs),
}

#[derive(Debug, clap::Args)]
struct AllArgs {
    /// Runs M of every protocol (default: each protocol's own).
    #[arg(long)]
    m: Option<usize>,
    /// Protocols to leave out, e.g. `--skip e3`.
    #[arg(long, value_delimiter = ',')]
    skip: Vec<ProtocolId>,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    // The worker threads, once their count is checked: runs on the CPU
    // start them, runs on the GPU and a merge none.
    let threads = cli.backend.start_workers(cli.threads, cli.merge)?;
    let jobs: Vec<(ProtocolId, Overrides)> = match &cli.command {
        Command::E1(o) => vec![(ProtocolId::E1, o.clone())],
        Command::T1(o) => vec![(ProtocolId::T1, o.clone())],
        Command::E2(o) => vec![(ProtocolId::E2, o.clone())],
        Command::E3(o) => vec![(ProtocolId::E3, o.clone())],
        Command::E4(o) => vec![(ProtocolId::E4, o.clone())],
        Command::E5(o) => vec![(ProtocolId::E5, o.clone())],
        Command::T2(o) => vec![(ProtocolId::T2, o.clone())],
        Command::T3(o) => vec![(ProtocolId::T3, o.clone())],
        Command::All(all) => ProtocolId::ALL
            .into_iter()
            .filter(|id| !all.skip.contains(id))
            .map(|id| {
                let o = Overrides {
                    m: all.m,
                    ..Overrides::default()
                };
                (id, o)
            })
            .collect(),
    };
    // Plan everything first: a bad option fails before hours of running.
    let plans = jobs
        .iter()
        .map(|(id, o)| plan(*id, o, cli.quick).with_context(|| format!("protocol {}", id.name())))
        .collect::<Result<Vec<_>>>()?;
    // The device, once, before anything runs, for plans it runs: no
    // adapter is an error here.
    let device = match cli.backend {
        Backend::Gpu if !cli.merge => {
            for p in &plans {
                GpuBackend::check(p).with_context(|| format!("protocol {}", p.id.name()))?;
            }
            Some(GpuBackend::open()?)
        }
        _ => None,
    };
    // And every plan within the machine's memory, before any of them runs
    // (on a GPU, one batch of runs at a time reads back).
    let memory = limits::machine_memory();
    let workers = match &device {
        Some(_) => Some(1),
        None => threads,
    };
    for p in &plans {
        limits::check_memory(&p.configs, p.runs, workers, memory)
            .with_context(|| format!("protocol {}", p.id.name()))?;
    }
    // The program's own name, not the build directory it ran from.
    let command = std::iter::once("repro".to_string())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let mut total = Duration::ZERO;
    for p in &plans {
        let context = || format!("protocol {}", p.id.name());
        if let Some(part) = cli.shard {
            total +=
                run_one_shard(&cli, device.as_ref(), threads, p, part).with_context(context)?;
            continue;
        }
        let load_before = load_average();
        let (result, mut notes) = if cli.merge {
            let (part, threads) =
                shard::merge(&cli.out, p, cli.seed, cli.backend).with_context(context)?;
            let result = finish(p, cli.seed, part, threads);
            let note = ("wall time", "the sum of the shards'".to_string());
            (result, vec![note])
        } else {
            let bar = progress_bar(cli.quiet, p.chain_steps(), p.id.name());
            let result = match &device {
                Some(gpu) => gpu.execute(p, cli.seed, &bar),
                None => execute(p, cli.seed, &bar),
            }
            .with_context(context)?;
            bar.finish_and_clear();
            let notes = device
                .iter()
                .map(|gpu| ("backend", gpu.describe()))
                .collect();
            (result, notes)
        };
        notes.extend([
            ("command", command.clone()),
            ("load average before", load_before),
            ("load average after", load_average()),
        ]);
        let files = write_all(&result, &cli.out, &notes).with_context(context)?;
        total += result.wall;
        if !cli.quiet {
            report(&result, &files);
        }
    }
    if !cli.quiet && plans.len() > 1 {
        println!("Total wall time: {:.1} s", total.as_secs_f64());
    }
    Ok(())
}

/// Runs one shard of a plan (on the device, if any) and writes its file;
/// returns the wall time.
fn run_one_shard(
    cli: &Cli,
    device: Option<&GpuBackend>,
    threads: Option<usize>,
    p: &Plan,
    part: Shard,
) -> Result<Duration> {
    let steps = p
        .tasks(part)
        .iter()
        .map(|&(c, _)| p.configs[c].chain_steps())
        .sum();
    let bar = progress_bar(cli.quiet, steps, p.id.name());
    let result: Part = match device {
        Some(gpu) => gpu.run_shard(p, cli.seed, part, &bar)?,
        None => run_shard(p, cli.seed, part, &bar)?,
    };
    bar.finish_and_clear();
    // A shard runs on the device or on the CPU's workers.
    let threads = threads.unwrap_or(1);
    let file = shard::write(&cli.out, p, cli.seed, cli.backend, part, &result, threads)?;
    if !cli.quiet {
        println!(
            "{} shard {part}: {} runs, {} chain-steps in {:.2} s; wrote {}",
            p.id.name(),
            p.tasks(part).len(),
            result.chain_steps,
            result.wall.as_secs_f64(),
            file.display()
        );
    }
    Ok(result.wall)
}

/// The 1, 5 and 15 minute load averages, so that a wall time measured on a
/// shared machine says how shared it was (Linux; "unknown" elsewhere).
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|| "unknown".to_string())
}

fn progress_bar(quiet: bool, total: u64, name: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total);
    // The template is a constant; fall back to the default style if a
    // future indicatif rejects it rather than failing a long run.
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix} [{elapsed_precise}] {wide_bar} {human_pos}/{human_len} chain-steps, eta {eta}",
    ) {
        bar.set_style(style);
    }
    bar.set_prefix(name.to_string());
    bar
}

fn report(r: &ProtocolResult, files: &[PathBuf]) {
    println!("## {}: {}\n", r.plan.id.name(), r.plan.id.title());
    println!("{}", summary_markdown(r));
    if has_peers(r) {
        println!("{}", comparison_markdown(r));
        println!("{}", cost_markdown(r));
    }
    println!(
        "Wall time {:.2} s for {} chain-steps ({:.3e} per second, {} threads).",
        r.wall.as_secs_f64(),
        r.chain_steps,
        r.chain_steps_per_second(),
        r.threads
    );
    for f in files {
        println!("  wrote {}", f.display());
    }
    println!();
}
