//! The optimiser with everything hostile at once: potential, schedule
//! (built-in or an arbitrary table of values), start, chain count, stride,
//! target and seed are all drawn from `hrla_tests::hostile`, and the
//! sampler's parameters too.
//!
//! The per-constructor tests cannot see what goes wrong only in
//! combination: a valid schedule whose value the sampler refuses mid-run, a
//! start that is finite but whose potential is not, chains that all diverge.
//! The contract checked:
//!
//! - construction fails exactly with `Count` for a bad chain count, then
//!   with the sampler's error when it refuses the schedule's `a_0`, then
//!   with `NonFiniteStart` naming the first chain whose point or potential
//!   is not finite (replayed from the same random numbers);
//! - `step` and `run` never panic and never return a NaN best, whatever the
//!   start, schedule, stride and target, and the best never rises;
//! - `run` fails only with the error the sampler gives for the schedule's
//!   value at that iterate.

use std::fmt::Debug;

use hrla::{
    Constant, Error, Gaussian, Geometric, Hrla, HrlaParams, Kernel, Linear, Ola, OlaParams,
    Optimizer, Point, Potential, Quadratic, Rastrigin, Sampler, Schedule, Start, Status, Ula,
    UlaParams,
};
use hrla_tests::hostile::{
    SEED, expect_error, mostly_sane64, no_panic, same_error, steps_strategy, wild64,
};
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

impl Start<f64, 2> for AnyStart {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R) -> [f64; 2] {
        match self {
            Self::Point(s) => s.initial_point(chain, rng),
            Self::Gaussian(s) => s.initial_point(chain, rng),
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

const CAP: usize = 4;
const STEPS: u64 = 30;

#[derive(Clone, Copy, Debug)]
struct Wild {
    potential: Option<AnyPotential>,
    schedule: Option<AnySchedule>,
    start: Option<AnyStart>,
    chains: usize,
    stride: u64,
    target: f64,
    seed: u64,
}

fn wild_setup() -> impl Strategy<Value = Wild> {
    (
        any_potential(),
        any_schedule(),
        any_start(),
        prop_oneof![
            1 => Just(0),
            6 => 1..=CAP,
            1 => Just(CAP + 1),
            1 => Just(usize::MAX),
        ],
        prop_oneof![
            1 => Just(0u64),
            4 => 1..5u64,
            1 => Just(u64::MAX),
            1 => any::<u64>(),
        ],
        prop_oneof![1 => wild64(), 3 => -10.0f64..10.0],
        any::<u64>(),
    )
        .prop_map(
            |(potential, schedule, start, chains, stride, target, seed)| Wild {
                potential,
                schedule,
                start,
                chains,
                stride,
                target,
                seed,
            },
        )
}

/// Constructs and runs an optimiser from a wild setup, checking every
/// outcome against its documented contract.
fn exercise<S: Sampler<f64> + Clone + Debug>(sampler: S, w: &Wild) -> Result<(), TestCaseError>
where
    S::Kernel: Debug,
{
    let (Some(potential), Some(schedule), Some(mut start)) = (w.potential, w.schedule, w.start)
    else {
        return Ok(());
    };
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(w.seed);
    let rng0 = rng.clone();
    let start0 = start;
    let got = no_panic("Optimizer::new", || {
        Optimizer::<f64, AnyPotential, S, AnySchedule, 2, CAP>::new(
            potential,
            sampler.clone(),
            schedule,
            w.chains,
            &mut start,
            &mut rng,
        )
    })?;
    if w.chains == 0 || w.chains > CAP {
        prop_assert_eq!(
            got.unwrap_err(),
            Error::Count {
                name: "chains",
                value: w.chains,
                max: CAP
            }
        );
        return Ok(());
    }
    // The kernel at a_0 is taken before any initial point: its refusal is
    // the error.
    let a0 = schedule.inverse_temperature(0);
    if let Err(refusal) = sampler.at(a0) {
        let e = got.map(|o| o.report()).unwrap_err();
        prop_assert!(
            same_error(&e, &refusal),
            "construction failed with {:?}, but the sampler gives {:?} for a_0 = {}",
            e,
            refusal,
            a0
        );
        return Ok(());
    }
    // Replay the draws: the first chain whose point or potential is not
    // finite is the one reported.
    let mut replay_rng = rng0;
    let mut replay_start = start0;
    let mut first_bad = None;
    for c in 0..w.chains {
        let x = replay_start.initial_point(c, &mut replay_rng);
        let mut g = [0.0; 2];
        let v = potential.value_and_gradient(&x, &mut g);
        if !(v.is_finite() && x.iter().chain(&g).all(|t| t.is_finite())) {
            first_bad = Some(c);
            break;
        }
    }
    let opt = match (got, first_bad) {
        (Err(e), Some(c)) => {
            prop_assert_eq!(e, Error::NonFiniteStart { chain: c });
            return Ok(());
        }
        (Ok(opt), None) => opt,
        (got, bad) => {
            return Err(TestCaseError::fail(format!(
                "construction gave {:?}, expected bad chain {bad:?}",
                got.map(|o| o.report())
            )));
        }
    };
    let initial_best = opt.best().value;
    prop_assert!(initial_best.is_finite());
    prop_assert_eq!(opt.kernel().inverse_temperature().to_bits(), a0.to_bits());

    let opt = match no_panic("with_stride", || opt.with_stride(w.stride))? {
        Ok(o) => o,
        Err(e) => {
            prop_assert_eq!(w.stride, 0);
            prop_assert_eq!(e, Error::Zero { name: "stride" });
            return Ok(());
        }
    };
    prop_assert!(w.stride > 0);
    let mut opt = match no_panic("with_target", || opt.with_target(w.target))? {
        Ok(o) => o,
        Err(e) => {
            prop_assert!(!w.target.is_finite());
            expect_error::<()>(
                Err(e),
                Error::NotFinite {
                    name: "target",
                    value: w.target,
                },
            )?;
            return Ok(());
        }
    };
    prop_assert!(w.target.is_finite());

    let result = no_panic("run", || opt.run(STEPS, &mut rng))?;
    prop_assert!(opt.best().value.is_finite(), "best {}", opt.best().value);
    prop_assert!(opt.best().value <= initial_best);
    prop_assert_eq!(opt.best().iteration % w.stride, 0);
    match result {
        Ok(report) => {
            prop_assert!(report.best.value.is_finite());
            prop_assert!(report.iterations <= STEPS);
            prop_assert!(report.diverged_chains <= w.chains);
            prop_assert!(report.gradient_evaluations >= w.chains as u64);
            prop_assert!(report.gradient_evaluations <= w.chains as u64 * (report.iterations + 1));
            match report.status {
                Status::Running => prop_assert_eq!(report.iterations, STEPS),
                Status::TargetReached => prop_assert!(report.best.value <= w.target),
                Status::AllDiverged => prop_assert_eq!(report.diverged_chains, w.chains),
            }
        }
        Err(e) => {
            // Only the sampler's refusal of the schedule's value at this
            // iterate can stop a run.
            let a = schedule.inverse_temperature(opt.iteration());
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
        let _ = no_panic("step", || opt.step(&mut rng))?;
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
