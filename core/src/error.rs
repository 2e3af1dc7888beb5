//! The one error type of the crate.

use core::fmt;

use crate::float::Float;

/// Why a constructor or a step refused its input.
///
/// Every fallible function of the crate returns this; nothing in the public
/// API panics on bad numbers. Values are carried as `f64` (exact for `f32`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A parameter that must be finite and strictly positive was not.
    NotPositive {
        /// The parameter's name, as in the documentation (`h`, `a`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A parameter that must be finite and non-negative was not.
    Negative {
        /// The parameter's name (`std_dev`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A parameter or state that must be finite was NaN or infinite.
    NotFinite {
        /// What was not finite (`mean`, `target`, `initial point`, ...).
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The parameters are valid one by one, but a derived step coefficient
    /// overflowed or underflowed to a useless value (for example `h^3`
    /// overflowing for a huge `h`).
    DegenerateCoefficients,
    /// A count that must be at least 1 was zero (a stride, a schedule
    /// length).
    Zero {
        /// What was counted (`stride`, `steps`).
        name: &'static str,
    },
    /// The number of chains is zero or above the optimiser's capacity.
    Count {
        /// What was counted (`chains`).
        name: &'static str,
        /// The count given.
        value: usize,
        /// The largest count allowed.
        max: usize,
    },
    /// A name that is not one of those known, such as a sampler's.
    Unknown {
        /// What was named (`sampler`, ...).
        what: &'static str,
        /// The names known, each after a space.
        expected: &'static str,
    },
    /// The potential or its gradient is not finite at an initial point.
    NonFiniteStart {
        /// The chain whose initial point was bad.
        chain: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::NotPositive { name, value } => {
                write!(f, "`{name}` must be finite and > 0, got {value}")
            }
            Error::Negative { name, value } => {
                write!(f, "`{name}` must be finite and >= 0, got {value}")
            }
            Error::NotFinite { name, value } => write!(f, "`{name}` must be finite, got {value}"),
            Error::Zero { name } => write!(f, "`{name}` must be at least 1, got 0"),
            Error::DegenerateCoefficients => f.write_str(
                "the step coefficients overflow or vanish for these parameters \
                 (h, alpha or the temperature is out of range)",
            ),
            Error::Count { name, value, max } => {
                write!(f, "`{name}` must be between 1 and {max}, got {value}")
            }
            Error::Unknown { what, expected } => {
                write!(f, "unknown {what}; expected one of:{expected}")
            }
            Error::NonFiniteStart { chain } => write!(
                f,
                "the potential or its gradient is not finite at the initial point of chain {chain}"
            ),
        }
    }
}

impl core::error::Error for Error {}

/// `Ok(v)` when `v` is finite and strictly positive.
pub(crate) fn positive<F: Float>(name: &'static str, v: F) -> Result<F, Error> {
    if v.is_finite() && v > F::ZERO {
        Ok(v)
    } else {
        Err(Error::NotPositive {
            name,
            value: v.to_f64(),
        })
    }
}

/// `Ok(v)` when `v` is finite.
pub(crate) fn finite<F: Float>(name: &'static str, v: F) -> Result<F, Error> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::NotFinite {
            name,
            value: v.to_f64(),
        })
    }
}
