//! Hostile numbers for the bad-input tests (`bad_sampler_params`,
//! `bad_schedules_and_starts`, `wild_optimizer`), and the checks of the
//! error contract they share.
//!
//! Values are drawn from a mix of special values (±0, ±1, NaN, ±inf, the
//! smallest subnormal, `MIN_POSITIVE`, 1e300, `f32::MAX`, `f64::MAX`, ...),
//! arbitrary bit patterns (`any::<f64>()`) and log-uniform magnitudes from
//! 1e-320 to 1e308 of either sign: arbitrary bits alone almost never hit the
//! edges where arithmetic breaks (0, subnormals, the overflow thresholds),
//! and special values alone never reach the magnitudes in between.
//!
//! The contract: a constructor returns a typed error or a valid object and
//! never panics; where one bad parameter determines the error, it is exactly
//! `NotPositive`/`NotFinite` with that parameter's name and value; a valid
//! parameter outside the range the kernel's accuracy is tested for (`alpha
//! h` in `[1e-8, 50]`, `a` in `[1e-6, 1e6]`) is exactly `OutOfRange` with
//! its name, value and range.

use std::fmt::Debug;
use std::panic::{AssertUnwindSafe, catch_unwind};

use hrla::{Error, Float};
use proptest::prelude::*;

/// The proptest seed of the bad-input tests (see [`crate::prop::config`]).
pub const SEED: u64 = 0xbad_1e57;

const SPECIAL_F64: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.01,
    4.0,
    10.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    5e-324,
    -5e-324,
    1e-310,
    f64::MIN_POSITIVE,
    f64::EPSILON,
    1e-154,
    1e154,
    1e300,
    -1e300,
    f64::MAX,
    -f64::MAX,
    f32::MAX as f64,
    f32::MIN_POSITIVE as f64,
    1e-45,
];

const SPECIAL_F32: &[f32] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.01,
    4.0,
    10.0,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    1e-45,
    -1e-45,
    1e-40,
    f32::MIN_POSITIVE,
    f32::EPSILON,
    1e-19,
    1e19,
    1e30,
    -1e30,
    f32::MAX,
    -f32::MAX,
];

/// `±10^e`, e uniform in [lo, hi].
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..hi, any::<bool>()).prop_map(|(e, neg)| {
        let v = 10f64.powf(e);
        if neg { -v } else { v }
    })
}

/// Any `f64`, weighted towards the values where arithmetic breaks.
pub fn wild64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => prop::sample::select(SPECIAL_F64),
        2 => any::<f64>(),
        4 => log_uniform(-320.0, 308.0),
    ]
}

/// Mostly sensible positive values, sometimes wild: so that constructions
/// succeed often enough to exercise `step` and `run`.
pub fn mostly_sane64() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => (-3.0f64..2.0).prop_map(|e| 10f64.powf(e)),
        1 => wild64(),
    ]
}

/// Any `f32`, weighted towards the values where arithmetic breaks.
pub fn wild32() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => prop::sample::select(SPECIAL_F32),
        2 => any::<f32>(),
        4 => log_uniform(-45.0, 38.5).prop_map(|v| v as f32),
    ]
}

/// [`mostly_sane64`] in `f32`.
pub fn mostly_sane32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => (-3.0f64..2.0).prop_map(|e| 10f64.powf(e) as f32),
        1 => wild32(),
    ]
}

/// Step counts of a schedule: 0 (refused), small, and the extremes.
pub fn steps_strategy() -> impl Strategy<Value = u64> {
    prop_oneof![Just(0u64), 1..20u64, Just(u64::MAX), any::<u64>()]
}

/// Finite and > 0: what `NotPositive` parameters must be.
pub fn valid<F: Float>(v: F) -> bool {
    v.is_finite() && v > F::ZERO
}

/// Equal bit patterns, or both NaN.
pub fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// `Error` equality that treats NaN values as equal.
pub fn same_error(a: &Error, b: &Error) -> bool {
    match (*a, *b) {
        (Error::NotPositive { name: n, value: v }, Error::NotPositive { name: m, value: w })
        | (Error::Negative { name: n, value: v }, Error::Negative { name: m, value: w })
        | (Error::NotFinite { name: n, value: v }, Error::NotFinite { name: m, value: w }) => {
            n == m && same(v, w)
        }
        _ => a == b,
    }
}

/// `got` is exactly the error `want` (NaN values match NaN).
pub fn expect_error<T: Debug>(got: Result<T, Error>, want: Error) -> Result<(), TestCaseError> {
    match got {
        Err(e) if same_error(&e, &want) => Ok(()),
        other => Err(TestCaseError::fail(format!(
            "expected {want:?}, got {other:?}"
        ))),
    }
}

/// Runs `f`, turning a panic into a test failure that names `what`.
pub fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|e| {
        let msg = e
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| e.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        TestCaseError::fail(format!("{what} panicked: {msg}"))
    })
}

/// The range of `alpha h` that `Hrla::new` and `Ula::new` accept.
pub const ALPHA_H: (f64, f64) = (1e-8, 50.0);

/// The range of inverse temperatures that every sampler's `at` accepts.
pub const INVERSE_TEMPERATURE: (f64, f64) = (1e-6, 1e6);

/// A value checked against a range after the parameters it derives from
/// were found valid one by one: `(name, value, (min, max))`.
pub type Ranged = (&'static str, f64, (f64, f64));

/// The `OutOfRange` error a ranged value gives, if it lies outside.
pub fn out_of_range((name, value, (min, max)): Ranged) -> Option<Error> {
    (!(value >= min && value <= max)).then_some(Error::OutOfRange {
        name,
        value,
        min,
        max,
    })
}

/// [`check_outcome`] with a range check between the parameters and the
/// derived coefficients: when every early parameter is fine and `range`
/// lies outside its bounds, the error is exactly its `OutOfRange` (the
/// late parameters and the coefficients come after it).
pub fn check_outcome_in_range<T: Debug>(
    got: &Result<T, Error>,
    early: &[(&'static str, f64, bool)],
    range: Option<Ranged>,
    degenerate_ok: bool,
) -> Result<(), TestCaseError> {
    let early_ok = early.iter().all(|p| p.2);
    if let (true, Some(want)) = (early_ok, range.and_then(out_of_range)) {
        prop_assert!(
            matches!(got, Err(e) if *e == want),
            "expected {:?}, got {:?}",
            want,
            got
        );
        return Ok(());
    }
    check_outcome(got, early, &[], degenerate_ok)
}

/// The outcome of a constructor with parameters `(name, value, must_be)`
/// checked in some order, where `must_be` says whether the parameter is
/// fine on its own (`NotPositive` or `NotFinite` otherwise), and `late`
/// lists the parameters checked only after the derived coefficients (their
/// error may be masked by `DegenerateCoefficients`):
///
/// - some early parameter bad: `Err(NotPositive/NotFinite)` naming one of
///   the bad ones with its value (exactly that one if it is the only one);
/// - only late parameters bad: that error, or `DegenerateCoefficients`;
/// - all fine: `Ok`, or `DegenerateCoefficients` if `degenerate_ok`.
pub fn check_outcome<T: Debug>(
    got: &Result<T, Error>,
    early: &[(&'static str, f64, bool)],
    late: &[(&'static str, f64, bool)],
    degenerate_ok: bool,
) -> Result<(), TestCaseError> {
    let bad_early: Vec<_> = early.iter().filter(|p| !p.2).collect();
    let bad_late: Vec<_> = late.iter().filter(|p| !p.2).collect();
    let names = |e: &Error, bad: &[&(&'static str, f64, bool)]| match *e {
        Error::NotPositive { name, value }
        | Error::Negative { name, value }
        | Error::NotFinite { name, value } => {
            bad.iter().any(|&&(n, v, _)| n == name && same(v, value))
        }
        _ => false,
    };
    match got {
        Ok(_) => {
            prop_assert!(
                bad_early.is_empty() && bad_late.is_empty(),
                "accepted bad input"
            );
        }
        Err(e) if !bad_early.is_empty() => {
            prop_assert!(
                names(e, &bad_early),
                "{:?} does not name a bad {:?}",
                e,
                bad_early
            );
        }
        Err(e) if !bad_late.is_empty() => {
            prop_assert!(
                names(e, &bad_late) || *e == Error::DegenerateCoefficients,
                "{:?} for bad {:?}",
                e,
                bad_late
            );
        }
        Err(e) => {
            prop_assert!(
                degenerate_ok && *e == Error::DegenerateCoefficients,
                "valid parameters refused: {:?}",
                e
            );
        }
    }
    Ok(())
}
