//! WebAssembly face of the `hrla` kernel for the live 2-D demo page.
//!
//! A thin `wasm-bindgen` layer with no maths of its own but a visitor's
//! formula ([`Formula`]: parsed, differentiated exactly in forward mode):
//! one exported type, [`Optimizer`], translates the page's settings into
//! the run-time layer's ([`hrla_dyn::Settings`]) and owns the layer's run
//! ([`hrla_dyn::Engine`], the kernel's optimiser) on one of the kernel's
//! built-in potentials in 2-D or a formula ([`Landscape`]), in f64, with
//! up to [`MAX_CHAINS`] chains, each with its own generator, and flat
//! buffers that JavaScript reads through typed-array views into wasm
//! memory:
//!
//! ```js
//! import init, { Optimizer, Summary, wasm_memory } from "./pkg/hrla_wasm.js";
//! await init();
//! const opt = new Optimizer({ sampler: "hrla", a: 4, h: 0.01, chains: 256,
//!                             centre: [3, 3], spread: Math.sqrt(10), seed: 1n });
//! opt.advance(100);
//! const x = new Float64Array(wasm_memory().buffer, opt.positions_ptr(), 2 * opt.chains());
//! const s = new Float64Array(wasm_memory().buffer, opt.summary_ptr(), Summary.Len);
//! console.log(s[Summary.Iteration], s[Summary.BestValue]);
//! ```
//!
//! Views stay valid until wasm memory grows (creating an optimiser may grow
//! it): rebuild them when `view.buffer !== wasm_memory().buffer`.
//!
//! Bad input comes back as a JS `Error` (an [`Error`]: the kernel's typed
//! [`hrla::Error`], or the wrapper's own refusal of a malformed settings
//! object or argument), never a trap, with a `field` property naming the
//! setting or argument at fault (`"h"`, `"a_low"`, `"steps"`, ...) when
//! there is one; so does a run that fails on the way (`advance` throws the
//! kernel's [`hrla::Error::AllDiverged`] once every chain has diverged).
//! Nothing is coerced or guessed: numbers must be JS numbers, counts whole
//! numbers in their range, an unknown key is refused, and an exception
//! thrown by a getter or a `Proxy` while the settings are read is rethrown
//! as an `Error` naming the setting, with the thrown message. A run given
//! stopping rules (`stopSteps`, `stopTarget`) stops at the first that
//! holds: `advance` then returns at once having done nothing, and
//! `termination()` says why.
//!
//! [`potential_grid`] evaluates a landscape on a grid, for the page's heat
//! map, density and exact marginals: the kernel's own potential, so the
//! picture is of the function the chains see. Every value it returns is
//! finite; a box whose grid cannot be computed finitely is refused.
//!
//! Seeds are `u64`: a JS number up to `2^53 - 1` or a BigInt. Chain `c`
//! draws from `Xoshiro256PlusPlus::seed_from_u64(hrla::chain_seed(seed, c))`,
//! the same on every target, so a seed and settings give bit-identical runs
//! natively, in Node and in the browser (checked by `scripts/test-web.sh`).
//! [`random_seed`] draws a seed from the browser's crypto (or the OS
//! natively), to be shown and replayed.

#![deny(missing_docs)]
#![forbid(unsafe_code)]

/// Exports what the page's `sim.js` reads of every run type alike:
/// `chains()`, `seed()` and the addresses of the buffers in `$run`'s fields
/// `positions`, `velocities`, `values` and `summary`, in [`Optimizer`]'s
/// layout. A macro, since wasm-bindgen exports no trait's methods.
macro_rules! export_run_buffers {
    ($run:ty) => {
        /// What JavaScript reads of every run type alike.
        #[wasm_bindgen]
        impl $run {
            /// Number of chains.
            #[wasm_bindgen(js_name = chains)]
            pub fn chain_count(&self) -> usize {
                self.values.len()
            }

            /// The seed of this run (a BigInt).
            #[wasm_bindgen(js_name = seed)]
            pub fn seed_value(&self) -> u64 {
                self.seed
            }

            /// Address of the positions, `2 * chains()` f64.
            pub fn positions_ptr(&self) -> *const f64 {
                self.positions.as_ptr()
            }

            /// Address of the velocities, `2 * chains()` f64 (zeros for
            /// OLA and for descent).
            pub fn velocities_ptr(&self) -> *const f64 {
                self.velocities.as_ptr()
            }

            /// Address of the per-chain values, `chains()` f64: an
            /// optimiser's `U` of each chain (NaN for a chain that diverged,
            /// finite for every other), descent's best of each so far.
            pub fn values_ptr(&self) -> *const f64 {
                self.values.as_ptr()
            }

            /// Address of the summary, `Summary.Len` f64 indexed by `Summary`.
            pub fn summary_ptr(&self) -> *const f64 {
                self.summary.as_ptr()
            }
        }
    };
}

mod descent;
mod error;
mod experiment;
mod formula;
mod gpu;
mod landscape;
mod num;
mod read;
mod settings;

use hrla::{AnySampler, Gaussian, KnownMinimum, Termination};
use hrla::{Kernel as _, StepMoments};
use hrla_dyn::{Engine, StartSpec};
use wasm_bindgen::prelude::*;

pub use descent::Descent;
pub use error::{Error, Given};
pub use experiment::{Experiment, ExperimentSettings, ROW, SAMPLERS};
pub use formula::{Formula, FormulaError, FormulaErrorKind, MAX_FORMULA_DEPTH, MAX_FORMULA_LEN};
pub use landscape::{
    Custom, CustomError, GridError, Landscape, MAX_GRID, UnknownLandscape, formula_picture,
};
pub use settings::{KEYS, Settings, Temperature, parse_sampler, potential};

/// The most chains a run may have (the page offers up to 1024): more is
/// refused with [`hrla::Error::Count`].
pub const MAX_CHAINS: usize = 1024;

/// The most steps one call of `advance` asks for, `2^32 - 1`: more is
/// refused with [`Error::NotACount`] (the page asks for at most `1e9`).
pub const MAX_STEPS: u32 = u32::MAX;

/// Slots of the summary buffer ([`Optimizer::summary_ptr`]), all f64.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Summary {
    /// Steps done (the current iterate index `k`); exact below `2^53`.
    Iteration = 0,
    /// First coordinate of the running best point.
    BestX0 = 1,
    /// Second coordinate of the running best point.
    BestX1 = 2,
    /// `U` at the running best point.
    BestValue = 3,
    /// Iterate at which the running best was visited.
    BestIteration = 4,
    /// Inverse temperature `a` of the last step (of the first, before any).
    A = 5,
    /// Chains that diverged (frozen, excluded from the best).
    Diverged = 6,
    /// The landscape's global minimum `U*`.
    Minimum = 7,
    /// Why the run stopped ([`termination_code`]): 0 while it runs.
    Termination = 8,
    /// Number of slots.
    Len = 9,
}

/// The code of a stopping reason in [`Summary::Termination`]: 1 step
/// budget, 2 evaluation budget, 3 target, 4 stalled, 5 observer (the
/// run-time layer's one mapping).
pub use hrla_dyn::termination_code;

/// One run of Algorithm 1 on a 2-D landscape, with its chains and the
/// buffers that JavaScript views.
#[wasm_bindgen]
pub struct Optimizer {
    /// The run-time layer's run of the settings.
    engine: Engine,
    /// The potential, for its name and minimum.
    landscape: Landscape,
    seed: u64,
    /// The sampler and the temperature it was made with, for [`Optimizer::retune`].
    sampler: hrla::SamplerKind,
    temperature: Temperature,
    /// Whether the run has stopping rules to consult before each step.

    /// Whether the page set stopping rules: without, it steps past the
    /// end of an annealing schedule (at its last temperature), never
    /// consulting the step budget the schedule's length gives the kernel.
    stops: bool,
    /// Why the run stopped, once it has.
    termination: Option<Termination>,
    /// The run's failure when every chain ran away, returned again by
    /// every later call before anything else.
    failed: Option<Error>,
    /// `x` of chain `c` at `2c`, `2c + 1`.
    positions: Vec<f64>,
    /// `y` of chain `c` at `2c`, `2c + 1` (zero for OLA).
    velocities: Vec<f64>,
    /// `U(x)` of each chain: NaN once a chain diverged, finite for every
    /// other.
    values: Vec<f64>,
    summary: [f64; Summary::Len as usize],
}

// Rust side: used by the exports below and by native code (the bit-identity
// trace).
impl Optimizer {
    /// Makes the chains, draws their initial points and evaluates them, as
    /// the kernel does.
    pub fn from_settings(settings: &Settings) -> Result<Self, Error> {
        let schedule = settings.temperature.schedule()?;
        let sampler = AnySampler::paper(settings.sampler, settings.h)?;
        // The kernel's check of the start, before the chains' count.
        Gaussian::new(settings.centre, settings.spread)?;
        let n = settings.chains;
        if !(1..=MAX_CHAINS).contains(&n) {
            return Err(hrla::Error::Count {
                name: "chains",
                value: n,
                max: MAX_CHAINS,
            }
            .into());
        }
        // The page steps the run itself; without stopping rules, without
        // end.
        let stop = settings.stop();
        let engine = hrla_dyn::Settings {
            potential: settings.landscape.spec(),
            sampler,
            schedule,
            start: StartSpec::Gaussian {
                mean: settings.centre.to_vec(),
                std_dev: settings.spread,
            },
            domain: None,
            seed: settings.seed,
            stride: 1,
            stop: stop.unwrap_or_default(),
            chains: n,
            dim: Some(2),
            escape: settings.escape,
        }
        .build()?;
        let mut this = Self {
            engine,
            landscape: settings.landscape.clone(),
            seed: settings.seed,
            sampler: settings.sampler,
            temperature: settings.temperature,
            stops: stop.is_some(),
            termination: None,
            failed: None,
            positions: vec![0.0; 2 * n],
            velocities: vec![0.0; 2 * n],
            values: vec![0.0; n],
            summary: [0.0; Summary::Len as usize],
        };
        this.publish();
        Ok(this)
    }

    /// Advances every live chain by `steps` steps and returns the steps
    /// done; fewer when a stopping rule holds first (then
    /// [`Optimizer::stopped`] says which, and later calls return 0 at
    /// once) or on error: [`hrla::Error::AllDiverged`] once every chain
    /// has diverged, the sampler's refusal of a temperature, or
    /// [`Error::RanAway`] after the first step at which every chain has run
    /// away beyond the escape radius or diverged (checked after every
    /// step, so the run ends at the same iteration however it is driven).
    /// The buffers show the state reached either way, and a failed run
    /// keeps failing.
    pub fn step_n(&mut self, steps: u32) -> Result<u32, Error> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        // An ended run has nothing left to do: no spinning through the
        // rest of the count.
        if self.termination.is_some() {
            return Ok(0);
        }
        let before = self.engine.iteration();
        let steps = u64::from(steps);
        let result = if self.stops {
            self.engine.run_for(steps)
        } else {
            self.engine.step(steps).map(|()| None)
        };
        let mut result = result.map_err(Error::from);
        if let Err(Error::RanAway { lowest, .. }) = &mut result {
            // Downhill or uphill: an unbounded U, or a step too long.
            let low = self
                .engine
                .values()
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            *lowest = (low < self.landscape.global_minimum()).then_some(low);
        }
        match &result {
            Ok(termination) => self.termination = self.termination.or(*termination),
            Err(e @ Error::RanAway { .. }) => self.failed = Some(e.clone()),
            Err(_) => {}
        }
        self.publish();
        // At most `steps`, a `u32`: the count fits.
        let done = u32::try_from(self.engine.iteration() - before).unwrap_or(u32::MAX);
        result.map(|_| done)
    }

    /// Sets the step `h` of the next steps and, for a run at a constant
    /// temperature, its inverse temperature `a` (`None` keeps it; an
    /// annealing run keeps its schedule, which is indexed by the
    /// iteration). Every chain keeps its state, its running best and its
    /// random stream: a run retuned at iteration `k` goes on exactly as a
    /// replay retuned at the same `k`. Refused, with the run unchanged: an
    /// `h` or `a` the sampler or the schedule refuses, an `a` for an
    /// annealing run, and any change to a run that failed.
    pub fn retune(&mut self, h: f64, a: Option<f64>) -> Result<(), Error> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let temperature = match (self.temperature, a) {
            (Temperature::Constant(_), Some(a)) => Temperature::Constant(a),
            (t, None) => t,
            (_, Some(_)) => return Err(Error::AnnealedA),
        };
        let schedule = temperature.schedule()?;
        let sampler = AnySampler::paper(self.sampler, h)?;
        self.engine.retune(sampler, schedule)?;
        self.temperature = temperature;
        self.publish();
        Ok(())
    }

    /// Why the run stopped, once a stopping rule held.
    pub fn stopped(&self) -> Option<Termination> {
        self.termination
    }

    /// The law of chain `chain`'s next step, from the kernel's own
    /// coefficients at the inverse temperature that step runs at
    /// (`a_k` of the schedule at the current iteration `k`): per
    /// coordinate, the mean and covariance of the new `(x_i, y_i)` given the
    /// current `x`, `y` and the gradient frozen at `x`
    /// ([`hrla::Kernel::moments`]). Coordinates are independent given the
    /// current state. Errors: a chain index out of range
    /// ([`Error::NotACount`]), a chain that has diverged
    /// ([`Error::Diverged`]: it is frozen, it has no next step), or the
    /// sampler's refusal of `a_k`.
    pub fn next_step(&self, chain: usize) -> Result<NextStep, Error> {
        let n = self.values.len();
        if chain >= n {
            return Err(Error::NotACount {
                name: "chain",
                given: Given::Number(chain as f64),
                min: 0,
                max: n as u64 - 1,
            });
        }
        if self.engine.diverged()[chain] {
            return Err(Error::Diverged { chain });
        }
        let step = self.engine.next_kernel()?;
        let a = step.inverse_temperature();
        let of = |v: Vec<f64>| [v[2 * chain], v[2 * chain + 1]];
        let (x, y, g) = (
            of(self.engine.positions()),
            of(self.engine.velocities()),
            of(self.engine.gradients()),
        );
        // The mean is affine in (x, y, g): its parts come from the same
        // moments at a zero position with only the gradient, or only the
        // velocity.
        Ok(NextStep {
            a,
            x,
            y,
            gradient: g,
            moments: [0, 1].map(|i| step.moments(x[i], y[i], g[i])),
            gradient_push: [0, 1].map(|i| step.moments(0.0, 0.0, g[i]).mean_x),
            velocity_push: [0, 1].map(|i| step.moments(0.0, y[i], 0.0).mean_x),
        })
    }

    /// The run-time layer's run.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// Positions, `[x0, x1]` per chain.
    pub fn positions(&self) -> &[f64] {
        &self.positions
    }

    /// Velocities, `[y0, y1]` per chain.
    pub fn velocities(&self) -> &[f64] {
        &self.velocities
    }

    /// `U(x)` per chain; NaN for a diverged chain.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The summary, indexed by [`Summary`].
    pub fn summary(&self) -> &[f64; Summary::Len as usize] {
        &self.summary
    }

    /// Copies the kernel's state into the flat buffers JavaScript views:
    /// the kernel keeps each chain as one struct, JS wants one array per
    /// quantity.
    fn publish(&mut self) {
        // Copied into the buffers JavaScript views (their addresses never
        // change).
        self.positions.copy_from_slice(&self.engine.positions());
        self.velocities.copy_from_slice(&self.engine.velocities());
        // The kernel keeps a diverged chain's last value, finite when only
        // the position or gradient overflowed; the buffer promises a
        // non-finite value, so that no reader takes the chain for live.
        let diverged = self.engine.diverged();
        for ((v, u), d) in self
            .values
            .iter_mut()
            .zip(self.engine.values())
            .zip(diverged)
        {
            *v = if d { f64::NAN } else { u };
        }
        let (x, value, iteration) = self.engine.best();
        self.summary = [
            self.engine.iteration() as f64,
            x[0],
            x[1],
            value,
            iteration as f64,
            self.engine.inverse_temperature(),
            self.engine.diverged_chains() as f64,
            self.landscape.global_minimum(),
            termination_code(self.termination),
        ];
    }
}

/// One chain's next step laid bare: the state it starts from and the
/// Gaussian law of where it lands ([`Optimizer::next_step`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NextStep {
    /// The inverse temperature of the step.
    pub a: f64,
    /// The position.
    pub x: [f64; 2],
    /// The velocity (zero for OLA, which has none).
    pub y: [f64; 2],
    /// `∇U(x)`, frozen over the step.
    pub gradient: [f64; 2],
    /// Per coordinate, the mean and covariance of the new `(x_i, y_i)`.
    pub moments: [StepMoments<f64>; 2],
    /// The gradient's part of the mean move of the position (`-c g`).
    pub gradient_push: [f64; 2],
    /// The velocity's part of the mean move of the position (`c' y`; zero
    /// for OLA).
    pub velocity_push: [f64; 2],
}

impl NextStep {
    /// Number of f64 in [`NextStep::to_array`].
    pub const LEN: usize = 21;

    /// Flat, for JavaScript: `a, x0, x1, y0, y1, g0, g1`, then per
    /// coordinate `mean_x, mean_y, var_x, cov_xy, var_y`, then the
    /// gradient's push (two) and the velocity's push (two).
    pub fn to_array(&self) -> [f64; Self::LEN] {
        let [m0, m1] = self.moments;
        [
            self.a,
            self.x[0],
            self.x[1],
            self.y[0],
            self.y[1],
            self.gradient[0],
            self.gradient[1],
            m0.mean_x,
            m0.mean_y,
            m0.var_x,
            m0.cov_xy,
            m0.var_y,
            m1.mean_x,
            m1.mean_y,
            m1.var_x,
            m1.cov_xy,
            m1.var_y,
            self.gradient_push[0],
            self.gradient_push[1],
            self.velocity_push[0],
            self.velocity_push[1],
        ]
    }
}

/// Exported to JavaScript.
#[wasm_bindgen]
impl Optimizer {
    /// The law of chain `chain`'s next step (see [`Optimizer::next_step`]),
    /// flat as [`NextStep::to_array`]: `[a, x0, x1, y0, y1, g0, g1,` then
    /// per coordinate `mean_x, mean_y, var_x, cov_xy, var_y`, then the
    /// gradient's and the velocity's push of the mean, two each`]`. `chain` must
    /// be a JS number holding a whole number below `chains()`; throws an
    /// `Error` with `field` `"chain"` otherwise, or for a chain that has
    /// diverged.
    #[wasm_bindgen(js_name = nextStep)]
    pub fn next_step_js(&self, chain: &JsValue) -> Result<Vec<f64>, JsValue> {
        let max = self.values.len() as u64 - 1;
        let c = read::count(chain, "chain", 0, max).map_err(|e| e.to_js())?;
        // In range by the check above.
        self.next_step(c as usize)
            .map(|s| s.to_array().to_vec())
            .map_err(|e| e.to_js())
    }

    /// Creates a run from a settings object (see [`Settings::from_js`]);
    /// throws an `Error` with the reason when a setting is refused.
    #[wasm_bindgen(constructor)]
    pub fn new(settings: &JsValue) -> Result<Optimizer, JsValue> {
        Settings::from_js(settings)
            .and_then(|s| Self::from_settings(&s))
            .map_err(|e| e.to_js())
    }

    /// Advances every live chain by `steps` steps, refreshes the buffers
    /// and returns the steps done: fewer once a stopping rule holds, and 0
    /// at once when one already held. `steps` must be a JS number holding
    /// a whole number from 0 to [`MAX_STEPS`], else it throws an `Error`
    /// with `field` `"steps"` and nothing is done. Throws an `Error` with
    /// the kernel's message once every chain has diverged (`all N chains
    /// diverged ...`, again on every later call), or if annealing reaches
    /// a temperature the sampler refuses; the buffers then show the state
    /// reached.
    pub fn advance(&mut self, steps: &JsValue) -> Result<u32, JsValue> {
        let steps = read::count(steps, "steps", 0, MAX_STEPS.into()).map_err(|e| e.to_js())?;
        // In range by the check above.
        let steps = u32::try_from(steps).unwrap_or(MAX_STEPS);
        self.step_n(steps).map_err(|e| e.to_js())
    }

    /// Sets the step `h` and the inverse temperature `a` of the next steps
    /// without a restart (see [`Optimizer::retune`]); `a` `undefined` or
    /// `null` keeps the temperature (an annealing run takes no `a`).
    /// Throws an `Error` with `field` `"h"` or `"a"` on a value refused.
    #[wasm_bindgen(js_name = retune)]
    pub fn retune_js(&mut self, h: &JsValue, a: &JsValue) -> Result<(), JsValue> {
        let h = read::number(h, "h").map_err(|e| e.to_js())?;
        let a = if a.is_undefined() || a.is_null() {
            None
        } else {
            Some(read::number(a, "a").map_err(|e| e.to_js())?)
        };
        self.retune(h, a).map_err(|e| e.to_js())
    }

    /// Why the run stopped (`"target reached"`, `"step budget spent"`), or
    /// `undefined` while it runs.
    #[wasm_bindgen(js_name = termination)]
    pub fn termination_text(&self) -> Option<String> {
        self.termination.map(|t| t.to_string())
    }

    /// The landscape's name.
    #[wasm_bindgen(js_name = potential)]
    pub fn potential_name(&self) -> String {
        self.landscape.name().into()
    }

    /// The landscape's global minimiser `x*`, `[x0, x1]` (one of them
    /// when there are several).
    pub fn minimiser(&self) -> Vec<f64> {
        self.landscape.global_minimiser().to_vec()
    }
}

export_run_buffers!(Optimizer);

/// The landscape a JS value names: see [`settings::potential`].
fn landscape(name: &JsValue) -> Result<Landscape, Error> {
    settings::potential(name)
}

/// `U` of the landscape `name` at the cell centres of an `nx` by `ny` grid
/// over `[x0, x1] x [y0, y1]`, row by row from the top: the kernel's own
/// potential, for the page's pictures (see [`Landscape::grid`]). Every
/// value is finite. Throws an `Error` with a `field` (`potential`, `x0`,
/// ..., `nx`, `ny`, `box`) on a name that is not a landscape's, a bound
/// that is not a JS number, a count that is not a whole number in
/// `1..=MAX_GRID`, a box that is not finite and increasing or whose width
/// overflows, more than [`MAX_GRID`] points, or a cell where `U` is not
/// finite.
#[wasm_bindgen]
pub fn potential_grid(
    name: &JsValue,
    x0: &JsValue,
    x1: &JsValue,
    y0: &JsValue,
    y1: &JsValue,
    nx: &JsValue,
    ny: &JsValue,
) -> Result<Vec<f64>, JsValue> {
    let grid = || -> Result<Vec<f64>, Error> {
        let landscape = landscape(name)?;
        let ([x0, x1, y0, y1], nx, ny) = grid_layout([x0, x1, y0, y1], [nx, ny])?;
        Ok(landscape.grid(x0, x1, y0, y1, nx, ny)?)
    };
    grid().map_err(|e| e.to_js())
}

/// Reads a grid's box and counts as [`potential_grid`] takes them: the
/// counts first, then the bounds.
fn grid_layout(
    bounds: [&JsValue; 4],
    counts: [&JsValue; 2],
) -> Result<([f64; 4], usize, usize), Error> {
    let max = MAX_GRID as u64;
    // Counts up to MAX_GRID fit a usize on every target.
    let [nx, ny] = [(counts[0], "nx"), (counts[1], "ny")]
        .map(|(v, n)| read::count(v, n, 1, max).map(|c| c as usize));
    let (nx, ny) = (nx?, ny?);
    let [x0, x1, y0, y1] = [
        (bounds[0], "x0"),
        (bounds[1], "x1"),
        (bounds[2], "y0"),
        (bounds[3], "y1"),
    ]
    .map(|(v, n)| read::number(v, n));
    Ok(([x0?, x1?, y0?, y1?], nx, ny))
}

/// A visitor's formula `U` on a grid laid out as [`potential_grid`]'s, NaN
/// where it is not finite ([`formula_picture`]): the picture of a formula
/// the page refuses on its box, or sees beyond it. Throws an `Error` with
/// `field` `"formula"` (with a `column`) when the formula cannot be read,
/// and as [`potential_grid`] on the bounds and counts.
#[wasm_bindgen(js_name = formulaPicture)]
pub fn formula_picture_js(
    formula: &str,
    x0: &JsValue,
    x1: &JsValue,
    y0: &JsValue,
    y1: &JsValue,
    nx: &JsValue,
    ny: &JsValue,
) -> Result<Vec<f64>, JsValue> {
    let grid = || -> Result<Vec<f64>, Error> {
        let (bounds, nx, ny) = grid_layout([x0, x1, y0, y1], [nx, ny])?;
        Ok(formula_picture(formula, bounds, nx, ny)?)
    };
    grid().map_err(|e| e.to_js())
}

/// The global minimum `U*` of the landscape `name` (the kernel's
/// [`KnownMinimum`]; for a visitor's formula, the estimate of
/// [`Landscape::formula`]); throws an `Error` with `field` `"potential"`
/// when `name` is not a landscape's name or a formula object, `"formula"`
/// (with a `column`) when the formula cannot be read, `"box"` when it
/// cannot be evaluated finitely over its box.
#[wasm_bindgen]
pub fn global_minimum(name: &JsValue) -> Result<f64, JsValue> {
    landscape(name)
        .map(|l| l.global_minimum())
        .map_err(|e| e.to_js())
}

/// A global minimiser `x*` of the landscape `potential` (one of them when
/// there are several; for a visitor's formula, where its estimated `U*`
/// was found), `[x0, x1]`; throws like [`global_minimum`].
#[wasm_bindgen]
pub fn global_minimiser(potential: &JsValue) -> Result<Vec<f64>, JsValue> {
    landscape(potential)
        .map(|l| l.global_minimiser().to_vec())
        .map_err(|e| e.to_js())
}

/// The names of the landscapes, as `potential` takes them.
#[wasm_bindgen]
pub fn potential_names() -> Vec<String> {
    Landscape::NAMES.iter().map(|&n| n.into()).collect()
}

/// The capacity in chains, [`MAX_CHAINS`].
#[wasm_bindgen]
pub fn max_chains() -> usize {
    MAX_CHAINS
}

/// A fresh seed from the browser's `crypto.getRandomValues` (the OS
/// natively), as a BigInt, for the "random" button: the page shows it so
/// the run can be replayed.
#[wasm_bindgen]
pub fn random_seed() -> Result<u64, JsError> {
    getrandom::u64().map_err(|e| JsError::new(&format!("no random seed available: {e}")))
}

/// The module's `WebAssembly.Memory`, for typed-array views (named so as
/// not to clash with the module's own `memory` export).
#[wasm_bindgen]
pub fn wasm_memory() -> JsValue {
    wasm_bindgen::memory()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_follow_the_kernel() {
        let settings = Settings {
            chains: 7,
            ..Settings::default()
        };
        let mut opt = Optimizer::from_settings(&settings).unwrap();
        opt.step_n(50).unwrap();
        let run = opt.engine();
        assert_eq!(opt.summary()[Summary::Iteration as usize], 50.0);
        assert_eq!(opt.summary()[Summary::BestValue as usize], run.best().1);
        assert_eq!(opt.positions(), run.positions());
        assert_eq!(opt.velocities(), run.velocities());
        assert!(run.diverged().iter().all(|d| !d));
        for (mine, theirs) in opt.values().iter().zip(run.values()) {
            assert_eq!(mine.to_bits(), theirs.to_bits());
        }
    }

    #[test]
    fn bad_settings_are_typed_errors() {
        let bad_h = Settings {
            h: -1.0,
            ..Settings::default()
        };
        assert!(matches!(
            Optimizer::from_settings(&bad_h),
            Err(Error::Kernel(hrla::Error::NotPositive { name: "h", .. }))
        ));
        for sampler in hrla::SamplerKind::ALL {
            let nan_h = Settings {
                sampler,
                h: f64::NAN,
                ..Settings::default()
            };
            assert!(Optimizer::from_settings(&nan_h).is_err(), "{sampler:?}");
        }
        let too_many = Settings {
            chains: MAX_CHAINS + 1,
            ..Settings::default()
        };
        let message = Optimizer::from_settings(&too_many)
            .err()
            .unwrap()
            .to_string();
        assert_eq!(message, "`chains` must be between 1 and 1024, got 1025");
        let bad_schedule = Settings {
            temperature: Temperature::Linear {
                a_low: 0.1,
                a_high: 4.0,
                steps: 0,
            },
            ..Settings::default()
        };
        assert!(Optimizer::from_settings(&bad_schedule).is_err());
    }

    #[test]
    fn same_seed_same_run() {
        let settings = Settings {
            sampler: hrla::SamplerKind::Ula,
            temperature: Temperature::Linear {
                a_low: 0.1,
                a_high: 4.0,
                steps: 300,
            },
            chains: 16,
            seed: u64::MAX,
            ..Settings::default()
        };
        let mut a = Optimizer::from_settings(&settings).unwrap();
        let mut b = Optimizer::from_settings(&settings).unwrap();
        a.step_n(400).unwrap();
        for _ in 0..4 {
            b.step_n(100).unwrap();
        }
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.summary(), b.summary());
        assert_eq!(a.summary()[Summary::A as usize], 4.0);
    }

    /// Each chain has its own stream: chain `c` of a run is the same
    /// whatever the number of chains beside it.
    #[test]
    fn a_chain_does_not_depend_on_the_others() {
        let settings = Settings {
            chains: 3,
            seed: 9,
            ..Settings::default()
        };
        let mut few = Optimizer::from_settings(&settings).unwrap();
        let mut many = Optimizer::from_settings(&Settings {
            chains: 40,
            ..settings
        })
        .unwrap();
        few.step_n(300).unwrap();
        many.step_n(300).unwrap();
        assert_eq!(few.positions(), &many.positions()[..6]);
        assert_eq!(few.values(), &many.values()[..3]);
    }

    /// A step far too long for Rastrigin: every chain overflows, and the
    /// run ends with the kernel's `AllDiverged`, then keeps refusing.
    #[test]
    fn all_diverged_is_an_error_with_the_state_published() {
        let settings = Settings {
            sampler: hrla::SamplerKind::Ola,
            h: 50.0,
            chains: 10,
            ..Settings::default()
        };
        let mut opt = Optimizer::from_settings(&settings).unwrap();
        let err = opt.step_n(1000).unwrap_err();
        assert_eq!(err, Error::Kernel(hrla::Error::AllDiverged { chains: 10 }));
        assert_eq!(
            err.to_string(),
            "all 10 chains diverged (non-finite position, potential or gradient): try a smaller step h"
        );
        let s = *opt.summary();
        assert_eq!(s[Summary::Diverged as usize], 10.0);
        assert!(s[Summary::Iteration as usize] > 0.0 && s[Summary::Iteration as usize] < 1000.0);
        assert!(s[Summary::BestValue as usize].is_finite());
        assert_eq!(
            opt.step_n(1),
            Err(Error::Kernel(hrla::Error::AllDiverged { chains: 10 }))
        );
        assert_eq!(opt.summary(), &s);
    }

    /// A step far too long for Rastrigin (h = 1): the chains grow
    /// geometrically with finite values, so the kernel sees no divergence;
    /// with an escape radius the run fails at the first step where every
    /// chain is beyond it, whatever the steps asked per call, and keeps
    /// failing.
    /// A retune keeps every chain's state and stream: the same change at
    /// the same iteration gives the same bits, however the run is driven.
    #[test]
    fn a_retuned_run_replays_bit_for_bit() {
        let settings = Settings {
            chains: 8,
            ..Settings::default()
        };
        let drive = |chunks: &[u32]| {
            let mut opt = Optimizer::from_settings(&settings).unwrap();
            let mut done = 0;
            for &k in chunks {
                opt.step_n(k).unwrap();
                done += k;
                if done == 30 {
                    opt.retune(0.05, Some(2.5)).unwrap();
                }
            }
            assert_eq!(opt.summary()[Summary::A as usize], 2.5);
            opt.positions().to_vec()
        };
        let a = drive(&[30, 70]);
        assert_eq!(a, drive(&[10, 20, 1, 69]));
        // A retune changes the run from there on.
        let mut plain = Optimizer::from_settings(&settings).unwrap();
        plain.step_n(100).unwrap();
        assert_ne!(a, plain.positions());
        // Refused values leave the run as it is.
        let mut opt = Optimizer::from_settings(&settings).unwrap();
        assert_eq!(opt.retune(-1.0, None).unwrap_err().field(), Some("h"));
        assert_eq!(opt.retune(0.1, Some(-2.0)).unwrap_err().field(), Some("a"));
        opt.step_n(100).unwrap();
        assert_eq!(opt.positions(), plain.positions());
    }

    #[test]
    fn every_chain_beyond_the_escape_radius_fails_the_run() {
        let settings = Settings {
            h: 1.0,
            chains: 16,
            centre: [3.0, 3.0],
            spread: 0.5,
            escape: Some(5000.0),
            ..Settings::default()
        };
        let mut whole = Optimizer::from_settings(&settings).unwrap();
        let err = whole.step_n(10_000).unwrap_err();
        let at = whole.summary()[Summary::Iteration as usize];
        assert!(at > 1.0 && at < 1000.0, "failed at {at}");
        assert_eq!(whole.summary()[Summary::Diverged as usize], 0.0);
        let Error::RanAway {
            chains,
            radius,
            farthest,
            diverged,
            lowest: None,
        } = err
        else {
            panic!("{err:?}");
        };
        assert_eq!((chains, radius, diverged), (16, 5000.0, 0));
        assert!(farthest > 5000.0 && farthest.is_finite());
        for x in whole.positions().chunks_exact(2) {
            assert!(x[0].hypot(x[1]) > 5000.0);
        }
        assert!(
            err.to_string()
                .starts_with("all 16 chains ran away beyond |x| = 5000")
        );
        assert_eq!(err.field(), Some("h"));
        // One step at a time: the same iteration, the same state.
        let mut single = Optimizer::from_settings(&settings).unwrap();
        let mut failed = None;
        for _ in 0..10_000 {
            if let Err(e) = single.step_n(1) {
                failed = Some(e);
                break;
            }
        }
        assert_eq!(failed, Some(err.clone()));
        assert_eq!(single.summary(), whole.summary());
        assert_eq!(single.positions(), whole.positions());
        assert_eq!(single.step_n(1), Err(err));
        assert_eq!(single.summary()[Summary::Iteration as usize], at);
        // Without a radius the same run goes on.
        let mut free = Optimizer::from_settings(&Settings {
            escape: None,
            ..settings
        })
        .unwrap();
        assert_eq!(free.step_n(at as u32 + 10), Ok(at as u32 + 10));
    }

    /// The law `next_step` shows is the one the next step draws from: over
    /// 1024 chains (2048 coordinates, seed fixed), the standardised
    /// residuals of the new position (and for HRLA and ULA of the new
    /// velocity) have mean 0 and variance 1, and HRLA's and ULA's position
    /// and velocity residuals the correlation of the covariance shown.
    /// Tolerances: 4 standard errors (mean 1/sqrt(n), variance sqrt(2/n),
    /// the mean product of the residuals, whose variance is
    /// (1 + rho^2)/n), under annealing so that `a_k` matters.
    #[test]
    fn next_step_is_the_law_the_step_draws_from() {
        for sampler in hrla::SamplerKind::ALL {
            let settings = Settings {
                sampler,
                temperature: Temperature::Linear {
                    a_low: 0.5,
                    a_high: 4.0,
                    steps: 40,
                },
                chains: 1024,
                spread: 1.0,
                seed: 77,
                ..Settings::default()
            };
            let mut opt = Optimizer::from_settings(&settings).unwrap();
            opt.step_n(17).unwrap();
            let laws: Vec<NextStep> = (0..1024).map(|c| opt.next_step(c).unwrap()).collect();
            for law in &laws {
                for i in 0..2 {
                    let parts = law.x[i] + law.gradient_push[i] + law.velocity_push[i];
                    let mean = law.moments[i].mean_x;
                    assert!(
                        (parts - mean).abs() <= 1e-12 * (1.0 + mean.abs()),
                        "{sampler:?}"
                    );
                }
            }
            assert_eq!(laws[0].a, 0.5 + 3.5 * 17.0 / 40.0, "{sampler:?}");
            opt.step_n(1).unwrap();
            let (mut zx, mut zy) = (Vec::new(), Vec::new());
            let mut rho = 0.0;
            for (c, law) in laws.iter().enumerate() {
                for (i, m) in law.moments.iter().enumerate() {
                    zx.push((opt.positions()[2 * c + i] - m.mean_x) / m.var_x.sqrt());
                    if m.var_y > 0.0 {
                        zy.push((opt.velocities()[2 * c + i] - m.mean_y) / m.var_y.sqrt());
                        rho = m.cov_xy / (m.var_x * m.var_y).sqrt();
                    } else {
                        assert_eq!(opt.velocities()[2 * c + i], m.mean_y, "{sampler:?}");
                    }
                }
            }
            let n = zx.len() as f64;
            let mean = |z: &[f64]| z.iter().sum::<f64>() / z.len() as f64;
            let var = |z: &[f64]| {
                let m = mean(z);
                z.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (z.len() as f64 - 1.0)
            };
            assert!(
                mean(&zx).abs() < 4.0 / n.sqrt(),
                "{sampler:?} {}",
                mean(&zx)
            );
            assert!(
                (var(&zx) - 1.0).abs() < 4.0 * (2.0 / n).sqrt(),
                "{sampler:?} {}",
                var(&zx)
            );
            if sampler == hrla::SamplerKind::Ola {
                assert!(zy.is_empty());
                continue;
            }
            assert!(mean(&zy).abs() < 4.0 / n.sqrt(), "{sampler:?}");
            assert!(
                (var(&zy) - 1.0).abs() < 4.0 * (2.0 / n).sqrt(),
                "{sampler:?}"
            );
            let r = zx.iter().zip(&zy).map(|(a, b)| a * b).sum::<f64>() / n;
            assert!(
                (r - rho).abs() < 4.0 * ((1.0 + rho * rho) / n).sqrt(),
                "{sampler:?}: correlation {r} against {rho}"
            );
        }
        let opt = Optimizer::from_settings(&Settings {
            chains: 3,
            ..Settings::default()
        })
        .unwrap();
        assert!(matches!(
            opt.next_step(3),
            Err(Error::NotACount { name: "chain", .. })
        ));
    }

    /// A step budget stops the run there; a target alone stops it when
    /// reached, and an annealing schedule's length is not a budget.
    #[test]
    fn stopping_rules_stop_the_run_and_say_why() {
        let budget = Settings {
            stop_steps: Some(30),
            chains: 8,
            ..Settings::default()
        };
        let mut opt = Optimizer::from_settings(&budget).unwrap();
        assert_eq!(opt.step_n(100), Ok(30));
        assert_eq!(opt.summary()[Summary::Iteration as usize], 30.0);
        assert_eq!(opt.stopped(), Some(Termination::Steps));
        assert_eq!(opt.summary()[Summary::Termination as usize], 1.0);
        assert_eq!(opt.step_n(10), Ok(0));
        // An ended run returns at once, however many steps are asked.
        assert_eq!(opt.step_n(MAX_STEPS), Ok(0));
        assert_eq!(opt.summary()[Summary::Iteration as usize], 30.0);

        let annealed_target = Settings {
            landscape: "quadratic".parse().unwrap(),
            temperature: Temperature::Linear {
                a_low: 0.5,
                a_high: 4.0,
                steps: 50,
            },
            stop_target: Some(1e-12),
            chains: 8,
            ..Settings::default()
        };
        let mut opt = Optimizer::from_settings(&annealed_target).unwrap();
        opt.step_n(200).unwrap();
        assert_eq!(opt.summary()[Summary::Iteration as usize], 200.0);
        assert_eq!(opt.stopped(), None);

        let target = Settings {
            stop_target: Some(1.0),
            ..annealed_target
        };
        let mut opt = Optimizer::from_settings(&target).unwrap();
        opt.step_n(10_000).unwrap();
        assert_eq!(opt.stopped(), Some(Termination::Target));
        assert!(opt.summary()[Summary::BestValue as usize] <= 1.0);
        assert!(opt.summary()[Summary::Iteration as usize] < 10_000.0);
    }

    #[test]
    fn errors_name_the_setting_at_fault() {
        let field = |s: Settings| Optimizer::from_settings(&s).err().unwrap().field();
        let d = Settings::default();
        assert_eq!(
            field(Settings {
                h: 0.0,
                ..d.clone()
            }),
            Some("h")
        );
        assert_eq!(
            field(Settings {
                h: 1e9,
                ..d.clone()
            }),
            Some("alpha h")
        );
        assert_eq!(
            field(Settings {
                chains: 0,
                ..d.clone()
            }),
            Some("chains")
        );
        assert_eq!(
            field(Settings {
                spread: -1.0,
                ..d.clone()
            }),
            Some("std_dev")
        );
        assert_eq!(
            field(Settings {
                stop_steps: Some(10),
                temperature: Temperature::Linear {
                    a_low: 1.0,
                    a_high: 2.0,
                    steps: 100
                },
                ..d.clone()
            }),
            Some("stopSteps")
        );
        assert_eq!(
            field(Settings {
                stop_target: Some(f64::NAN),
                ..d.clone()
            }),
            Some("target")
        );
    }

    /// The kernel keeps a diverged chain's last value, which may be finite
    /// (a finite `U` beside an overflowing gradient); the published value
    /// is not, so that no diverged chain counts as near the minimum.
    #[test]
    fn a_diverged_chain_publishes_no_finite_value() {
        // Levy with a step far too long: within 100 steps a chain diverges
        // with a finite last value (found by search; the run is seeded).
        let settings = Settings {
            landscape: "levy".parse().unwrap(),
            h: 1.0,
            chains: 64,
            ..Settings::default()
        };
        let mut opt = Optimizer::from_settings(&settings).unwrap();
        let mut seen = false;
        for _ in 0..100 {
            opt.step_n(1).unwrap();
            let (diverged, values) = (opt.engine().diverged(), opt.engine().values());
            for c in 0..values.len() {
                seen |= diverged[c] && values[c].is_finite();
                assert_eq!(opt.values()[c].is_finite(), !diverged[c], "chain {c}");
            }
        }
        assert!(
            seen,
            "no diverged chain with a finite value: the case tests nothing"
        );
        let live = opt.values().iter().filter(|u| u.is_finite()).count();
        assert_eq!(live, 64 - opt.engine().diverged_chains());
    }

    #[test]
    fn the_summary_carries_the_landscape_minimum() {
        let settings = Settings {
            landscape: "styblinski-tang".parse().unwrap(),
            chains: 4,
            ..Settings::default()
        };
        let opt = Optimizer::from_settings(&settings).unwrap();
        assert_eq!(
            opt.summary()[Summary::Minimum as usize],
            2.0 * -39.166_165_703_771_41
        );
    }
}
