//! Hostile parameters for the samplers: `Hrla::new`, `Ula::new`, `Ola::new`
//! and the kernel at an inverse temperature, `Sampler::at`, with values
//! from `hrla_tests::hostile`.
//!
//! A sampler is built from parameters a caller may compute at run time (a
//! user's input), and its kernel from an annealing schedule's `a`, so a bad
//! value must come back as a typed error naming it, never as a panic or a
//! kernel that later produces NaN. The contract checked:
//!
//! - every constructor and `at` returns a typed error or a valid sampler or
//!   kernel, never panics; where one bad parameter determines the error, it
//!   is exactly `NotPositive` with that parameter's name and value; the
//!   parameters `b`, `alpha`, `beta`, `h` are checked by `new`, and `a`
//!   only by `at`, so a bad `a` is reported only once the others are fine;
//! - valid parameters outside the range the step's accuracy is tested for
//!   are refused with exactly `OutOfRange`: `alpha h` outside `[1e-8, 50]`
//!   by `Hrla::new` and `Ula::new` (after the parameters, before the
//!   coefficients), `a` outside `[1e-6, 1e6]` by every `at` (values such
//!   as `h = 1e300` or `a = 5e-324`, which the kernel used to accept or
//!   refuse only when a coefficient overflowed);
//! - a valid kernel gives finite means and finite, non-negative variances
//!   (and a positive semi-definite covariance) for finite states of moderate
//!   size (|x|, |y|, |g| <= 1: far out, `x + c g` may overflow legitimately),
//!   is at exactly the `a` asked for, and runs; `at` leaves the sampler
//!   unchanged, so the kernel at an `a` is the same whatever was asked
//!   before;
//! - `exact_errors` writes out the errors of every constructor of the crate
//!   (samplers, schedules, starts, quadratic) that one parameter determines.
//!
//! Every proptest runs a few hundred cases from a fixed seed.

use std::fmt::Debug;

use hrla::{
    Builder, Chain, Constant, Error, Float, Gaussian, Geometric, Hrla, HrlaParams, Kernel, Linear,
    Ola, OlaParams, Point, Quadratic, Rastrigin, Sampler, Stop, Termination, Ula, UlaParams,
};
use hrla_tests::hostile::{
    ALPHA_H, INVERSE_TEMPERATURE, Ranged, SEED, check_outcome_in_range, mostly_sane32,
    mostly_sane64, no_panic, out_of_range, same_error, valid, wild32, wild64,
};
use hrla_tests::prop::config;
use proptest::prelude::*;

/// A valid kernel: finite means, finite non-negative variances and a
/// positive semi-definite covariance from moderate finite states.
fn check_moments<F: Float>(kernel: &impl Kernel<F>) -> Result<(), TestCaseError> {
    let vals = [-1.0, -0.5, 0.0, 0.25, 1.0].map(F::from_f64);
    // Positive semi-definiteness is checked when both variances are normal
    // numbers of F: below that, an entry may round to 0 while the others do
    // not. (For f32 ULA at h = 8e-19, var_x = (2/3) sy2 h^3 = 4e-55 rounds to
    // 0 beside cov_xy = 7e-37 and var_y = 2e-18, correctly rounded each.)
    let tiny = if F::from_f64(1e-300) == F::ZERO {
        f64::from(f32::MIN_POSITIVE)
    } else {
        f64::MIN_POSITIVE
    };
    for &x in &vals {
        for &y in &vals {
            for &g in &vals {
                let m = kernel.moments(x, y, g);
                prop_assert!(m.mean_x.is_finite() && m.mean_y.is_finite(), "{:?}", m);
                prop_assert!(m.var_x.is_finite() && m.var_x >= F::ZERO, "{:?}", m);
                prop_assert!(m.var_y.is_finite() && m.var_y >= F::ZERO, "{:?}", m);
                prop_assert!(m.cov_xy.is_finite(), "{:?}", m);
                let (vx, vy, c) = (m.var_x.to_f64(), m.var_y.to_f64(), m.cov_xy.to_f64());
                prop_assert!(
                    vx < tiny || vy < tiny || c.abs() <= vx.sqrt() * vy.sqrt() * (1.0 + 1e-5),
                    "covariance not PSD: {:?}",
                    m
                );
            }
        }
    }
    Ok(())
}

/// `sampler.at(a)`: an invalid `a` is `NotPositive { "a" }`, a valid one
/// outside `[1e-6, 1e6]` is `OutOfRange { "a" }` (otherwise the
/// coefficients may still give `DegenerateCoefficients`), an accepted one
/// gives a kernel at exactly `a`; the kernel, if any.
fn kernel_at<F: Float, S: Sampler<F> + Debug>(
    sampler: &S,
    a: F,
) -> Result<Option<S::Kernel>, TestCaseError>
where
    S::Kernel: Debug,
{
    let got = no_panic("at", || sampler.at(a))?;
    check_outcome_in_range(
        &got,
        &[("a", a.to_f64(), valid(a))],
        Some(("a", a.to_f64(), INVERSE_TEMPERATURE)),
        true,
    )?;
    if let Ok(k) = &got {
        prop_assert_eq!(k.inverse_temperature().to_bits_u64(), a.to_bits_u64());
    }
    Ok(got.ok())
}

/// The kernel at a second temperature `a2` is checked as the first, and
/// asking for it changes nothing: the sampler is as it was, and its kernel
/// at `a` is still `kernel` (it depends on nothing but the parameters and
/// `a`).
fn check_other_temperature<F: Float, S: Sampler<F> + Clone + PartialEq + Debug>(
    sampler: &S,
    kernel: &S::Kernel,
    a: F,
    a2: F,
) -> Result<(), TestCaseError>
where
    S::Kernel: PartialEq + Debug,
{
    let before = sampler.clone();
    if let Some(k2) = kernel_at(sampler, a2)? {
        check_moments(&k2)?;
    }
    prop_assert_eq!(sampler, &before);
    let again = sampler.at(a);
    prop_assert_eq!(again.as_ref(), Ok(kernel));
    Ok(())
}

/// A short run of a valid sampler on 2-D Rastrigin at an accepted constant
/// temperature `a` never panics and keeps a finite best: it spends its
/// step budget with at least one live chain, or ends with `AllDiverged`
/// (Rastrigin is bounded below, so never with `UnboundedBelow`), after
/// which a step is `AllDiverged` again.
fn check_runs<F: Float, S: Sampler<F> + Clone + Debug>(
    sampler: &S,
    a: F,
) -> Result<(), TestCaseError> {
    let start = Point::new([F::from_f64(0.5), F::from_f64(-0.25)]).unwrap();
    let mut opt = Builder::new(Rastrigin, sampler.clone(), a, start)
        .seed(1)
        .stop(Stop::new().steps(20))
        .build(vec![Chain::<F, 2>::new(); 3])
        .unwrap();
    let result = no_panic("run", || opt.run())?;
    prop_assert!(opt.best().value.is_finite());
    // U(0.5, -0.25) = (0.25 + 2) + (0.0625 + 1) = 3.3125: the best never exceeds the start.
    prop_assert!(opt.best().value <= F::from_f64(3.3125 + 1e-6));
    prop_assert!(opt.iteration() <= 20);
    match result {
        Ok(report) => {
            prop_assert_eq!(report.termination, Termination::Steps);
            prop_assert_eq!(report.iterations, 20);
            prop_assert!(report.diverged_chains < 3);
            prop_assert_eq!(report.value.to_bits_u64(), opt.best().value.to_bits_u64());
            let after = no_panic("step", || opt.step().map(|_| ()))?;
            if opt.diverged_chains() < 3 {
                prop_assert_eq!(after, Ok(()));
            } else {
                prop_assert_eq!(after, Err(Error::AllDiverged { chains: 3 }));
            }
        }
        Err(e) => {
            prop_assert_eq!(e, Error::AllDiverged { chains: 3 });
            prop_assert_eq!(opt.diverged_chains(), 3);
            let after = no_panic("step", || opt.step())?;
            prop_assert_eq!(after, Err(Error::AllDiverged { chains: 3 }));
        }
    }
    prop_assert!(opt.best().value.is_finite());
    Ok(())
}

/// Constructs a sampler with `new` and checks the outcome against the
/// parameters `early` and the derived `range` (see
/// `check_outcome_in_range`): the sampler, if accepted.
fn construct<S: Debug>(
    what: &str,
    new: impl FnOnce() -> Result<S, Error>,
    early: &[(&'static str, f64, bool)],
    range: Option<Ranged>,
) -> Result<Option<S>, TestCaseError> {
    let got = no_panic(what, new)?;
    check_outcome_in_range(&got, early, range, true)?;
    Ok(got.ok())
}

/// `alpha h` as the samplers compute it, in `F`, with its range.
fn alpha_h<F: Float>(alpha: F, h: F) -> Option<Ranged> {
    Some(("alpha h", (alpha * h).to_f64(), ALPHA_H))
}

/// What every accepted sampler promises at a temperature `a`: a kernel
/// refused cleanly or accepted with sound moments; then another
/// temperature `a2` that changes nothing, and a run.
fn check_accepted<F: Float, S: Sampler<F> + Clone + PartialEq + Debug>(
    sampler: &S,
    a: F,
    a2: F,
) -> Result<(), TestCaseError>
where
    S::Kernel: PartialEq + Debug,
{
    let Some(kernel) = kernel_at(sampler, a)? else {
        return Ok(());
    };
    check_moments(&kernel)?;
    check_other_temperature(sampler, &kernel, a, a2)?;
    check_runs(sampler, a)
}

fn check_hrla<F: Float>(p: HrlaParams<F>, a: F, a2: F) -> Result<(), TestCaseError> {
    let early = [
        ("beta", p.beta.to_f64(), valid(p.beta)),
        ("b", p.b.to_f64(), valid(p.b)),
        ("alpha", p.alpha.to_f64(), valid(p.alpha)),
        ("h", p.h.to_f64(), valid(p.h)),
    ];
    if let Some(s) = construct("Hrla::new", || Hrla::new(p), &early, alpha_h(p.alpha, p.h))? {
        prop_assert_eq!(s.params(), p);
        check_accepted(&s, a, a2)?;
    }
    Ok(())
}

fn check_ula<F: Float>(p: UlaParams<F>, a: F, a2: F) -> Result<(), TestCaseError> {
    let early = [
        ("b", p.b.to_f64(), valid(p.b)),
        ("alpha", p.alpha.to_f64(), valid(p.alpha)),
        ("h", p.h.to_f64(), valid(p.h)),
    ];
    if let Some(s) = construct("Ula::new", || Ula::new(p), &early, alpha_h(p.alpha, p.h))? {
        prop_assert_eq!(s.params(), p);
        check_accepted(&s, a, a2)?;
    }
    Ok(())
}

fn check_ola<F: Float>(p: OlaParams<F>, a: F, a2: F) -> Result<(), TestCaseError> {
    let early = [
        ("alpha", p.alpha.to_f64(), valid(p.alpha)),
        ("h", p.h.to_f64(), valid(p.h)),
    ];
    // OLA has no `alpha h` range (its step is Euler's, with no
    // coefficient to lose accuracy); only its `a` is ranged.
    if let Some(s) = construct("Ola::new", || Ola::new(p), &early, None)? {
        prop_assert_eq!(s.params(), p);
        check_accepted(&s, a, a2)?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(300, SEED))]

    /// One wild parameter, the others the paper's (`a = 4`): a bad one is
    /// named exactly, e.g. `h = NaN` gives `NotPositive { name: "h", value:
    /// NaN }` from `new`, and `a = NaN` the same for "a" from `at`; a valid
    /// one that takes `alpha h` or `a` out of its range is exactly
    /// `OutOfRange` (`h = 1e300`: `OutOfRange { "alpha h", 1e300, 1e-8, 50 }`).
    #[test]
    fn hrla_one_bad_parameter(which in 0..5usize, v in wild64(), a2 in wild64()) {
        let mut p = HrlaParams { b: 10.0, alpha: 1.0, beta: 1.0, h: 0.01 };
        let mut a = 4.0;
        let name = ["a", "b", "alpha", "beta", "h"][which];
        *[&mut a, &mut p.b, &mut p.alpha, &mut p.beta, &mut p.h][which] = v;
        let sampler = Hrla::new(p);
        if name == "a" {
            prop_assert!(sampler.is_ok());
        }
        let got = sampler.and_then(|s| s.at(a));
        let range = match name {
            "alpha" | "h" => out_of_range(("alpha h", p.alpha * p.h, ALPHA_H)),
            "a" => out_of_range(("a", a, INVERSE_TEMPERATURE)),
            _ => None,
        };
        if let (true, Some(want)) = (valid(v), range) {
            prop_assert_eq!(got, Err(want));
        } else if valid(v) {
            prop_assert!(got.is_ok() || got == Err(Error::DegenerateCoefficients), "{:?}", got);
        } else {
            let e = got.unwrap_err();
            prop_assert!(same_error(&e, &Error::NotPositive { name, value: v }), "{:?}", e);
        }
        check_hrla(p, a, a2)?;
    }

    #[test]
    fn hrla_all_wild_f64(
        a in mostly_sane64(), b in mostly_sane64(), alpha in mostly_sane64(),
        beta in mostly_sane64(), h in mostly_sane64(), a2 in wild64(),
    ) {
        check_hrla(HrlaParams { b, alpha, beta, h }, a, a2)?;
    }

    #[test]
    fn hrla_all_wild_f32(
        a in mostly_sane32(), b in mostly_sane32(), alpha in mostly_sane32(),
        beta in mostly_sane32(), h in mostly_sane32(), a2 in wild32(),
    ) {
        check_hrla(HrlaParams { b, alpha, beta, h }, a, a2)?;
    }

    #[test]
    fn ula_all_wild(
        a in mostly_sane64(), b in mostly_sane64(), alpha in mostly_sane64(),
        h in mostly_sane64(), a2 in wild64(),
        a32 in mostly_sane32(), b32 in mostly_sane32(), alpha32 in mostly_sane32(),
        h32 in mostly_sane32(), a232 in wild32(),
    ) {
        check_ula(UlaParams { b, alpha, h }, a, a2)?;
        check_ula(UlaParams { b: b32, alpha: alpha32, h: h32 }, a32, a232)?;
    }

    #[test]
    fn ola_all_wild(
        a in mostly_sane64(), alpha in mostly_sane64(), h in mostly_sane64(), a2 in wild64(),
        a32 in mostly_sane32(), alpha32 in mostly_sane32(), h32 in mostly_sane32(),
        a232 in wild32(),
    ) {
        check_ola(OlaParams { alpha, h }, a, a2)?;
        check_ola(OlaParams { alpha: alpha32, h: h32 }, a32, a232)?;
    }
}

/// Errors fully determined by one parameter, written out.
#[test]
fn exact_errors() {
    let paper = HrlaParams {
        b: 10.0,
        alpha: 1.0,
        beta: 1.0,
        h: 0.01,
    };
    assert_eq!(paper, HrlaParams::paper(0.01));
    let e = Hrla::new(HrlaParams {
        h: f64::NAN,
        ..paper
    })
    .unwrap_err();
    assert!(matches!(e, Error::NotPositive { name: "h", value } if value.is_nan()));
    assert_eq!(
        Hrla::new(HrlaParams { h: 0.0, ..paper }),
        Err(Error::NotPositive {
            name: "h",
            value: 0.0
        })
    );
    assert_eq!(
        Hrla::new(paper).unwrap().at(-1.0),
        Err(Error::NotPositive {
            name: "a",
            value: -1.0
        })
    );
    assert_eq!(
        Hrla::new(HrlaParams {
            b: f64::INFINITY,
            ..paper
        }),
        Err(Error::NotPositive {
            name: "b",
            value: f64::INFINITY
        })
    );
    // beta = 0 is ULA, not HRLA.
    assert_eq!(
        Hrla::new(HrlaParams { beta: 0.0, ..paper }),
        Err(Error::NotPositive {
            name: "beta",
            value: 0.0
        })
    );
    assert_eq!(
        Hrla::new(HrlaParams {
            alpha: -f64::MAX,
            ..paper
        }),
        Err(Error::NotPositive {
            name: "alpha",
            value: -f64::MAX
        })
    );
    // alpha h = 1e300 is far outside [1e-8, 50] (it used to be refused
    // only because h^2 overflowed).
    assert_eq!(
        Hrla::new(HrlaParams { h: 1e300, ..paper }),
        Err(Error::OutOfRange {
            name: "alpha h",
            value: 1e300,
            min: 1e-8,
            max: 50.0
        })
    );
    // With alpha h = 1e-8 in range, h = 1e292 still makes h^3 overflow.
    assert_eq!(
        Hrla::new(HrlaParams {
            alpha: 1e-300,
            h: 1e292,
            ..paper
        }),
        Err(Error::DegenerateCoefficients)
    );
    // a = 5e-324 is outside [1e-6, 1e6] (it used to be refused only
    // because sx2 = beta / a overflowed).
    assert_eq!(
        Hrla::new(paper).unwrap().at(5e-324),
        Err(Error::OutOfRange {
            name: "a",
            value: 5e-324,
            min: 1e-6,
            max: 1e6
        })
    );
    // An `a` in range can still overflow a coefficient: with h = 1e152
    // (alpha h = 1), a h^2 phi2(1) / b overflows at a = 1e6 but not at 1.
    let steep = Hrla::new(HrlaParams {
        b: 1.0,
        alpha: 1e-152,
        beta: 1.0,
        h: 1e152,
    })
    .unwrap();
    assert!(steep.at(1.0).is_ok());
    assert_eq!(steep.at(1e6), Err(Error::DegenerateCoefficients));
    // The parameters are checked by `new`, before any `a`: a bad h with a
    // bad a is the error of h.
    assert_eq!(
        Hrla::new(HrlaParams { h: -1.0, ..paper }).and_then(|s| s.at(-1.0)),
        Err(Error::NotPositive {
            name: "h",
            value: -1.0
        })
    );
    // ULA has no sx2, and used to accept the same tiny a: it is now out of
    // range too, as is anything beyond 1e6 or below 1e-6.
    let ula = Ula::new(UlaParams::paper(0.01)).unwrap();
    for a in [5e-324, 1e-7, 1.000001e6, 1e300] {
        assert_eq!(
            ula.at(a),
            Err(Error::OutOfRange {
                name: "a",
                value: a,
                min: 1e-6,
                max: 1e6
            })
        );
    }
    // The ends are accepted.
    assert!(ula.at(1e-6).is_ok() && ula.at(1e6).is_ok());
    // alpha h = 1e-30 and 1e8: refused; 1e-8 and 50: accepted.
    for h in [1e-30, 1e8] {
        assert_eq!(
            Ula::new(UlaParams::paper(h)),
            Err(Error::OutOfRange {
                name: "alpha h",
                value: h,
                min: 1e-8,
                max: 50.0
            })
        );
    }
    assert!(Ula::paper(1e-8).is_ok() && Ula::paper(50.0).is_ok());
    assert_eq!(
        Ula::new(UlaParams::paper(-0.0)),
        Err(Error::NotPositive {
            name: "h",
            value: -0.0
        })
    );
    assert_eq!(
        Ola::new(OlaParams::paper(0.01f32))
            .unwrap()
            .at(f32::INFINITY),
        Err(Error::NotPositive {
            name: "a",
            value: f64::INFINITY
        })
    );
    // A subnormal a, which used to be refused only because OLA's noise
    // sqrt(2 alpha h / a) overflowed, is out of range.
    assert_eq!(
        Ola::new(OlaParams::paper(1.0f32)).unwrap().at(1e-45),
        Err(Error::OutOfRange {
            name: "a",
            value: f64::from(1e-45f32),
            min: 1e-6,
            max: 1e6
        })
    );
    // OLA's noise sqrt(2 alpha h / a) still overflows for a huge alpha h
    // (OLA has no alpha h range) at an a in range.
    assert_eq!(
        Ola::new(OlaParams::paper(3e38f32)).unwrap().at(1.0),
        Err(Error::DegenerateCoefficients)
    );
    assert_eq!(
        Ola::paper(f32::NAN).map(|_| ()).unwrap_err().to_string(),
        "`h` must be finite and > 0, got NaN"
    );
    assert_eq!(
        Constant::new(0.0f64),
        Err(Error::NotPositive {
            name: "a",
            value: 0.0
        })
    );
    assert_eq!(
        Linear::new(1.0, 2.0f64, 0),
        Err(Error::Zero { name: "steps" })
    );
    assert_eq!(
        Geometric::new(1.0, -2.0f64, 5),
        Err(Error::NotPositive {
            name: "a_high",
            value: -2.0
        })
    );
    assert_eq!(
        Linear::new(f64::NEG_INFINITY, 2.0f64, 5),
        Err(Error::NotPositive {
            name: "a_low",
            value: f64::NEG_INFINITY
        })
    );
    assert_eq!(
        Gaussian::new([0.0, f64::INFINITY], 1.0),
        Err(Error::NotFinite {
            name: "mean",
            value: f64::INFINITY
        })
    );
    assert_eq!(
        Gaussian::new([0.0f32; 2], -1.0),
        Err(Error::Negative {
            name: "std_dev",
            value: -1.0
        })
    );
    // std_dev = 0 is allowed (documented): every chain at the mean.
    assert!(Gaussian::new([0.0; 2], 0.0f64).is_ok());
    assert_eq!(
        Point::new([1.0, f64::NEG_INFINITY, f64::NAN]),
        Err(Error::NotFinite {
            name: "initial point",
            value: f64::NEG_INFINITY
        })
    );
    assert_eq!(
        Quadratic::new(0.0, [1.0f64; 2]),
        Err(Error::NotPositive {
            name: "stiffness",
            value: 0.0
        })
    );
    assert_eq!(
        Quadratic::new(1.0, [1.0f64, -f64::INFINITY]),
        Err(Error::NotFinite {
            name: "centre",
            value: -f64::INFINITY
        })
    );
}
