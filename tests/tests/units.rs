//! `Auto` does not depend on the units of the problem: `U` multiplied by
//! any `c` in `[1e-14, 1e14]`, or the box scaled by any `s` in
//! `[1e-10, 1e10]` with the potential re-expressed in the scaled
//! coordinates (`U_s(x) = U(x / s)` on `s·box`), gives the decisions of
//! the run in the problem's own units: the same rounds, the same
//! evaluations, and a solution whose `x / s`, `U / c`, step
//! `h c / s^2` and inverse temperature `a c` are the unscaled run's up to
//! rounding. Through the const-generic chains and the flat storage alike.

use std::ops::ControlFlow;

use hrla::{Auto, AutoProgress, Chain, FnPotential, Interval, Lbfgs, Problem};
use hrla_tests::fixtures::AutoArrays;

/// The factors on `U`.
const C: [f64; 5] = [1e-14, 1e-7, 1.0, 1e7, 1e14];
/// The factors on the box.
const S: [f64; 5] = [1e-10, 1e-5, 1.0, 1e5, 1e10];

/// A problem in its own units: `U` and its gradient at `z`, and the box.
#[derive(Clone, Copy)]
struct Base {
    u: fn(&[f64], &mut [f64]) -> f64,
    lo: f64,
    hi: f64,
    /// A point's representative among those `U`'s symmetries map it to:
    /// minima that `U` gives one value are told apart by rounding alone,
    /// so a run may hold any of them as its best.
    canonical: fn(&mut [f64]),
}

/// A problem without symmetries: every point its own representative.
fn asymmetric(_: &mut [f64]) {}

/// Rastrigin's representative: `U` is the same under any permutation of
/// the coordinates and any change of their signs.
fn sorted_magnitudes(z: &mut [f64]) {
    for zi in z.iter_mut() {
        *zi = zi.abs();
    }
    z.sort_by(f64::total_cmp);
}

/// The convex bowl `sum (z_i - 0.3)^2` in `[0, 1]^d`.
fn bowl(z: &[f64], g: &mut [f64]) -> f64 {
    let mut u = 0.0;
    for (gi, &zi) in g.iter_mut().zip(z) {
        *gi = 2.0 * (zi - 0.3);
        u += (zi - 0.3) * (zi - 0.3);
    }
    u
}

/// Rastrigin in the paper's form, in `[-5.12, 5.12]^d`.
fn rastrigin(z: &[f64], g: &mut [f64]) -> f64 {
    let tau = std::f64::consts::TAU;
    let mut u = z.len() as f64;
    for (gi, &zi) in g.iter_mut().zip(z) {
        u += zi * zi - (tau * zi).cos();
        *gi = 2.0 * zi + tau * (tau * zi).sin();
    }
    u
}

/// `c U(x / s)` and its gradient at `x`.
fn scaled(base: Base, c: f64, s: f64, x: &[f64], g: &mut [f64]) -> f64 {
    let z: Vec<f64> = x.iter().map(|&xi| xi / s).collect();
    let u = (base.u)(&z, g);
    for gi in g.iter_mut() {
        *gi *= c / s;
    }
    c * u
}

/// What a run decided, and where it ended, in the problem's own units.
#[derive(Debug)]
struct Run {
    rounds: u64,
    evaluations: u64,
    /// `x / s`, `U / c`, `h c / s^2`, `a c`.
    z: Vec<f64>,
    value: f64,
    step: f64,
    a: f64,
}

impl Run {
    fn new(s: hrla::Solution<f64, impl AsRef<[f64]>>, c: f64, scale: f64, budget: u64) -> Self {
        assert!(s.evaluations <= budget);
        Self {
            rounds: s.rounds,
            evaluations: s.evaluations,
            z: s.x.as_ref().iter().map(|&xi| xi / scale).collect(),
            value: s.value / c,
            step: s.step * c / (scale * scale),
            a: s.inverse_temperature * c,
        }
    }
}

/// Stops the run once `rounds` rounds are done (`u64::MAX`: never), where
/// the observer first sees them: before the final polish, whose length is
/// decided by rounding (it searches every direction until no step lowers
/// `U`, and at a minimum whose value is not 0 the steps that do lower it
/// are within its last bits: 5 to 76 evaluations for the same point of
/// 4-D Rastrigin in different units).
fn stop_after(rounds: u64) -> impl FnMut(&AutoProgress<'_, f64>) -> ControlFlow<()> {
    move |p| {
        if p.rounds >= rounds {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// `base` scaled by `(c, s)` through `Chain<f64, D>`s, over `budget`
/// evaluations, stopped after `rounds` rounds.
fn fixed<const D: usize>(base: Base, c: f64, s: f64, budget: u64, rounds: u64, seed: u64) -> Run {
    let p = FnPotential::new(move |x: &[f64; D], g: &mut [f64; D]| scaled(base, c, s, x, g));
    let domain = Interval::new(base.lo * s, base.hi * s).unwrap();
    let mut chains: Vec<Chain<f64, D>> = (0..4).map(|_| Chain::new()).collect();
    let mut lbfgs: Lbfgs<f64, D, 8> = Lbfgs::new();
    let found = Auto::default()
        .minimize_with(
            &Problem::new(&p, &domain, budget).seed(seed),
            (chains.as_mut_slice(), &mut lbfgs),
            stop_after(rounds),
        )
        .unwrap();
    Run::new(found, c, s, budget)
}

/// The same through the flat storage at dimension `d`.
fn flat(base: Base, d: usize, c: f64, s: f64, budget: u64, rounds: u64, seed: u64) -> Run {
    let p = FnPotential::slices(move |x: &[f64], g: &mut [f64]| scaled(base, c, s, x, g));
    let domain = Interval::new(base.lo * s, base.hi * s).unwrap();
    let (n, m) = (4, 8);
    let mut arrays = AutoArrays::<f64>::new(n, d, m);
    let mut storage = arrays.storage();
    let found = Auto::default()
        .minimize_with(
            &Problem::new(&p, &domain, budget).seed(seed),
            &mut storage,
            stop_after(rounds),
        )
        .unwrap();
    Run::new(found, c, s, budget)
}

/// The largest differences between `got` and `want`: of the point
/// (of its representative, relative to the box's width), of the value (relative to `max(1,
/// |want|)`: the problems' values are of order 1), and of the step and the
/// inverse temperature (relative to `want`'s).
fn gaps(got: &Run, want: &Run, base: Base) -> [f64; 3] {
    let width = base.hi - base.lo;
    let (mut g, mut w) = (got.z.clone(), want.z.clone());
    (base.canonical)(&mut g);
    (base.canonical)(&mut w);
    let point = g
        .iter()
        .zip(&w)
        .map(|(a, b)| (a - b).abs() / width)
        .fold(0.0, f64::max);
    let value = (got.value - want.value).abs() / want.value.abs().max(1.0);
    let settings = ((got.step - want.step) / want.step)
        .abs()
        .max(((got.a - want.a) / want.a).abs());
    [point, value, settings]
}

/// Every `(c, s)` of [`C`] and [`S`] over both stores, for each seed:
/// each run that `alike` finds unlike the unscaled one, or that `solved`
/// refuses, listed in the panic.
fn check<const D: usize>(
    base: Base,
    budget: u64,
    rounds: u64,
    seeds: std::ops::Range<u64>,
    alike: fn(&Run, &Run, [f64; 3]) -> bool,
    solved: fn(&Run) -> bool,
) {
    let mut failures = Vec::new();
    for seed in seeds {
        let want = fixed::<D>(base, 1.0, 1.0, budget, rounds, seed);
        for c in C {
            for s in S {
                for (store, got) in [
                    ("chains", fixed::<D>(base, c, s, budget, rounds, seed)),
                    ("flat", flat(base, D, c, s, budget, rounds, seed)),
                ] {
                    let gaps = gaps(&got, &want, base);
                    if !alike(&got, &want, gaps) || !solved(&got) {
                        failures.push(format!(
                            "c = {c:e}, s = {s:e}, seed {seed}, {store}: {got:?}"
                        ));
                    }
                }
            }
        }
        if !failures.is_empty() {
            failures.push(format!("unscaled, seed {seed}: {want:?}"));
        }
    }
    assert!(
        failures.is_empty(),
        "{} runs differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The same decisions (rounds, evaluations), the point within
/// [`POINT_TOL`] and the other numbers within [`TOL`] of the unscaled
/// run's.
fn same_decisions(got: &Run, want: &Run, gaps: [f64; 3]) -> bool {
    (got.rounds, got.evaluations) == (want.rounds, want.evaluations)
        && gaps[0] <= POINT_TOL
        && gaps[1..].iter().all(|&g| g <= TOL)
}

/// The same settings, measured before any round.
fn same_settings(_: &Run, _: &Run, gaps: [f64; 3]) -> bool {
    gaps[2] <= TOL
}

/// The tolerance. With the same decisions, the runs do the same
/// arithmetic on inputs that differ by their rounding (of `c U`, of
/// `x / s`, of the units measured on each), a few units in the last
/// place, and their results differ by that times the computation's
/// condition. The quenches' ends, points and values, are where L-BFGS
/// converged: a few units in the last place (measured: `2e-17` of the
/// box, `5e-16` of the value). The settings come from a difference of
/// gradients `1e-4` of the box apart, which loses about four digits:
/// `eps / 1e-4 = 2e-12` (measured: `4e-13`). `1e-10` bounds both.
const TOL: f64 = 1e-10;

/// The tolerance on a point a quench ended at, relative to the box's
/// width. A quench ends where the decrease its next step predicts is
/// below `64 eps max(ε, |U|)`, anywhere within `sqrt(2 · 64 eps |U| / L)`
/// of its minimum; two runs with the same decisions end at different
/// points of that ball, the last L-BFGS steps being taken from gradient
/// differences that have lost most of their digits. On 4-D Rastrigin in
/// its units (`L ≥ 2 + 4π^2`, `|U| ≤ 10` at the basins the first rounds
/// hold): `sqrt(2 · 64 · 2.2e-16 · 10 / 41.5) = 8.3e-8`, over the width
/// 10.24: `8e-9` (measured: `1.2e-10`). After the final polish (the
/// bowl's whole runs) the points agree far closer.
const POINT_TOL: f64 = 1e-8;

/// The convex bowl is run with the same decisions in any units, and ends
/// at its minimum to the float type's precision.
#[test]
fn the_bowl_is_run_alike_in_any_units() {
    let base = Base {
        u: bowl,
        lo: 0.0,
        hi: 1.0,
        canonical: asymmetric,
    };
    check::<2>(base, 5_000, u64::MAX, 0..2, same_decisions, |run| {
        run.z.iter().all(|&z| (z - 0.3).abs() < 1e-8) && run.value < 1e-16
    });
}

/// Rastrigin in 4-D, a rugged landscape of `11^4` basins, in any units:
/// its first two rounds make the same decisions (up to the final polish:
/// [`stop_after`]), and a whole run measures the
/// same settings and is solved. (A whole run's decisions differ: the
/// trajectories of the hot rungs, across the barriers with long steps,
/// multiply a difference in the last bits a hundredfold or more per
/// step, so that the proposals of the fifth round or so land in other
/// basins.)
#[test]
fn rastrigin_is_run_alike_in_any_units() {
    let base = Base {
        u: rastrigin,
        lo: -5.12,
        hi: 5.12,
        canonical: sorted_magnitudes,
    };
    check::<4>(base, 10_000, 2, 0..16, same_decisions, |_| true);
    check::<4>(base, 10_000, u64::MAX, 0..2, same_settings, |run| {
        run.value < 1e-12
    });
}
