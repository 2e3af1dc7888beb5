//! Everything the wrapper refuses, and how a refusal reaches JavaScript: a
//! real `Error` whose message says what is wrong, with a `field` property
//! naming the setting or argument at fault.

use core::fmt;

use wasm_bindgen::JsValue;

use crate::formula::FormulaError;
use crate::landscape::{CustomError, GridError, UnknownLandscape};
use crate::num::Num;

/// Why the wrapper refused a settings object or an argument, or why the
/// kernel did ([`Error::Kernel`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The settings value is not an object.
    NotAnObject,
    /// The settings (or their `annealing`) have a key that is no setting:
    /// a misspelt setting would otherwise be ignored without a word.
    UnknownSetting {
        /// The key.
        key: String,
        /// The keys allowed there.
        known: &'static [&'static str],
        /// The object: `settings`, or the setting it is the value of
        /// (`annealing`, `potential`), which is then the field at fault.
        within: &'static str,
    },
    /// Reading a setting threw (a getter, or a `Proxy` trap): the message
    /// of what was thrown.
    Threw {
        /// The setting being read (`settings` while listing its keys).
        field: &'static str,
        /// The thrown error's message.
        message: String,
    },
    /// A field is missing or is not a number.
    NotANumber(&'static str),
    /// A setting that counts (`chains`, `steps`, `stopSteps`) is not a
    /// whole number in `0..=2^53 - 1`.
    NotAnInteger(&'static str),
    /// An argument that counts (`steps` of `advance`, `nx`, `ny`) is not a
    /// JS number holding a whole number in `min..=max`.
    NotACount {
        /// The argument.
        name: &'static str,
        /// What was given.
        given: Given,
        /// The smallest count allowed.
        min: u64,
        /// The largest count allowed.
        max: u64,
    },
    /// `sampler` is not one of `"hrla"`, `"ula"`, `"ola"`.
    UnknownSampler,
    /// `annealing` is neither an object `{ aLow, aHigh, steps }` nor
    /// `null` or absent.
    BadAnnealing,
    /// An `a` for a run that anneals: its schedule sets `a` at every step.
    AnnealedA,
    /// `centre` is not an array of exactly two numbers.
    BadCentre,
    /// `potential` names no landscape.
    UnknownPotential(UnknownLandscape),
    /// `seed` is neither a safe non-negative integer nor a BigInt in
    /// `0..2^64`.
    BadSeed,
    /// A grid of the potential cannot be computed finitely.
    Grid(GridError),
    /// A visitor's formula cannot be read.
    Formula(FormulaError),
    /// A box is not an array of four numbers `[x0, x1, y0, y1]`.
    BadBox,
    /// A visitor's potential is not an object `{ formula, box }` with a
    /// string and four numbers.
    BadFormulaPotential,
    /// The kernel refused a parameter, or a run failed.
    Kernel(hrla::Error),
    /// The chain asked about has diverged: it is frozen and has no next
    /// step.
    Diverged {
        /// The chain.
        chain: usize,
    },
    /// Every chain has run away beyond the escape radius or diverged: the
    /// step is too long for the landscape, or the potential does not hold
    /// the chains. The run has no result to trust.
    RanAway {
        /// The number of chains.
        chains: usize,
        /// The escape radius.
        radius: f64,
        /// The largest finite `|x|` of a chain (0 when every chain diverged).
        farthest: f64,
        /// How many of the chains diverged rather than ran away.
        diverged: usize,
        /// The lowest `U` the chains reached, when it is below the
        /// landscape's `U*` (a formula's lowest value on its box): they ran
        /// downhill, and `U` looks unbounded below, which no step holds.
        lowest: Option<f64>,
    },
    /// The run-time layer refused the run for a reason the page's settings
    /// cannot give (its message).
    Layer(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotAnObject => f.write_str("settings must be an object"),
            Self::UnknownSetting { key, known, .. } => write!(
                f,
                "`{key}` is not a setting; the settings are {}",
                known.join(", ")
            ),
            Self::Threw { field, message } => write!(f, "reading `{field}` threw: {message}"),
            Self::NotANumber(name) => write!(f, "`{name}` must be a number"),
            Self::NotAnInteger(name) => write!(f, "`{name}` must be a whole number >= 0"),
            Self::NotACount {
                name,
                given,
                min,
                max,
            } => write!(
                f,
                "`{name}` must be a whole number between {min} and {max}, got {given}"
            ),
            Self::UnknownSampler => f.write_str("`sampler` must be \"hrla\", \"ula\" or \"ola\""),
            Self::BadAnnealing => f.write_str(
                "`annealing` must be an object { aLow, aHigh, steps }, or null for a constant `a`",
            ),
            Self::AnnealedA => f.write_str(
                "`a` cannot be set on a run that anneals: its schedule sets a at every step",
            ),
            Self::UnknownPotential(e) => fmt::Display::fmt(e, f),
            Self::BadCentre => f.write_str("`centre` must be an array of two numbers"),
            Self::BadSeed => f.write_str(
                "`seed` must be a whole number between 0 and 2^53 - 1, or a BigInt between 0 and 2^64 - 1",
            ),
            Self::Grid(e) => fmt::Display::fmt(e, f),
            Self::Formula(e) => fmt::Display::fmt(e, f),
            Self::BadBox => f.write_str("`box` must be an array of four numbers [x0, x1, y0, y1]"),
            Self::BadFormulaPotential => write!(
                f,
                "`potential` must be one of {}, or a formula {{ formula: \"U in x and y\", box: [x0, x1, y0, y1] }}",
                crate::landscape::Landscape::NAMES.join(", ")
            ),
            Self::Kernel(e) => fmt::Display::fmt(e, f),
            Self::Layer(message) => f.write_str(message),
            Self::Diverged { chain } => write!(
                f,
                "`chain` {chain} has diverged: it is frozen and has no next step"
            ),
            Self::RanAway {
                chains,
                radius,
                farthest,
                diverged,
                lowest,
            } => {
                write!(
                    f,
                    "all {chains} chains ran away beyond |x| = {} (the farthest at {farthest:.2e})",
                    Num(*radius)
                )?;
                if *diverged > 0 {
                    write!(f, " or diverged ({diverged} of them)")?;
                }
                match lowest {
                    Some(u) => write!(
                        f,
                        ", downhill to U = {u:.2e}, below the landscape's U*: U looks unbounded below, \
                         and U does not hold the chains at any step or temperature: \
                         give U a floor (for a formula, add a term that grows, such as (x^2 + y^2)^2 / 1000)"
                    ),
                    None => f.write_str(
                        ": the step is too long for this landscape, or U does not hold the chains: \
                         try a smaller `h`",
                    ),
                }
            }
        }
    }
}

impl core::error::Error for Error {}

impl Error {
    /// The setting or argument at fault, by the name the messages use
    /// (`h`, `a_low`, `steps`, ...), when there is one: the page marks its
    /// field.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            Self::NotAnObject => None,
            Self::UnknownSetting { within, .. } => (*within != "settings").then_some(*within),
            Self::Threw { field, .. } => Some(field),
            Self::NotANumber(name) | Self::NotAnInteger(name) => Some(name),
            Self::NotACount { name, .. } => Some(name),
            Self::UnknownSampler => Some("sampler"),
            Self::BadAnnealing => Some("annealing"),
            Self::AnnealedA => Some("a"),
            Self::UnknownPotential(_) => Some("potential"),
            Self::BadCentre => Some("centre"),
            Self::BadSeed => Some("seed"),
            Self::Grid(e) => Some(e.field()),
            Self::Formula(_) => Some("formula"),
            Self::BadBox => Some("box"),
            Self::BadFormulaPotential => Some("potential"),
            Self::Kernel(e) => kernel_field(e),
            Self::Diverged { .. } => Some("chain"),
            Self::RanAway { lowest: None, .. } => Some("h"),
            // No step holds chains on a U unbounded below: the landscape is at fault.
            Self::RanAway { .. } => Some("potential"),
            Self::Layer(_) => None,
        }
    }

    /// The JS `Error` thrown for this refusal: the message, and a `field`
    /// property when [`Error::field`] names one.
    pub fn to_js(&self) -> JsValue {
        let error = js_sys::Error::new(&self.to_string());
        if let Some(field) = self.field() {
            // Setting a property on a fresh Error object cannot fail.
            let _ = js_sys::Reflect::set(&error, &"field".into(), &field.into());
        }
        if let Self::Formula(e) = self {
            let _ = js_sys::Reflect::set(&error, &"column".into(), &(e.column as f64).into());
        }
        error.into()
    }
}

/// The setting a kernel error names.
fn kernel_field(e: &hrla::Error) -> Option<&'static str> {
    use hrla::Error as E;
    match *e {
        E::NotPositive { name, .. }
        | E::Negative { name, .. }
        | E::NotFinite { name, .. }
        | E::Zero { name }
        | E::Count { name, .. }
        | E::OutOfRange { name, .. } => Some(name),
        E::ScheduleLongerThanRun { .. } => Some("stopSteps"),
        E::AllDiverged { .. } | E::DegenerateCoefficients => Some("h"),
        _ => None,
    }
}

impl From<hrla::Error> for Error {
    fn from(e: hrla::Error) -> Self {
        Self::Kernel(e)
    }
}

impl From<hrla_dyn::Error> for Error {
    fn from(e: hrla_dyn::Error) -> Self {
        match e {
            hrla_dyn::Error::Kernel(e) => Self::Kernel(e),
            hrla_dyn::Error::RanAway(r) => Self::RanAway {
                chains: r.chains,
                radius: r.radius,
                farthest: r.farthest,
                diverged: r.diverged,
                lowest: None,
            },
            other => Self::Layer(other.to_string()),
        }
    }
}

impl From<CustomError> for Error {
    fn from(e: CustomError) -> Self {
        match e {
            CustomError::Formula(e) => Self::Formula(e),
            CustomError::Grid(e) => Self::Grid(e),
        }
    }
}

impl From<GridError> for Error {
    fn from(e: GridError) -> Self {
        Self::Grid(e)
    }
}

/// What JavaScript handed in where a number was asked for, as a message
/// names it: a number by its value, anything else by its type, so that
/// `5n` is not reported as NaN.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Given {
    /// A JS number (NaN and the infinities included).
    Number(f64),
    /// A BigInt, by its decimal digits (a sign and at most 20 digits;
    /// longer ones by their count, [`Given::LongBigInt`]).
    BigInt(String),
    /// A BigInt of this many characters, too long to repeat.
    LongBigInt(usize),
    /// Anything else, by its type as a message says it (`"a string"`,
    /// `"undefined"`, `"null"`, `"a boolean"`, `"a symbol"`,
    /// `"a function"`, `"an object"`).
    Other(&'static str),
}

impl fmt::Display for Given {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Number(v) => Num(*v).fmt(f),
            Self::BigInt(digits) => write!(f, "a BigInt {digits}n; pass a Number"),
            Self::LongBigInt(len) => write!(f, "a BigInt of {len} characters; pass a Number"),
            Self::Other(kind) => write!(f, "{kind}; pass a Number"),
        }
    }
}
