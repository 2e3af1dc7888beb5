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
    /// The dimension is not one of those compiled in.
    #[error("dimension {0} is not compiled in; supported: {dims:?}", dims = crate::config::DIMENSIONS)]
    Dimension(usize),
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
    /// Drawing a figure failed.
    #[error("cannot draw {path}: {message}")]
    Plot {
        /// The figure file.
        path: PathBuf,
        /// What plotters said.
        message: String,
    },
}
