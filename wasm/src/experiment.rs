//! The paper's comparison of the three dynamics (spec section 7, E2) as a
//! live run: `M` independent runs of `N` chains each on `d`-dimensional
//! Rastrigin, for HRLA, ULA and OLA from the same starts, with the
//! statistics the reproduction tool (`tools/repro`) reports.
//!
//! Every run is the run-time layer's ([`hrla_dyn::Engine`]) on the kernel's
//! Rastrigin at dimension `d`, seeded as the tool seeds its runs (run `i`
//! with `seed ^ splitmix64(i)`, chain `c` of it from
//! `chain_seed(seed ^ splitmix64(i), c)`), so that with the tool's base
//! seed 2025 the counts are the tool's to the bit. The same run index has
//! the same seed for the three samplers (common random numbers): chain `c`
//! of run `i` starts at the same point under each.
//!
//! Per iterate `k` the run records, per sampler, the statistics of the
//! paper (as `docs/REPRODUCTION.md` defines them):
//! - the **hits**: how many of the `M` runs have their best chain *at
//!   iterate `k`* within `eps` of `U* = 0` (not running); the empirical
//!   success probability is `hits / M`;
//! - the **mean running best**: per run, the least `U` over its chains and
//!   the iterates `1..=k` (iterate 0 excluded, as in the paper), averaged
//!   over the `M` runs (NaN at `k = 0`, before any).

use hrla::{AnySampler, Constant, SamplerKind, splitmix64};
use hrla_dyn::{BuiltinKind, BuiltinSpec, Engine, PotentialSpec, StartSpec};
use wasm_bindgen::prelude::*;

use crate::error::Error;
use crate::read;

/// The samplers, in the order of every per-sampler slot.
pub const SAMPLERS: [SamplerKind; 3] = [SamplerKind::Hrla, SamplerKind::Ula, SamplerKind::Ola];

/// Numbers recorded per iterate: the hits of each sampler, then the mean
/// running best of each.
pub const ROW: usize = 2 * SAMPLERS.len();

/// The largest dimension offered (the paper's E4 goes to 20).
pub const MAX_DIM: usize = 50;

/// The most runs `M`.
pub const MAX_RUNS: usize = 1000;

/// The most chains per run `N`.
pub const MAX_CHAINS_PER_RUN: usize = 1000;

/// The most chains of one sampler, `M * N`: a step of all three samplers
/// stays within a few milliseconds in the browser at `d = 10`.
pub const MAX_TOTAL_CHAINS: usize = 10_000;

/// The longest run `K`: its record, `(K + 1) * ROW` f64, is allocated once
/// (4.8 MB), so that its address never changes while JavaScript views it.
pub const MAX_STEPS: u64 = 100_000;

/// The settings of one comparison; [`Default`] is the paper's E2 panel
/// `(a = 4, eps = 2)` with the reproduction tool's base seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExperimentSettings {
    /// The dimension `d`.
    pub dim: usize,
    /// Independent runs `M`.
    pub runs: usize,
    /// Chains per run `N`.
    pub chains: usize,
    /// The inverse temperature `a` (constant).
    pub a: f64,
    /// The step `h`.
    pub h: f64,
    /// The tolerance of a success, `U - U* <= eps`.
    pub eps: f64,
    /// The run's length `K`.
    pub steps: u64,
    /// The base seed.
    pub seed: u64,
}

impl Default for ExperimentSettings {
    fn default() -> Self {
        Self {
            dim: 10,
            runs: 100,
            chains: 10,
            a: 4.0,
            h: 0.01,
            eps: 2.0,
            steps: 14_000,
            seed: 2025,
        }
    }
}

/// The keys of the settings object of [`Experiment::new_js`].
pub const EXPERIMENT_KEYS: &[&str] = &["d", "runs", "chains", "a", "h", "eps", "steps", "seed"];

impl ExperimentSettings {
    /// From a JS object with the keys [`EXPERIMENT_KEYS`]; a missing key
    /// takes its default.
    fn from_js(value: &JsValue) -> Result<Self, Error> {
        if !value.is_object() {
            return Err(Error::NotAnObject);
        }
        read::only_keys(value, EXPERIMENT_KEYS, "settings")?;
        let mut s = Self::default();
        let given = |key: &'static str| -> Result<Option<JsValue>, Error> {
            let v = read::get(value, key)?;
            Ok((!v.is_undefined()).then_some(v))
        };
        let count = |key: &'static str, min: u64, max: u64| -> Result<Option<u64>, Error> {
            given(key)?
                .map(|v| read::count(&v, key, min, max))
                .transpose()
        };
        if let Some(v) = count("d", 1, MAX_DIM as u64)? {
            s.dim = v as usize;
        }
        if let Some(v) = count("runs", 1, MAX_RUNS as u64)? {
            s.runs = v as usize;
        }
        if let Some(v) = count("chains", 1, MAX_CHAINS_PER_RUN as u64)? {
            s.chains = v as usize;
        }
        if let Some(v) = count("steps", 1, MAX_STEPS)? {
            s.steps = v;
        }
        for (key, slot) in [("a", &mut s.a), ("h", &mut s.h), ("eps", &mut s.eps)] {
            if let Some(v) = given(key)? {
                *slot = read::number(&v, key)?;
            }
        }
        if let Some(v) = given("seed")? {
            s.seed = read::seed(&v)?;
        }
        Ok(s)
    }

    /// The run-time layer's settings of run `run` of `sampler`.
    pub fn run_settings(
        &self,
        sampler: SamplerKind,
        run: usize,
    ) -> Result<hrla_dyn::Settings, Error> {
        Ok(hrla_dyn::Settings {
            potential: PotentialSpec::Builtin(BuiltinSpec::Named(BuiltinKind::Rastrigin)),
            sampler: AnySampler::paper(sampler, self.h)?,
            schedule: hrla::AnySchedule::Constant(Constant::new(self.a)?),
            // The paper's initial law, N(3·1, 10 I).
            start: StartSpec::Isotropic {
                centre: 3.0,
                std_dev: 10f64.sqrt(),
            },
            domain: None,
            seed: self.seed ^ splitmix64(run as u64),
            stride: 1,
            stop: hrla::Stop::default(),
            chains: self.chains,
            dim: Some(self.dim),
            escape: None,
        })
    }

    /// The checks the kernel does not make: counts in range and a
    /// tolerance that is a positive number.
    fn check(&self) -> Result<(), Error> {
        let counted = |name, value: usize, min: usize, max: usize| {
            if (min..=max).contains(&value) {
                Ok(())
            } else {
                Err(Error::NotACount {
                    name,
                    given: crate::error::Given::Number(value as f64),
                    min: min as u64,
                    max: max as u64,
                })
            }
        };
        counted("d", self.dim, 1, MAX_DIM)?;
        counted("runs", self.runs, 1, MAX_RUNS)?;
        counted("chains", self.chains, 1, MAX_CHAINS_PER_RUN)?;
        if self.runs * self.chains > MAX_TOTAL_CHAINS {
            return Err(hrla::Error::Count {
                name: "chains",
                value: self.runs * self.chains,
                max: MAX_TOTAL_CHAINS,
            }
            .into());
        }
        if !(1..=MAX_STEPS).contains(&self.steps) {
            return Err(Error::NotACount {
                name: "steps",
                given: crate::error::Given::Number(self.steps as f64),
                min: 1,
                max: MAX_STEPS,
            });
        }
        if !(self.eps.is_finite() && self.eps > 0.0) {
            return Err(hrla::Error::NotPositive {
                name: "eps",
                value: self.eps,
            }
            .into());
        }
        Ok(())
    }
}

/// HRLA, ULA and OLA side by side on `d`-dimensional Rastrigin, with the
/// record JavaScript views.
#[wasm_bindgen]
pub struct Experiment {
    settings: ExperimentSettings,
    /// `runs[s][i]`: run `i` of sampler `SAMPLERS[s]`.
    runs: Vec<Vec<Engine>>,
    /// `best[s][i]`: the paper's running best of run `i` (`+inf` before
    /// iterate 1).
    best: Vec<Vec<f64>>,
    /// Row `k` (`ROW` f64) for every iterate done, `0..=k`; allocated for
    /// `K + 1` rows at once so that its address never changes.
    record: Vec<f64>,
}

impl Experiment {
    /// The `3 M` runs, their initial points drawn and recorded as row 0.
    pub fn new(settings: ExperimentSettings) -> Result<Self, Error> {
        settings.check()?;
        let runs = SAMPLERS
            .iter()
            .map(|&kind| {
                (0..settings.runs)
                    .map(|i| Ok(settings.run_settings(kind, i)?.build()?))
                    .collect::<Result<Vec<_>, Error>>()
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let rows = settings.steps as usize + 1;
        let mut record = Vec::with_capacity(rows * ROW);
        record.resize(ROW, 0.0);
        let mut this = Self {
            settings,
            best: vec![vec![f64::INFINITY; settings.runs]; SAMPLERS.len()],
            runs,
            record,
        };
        this.observe(0);
        Ok(this)
    }

    /// Steps every run `steps` times, or to `K` if sooner; returns the
    /// steps done. A run whose chains have all diverged stays as it is
    /// (no best chain: within no tolerance), as in the reproduction tool.
    pub fn step_n(&mut self, steps: u64) -> Result<u64, Error> {
        let todo = steps.min(self.settings.steps - self.iteration());
        for _ in 0..todo {
            for runs in &mut self.runs {
                for run in runs {
                    match run.step(1) {
                        Ok(()) | Err(hrla_dyn::Error::Kernel(hrla::Error::AllDiverged { .. })) => {}
                        Err(e) => return Err(e.into()),
                    }
                }
            }
            let k = self.iteration() + 1;
            self.record.resize((k as usize + 1) * ROW, 0.0);
            self.observe(k);
        }
        Ok(todo)
    }

    /// Fills row `k` from the runs' chains now.
    fn observe(&mut self, k: u64) {
        let row = k as usize * ROW;
        let m = self.settings.runs as f64;
        for (s, runs) in self.runs.iter().enumerate() {
            let mut hits = 0u32;
            for (i, run) in runs.iter().enumerate() {
                let now = run.current_best().map_or(f64::INFINITY, |(_, v)| v);
                if now <= self.settings.eps {
                    hits += 1;
                }
                if k > 0 {
                    self.best[s][i] = self.best[s][i].min(now);
                }
            }
            self.record[row + s] = f64::from(hits);
            self.record[row + SAMPLERS.len() + s] = if k == 0 {
                f64::NAN
            } else {
                self.best[s].iter().sum::<f64>() / m
            };
        }
    }

    /// Iterates done.
    pub fn iteration(&self) -> u64 {
        (self.record.len() / ROW) as u64 - 1
    }

    /// The settings.
    pub fn settings(&self) -> &ExperimentSettings {
        &self.settings
    }

    /// Rows `0..=k` of the record.
    pub fn record(&self) -> &[f64] {
        &self.record
    }

    /// Run `run` of `SAMPLERS[sampler]`.
    pub fn run(&self, sampler: usize, run: usize) -> &Engine {
        &self.runs[sampler][run]
    }
}

/// Exported to JavaScript.
#[wasm_bindgen]
impl Experiment {
    /// The comparison of a settings object `{ d, runs, chains, a, h, eps,
    /// steps, seed }` (each optional: the paper's E2 panel `a = 4, eps =
    /// 2` in `d = 10`, `M = 100`, `N = 10`, `h = 0.01`, `K = 14000`, seed
    /// 2025); throws an `Error` with a `field` when one is refused.
    #[wasm_bindgen(constructor)]
    pub fn new_js(settings: &JsValue) -> Result<Experiment, JsValue> {
        ExperimentSettings::from_js(settings)
            .and_then(Experiment::new)
            .map_err(|e| e.to_js())
    }

    /// Up to `steps` more steps of every run (a whole number from 0 to
    /// `K`, else an `Error` with `field` `"steps"`), never past `K`;
    /// returns the steps done.
    pub fn advance(&mut self, steps: &JsValue) -> Result<f64, JsValue> {
        let steps = read::count(steps, "steps", 0, MAX_STEPS).map_err(|e| e.to_js())?;
        self.step_n(steps)
            .map(|done| done as f64)
            .map_err(|e| e.to_js())
    }

    /// Iterates done, `k`.
    #[wasm_bindgen(js_name = iteration)]
    pub fn iteration_js(&self) -> f64 {
        self.iteration() as f64
    }

    /// The run's length `K`.
    #[wasm_bindgen(js_name = steps)]
    pub fn steps_js(&self) -> f64 {
        self.settings.steps as f64
    }

    /// Runs per sampler, `M`.
    #[wasm_bindgen(js_name = runs)]
    pub fn runs_js(&self) -> usize {
        self.settings.runs
    }

    /// Numbers per row of the record.
    #[wasm_bindgen(js_name = rowLength)]
    pub fn row_length() -> usize {
        ROW
    }

    /// Address of the record: `(iteration() + 1) * rowLength()` f64, row
    /// `k` holding the hits of HRLA, ULA, OLA at iterate `k`, then their
    /// mean running bests. Its address never changes; its valid length
    /// grows with `iteration()`.
    pub fn record_ptr(&self) -> *const f64 {
        self.record.as_ptr()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_settings_are_refused_with_their_field() {
        let d = ExperimentSettings::default();
        let field = |s: ExperimentSettings| Experiment::new(s).err().and_then(|e| e.field());
        assert_eq!(field(ExperimentSettings { dim: 0, ..d }), Some("d"));
        assert_eq!(field(ExperimentSettings { runs: 0, ..d }), Some("runs"));
        assert_eq!(
            field(ExperimentSettings {
                runs: 1000,
                chains: 1000,
                ..d
            }),
            Some("chains")
        );
        assert_eq!(field(ExperimentSettings { steps: 0, ..d }), Some("steps"));
        assert_eq!(field(ExperimentSettings { eps: 0.0, ..d }), Some("eps"));
        assert_eq!(field(ExperimentSettings { h: -1.0, ..d }), Some("h"));
        assert_eq!(field(ExperimentSettings { a: f64::NAN, ..d }), Some("a"));
    }

    #[test]
    fn a_run_stops_at_its_length() {
        let s = ExperimentSettings {
            runs: 2,
            chains: 3,
            steps: 5,
            ..Default::default()
        };
        let mut e = Experiment::new(s).unwrap();
        assert_eq!(e.step_n(3).unwrap(), 3);
        assert_eq!(e.step_n(10).unwrap(), 2);
        assert_eq!(e.step_n(10).unwrap(), 0);
        assert_eq!(e.iteration(), 5);
        assert_eq!(e.record().len(), 6 * ROW);
    }
}
