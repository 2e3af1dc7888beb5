//! [`ReproError`], the one error type of the library: why a protocol could
//! not be planned, run or written.

use std::path::PathBuf;

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
        problem: crate::stats::BadRunningBest,
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
        problem: crate::shard::ShardProblem,
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
