//! The kernel's error contract, one hostile input at a time: a value below
//! `-sqrt(MAX)` is an error on every path that records one (steps, starts,
//! polish, quench, restart, L-BFGS alone); a box as wide as the floats
//! never makes a NaN; counts that overflow saturate; a schedule of no
//! steps is refused like a step budget of none; a point where `U` is not
//! finite is infeasible, never fatal (starts are redrawn, `Auto` restarts
//! and keeps its best); a potential that panics poisons the optimiser;
//! `Auto` can be stopped; a result says why it ended and how many chains
//! diverged.

use std::cell::Cell;
use std::ops::ControlFlow;
use std::panic::{AssertUnwindSafe, catch_unwind};

use hrla::{
    Auto, Builder, Chain, Error, FnPotential, Gaussian, Hrla, Interval, Lbfgs, Point,
    PolishSettings, Potential, Problem, Rastrigin, START_TRIES, Schedule, Stop, Termination,
    chain_seed,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    (0..n).map(|_| Chain::new()).collect()
}

/// `-sqrt(f64::MAX)`: values below it are "unbounded below".
fn floor() -> f64 {
    -f64::MAX.sqrt()
}

/// `U = -exp(x)`: unbounded below, falling to `-MAX` near `x = 709.8`.
struct MinusExp;

impl Potential<f64, 1> for MinusExp {
    fn value_and_gradient(&self, x: &[f64; 1], g: &mut [f64; 1]) -> f64 {
        let v = -libm::exp(x[0]);
        g[0] = v;
        v
    }
}

type Run<'a, P, const D: usize, S> =
    hrla::Optimizer<f64, P, Hrla<f64>, f64, hrla::Chains<f64, &'a mut Vec<Chain<f64, D>>, D>, S>;

/// Chains of `U = -exp(x)`, all at 0, for 10 steps.
fn minus_exp_run(store: &mut Vec<Chain<f64, 1>>) -> Run<'_, MinusExp, 1, hrla::Unbounded> {
    Builder::new(
        MinusExp,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Point::new([0.0]).unwrap(),
    )
    .stop(Stop::new().steps(10))
    .build(store)
    .unwrap()
}

fn is_unbounded(got: &Result<impl std::fmt::Debug, Error>, chain: usize) -> bool {
    matches!(got, Err(Error::UnboundedBelow { chain: c, value }) if *c == chain && *value < floor())
}

/// A polish of `U = -exp(x)` walks down to `-1.8e308`: an error naming the
/// chain, and the run stays failed, never a report of "best U = -1.8e308".
#[test]
fn polish_quench_and_restart_refuse_a_potential_unbounded_below() {
    let p = MinusExp;
    let mut store = chains::<1>(2);
    let mut opt = minus_exp_run(&mut store);
    let mut lbfgs: Lbfgs<f64, 1, 8> = Lbfgs::new();
    let got = opt.polish(1, &mut lbfgs, PolishSettings::new(1000));
    assert!(is_unbounded(&got, 1), "{got:?}");
    assert!(opt.best().value > floor());
    assert!(is_unbounded(&opt.run(), 1));
    assert!(is_unbounded(&opt.step(), 1));
    assert!(is_unbounded(&opt.restart(0, &[0.0]), 1));

    let mut store = chains::<1>(2);
    let mut opt = minus_exp_run(&mut store);
    let got = opt.quench(0, &mut lbfgs, PolishSettings::new(1000));
    assert!(is_unbounded(&got, 0), "{got:?}");
    assert!(is_unbounded(&opt.run(), 0));

    // -exp(400) = -5e173 and -exp(800) = -inf, both at a finite point.
    for x in [400.0, 800.0] {
        let mut store = chains::<1>(2);
        let mut opt = minus_exp_run(&mut store);
        assert!(is_unbounded(&opt.restart(1, &[x]), 1), "{x}");
        assert!(is_unbounded(&opt.run(), 1));
    }

    // L-BFGS alone, and from a start already below the floor.
    let got = lbfgs.minimize(&p, &mut [0.0], PolishSettings::new(1000));
    assert!(is_unbounded(&got, 0), "{got:?}");
    let got = lbfgs.minimize(&p, &mut [400.0], PolishSettings::new(1000));
    assert!(is_unbounded(&got, 0), "{got:?}");
    // So does a start that is already there.
    let got = Builder::new(
        &p,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Point::new([400.0]).unwrap(),
    )
    .stop(Stop::new().steps(10))
    .build(chains::<1>(2))
    .map(drop);
    assert!(is_unbounded(&got, 0), "{got:?}");
}

/// A failure in a polish never turns into a report, even once a stopping
/// rule holds: `run` checks the failure before the stopping rules.
#[test]
fn a_failed_polish_is_not_a_report_after_the_run_ended() {
    let mut store = chains::<1>(2);
    let mut opt = minus_exp_run(&mut store);
    while opt.termination().is_none() {
        opt.step().unwrap();
    }
    let mut lbfgs: Lbfgs<f64, 1, 8> = Lbfgs::new();
    assert!(is_unbounded(
        &opt.polish(0, &mut lbfgs, PolishSettings::new(1000)),
        0
    ));
    assert!(is_unbounded(&opt.run(), 0));
    assert!(is_unbounded(
        &opt.run_with(
            hrla::Observe::EveryAndNewBest(1),
            |_| ControlFlow::Continue(())
        ),
        0
    ));
}

/// Reflection into a box of width near `MAX` stays finite: `6.5e307`
/// folds to `5.5e307` inside `[-6e307, 6e307]`.
#[test]
fn restart_in_a_box_as_wide_as_the_floats_stays_finite() {
    let domain = Interval::new(-6e307, 6e307).unwrap();
    // Linear and small over the whole box.
    let p = FnPotential::new(|x: &[f64; 1], g: &mut [f64; 1]| {
        g[0] = 1e-300;
        x[0] * 1e-300
    });
    let mut store = chains::<1>(2);
    let mut opt = Builder::new(&p, Hrla::paper(0.01).unwrap(), 1.0, domain)
        .domain(domain)
        .stop(Stop::new().steps(10))
        .build(&mut store)
        .unwrap();
    for x in [6.5e307, -6.5e307, f64::MAX, -f64::MAX] {
        assert_eq!(opt.restart(0, &[x]), Ok(true));
        let c = &opt.chains()[0];
        assert!(!c.is_diverged(), "{x}");
        let y = c.x()[0];
        assert!(y.is_finite() && y.abs() <= 6e307, "{x} -> {y}");
    }
    assert!((opt.chains()[0].x()[0] + 6e307 - (f64::MAX - 6e307)).abs() < 1e294);
    assert_eq!(opt.restart(0, &[6.5e307]), Ok(true));
    assert!((opt.chains()[0].x()[0] - 5.5e307).abs() < 1e294);
    // Steps of a chain pushed across the box by a huge drift stay inside.
    let steep = FnPotential::new(|x: &[f64; 1], g: &mut [f64; 1]| {
        g[0] = -1e306;
        -x[0] * 1e-300
    });
    let mut store = chains::<1>(4);
    let mut opt = Builder::new(&steep, Hrla::paper(1.0).unwrap(), 1.0, domain)
        .domain(domain)
        .stop(Stop::new().steps(20))
        .build(&mut store)
        .unwrap();
    opt.run().unwrap();
    for c in opt.chains() {
        assert!(!c.is_diverged() && c.x()[0].abs() <= 6e307, "{:?}", c.x());
    }
}

/// Constants far above any budget (quenches, stall, steps) are bounded by
/// the budget: the run ends within it, at a local minimum it evaluated.
#[test]
fn auto_constants_above_the_budget_are_bounded_by_it() {
    for (steps, quench, stall) in [
        (hrla::MAX_STEPS, 10, 30),
        (10, u64::MAX, 30),
        (10, 1000, u64::MAX),
    ] {
        let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
        let found = Auto {
            steps,
            quench,
            stall,
            ..Auto::default()
        }
        .minimize(
            &Problem::new(&Rastrigin, &Interval::new(-5.12, 5.12).unwrap(), 5_000).seed(3),
            (&mut chains::<2>(4)[..], &mut lbfgs),
        )
        .unwrap();
        assert!(found.evaluations <= 5_000, "{found:?}");
        assert_eq!(Rastrigin.value(&found.x), found.value);
    }
}

/// A schedule whose length is 0 would be a run of no steps reported as
/// fine: refused like `Stop::steps(0)`.
#[test]
fn a_schedule_of_no_steps_is_refused() {
    struct Empty;
    impl Schedule<f64> for Empty {
        fn inverse_temperature(&self, _k: u64) -> f64 {
            1.0
        }
        fn length(&self) -> Option<u64> {
            Some(0)
        }
    }
    let got = Builder::new(
        Rastrigin,
        Hrla::paper(0.01).unwrap(),
        Empty,
        Point::new([1.0; 2]).unwrap(),
    )
    .build(chains::<2>(2))
    .map(drop);
    assert_eq!(
        got,
        Err(Error::Zero {
            name: "schedule length"
        })
    );
}

/// `U = x0 - ln x0 + (x1 - 1/2)^2`, NaN for `x0 < 0` and `+inf` at 0: the
/// minimum 1 at `(1, 1/2)`, 40% of the box `[-2, 3]^2` infeasible.
struct LogBarrier;

impl Potential<f64, 2> for LogBarrier {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        *g = [1.0 - 1.0 / x[0], 2.0 * (x[1] - 0.5)];
        x[0] - libm::log(x[0]) + (x[1] - 0.5) * (x[1] - 0.5)
    }
}

/// A start where `U` is not finite is redrawn from the chain's own stream:
/// each chain starts at the first feasible point of its stream, every
/// draw counts as an evaluation, and a run whose starts are all feasible
/// draws once per chain.
#[test]
fn infeasible_starts_are_redrawn() {
    let p = LogBarrier;
    let domain = Interval::new(-2.0, 3.0).unwrap();
    let n = 16;
    let mut store = chains::<2>(n);
    let opt = Builder::new(&p, Hrla::paper(0.01).unwrap(), 1.0, domain)
        .domain(domain)
        .seed(7)
        .stop(Stop::new().steps(100))
        .build(&mut store)
        .unwrap();
    let mut draws = 0;
    for c in 0..n {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(chain_seed(7, c as u64));
        let x = loop {
            let mut x = [0.0; 2];
            hrla::Start::initial_point(&mut domain.clone(), c, &mut rng, &mut x);
            draws += 1;
            if x[0] > 0.0 {
                break x;
            }
        };
        assert_eq!(opt.chains()[c].x(), &x, "chain {c}");
        assert_eq!(opt.chains()[c].rng(), &rng, "chain {c}");
    }
    assert!(
        draws > n as u64,
        "no start was infeasible: the test tests nothing"
    );
    assert_eq!(opt.evaluations(), draws);

    // A start law with no feasible point: all `START_TRIES` tried, or as
    // many as the evaluation budget allows.
    let nowhere = Point::new([-1.0, 0.0]).unwrap();
    let got = Builder::new(&p, Hrla::paper(0.01).unwrap(), 1.0, nowhere)
        .stop(Stop::new().steps(10))
        .build(chains::<2>(3))
        .map(drop);
    let want = Error::NonFiniteStart {
        chain: 0,
        what: "value",
        tries: START_TRIES,
    };
    assert_eq!(got, Err(want));
    assert_eq!(
        want.to_string(),
        "no feasible initial point for chain 0: 100 drawn, the last one's value is not finite"
    );
    let got = Builder::new(&p, Hrla::paper(0.01).unwrap(), 1.0, nowhere)
        .stop(Stop::new().evaluations(3 + 4))
        .build(chains::<2>(3))
        .map(drop);
    assert_eq!(
        got,
        Err(Error::NonFiniteStart {
            chain: 0,
            what: "value",
            tries: 5,
        })
    );
    // The evaluation budget holds every redraw.
    for budget in [16, 20, 40] {
        let mut store = chains::<2>(n);
        let got = Builder::new(&p, Hrla::paper(0.01).unwrap(), 1.0, domain)
            .domain(domain)
            .seed(7)
            .stop(Stop::new().evaluations(budget))
            .build(&mut store);
        match got {
            Ok(opt) => assert!(opt.evaluations() <= budget),
            Err(e) => assert!(matches!(e, Error::NonFiniteStart { .. }), "{e:?}"),
        }
    }
}

/// `Auto` on a problem with an infeasible region returns the minimum: its
/// starts are redrawn, and chains that step into the region restart.
#[test]
fn auto_treats_non_finite_points_as_infeasible() {
    let p = LogBarrier;
    for seed in 0..8 {
        let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
        let found = Auto::default()
            .minimize(
                &Problem::new(&p, &Interval::new(-2.0, 3.0).unwrap(), 4_000).seed(seed),
                (&mut chains::<2>(8)[..], &mut lbfgs),
            )
            .unwrap();
        assert!((found.value - 1.0).abs() < 1e-12, "{found:?}");
        assert!((found.x[0] - 1.0).abs() < 1e-5 && (found.x[1] - 0.5).abs() < 1e-5);
        assert_eq!(found.termination, Termination::Evaluations);
    }
}

/// A potential that fails now and then (NaN at one call in 7, wherever it
/// is: a simulation that does not converge) never costs `Auto` its best
/// point: a quench that meets it at its start skips the chain.
#[test]
fn auto_keeps_its_best_through_failing_evaluations() {
    let calls = Cell::new(0u64);
    let p = FnPotential::new(|x: &[f64; 4], g: &mut [f64; 4]| {
        calls.set(calls.get() + 1);
        let v = Rastrigin.value_and_gradient(x, g);
        if calls.get().is_multiple_of(7) {
            f64::NAN
        } else {
            v
        }
    });
    for seed in 0..4 {
        let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
        let found = Auto::default()
            .minimize(
                &Problem::new(&p, &Interval::new(-5.12, 5.12).unwrap(), 20_000).seed(seed),
                (&mut chains::<4>(8)[..], &mut lbfgs),
            )
            .unwrap();
        assert!(found.value.is_finite() && found.value < 1.0, "{found:?}");
        assert_eq!(Rastrigin.value(&found.x), found.value);
    }
}

/// Every chain steps into the half of the box where `U` is NaN (long steps
/// of a large `step_scale`): `Auto` keeps each chain in its basin and
/// returns the best.
#[test]
fn auto_survives_all_chains_diverging() {
    let p = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
        *g = [2.0 * x[0], 2.0 * x[1]];
        if x[0] > 0.5 {
            f64::NAN
        } else {
            x[0] * x[0] + x[1] * x[1]
        }
    });
    let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
    let mut all_diverged = 0;
    let found = Auto {
        step_scale: 20.0,
        ..Auto::default()
    }
    .minimize_with(
        &Problem::new(&p, &Interval::new(-5.0, 5.0).unwrap(), 3_000).seed(1),
        (&mut chains::<2>(8)[..], &mut lbfgs),
        |p| {
            all_diverged += usize::from(p.diverged_chains == 8);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert!(
        all_diverged > 0,
        "the chains never all diverged: the test tests nothing"
    );
    assert!(found.value < 1e-20, "{found:?}");
    assert_eq!(found.termination, Termination::Evaluations);
    assert!(found.evaluations <= 3_000);
}

/// `Auto` with a budget that never runs out ends when its observer says
/// so; the observer is called after every step, quench and restart (never
/// more than `max(N, quench)` evaluations apart), sees every
/// improvement, and the solution is the best it last saw.
#[test]
fn auto_stops_when_its_observer_says_so() {
    let n = 8;
    let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    let auto = Auto::<f64>::default();
    let gap = (n as u64).max(auto.quench);
    let mut last = 0;
    let mut calls = 0;
    let mut best = f64::INFINITY;
    let found = auto
        .minimize_with(
            &Problem::new(&Rastrigin, &Interval::new(-5.12, 5.12).unwrap(), u64::MAX).seed(2),
            (&mut chains::<4>(n)[..], &mut lbfgs),
            |p| {
                calls += 1;
                assert!(
                    p.evaluations - last <= gap,
                    "{} after {last}",
                    p.evaluations
                );
                assert_eq!(p.improved, p.value < best);
                assert_eq!(
                    Rastrigin.value(<&[f64; 4]>::try_from(p.x).unwrap()),
                    p.value
                );
                last = p.evaluations;
                best = best.min(p.value);
                if p.evaluations >= 30_000 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
    assert_eq!(found.termination, Termination::Observer);
    assert_eq!(found.evaluations, last);
    assert_eq!(found.value, best);
    assert!(calls > 100, "{calls} calls, {found:?}");
    assert!(found.to_string().starts_with("stopped by the observer"));

    // Stopped at the first call: the best initial point, no round.
    let found = auto
        .minimize_with(
            &Problem::new(&Rastrigin, &Interval::new(-5.12, 5.12).unwrap(), u64::MAX).seed(2),
            (&mut chains::<4>(n)[..], &mut lbfgs),
            |_| ControlFlow::Break(()),
        )
        .unwrap();
    assert_eq!(
        (found.rounds, found.termination),
        (0, Termination::Observer)
    );
    // The initial points, nothing else.
    assert_eq!(found.evaluations, n as u64);

    // An observer that never stops changes nothing.
    let quiet = |observer: bool| {
        let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
        let domain = Interval::new(-5.12, 5.12).unwrap();
        let mut store = chains::<4>(n);
        if observer {
            auto.minimize_with(
                &Problem::new(&Rastrigin, &domain, 10_000).seed(4),
                (&mut store[..], &mut lbfgs),
                |_| ControlFlow::Continue(()),
            )
        } else {
            auto.minimize(
                &Problem::new(&Rastrigin, &domain, 10_000).seed(4),
                (&mut store[..], &mut lbfgs),
            )
        }
        .unwrap()
    };
    assert_eq!(quiet(true), quiet(false));
}

/// A solution says why it ended and how many chains diverged, and its text
/// never claims more.
#[test]
fn a_solution_says_how_it_ended() {
    let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
    let found = Auto::default()
        .minimize(
            &Problem::new(&Rastrigin, &Interval::new(-5.12, 5.12).unwrap(), 2_000).seed(0),
            (&mut chains::<2>(8)[..], &mut lbfgs),
        )
        .unwrap();
    assert_eq!(found.termination, Termination::Evaluations);
    assert_eq!((found.diverged_chains, found.chains), (0, 8));
    assert!(!found.all_diverged());
    let text = found.to_string();
    assert!(
        text.starts_with("evaluation budget spent: best U = ")
            && text.ends_with("the last proposal of 0 of 8 chains met an infeasible point"),
        "{text}"
    );
    let dead = hrla::Solution {
        diverged_chains: 8,
        ..found
    };
    assert!(dead.all_diverged());
    assert!(
        dead.to_string()
            .contains("8 of 8 chains met an infeasible point"),
        "{dead}"
    );
}

/// A quadratic that panics at every third call once armed.
#[derive(Default)]
struct Fragile {
    armed: Cell<bool>,
    calls: Cell<u32>,
}

impl Potential<f64, 2> for Fragile {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        self.calls.set(self.calls.get() + 1);
        if self.armed.get() && self.calls.get().is_multiple_of(3) {
            panic!("the potential failed");
        }
        *g = [2.0 * x[0], 2.0 * x[1]];
        x[0] * x[0] + x[1] * x[1]
    }
}

fn fragile_run<'a>(
    p: &'a Fragile,
    store: &'a mut Vec<Chain<f64, 2>>,
) -> Run<'a, &'a Fragile, 2, hrla::Unbounded> {
    Builder::new(
        p,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Gaussian::new([1.0; 2], 1.0).unwrap(),
    )
    .stop(Stop::new().steps(100))
    .build(store)
    .unwrap()
}

/// A potential that panics in the middle of a step leaves chains stepped
/// and others not: every later call refuses with `Poisoned`, instead of
/// going on from a state that no serial run has.
#[test]
fn a_panic_in_the_potential_poisons_the_optimiser() {
    let p = Fragile::default();
    let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
    // A panic in a step, in a polish, in a restart.
    for site in 0..3 {
        let mut store = chains::<2>(8);
        let mut opt = fragile_run(&p, &mut store);
        opt.step().unwrap();
        p.armed.set(true);
        let panicked = catch_unwind(AssertUnwindSafe(|| match site {
            0 => opt.step().map(drop),
            1 => opt
                .polish(0, &mut lbfgs, PolishSettings::new(100))
                .map(drop),
            _ => (0..8).try_for_each(|c| opt.restart(c, &[0.5, 0.5]).map(drop)),
        }));
        assert!(panicked.is_err(), "site {site}: no panic");
        p.armed.set(false);
        assert_eq!(opt.step(), Err(Error::Poisoned), "site {site}");
        assert_eq!(opt.run(), Err(Error::Poisoned));
        assert_eq!(
            opt.polish(0, &mut lbfgs, PolishSettings::new(10)),
            Err(Error::Poisoned)
        );
        assert_eq!(
            opt.quench(0, &mut lbfgs, PolishSettings::new(10)),
            Err(Error::Poisoned)
        );
        assert_eq!(opt.restart(0, &[0.0; 2]), Err(Error::Poisoned));
    }
    // Without a panic, nothing is poisoned.
    let mut store = chains::<2>(8);
    let mut opt = fragile_run(&p, &mut store);
    opt.polish(0, &mut lbfgs, PolishSettings::new(100)).unwrap();
    assert_eq!(opt.restart(1, &[0.5, 0.5]), Ok(true));
    assert_eq!(opt.run().map(|r| r.termination), Ok(Termination::Steps));
}
