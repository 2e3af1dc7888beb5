//! The default solver, `Auto`: it counts every evaluation within its
//! budget, is a pure function of its seed, refuses bad settings with typed
//! errors, and reaches the minimum of smooth problems to the float type's
//! precision. (How it compares with other solvers is a benchmark, not a
//! test: `bench/quality`, `docs/QUALITY.md`.)

use std::cell::{Cell, RefCell};
use std::ops::ControlFlow;

use hrla::rand_core::SeedableRng;
use hrla::{
    Ackley, Auto, AutoStorage, Bounds, Chain, Error, FnPotential, Interval, Lbfgs, Parts,
    Potential, Problem, Rastrigin, Sampling, Solution, StyblinskiTang, Termination,
};
use hrla_tests::fixtures::AutoArrays;
use rand_xoshiro::Xoshiro256PlusPlus;

fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    (0..n).map(|_| Chain::new()).collect()
}

/// Every call of the potential is counted, and the budget is a hard cap.
#[test]
fn the_budget_is_exact() {
    for budget in [64, 100, 1_000, 5_000] {
        let calls = Cell::new(0u64);
        let p = FnPotential::new(|x: &[f64; 4], g: &mut [f64; 4]| {
            calls.set(calls.get() + 1);
            Rastrigin.value_and_gradient(x, g)
        });
        let mut lbfgs: Lbfgs<f64, 4, 5> = Lbfgs::new();
        let found = Auto::default()
            .minimize(
                &Problem::new(&p, &Interval::new(-5.12, 5.12).unwrap(), budget).seed(9),
                (&mut chains::<4>(32)[..], &mut lbfgs),
            )
            .unwrap();
        assert_eq!(found.evaluations, calls.get(), "budget {budget}");
        assert!(found.evaluations <= budget, "budget {budget}: {found:?}");
        assert_eq!(Rastrigin.value(&found.x), found.value);
    }
}

/// A 2-D Styblinski–Tang run of 8 chains in `[-5, 5]^2` (seed 3) and every
/// point it evaluated, in order.
fn styblinski_tang_run(budget: u64) -> (Solution<f64, [f64; 2]>, Vec<[f64; 2]>) {
    let points = RefCell::new(Vec::<[f64; 2]>::new());
    let p = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
        points.borrow_mut().push(*x);
        StyblinskiTang.value_and_gradient(x, g)
    });
    let mut lbfgs: Lbfgs<f64, 2, 5> = Lbfgs::new();
    let box5 = Interval::new(-5.0, 5.0).unwrap();
    let found = Auto::default()
        .minimize(
            &Problem::new(&p, &box5, budget).seed(3),
            (&mut chains::<2>(8)[..], &mut lbfgs),
        )
        .unwrap();
    (found, points.into_inner())
}

/// The initial points' quenches begin at the lowest of them: a budget that
/// ends within the quenches has searched the best start (the first point
/// the quenches evaluate is the first step from that start, along its
/// steepest descent: the start's own value and gradient are reused).
#[test]
fn the_lowest_initial_point_is_quenched_first() {
    let n = 8;
    let (_, points) = styblinski_tang_run(200);
    let starts = &points[..n];
    let value = |x: &[f64; 2]| StyblinskiTang.value(x);
    let lowest = starts
        .iter()
        .min_by(|a, b| value(a).total_cmp(&value(b)))
        .unwrap();
    // In chain order, chain 0's start would be searched first.
    assert_ne!(starts[0], *lowest);
    let mut g = [0.0; 2];
    StyblinskiTang.value_and_gradient(lowest, &mut g);
    let step = [points[n][0] - lowest[0], points[n][1] - lowest[1]];
    let cosine = -(step[0] * g[0] + step[1] * g[1]) / (step[0].hypot(step[1]) * g[0].hypot(g[1]));
    assert!(cosine > 1.0 - 1e-12, "{:?} after {starts:?}", points[n]);
}

/// A quench starts from what the step before it evaluated: an initial
/// point's value and gradient, or the last Langevin step's; a Langevin
/// step held in a corner of the box keeps its point's; the measurement
/// takes each basin's gradient from its quench. No point is evaluated
/// twice in a row, and the run's (minimum in the interior, Langevin steps
/// and quenches pushed into the corners) evaluates at most 4 of its 3 000
/// points again, a corner that another quench reaches later.
#[test]
fn a_quench_reuses_its_start() {
    let (found, points) = styblinski_tang_run(3_000);
    assert!(found.rounds > 10, "{found:?}");
    assert_eq!(points.len() as u64, found.evaluations);
    for (k, pair) in points.windows(2).enumerate() {
        assert!(pair[0] != pair[1], "evaluation {k} repeated: {:?}", pair[0]);
    }
    let mut seen = std::collections::HashSet::new();
    let again = points
        .iter()
        .filter(|p| !seen.insert(p.map(f64::to_bits)))
        .count();
    assert!(again <= 4, "{again} points evaluated again");
}

/// A soft budget lets the best start's quench run on past it, to the
/// budget: on a 10-D ellipsoid of condition `10^6`, a run of 60
/// evaluations ends with its first quench cut short (at `U` near 50), and
/// the same run given 1 200 with a soft budget of 60 converges that
/// quench (below `1e-6`), ends there (the soft budget spent: nothing else starts), and
/// spends at most the budget. A soft budget at or above the budget
/// changes no bit.
#[test]
fn a_soft_budget_lets_the_best_start_finish() {
    let calls = Cell::new(0u64);
    let p = FnPotential::new(|x: &[f64; 10], g: &mut [f64; 10]| {
        calls.set(calls.get() + 1);
        let mut u = 0.0;
        for i in 0..10 {
            let c = 10f64.powf(6.0 * i as f64 / 9.0);
            u += c * x[i] * x[i];
            g[i] = 2.0 * c * x[i];
        }
        u
    });
    let domain = Interval::new(-5.0, 5.0).unwrap();
    let run = |problem: Problem<'_, f64, _, _>| {
        calls.set(0);
        let mut lbfgs: Lbfgs<f64, 10, 20> = Lbfgs::new();
        let found = Auto::default()
            .minimize(&problem, (&mut chains::<10>(8)[..], &mut lbfgs))
            .unwrap();
        assert_eq!(found.evaluations, calls.get());
        found
    };
    let cut = run(Problem::new(&p, &domain, 60).seed(1));
    let soft = run(Problem::new(&p, &domain, 1_200).seed(1).soft_budget(60));
    assert_eq!(cut.termination, Termination::Evaluations);
    assert!(cut.value > 1.0, "{cut:?}");
    assert_eq!(soft.termination, Termination::Evaluations);
    assert_eq!(soft.rounds, 0, "{soft:?}");
    assert!(
        soft.evaluations > 60 && soft.evaluations <= 1_200,
        "{soft:?}"
    );
    assert!(soft.value < 1e-6, "{soft:?}");
    for budget in [60, 3_000] {
        let plain = run(Problem::new(&p, &domain, budget).seed(1));
        for above in [budget, 10 * budget] {
            let same = run(Problem::new(&p, &domain, budget).seed(1).soft_budget(above));
            assert_eq!(same, plain, "soft budget {above}");
        }
    }
}

/// A best start whose quench ends within the soft budget leaves a run
/// that plans within it bit for bit as a run with that budget: the
/// budget above the soft one goes to that quench only.
#[test]
fn a_soft_budget_is_the_budget_once_the_first_quench_ends() {
    let domain = Interval::new(-5.0, 5.0).unwrap();
    let run = |problem: Problem<'_, f64, StyblinskiTang, Interval<f64>>| {
        let mut lbfgs: Lbfgs<f64, 2, 5> = Lbfgs::new();
        Auto::default()
            .minimize(&problem, (&mut chains::<2>(8)[..], &mut lbfgs))
            .unwrap()
    };
    for soft in [1_000, 3_000] {
        let plain = run(Problem::new(&StyblinskiTang, &domain, soft).seed(3));
        let planned = run(Problem::new(&StyblinskiTang, &domain, 4 * soft)
            .seed(3)
            .soft_budget(soft));
        assert!(plain.rounds > 0, "{plain:?}");
        assert_eq!(planned, plain, "soft budget {soft}");
    }
}

/// A run is a pure function of the seed: the same seed, the same bits;
/// another seed, another run.
#[test]
fn runs_are_reproducible() {
    let run = |seed| {
        let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
        Auto::default()
            .minimize(
                &Problem::new(&Ackley, &Interval::new(-32.768, 32.768).unwrap(), 20_000).seed(seed),
                (&mut chains::<10>(32)[..], &mut lbfgs),
            )
            .unwrap()
    };
    let (a, b, c) = (run(4), run(4), run(5));
    assert_eq!(a.x.map(f64::to_bits), b.x.map(f64::to_bits));
    assert_eq!(a.value.to_bits(), b.value.to_bits());
    assert_ne!(a.x.map(f64::to_bits), c.x.map(f64::to_bits));
}

/// Styblinski–Tang in 10-D (`2^10` local minima, the global one in one
/// corner): every one of five fixed seeds ends within 1e-9 of `U*` with
/// 125 000 evaluations (deterministic; in the benchmark, 20 of 20 seeds).
#[test]
fn finds_styblinski_tang() {
    let minimum = hrla::KnownMinimum::<f64, 10>::global_minimum(&StyblinskiTang);
    for seed in 0..5 {
        let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
        let found = Auto::default()
            .minimize(
                &Problem::new(&StyblinskiTang, &Interval::new(-5.0, 5.0).unwrap(), 125_000)
                    .seed(seed),
                (&mut chains::<10>(32)[..], &mut lbfgs),
            )
            .unwrap();
        assert!(found.value - minimum < 1e-9, "seed {seed}: {found:?}");
    }
}

/// In f32 as well, with a 32-bit generator.
#[test]
fn works_in_f32() {
    let mut ch: Vec<Chain<f32, 2, rand_xoshiro::Xoshiro128PlusPlus>> =
        (0..16).map(|_| Chain::default()).collect();
    let mut lbfgs: Lbfgs<f32, 2, 4> = Lbfgs::new();
    let found = Auto::default()
        .minimize(
            &Problem::new(&Rastrigin, &Interval::new(-5.12f32, 5.12).unwrap(), 10_000).seed(2),
            (&mut ch[..], &mut lbfgs),
        )
        .unwrap();
    assert!(found.value < 1e-6, "{found:?}");
}

/// Bad settings and inputs are typed errors.
#[test]
fn bad_settings_are_refused() {
    let domain = Interval::new(-1.0, 1.0).unwrap();
    let mut lbfgs: Lbfgs<f64, 2, 3> = Lbfgs::new();
    let run = |auto: Auto<f64>, budget: u64, n: usize| {
        let mut lbfgs: Lbfgs<f64, 2, 3> = Lbfgs::new();
        auto.minimize(
            &Problem::new(&Rastrigin, &domain, budget).seed(0),
            (&mut chains::<2>(n)[..], &mut lbfgs),
        )
    };
    let d = Auto::default();
    assert!(matches!(
        run(Auto { steps: 0, ..d }, 1000, 4),
        Err(Error::Zero { name: "steps" })
    ));
    assert!(matches!(
        run(
            Auto {
                steps: hrla::MAX_STEPS + 1,
                ..d
            },
            1000,
            4
        ),
        Err(Error::OutOfRange { name: "steps", .. })
    ));
    assert!(matches!(
        run(Auto { quench: 0, ..d }, 1000, 4),
        Err(Error::Zero { name: "quench" })
    ));
    assert!(matches!(
        run(Auto { stall: 0, ..d }, 1000, 4),
        Err(Error::Zero { name: "stall" })
    ));
    assert!(matches!(
        run(Auto { ladder: -1.0, ..d }, 1000, 4),
        Err(Error::NotPositive { name: "ladder", .. })
    ));
    for accept in [f64::NAN, -0.1, 1.5] {
        assert!(matches!(
            run(Auto { accept, ..d }, 1000, 4),
            Err(Error::NotPositive {
                name: "accept (in [0, 1])",
                ..
            })
        ));
    }
    assert!(matches!(
        run(
            Auto {
                step_scale: 0.0,
                ..d
            },
            1000,
            4
        ),
        Err(Error::NotPositive {
            name: "step_scale",
            ..
        })
    ));
    assert!(matches!(
        run(d, 1000, 0),
        Err(Error::Zero { name: "chains" })
    ));
    assert!(matches!(
        run(d, 7, 4),
        Err(Error::Budget {
            budget: 7,
            chains: 8
        })
    ));
    let nan_start = FnPotential::new(|_: &[f64; 2], g: &mut [f64; 2]| {
        *g = [0.0; 2];
        f64::NAN
    });
    assert!(matches!(
        d.minimize(
            &Problem::new(&nan_start, &domain, 1000).seed(0),
            (&mut chains::<2>(4)[..], &mut lbfgs)
        ),
        Err(Error::NonFiniteStart { what: "value", .. })
    ));
}

/// `Optimizer::restart` moves a chain (confined to the domain, zero
/// velocity), counts one evaluation within the budget, records a better
/// point as the chain's best, and does nothing once the budget is spent.
#[test]
fn restart_moves_a_chain_within_the_budget() {
    use hrla::{Builder, Hrla, Stop};
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let mut ch = chains::<2>(4);
    let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01).unwrap(), 4.0, domain)
        .domain(domain)
        .stop(Stop::new().evaluations(6))
        .build(&mut ch)
        .unwrap();
    assert_eq!(opt.evaluations(), 4);
    assert_eq!(opt.restart(2, &[0.0, 9.0]), Ok(true));
    assert_eq!(opt.evaluations(), 5);
    // 9 reflects at 5.12 to 1.24 (up to rounding).
    let x = opt.chains()[2].x();
    assert!(x[0] == 0.0 && (x[1] - 1.24).abs() < 1e-12, "{x:?}");
    assert_eq!(*opt.chains()[2].y(), [0.0, 0.0]);
    assert_eq!(opt.restart(1, &[0.0, 0.0]), Ok(true));
    assert_eq!(opt.best().value, 0.0);
    assert_eq!(opt.best_chain(), 1);
    assert_eq!(opt.restart(0, &[1.0, 1.0]), Ok(false));
    assert_eq!(
        opt.restart(4, &[1.0, 1.0]),
        Err(Error::Index {
            name: "chain",
            index: 4,
            len: 4
        })
    );
    assert_eq!(opt.evaluations(), 6);
}

/// Rosenbrock in 6-D: `sum 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2`, one
/// narrow curved valley.
fn rosenbrock(x: &[f64; 6], g: &mut [f64; 6]) -> f64 {
    *g = [0.0; 6];
    let mut u = 0.0;
    for i in 0..5 {
        let a = x[i + 1] - x[i] * x[i];
        let b = 1.0 - x[i];
        u += 100.0 * a * a + b * b;
        g[i] += -400.0 * x[i] * a - 2.0 * b;
        g[i + 1] += 200.0 * a;
    }
    u
}

/// The returned point is a local minimum to machine precision even when
/// every quench is cut short (5 evaluations, far from converged in a
/// curved valley, and the initial quenches stop in the units of the values
/// at random points, up to `1e6` here): the best point is polished until
/// the gradient vanishes or no step lowers `U`.
#[test]
fn the_returned_point_is_polished() {
    for seed in 0..3 {
        let mut lbfgs: Lbfgs<f64, 6, 8> = Lbfgs::new();
        let found = Auto {
            quench: 5,
            ..Auto::default()
        }
        .minimize(
            &Problem::new(
                &FnPotential::new(rosenbrock),
                &Interval::new(-5.0, 10.0).unwrap(),
                5_000,
            )
            .seed(seed),
            (&mut chains::<6>(4)[..], &mut lbfgs),
        )
        .unwrap();
        let mut g = [0.0; 6];
        rosenbrock(&found.x, &mut g);
        let norm = g.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(
            norm < 1e-6 && found.value < 1e-12,
            "seed {seed}: |g| = {norm:e}, {found:?}"
        );
    }
}

/// The temperature comes from the problem's quenched minima and the step
/// from its curvature, so the scale of `U` does not matter: Rastrigin
/// times `1e9` (random points at `1e10` and more) is solved with the same
/// budget and seeds as Rastrigin itself (to `1e-12` relative).
#[test]
fn the_scale_of_u_does_not_matter() {
    let scaled = FnPotential::new(|x: &[f64; 4], g: &mut [f64; 4]| {
        let u = Rastrigin.value_and_gradient(x, g);
        for gi in g.iter_mut() {
            *gi *= 1e9;
        }
        1e9 * u
    });
    let domain = Interval::new(-5.12, 5.12).unwrap();
    for seed in 0..3 {
        let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
        let plain = Auto::default()
            .minimize(
                &Problem::new(&Rastrigin, &domain, 20_000).seed(seed),
                (&mut chains::<4>(4)[..], &mut lbfgs),
            )
            .unwrap();
        let big = Auto::default()
            .minimize(
                &Problem::new(&scaled, &domain, 20_000).seed(seed),
                (&mut chains::<4>(4)[..], &mut lbfgs),
            )
            .unwrap();
        assert!(plain.value < 1e-12, "seed {seed}: {plain:?}");
        assert!(big.value < 1e-3, "seed {seed}: {big:?}");
    }
}

/// A landscape flat at every start (a narrow well of width 0.2 in a box
/// of width 10: the gradient underflows to 0 at almost every point) gives
/// a finite step, and the run still finds the well. (The step is in the
/// units that the curvature of the tails the probes meet defines, whose
/// values underflow: a finite number of the order of their inverse.)
#[test]
fn flat_stretches_give_a_finite_step() {
    let well = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
        let d = [x[0] - 1.3, x[1] + 2.1];
        let e = (-(d[0] * d[0] + d[1] * d[1]) / (2.0 * 0.1 * 0.1)).exp();
        *g = [d[0] / 0.01 * e, d[1] / 0.01 * e];
        -e
    });
    let mut found_it = 0;
    for seed in 0..5 {
        let mut lbfgs: Lbfgs<f64, 2, 8> = Lbfgs::new();
        let found = Auto::default()
            .minimize(
                &Problem::new(&well, &Interval::new(-5.0, 5.0).unwrap(), 20_000).seed(seed),
                (&mut chains::<2>(4)[..], &mut lbfgs),
            )
            .unwrap();
        assert!(found.step.is_finite() && found.step > 0.0, "{found:?}");
        found_it += usize::from(found.value < -1.0 + 1e-12);
    }
    assert!(found_it >= 4, "the well found in {found_it} of 5 runs");
}

/// A run's best point, value, evaluations, rounds and step bits, the
/// chains' basins, and what its observer saw.
type Outcome<F> = (Result<(Vec<F>, F, u64, u64, u64), Error>, Vec<F>, Vec<u64>);

/// Runs `auto` over `n` chains of dimension `d` in lent flat storage, with
/// an observer that stops after `stop_at` evaluations.
#[allow(clippy::too_many_arguments)]
fn flat<F, P, B>(
    auto: &Auto<F>,
    p: &P,
    domain: &B,
    d: usize,
    n: usize,
    budget: u64,
    seed: u64,
    stop_at: u64,
) -> Outcome<F>
where
    F: hrla::Float,
    P: hrla::BatchPotential<F> + ?Sized,
    B: hrla::Sides<F> + ?Sized,
{
    let m = 6;
    let mut arrays = AutoArrays::<F>::new(n, d, m);
    let mut storage = arrays.storage();
    let mut seen = Vec::new();
    let found = auto
        .minimize_with(
            &Problem::new(p, &domain, budget).seed(seed),
            &mut storage,
            |pr| {
                seen.push(pr.evaluations);
                seen.push(pr.value.to_f64().to_bits());
                if pr.evaluations > stop_at {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .map(|s| {
            (
                s.x.to_vec(),
                s.value,
                s.evaluations,
                s.rounds,
                s.step.to_f64().to_bits(),
            )
        });
    let positions = storage.positions().to_vec();
    (found, positions, seen)
}

/// The same run through the const-generic entry point.
fn fixed<F, P, const D: usize>(
    auto: &Auto<F>,
    p: &P,
    domain: Interval<F>,
    n: usize,
    budget: u64,
    seed: u64,
    stop_at: u64,
) -> Outcome<F>
where
    F: hrla::Float,
    P: Potential<F, D>,
{
    let mut chains: Vec<Chain<F, D>> = (0..n).map(|_| Chain::default()).collect();
    let mut lbfgs: Lbfgs<F, D, 6> = Lbfgs::new();
    let mut seen = Vec::new();
    let found = auto
        .minimize_with(
            &Problem::new(p, &domain, budget).seed(seed),
            (&mut chains[..], &mut lbfgs),
            |pr| {
                seen.push(pr.evaluations);
                seen.push(pr.value.to_f64().to_bits());
                if pr.evaluations > stop_at {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .map(|s| {
            (
                s.x.to_vec(),
                s.value,
                s.evaluations,
                s.rounds,
                s.step.to_f64().to_bits(),
            )
        });
    let positions = chains.iter().flat_map(|c| c.x().to_vec()).collect();
    (found, positions, seen)
}

/// `Auto` over lent flat storage at a run-time dimension gives the bits
/// of the const-generic run at `Const<17>`: every part of a round, f64 and
/// f32, infeasible regions, an observer that stops the run, a box given as
/// an `Interval` or as `Bounds` with equal sides.
#[test]
fn a_run_time_dimension_gives_the_const_bits() {
    let holes = FnPotential::new(|x: &[f64; 17], g: &mut [f64; 17]| {
        let v = Rastrigin.value_and_gradient(x, g);
        if x[0] < -3.0 { f64::NAN } else { v }
    });
    let holes_flat = FnPotential::slices(|x: &[f64], g: &mut [f64]| {
        let v =
            Rastrigin.value_and_gradient(<&[f64; 17]>::try_from(x).unwrap(), g.try_into().unwrap());
        if x[0] < -3.0 { f64::NAN } else { v }
    });
    let box17 = Interval::new(-5.12, 5.12).unwrap();
    let sides = Bounds::new(vec![-5.12; 17], vec![5.12; 17]).unwrap();
    let mut cases = 0;
    for seed in 0..2 {
        for parts in [
            Parts::default(),
            Parts {
                sampling: Sampling::Jump,
                ..Parts::default()
            },
            Parts {
                sampling: Sampling::Differential,
                ..Parts::default()
            },
            Parts {
                quenches: false,
                ..Parts::default()
            },
        ] {
            let auto = Auto {
                parts,
                stall: 3,
                ..Auto::default()
            };
            let want = fixed::<_, _, 17>(&auto, &Rastrigin, box17, 6, 6_000, seed, u64::MAX);
            assert_eq!(
                flat(&auto, &Rastrigin, &box17, 17, 6, 6_000, seed, u64::MAX),
                want
            );
            assert_eq!(
                flat(&auto, &Rastrigin, &sides, 17, 6, 6_000, seed, u64::MAX),
                want
            );
            assert!(want.0.is_ok());
            cases += 1;
        }
        let auto = Auto::default();
        let want = fixed::<_, _, 17>(&auto, &holes, box17, 8, 8_000, seed, u64::MAX);
        assert_eq!(
            flat(&auto, &holes_flat, &sides, 17, 8, 8_000, seed, u64::MAX),
            want
        );
        let want = fixed::<_, _, 17>(&auto, &Ackley, box17, 5, 50_000, seed, 3_000);
        let got = flat(&auto, &Ackley, &box17, 17, 5, 50_000, seed, 3_000);
        assert_eq!(got, want);
        assert!(got.0.unwrap().2 < 4_000, "the observer stopped it");
        let want = fixed::<f32, _, 17>(
            &Auto::default(),
            &Rastrigin,
            Interval::new(-5.12, 5.12).unwrap(),
            4,
            5_000,
            seed,
            u64::MAX,
        );
        assert_eq!(
            flat(
                &Auto::default(),
                &Rastrigin,
                &Interval::new(-5.12f32, 5.12).unwrap(),
                17,
                4,
                5_000,
                seed,
                u64::MAX
            ),
            want
        );
        cases += 3;
    }
    assert_eq!(cases, 14);
}

/// `Auto` in the box `[-5.12 s_i, 5.12 s_i]` on `U(x) = base(z)`,
/// `z_i = x_i / s_i - shift_i` (each coordinate on its side's scale, the
/// minimum `base(0) = 0` at `x_i = s_i shift_i`): how many of `seeds` runs
/// end within `1e-10` of it, each such point checked.
fn scaled_hits(
    base: fn(&[f64], &mut [f64]) -> f64,
    side: [f64; 6],
    budget: u64,
    seeds: u64,
) -> u64 {
    let d = side.len();
    let lo: Vec<f64> = side.iter().map(|s| -5.12 * s).collect();
    let hi: Vec<f64> = side.iter().map(|s| 5.12 * s).collect();
    let bounds = Bounds::new(lo, hi).unwrap();
    let shift = [0.7, -1.3, 2.1, -0.4, 1.9, 0.2];
    let p = FnPotential::slices(move |x: &[f64], g: &mut [f64]| {
        let z: Vec<f64> = (0..x.len()).map(|i| x[i] / side[i] - shift[i]).collect();
        let v = base(&z, g);
        for i in 0..x.len() {
            g[i] /= side[i];
        }
        v
    });
    let mut hits = 0;
    for seed in 0..seeds {
        let n = Auto::<f64>::chains_for(budget);
        let (found, ..) = flat(&Auto::default(), &p, &bounds, d, n, budget, seed, u64::MAX);
        let (x, value, evaluations, ..) = found.unwrap();
        assert!(evaluations <= budget);
        // U >= sum z_i^2 for both bases: U < 1e-10 puts every z_i within
        // 1e-5 of 0.
        if value < 1e-10 {
            hits += 1;
            for i in 0..d {
                assert!(
                    (x[i] - side[i] * shift[i]).abs() < 1e-5 * side[i],
                    "{seed}: {x:?}"
                );
            }
        }
    }
    hits
}

fn sphere(z: &[f64], g: &mut [f64]) -> f64 {
    z.iter()
        .zip(g.iter_mut())
        .map(|(&z, g)| {
            *g = 2.0 * z;
            z * z
        })
        .sum()
}

fn rastrigin6(z: &[f64], g: &mut [f64]) -> f64 {
    Rastrigin.value_and_gradient(<&[f64; 6]>::try_from(z).unwrap(), g.try_into().unwrap())
}

/// A box whose sides differ by 10^6: the dynamics and the quenches run in
/// the box's unit coordinates, and `Auto` finds the minimum of a shifted
/// sphere scaled per coordinate every time (a condition number of 10^12
/// in `x`, 1 in unit coordinates), and of Rastrigin scaled per
/// coordinate over sides that differ by 10^2 (at `B = 10 000`) and by
/// 10^6 (at `125 000`). (With one step size in `x` for every coordinate,
/// the last two were solved in none of these 5 runs: `bench/src/bin/sides.rs`
/// measures 20 seeds.)
#[test]
fn auto_finds_minima_in_a_box_of_sides_on_different_scales() {
    assert_eq!(
        scaled_hits(sphere, [1e-3, 1.0, 1e3, 0.1, 10.0, 999.0], 5_000, 5),
        5
    );
    assert_eq!(
        scaled_hits(rastrigin6, [0.1, 1.0, 10.0, 0.3, 3.0, 9.9], 10_000, 5),
        5
    );
    assert_eq!(
        scaled_hits(rastrigin6, [1e-3, 1.0, 1e3, 0.1, 10.0, 999.0], 125_000, 5),
        5
    );
}

/// Lent storage of the wrong shape, and a box or a potential of another
/// dimension, are typed errors before any evaluation.
#[test]
fn auto_storage_refuses_bad_shapes() {
    let (n, d, m) = (4, 3, 5);
    let size = AutoStorage::<f64, Xoshiro256PlusPlus>::floats(n, d, m);
    let mut floats = vec![0.0; size + 1];
    let mut diverged = vec![false; n];
    let mut rngs: Vec<_> = (0..n)
        .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
        .collect();
    assert!(matches!(
        AutoStorage::new(d, m, &mut floats, &mut diverged, &mut rngs),
        Err(Error::Length { name: "floats", .. })
    ));
    assert!(matches!(
        AutoStorage::new(0, m, &mut floats[..size], &mut diverged, &mut rngs),
        Err(Error::Zero { name: "dimension" })
    ));
    assert!(matches!(
        AutoStorage::new(d, 0, &mut floats[..size], &mut diverged, &mut rngs),
        Err(Error::Zero { .. })
    ));
    assert!(matches!(
        AutoStorage::new(d, m, &mut floats[..size], &mut diverged[..3], &mut rngs),
        Err(Error::Length {
            name: "diverged",
            ..
        })
    ));
    assert!(matches!(
        AutoStorage::<f64, Xoshiro256PlusPlus>::new(d, m, &mut floats[..size], &mut [], &mut []),
        Err(Error::Zero { name: "chains" })
    ));
    assert_eq!(
        AutoStorage::<f64, Xoshiro256PlusPlus>::floats(usize::MAX, 2, 2),
        usize::MAX
    );
    let mut storage =
        AutoStorage::new(d, m, &mut floats[..size], &mut diverged, &mut rngs).unwrap();
    let calls = Cell::new(0);
    let p = FnPotential::slices(|x: &[f64], g: &mut [f64]| {
        calls.set(calls.get() + 1);
        Rastrigin.value_and_gradient(<&[f64; 3]>::try_from(x).unwrap(), g.try_into().unwrap())
    });
    let four = Bounds::new([-1.0; 4], [1.0; 4]).unwrap();
    assert!(matches!(
        Auto::default().minimize(&Problem::new(&p, &four, 1_000).seed(0), &mut storage),
        Err(Error::Length {
            name: "box sides",
            expected: 3,
            got: 4
        })
    ));
    let q = hrla::Quadratic::<f64, 2>::new(1.0, [0.0; 2]).unwrap();
    assert!(matches!(
        Auto::default().minimize(
            &Problem::new(&q, &Interval::new(-1.0, 1.0).unwrap(), 1_000).seed(0),
            &mut storage
        ),
        Err(Error::Length {
            name: "potential",
            expected: 3,
            got: 2
        })
    ));
    assert!(matches!(
        Auto::default().minimize(
            &Problem::new(&p, &Interval::new(-1.0, 1.0).unwrap(), 7).seed(0),
            &mut storage
        ),
        Err(Error::Budget { .. })
    ));
    assert_eq!(calls.get(), 0);
    let found = Auto::default()
        .minimize(
            &Problem::new(&p, &Interval::new(-5.12, 5.12).unwrap(), 3_000).seed(0),
            &mut storage,
        )
        .unwrap();
    assert_eq!(found.evaluations, calls.get());
    let (x, value) = (found.x.to_vec(), found.value);
    assert_eq!(storage.best(), &x[..]);
    assert_eq!(storage.values().len(), n);
    assert!(storage.values().iter().all(|&v| v >= value));
}

/// A caller's start `x0` is chain 0's initial point: started at the
/// global minimum of 6-D Rastrigin, a budget of 200 evaluations returns
/// it exactly; without `x0`, the same budget finds no point within 0.5 of
/// it (on these seeds: the global basin is one of 11^6 in the box). The
/// start costs chain 0's one evaluation, counted.
#[test]
fn a_start_x0_is_where_chain_0_begins() {
    let domain = Interval::new(-5.12, 5.12).unwrap();
    for seed in 0..5 {
        let calls = Cell::new(0u64);
        let p = FnPotential::new(|x: &[f64; 6], g: &mut [f64; 6]| {
            calls.set(calls.get() + 1);
            Rastrigin.value_and_gradient(x, g)
        });
        let mut lbfgs: Lbfgs<f64, 6, 8> = Lbfgs::new();
        let found = Auto::default()
            .minimize_with(
                &Problem::new(&p, &domain, 200).seed(seed).x0(&[0.0; 6]),
                (&mut chains::<6>(4)[..], &mut lbfgs),
                |_| ControlFlow::Continue(()),
            )
            .unwrap();
        assert_eq!((found.value, found.x), (0.0, [0.0; 6]), "{seed}");
        assert_eq!(found.evaluations, calls.get());
        assert!(found.evaluations <= 200);
        let mut lbfgs: Lbfgs<f64, 6, 8> = Lbfgs::new();
        let drawn = Auto::default()
            .minimize(
                &Problem::new(&Rastrigin, &domain, 200).seed(seed),
                (&mut chains::<6>(4)[..], &mut lbfgs),
            )
            .unwrap();
        assert!(drawn.value > 0.5, "{seed}: {drawn:?}");
    }
}

/// With `x0`, the flat entry point gives the const-generic bits too, and
/// only chain 0's start differs from a run without it: the other chains'
/// initial points are the same draws.
#[test]
fn a_start_x0_gives_the_same_bits_flat_and_const() {
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let sides = Bounds::new(vec![-5.12; 17], vec![5.12; 17]).unwrap();
    let x0: [f64; 17] = core::array::from_fn(|i| 0.3 * i as f64 - 2.0);
    let (n, m, budget) = (5, 6, 6_000);
    for seed in 0..2 {
        let mut chains: Vec<Chain<f64, 17>> = chains::<17>(n);
        let mut lbfgs: Lbfgs<f64, 17, 6> = Lbfgs::new();
        let mut first = Vec::new();
        let want = Auto::default()
            .minimize_with(
                &Problem::new(&Rastrigin, &domain, budget).seed(seed).x0(&x0),
                (&mut chains[..], &mut lbfgs),
                |p| {
                    first.push(p.evaluations);
                    ControlFlow::Continue(())
                },
            )
            .unwrap();
        let mut arrays = AutoArrays::<f64>::new(n, 17, m);
        let mut storage = arrays.storage();
        let mut second = Vec::new();
        let got = Auto::default()
            .minimize_with(
                &Problem::new(&Rastrigin, &sides, budget).seed(seed).x0(&x0),
                &mut storage,
                |p| {
                    second.push(p.evaluations);
                    ControlFlow::Continue(())
                },
            )
            .unwrap();
        assert_eq!(got.x, want.x.as_slice());
        assert_eq!(got.value.to_bits(), want.value.to_bits());
        assert_eq!(
            (got.evaluations, got.rounds),
            (want.evaluations, want.rounds)
        );
        assert_eq!(first, second);
        assert_eq!(
            storage.positions(),
            chains
                .iter()
                .flat_map(|c| c.x().to_vec())
                .collect::<Vec<_>>()
        );
    }
    // The initial points: chain 0 at x0, the others drawn as without it.
    let starts = |x0: Option<&[f64; 17]>| {
        let mut chains: Vec<Chain<f64, 17>> = chains::<17>(n);
        let mut lbfgs: Lbfgs<f64, 17, 6> = Lbfgs::new();
        let stop = |_: &hrla::AutoProgress<'_, f64>| ControlFlow::Break(());
        let auto = Auto::<f64>::default();
        let found = match x0 {
            Some(x0) => auto.minimize_with(
                &Problem::new(&Rastrigin, &domain, budget).seed(3).x0(x0),
                (&mut chains[..], &mut lbfgs),
                stop,
            ),
            None => auto.minimize_with(
                &Problem::new(&Rastrigin, &domain, budget).seed(3),
                (&mut chains[..], &mut lbfgs),
                stop,
            ),
        };
        assert_eq!(found.unwrap().evaluations, n as u64);
        chains.iter().map(|c| *c.x()).collect::<Vec<_>>()
    };
    let (with, without) = (starts(Some(&x0)), starts(None));
    assert_eq!(with[0], x0);
    assert_ne!(without[0], x0);
    assert_eq!(with[1..], without[1..]);
}

/// A start the caller cannot mean is a typed error naming `x0`, before
/// or at its one evaluation: outside the box (or NaN) in a coordinate,
/// of another dimension than the storage's, where `U` or its gradient is
/// not finite (not redrawn: the caller chose it), or where `U` is below
/// the floor.
#[test]
fn a_bad_start_x0_is_a_typed_error() {
    let domain = Interval::new(-1.0, 1.0).unwrap();
    let run = |p: &dyn Fn(&[f64; 3], &mut [f64; 3]) -> f64, x0: [f64; 3]| {
        let calls = Cell::new(0u64);
        let counted = FnPotential::new(|x: &[f64; 3], g: &mut [f64; 3]| {
            calls.set(calls.get() + 1);
            p(x, g)
        });
        let mut lbfgs: Lbfgs<f64, 3, 4> = Lbfgs::new();
        let got = Auto::default()
            .minimize_with(
                &Problem::new(&counted, &domain, 1_000).seed(0).x0(&x0),
                (&mut chains::<3>(4)[..], &mut lbfgs),
                |_| ControlFlow::Continue(()),
            )
            .map(|s| s.value);
        (got, calls.get())
    };
    let bowl = |x: &[f64; 3], g: &mut [f64; 3]| {
        for i in 0..3 {
            g[i] = 2.0 * x[i];
        }
        x.iter().map(|v| v * v).sum::<f64>()
    };
    assert_eq!(
        run(&bowl, [0.0, 0.5, 1.5]),
        (
            Err(Error::OutsideBox {
                index: 2,
                value: 1.5,
                lo: -1.0,
                hi: 1.0
            }),
            0
        )
    );
    let (got, calls) = run(&bowl, [f64::NAN, 0.0, 0.0]);
    assert!(
        matches!(got, Err(Error::OutsideBox { index: 0, value, .. }) if value.is_nan()),
        "{got:?}"
    );
    assert_eq!(calls, 0);
    // The ends of the box are inside.
    assert_eq!(run(&bowl, [-1.0, 1.0, 0.0]).0.map(|v| v < 1e-12), Ok(true));
    let hole = |x: &[f64; 3], g: &mut [f64; 3]| if x[0] > 0.5 { f64::NAN } else { bowl(x, g) };
    let (got, calls) = run(&hole, [0.9, 0.0, 0.0]);
    assert!(
        matches!(got, Err(Error::NotFinite { name: "U at x0", value }) if value.is_nan()),
        "{got:?}"
    );
    assert_eq!(calls, 1);
    let steep = |x: &[f64; 3], g: &mut [f64; 3]| {
        let v = bowl(x, g);
        g[1] = if x[1] > 0.5 { f64::INFINITY } else { g[1] };
        v
    };
    assert_eq!(
        run(&steep, [0.0, 0.9, 0.0]).0,
        Err(Error::NotFinite {
            name: "the gradient at x0",
            value: f64::INFINITY
        })
    );
    let abyss = |x: &[f64; 3], g: &mut [f64; 3]| {
        *g = [0.0; 3];
        if x[2] < -0.5 { -f64::MAX } else { 0.0 }
    };
    assert!(matches!(
        run(&abyss, [0.0, 0.0, -0.9]).0,
        Err(Error::UnboundedBelow { chain: 0, .. })
    ));
    // Flat storage of dimension 3 and an x0 of 2.
    let (n, d, m) = (4, 3, 4);
    let mut arrays = AutoArrays::<f64>::new(n, d, m);
    let mut storage = arrays.storage();
    let got = Auto::default()
        .minimize_with(
            &Problem::new(&Rastrigin, &domain, 1_000)
                .seed(0)
                .x0(&[0.0, 0.0]),
            &mut storage,
            |_| ControlFlow::Continue(()),
        )
        .map(|s| s.value);
    assert_eq!(
        got,
        Err(Error::Length {
            name: "x0",
            expected: 3,
            got: 2
        })
    );
}

/// FNV-1a over the bits of a run's outcome: its point, value, evaluations,
/// rounds and step.
fn outcome_hash(x: &[f64], value: f64, evaluations: u64, rounds: u64, step: f64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let words =
        x.iter()
            .map(|v| v.to_bits())
            .chain([value.to_bits(), evaluations, rounds, step.to_bits()]);
    for w in words {
        for byte in w.to_le_bytes() {
            h = (h ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// In a box whose sides are all equal the unit coordinates are the box's
/// own (every `w_i` is exactly 1): Auto's outcomes there are pinned, bit
/// for bit, on a smooth, a rugged and an infeasible-holed landscape, given
/// as an `Interval` and as `Bounds`.
#[test]
fn a_box_of_equal_sides_keeps_its_bits() {
    let holes = FnPotential::slices(|x: &[f64], g: &mut [f64]| {
        let v =
            Ackley.value_and_gradient(<&[f64; 10]>::try_from(x).unwrap(), g.try_into().unwrap());
        if x[0] < -20.0 { f64::NAN } else { v }
    });
    let mut hashes = Vec::new();
    for seed in 0..2 {
        let interval = Interval::new(-32.768, 32.768).unwrap();
        let bounds = Bounds::new(vec![-32.768; 10], vec![32.768; 10]).unwrap();
        for (n, budget) in [(4, 10_000), (8, 40_000)] {
            let (found, ..) = flat(
                &Auto::default(),
                &Ackley,
                &interval,
                10,
                n,
                budget,
                seed,
                u64::MAX,
            );
            let (x, value, evaluations, rounds, step) = found.unwrap();
            let h = outcome_hash(&x, value, evaluations, rounds, f64::from_bits(step));
            let (again, ..) = flat(
                &Auto::default(),
                &holes,
                &bounds,
                10,
                n,
                budget,
                seed,
                u64::MAX,
            );
            let (x, value, evaluations, rounds, step) = again.unwrap();
            hashes.push((
                h,
                outcome_hash(&x, value, evaluations, rounds, f64::from_bits(step)),
            ));
        }
        let (found, ..) = flat(
            &Auto::default(),
            &Rastrigin,
            &Bounds::new(vec![-5.12; 10], vec![5.12; 10]).unwrap(),
            10,
            4,
            20_000,
            seed,
            u64::MAX,
        );
        let (x, value, evaluations, rounds, step) = found.unwrap();
        let h = outcome_hash(&x, value, evaluations, rounds, f64::from_bits(step));
        hashes.push((h, h));
    }
    // Pinned: rounds of sampling, quench and acceptance, in the problem's
    // units.
    assert_eq!(
        hashes,
        [
            (0xca96e43e5dcecbae, 0x66ebe50fdc04662b),
            (0x5c896e33d4808e05, 0x554a963af7cf4fb9),
            (0x7a31b2bb494737bb, 0x7a31b2bb494737bb),
            (0xe8941b8a97dbb03a, 0x0b677bdbe92ff15b),
            (0x30334f86f36220e8, 0xe53b497a078f6c11),
            (0xcdbad00d38bbc981, 0xcdbad00d38bbc981),
        ]
    );
}

/// The step that follows each rung's acceptance rate is what crosses the
/// deep, regular barriers of 10-D Rastrigin with `A = 10` (the benchmark
/// measures 15 of 20 runs solved at `B = 125 000` with it, 1 of 20 with
/// the measured step fixed). Over 20 fixed seeds the default must solve at
/// least 8 more runs than `accept: 0.0`: the expected difference is about
/// 14 and its standard error `sqrt(20 (0.75 * 0.25 + 0.05 * 0.95)) = 2.2`,
/// so 8 is almost three standard errors short of it.
#[test]
fn the_step_rule_crosses_deep_regular_barriers() {
    let rastrigin = FnPotential::new(|x: &[f64; 10], g: &mut [f64; 10]| {
        let tau = 2.0 * core::f64::consts::PI;
        let mut u = 100.0;
        for i in 0..10 {
            u += x[i] * x[i] - 10.0 * (tau * x[i]).cos();
            g[i] = 2.0 * x[i] + 10.0 * tau * (tau * x[i]).sin();
        }
        u
    });
    let solved = |auto: Auto<f64>| {
        (0..20)
            .filter(|&seed| {
                let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
                let found = auto
                    .minimize(
                        &Problem::new(&rastrigin, &Interval::new(-5.12, 5.12).unwrap(), 125_000)
                            .seed(seed),
                        (
                            &mut chains::<10>(Auto::<f64>::chains_for(125_000))[..],
                            &mut lbfgs,
                        ),
                    )
                    .unwrap();
                found.value < 1e-6
            })
            .count()
    };
    let steered = solved(Auto::default());
    let fixed = solved(Auto {
        accept: 0.0,
        ..Auto::default()
    });
    assert!(
        steered >= fixed + 8,
        "solved {steered} of 20 with the step rule, {fixed} without"
    );
}

/// A caller's own `Sides` is checked as `Bounds::new` checks its sides: a
/// side whose ends are reversed, equal or not finite is refused before any
/// evaluation, never run as a box that is not one.
#[test]
fn a_callers_sides_are_checked_as_bounds_are() {
    /// Sides given by a function of the coordinate.
    struct Own(fn(usize) -> (f64, f64));
    impl hrla::Domain<f64> for Own {
        fn confine(&self, _x: &mut [f64], _y: &mut [f64]) {}
        fn project(&self, _x: &mut [f64]) {}
        fn feasible_direction(&self, _x: &[f64], _d: &mut [f64]) {}
    }
    impl hrla::Sides<f64> for Own {
        fn side(&self, i: usize) -> (f64, f64) {
            (self.0)(i)
        }
    }
    let (n, d, m) = (4, 2, 4);
    let mut arrays = AutoArrays::<f64>::new(n, d, m);
    let mut storage = arrays.storage();
    let calls = Cell::new(0);
    let p = FnPotential::slices(|x: &[f64], g: &mut [f64]| {
        calls.set(calls.get() + 1);
        Rastrigin.value_and_gradient(<&[f64; 2]>::try_from(x).unwrap(), g.try_into().unwrap())
    });
    let sides: [fn(usize) -> (f64, f64); 3] = [
        |i| if i == 1 { (1.0, -1.0) } else { (-1.0, 1.0) },
        |_| (0.5, 0.5),
        |i| if i == 0 { (f64::NAN, 1.0) } else { (-1.0, 1.0) },
    ];
    for side in sides {
        let got =
            Auto::default().minimize(&Problem::new(&p, &Own(side), 1_000).seed(0), &mut storage);
        let want = Interval::new(side(0).0, side(0).1)
            .and(Interval::new(side(1).0, side(1).1))
            .unwrap_err();
        // As text: the error of a NaN side carries the NaN.
        assert_eq!(
            format!("{:?}", got.map(|s| s.value)),
            format!("{:?}", Err::<f64, _>(want))
        );
    }
    assert_eq!(calls.get(), 0, "a refused box evaluated the potential");
    // The same sides, in order, run.
    let fine = Auto::default().minimize(
        &Problem::new(&p, &Own(|_| (-1.0, 1.0)), 1_000).seed(0),
        &mut storage,
    );
    assert!(fine.is_ok());
}

/// The problem's rules end a run for their named reason: the target at
/// once (no polish), the round limit and the stall rule after a round and
/// the polish; `rounds(0)` runs the starts and the polish only. A rule
/// that ends the run early changes nothing before it: the run up to the
/// first end is the bits of the run without it.
#[test]
fn the_problems_rules_end_a_run_for_their_reason() {
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    let mut run = |problem: &Problem<'_, f64, Rastrigin, Interval<f64>>| {
        let mut trace = Vec::new();
        let found = Auto::default()
            .minimize_with(problem, (&mut chains::<4>(4)[..], &mut lbfgs), |p| {
                trace.push((p.evaluations, p.rounds, p.value.to_bits()));
                ControlFlow::Continue(())
            })
            .unwrap();
        (found, trace)
    };
    let base = Problem::new(&Rastrigin, &domain, 20_000).seed(3);
    let (free, free_trace) = run(&base);
    assert_eq!(free.termination, Termination::Evaluations);
    assert!(free.value < 1e-9 && free.rounds > 5, "{free}");

    // The target: the first look at or below it ends the run.
    let target = 1.5;
    let (hit, hit_trace) = run(&base.target(target));
    assert_eq!(hit.termination, Termination::Target, "{hit}");
    let first = free_trace
        .iter()
        .position(|&(_, _, v)| f64::from_bits(v) <= target)
        .unwrap();
    assert_eq!(hit_trace[..], free_trace[..first]);
    assert_eq!(hit.evaluations, free_trace[first].0);
    assert!(hit.value <= target);

    // Rounds: exactly that many, then the polish.
    let (three, _) = run(&base.rounds(3));
    assert_eq!(three.termination, Termination::Steps, "{three}");
    assert_eq!(three.rounds, 3);
    assert!(three.evaluations < free.evaluations);
    let (none, none_trace) = run(&base.rounds(0));
    assert_eq!((none.termination, none.rounds), (Termination::Steps, 0));
    assert!(none_trace.iter().all(|&(_, rounds, _)| rounds == 0));

    // Stall: a window of 2 rounds with no gain beyond an unreachable
    // tolerance ends the rounds after exactly 2.
    let (stalled, _) = run(&base.stall(2, 1e9));
    assert_eq!(stalled.termination, Termination::Stalled, "{stalled}");
    assert_eq!(stalled.rounds, 2);
    // With no tolerance, the run ends `window` rounds after the best last
    // fell: it ran at least `window` rounds and stopped before the budget.
    let (quiet, _) = run(&base.stall(5, 0.0));
    assert_eq!(quiet.termination, Termination::Stalled, "{quiet}");
    assert!(quiet.rounds >= 5 && quiet.evaluations < free.evaluations);
}

/// A bad rule is a typed error before any evaluation, whichever store.
#[test]
fn bad_rules_are_refused() {
    let domain = Interval::new(-1.0, 1.0).unwrap();
    let mut lbfgs: Lbfgs<f64, 2, 4> = Lbfgs::new();
    for (problem, name) in [
        (
            Problem::new(&Rastrigin, &domain, 1_000).target(f64::NAN),
            "target",
        ),
        (
            Problem::new(&Rastrigin, &domain, 1_000).stall(0, 0.0),
            "stall window",
        ),
        (
            Problem::new(&Rastrigin, &domain, 1_000).stall(3, -1.0),
            "stall tolerance",
        ),
    ] {
        let got = Auto::default().minimize(&problem, (&mut chains::<2>(4)[..], &mut lbfgs));
        let said = format!("{:?}", got.unwrap_err());
        assert!(said.contains(name), "{name}: {said}");
    }
}

/// The convergence rule ends a run whose best stopped falling: on a bowl,
/// where every chain finds the same basin, after a sixth of its window,
/// polished to the minimum; its tolerance is
/// relative to the spread of `U` at the initial points, so the same bowl
/// times `1e-10` converges after the same rounds. On
/// Rastrigin the run is the unconverged run's bits up to its end.
#[test]
fn a_converged_run_ends_by_itself() {
    let domain = Interval::new(-5.0, 5.0).unwrap();
    let mut lbfgs: Lbfgs<f64, 3, 8> = Lbfgs::new();
    let bowl = |c: f64| {
        FnPotential::new(move |x: &[f64; 3], g: &mut [f64; 3]| {
            let mut u = 0.0;
            for i in 0..3 {
                let z = x[i] - 0.3 * i as f64;
                u += c * z * z;
                g[i] = 2.0 * c * z;
            }
            u
        })
    };
    let auto = Auto::default();
    let mut ends = Vec::new();
    for c in [1.0, 1e-10] {
        let p = bowl(c);
        let found = auto
            .minimize(
                &Problem::new(&p, &domain, 1_000_000)
                    .seed(4)
                    .converged(&auto),
                (&mut chains::<3>(4)[..], &mut lbfgs),
            )
            .unwrap();
        assert_eq!(found.termination, Termination::Converged, "{found}");
        // Every chain's basin is the bowl's one minimum from the first
        // round on: the rule's shorter window (a sixth) ends the run.
        assert!(found.rounds <= 1 + 60 / 6, "{found}");
        assert!(found.value <= 1e-20 * c, "{found}");
        ends.push(found.rounds);
    }
    assert_eq!(ends[0], ends[1]);

    let domain = Interval::new(-5.12, 5.12).unwrap();
    let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    let mut trace = |problem: Problem<'_, f64, Rastrigin, Interval<f64>>| {
        let mut seen = Vec::new();
        let found = auto
            .minimize_with(&problem, (&mut chains::<4>(4)[..], &mut lbfgs), |p| {
                seen.push((p.evaluations, p.value.to_bits()));
                ControlFlow::Continue(())
            })
            .unwrap();
        (found, seen)
    };
    let base = Problem::new(&Rastrigin, &domain, 200_000).seed(5);
    let (done, done_seen) = trace(base.converge(20));
    let (free, free_seen) = trace(base);
    assert_eq!(done.termination, Termination::Converged, "{done}");
    assert_eq!(free.termination, Termination::Evaluations);
    assert!(done.evaluations < free.evaluations);
    // Up to the polish, which the budget-ended run reaches later.
    let rounds_end = done_seen.len() - 1;
    assert_eq!(done_seen[..rounds_end], free_seen[..rounds_end]);
    let window = Problem::new(&Rastrigin, &domain, 1_000).converge(0);
    assert!(matches!(
        auto.minimize(&window, (&mut chains::<4>(4)[..], &mut lbfgs)),
        Err(Error::Zero {
            name: "convergence window"
        })
    ));
}
