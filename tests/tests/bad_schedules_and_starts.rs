//! Hostile parameters for everything around a sampler: the schedules
//! (`Constant`, `Linear`, `Geometric`), the starts (`Gaussian`, `Point`) and
//! the `Quadratic` potential, with values from `hrla_tests::hostile`.
//!
//! These constructors take the same kind of run-time input as the samplers,
//! and an optimiser trusts what they build: a schedule's endpoints, a start's
//! points and a potential's centre must be what was asked for, and a bad
//! value must come back as a typed error that names it, never as a panic.
//! The checks follow each constructor's documented order of validation, so
//! that the error names the first bad parameter.

use hrla::{
    Constant, Error, Gaussian, Geometric, Linear, Point, Potential, Quadratic, Schedule, Start,
};
use hrla_tests::hostile::{
    SEED, check_outcome, expect_error, mostly_sane32, mostly_sane64, no_panic, steps_strategy,
    valid, wild32, wild64,
};
use hrla_tests::prop::config;
use proptest::prelude::*;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// The iterates at which a schedule is probed.
fn probe_ks(steps: u64) -> [u64; 7] {
    [
        0,
        1,
        steps / 2,
        steps.saturating_sub(1),
        steps,
        steps.saturating_add(1),
        u64::MAX,
    ]
}

proptest! {
    #![proptest_config(config(400, SEED))]

    #[test]
    fn constant_schedule(a in wild64(), a32 in wild32(), k in any::<u64>()) {
        let got = no_panic("Constant::new", || Constant::new(a))?;
        check_outcome(&got, &[("a", a, valid(a))], &[], false)?;
        if let Ok(s) = got {
            prop_assert_eq!(s.inverse_temperature(k).to_bits(), a.to_bits());
        }
        let got = Constant::new(a32);
        check_outcome(&got, &[("a", f64::from(a32), valid(a32))], &[], false)?;
    }

    /// Linear and geometric schedules: typed errors, and the documented
    /// endpoints `a_0 = a_low`, `a_k = a_high` for `k >= K`, exactly. (That
    /// the values in between stay in range is `built_in_schedules_stay_in_range`
    /// in `extreme_valid_params.rs`.)
    #[test]
    fn linear_and_geometric_schedules(
        lo in mostly_sane64(), hi in mostly_sane64(), steps in steps_strategy(),
        lo32 in mostly_sane32(), hi32 in mostly_sane32(),
    ) {
        let early = [("a_low", lo, valid(lo)), ("a_high", hi, valid(hi))];
        let count_ok = steps > 0;
        let expect_count = |got: &Result<(), Error>| -> Result<(), TestCaseError> {
            if valid(lo) && valid(hi) && !count_ok {
                prop_assert_eq!(
                    got.unwrap_err(),
                    Error::Zero { name: "steps" }
                );
            }
            Ok(())
        };
        let lin = no_panic("Linear::new", || Linear::new(lo, hi, steps))?;
        let geo = no_panic("Geometric::new", || Geometric::new(lo, hi, steps))?;
        for got in [lin.map(|_| ()), geo.map(|_| ())] {
            if count_ok || !(valid(lo) && valid(hi)) {
                check_outcome(&got, &early, &[], false)?;
            }
            expect_count(&got)?;
        }
        if let Ok(s) = lin {
            for k in probe_ks(steps) {
                no_panic("Linear::inverse_temperature", || s.inverse_temperature(k))?;
            }
            prop_assert_eq!(s.inverse_temperature(0).to_bits(), lo.to_bits());
            prop_assert_eq!(s.inverse_temperature(steps).to_bits(), hi.to_bits());
            prop_assert_eq!(s.inverse_temperature(u64::MAX).to_bits(), hi.to_bits());
        }
        if let Ok(s) = geo {
            for k in probe_ks(steps) {
                no_panic("Geometric::inverse_temperature", || s.inverse_temperature(k))?;
            }
            prop_assert_eq!(s.inverse_temperature(0).to_bits(), lo.to_bits());
            prop_assert_eq!(s.inverse_temperature(steps).to_bits(), hi.to_bits());
        }
        let lin32 = Linear::new(lo32, hi32, steps);
        let geo32 = Geometric::new(lo32, hi32, steps);
        if let (Ok(l), Ok(g)) = (lin32, geo32) {
            prop_assert_eq!(l.inverse_temperature(0), lo32);
            prop_assert_eq!(g.inverse_temperature(0), lo32);
            prop_assert_eq!(l.inverse_temperature(steps), hi32);
            prop_assert_eq!(g.inverse_temperature(steps), hi32);
        } else {
            prop_assert!(!(valid(lo32) && valid(hi32) && count_ok));
        }
    }

    #[test]
    fn starts_and_quadratic(
        m0 in wild64(), m1 in wild64(), s in wild64(), p2 in wild64(), k in wild64(),
        m32 in wild32(), s32 in wild32(),
    ) {
        let mean = [m0, m1];
        // Gaussian: the mean is checked first, then the standard deviation
        // (finite and >= 0).
        let got = no_panic("Gaussian::new", || Gaussian::new(mean, s))?;
        let std_ok = s.is_finite() && s >= 0.0;
        let first_bad_mean = mean.iter().copied().find(|v| !v.is_finite());
        match (first_bad_mean, std_ok) {
            (Some(v), _) => expect_error(got, Error::NotFinite { name: "mean", value: v })?,
            (None, false) => expect_error(got, Error::Negative { name: "std_dev", value: s })?,
            (None, true) => prop_assert!(got.is_ok()),
        }
        let got32 = Gaussian::new([m32; 3], s32);
        prop_assert_eq!(got32.is_ok(), m32.is_finite() && s32.is_finite() && s32 >= 0.0);

        // Point: the first non-finite coordinate is reported.
        let x = [m0, m1, p2];
        let got = no_panic("Point::new", || Point::new(x))?;
        match x.iter().copied().find(|v| !v.is_finite()) {
            Some(v) => expect_error(got, Error::NotFinite { name: "initial point", value: v })?,
            None => {
                let mut p = got.unwrap();
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(0);
                let mut drawn = [f64::NAN; 3];
                p.initial_point(3, &mut rng, &mut drawn);
                prop_assert_eq!(drawn.map(f64::to_bits), x.map(f64::to_bits));
            }
        }

        // Quadratic: stiffness > 0 first, then a finite centre.
        let got = no_panic("Quadratic::new", || Quadratic::new(k, mean))?;
        match (valid(k), first_bad_mean) {
            (false, _) => expect_error(got, Error::NotPositive { name: "stiffness", value: k })?,
            (true, Some(v)) => expect_error(got, Error::NotFinite { name: "centre", value: v })?,
            (true, None) => {
                let q = got.unwrap();
                // Any value and gradient, no panic; finite inputs give a
                // non-negative (possibly infinite) value, never NaN, for a
                // normal k (a subnormal one, where k/2 may underflow, has its
                // own test: `quadratic_with_smallest_stiffness_is_not_nan`).
                let mut g = [0.0; 2];
                let v = no_panic("Quadratic", || q.value_and_gradient(&[p2, m0], &mut g))?;
                if p2.is_finite() && k >= f64::MIN_POSITIVE {
                    prop_assert!(v >= 0.0, "U = {}", v);
                }
            }
        }
    }
}
