//! The settings of a run, as plain Rust values, and how they are read from
//! the JavaScript object the page passes in.

use hrla::{SamplerKind, Stop};
use hrla_dyn::BuiltinKind;
pub use hrla_dyn::Temperature;
use wasm_bindgen::JsValue;

use crate::error::Error;
use crate::landscape::{Landscape, UnknownLandscape};
use crate::read::{get, get_as, get_index, is_array, number, only_keys, safe_whole, seed};

/// The keys a settings object may have.
pub const KEYS: [&str; 12] = [
    "potential",
    "sampler",
    "a",
    "annealing",
    "h",
    "chains",
    "centre",
    "spread",
    "seed",
    "stopSteps",
    "stopTarget",
    "escape",
];

/// The keys of the `annealing` object.
const ANNEALING_KEYS: [&str; 3] = ["aLow", "aHigh", "steps"];

/// Parses a sampler's name, `"hrla"`, `"ula"` or `"ola"` (any case).
pub fn parse_sampler(name: &str) -> Result<SamplerKind, Error> {
    name.parse().map_err(|_| Error::UnknownSampler)
}

/// Everything that determines a run: the same settings give the same numbers
/// on every target.
///
/// The sampler's other parameters are the paper's (`alpha = beta = 1`,
/// `b = 10`).
#[derive(Clone, Debug, PartialEq)]
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
    /// The escape radius `R`: a chain with `|x| > R` has run away, and the
    /// run fails ([`Error::RanAway`]) once every chain has run away or
    /// diverged (none: chains may wander anywhere finite).
    pub escape: Option<f64>,
}

impl Default for Settings {
    /// HRLA on Rastrigin at the paper's `a = 4`, `h = 0.01`, 256 chains
    /// from the paper's `N(3·1, 10 I)`, seed 1, no stopping rule.
    fn default() -> Self {
        Self {
            landscape: Landscape::named(BuiltinKind::Rastrigin),
            sampler: SamplerKind::Hrla,
            temperature: Temperature::Constant(4.0),
            h: 0.01,
            chains: 256,
            centre: [3.0, 3.0],
            spread: 10f64.sqrt(),
            seed: 1,
            stop_steps: None,
            stop_target: None,
            escape: None,
        }
    }
}

/// The keys of a visitor's potential.
const FORMULA_KEYS: [&str; 2] = ["formula", "box"];

/// A landscape from a JS value: a built-in's name (a string among
/// [`Landscape::NAMES`]), or a visitor's `{ formula: string, box: [x0, x1,
/// y0, y1] }` ([`Landscape::formula`]).
pub fn potential(value: &JsValue) -> Result<Landscape, Error> {
    if let Some(name) = value.as_string() {
        return name.parse().map_err(Error::UnknownPotential);
    }
    if !value.is_object() || is_array(value, "potential")? {
        return Err(Error::UnknownPotential(UnknownLandscape));
    }
    only_keys(value, &FORMULA_KEYS, "potential")?;
    let text = get(value, "formula")?
        .as_string()
        .ok_or(Error::BadFormulaPotential)?;
    let bounds = get(value, "box")?;
    if !is_array(&bounds, "box")? || get_as(&bounds, "length", "box")?.as_f64() != Some(4.0) {
        return Err(Error::BadFormulaPotential);
    }
    let mut b = [0.0; 4];
    for (i, v) in (0_u32..).zip(b.iter_mut()) {
        *v = get_index(&bounds, i, "box")?
            .as_f64()
            .ok_or(Error::BadFormulaPotential)?;
    }
    Ok(Landscape::formula(&text, b)?)
}

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
    ///   stopSteps: number | null, stopTarget: number | null,   // optional
    ///   escape: number | null }                                // optional, > 0
    /// ```
    ///
    /// Numbers are checked only for type here (and for being whole where a
    /// count is expected); their ranges are the kernel's business, so a bad
    /// `h` comes back as the kernel's own message. A `seed` is a u64: a JS
    /// number is accepted when it is a whole number up to `2^53 - 1` (so it
    /// is exact), a BigInt for the full range.
    ///
    /// Nothing is guessed: a key that is no setting, a `centre` that is not
    /// exactly two numbers, or an `annealing` that is neither an object nor
    /// `null` is refused, and an exception thrown while reading a setting
    /// (a getter, a `Proxy` trap) is [`Error::Threw`] with its message.
    /// Each setting is read once.
    pub fn from_js(value: &JsValue) -> Result<Self, Error> {
        if !value.is_object() || is_array(value, "settings")? {
            return Err(Error::NotAnObject);
        }
        only_keys(value, &KEYS, "settings")?;
        let landscape = match get(value, "potential")? {
            p if p.is_undefined() || p.is_null() => Landscape::named(BuiltinKind::Rastrigin),
            p => potential(&p)?,
        };
        let sampler = match get(value, "sampler")?.as_string() {
            Some(name) => parse_sampler(&name)?,
            None => return Err(Error::UnknownSampler),
        };
        let annealing = get(value, "annealing")?;
        let temperature = if annealing.is_undefined() || annealing.is_null() {
            Temperature::Constant(number(&get(value, "a")?, "a")?)
        } else if annealing.is_object() && !is_array(&annealing, "annealing")? {
            only_keys(&annealing, &ANNEALING_KEYS, "annealing")?;
            Temperature::Linear {
                a_low: number(&get(&annealing, "aLow")?, "aLow")?,
                a_high: number(&get(&annealing, "aHigh")?, "aHigh")?,
                steps: whole(&get(&annealing, "steps")?, "steps")?,
            }
        } else {
            return Err(Error::BadAnnealing);
        };
        let h = number(&get(value, "h")?, "h")?;
        // Saturates: a huge count then meets the kernel's own limit.
        let chains =
            usize::try_from(whole(&get(value, "chains")?, "chains")?).unwrap_or(usize::MAX);
        let centre = centre(&get(value, "centre")?)?;
        let spread = number(&get(value, "spread")?, "spread")?;
        let seed = seed(&get(value, "seed")?)?;
        let optional = |key: &'static str| {
            let v = get(value, key)?;
            if v.is_undefined() || v.is_null() {
                Ok(None)
            } else {
                number(&v, key).map(Some)
            }
        };
        let stop_steps = optional("stopSteps")?
            .map(|v| safe_whole(v).ok_or(Error::NotAnInteger("stopSteps")))
            .transpose()?;
        let stop_target = optional("stopTarget")?;
        let escape = optional("escape")?
            .map(|r| {
                if r.is_finite() && r > 0.0 {
                    Ok(r)
                } else {
                    Err(hrla::Error::NotPositive {
                        name: "escape",
                        value: r,
                    })
                }
            })
            .transpose()?;
        Ok(Self {
            landscape,
            sampler,
            temperature,
            h,
            chains,
            centre,
            spread,
            seed,
            stop_steps,
            stop_target,
            escape,
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

fn whole(value: &JsValue, key: &'static str) -> Result<u64, Error> {
    safe_whole(number(value, key)?).ok_or(Error::NotAnInteger(key))
}

/// Exactly two numbers: a third would otherwise be dropped unseen.
fn centre(value: &JsValue) -> Result<[f64; 2], Error> {
    if !is_array(value, "centre")? || get_as(value, "length", "centre")?.as_f64() != Some(2.0) {
        return Err(Error::BadCentre);
    }
    let coordinate = |i| {
        get_index(value, i, "centre")?
            .as_f64()
            .ok_or(Error::BadCentre)
    };
    Ok([coordinate(0)?, coordinate(1)?])
}
