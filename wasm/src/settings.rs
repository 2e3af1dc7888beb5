//! The settings of a run, as plain Rust values, and how they are read from
//! the JavaScript object the page passes in.

use core::fmt;

use hrla::{AnySchedule, Constant, Linear, SamplerKind, Stop};
use wasm_bindgen::JsValue;

use crate::landscape::{Landscape, UnknownLandscape};

/// Parses a sampler's name, `"hrla"`, `"ula"` or `"ola"` (any case).
pub fn parse_sampler(name: &str) -> Result<SamplerKind, SettingsError> {
    name.parse().map_err(|_| SettingsError::UnknownSampler)
}

/// The inverse temperature along the run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Temperature {
    /// A constant `a`.
    Constant(f64),
    /// The paper's linear annealing, `a_low -> a_high` over `steps` iterations,
    /// then `a_high`.
    Linear {
        /// `a_0`.
        a_low: f64,
        /// `a_K` and beyond.
        a_high: f64,
        /// `K`.
        steps: u64,
    },
}

impl Temperature {
    /// The kernel's schedule, its parameters validated by the kernel.
    pub fn schedule(self) -> Result<AnySchedule<f64>, hrla::Error> {
        Ok(match self {
            Temperature::Constant(a) => AnySchedule::Constant(Constant::new(a)?),
            Temperature::Linear {
                a_low,
                a_high,
                steps,
            } => AnySchedule::Linear(Linear::new(a_low, a_high, steps)?),
        })
    }
}

/// Everything that determines a run: the same settings give the same numbers
/// on every target.
///
/// The sampler's other parameters are the paper's (`alpha = beta = 1`,
/// `b = 10`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The potential.
    pub landscape: Landscape,
    /// The sampler.
    pub sampler: SamplerKind,
    /// Constant `a` or an annealing schedule.
    pub temperature: Temperature,
    /// Step size `h`.
    pub h: f64,
    /// Number of chains, `1..=MAX_CHAINS`.
    pub chains: usize,
    /// Mean of the Gaussian initial law.
    pub centre: [f64; 2],
    /// Standard deviation of the Gaussian initial law (per coordinate).
    pub spread: f64,
    /// The run's seed: chain `c` draws from its own generator,
    /// `Xoshiro256PlusPlus::seed_from_u64(hrla::chain_seed(seed, c))`.
    pub seed: u64,
    /// Stop after this many steps (none: never).
    pub stop_steps: Option<u64>,
    /// Stop once the best value is at most this (none: never).
    pub stop_target: Option<f64>,
}

impl Default for Settings {
    /// HRLA on Rastrigin at the paper's `a = 4`, `h = 0.01`, 256 chains
    /// from the paper's `N(3·1, 10 I)`, seed 1, no stopping rule.
    fn default() -> Self {
        Self {
            landscape: Landscape::Rastrigin,
            sampler: SamplerKind::Hrla,
            temperature: Temperature::Constant(4.0),
            h: 0.01,
            chains: 256,
            centre: [3.0, 3.0],
            spread: 10f64.sqrt(),
            seed: 1,
            stop_steps: None,
            stop_target: None,
        }
    }
}

/// Why settings from JavaScript were refused before reaching the kernel
/// (the kernel's own refusals are [`hrla::Error`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SettingsError {
    /// The settings value is not an object.
    NotAnObject,
    /// A field is missing or is not a number.
    NotANumber(&'static str),
    /// A count (`chains`, `steps`) is not a non-negative integer.
    NotAnInteger(&'static str),
    /// `sampler` is not one of `"hrla"`, `"ula"`, `"ola"`.
    UnknownSampler,
    /// `centre` is not an array of two numbers.
    BadCentre,
    /// `potential` names no landscape.
    UnknownPotential(UnknownLandscape),
    /// `seed` is neither a safe non-negative integer nor a BigInt in
    /// `0..2^64`.
    BadSeed,
    /// The kernel refused a parameter.
    Kernel(hrla::Error),
}

impl fmt::Display for SettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotAnObject => f.write_str("settings must be an object"),
            Self::NotANumber(name) => write!(f, "`{name}` must be a number"),
            Self::NotAnInteger(name) => write!(f, "`{name}` must be a whole number >= 0"),
            Self::UnknownSampler => f.write_str("`sampler` must be \"hrla\", \"ula\" or \"ola\""),
            Self::UnknownPotential(e) => fmt::Display::fmt(e, f),
            Self::BadCentre => f.write_str("`centre` must be an array of two numbers"),
            Self::BadSeed => f.write_str(
                "`seed` must be a whole number between 0 and 2^53 - 1, or a BigInt between 0 and 2^64 - 1",
            ),
            Self::Kernel(e) => fmt::Display::fmt(e, f),
        }
    }
}

impl core::error::Error for SettingsError {}

impl SettingsError {
    /// The setting at fault, by the name the messages use (`h`,
    /// `a_low`, ...), when one is: the page marks its field.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            Self::NotAnObject => None,
            Self::NotANumber(name) | Self::NotAnInteger(name) => Some(name),
            Self::UnknownSampler => Some("sampler"),
            Self::UnknownPotential(_) => Some("potential"),
            Self::BadCentre => Some("mean"),
            Self::BadSeed => Some("seed"),
            Self::Kernel(e) => kernel_field(e),
        }
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

impl From<hrla::Error> for SettingsError {
    fn from(e: hrla::Error) -> Self {
        Self::Kernel(e)
    }
}

/// Largest integer a JS number holds exactly, `2^53 - 1`.
const MAX_SAFE_INTEGER: f64 = 9_007_199_254_740_991.0;

impl Settings {
    /// Reads settings from a JS object:
    ///
    /// ```text
    /// { potential: "rastrigin" | "ackley" | ...,     // optional, default Rastrigin
    ///   sampler: "hrla" | "ula" | "ola",
    ///   a: number,                                   // constant a, or
    ///   annealing: { aLow, aHigh, steps } | null,    // linear annealing (wins over a)
    ///   h: number, chains: number,
    ///   centre: [number, number], spread: number,
    ///   seed: number | bigint,
    ///   stopSteps: number | null, stopTarget: number | null }  // optional
    /// ```
    ///
    /// Numbers are checked only for type here (and for being whole where a
    /// count is expected); their ranges are the kernel's business, so a bad
    /// `h` comes back as the kernel's own message. A `seed` is a u64: a JS
    /// number is accepted when it is a whole number up to `2^53 - 1` (so it
    /// is exact), a BigInt for the full range.
    pub fn from_js(value: &JsValue) -> Result<Self, SettingsError> {
        if !value.is_object() {
            return Err(SettingsError::NotAnObject);
        }
        let landscape = match get(value, "potential") {
            p if p.is_undefined() || p.is_null() => Landscape::Rastrigin,
            p => p
                .as_string()
                .ok_or(SettingsError::UnknownPotential(UnknownLandscape))?
                .parse()
                .map_err(SettingsError::UnknownPotential)?,
        };
        let sampler = match get(value, "sampler").as_string() {
            Some(name) => parse_sampler(&name)?,
            None => return Err(SettingsError::UnknownSampler),
        };
        let annealing = get(value, "annealing");
        let temperature = if annealing.is_object() {
            Temperature::Linear {
                a_low: number(&annealing, "aLow")?,
                a_high: number(&annealing, "aHigh")?,
                steps: whole(&annealing, "steps")?,
            }
        } else {
            Temperature::Constant(number(value, "a")?)
        };
        let centre = get(value, "centre");
        let coordinate = |i: u32| {
            js_sys::Reflect::get_u32(&centre, i)
                .ok()
                .and_then(|v| v.as_f64())
                .ok_or(SettingsError::BadCentre)
        };
        if !js_sys::Array::is_array(&centre) {
            return Err(SettingsError::BadCentre);
        }
        let optional = |key: &'static str| {
            let v = get(value, key);
            if v.is_undefined() || v.is_null() {
                Ok(None)
            } else {
                v.as_f64().map(Some).ok_or(SettingsError::NotANumber(key))
            }
        };
        let stop_steps = optional("stopSteps")?
            .map(|v| safe_whole(v).ok_or(SettingsError::NotAnInteger("stopSteps")))
            .transpose()?;
        let stop_target = optional("stopTarget")?;
        Ok(Self {
            landscape,
            sampler,
            temperature,
            h: number(value, "h")?,
            // Saturates: a huge count then meets the kernel's own limit.
            chains: usize::try_from(whole(value, "chains")?).unwrap_or(usize::MAX),
            centre: [coordinate(0)?, coordinate(1)?],
            spread: number(value, "spread")?,
            seed: seed(&get(value, "seed"))?,
            stop_steps,
            stop_target,
        })
    }

    /// The kernel's stopping rules, or `None` for a run without end. A
    /// target alone comes with an unreachable step budget, so that an
    /// annealing schedule's length does not become one.
    pub fn stop(&self) -> Option<Stop<f64>> {
        if self.stop_steps.is_none() && self.stop_target.is_none() {
            return None;
        }
        let stop = Stop::new().steps(self.stop_steps.unwrap_or(u64::MAX));
        Some(match self.stop_target {
            Some(t) => stop.target(t),
            None => stop,
        })
    }
}

fn get(object: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(object, &JsValue::from_str(key)).unwrap_or(JsValue::UNDEFINED)
}

/// Any JS number, NaN and infinities included: the kernel judges them.
fn number(object: &JsValue, key: &'static str) -> Result<f64, SettingsError> {
    get(object, key)
        .as_f64()
        .ok_or(SettingsError::NotANumber(key))
}

/// `v` as a u64 when it is a whole number in `0..=2^53 - 1`, where the
/// conversion is exact.
fn safe_whole(v: f64) -> Option<u64> {
    ((0.0..=MAX_SAFE_INTEGER).contains(&v) && v.fract() == 0.0).then_some(v as u64)
}

fn whole(object: &JsValue, key: &'static str) -> Result<u64, SettingsError> {
    safe_whole(number(object, key)?).ok_or(SettingsError::NotAnInteger(key))
}

fn seed(value: &JsValue) -> Result<u64, SettingsError> {
    if value.is_bigint() {
        return u64::try_from(value.clone()).map_err(|_| SettingsError::BadSeed);
    }
    value
        .as_f64()
        .and_then(safe_whole)
        .ok_or(SettingsError::BadSeed)
}
