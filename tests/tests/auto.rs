//! The default solver, `Auto`: it counts every evaluation within its
//! budget, is a pure function of its seed, refuses bad settings with typed
//! errors, and reaches the minimum of smooth problems to the float type's
//! precision. (How it compares with other solvers is a benchmark, not a
//! test: `bench/quality`, `docs/QUALITY.md`.)

use std::cell::Cell;

use hrla::{
    Ackley, Auto, Chain, Error, FnPotential, Interval, Lbfgs, Potential, Rastrigin, StyblinskiTang,
};

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
                &p,
                Interval::new(-5.12, 5.12).unwrap(),
                budget,
                9,
                &mut chains::<4>(32),
                &mut lbfgs,
            )
            .unwrap();
        assert_eq!(found.evaluations, calls.get(), "budget {budget}");
        assert!(found.evaluations <= budget, "budget {budget}: {found:?}");
        assert_eq!(Rastrigin.value(&found.x), found.value);
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
                &Ackley,
                Interval::new(-32.768, 32.768).unwrap(),
                20_000,
                seed,
                &mut chains::<10>(32),
                &mut lbfgs,
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
                &StyblinskiTang,
                Interval::new(-5.0, 5.0).unwrap(),
                125_000,
                seed,
                &mut chains::<10>(32),
                &mut lbfgs,
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
            &Rastrigin,
            Interval::new(-5.12f32, 5.12).unwrap(),
            10_000,
            2,
            &mut ch,
            &mut lbfgs,
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
            &Rastrigin,
            domain,
            budget,
            0,
            &mut chains::<2>(n),
            &mut lbfgs,
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
    for jump_rate in [f64::NAN, -0.1, 1.5] {
        assert!(matches!(
            run(Auto { jump_rate, ..d }, 1000, 4),
            Err(Error::NotPositive {
                name: "jump_rate (in [0, 1])",
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
        d.minimize(&nan_start, domain, 1000, 0, &mut chains::<2>(4), &mut lbfgs),
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
/// curved valley): the best point is polished until L-BFGS converges.
#[test]
fn the_returned_point_is_polished() {
    for seed in 0..3 {
        let mut lbfgs: Lbfgs<f64, 6, 8> = Lbfgs::new();
        let found = Auto {
            quench: 5,
            ..Auto::default()
        }
        .minimize(
            &FnPotential::new(rosenbrock),
            Interval::new(-5.0, 10.0).unwrap(),
            5_000,
            seed,
            &mut chains::<6>(4),
            &mut lbfgs,
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
                &Rastrigin,
                domain,
                20_000,
                seed,
                &mut chains::<4>(4),
                &mut lbfgs,
            )
            .unwrap();
        let big = Auto::default()
            .minimize(
                &scaled,
                domain,
                20_000,
                seed,
                &mut chains::<4>(4),
                &mut lbfgs,
            )
            .unwrap();
        assert!(plain.value < 1e-12, "seed {seed}: {plain:?}");
        assert!(big.value < 1e-3, "seed {seed}: {big:?}");
    }
}

/// A landscape flat at every start (a narrow well of width 0.2 in a box
/// of width 10: the gradient underflows to 0 at almost every point) gives
/// a step bounded by the box, not the exact step's cap of 50, and the run
/// still finds the well.
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
                &well,
                Interval::new(-5.0, 5.0).unwrap(),
                20_000,
                seed,
                &mut chains::<2>(4),
                &mut lbfgs,
            )
            .unwrap();
        // At most the longest step: a tenth of the box by the velocity.
        assert!(found.step <= 0.1 * 10f64.sqrt() * 10.0, "{found:?}");
        found_it += usize::from(found.value < -1.0 + 1e-12);
    }
    assert!(found_it >= 4, "the well found in {found_it} of 5 runs");
}
