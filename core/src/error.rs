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
    /// A count outside the range a caller allows (for example more chains
    /// than a user interface offers).
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
    /// No feasible initial point: every point drawn for a chain from the
    /// start law (up to [`START_TRIES`](crate::START_TRIES), within the
    /// evaluation budget) had a non-finite position, potential or
    /// gradient.
    NonFiniteStart {
        /// The chain whose initial points were all bad.
        chain: usize,
        /// What was not finite at the last one: `position`, `value` or
        /// `gradient`.
        what: &'static str,
        /// The points drawn for that chain.
        tries: u32,
    },
    /// An index outside `0..len`, such as a chain's.
    Index {
        /// What was indexed (`chain`).
        name: &'static str,
        /// The index given.
        index: usize,
        /// The number of items: valid indices are `0..len`.
        len: usize,
    },
    /// A length that must match another did not: a box's sides against
    /// the run's dimension, caller storage against its chains.
    Length {
        /// What was measured (`lo`, `hi`, `floats`, ...).
        name: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A potential panicked while the optimiser was evaluating it: the
    /// chains may be partly stepped and the counters stale, so every later
    /// step, run, polish, quench or restart refuses to go on. Rebuild the
    /// optimiser.
    Poisoned,
    /// A parameter lies outside the range the crate's accuracy is
    /// documented and tested for.
    OutOfRange {
        /// The parameter (`alpha h`, `a`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
        /// The smallest value allowed.
        min: f64,
        /// The largest value allowed.
        max: f64,
    },
    /// A start the caller gave (`x0`) outside the box in one coordinate
    /// (or NaN there). No name field: the error keeps the size of the
    /// largest variant before it (firmware holds one in static RAM).
    OutsideBox {
        /// The coordinate.
        index: usize,
        /// Its value.
        value: f64,
        /// The box's side in that coordinate.
        lo: f64,
        /// The side's upper end.
        hi: f64,
    },
    /// An evaluation budget smaller than the evaluations of the initial
    /// points (one per chain).
    Budget {
        /// The budget.
        budget: u64,
        /// The number of chains.
        chains: usize,
    },
    /// A step budget shorter than the schedule: the annealing would be cut
    /// short.
    ScheduleLongerThanRun {
        /// The schedule's length.
        schedule: u64,
        /// The step budget.
        steps: u64,
    },
    /// [`run`](crate::Optimizer::run) without a stopping rule would never
    /// end.
    NoStoppingRule,
    /// Every chain has diverged (its position, potential or gradient went
    /// non-finite): the run has no live chain and no result to trust.
    AllDiverged {
        /// The number of chains.
        chains: usize,
    },
    /// A chain's potential fell to `-inf` or below `-sqrt(MAX)` of its
    /// float type: the potential looks unbounded below, and the run's best
    /// value means nothing.
    UnboundedBelow {
        /// The first chain that showed it.
        chain: usize,
        /// Its value.
        value: f64,
    },
    /// The potential stopped the run: its batch seam answered
    /// [`Break`](core::ops::ControlFlow::Break) (a user's function failed,
    /// and the front end that called it keeps the cause). The step that
    /// asked may be half done, so every later call refuses to go on.
    Stopped,
}

/// `Ok` if every `(name, expected, got)` has `got == expected`; otherwise
/// [`Error::Length`] for the first that does not.
pub(crate) fn check_lengths(
    lengths: impl IntoIterator<Item = (&'static str, usize, usize)>,
) -> Result<(), Error> {
    match lengths
        .into_iter()
        .find(|&(_, expected, got)| got != expected)
    {
        Some((name, expected, got)) => Err(Error::Length {
            name,
            expected,
            got,
        }),
        None => Ok(()),
    }
}

/// `Ok` if every known (`Some`) dimension in `dimensions` is `d`;
/// otherwise [`Error::Length`] naming the first that is not. A `None`
/// (a box, start or potential that fits any dimension) passes.
pub(crate) fn check_dimensions(
    d: usize,
    dimensions: impl IntoIterator<Item = (&'static str, Option<usize>)>,
) -> Result<(), Error> {
    check_lengths(
        dimensions
            .into_iter()
            .filter_map(|(name, dimension)| Some((name, d, dimension?))),
    )
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let value = |v: f64| Num(v);
        // A run that failed; every other error refuses an input.
        match *self {
            Error::NonFiniteStart { chain, what, tries } => write!(
                f,
                "no feasible initial point for chain {chain}: {tries} drawn, \
                 the last one's {what} is not finite"
            ),
            Error::Poisoned => f.write_str(
                "the potential panicked during an evaluation: the optimiser's state is \
                 inconsistent and it refuses to go on; build a new one",
            ),
            Error::AllDiverged { chains } => write!(
                f,
                "all {chains} chains diverged (non-finite position, potential or gradient): \
                 try a smaller step h"
            ),
            Error::UnboundedBelow { chain, value: v } => write!(
                f,
                "the potential looks unbounded below: chain {chain} reached U = {}",
                value(v)
            ),
            Error::Stopped => f.write_str("the potential stopped the run"),
            _ => self.refusal(f),
        }
    }
}

impl Error {
    /// The message of an error that refuses an input.
    fn refusal(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let value = |v: f64| Num(v);
        match *self {
            Error::NotPositive { name, value: v } => {
                write!(f, "`{name}` must be finite and > 0, got {}", value(v))
            }
            Error::Negative { name, value: v } => {
                write!(f, "`{name}` must be finite and >= 0, got {}", value(v))
            }
            Error::NotFinite { name, value: v } => {
                write!(f, "`{name}` must be finite, got {}", value(v))
            }
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
            Error::Index { name, index, len } => match len {
                0 => write!(f, "`{name}` = {index} is out of range: there are none"),
                _ => write!(
                    f,
                    "`{name}` must be between 0 and {}, got {index}",
                    len - 1
                ),
            },
            Error::Length {
                name,
                expected,
                got,
            } => write!(f, "`{name}` must have length {expected}, got {got}"),
            Error::OutOfRange {
                name,
                value: v,
                min,
                max,
            } => write!(
                f,
                "`{name}` = {} is outside [{min:e}, {max:e}], the range the step's accuracy is tested for",
                value(v)
            ),
            Error::OutsideBox {
                index,
                value: v,
                lo,
                hi,
            } => write!(
                f,
                "`x0[{index}]` = {} is outside the box's side [{}, {}]",
                value(v),
                value(lo),
                value(hi)
            ),
            Error::Budget { budget, chains } => write!(
                f,
                "an evaluation budget of {budget} is below the {chains} evaluations of the initial points"
            ),
            Error::ScheduleLongerThanRun { schedule, steps } => write!(
                f,
                "a step budget of {steps} would cut the schedule of {schedule} steps short"
            ),
            Error::NoStoppingRule => f.write_str(
                "the run has no stopping rule: give a step or evaluation budget, a target or a stall rule",
            ),
            // Written by `fmt`.
            Error::NonFiniteStart { .. }
            | Error::Poisoned
            | Error::AllDiverged { .. }
            | Error::UnboundedBelow { .. }
            | Error::Stopped => Ok(()),
        }
    }
}

impl core::error::Error for Error {}

/// A number as a person reads it: plain in the usual range, in exponent
/// form when very large or small (so that `-1e300` is not 300 digits).
struct Num(f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a != 0.0 && a.is_finite() && !(1e-4..1e6).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

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

/// The range of `u = alpha h` over which the exact step's coefficients are
/// tested against a double-double reference (`tests/tests/moments.rs`), in
/// f32 and f64; outside it their accuracy is not known.
pub(crate) const ALPHA_H: (f64, f64) = (1e-8, 50.0);

/// The range of inverse temperatures over which the samplers'
/// coefficients are tested (`tests/tests/moments.rs`): from a nearly flat
/// `exp(-a U)` to one concentrated within about `1e-3` of a minimum of
/// unit curvature.
pub(crate) const INVERSE_TEMPERATURE: (f64, f64) = (1e-6, 1e6);

/// `Ok(v)` when `v` lies in `[range.0, range.1]`, the ends rounded to `F`
/// (so that `1e-8f32`, which is just below `1e-8`, is in range in f32).
pub(crate) fn in_range<F: Float>(name: &'static str, v: F, range: (f64, f64)) -> Result<F, Error> {
    if v >= F::from_f64(range.0) && v <= F::from_f64(range.1) {
        Ok(v)
    } else {
        Err(Error::OutOfRange {
            name,
            value: v.to_f64(),
            min: range.0,
            max: range.1,
        })
    }
}

/// The lowest value a potential may take before the crate calls it
/// unbounded below: `-sqrt(MAX)` of the float type, far below any
/// meaningful minimum and far enough above `-MAX` that differences of
/// values near it do not overflow.
#[inline(always)]
pub(crate) fn floor<F: Float>() -> F {
    -(F::MAX.sqrt())
}
