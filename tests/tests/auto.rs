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
