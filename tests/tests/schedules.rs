//! The built-in annealing schedules' values: `Linear` and `Geometric` hit
//! their endpoints exactly and interpolate as documented (increasing and
//! decreasing, f64 and f32, the paper's annealing), `Constant` and
//! `FnSchedule` return what they were given.
//!
//! The sampler runs at whatever `a_k` the schedule returns, so an endpoint
//! off by a rounding or an interpolation off by one step changes every run
//! that anneals; the schedules are checked here on their own, the
//! optimiser's use of them in `optimizer.rs`.

use hrla::{Constant, FnSchedule, Geometric, Linear, Schedule};

#[test]
fn linear_schedule_values() {
    let s = Linear::new(1.0f64, 3.0, 4).unwrap();
    let got: Vec<f64> = (0..8).map(|k| s.inverse_temperature(k)).collect();
    assert_eq!(got, [1.0, 1.5, 2.0, 2.5, 3.0, 3.0, 3.0, 3.0]);
    assert_eq!(s.inverse_temperature(u64::MAX), 3.0);
    // Decreasing (either order is allowed).
    let s = Linear::new(4.0f64, 2.0, 4).unwrap();
    let got: Vec<f64> = (0..6).map(|k| s.inverse_temperature(k)).collect();
    assert_eq!(got, [4.0, 3.5, 3.0, 2.5, 2.0, 2.0]);
    // The paper's annealing, a_low = 0.1 to a_high = 4 over K = 14000.
    let s = Linear::new(0.1f64, 4.0, 14_000).unwrap();
    assert_eq!(s.inverse_temperature(0), 0.1);
    for k in [1u64, 7, 3500, 7000, 13_999] {
        let want = 0.1 + 3.9 * k as f64 / 14_000.0;
        let got = s.inverse_temperature(k);
        assert!((got - want).abs() <= 2.0 * f64::EPSILON * want, "k = {k}");
    }
    assert!((s.inverse_temperature(7000) - 2.05).abs() < 1e-15);
    assert_eq!(s.inverse_temperature(14_000), 4.0);
    assert_eq!(s.inverse_temperature(1_000_000), 4.0);
    // f32.
    let s = Linear::new(0.5f32, 4.5, 8).unwrap();
    let got: Vec<f32> = (0..10).map(|k| s.inverse_temperature(k)).collect();
    assert_eq!(got, [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 4.5]);
}

#[test]
fn geometric_schedule_values() {
    let s = Geometric::new(1.0f64, 16.0, 4).unwrap();
    assert_eq!(s.inverse_temperature(0), 1.0);
    for k in 1..4u64 {
        let want = (1u64 << k) as f64;
        let got = s.inverse_temperature(k);
        assert!(
            (got - want).abs() <= 4.0 * f64::EPSILON * want,
            "k = {k}: {got}"
        );
    }
    assert_eq!(s.inverse_temperature(4), 16.0);
    assert_eq!(s.inverse_temperature(u64::MAX), 16.0);
    // The paper's range: a_{K/2} is the geometric mean, and the values rise.
    let s = Geometric::new(0.1f64, 40.0, 14_000).unwrap();
    assert_eq!(s.inverse_temperature(0), 0.1);
    assert!((s.inverse_temperature(7000) - 2.0).abs() < 1e-13);
    assert_eq!(s.inverse_temperature(14_000), 40.0);
    let mut prev = 0.0;
    for k in (0..=14_000).step_by(100) {
        let a = s.inverse_temperature(k);
        assert!(a > prev && a <= 40.0);
        prev = a;
    }
    // Decreasing.
    let s = Geometric::new(8.0f32, 0.5, 4).unwrap();
    assert_eq!(s.inverse_temperature(0), 8.0);
    assert!((s.inverse_temperature(2) - 2.0).abs() < 1e-6);
    assert_eq!(s.inverse_temperature(4), 0.5);
}

#[test]
fn constant_and_fn_schedules() {
    let s = Constant::new(2.5f64).unwrap();
    assert_eq!(s.inverse_temperature(0), 2.5);
    assert_eq!(s.inverse_temperature(u64::MAX), 2.5);
    let s = FnSchedule(|k: u64| 1.0 + k as f64);
    assert_eq!(Schedule::<f64>::inverse_temperature(&s, 41), 42.0);
}
