//! The six problems of the optimiser's API that the redesign set out to fix,
//! each shown fixed by a test:
//!
//! 1. large sizes overflowed the stack (`[Chain; N]` by value): `large.rs`
//!    runs `N = 100_000` and `D = 10_000` on a 256 KiB stack, and
//!    `footprint.rs` checks that the optimiser holds no array of size `D`;
//! 2. a potential had to be a type of one's own: a closure is a potential
//!    ([`FnPotential`]), `&P` is one (two optimisers share a potential that
//!    is not `Clone`), `value_and_gradient` is the one required method, and
//!    [`check_gradient`] finds a wrong gradient;
//! 3. a run needed turbofish and annotations: one annotation (the storage's
//!    element type) is enough, and the schedule's length is the step budget;
//! 4. a run stopped only at a step count or a target: budgets of steps and
//!    evaluations, a target, a stall rule and an observer, each exact;
//! 5. the report hid failures: it says why the run ended (`Display`), and
//!    a run whose chains all diverged or whose potential is unbounded below
//!    is an error, not a report;
//! 6. silent failures: out-of-range `a` and `h`, non-finite starts (named),
//!    `D = 0` and `N = 0` are typed errors from the constructors or `build`.
//!
//! Everything here is deterministic (fixed seeds, exact counts); no test
//! depends on timing.

use hrla_tests::fixtures::Cliff;
use std::cell::Cell;
use std::ops::ControlFlow;

use hrla::{
    Ackley, Builder, Chain, Error, FnPotential, FromFn, Gaussian, Geometric, Hrla, HrlaParams,
    Kernel, Levy, Linear, Ola, Point, Potential, Quadratic, Rastrigin, Sampler, Schedule, Stop,
    StyblinskiTang, Termination, check_gradient,
};
use rand_xoshiro::rand_core::Rng;

/// `n` chains of the default generator.
fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    vec![Chain::new(); n]
}

/// Every chain's state as bits.
fn bits<const D: usize>(chains: &[Chain<f64, D>]) -> Vec<u64> {
    let mut out = Vec::new();
    for c in chains {
        out.extend(
            c.x()
                .iter()
                .chain(c.y())
                .chain(c.gradient())
                .map(|v| v.to_bits()),
        );
        out.push(c.value().to_bits());
        out.push(c.best().value.to_bits());
    }
    out
}

// ---------------------------------------------------------------------------
// (2) Potentials: closures, references, one required method, a gradient
// check.

/// The textbook Ackley function (`-20 exp(-0.2 r) - exp(mean cos 2πx) + 20
/// + e`), as a user would write it, with its gradient.
fn textbook_ackley(x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
    use std::f64::consts::{E, PI};
    let r = ((x[0] * x[0] + x[1] * x[1]) / 2.0).sqrt();
    let c = ((2.0 * PI * x[0]).cos() + (2.0 * PI * x[1]).cos()) / 2.0;
    let (outer, inner) = ((-0.2 * r).exp(), c.exp());
    for i in 0..2 {
        let radial = if r > 0.0 { 2.0 * outer * x[i] / r } else { 0.0 };
        g[i] = radial + inner * PI * (2.0 * PI * x[i]).sin();
    }
    -20.0 * outer - inner + 20.0 + E
}

/// The same function as a type implementing `Potential`.
struct TextbookAckley;

impl Potential<f64, 2> for TextbookAckley {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        textbook_ackley(x, g)
    }
}

/// Six chains annealed from `a = 0.5` to 8 over 500 steps: the steps run,
/// and the chains.
fn annealed_run(p: impl Potential<f64, 2>) -> (u64, Vec<Chain<f64, 2>>) {
    let mut opt = Builder::new(
        p,
        Hrla::paper(0.01).unwrap(),
        Linear::new(0.5, 8.0, 500).unwrap(),
        Gaussian::new([2.0; 2], 1.0).unwrap(),
    )
    .seed(4)
    .build(chains::<2>(6))
    .unwrap();
    let k = opt.run().unwrap().iterations;
    (k, opt.into_chains().into_inner())
}

/// A closure is a potential: the same run, bit for bit, as the type that
/// implements the same function; its gradient passes `check_gradient`; and
/// it agrees with the built-in `Ackley` (written without cancellation) to
/// rounding.
#[test]
fn a_closure_is_a_potential() {
    let closure = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| textbook_ackley(x, g));
    let (k1, by_closure) = annealed_run(closure);
    let (k2, by_type) = annealed_run(TextbookAckley);
    assert_eq!((k1, k2), (500, 500));
    assert_eq!(bits(&by_closure), bits(&by_type));
    assert_ne!(by_closure[0].x(), &[2.0; 2]);

    for x in [[0.3, -1.7], [2.5, 0.01], [-0.9, 0.6]] {
        let check = check_gradient(&closure, &x).unwrap();
        assert!(check.error < 1e-8, "{x:?}: {check:?}");
        let (mut g1, mut g2) = ([0.0; 2], [0.0; 2]);
        let u1 = closure.value_and_gradient(&x, &mut g1);
        let u2 = Ackley.value_and_gradient(&x, &mut g2);
        assert!((u1 - u2).abs() <= 1e-13 * u2.abs().max(1.0), "{u1} vs {u2}");
        for i in 0..2 {
            assert!((g1[i] - g2[i]).abs() <= 1e-12 * g2[i].abs().max(1.0));
        }
    }
}

/// Rastrigin that counts its evaluations; neither `Clone` nor `Copy`.
struct Counted {
    calls: Cell<u64>,
}

impl Potential<f64, 2> for Counted {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        self.calls.set(self.calls.get() + 1);
        Rastrigin.value_and_gradient(x, g)
    }
}

/// `&P` is a potential: two optimisers live at once on one potential that
/// cannot be cloned, stepped in turn; every evaluation of both reaches it
/// (so both optimisers' evaluation counts are exact), and each run is the
/// run of an owned potential, bit for bit.
#[test]
fn a_reference_is_a_potential_shared_without_clone() {
    let p = Counted {
        calls: Cell::new(0),
    };
    let start = Gaussian::new([3.0; 2], 1.0).unwrap();
    let hrla = Hrla::paper(0.01).unwrap();
    let mut one = Builder::new(&p, hrla, 4.0, start)
        .seed(1)
        .build(chains::<2>(3))
        .unwrap();
    let mut two = Builder::new(&p, hrla, 2.0, start)
        .seed(2)
        .build(chains::<2>(5))
        .unwrap();
    assert_eq!(p.calls.get(), 3 + 5);
    for _ in 0..100 {
        one.step().unwrap();
        two.step().unwrap();
        two.step().unwrap();
    }
    assert_eq!(one.evaluations(), 3 * 101);
    assert_eq!(two.evaluations(), 5 * 201);
    assert_eq!(p.calls.get(), one.evaluations() + two.evaluations());
    // The same runs with an owned potential.
    let mut owned = Builder::new(Rastrigin, hrla, 4.0, start)
        .seed(1)
        .build(chains::<2>(3))
        .unwrap();
    for _ in 0..100 {
        owned.step().unwrap();
    }
    assert_eq!(bits(one.chains()), bits(owned.chains()));
}

/// `U(x) = cosh(x_1) + x_2^2 / 2`, implementing only `value_and_gradient`.
struct OnlyValueAndGradient;

impl Potential<f64, 2> for OnlyValueAndGradient {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        *g = [x[0].sinh(), x[1]];
        x[0].cosh() + 0.5 * x[1] * x[1]
    }
}

/// `value_and_gradient` is the only required method: `value` and
/// `gradient` follow from it, and the potential runs to its minimum
/// `U* = 1` at the origin. At `a = 4` the law `exp(-4 U)` there is close
/// to `N(0, I/4)`, under which `U - 1 ≈ |x|^2 / 2 = chi^2_2 / 8`: any one
/// iterate is above `U* + 0.5` with probability `P(chi^2_2 > 4) = e^-2 ≈
/// 0.14`. A chain's running best over 2 000 steps (some twenty
/// relaxation times of about 100 steps at `h = 0.01`) stays above it with
/// probability about `0.14^20 ≈ 1e-17`; the fixed seed makes it a fact.
#[test]
fn value_and_gradient_is_the_only_required_method() {
    let p = OnlyValueAndGradient;
    let x = [0.7, -1.2];
    let mut g = [0.0; 2];
    let u = p.value_and_gradient(&x, &mut g);
    assert_eq!(p.value(&x), u);
    let mut g2 = [f64::NAN; 2];
    p.gradient(&x, &mut g2);
    assert_eq!(g2, g);
    assert_eq!(g, [0.7f64.sinh(), -1.2]);
    let mut opt = Builder::new(
        &p,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Point::new([2.0, 2.0]).unwrap(),
    )
    .seed(8)
    .stop(Stop::new().steps(2_000))
    .build(chains::<2>(4))
    .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(report.termination, Termination::Steps);
    for c in opt.chains() {
        assert!(c.best().value < 1.5, "{:?}", c.best());
    }
    assert!(report.value < 1.5 && report.value >= 1.0);
}

/// `U = x_0^2 + 2 x_1^2 + x_0 x_1 + 3 x_2^4 + sin(x_3)`; `wrong` makes the
/// derivative in `x_2` `6 x_2^3` instead of `12 x_2^3`.
fn quartic(x: &[f64; 4], g: &mut [f64; 4], wrong: bool) -> f64 {
    g[0] = 2.0 * x[0] + x[1];
    g[1] = 4.0 * x[1] + x[0];
    g[2] = if wrong { 6.0 } else { 12.0 } * x[2].powi(3);
    g[3] = x[3].cos();
    x[0] * x[0] + 2.0 * x[1] * x[1] + x[0] * x[1] + 3.0 * x[2].powi(4) + x[3].sin()
}

/// `check_gradient` passes a right gradient (error around `eps^(2/3)`,
/// 1e-10, in f64; asserted below 1e-8) and finds the coordinate of a wrong
/// one, with its analytic and numeric values; also in f32 (error around
/// 1e-5 there; asserted below 1e-3), and for every built-in potential.
#[test]
fn check_gradient_finds_a_wrong_gradient() {
    let right = FnPotential::new(|x: &[f64; 4], g: &mut [f64; 4]| quartic(x, g, false));
    let wrong = FnPotential::new(|x: &[f64; 4], g: &mut [f64; 4]| quartic(x, g, true));
    for x in [[0.5, -1.0, 1.5, 0.25], [-2.0, 0.3, -0.8, 3.0]] {
        let ok = check_gradient(&right, &x).unwrap();
        assert!(ok.error < 1e-8, "{ok:?}");
        let bad = check_gradient(&wrong, &x).unwrap();
        assert_eq!(bad.coordinate, 2, "{bad:?}");
        assert!(bad.error > 0.1, "{bad:?}");
        assert_eq!(bad.analytic, 6.0 * x[2].powi(3));
        assert!((bad.numeric - 12.0 * x[2].powi(3)).abs() < 1e-6 * bad.numeric.abs());
    }
    let right32 = FnPotential::new(|x: &[f32; 2], g: &mut [f32; 2]| {
        *g = [2.0 * x[0], 3.0 * x[1] * x[1]];
        x[0] * x[0] + x[1] * x[1] * x[1]
    });
    let wrong32 = FnPotential::new(|x: &[f32; 2], g: &mut [f32; 2]| {
        *g = [2.0 * x[0], 2.0 * x[1]];
        x[0] * x[0] + x[1] * x[1] * x[1]
    });
    assert!(check_gradient(&right32, &[0.5, -1.5]).unwrap().error < 1e-3);
    let bad = check_gradient(&wrong32, &[0.5, -1.5]).unwrap();
    assert_eq!(bad.coordinate, 1);
    assert!(bad.error > 0.1);
    // The built-in potentials' gradients, away from Ackley's kink.
    let points = [[0.3, -1.7, 2.2], [1.1, 0.45, -0.35], [-2.6, 3.1, 0.05]];
    for x in points {
        let checks = [
            ("Rastrigin", check_gradient(&Rastrigin, &x)),
            ("Ackley", check_gradient(&Ackley, &x)),
            ("Levy", check_gradient(&Levy, &x)),
            ("StyblinskiTang", check_gradient(&StyblinskiTang, &x)),
            ("DoubleWell", check_gradient(&hrla::DoubleWell, &x)),
            (
                "Quadratic",
                check_gradient(&Quadratic::new(2.0, [1.0, -1.0, 0.5]).unwrap(), &x),
            ),
        ];
        for (name, c) in checks {
            let c = c.unwrap();
            assert!(c.error < 1e-6, "{name} at {x:?}: {c:?}");
        }
    }
    // Non-finite input is an error, not a check.
    assert!(matches!(
        check_gradient(&right, &[0.0, f64::NAN, 0.0, 0.0]),
        Err(Error::NotFinite { name: "x", .. })
    ));
}

// ---------------------------------------------------------------------------
// (3) One type annotation at most; the schedule's length is the budget.

#[test]
fn one_type_annotation_at_most() -> Result<(), Error> {
    // The one annotation: the storage's element type.
    let mut chains: Vec<Chain<f64, 2>> = (0..8).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01)?,
        Linear::new(0.5, 4.0, 300)?,
        Gaussian::new([3.0; 2], 1.0)?,
    )
    .seed(3)
    .build(&mut chains)?;
    let report = opt.run()?;
    // The schedule's length was the step budget, and a = a_high at its end.
    assert_eq!(report.iterations, 300);
    assert_eq!(report.termination, Termination::Steps);
    assert_eq!(report.evaluations, 8 * 301);
    let last = Linear::new(0.5, 4.0, 300)?.inverse_temperature(299);
    assert_eq!(opt.kernel().inverse_temperature(), last);
    assert!(chains.iter().all(|c| !c.is_diverged()));
    // Or written where the chains are made; the float type follows from
    // the sampler.
    let mut opt = Builder::new(Rastrigin, Ola::paper(0.01)?, 2.0, Point::new([1.0; 5])?)
        .stop(Stop::new().steps(10))
        .build(vec![Chain::<_, 5>::new(); 3])?;
    assert_eq!(opt.run()?.iterations, 10);
    assert_eq!(opt.chains()[0].x().len(), 5);
    Ok(())
}

/// A `Linear` or `Geometric` schedule of length K: no step budget means K
/// steps; a budget of K or more is kept; a budget below K is
/// `ScheduleLongerThanRun`, from `build`.
#[test]
fn the_schedule_length_is_the_default_step_budget() {
    let start = Point::new([1.0; 2]).unwrap();
    let hrla = Hrla::paper(0.01).unwrap();
    let linear = Linear::new(0.5, 4.0, 300).unwrap();
    let geometric = Geometric::new(0.5, 4.0, 300).unwrap();
    let mut opt = Builder::new(Rastrigin, hrla, linear, start)
        .build(chains::<2>(2))
        .unwrap();
    assert_eq!(*opt.stop(), Stop::new().steps(300));
    assert_eq!(opt.run().unwrap().iterations, 300);
    let mut opt = Builder::new(Rastrigin, hrla, geometric, start)
        .stop(Stop::new().target(-1.0))
        .build(chains::<2>(2))
        .unwrap();
    assert_eq!(*opt.stop(), Stop::new().target(-1.0).steps(300));
    assert_eq!(opt.run().unwrap().iterations, 300);
    // Longer: the annealing ends at a_high and the run goes on there.
    let mut opt = Builder::new(Rastrigin, hrla, linear, start)
        .stop(Stop::new().steps(400))
        .build(chains::<2>(2))
        .unwrap();
    assert_eq!(opt.run().unwrap().iterations, 400);
    assert_eq!(opt.kernel().inverse_temperature(), 4.0);
    for (schedule, steps) in [(linear, 299), (linear, 1)] {
        let got = Builder::new(Rastrigin, hrla, schedule, start)
            .stop(Stop::new().steps(steps))
            .build(chains::<2>(2))
            .map(|o| o.iteration());
        assert_eq!(
            got,
            Err(Error::ScheduleLongerThanRun {
                schedule: 300,
                steps
            })
        );
    }
    let got = Builder::new(Rastrigin, hrla, geometric, start)
        .stop(Stop::new().steps(299).evaluations(10_000))
        .build(chains::<2>(2))
        .map(|o| o.iteration());
    assert_eq!(
        got,
        Err(Error::ScheduleLongerThanRun {
            schedule: 300,
            steps: 299
        })
    );
    // A constant schedule has no length: without a rule, `run` refuses.
    let mut opt = Builder::new(Rastrigin, hrla, 4.0, start)
        .build(chains::<2>(2))
        .unwrap();
    assert_eq!(opt.run(), Err(Error::NoStoppingRule));
    assert_eq!(opt.iteration(), 0);
}

// ---------------------------------------------------------------------------
// (4) Stopping rules.

/// The evaluation budget is never exceeded and the run stops only when the
/// next step would exceed it, with one evaluation per live chain and step:
/// exactly, with every chain live (`3 (k + 1) <= 100`: k = 32), and with
/// half the chains diverging on the way (checked against a twin stepped by
/// hand).
#[test]
fn the_evaluation_budget_is_exact() {
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Point::new([1.0; 2]).unwrap(),
    )
    .stop(Stop::new().evaluations(100))
    .build(chains::<2>(3))
    .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(report.termination, Termination::Evaluations);
    assert_eq!((report.iterations, report.evaluations), (32, 99));

    for budget in [50, 200, 1_000, 1_001] {
        let build = || {
            let start = FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| {
                x.copy_from_slice(&if c.is_multiple_of(2) { [0.0] } else { [4.5] })
            });
            Builder::new(Cliff::NAN, Hrla::paper(0.01).unwrap(), 4.0, start)
                .seed(12)
                .stop(Stop::new().evaluations(budget))
                .build(chains::<1>(4))
                .unwrap()
        };
        let mut opt = build();
        let report = opt.run().unwrap();
        assert_eq!(report.termination, Termination::Evaluations);
        let live = (4 - report.diverged_chains) as u64;
        assert!(report.evaluations <= budget);
        assert!(report.evaluations + live > budget, "stopped early");
        // The twin: the first iterate at which one more step would exceed.
        let mut twin = build();
        let mut k = 0;
        while twin.evaluations() + (4 - twin.diverged_chains()) as u64 <= budget {
            twin.step().unwrap();
            k += 1;
        }
        assert_eq!(report.iterations, k, "budget {budget}");
        assert_eq!(report.evaluations, twin.evaluations());
        if budget >= 1_000 {
            // By then the slope chains diverged, and the budget lasted
            // longer than 4 chains' worth: (1000 - 4) / 4 = 249 steps.
            assert_eq!(report.diverged_chains, 2);
            assert!(report.iterations > 249);
        }
    }
}

/// The step budget and the target stop the run exactly where they hold.
#[test]
fn the_step_budget_and_the_target_are_exact() {
    let start = Gaussian::new([3.0; 2], 1.0).unwrap();
    let hrla = Hrla::paper(0.01).unwrap();
    let mut opt = Builder::new(Rastrigin, hrla, 4.0, start)
        .stop(Stop::new().steps(57))
        .build(chains::<2>(4))
        .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(
        (report.iterations, report.termination),
        (57, Termination::Steps)
    );
    // A target: the run stops at the first iterate whose best meets it.
    let build = || {
        Builder::new(Rastrigin, hrla, 4.0, start)
            .seed(6)
            .stop(Stop::new().target(2.0).steps(100_000))
            .build(chains::<2>(4))
            .unwrap()
    };
    let mut opt = build();
    assert!(opt.best().value > 2.0);
    let report = opt.run().unwrap();
    assert_eq!(report.termination, Termination::Target);
    assert!(report.value <= 2.0);
    let mut twin = build();
    for _ in 1..report.iterations {
        twin.step().unwrap();
        assert!(twin.best().value > 2.0);
    }
    twin.step().unwrap();
    assert!(twin.best().value <= 2.0);
}

/// `U = -min(j, m)` at its `j`-th evaluation (from 0), whatever `x`: with
/// one chain, the best falls by exactly 1 at each of the first `m` steps,
/// then never again.
fn staircase(m: u64) -> impl Potential<f64, 1> {
    let calls = Cell::new(0u64);
    FnPotential::new(move |_: &[f64; 1], g: &mut [f64; 1]| {
        let j = calls.get();
        calls.set(j + 1);
        g[0] = 0.0;
        -(j.min(m) as f64)
    })
}

/// The stall rule fires at exactly the expected iteration: on a flat
/// potential after `window` steps; on a staircase of `m` unit falls,
/// `window` steps after the last fall that beat the tolerance.
#[test]
fn the_stall_rule_fires_exactly() {
    let flat = FnPotential::new(|_: &[f64; 2], g: &mut [f64; 2]| {
        *g = [0.0; 2];
        0.0
    });
    let mut opt = Builder::new(
        flat,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Gaussian::new([0.0; 2], 1.0).unwrap(),
    )
    .stop(Stop::new().stall(25, 0.0).steps(1000))
    .build(chains::<2>(3))
    .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(report.termination, Termination::Stalled);
    assert_eq!(report.iterations, 25);
    assert_eq!(report.found_at, 0);

    // (window, tolerance, expected iteration) on a staircase of m = 10:
    // tolerance 0 counts every fall (last at 10); 1.5 counts a fall of 2,
    // every second step (last at 10); 2.5 needs 3 steps, longer than the
    // window of 2, so the run stalls at 2.
    for (window, tolerance, want) in [(5, 0.0, 15), (2, 1.5, 12), (2, 2.5, 2), (3, 2.5, 12)] {
        let mut opt = Builder::new(
            staircase(10),
            Hrla::paper(0.01).unwrap(),
            4.0,
            Point::new([0.0]).unwrap(),
        )
        .stop(Stop::new().stall(window, tolerance).steps(1000))
        .build(chains::<1>(1))
        .unwrap();
        let report = opt.run().unwrap();
        assert_eq!(report.termination, Termination::Stalled);
        assert_eq!(
            report.iterations, want,
            "window {window}, tolerance {tolerance}"
        );
        assert_eq!(report.value, -(want.min(10) as f64));
    }
}

/// The observer is called after exactly the steps that are multiples of
/// `every` or improve the best, with the run's numbers; `Break` ends the
/// run with `Termination::Observer` there.
#[test]
fn the_observer_is_called_exactly_and_can_stop_the_run() {
    let schedule = Linear::new(1.0, 4.0, 30).unwrap();
    let mut opt = Builder::new(
        staircase(10),
        Hrla::paper(0.01).unwrap(),
        schedule,
        Point::new([0.0]).unwrap(),
    )
    .build(chains::<1>(1))
    .unwrap();
    let mut calls = Vec::new();
    let report = opt
        .run_with(hrla::Observe::EveryAndNewBest(7), |p| {
            calls.push((p.iteration, p.improved));
            assert_eq!(p.evaluations, p.iteration + 1);
            assert_eq!(p.best.value, -(p.iteration.min(10) as f64));
            let a = schedule.inverse_temperature(p.iteration - 1);
            assert_eq!(p.inverse_temperature, a);
            assert_eq!(p.diverged_chains, 0);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(report.termination, Termination::Steps);
    // Improvements at 1..=10, multiples of 7 at 7, 14, 21, 28.
    let mut want: Vec<(u64, bool)> = (1..=10).map(|k| (k, true)).collect();
    want.extend([14, 21, 28].map(|k| (k, false)));
    assert_eq!(calls, want);
    assert_eq!(calls.len(), 13);

    // `every = 0`: only the improvements; `Break` at the fourth.
    let mut opt = Builder::new(
        staircase(10),
        Hrla::paper(0.01).unwrap(),
        4.0,
        Point::new([0.0]).unwrap(),
    )
    .stop(Stop::new().steps(30))
    .build(chains::<1>(1))
    .unwrap();
    let mut seen = 0;
    let report = opt
        .run_with(hrla::Observe::NewBest, |p| {
            seen += 1;
            assert!(p.improved);
            if p.iteration == 4 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
    assert_eq!(seen, 4);
    assert_eq!(report.termination, Termination::Observer);
    assert_eq!(report.iterations, 4);
    assert_eq!(opt.termination(), None);
    // The run resumes where it stopped: 6 more improvements, then steps
    // without any (no call with `every = 0`).
    let report = opt
        .run_with(hrla::Observe::NewBest, |_| {
            seen += 1;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(seen, 10);
    assert_eq!(report.iterations, 30);
}

// ---------------------------------------------------------------------------
// (5) The report says why; failures are errors.

/// Each termination's report, displayed, says why the run ended and gives
/// its numbers.
#[test]
fn the_report_says_why_the_run_ended() {
    let hrla = Hrla::paper(0.01).unwrap();
    let point = Point::new([0.0]).unwrap();
    let stairs = |stop: Stop<f64>| {
        Builder::new(staircase(10), hrla, 4.0, point)
            .stop(stop)
            .build(chains::<1>(1))
            .unwrap()
    };
    let reports = [
        stairs(Stop::new().steps(5)).run().unwrap(),
        stairs(Stop::new().evaluations(7)).run().unwrap(),
        stairs(Stop::new().target(-3.0)).run().unwrap(),
        stairs(Stop::new().stall(4, 0.0)).run().unwrap(),
        stairs(Stop::new().steps(50))
            .run_with(hrla::Observe::NewBest, |p| {
                if p.iteration == 2 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })
            .unwrap(),
    ];
    let reasons = [
        (Termination::Steps, "step budget spent", 5),
        (Termination::Evaluations, "evaluation budget spent", 6),
        (Termination::Target, "target reached", 3),
        (Termination::Stalled, "stalled", 14),
        (Termination::Observer, "stopped by the observer", 2),
    ];
    for (report, (termination, reason, k)) in reports.iter().zip(reasons) {
        let text = report.to_string();
        println!("{text}");
        assert_eq!(report.termination, termination);
        assert_eq!(report.iterations, k);
        assert!(text.starts_with(reason), "{text}");
        assert!(
            text.contains(&format!("best U = {}", report.value)),
            "{text}"
        );
        assert!(text.contains(&format!("after {k} steps")), "{text}");
        assert!(text.contains(&format!("{} evaluations", k + 1)), "{text}");
        assert!(text.contains("0 of 1 chains diverged"), "{text}");
    }
}

/// A `Quadratic` of stiffness 1e3 with HRLA at `alpha h = 50`, the top of
/// the accepted range: the frozen-gradient step overshoots by a factor of
/// about `1e3 * 50` per step, every chain overflows to `U = +inf`, and the
/// run is `Err(AllDiverged)` (never a report); so is a well whose value and
/// gradient are NaN beyond a radius that every chain crosses.
#[test]
fn all_chains_diverging_is_an_error() {
    let steep = Quadratic::new(1e3, [0.0; 2]).unwrap();
    let mut opt = Builder::new(
        steep,
        Hrla::new(HrlaParams {
            h: 50.0,
            ..HrlaParams::paper(0.01)
        })
        .unwrap(),
        4.0,
        Gaussian::new([1.0; 2], 0.1).unwrap(),
    )
    .seed(17)
    .stop(Stop::new().steps(10_000))
    .build(chains::<2>(5))
    .unwrap();
    let err = opt.run().unwrap_err();
    println!("{err} after {} steps", opt.iteration());
    assert_eq!(err, Error::AllDiverged { chains: 5 });
    assert!(err.to_string().contains("all 5 chains diverged"));
    assert!(opt.iteration() < 10_000);
    assert!(opt.chains().iter().all(|c| c.is_diverged()));
    assert!(opt.best().value.is_finite());

    let mut opt = Builder::new(
        Cliff::NAN,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Point::new([4.5]).unwrap(),
    )
    .stop(Stop::new().steps(10_000))
    .build(chains::<1>(3))
    .unwrap();
    let mut observed = 0;
    let got = opt.run_with(hrla::Observe::EveryAndNewBest(1), |_| {
        observed += 1;
        ControlFlow::Continue(())
    });
    assert_eq!(got, Err(Error::AllDiverged { chains: 3 }));
    // Every step but the one that failed was observed.
    assert_eq!(observed + 1, opt.iteration());
}

/// `U = -exp(x)` is unbounded below: the run is `Err(UnboundedBelow)` once
/// a chain's value falls below `-sqrt(f64::MAX)` (about -1.3e154), never a
/// report of a huge negative "best".
#[test]
fn a_potential_unbounded_below_is_an_error() {
    let falling = FnPotential::new(|x: &[f64; 1], g: &mut [f64; 1]| {
        g[0] = -x[0].exp();
        -x[0].exp()
    });
    for n in [1, 4] {
        let mut opt = Builder::new(
            &falling,
            Hrla::paper(0.01).unwrap(),
            4.0,
            Gaussian::new([2.0], 0.5).unwrap(),
        )
        .seed(23)
        .stop(Stop::new().steps(100_000))
        .build(chains::<1>(n))
        .unwrap();
        let err = opt.run().unwrap_err();
        let Error::UnboundedBelow { chain, value } = err else {
            panic!("expected UnboundedBelow, got {err:?}");
        };
        println!("{err} (step {})", opt.iteration());
        assert!(value < -f64::MAX.sqrt());
        assert!(chain < n);
        assert_eq!(opt.chains()[chain].value(), value);
        assert!(err.to_string().contains("unbounded below"));
        assert!(opt.iteration() < 100_000);
    }
}

// ---------------------------------------------------------------------------
// (6) No silent failure.

/// Out-of-range `a` and `h`, which used to be accepted (a run at `a =
/// 1e300` or `h = 1e8` gave numbers of unknown accuracy), are refused.
#[test]
fn out_of_range_parameters_are_refused() {
    let out = |name, value, min, max| Error::OutOfRange {
        name,
        value,
        min,
        max,
    };
    let hrla = Hrla::paper(0.01).unwrap();
    assert_eq!(hrla.at(1e300), Err(out("a", 1e300, 1e-6, 1e6)));
    let got = Builder::new(Rastrigin, hrla, 1e300, Point::new([1.0; 2]).unwrap())
        .stop(Stop::new().steps(10))
        .build(chains::<2>(2))
        .map(|o| o.iteration());
    assert_eq!(got, Err(out("a", 1e300, 1e-6, 1e6)));
    for h in [1e-30, 1e8] {
        assert_eq!(Hrla::paper(h), Err(out("alpha h", h, 1e-8, 50.0)));
        assert_eq!(hrla::Ula::paper(h), Err(out("alpha h", h, 1e-8, 50.0)));
    }
    let text = Hrla::paper(1e8).unwrap_err().to_string();
    assert!(text.contains("alpha h") && text.contains("1e-8") && text.contains("5e1"));
}

/// `NonFiniteStart` names the chain and what was not finite.
#[test]
fn non_finite_starts_are_named() {
    let hrla = Hrla::paper(0.01).unwrap();
    let start =
        FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| x.copy_from_slice(&[c as f64, 0.0]));
    let nan_at = |bad: usize, what: &'static str| {
        FnPotential::new(move |x: &[f64; 2], g: &mut [f64; 2]| {
            let here = x[0] == bad as f64;
            *g = [
                if here && what == "gradient" {
                    f64::NAN
                } else {
                    1.0
                },
                0.0,
            ];
            if here && what == "value" {
                f64::INFINITY
            } else {
                1.0
            }
        })
    };
    for (bad, what) in [(0, "value"), (3, "value"), (1, "gradient"), (4, "gradient")] {
        let got = Builder::new(nan_at(bad, what), hrla, 4.0, start)
            .build(chains::<2>(5))
            .map(|o| o.iteration());
        assert_eq!(
            got,
            Err(Error::NonFiniteStart {
                chain: bad,
                what,
                tries: hrla::START_TRIES
            })
        );
    }
    let start = FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| {
        x.copy_from_slice(&{ if c == 2 { [f64::NAN, 0.0] } else { [0.0; 2] } })
    });
    let got = Builder::new(Rastrigin, hrla, 4.0, start)
        .build(chains::<2>(5))
        .map(|o| o.iteration());
    let err = got.unwrap_err();
    assert_eq!(
        err,
        Error::NonFiniteStart {
            chain: 2,
            what: "position",
            tries: 100
        }
    );
    assert_eq!(
        err.to_string(),
        "no feasible initial point for chain 2: 100 drawn, the last one's position is not finite"
    );
}

/// `D = 0` and `N = 0` are errors from `build`, not empty runs that
/// report nothing (or divide by zero in a mean).
#[test]
fn no_dimension_and_no_chain_are_errors() {
    let hrla = Hrla::paper(0.01).unwrap();
    let got = Builder::new(Rastrigin, hrla, 4.0, Point::new([]).unwrap())
        .stop(Stop::new().steps(10))
        .build(vec![Chain::<f64, 0>::new(); 3])
        .map(|o| o.iteration());
    assert_eq!(
        got,
        Err(Error::Zero {
            name: "dimension D"
        })
    );
    let got = Builder::new(Rastrigin, hrla, 4.0, Point::new([1.0; 2]).unwrap())
        .stop(Stop::new().steps(10))
        .build(Vec::<Chain<f64, 2>>::new())
        .map(|o| o.iteration());
    assert_eq!(got, Err(Error::Zero { name: "chains" }));
    let mut empty: [Chain<f64, 2>; 0] = [];
    let got = Builder::new(Rastrigin, hrla, 4.0, Point::new([1.0; 2]).unwrap())
        .build(&mut empty[..])
        .map(|o| o.iteration());
    assert_eq!(got, Err(Error::Zero { name: "chains" }));
    // Both: the chains are checked first.
    let got = Builder::new(Rastrigin, hrla, 4.0, Point::new([]).unwrap())
        .build(Vec::<Chain<f64, 0>>::new())
        .map(|o| o.iteration());
    assert_eq!(got, Err(Error::Zero { name: "chains" }));
}
