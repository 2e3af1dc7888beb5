//! A hostile campaign over the public entry points: `Interval`, the
//! schedules, `Lbfgs`, `Builder` and `Optimizer` (step, run, polish,
//! quench, restart in any order), and `Auto`, each with wild numbers and
//! with potentials that are unbounded below, infeasible (NaN) in regions,
//! NaN in scattered pockets, or flat over boxes as wide as the floats.
//!
//! The contract checked everywhere: no panic; no hang (every budget and
//! step count drawn is bounded, or an observer bounds it); and no `Ok`
//! whose value is non-finite or below `-sqrt(MAX)` (the floor): every
//! value a result carries, every best point and every live chain is
//! finite and above it. Errors are typed; the ones that end a run
//! (`UnboundedBelow`, `AllDiverged`) stay.

use std::cell::RefCell;
use std::ops::ControlFlow;

use hrla::{
    Auto, Builder, Chain, Constant, Domain, Error, Gaussian, Geometric, Hrla, Interval, Lbfgs,
    Linear, Parts, Point, PolishSettings, Potential, Problem, Quadratic, Rastrigin, Sampling,
    Schedule, Start, Stop, Termination, Unbounded,
};
use hrla_tests::hostile::{mostly_sane64, no_panic, steps_strategy, wild64};
use hrla_tests::prop::config;
use proptest::prelude::*;
use rand_xoshiro::rand_core::Rng;

/// The proptest seed of the campaign.
const SEED: u64 = 0xca3_9a16;

fn floor() -> f64 {
    -f64::MAX.sqrt()
}

/// A value that a successful result may carry.
fn sound(v: f64) -> bool {
    v.is_finite() && v >= floor()
}

/// Potentials in 2-D that break things in every way but panicking.
#[derive(Clone, Copy, Debug)]
enum Wild {
    Rastrigin,
    Quadratic(Quadratic<f64, 2>),
    /// `-|x|^4`: every chain leaves for `-inf`.
    Explode,
    /// `-exp(x0)`: unbounded below in one direction only, bounded in the
    /// other.
    MinusExp,
    /// `x0 - ln x0 + x1^2`: NaN for `x0 < 0`.
    LogBarrier,
    /// Rastrigin with NaN at one point in 5 (by the bits of `x`, so that
    /// the same point always gives the same value).
    Pockets,
    /// `1e-300 x0`: tiny values over boxes as wide as the floats.
    Flat,
}

impl Potential<f64, 2> for Wild {
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
            Self::MinusExp => {
                let v = -libm::exp(x[0]);
                *g = [v, 2.0 * x[1]];
                v + x[1] * x[1]
            }
            Self::LogBarrier => {
                *g = [1.0 - 1.0 / x[0], 2.0 * x[1]];
                x[0] - libm::log(x[0]) + x[1] * x[1]
            }
            Self::Pockets => {
                let v = Rastrigin.value_and_gradient(x, g);
                let h = (x[0].to_bits() ^ x[1].to_bits().rotate_left(17))
                    .wrapping_mul(0x9e37_79b9_7f4a_7c15);
                if h >> 61 == 0 { f64::NAN } else { v }
            }
            Self::Flat => {
                *g = [1e-300, 0.0];
                x[0] * 1e-300
            }
        }
    }
}

fn wild_potential() -> impl Strategy<Value = Wild> {
    prop_oneof![
        Just(Wild::Rastrigin),
        (mostly_sane64(), prop::array::uniform2(mostly_sane64()))
            .prop_map(|(k, m)| Quadratic::new(k, m).map_or(Wild::Rastrigin, Wild::Quadratic)),
        Just(Wild::Explode),
        Just(Wild::MinusExp),
        Just(Wild::LogBarrier),
        Just(Wild::Pockets),
        Just(Wild::Flat),
    ]
}

/// All of `R^2` or a box.
#[derive(Clone, Copy, Debug)]
enum AnyDomain {
    Free,
    Box(Interval<f64>),
}

impl Domain<f64> for AnyDomain {
    fn confine(&self, x: &mut [f64], y: &mut [f64]) {
        match self {
            Self::Free => Unbounded.confine(x, y),
            Self::Box(b) => b.confine(x, y),
        }
    }
    fn project(&self, x: &mut [f64]) {
        match self {
            Self::Free => Domain::<f64>::project(&Unbounded, x),
            Self::Box(b) => Domain::<f64>::project(b, x),
        }
    }
    fn feasible_direction(&self, x: &[f64], d: &mut [f64]) {
        match self {
            Self::Free => Unbounded.feasible_direction(x, d),
            Self::Box(b) => b.feasible_direction(x, d),
        }
    }
}

impl AnyDomain {
    fn contains(&self, x: &[f64; 2]) -> bool {
        match self {
            Self::Free => true,
            Self::Box(b) => x.iter().all(|&v| v >= b.lo() && v <= b.hi()),
        }
    }
}

/// Ends of an interval: ordinary, wild, or as wide as the floats.
fn wild_end() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -10.0f64..10.0,
        2 => wild64(),
        1 => prop::sample::select(vec![6e307, -6e307, 8.9e307, -8.9e307, 1e-300, -1e-300]),
    ]
}

fn wild_interval() -> impl Strategy<Value = Option<Interval<f64>>> {
    (wild_end(), wild_end()).prop_map(|(lo, hi)| Interval::new(lo.min(hi), lo.max(hi)).ok())
}

fn wild_domain() -> impl Strategy<Value = AnyDomain> {
    prop_oneof![
        1 => Just(AnyDomain::Free),
        2 => wild_interval().prop_map(|b| b.map_or(AnyDomain::Free, AnyDomain::Box)),
    ]
}

#[derive(Clone, Copy, Debug)]
enum AnyStart {
    Point(Point<f64, 2>),
    Gaussian(Gaussian<f64, 2>),
    Box(Interval<f64>),
}

impl Start<f64> for AnyStart {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [f64]) {
        match self {
            Self::Point(s) => s.initial_point(chain, rng, x),
            Self::Gaussian(s) => s.initial_point(chain, rng, x),
            Self::Box(s) => s.initial_point(chain, rng, x),
        }
    }
}

fn wild_start() -> impl Strategy<Value = AnyStart> {
    let fallback = AnyStart::Point(Point::new([1.0, 1.0]).unwrap());
    prop_oneof![
        prop::array::uniform2(wild64())
            .prop_map(move |x| Point::new(x).map_or(fallback, AnyStart::Point)),
        (prop::array::uniform2(mostly_sane64()), mostly_sane64())
            .prop_map(move |(m, s)| Gaussian::new(m, s).map_or(fallback, AnyStart::Gaussian)),
        wild_interval().prop_map(move |b| b.map_or(fallback, AnyStart::Box)),
    ]
}

/// The built-in schedules, a plain float, a table of any values, and one
/// that claims a length of 0.
#[derive(Clone, Copy, Debug)]
enum AnySchedule {
    Constant(Constant<f64>),
    Linear(Linear<f64>),
    Geometric(Geometric<f64>),
    Plain(f64),
    Table([f64; 3]),
    Empty,
}

impl Schedule<f64> for AnySchedule {
    fn inverse_temperature(&self, k: u64) -> f64 {
        match self {
            Self::Constant(s) => s.inverse_temperature(k),
            Self::Linear(s) => s.inverse_temperature(k),
            Self::Geometric(s) => s.inverse_temperature(k),
            Self::Plain(a) => *a,
            Self::Table(t) => t[(k % 3) as usize],
            Self::Empty => 1.0,
        }
    }
    fn length(&self) -> Option<u64> {
        match self {
            Self::Linear(s) => s.length(),
            Self::Geometric(s) => s.length(),
            Self::Empty => Some(0),
            _ => None,
        }
    }
}

fn wild_schedule() -> impl Strategy<Value = AnySchedule> {
    let a = mostly_sane64;
    let plain = AnySchedule::Plain(1.0);
    prop_oneof![
        a().prop_map(move |v| Constant::new(v).map_or(plain, AnySchedule::Constant)),
        (a(), a(), steps_strategy())
            .prop_map(move |(l, h, k)| Linear::new(l, h, k).map_or(plain, AnySchedule::Linear)),
        (a(), a(), steps_strategy()).prop_map(
            move |(l, h, k)| Geometric::new(l, h, k).map_or(plain, AnySchedule::Geometric)
        ),
        a().prop_map(AnySchedule::Plain),
        prop::array::uniform3(a()).prop_map(AnySchedule::Table),
        Just(AnySchedule::Empty),
    ]
}

/// One call on a built optimiser.
#[derive(Clone, Copy, Debug)]
enum Op {
    Step,
    /// A run with an observer that stops it after this many more steps.
    Run(u64),
    Polish(usize, u64),
    Quench(usize, u64),
    Restart(usize, [f64; 2]),
}

fn wild_chain() -> impl Strategy<Value = usize> {
    prop_oneof![4 => 0..8usize, 1 => Just(usize::MAX)]
}

fn polish_budget() -> impl Strategy<Value = u64> {
    prop_oneof![Just(0u64), 1..50u64, 50..3_000u64]
}

fn wild_op() -> impl Strategy<Value = Op> {
    prop_oneof![
        Just(Op::Step),
        (1..40u64).prop_map(Op::Run),
        (wild_chain(), polish_budget()).prop_map(|(c, b)| Op::Polish(c, b)),
        (wild_chain(), polish_budget()).prop_map(|(c, b)| Op::Quench(c, b)),
        (wild_chain(), prop::array::uniform2(wild64())).prop_map(|(c, x)| Op::Restart(c, x)),
    ]
}

/// Steps a run may take in all: `Op::Run` is at most 40, at most 8 ops.
const MAX_STEPS: u64 = 8 * 40;

#[derive(Clone, Debug)]
struct Setup {
    potential: Wild,
    domain: AnyDomain,
    start: AnyStart,
    schedule: AnySchedule,
    h: f64,
    chains: usize,
    steps: Option<u64>,
    evaluations: Option<u64>,
    seed: u64,
    ops: Vec<Op>,
}

fn wild_setup() -> impl Strategy<Value = Setup> {
    (
        (
            wild_potential(),
            wild_domain(),
            wild_start(),
            wild_schedule(),
        ),
        mostly_sane64(),
        prop_oneof![1 => Just(0usize), 8 => 1..=8usize],
        prop::option::of(prop_oneof![Just(0u64), 1..100u64, Just(u64::MAX)]),
        prop::option::of(prop_oneof![
            Just(0u64),
            1..40u64,
            40..3_000u64,
            Just(u64::MAX)
        ]),
        any::<u64>(),
        prop::collection::vec(wild_op(), 1..8),
    )
        .prop_map(
            |((potential, domain, start, schedule), h, chains, steps, evaluations, seed, ops)| {
                Setup {
                    potential,
                    domain,
                    start,
                    schedule,
                    h,
                    chains,
                    steps,
                    evaluations,
                    seed,
                    ops,
                }
            },
        )
}

/// The state every call must leave: a sound best, live chains finite,
/// above the floor and in the domain, the budgets kept.
fn check_state<O>(opt: &O, s: &Setup) -> Result<(), TestCaseError>
where
    O: View,
{
    let (best, evaluations, iteration) = opt.view();
    prop_assert!(sound(best), "best {}", best);
    // `step` does what it is told: only the other calls keep the budget.
    let by_hand = s.ops.iter().any(|op| matches!(op, Op::Step));
    if let (Some(b), false) = (s.evaluations, by_hand) {
        prop_assert!(
            evaluations <= b,
            "{} evaluations > budget {}",
            evaluations,
            b
        );
    }
    prop_assert!(iteration <= MAX_STEPS);
    for (c, chain) in opt.chains_view().iter().enumerate() {
        prop_assert!(
            sound(chain.best().value),
            "chain {} best {}",
            c,
            chain.best().value
        );
        prop_assert!(s.domain.contains(chain.best().x.try_into().unwrap()));
        if !chain.is_diverged() {
            prop_assert!(sound(chain.value()), "chain {} at {}", c, chain.value());
            prop_assert!(chain.x().iter().all(|v| v.is_finite()));
            prop_assert!(
                s.domain.contains(chain.x()),
                "chain {} at {:?}",
                c,
                chain.x()
            );
        }
    }
    Ok(())
}

/// What [`check_state`] reads from an optimiser (whose full type is long).
trait View {
    fn view(&self) -> (f64, u64, u64);
    fn chains_view(&self) -> &[Chain<f64, 2>];
}

impl<St: AsRef<[Chain<f64, 2>]> + AsMut<[Chain<f64, 2>]>> View
    for hrla::Optimizer<f64, Wild, Hrla<f64>, AnySchedule, hrla::Chains<f64, St, 2>, AnyDomain>
{
    fn view(&self) -> (f64, u64, u64) {
        (self.best().value, self.evaluations(), self.iteration())
    }
    fn chains_view(&self) -> &[Chain<f64, 2>] {
        self.chains()
    }
}

/// The errors after which a run stays failed.
fn sticky(e: &Error) -> bool {
    matches!(
        e,
        Error::UnboundedBelow { .. } | Error::AllDiverged { .. } | Error::Poisoned
    )
}

fn exercise_optimizer(s: &Setup, counts: &mut [u32; 4]) -> Result<(), TestCaseError> {
    let sampler = Hrla::paper(s.h).unwrap_or(Hrla::paper(0.01).unwrap());
    let mut stop = Stop::new();
    if let Some(k) = s.steps {
        stop = stop.steps(k);
    }
    if let Some(b) = s.evaluations {
        stop = stop.evaluations(b);
    }
    let built = no_panic("build", || {
        Builder::new(s.potential, sampler, s.schedule, s.start)
            .domain(s.domain)
            .seed(s.seed)
            .stop(stop)
            .build(vec![Chain::<f64, 2>::new(); s.chains])
    })?;
    let mut opt = match built {
        Ok(opt) => opt,
        Err(e) => {
            counts[0] += 1;
            if matches!(s.schedule, AnySchedule::Empty) && s.chains > 0 {
                prop_assert!(
                    matches!(e, Error::Zero { .. } | Error::Budget { .. }),
                    "{:?}",
                    e
                );
            }
            return Ok(());
        }
    };
    counts[1] += 1;
    prop_assert!(!matches!(s.schedule, AnySchedule::Empty));
    check_state(&opt, s)?;
    let mut lbfgs: Lbfgs<f64, 2, 4> = Lbfgs::new();
    let mut failed: Option<Error> = None;
    for &op in &s.ops {
        let done: Result<Option<f64>, Error> = no_panic("op", || match op {
            Op::Step => opt.step().map(|_| None),
            Op::Run(k) => {
                let until = opt.iteration() + k;
                opt.run_with(hrla::Observe::EveryAndNewBest(1), |p| {
                    if p.iteration >= until {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                })
                .map(|r| Some(r.value))
            }
            Op::Polish(c, b) => opt
                .polish(c, &mut lbfgs, PolishSettings::new(b))
                .map(|p| Some(p.value)),
            Op::Quench(c, b) => opt
                .quench(c, &mut lbfgs, PolishSettings::new(b))
                .map(|p| Some(p.value)),
            Op::Restart(c, x) => opt.restart(c, &x).map(|_| None),
        })?;
        match done {
            Ok(Some(v)) => prop_assert!(sound(v), "{:?} gave {}", op, v),
            Ok(None) => {}
            Err(e) => {
                // An index out of range is refused before anything else.
                if let (Some(f), false) = (failed, matches!(e, Error::Index { .. })) {
                    prop_assert_eq!(e, f, "a failed run changed its error");
                }
                if sticky(&e) {
                    failed = Some(e);
                }
                if let Error::UnboundedBelow { value, .. } = e {
                    prop_assert!(value < floor());
                }
            }
        }
        if let Some(f) = failed {
            prop_assert_eq!(opt.step(), Err(f));
        }
        check_state(&opt, s)?;
    }
    counts[2] += 1;
    if failed.is_some() {
        counts[3] += 1;
    }
    Ok(())
}

/// Auto's constants, anything.
fn wild_auto() -> impl Strategy<Value = Auto<f64>> {
    (
        prop_oneof![
            1 => Just(0u64),
            6 => 1..100u64,
            1 => Just(hrla::MAX_STEPS),
            1 => Just(hrla::MAX_STEPS + 1),
            1 => Just(u64::MAX),
            1 => any::<u64>()
        ],
        mostly_sane64(),
        mostly_sane64(),
        prop_oneof![Just(0u64), 1..200u64, Just(u64::MAX)],
        prop_oneof![1 => Just(0u64), 4 => 1..100u64, 1 => Just(u64::MAX)],
        prop_oneof![
            Just(Sampling::Langevin),
            Just(Sampling::Jump),
            Just(Sampling::Differential)
        ],
        any::<bool>(),
        prop_oneof![1 => mostly_sane64(), 3 => 0.0f64..=1.0],
    )
        .prop_map(
            |(steps, step_scale, ladder, quench, stall, sampling, quenches, accept)| Auto {
                steps,
                step_scale,
                ladder,
                quench,
                first_quench: quench,
                stall,
                accept,
                parts: Parts { sampling, quenches },
            },
        )
}

/// Budgets that end by themselves, or never (an observer ends the run).
fn auto_budget() -> impl Strategy<Value = u64> {
    prop_oneof![Just(0u64), 1..100u64, 100..6_000u64, Just(u64::MAX)]
}

/// Evaluations after which the observer stops a run of endless budget.
const AUTO_CAP: u64 = 6_000;

fn exercise_auto(
    auto: &Auto<f64>,
    potential: Wild,
    domain: Option<Interval<f64>>,
    budget: u64,
    n: usize,
    seed: u64,
    counts: &mut [u32; 4],
) -> Result<(), TestCaseError> {
    let Some(domain) = domain else {
        counts[2] += 1;
        return Ok(());
    };
    let mut lbfgs: Lbfgs<f64, 2, 3> = Lbfgs::new();
    let mut chains = vec![Chain::<f64, 2>::new(); n];
    let mut calls = 0u64;
    let got = no_panic("Auto::minimize_with", || {
        auto.minimize_with(
            &Problem::new(&potential, &domain, budget).seed(seed),
            (&mut chains[..], &mut lbfgs),
            |p| {
                calls += 1;
                assert!(sound(p.value), "observer saw {}", p.value);
                if p.evaluations >= AUTO_CAP {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
    })?;
    match got {
        Ok(found) => {
            counts[1] += 1;
            prop_assert!(sound(found.value), "{:?}", found);
            prop_assert!(found.evaluations <= budget, "{:?}", found);
            prop_assert!(AnyDomain::Box(domain).contains(&found.x), "{:?}", found);
            prop_assert_eq!(
                potential.value(&found.x).to_bits(),
                found.value.to_bits(),
                "{:?}",
                found
            );
            prop_assert_eq!(found.chains, n);
            prop_assert!(found.diverged_chains <= n);
            prop_assert!(calls >= 1);
            match found.termination {
                Termination::Observer => prop_assert!(budget > AUTO_CAP),
                Termination::Evaluations => {}
                t => prop_assert!(false, "Auto ended with {:?}", t),
            }
        }
        Err(e) => {
            counts[0] += 1;
            if let Error::UnboundedBelow { value, .. } = e {
                counts[3] += 1;
                prop_assert!(value < floor());
            }
        }
    }
    Ok(())
}

/// Case counts of the properties, printed so that `--nocapture` shows
/// what each covered.
fn report(what: &str, counts: &[u32; 4], names: [&str; 4]) {
    let parts: Vec<String> = names
        .iter()
        .zip(counts)
        .map(|(n, c)| format!("{c} {n}"))
        .collect();
    println!("{what}: {}", parts.join(", "));
}

const OPTIMIZER_CASES: u32 = 10_000;
const AUTO_CASES: u32 = 2_000;
const LBFGS_CASES: u32 = 20_000;
const INTERVAL_CASES: u32 = 50_000;
const SCHEDULE_CASES: u32 = 50_000;

#[test]
fn optimizer_campaign() {
    let counts = RefCell::new([0u32; 4]);
    let mut runner = proptest::test_runner::TestRunner::new(config(OPTIMIZER_CASES, SEED));
    runner
        .run(&wild_setup(), |s| {
            exercise_optimizer(&s, &mut counts.borrow_mut())
        })
        .unwrap();
    let counts = counts.into_inner();
    report(
        "Builder + Optimizer",
        &counts,
        [
            "refused by build",
            "built",
            "op sequences run",
            "ended failed",
        ],
    );
    // The campaign reaches both sides of every door.
    assert!(
        counts[0] > 500 && counts[1] > 3_000 && counts[3] > 300,
        "{counts:?}"
    );
}

#[test]
fn auto_campaign() {
    let counts = RefCell::new([0u32; 4]);
    let mut runner = proptest::test_runner::TestRunner::new(config(AUTO_CASES, SEED + 1));
    let strategy = (
        wild_auto(),
        wild_potential(),
        wild_interval(),
        auto_budget(),
        prop_oneof![1 => Just(0usize), 6 => 1..12usize, 1 => 60..70usize],
        any::<u64>(),
    );
    runner
        .run(&strategy, |(auto, p, domain, budget, n, seed)| {
            exercise_auto(&auto, p, domain, budget, n, seed, &mut counts.borrow_mut())
        })
        .unwrap();
    // Sane constants, so that most runs get going.
    let mut runner = proptest::test_runner::TestRunner::new(config(AUTO_CASES, SEED + 2));
    let strategy = (
        wild_potential(),
        wild_interval(),
        auto_budget(),
        1..12usize,
        any::<u64>(),
    );
    runner
        .run(&strategy, |(p, domain, budget, n, seed)| {
            exercise_auto(
                &Auto::default(),
                p,
                domain,
                budget,
                n,
                seed,
                &mut counts.borrow_mut(),
            )
        })
        .unwrap();
    let counts = counts.into_inner();
    report(
        "Auto",
        &counts,
        [
            "refused",
            "solved",
            "skipped (no valid box drawn)",
            "unbounded below",
        ],
    );
    assert!(
        counts[0] > 500 && counts[1] > 1_000 && counts[3] > 30,
        "{counts:?}"
    );
}

/// L-BFGS alone: `Ok` only with a sound value at a finite point of the
/// domain, `U` there, and never above the start.
fn exercise_lbfgs<const M: usize>(
    p: Wild,
    domain: AnyDomain,
    x0: [f64; 2],
    budget: u64,
    counts: &mut [u32; 4],
) -> Result<(), TestCaseError> {
    let mut lbfgs: Lbfgs<f64, 2, M> = Lbfgs::new();
    let mut x = x0;
    let got = no_panic("Lbfgs::minimize_in", || {
        lbfgs.minimize_in(&p, &domain, &mut x, PolishSettings::new(budget))
    })?;
    match got {
        Ok(done) => {
            counts[1] += 1;
            prop_assert!(sound(done.value), "{:?}", done);
            prop_assert!(x.iter().all(|v| v.is_finite()) && domain.contains(&x));
            prop_assert_eq!(p.value(&x).to_bits(), done.value.to_bits());
            prop_assert!(done.evaluations <= budget);
            let mut start = x0;
            domain.project(&mut start);
            prop_assert!(done.value <= p.value(&start));
        }
        Err(e) => {
            counts[0] += 1;
            if let Error::UnboundedBelow { value, .. } = e {
                counts[3] += 1;
                prop_assert!(value < floor());
            }
        }
    }
    Ok(())
}

#[test]
fn lbfgs_campaign() {
    let counts = RefCell::new([0u32; 4]);
    let mut runner = proptest::test_runner::TestRunner::new(config(LBFGS_CASES, SEED + 3));
    let strategy = (
        wild_potential(),
        wild_domain(),
        prop::array::uniform2(prop_oneof![3 => -10.0f64..10.0, 1 => wild64()]),
        polish_budget(),
        0..3usize,
    );
    runner
        .run(&strategy, |(p, domain, x0, budget, m)| match m {
            0 => exercise_lbfgs::<1>(p, domain, x0, budget, &mut counts.borrow_mut()),
            1 => exercise_lbfgs::<3>(p, domain, x0, budget, &mut counts.borrow_mut()),
            _ => exercise_lbfgs::<8>(p, domain, x0, budget, &mut counts.borrow_mut()),
        })
        .unwrap();
    let counts = counts.into_inner();
    report(
        "Lbfgs",
        &counts,
        ["refused", "polished", "", "unbounded below"],
    );
    assert!(
        counts[0] > 1_000 && counts[1] > 5_000 && counts[3] > 200,
        "{counts:?}"
    );
}

/// `Interval::new` accepts exactly the finite `lo < hi` of finite width;
/// reflecting any finite point into it, projecting onto it and drawing
/// from it give finite points inside it.
#[test]
fn interval_campaign() {
    let counts = RefCell::new([0u32; 4]);
    let mut runner = proptest::test_runner::TestRunner::new(config(INTERVAL_CASES, SEED + 4));
    let strategy = (
        wild_end(),
        wild_end(),
        prop::array::uniform2(prop_oneof![wild64(), wild_end()]),
        any::<u64>(),
    );
    runner
        .run(&strategy, |(lo, hi, x0, seed)| {
            let got = no_panic("Interval::new", || Interval::new(lo, hi))?;
            let valid = lo.is_finite() && hi.is_finite() && hi > lo && (hi - lo).is_finite();
            prop_assert_eq!(got.is_ok(), valid, "{} {}", lo, hi);
            let Ok(b) = got else {
                counts.borrow_mut()[0] += 1;
                return Ok(());
            };
            counts.borrow_mut()[1] += 1;
            let inside = |x: &[f64; 2]| x.iter().all(|&v| v >= lo && v <= hi);
            let (mut x, mut y) = (x0, [1.0, -1.0]);
            no_panic("confine", || b.confine(&mut x, &mut y))?;
            for (xi, x0i) in x.iter().zip(&x0) {
                if x0i.is_finite() {
                    prop_assert!(xi.is_finite() && *xi >= lo && *xi <= hi, "{:?} -> {:?} in [{}, {}]", x0, x, lo, hi);
                }
            }
            prop_assert!(y.iter().all(|v| v.abs() == 1.0));
            let mut p = x0;
            Domain::<f64>::project(&b, &mut p);
            if x0.iter().all(|v| v.is_finite()) {
                counts.borrow_mut()[2] += 1;
                prop_assert!(inside(&p));
            }
            let mut rng = <rand_xoshiro::Xoshiro256PlusPlus as rand_xoshiro::rand_core::SeedableRng>::seed_from_u64(seed);
            let mut s = b;
            let mut d = [0.0; 2];
            s.initial_point(0, &mut rng, &mut d);
            prop_assert!(inside(&d), "{:?}", d);
            Ok(())
        })
        .unwrap();
    let counts = counts.into_inner();
    report(
        "Interval",
        &counts,
        ["refused", "accepted", "finite points reflected", ""],
    );
    assert!(counts[0] > 5_000 && counts[1] > 10_000, "{counts:?}");
}

/// A built-in schedule is refused, or gives a finite `a_k > 0` between its
/// ends at every `k`, and a length of at least 1.
#[test]
fn schedule_campaign() {
    let counts = RefCell::new([0u32; 4]);
    let mut runner = proptest::test_runner::TestRunner::new(config(SCHEDULE_CASES, SEED + 5));
    let strategy = (
        wild64(),
        wild64(),
        steps_strategy(),
        any::<u64>(),
        0..3usize,
    );
    runner
        .run(&strategy, |(l, h, k, at, which)| {
            let got: Result<(AnySchedule, f64, f64), Error> =
                no_panic("schedule", || match which {
                    0 => Constant::new(l).map(|s| (AnySchedule::Constant(s), l, l)),
                    1 => Linear::new(l, h, k).map(|s| (AnySchedule::Linear(s), l.min(h), l.max(h))),
                    _ => Geometric::new(l, h, k)
                        .map(|s| (AnySchedule::Geometric(s), l.min(h), l.max(h))),
                })?;
            let Ok((s, lo, hi)) = got else {
                counts.borrow_mut()[0] += 1;
                return Ok(());
            };
            counts.borrow_mut()[1] += 1;
            prop_assert!(s.length().is_none_or(|n| n >= 1));
            for k in [0, 1, at, at / 2, u64::MAX, s.length().unwrap_or(0)] {
                let a = no_panic("inverse_temperature", || s.inverse_temperature(k))?;
                prop_assert!(
                    a.is_finite() && a > 0.0 && a >= lo && a <= hi,
                    "{:?} at {}: {}",
                    s,
                    k,
                    a
                );
            }
            Ok(())
        })
        .unwrap();
    let counts = counts.into_inner();
    report("schedules", &counts, ["refused", "accepted", "", ""]);
    assert!(counts[0] > 5_000 && counts[1] > 5_000, "{counts:?}");
}
