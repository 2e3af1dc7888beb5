//! Why the layer refused a run or a run failed.

use core::fmt;

use crate::user::UserError;

/// Everything the layer can refuse or report as failed. A front end maps
/// each variant to its own kind of error (a Python exception class, a JS
/// `Error` with a field), keeping the message.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The kernel refused its input, or the run failed there
    /// ([`hrla::Error::AllDiverged`], [`hrla::Error::UnboundedBelow`], ...).
    Kernel(hrla::Error),
    /// Two sources fix different dimensions.
    DimensionMismatch {
        /// The first source that fixed one.
        first: &'static str,
        /// Its dimension.
        first_dim: usize,
        /// The source that disagrees.
        other: &'static str,
        /// Its dimension.
        other_dim: usize,
    },
    /// Nothing fixes the dimension.
    NoDimension,
    /// A vector whose length is not the run's dimension.
    Length {
        /// What it is: `"the start"`, `"the quadratic's centre"`, `"x"`.
        what: &'static str,
        /// Its length.
        len: usize,
        /// The run's dimension.
        dim: usize,
    },
    /// The chains' storage cannot be allocated.
    Memory {
        /// Chains asked for.
        chains: usize,
        /// Their dimension.
        dim: usize,
        /// The bytes of one chain.
        bytes: usize,
        /// Why: too many bytes for an address space, or the allocation failed.
        address_space: bool,
    },
    /// Every chain has run away beyond the escape radius or diverged, one
    /// at least having run away ([`crate::Settings::escape`]).
    RanAway(RanAway),
    /// A user's function failed: its own error, as it returned it.
    User(UserError),
    /// A bug of the layer (say, a batch of answers not all read).
    Internal(String),
}

/// A run whose chains all ran away ([`Error::RanAway`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RanAway {
    /// The chains of the run.
    pub chains: usize,
    /// The escape radius.
    pub radius: f64,
    /// The largest `|x|` of a chain that ran away.
    pub farthest: f64,
    /// The chains that diverged instead.
    pub diverged: usize,
}

impl fmt::Display for RanAway {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "all {} chains ran away beyond |x| = {} (the farthest at {:.2e})",
            self.chains, self.radius, self.farthest
        )?;
        if self.diverged > 0 {
            write!(f, " or diverged ({} of them)", self.diverged)?;
        }
        f.write_str(
            ": the step is too long for this landscape, or U does not hold the chains: \
             try a smaller `h`",
        )
    }
}

impl From<hrla::Error> for Error {
    fn from(e: hrla::Error) -> Self {
        Self::Kernel(e)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Kernel(e) => write!(f, "{e}"),
            Self::DimensionMismatch {
                first,
                first_dim,
                other,
                other_dim,
            } => write!(
                f,
                "{first} has dimension {first_dim} but {other} has {other_dim}"
            ),
            Self::NoDimension => write!(
                f,
                "the dimension is not fixed by the potential or the start: give dim="
            ),
            Self::Length { what, len, dim } => {
                write!(f, "{what} has {len} coordinates, the run {dim}")
            }
            Self::Memory {
                chains,
                dim,
                bytes,
                address_space,
            } => write!(
                f,
                "chains={chains}: {chains} chains of dimension {dim} ({bytes} bytes each) {}",
                if *address_space {
                    "need more bytes than an address space holds"
                } else {
                    "cannot be allocated"
                }
            ),
            Self::RanAway(r) => write!(f, "{r}"),
            Self::User(e) => write!(f, "{e}"),
            Self::Internal(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Kernel(e) => Some(e),
            Self::User(e) => Some(&**e),
            _ => None,
        }
    }
}
