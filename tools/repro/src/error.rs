//! [`ReproError`], the one error type of the library: why a protocol could
//! not be planned, run or written; and [`ShardProblem`], why a shard file
//! is refused.

use std::path::{Path, PathBuf};

use crate::split::Shard;
use crate::stats::BadRunningBest;

/// Why a protocol could not be planned, run or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReproError {
    /// The kernel refused a parameter (step size, temperature, start, ...).
    #[error("the hrla kernel refused the parameters: {0}")]
    Kernel(#[from] hrla::Error),
    /// A command-line combination that does not make sense for the protocol.
    #[error("{0}")]
    Usage(String),
    /// Writing an output file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// An option whose value the tool cannot honour, named: a size beyond
    /// what the tool counts exactly or the machine can hold (see
    /// [`crate::limits`]), or a stride that leaves no iterate.
    #[error("{flag}: {reason}")]
    Flag {
        /// The option, e.g. `--k`.
        flag: &'static str,
        /// The value and why it is refused.
        reason: String,
    },
    /// A run whose running bests are not a run's: above all, none finite
    /// (every chain diverged, or left the domain, before the first iterate
    /// on the stride). A failed run, never a table entry.
    #[error("{config}, run {run}: {problem}")]
    FailedRun {
        /// The configuration, as the tables label it.
        config: String,
        /// The run index.
        run: usize,
        /// What is wrong with its running bests.
        problem: BadRunningBest,
    },
    /// A counter of the merged runs would overflow its type.
    #[error("the {0} of the runs overflow")]
    Overflow(&'static str),
    /// A shard file, or the set of them, that `--merge` refuses.
    #[error("{path}: {problem}")]
    Shard {
        /// The file, or the directory for a problem of the set.
        path: PathBuf,
        /// What is wrong with it.
        problem: ShardProblem,
    },
    /// The GPU backend (`--backend gpu`) could not run: no adapter, a
    /// device failure, a buffer beyond the device's limits (see
    /// [`hrla_gpu::GpuError`]).
    #[error("the GPU backend: {0}")]
    Gpu(hrla_gpu::GpuError),
    /// Drawing a figure failed.
    #[error("cannot draw {path}: {message}")]
    Plot {
        /// The figure file.
        path: PathBuf,
        /// What plotters said.
        message: String,
    },
}

impl ReproError {
    /// The error of a failed file operation at `path`, for `map_err`.
    pub fn io(path: &Path) -> impl Fn(std::io::Error) -> ReproError + Copy + '_ {
        move |source| ReproError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Why `--merge` refuses a shard file, or the set of them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ShardProblem {
    /// Larger than any shard of the plan can be.
    #[error("{bytes} bytes, more than any shard of this plan can be ({most})")]
    TooLarge {
        /// The file's size.
        bytes: u64,
        /// The most a shard of the plan can take.
        most: u64,
    },
    /// The first line is not the format's
    /// ([`MAGIC`](crate::shard::MAGIC)).
    #[error("not a shard file of this format (its first line is `{first}`, not `{magic}`)")]
    NotAShard {
        /// The first line, or its first 80 characters.
        first: String,
        /// The first line of this format.
        magic: &'static str,
    },
    /// The file does not end with its checksum line.
    #[error("truncated: the file does not end with its checksum line")]
    Truncated,
    /// The checksum line does not match the content.
    #[error(
        "checksum mismatch: the file says {stored}, its content gives {computed:016x}; \
         it was changed or damaged after it was written"
    )]
    Checksum {
        /// What the checksum line says.
        stored: String,
        /// The checksum of the content.
        computed: u64,
    },
    /// Not UTF-8 text.
    #[error("not text (invalid UTF-8)")]
    NotText,
    /// A plan line is missing.
    #[error("the plan line `{expected}` is missing: a shard of an unknown plan")]
    PlanMissing {
        /// The first line that is missing.
        expected: String,
    },
    /// A plan line differs from the merge's.
    #[error(
        "a shard of other options or another seed (or another version of the tool) than \
         this merge's: it has `{shard}` where this merge has `{merge}`"
    )]
    PlanDiffers {
        /// The shard's line.
        shard: String,
        /// The merge's line.
        merge: String,
    },
    /// A line that is not the one expected there, or not well formed.
    #[error("line {line}: `{text}`: expected {expected}")]
    Malformed {
        /// The line number, from 1.
        line: usize,
        /// The line, or its first 80 characters.
        text: String,
        /// What the format has there.
        expected: String,
    },
    /// The file's name and its `shard` line disagree.
    #[error("its name says shard {named}, its content shard {inside}")]
    Misnamed {
        /// The shard the name says.
        named: Shard,
        /// The shard the content says.
        inside: Shard,
    },
    /// A run's running bests that no run makes.
    #[error("line {line}, run {run}: {problem}")]
    Value {
        /// The line number, from 1.
        line: usize,
        /// The run index.
        run: usize,
        /// What is wrong.
        problem: BadRunningBest,
    },
    /// A number out of its range.
    #[error("line {line}: {what}")]
    OutOfRange {
        /// The line number, from 1.
        line: usize,
        /// The number and its range.
        what: String,
    },
    /// Counters that overflow when the shards are added.
    #[error("the shards' {0} overflow when added")]
    Overflow(&'static str),
    /// A file named `shard-*.txt` whose name is not `shard-i-of-n.txt`.
    #[error("named like a shard file, but not shard-i-of-n.txt with 0 <= i < n")]
    BadName,
    /// No shard file in the directory.
    #[error("no shard files to merge")]
    NoShards,
    /// Shards of different counts.
    #[error("shards of different counts: {first} and {other}")]
    OtherCount {
        /// The first shard.
        first: Shard,
        /// A shard of another count.
        other: Shard,
    },
    /// A shard is missing.
    #[error("shard {index}/{count} is missing")]
    Missing {
        /// The missing shard's index.
        index: usize,
        /// The count.
        count: usize,
    },
}
