//! The optimiser with everything hostile at once: potential, schedule
//! (built-in or an arbitrary table of values), start, chain count, stride,
//! stopping rules (step and evaluation budgets, target, stall window and
//! tolerance) and seed are all drawn from `hrla_tests::hostile`, and the
//! sampler's parameters too.
//!
//! The per-constructor tests cannot see what goes wrong only in
//! combination: a valid schedule whose value the sampler refuses mid-run, a
//! start that is finite but whose potential is not, chains that all diverge,
//! a potential unbounded below, a budget below the chain count. The
//! contract checked:
//!
//! - `build` fails exactly with the first error in its order: `Zero` for an
//!   empty storage, then for a zero stride; the `Stop` rules' errors (zero
//!   budgets or stall window, non-finite target, negative or non-finite
//!   stall tolerance); `Budget` for an evaluation budget below the chain
//!   count; `ScheduleLongerThanRun`; the sampler's error when it refuses the
//!   schedule's `a_0`; then `NonFiniteStart` naming the first chain that
//!   drew no point with finite position, value and gradient in
//!   `START_TRIES` tries (or in its evaluation budget), which was not
//!   finite at the last try, and how many it drew, or `UnboundedBelow` for
//!   a start below `-sqrt(MAX)` (replayed from each chain's own
//!   generator, redraws included);
//! - `step`, `run` and `run_with` never panic and never return a NaN best,
//!   whatever the start, schedule, stride and rules, and the best never
//!   rises; a report's termination is a rule that holds, and the
//!   evaluation budget is never exceeded;
//! - a run fails only with `AllDiverged` (every chain diverged),
//!   `UnboundedBelow` (only for the potential unbounded below, naming a
//!   chain below `-sqrt(MAX)`), or the error the sampler gives for the
//!   schedule's value at that iterate; `run` without any rule is
//!   `NoStoppingRule`.

use std::fmt::Debug;

use std::ops::ControlFlow;

use hrla::{
    Builder, Chain, Constant, Error, Gaussian, Geometric, Hrla, HrlaParams, Kernel, Linear, Ola,
    OlaParams, Point, Potential, Quadratic, Rastrigin, START_TRIES, Sampler, Schedule, Start, Stop,
    Termination, Ula, UlaParams, chain_seed,
};
use hrla_tests::hostile::{SEED, mostly_sane64, no_panic, same_error, steps_strategy, wild64};
use hrla_tests::prop::config;
use proptest::prelude::*;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// One of the built-in schedules, a plain float (any value: the sampler
/// judges it), or a table of arbitrary values.
#[derive(Clone, Copy, Debug)]
enum AnySchedule {
    Constant(Constant<f64>),
    Linear(Linear<f64>),
    Geometric(Geometric<f64>),
    Plain(f64),
    Table([f64; 4]),
}

impl Schedule<f64> for AnySchedule {
    fn length(&self) -> Option<u64> {
        match self {
            Self::Constant(s) => s.length(),
            Self::Linear(s) => s.length(),
            Self::Geometric(s) => s.length(),
            Self::Plain(a) => a.length(),
            Self::Table(_) => None,
        }
    }

    fn inverse_temperature(&self, k: u64) -> f64 {
        match self {
            Self::Constant(s) => s.inverse_temperature(k),
            Self::Linear(s) => s.inverse_temperature(k),
            Self::Geometric(s) => s.inverse_temperature(k),
            Self::Plain(a) => a.inverse_temperature(k),
            Self::Table(t) => t[(k % 4) as usize],
        }
    }
}

fn any_schedule() -> impl Strategy<Value = Option<AnySchedule>> {
    let a = mostly_sane64;
    prop_oneof![
        a().prop_map(|v| Constant::new(v).ok().map(AnySchedule::Constant)),
        (a(), a(), steps_strategy())
            .prop_map(|(l, h, k)| Linear::new(l, h, k).ok().map(AnySchedule::Linear)),
        (a(), a(), steps_strategy())
            .prop_map(|(l, h, k)| Geometric::new(l, h, k).ok().map(AnySchedule::Geometric)),
        prop::array::uniform4(a()).prop_map(|t| Some(AnySchedule::Table(t))),
    ]
}

#[derive(Clone, Copy, Debug)]
enum AnyStart {
    Point(Point<f64, 2>),
    Gaussian(Gaussian<f64, 2>),
}

impl Start<f64> for AnyStart {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [f64]) {
        match self {
            Self::Point(s) => s.initial_point(chain, rng, x),
            Self::Gaussian(s) => s.initial_point(chain, rng, x),
        }
    }
}

fn any_start() -> impl Strategy<Value = Option<AnyStart>> {
    prop_oneof![
        prop::array::uniform2(mostly_sane64())
            .prop_map(|x| Point::new(x).ok().map(AnyStart::Point)),
        (prop::array::uniform2(mostly_sane64()), mostly_sane64()).prop_map(|(m, s)| Gaussian::new(
            m, s
        )
        .ok()
        .map(AnyStart::Gaussian)),
    ]
}

/// Rastrigin, a quadratic, or `U = -|x|^4`, which sends every chain to
/// infinity in finite time (divergence paths).
#[derive(Clone, Copy, Debug)]
enum AnyPotential {
    Rastrigin,
    Quadratic(Quadratic<f64, 2>),
    Explode,
}

impl Potential<f64, 2> for AnyPotential {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        match self {
            Self::Rastrigin => Rastrigin.value_and_gradient(x, g),
            Self::Quadratic(q) => q.value_and_gradient(x, g),
            Self::Explode => {
                for (gi, xi) in g.iter_mut().zip(x) {
                    *gi = -4.0 * xi * xi * xi;
                }
                -x.iter().map(|v| v * v * v * v).sum::<f64>()
            }
        }
    }
}

fn any_potential() -> impl Strategy<Value = Option<AnyPotential>> {
    prop_oneof![
        Just(Some(AnyPotential::Rastrigin)),
        Just(Some(AnyPotential::Explode)),
        (mostly_sane64(), prop::array::uniform2(mostly_sane64()))
            .prop_map(|(k, m)| Quadratic::new(k, m).ok().map(AnyPotential::Quadratic)),
    ]
}

/// No run here goes beyond this many steps: the observer of `run_with`
/// stops it (a drawn step budget or schedule length may be huge).
const STEPS: u64 = 30;

#[derive(Clone, Copy, Debug)]
struct Wild {
    potential: Option<AnyPotential>,
    schedule: Option<AnySchedule>,
    start: Option<AnyStart>,
    chains: usize,
    stride: u64,
    steps: Option<u64>,
    evaluations: Option<u64>,
    target: Option<f64>,
    stall: Option<(u64, f64)>,
    seed: u64,
}

fn wild_setup() -> impl Strategy<Value = Wild> {
    (
        (any_potential(), any_schedule(), any_start()),
        // The zero counts, each refused by `build`, are rare enough that
        // most cases get to run.
        prop_oneof![
            1 => Just(0usize),
            10 => 1..=4usize,
            2 => Just(7usize),
        ],
        prop_oneof![
            1 => Just(0u64),
            8 => 1..5u64,
            1 => Just(u64::MAX),
            2 => any::<u64>(),
        ],
        prop_oneof![
            4 => Just(None),
            1 => Just(Some(0u64)),
            6 => (1..=STEPS).prop_map(Some),
            2 => any::<u64>().prop_map(Some),
        ],
        prop_oneof![
            6 => Just(None),
            1 => Just(Some(0u64)),
            2 => (1..8u64).prop_map(Some),
            4 => (8..200u64).prop_map(Some),
            1 => any::<u64>().prop_map(Some),
        ],
        prop_oneof![
            2 => Just(None),
            1 => wild64().prop_map(Some),
            2 => (-10.0f64..10.0).prop_map(Some),
        ],
        prop_oneof![
            4 => Just(None),
            1 => (0..5u64, wild64()).prop_map(Some),
            3 => (1..10u64, 0.0f64..1.0).prop_map(Some),
        ],
        any::<u64>(),
    )
        .prop_map(
            |(
                (potential, schedule, start),
                chains,
                stride,
                steps,
                evaluations,
                target,
                stall,
                seed,
            )| Wild {
                potential,
                schedule,
                start,
                chains,
                stride,
                steps,
                evaluations,
                target,
                stall,
                seed,
            },
        )
}

impl Wild {
    fn stop(&self) -> Stop<f64> {
        let mut stop = Stop::new();
        if let Some(k) = self.steps {
            stop = stop.steps(k);
        }
        if let Some(n) = self.evaluations {
            stop = stop.evaluations(n);
        }
        if let Some(t) = self.target {
            stop = stop.target(t);
        }
        if let Some((window, tolerance)) = self.stall {
            stop = stop.stall(window, tolerance);
        }
        stop
    }
}

/// The error `build` must give before drawing any initial point, in its
/// order of checks, if any.
fn settings_error<S: Sampler<f64>>(sampler: &S, schedule: &AnySchedule, w: &Wild) -> Option<Error> {
    let n = w.chains;
    if n == 0 {
        return Some(Error::Zero { name: "chains" });
    }
    if w.stride == 0 {
        return Some(Error::Zero { name: "stride" });
    }
    if w.steps == Some(0) {
        return Some(Error::Zero {
            name: "step budget",
        });
    }
    if w.evaluations == Some(0) {
        return Some(Error::Zero {
            name: "evaluation budget",
        });
    }
    if let Some(t) = w.target.filter(|t| !t.is_finite()) {
        return Some(Error::NotFinite {
            name: "target",
            value: t,
        });
    }
    if let Some((window, tolerance)) = w.stall {
        if window == 0 {
            return Some(Error::Zero {
                name: "stall window",
            });
        }
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Some(Error::Negative {
                name: "stall tolerance",
                value: tolerance,
            });
        }
    }
    if let Some(budget) = w.evaluations.filter(|&b| b < n as u64) {
        return Some(Error::Budget { budget, chains: n });
    }
    if let (Some(schedule), Some(steps)) = (schedule.length(), w.steps)
        && steps < schedule
    {
        return Some(Error::ScheduleLongerThanRun { schedule, steps });
    }
    sampler.at(schedule.inverse_temperature(0)).err()
}

/// Replays the initial points from each chain's own generator, with the
/// redraws of an infeasible point (non-finite position, value or gradient;
/// up to `START_TRIES` per chain, within the evaluation budget): the
/// evaluations they take, or the error of the first chain that found no
/// feasible point, or whose value is below `-sqrt(MAX)`.
fn replay_starts(potential: &AnyPotential, start: &mut AnyStart, w: &Wild) -> Result<u64, Error> {
    let n = w.chains as u64;
    let mut spare = w.evaluations.map_or(u64::MAX, |b| b - n);
    let mut evaluations = 0;
    for c in 0..w.chains {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(chain_seed(w.seed, c as u64));
        for tries in 1.. {
            let mut x = [0.0; 2];
            start.initial_point(c, &mut rng, &mut x);
            let mut g = [0.0; 2];
            let v = potential.value_and_gradient(&x, &mut g);
            evaluations += 1;
            let what = if !x.iter().all(|t| t.is_finite()) {
                "position"
            } else if v < -f64::MAX.sqrt() {
                return Err(Error::UnboundedBelow { chain: c, value: v });
            } else if !v.is_finite() {
                "value"
            } else if !g.iter().all(|t| t.is_finite()) {
                "gradient"
            } else {
                break;
            };
            if tries == START_TRIES || spare == 0 {
                return Err(Error::NonFiniteStart {
                    chain: c,
                    what,
                    tries,
                });
            }
            spare -= 1;
        }
    }
    Ok(evaluations)
}

/// Builds and runs an optimiser from a wild setup, checking every outcome
/// against its documented contract.
fn exercise<S: Sampler<f64> + Clone + Debug>(sampler: S, w: &Wild) -> Result<(), TestCaseError>
where
    S::Kernel: Debug,
{
    let (Some(potential), Some(schedule), Some(start)) = (w.potential, w.schedule, w.start) else {
        return Ok(());
    };
    let n = w.chains;
    let got = no_panic("build", || {
        Builder::new(potential, sampler.clone(), schedule, start)
            .seed(w.seed)
            .stride(w.stride)
            .stop(w.stop())
            .build(vec![Chain::<f64, 2>::new(); n])
    })?;
    let mut replay_start = start;
    let replayed = match settings_error(&sampler, &schedule, w) {
        Some(e) => Err(e),
        None => replay_starts(&potential, &mut replay_start, w),
    };
    let (want, initial) = match replayed {
        Ok(initial) => (None, initial),
        Err(e) => (Some(e), 0),
    };
    let mut opt = match (got, want) {
        (Err(e), Some(want)) => {
            prop_assert!(
                same_error(&e, &want),
                "build gave {:?}, expected {:?}",
                e,
                want
            );
            return Ok(());
        }
        (Ok(opt), None) => opt,
        (got, want) => {
            return Err(TestCaseError::fail(format!(
                "build gave {:?}, expected {want:?}",
                got.map(|o| o.iteration())
            )));
        }
    };
    let initial_best = opt.best().value;
    prop_assert!(initial_best.is_finite());
    let a0 = schedule.inverse_temperature(0);
    prop_assert_eq!(opt.kernel().inverse_temperature().to_bits(), a0.to_bits());
    prop_assert_eq!(opt.evaluations(), initial);
    // The schedule's length is the step budget when the rules have none.
    let step_budget = w.steps.or(schedule.length());
    prop_assert_eq!(*opt.stop(), {
        let mut stop = w.stop();
        if let (None, Some(k)) = (w.steps, schedule.length()) {
            stop = stop.steps(k);
        }
        stop
    });

    let no_rule =
        step_budget.is_none() && w.evaluations.is_none() && w.target.is_none() && w.stall.is_none();
    if no_rule {
        prop_assert_eq!(opt.run(), Err(Error::NoStoppingRule));
        prop_assert_eq!(opt.iteration(), 0);
    }
    let mut seen = 0u64;
    let result = no_panic("run_with", || {
        opt.run_with(hrla::Observe::EveryAndNewBest(1), |p| {
            seen += 1;
            if p.iteration >= STEPS {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
    })?;
    let best = opt.best();
    prop_assert!(best.value.is_finite(), "best {}", best.value);
    prop_assert!(best.value <= initial_best);
    prop_assert_eq!(best.iteration % w.stride, 0);
    let k = opt.iteration();
    prop_assert!(k <= STEPS);
    // Every step was shown to the observer (`every = 1`), the failed one
    // excepted.
    prop_assert!(
        seen == k || (seen + 1 == k && result.is_err()),
        "{} of {}",
        seen,
        k
    );
    let evaluations = opt.evaluations();
    prop_assert!(evaluations >= initial && evaluations <= initial + n as u64 * k);
    if let Some(budget) = w.evaluations {
        prop_assert!(
            evaluations <= budget,
            "{} evaluations > {}",
            evaluations,
            budget
        );
    }
    match result {
        Ok(report) => {
            prop_assert_eq!(report.iterations, k);
            prop_assert_eq!(report.value.to_bits(), best.value.to_bits());
            prop_assert_eq!(report.found_at, best.iteration);
            prop_assert_eq!(opt.chains()[report.chain].best(), best);
            prop_assert_eq!(report.evaluations, evaluations);
            prop_assert_eq!(report.chains, n);
            prop_assert!(report.diverged_chains < n);
            let live = (n - report.diverged_chains) as u64;
            match report.termination {
                Termination::Steps => prop_assert_eq!(step_budget, Some(k)),
                Termination::Evaluations => {
                    prop_assert!(evaluations + live > w.evaluations.unwrap())
                }
                Termination::Target => prop_assert!(best.value <= w.target.unwrap()),
                Termination::Stalled => prop_assert!(k >= w.stall.unwrap().0),
                Termination::Observer => prop_assert_eq!(k, STEPS),
                Termination::Converged => prop_assert!(false, "only Auto converges"),
            }
            if report.termination != Termination::Observer {
                prop_assert_eq!(opt.termination(), Some(report.termination));
            }
        }
        Err(Error::AllDiverged { chains }) => {
            prop_assert_eq!(chains, n);
            prop_assert_eq!(opt.diverged_chains(), n);
        }
        Err(Error::UnboundedBelow { chain, value }) => {
            prop_assert!(
                matches!(potential, AnyPotential::Explode),
                "{:?}",
                potential
            );
            prop_assert!(value < -f64::MAX.sqrt(), "{}", value);
            prop_assert_eq!(opt.chains()[chain].value().to_bits(), value.to_bits());
        }
        Err(e) => {
            // Otherwise only the sampler's refusal of the schedule's value
            // at this iterate can stop a run.
            let a = schedule.inverse_temperature(k);
            let refusal = opt.sampler().at(a);
            prop_assert!(
                refusal.as_ref().is_err_and(|r| same_error(r, &e)),
                "run failed with {:?}, but the sampler gives {:?} for a = {}",
                e,
                refusal,
                a
            );
        }
    }
    // Stepping on after the run (even after an error or full divergence)
    // does not panic and keeps a finite best.
    for _ in 0..3 {
        let _ = no_panic("step", || opt.step())?;
    }
    prop_assert!(opt.best().value.is_finite());
    let _ = opt.current_best();
    Ok(())
}

proptest! {
    #![proptest_config(config(300, SEED))]

    /// Each sampler under the wild setup, and under the wild setup with a
    /// plain float `a` for its schedule.
    #[test]
    fn optimiser_with_hrla(w in wild_setup(), a in mostly_sane64(), h in mostly_sane64()) {
        let plain = Wild { schedule: Some(AnySchedule::Plain(a)), ..w };
        if let Ok(s) = Hrla::new(HrlaParams::paper(h)) {
            exercise(s, &w)?;
            exercise(s, &plain)?;
        }
        exercise(Hrla::new(HrlaParams::paper(0.01)).unwrap(), &w)?;
        exercise(Hrla::new(HrlaParams::paper(0.01)).unwrap(), &plain)?;
    }

    #[test]
    fn optimiser_with_ula(w in wild_setup(), a in mostly_sane64(), h in mostly_sane64()) {
        if let Ok(s) = Ula::new(UlaParams::paper(h)) {
            exercise(s, &w)?;
            exercise(s, &Wild { schedule: Some(AnySchedule::Plain(a)), ..w })?;
        }
    }

    #[test]
    fn optimiser_with_ola(w in wild_setup(), a in mostly_sane64(), h in mostly_sane64()) {
        if let Ok(s) = Ola::new(OlaParams::paper(h)) {
            exercise(s, &w)?;
            exercise(s, &Wild { schedule: Some(AnySchedule::Plain(a)), ..w })?;
        }
    }
}
