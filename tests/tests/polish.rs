//! The L-BFGS polish: on its own it reaches the minimum of smooth problems
//! to the float type's precision in few evaluations; inside a run it
//! respects the evaluation budget, lowers the best point without touching
//! the chains' states, and refuses bad input.

use hrla::{
    Builder, Chain, Error, FnPotential, Gaussian, Hrla, Interval, Lbfgs, PolishEnd, PolishSettings,
    Potential, Rastrigin, Stop,
};

/// Rosenbrock in 10-D: `sum 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2`.
fn rosenbrock(x: &[f64; 10], g: &mut [f64; 10]) -> f64 {
    g.fill(0.0);
    let mut u = 0.0;
    for i in 0..9 {
        let a = x[i + 1] - x[i] * x[i];
        let b = 1.0 - x[i];
        u += 100.0 * a * a + b * b;
        g[i] += -400.0 * x[i] * a - 2.0 * b;
        g[i + 1] += 200.0 * a;
    }
    u
}

/// From the classic start `(-1.2, 1, -1.2, 1, ...)`, Rosenbrock's curved
/// valley to `U < 1e-12` in at most 300 evaluations (measured: 89 from
/// all -1.2; deterministic), ending at `x = 1` within 1e-5.
#[test]
fn lbfgs_solves_rosenbrock() {
    let p = FnPotential::new(rosenbrock);
    let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
    let mut x: [f64; 10] = core::array::from_fn(|i| if i % 2 == 0 { -1.2 } else { 1.0 });
    let done = lbfgs
        .minimize(&p, &mut x, PolishSettings::new(300))
        .unwrap();
    assert!(done.value < 1e-12, "{done:?}");
    assert!(done.evaluations <= 300);
    assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-5), "{x:?}");
    assert_eq!(p.value(&x), done.value);
}

/// In f32 as well: 10-D Rastrigin from inside its global basin to 0.
#[test]
fn lbfgs_in_f32() {
    let mut lbfgs: Lbfgs<f32, 10, 4> = Lbfgs::new();
    let mut x = [0.3f32; 10];
    let done = lbfgs
        .minimize(&Rastrigin, &mut x, PolishSettings::new(100))
        .unwrap();
    assert!(done.value < 1e-10, "{done:?}");
}

/// A budget is a hard cap, counted exactly: the polish reports the
/// evaluations it used, and a potential that counts its own calls agrees.
#[test]
fn the_polish_budget_is_exact() {
    for budget in [1, 2, 3, 5, 8, 13, 40] {
        let calls = std::cell::Cell::new(0u64);
        let p = FnPotential::new(|x: &[f64; 10], g: &mut [f64; 10]| {
            calls.set(calls.get() + 1);
            rosenbrock(x, g)
        });
        let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
        let mut x = [-1.2; 10];
        let done = lbfgs
            .minimize(&p, &mut x, PolishSettings::new(budget))
            .unwrap();
        assert_eq!(done.evaluations, calls.get(), "budget {budget}");
        assert!(done.evaluations <= budget, "budget {budget}: {done:?}");
        if budget < 20 {
            assert_eq!(done.end, PolishEnd::Budget, "budget {budget}");
        }
    }
}

/// Inside a run: the polish of the best chain's best point lowers the
/// global best, counts in the run's evaluations, never beyond its budget,
/// and leaves every chain's position and velocity as they were.
#[test]
fn polishing_a_run_respects_its_budget_and_state() {
    // 1 000 steps of 16 chains use 16 016 evaluations; 3 984 are left.
    let budget = 20_000;
    let mut chains: Vec<Chain<f64, 10>> = (0..16).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Gaussian::new([0.0; 10], 0.3).unwrap(),
    )
    .seed(3)
    .stop(Stop::new().evaluations(budget).steps(1_000))
    .build(&mut chains)
    .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(report.evaluations, 16_016);
    let states: Vec<([f64; 10], [f64; 10])> =
        opt.chains().iter().map(|c| (*c.x(), *c.y())).collect();
    let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
    let used_before = opt.evaluations();
    let done = opt
        .polish(opt.best_chain(), &mut lbfgs, PolishSettings::new(1_000))
        .unwrap();
    assert!(opt.evaluations() <= budget);
    assert_eq!(opt.evaluations(), used_before + done.evaluations);
    assert!(opt.best().value <= report.value);
    assert!(opt.best().value < 1e-20, "{done:?}");
    let after: Vec<([f64; 10], [f64; 10])> =
        opt.chains().iter().map(|c| (*c.x(), *c.y())).collect();
    assert_eq!(states, after);
    // Nothing left to spend: a polish of no evaluation.
    let mut opt2 = opt;
    while opt2.evaluations() < budget {
        let left = budget - opt2.evaluations();
        opt2.polish(0, &mut lbfgs, PolishSettings::new(left))
            .unwrap();
        if opt2.evaluations() == budget {
            break;
        }
    }
    let none = opt2.polish(1, &mut lbfgs, PolishSettings::new(10)).unwrap();
    assert_eq!((none.evaluations, none.end), (0, PolishEnd::Budget));
}

/// Bad input is a typed error.
#[test]
fn polish_refuses_bad_input() {
    let mut lbfgs: Lbfgs<f64, 2, 3> = Lbfgs::new();
    let mut x = [1.0, 2.0];
    assert!(matches!(
        lbfgs.minimize(&Rastrigin, &mut x, PolishSettings::new(0)),
        Err(Error::Zero { .. })
    ));
    let mut bad = [f64::NAN, 0.0];
    assert!(matches!(
        lbfgs.minimize(&Rastrigin, &mut bad, PolishSettings::new(10)),
        Err(Error::NotFinite { name: "x", .. })
    ));
    let nan_value = FnPotential::new(|_: &[f64; 2], g: &mut [f64; 2]| {
        *g = [0.0; 2];
        f64::NAN
    });
    assert!(matches!(
        lbfgs.minimize(&nan_value, &mut x, PolishSettings::new(10)),
        Err(Error::NotFinite { name: "U(x)", .. })
    ));
    let mut chains: Vec<Chain<f64, 2>> = (0..3).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Gaussian::new([0.0; 2], 1.0).unwrap(),
    )
    .build(&mut chains)
    .unwrap();
    assert!(matches!(
        opt.polish(3, &mut lbfgs, PolishSettings::new(10)),
        Err(Error::Index {
            name: "chain",
            index: 3,
            len: 3
        })
    ));
    assert_eq!(
        opt.polish(3, &mut lbfgs, PolishSettings::new(10))
            .unwrap_err()
            .to_string(),
        "`chain` must be between 0 and 2, got 3"
    );
}

/// A probe goes on to the path's last wall where the path is straight:
/// on a slope `x_0 + 0.1 x_1 + 0.01 x_2` from the centre of `[-1, 1]^3`,
/// the first probe reaches the wall in `x_0` (cut short, straight), and in
/// `[-4, 4]^3` it stays inside (linear); either way the next probe goes to
/// the corner, where the path ends. Start, two probes and the end: 3
/// evaluations, the corner exactly (doubling along the walls took 34 on
/// the 2-D slope `x_0 + 0.01 x_1` in `[-1, 1]^2`; to the next wall only, 4
/// in `[-1, 1]^3`).
#[test]
fn a_slope_reaches_its_corner_in_two_probes() {
    for side in [1.0, 4.0] {
        let calls = std::cell::Cell::new(0u64);
        let slope = FnPotential::new(|x: &[f64; 3], g: &mut [f64; 3]| {
            calls.set(calls.get() + 1);
            *g = [1.0, 0.1, 0.01];
            x[0] + 0.1 * x[1] + 0.01 * x[2]
        });
        let mut lbfgs: Lbfgs<f64, 3, 5> = Lbfgs::new();
        let mut x = [0.0; 3];
        let cube = Interval::new(-side, side).unwrap();
        let done = lbfgs
            .minimize_in(&slope, &cube, &mut x, PolishSettings::new(100))
            .unwrap();
        assert_eq!(x, [-side; 3], "{done:?}");
        assert_eq!(done.evaluations, 3, "side {side}: {done:?}");
        assert_eq!(calls.get(), 3);
    }
}

/// Beyond the path's last wall every step of a line search is the same
/// point, the corner the path ends at: a zoom whose bracket ends there
/// searches up to that corner. And a step too short to move any
/// coordinate ends the search. On Styblinski–Tang in `[-5, 5]^2` (steep
/// walls near the corners, whose values are above the minima inside)
/// from 400 starts on a grid, no evaluation repeats the one before it
/// (without the first rule, a zoom that reached a corner probed it up to
/// four times in a row; without the second, a converged search probed its
/// own point until the zoom gave up, 35 times).
#[test]
fn a_zoom_never_probes_the_corner_twice() {
    let points = std::cell::RefCell::new(Vec::new());
    let st = FnPotential::new(|x: &[f64; 2], g: &mut [f64; 2]| {
        points.borrow_mut().push(*x);
        hrla::StyblinskiTang.value_and_gradient(x, g)
    });
    let square = Interval::new(-5.0, 5.0).unwrap();
    let mut lbfgs: Lbfgs<f64, 2, 5> = Lbfgs::new();
    let mut corners = 0;
    for i in 0..20 {
        for j in 0..20 {
            points.borrow_mut().clear();
            let mut x = [-4.75 + 0.5 * i as f64, -4.75 + 0.5 * j as f64];
            lbfgs
                .minimize_in(&st, &square, &mut x, PolishSettings::new(200))
                .unwrap();
            let points = points.borrow();
            for pair in points.windows(2) {
                assert_ne!(pair[0], pair[1], "from grid point ({i}, {j})");
            }
            corners += points
                .iter()
                .filter(|p| p.iter().all(|v| v.abs() == 5.0))
                .count();
        }
    }
    // The corners are reached: the rule is exercised.
    assert!(corners > 10, "{corners}");
}
