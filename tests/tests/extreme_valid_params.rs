//! Valid but extreme parameters at which the textbook formulas overflow or
//! give NaN: the in-between values of the annealing schedules, an optimiser
//! under such a schedule (whose values now lie outside the range the
//! samplers accept: a typed `OutOfRange`, never `inf`), the widest
//! schedules inside that range, and a quadratic with a subnormal stiffness.
//!
//! Every parameter here passes validation, so the caller has been promised
//! a working object; the kernel keeps that promise by evaluating the
//! formulas in an order that cannot overflow (`k/K` before the product, the
//! logarithms instead of the ratio, `(k r) r` instead of `k |r|^2`). These
//! tests hold it to that for the parameters where the direct order fails.

use hrla::{
    Builder, Chain, Error, Float, Geometric, Hrla, Linear, Point, Potential, Quadratic, Schedule,
};

/// The schedules promise never to produce a value the sampler refuses
/// ("the built-in schedules validate their parameters so that they never
/// produce one"), and mathematically `a_k` lies between `a_low` and
/// `a_high`. The direct formulas overflow for valid parameters:
///
/// - `(a_high - a_low) * k / K` overflows in the product for
///   `(a_high - a_low) k > MAX`, e.g. `Linear::new(1.0, 1e308, 10)` would
///   give `a_2 = inf` (f32: `Linear::new(1.0, f32::MAX, 10)`, or
///   `Linear::new(1.0f32, 1e35, 100_000)` from `a_3403` on);
/// - `a_low * (a_high / a_low)^(k / K)` overflows in the ratio when
///   `a_high / a_low > MAX`, e.g. `Geometric::new(1e-200, 1e200, 10)` would
///   give `a_8 = inf` (f32: `Geometric::new(1e-20f32, 1e20, 100)` would give
///   `a_97 = inf`).
///
/// An optimiser using such a schedule would then fail with
/// `NotPositive { name: "a", value: inf }` in the middle of the run.
#[test]
fn built_in_schedules_stay_in_range() {
    fn check<F: Float, S: Schedule<F>>(
        s: &S,
        lo: F,
        hi: F,
        steps: u64,
        what: &str,
    ) -> Option<String> {
        let (min, max) = if lo < hi { (lo, hi) } else { (hi, lo) };
        let mut bad = Vec::new();
        for k in 0..=steps {
            let a = s.inverse_temperature(k);
            // One part in 1e5 of slack for rounding.
            let slack = F::from_f64(1e-5);
            if !(a.is_finite() && a > F::ZERO && a >= min - min * slack && a <= max + max * slack) {
                bad.push((k, a));
            }
        }
        let first = bad.first()?;
        Some(format!(
            "{what}: a_k out of [{:e}, {:e}] at {} iterates, first a_{} = {}",
            min.to_f64(),
            max.to_f64(),
            bad.len(),
            first.0,
            first.1
        ))
    }
    let failures: Vec<String> = [
        check(
            &Linear::new(1.0, 1e308, 10).unwrap(),
            1.0,
            1e308,
            10,
            "Linear f64",
        ),
        check(
            &Linear::new(1.0f32, f32::MAX, 10).unwrap(),
            1.0,
            f32::MAX,
            10,
            "Linear f32",
        ),
        check(
            &Linear::new(1.0f32, 1e35, 100_000).unwrap(),
            1.0,
            1e35,
            100_000,
            "Linear f32 1e35",
        ),
        check(
            &Geometric::new(1e-200, 1e200, 10).unwrap(),
            1e-200,
            1e200,
            10,
            "Geometric f64",
        ),
        check(
            &Geometric::new(1e-20f32, 1e20, 100).unwrap(),
            1e-20,
            1e20,
            100,
            "Geometric f32",
        ),
    ]
    .into_iter()
    .flatten()
    .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A flat potential: every chain is a pure noise process, whatever `a`.
#[derive(Debug)]
struct Flat;

impl Potential<f64, 2> for Flat {
    fn value_and_gradient(&self, _: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        *g = [0.0; 2];
        0.0
    }
}

/// The same seen from the optimiser: a valid annealing schedule whose direct
/// formula reaches `a = inf` at k = 2 must not stop the run with
/// `NotPositive { name: "a", value: inf }`. Its values from `a_1 = 1e307`
/// on are now outside the range `[1e-6, 1e6]` the samplers accept (the
/// run used to go on at them): the step that would use `a_1` fails with
/// exactly `OutOfRange` for that finite value, and changes nothing.
#[test]
fn huge_but_valid_linear_schedule_is_out_of_range() {
    let sampler = Hrla::paper(0.01f64).unwrap();
    let schedule = Linear::new(1.0, 1e308, 10).unwrap();
    let a1 = schedule.inverse_temperature(1);
    assert!(a1.is_finite() && a1 > 1e306, "a_1 = {a1}");
    let start = Point::new([0.5f64, 0.5]).unwrap();
    let mut opt = Builder::new(Flat, sampler, schedule, start)
        .build(vec![Chain::new(); 2])
        .unwrap();
    // a_0 = 1 is in range: the first step runs.
    assert_eq!(opt.step().map(|_| ()), Ok(()));
    let before = opt.chains().to_vec();
    let want = Error::OutOfRange {
        name: "a",
        value: a1,
        min: 1e-6,
        max: 1e6,
    };
    assert_eq!(opt.step(), Err(want));
    assert_eq!(opt.iteration(), 1);
    assert_eq!(&opt.chains()[..], &before[..]);
    assert_eq!(opt.run(), Err(want));
}

/// The widest linear and geometric schedules whose values all lie in the
/// accepted range, `a` from `1e-6` to `1e6`, run their whole length (the
/// interpolation never steps outside the ends by rounding).
#[test]
fn widest_accepted_schedules_run() {
    let sampler = Hrla::paper(0.01f64).unwrap();
    for (low, high) in [(1e-6, 1e6), (1e6, 1e-6)] {
        let linear = Linear::new(low, high, 1000).unwrap();
        let geometric = Geometric::new(low, high, 1000).unwrap();
        let start = Point::new([0.5f64, 0.5]).unwrap();
        let mut opt = Builder::new(Flat, sampler, linear, start)
            .build(vec![Chain::new(); 2])
            .unwrap();
        let report = opt.run().unwrap();
        assert_eq!(report.iterations, 1000);
        let mut opt = Builder::new(Flat, sampler, geometric, start)
            .build(vec![Chain::new(); 2])
            .unwrap();
        let report = opt.run().unwrap();
        assert_eq!(report.iterations, 1000);
    }
}

/// `Quadratic` with the smallest subnormal stiffness at a finite point far
/// out: computed as `(0.5 k) |x - m|^2`, `0.5 k` underflows to 0 and
/// `|x - m|^2` overflows to inf, so the value would be `0 * inf = NaN`,
/// where the true value, 0.5 * 5e-324 * (3e200)^2 = 2.2e77, is finite. An
/// optimiser would treat the NaN as a divergence, so this is benign, but a
/// potential should not return NaN at a finite point.
#[test]
fn quadratic_with_smallest_stiffness_is_not_nan() {
    let q = Quadratic::new(5e-324, [0.0f64; 2]).unwrap();
    let v = q.value(&[3e200, 0.0]);
    assert!(!v.is_nan(), "U = {v}");
}
