//! Forty-six kinds of bad input, across the builder, the stopping rules,
//! the samplers, the schedules, the starts and the potentials, each drawn
//! at random within its kind (values from `hrla_tests::hostile`, counts,
//! chain indices, seeds) and each required to give exactly its typed error,
//! never a panic (checked with `catch_unwind`) or an abort (which would
//! kill this test binary).
//!
//! The kinds (46):
//!
//! Samplers (15)
//!  1. `Hrla::new`: `h` not finite and > 0 -> `NotPositive { "h" }`
//!  2. `Hrla::new`: `b` not finite and > 0 -> `NotPositive { "b" }`
//!  3. `Hrla::new`: `alpha` not finite and > 0 -> `NotPositive { "alpha" }`
//!  4. `Hrla::new`: `beta` not finite and > 0 (0 included: that is ULA)
//!     -> `NotPositive { "beta" }`
//!  5. `Hrla::new`: `alpha h` in (0, 1e-8) -> `OutOfRange { "alpha h" }`
//!  6. `Hrla::new`: `alpha h` finite above 50 -> `OutOfRange { "alpha h" }`
//!  7. `Ula::new`: `h` not finite and > 0 -> `NotPositive { "h" }`
//!  8. `Ula::new`: `alpha h` outside [1e-8, 50] -> `OutOfRange { "alpha h" }`
//!  9. `Ola::new`: `h` not finite and > 0 -> `NotPositive { "h" }`
//! 10. `Ola::new`: `alpha` not finite and > 0 -> `NotPositive { "alpha" }`
//! 11. `Sampler::at` (HRLA, ULA, OLA, f64 or f32): `a` not finite and > 0
//!     -> `NotPositive { "a" }`
//! 12. `Sampler::at`: `a` in (0, 1e-6) -> `OutOfRange { "a" }`
//! 13. `Sampler::at`: `a` finite above 1e6 -> `OutOfRange { "a" }`
//! 14. `AnySampler::paper`: any kind, `h` not finite and > 0
//!     -> `NotPositive { "h" }`
//! 15. `SamplerKind` from an unknown name -> `Unknown { "sampler" }`
//!
//! Schedules (7)
//! 16. `Constant::new`: `a` not finite and > 0 -> `NotPositive { "a" }`
//! 17. `Linear::new`: `a_low` bad -> `NotPositive { "a_low" }`
//! 18. `Linear::new`: `a_high` bad -> `NotPositive { "a_high" }`
//! 19. `Linear::new`: `K = 0` -> `Zero { "steps" }`
//! 20. `Geometric::new`: `a_low` or `a_high` bad -> `NotPositive`, naming it
//! 21. `Geometric::new`: `K = 0` -> `Zero { "steps" }`
//! 22. a schedule whose value at a random step is refused (not positive,
//!     or out of range): that step's error, every earlier step fine
//!
//! Starts (4)
//! 23. `Gaussian::new`: a non-finite mean coordinate -> `NotFinite { "mean" }`
//! 24. `Gaussian::new`: `std_dev` negative or not finite
//!     -> `Negative { "std_dev" }`
//! 25. `Point::new`: a non-finite coordinate -> `NotFinite { "initial point" }`
//! 26. `FromFn` giving a non-finite point to a random chain
//!     -> `NonFiniteStart { chain, "position" }`
//!
//! Potentials (7)
//! 27. `Quadratic::new`: stiffness bad -> `NotPositive { "stiffness" }`
//! 28. `Quadratic::new`: a non-finite centre -> `NotFinite { "centre" }`
//! 29. a potential whose value is not finite at a random chain's start
//!     -> `NonFiniteStart { chain, "value" }` after `START_TRIES` redraws
//!     (the start gives the same point), `UnboundedBelow` for `-inf`
//! 30. the same for its gradient -> `NonFiniteStart { chain, "gradient" }`
//! 31. `check_gradient` at a non-finite point -> `NotFinite { "x" }`
//! 32. `check_gradient` where `U` is not finite -> `NotFinite { "U(x)" }`
//! 33. `check_gradient` where the gradient is not finite
//!     -> `NotFinite { "gradient" }`
//!
//! Builder and stopping rules (11)
//! 34. an empty storage (`N = 0`) -> `Zero { "chains" }`
//! 35. `D = 0` -> `Zero { "dimension D" }`
//! 36. stride 0 -> `Zero { "stride" }`
//! 37. `Stop::steps(0)` -> `Zero { "step budget" }`
//! 38. `Stop::evaluations(0)` -> `Zero { "evaluation budget" }`
//! 39. an evaluation budget in [1, N) -> `Budget { budget, chains }`
//! 40. `Stop::target` not finite -> `NotFinite { "target" }`
//! 41. a stall window of 0 -> `Zero { "stall window" }`
//! 42. a stall tolerance negative or not finite
//!     -> `Negative { "stall tolerance" }`
//! 43. a step budget below the schedule's length
//!     -> `ScheduleLongerThanRun { schedule, steps }`
//! 44. `run()` without any stopping rule -> `NoStoppingRule`, no step
//!
//! Runs (2)
//! 45. every chain crossing into a region where `U` and `∇U` are NaN
//!     -> `AllDiverged { chains }` from `run`, then from every `step`
//! 46. a potential unbounded below (`U = -exp(x)`)
//!     -> `UnboundedBelow { chain, value }`, `value < -sqrt(MAX)`
//!
//! (`optimizer.rs` and `api_problems.rs` pin the runs' errors in detail;
//! `wild_optimizer.rs` mixes all of these at random.)

use hrla::{
    AnySampler, Builder, Chain, Constant, Error, FnPotential, FnSchedule, FromFn, Gaussian,
    Geometric, Hrla, HrlaParams, Linear, Ola, OlaParams, Point, Quadratic, Rastrigin, Sampler,
    SamplerKind, Start, Stop, Ula, UlaParams, check_gradient,
};
use hrla_tests::fixtures::Cliff;
use hrla_tests::hostile::{SEED, expect_error, no_panic, valid, wild64};
use hrla_tests::prop::config;
use proptest::prelude::*;
use rand_xoshiro::rand_core::Rng;

/// The number of kinds listed above.
const KINDS: usize = 46;

/// The random material of one case: a kind, hostile floats, a fraction, a
/// count and a seed; each kind projects them into its bad domain.
#[derive(Clone, Copy, Debug)]
struct Case {
    kind: usize,
    v: f64,
    w: f64,
    t: f64,
    n: usize,
    seed: u64,
}

fn case() -> impl Strategy<Value = Case> {
    (
        0..KINDS,
        wild64(),
        wild64(),
        0.001f64..1.0,
        1..6usize,
        any::<u64>(),
    )
        .prop_map(|(kind, v, w, t, n, seed)| Case {
            kind,
            v,
            w,
            t,
            n,
            seed,
        })
}

/// `v` if it is not finite and > 0, else a non-positive value from it.
fn not_positive(v: f64) -> f64 {
    if valid(v) { -v } else { v }
}

/// A non-finite value chosen by `v`: NaN, +inf or -inf.
fn not_finite(v: f64) -> f64 {
    [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][(v.to_bits() % 3) as usize]
}

/// A value in `(0, min)`, from the fraction `t` (log-uniform down to
/// `min * 1e-300`).
fn below(min: f64, t: f64) -> f64 {
    let v = min * 10f64.powf(-300.0 * t);
    if v > 0.0 && v < min { v } else { min / 2.0 }
}

/// A finite value above `max`, from the fraction `t`.
fn above(max: f64, t: f64) -> f64 {
    max * 10f64.powf(300.0 * t)
}

fn not_positive_err(name: &'static str, value: f64) -> Error {
    Error::NotPositive { name, value }
}

fn out_of_range(name: &'static str, value: f64, (min, max): (f64, f64)) -> Error {
    Error::OutOfRange {
        name,
        value,
        min,
        max,
    }
}

const ALPHA_H: (f64, f64) = (1e-8, 50.0);
const A: (f64, f64) = (1e-6, 1e6);

/// A start of `n` chains at `[c, 0]` for chain `c`.
fn indexed_start() -> FromFn<impl FnMut(usize, &mut dyn Rng, &mut [f64]) + Copy> {
    FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| x.copy_from_slice(&[c as f64, 0.0]))
}

/// `n` empty chains.
fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    vec![Chain::new(); n]
}

/// Runs the case and checks that it gives exactly its error.
fn check(c: Case) -> Result<(), TestCaseError> {
    let Case {
        kind,
        v,
        w,
        t,
        n,
        seed,
    } = c;
    let paper = HrlaParams::paper(0.01);
    let hrla = Hrla::new(paper).unwrap();
    // Build results are compared through `map(drop)`: an optimiser is not
    // `Debug` for every potential.
    let builder = || Builder::new(Rastrigin, hrla, 4.0, Point::new([1.0; 2]).unwrap()).seed(seed);
    match kind {
        0 => {
            let h = not_positive(v);
            let got = no_panic("Hrla::new", || Hrla::new(HrlaParams { h, ..paper }))?;
            expect_error(got, not_positive_err("h", h))
        }
        1 => {
            let b = not_positive(v);
            let got = no_panic("Hrla::new", || Hrla::new(HrlaParams { b, ..paper }))?;
            expect_error(got, not_positive_err("b", b))
        }
        2 => {
            let alpha = not_positive(v);
            let got = no_panic("Hrla::new", || Hrla::new(HrlaParams { alpha, ..paper }))?;
            expect_error(got, not_positive_err("alpha", alpha))
        }
        3 => {
            let beta = if t < 0.2 { 0.0 } else { not_positive(v) };
            let got = no_panic("Hrla::new", || Hrla::new(HrlaParams { beta, ..paper }))?;
            expect_error(got, not_positive_err("beta", beta))
        }
        4 => {
            let h = below(ALPHA_H.0, t);
            let got = no_panic("Hrla::new", || {
                Hrla::new(HrlaParams {
                    alpha: 1.0,
                    h,
                    ..paper
                })
            })?;
            expect_error(got, out_of_range("alpha h", h, ALPHA_H))
        }
        5 => {
            let h = above(ALPHA_H.1, t);
            let got = no_panic("Hrla::new", || Hrla::new(HrlaParams { h, ..paper }))?;
            expect_error(got, out_of_range("alpha h", h, ALPHA_H))
        }
        6 => {
            let h = not_positive(v);
            let got = no_panic("Ula::new", || Ula::new(UlaParams::paper(h)))?;
            expect_error(got, not_positive_err("h", h))
        }
        7 => {
            let h = if v.to_bits() % 2 == 0 {
                below(ALPHA_H.0, t)
            } else {
                above(ALPHA_H.1, t)
            };
            let got = no_panic("Ula::new", || Ula::new(UlaParams::paper(h)))?;
            expect_error(got, out_of_range("alpha h", h, ALPHA_H))
        }
        8 => {
            let h = not_positive(v);
            let got = no_panic("Ola::new", || Ola::new(OlaParams::paper(h)))?;
            expect_error(got, not_positive_err("h", h))
        }
        9 => {
            let alpha = not_positive(v);
            let got = no_panic("Ola::new", || Ola::new(OlaParams { alpha, h: 0.01 }))?;
            expect_error(got, not_positive_err("alpha", alpha))
        }
        10..=12 => {
            // The value in its bad domain, and whether an f32 value is in
            // the same domain (for the same check in f32).
            let bad: fn(f64) -> bool = match kind {
                10 => |a| !valid(a),
                11 => |a| a > 0.0 && a < A.0,
                _ => |a| a.is_finite() && a > A.1,
            };
            let a = match kind {
                10 => not_positive(v),
                11 => below(A.0, t),
                _ => above(A.1, t),
            };
            let want = |a: f64| {
                if kind == 10 {
                    not_positive_err("a", a)
                } else {
                    out_of_range("a", a, A)
                }
            };
            let which = SamplerKind::ALL[n % 3];
            let sampler = AnySampler::paper(which, 0.01).unwrap();
            expect_error(no_panic("at", || sampler.at(a))?.map(drop), want(a))?;
            let a32 = a as f32;
            if bad(f64::from(a32)) {
                let sampler = AnySampler::paper(which, 0.01f32).unwrap();
                let got = no_panic("at f32", || sampler.at(a32))?.map(drop);
                expect_error(got, want(f64::from(a32)))?;
            }
            Ok(())
        }
        13 => {
            let h = not_positive(v);
            let kind = SamplerKind::ALL[n % 3];
            let got = no_panic("AnySampler::paper", || AnySampler::paper(kind, h))?;
            expect_error(got, not_positive_err("h", h))
        }
        14 => {
            // A name that is none of the samplers' (in any case).
            let name = format!("{}-{:x}", ["hrla", "ULA", "", "ola "][n % 4], seed);
            let got = no_panic("parse", || name.parse::<SamplerKind>())?;
            expect_error(
                got,
                Error::Unknown {
                    what: "sampler",
                    expected: " hrla ula ola",
                },
            )
        }
        15 => {
            let a = not_positive(v);
            expect_error(
                no_panic("Constant::new", || Constant::new(a))?,
                not_positive_err("a", a),
            )
        }
        16 => {
            let lo = not_positive(v);
            let got = no_panic("Linear::new", || Linear::new(lo, 4.0, n as u64))?;
            expect_error(got, not_positive_err("a_low", lo))
        }
        17 => {
            let hi = not_positive(v);
            let got = no_panic("Linear::new", || Linear::new(0.5, hi, n as u64))?;
            expect_error(got, not_positive_err("a_high", hi))
        }
        18 => {
            let got = no_panic("Linear::new", || Linear::new(0.5 + t, 4.0, 0))?;
            expect_error(got, Error::Zero { name: "steps" })
        }
        19 => {
            let bad = not_positive(v);
            let (lo, hi, name) = if n % 2 == 0 {
                (bad, 4.0, "a_low")
            } else {
                (0.5, bad, "a_high")
            };
            let got = no_panic("Geometric::new", || Geometric::new(lo, hi, n as u64))?;
            expect_error(got, not_positive_err(name, bad))
        }
        20 => {
            let got = no_panic("Geometric::new", || Geometric::new(0.5, 4.0 + t, 0))?;
            expect_error(got, Error::Zero { name: "steps" })
        }
        21 => {
            // Fine until step k0, then a refused value.
            let k0 = 1 + (seed % 20);
            let (bad, want) = match n % 3 {
                0 => (not_positive(v), not_positive_err("a", not_positive(v))),
                1 => (below(A.0, t), out_of_range("a", below(A.0, t), A)),
                _ => (above(A.1, t), out_of_range("a", above(A.1, t), A)),
            };
            let schedule = FnSchedule(move |k: u64| if k < k0 { 2.0 } else { bad });
            let mut opt = Builder::new(Rastrigin, hrla, schedule, Point::new([1.0; 2]).unwrap())
                .seed(seed)
                .stop(Stop::new().steps(100))
                .build(chains::<2>(n))
                .unwrap();
            for _ in 0..k0 {
                prop_assert_eq!(no_panic("step", || opt.step().map(|_| ()))?, Ok(()));
            }
            expect_error(no_panic("step", || opt.step().map(|_| ()))?, want)?;
            prop_assert_eq!(opt.iteration(), k0);
            expect_error(no_panic("run", || opt.run())?, want)
        }
        22 => {
            let mean = [1.0, not_finite(v), w];
            let got = no_panic("Gaussian::new", || Gaussian::new(mean, 1.0))?;
            expect_error(
                got,
                Error::NotFinite {
                    name: "mean",
                    value: mean[1],
                },
            )
        }
        23 => {
            let s = if v.is_finite() {
                -v.abs() - f64::MIN_POSITIVE
            } else {
                v
            };
            let got = no_panic("Gaussian::new", || Gaussian::new([0.0; 2], s))?;
            expect_error(
                got,
                Error::Negative {
                    name: "std_dev",
                    value: s,
                },
            )
        }
        24 => {
            let x = [t, not_finite(v), not_finite(w)];
            let got = no_panic("Point::new", || Point::new(x))?;
            expect_error(
                got,
                Error::NotFinite {
                    name: "initial point",
                    value: x[1],
                },
            )
        }
        25 => {
            let bad = seed as usize % n;
            let value = not_finite(v);
            let start = FromFn(move |c: usize, _: &mut dyn Rng, x: &mut [f64]| {
                x.copy_from_slice(&{ if c == bad { [0.0, value] } else { [0.5, 0.5] } })
            });
            let got = no_panic("build", || {
                Builder::new(Rastrigin, hrla, 4.0, start)
                    .seed(seed)
                    .build(chains::<2>(n))
                    .map(drop)
            })?;
            expect_error(
                got,
                Error::NonFiniteStart {
                    chain: bad,
                    what: "position",
                    tries: hrla::START_TRIES,
                },
            )
        }
        26 => {
            let k = not_positive(v);
            let got = no_panic("Quadratic::new", || Quadratic::new(k, [0.0; 2]))?;
            expect_error(got, not_positive_err("stiffness", k))
        }
        27 => {
            let centre = [not_finite(v), 0.0];
            let got = no_panic("Quadratic::new", || Quadratic::new(1.0 + t, centre))?;
            expect_error(
                got,
                Error::NotFinite {
                    name: "centre",
                    value: centre[0],
                },
            )
        }
        28 | 29 => {
            let bad = seed as usize % n;
            let value = not_finite(v);
            let in_value = kind == 28;
            let potential = FnPotential::new(move |x: &[f64; 2], g: &mut [f64; 2]| {
                let here = x[0] == bad as f64;
                *g = [if here && !in_value { value } else { x[0] }, x[1]];
                if here && in_value { value } else { x[0] * x[0] }
            });
            let got = no_panic("build", || {
                Builder::new(potential, hrla, 4.0, indexed_start())
                    .seed(seed)
                    .build(chains::<2>(n))
                    .map(drop)
            })?;
            let what = if in_value { "value" } else { "gradient" };
            // `-inf` is no infeasible point but a potential unbounded below.
            let want = if in_value && value == f64::NEG_INFINITY {
                Error::UnboundedBelow { chain: bad, value }
            } else {
                Error::NonFiniteStart {
                    chain: bad,
                    what,
                    tries: hrla::START_TRIES,
                }
            };
            expect_error(got, want)
        }
        30 => {
            let x = [t, not_finite(v)];
            let got = no_panic("check_gradient", || check_gradient(&Rastrigin, &x))?;
            expect_error(
                got,
                Error::NotFinite {
                    name: "x",
                    value: x[1],
                },
            )
        }
        31 | 32 => {
            let value = not_finite(v);
            let in_value = kind == 31;
            let potential = FnPotential::new(move |x: &[f64; 2], g: &mut [f64; 2]| {
                *g = [if in_value { 1.0 } else { value }, 0.0];
                if in_value { value } else { x[0] }
            });
            let got = no_panic("check_gradient", || check_gradient(&potential, &[t, w]))?;
            if !w.is_finite() {
                // A non-finite point is named first.
                return expect_error(
                    got,
                    Error::NotFinite {
                        name: "x",
                        value: w,
                    },
                );
            }
            let name = if in_value { "U(x)" } else { "gradient" };
            expect_error(got, Error::NotFinite { name, value })
        }
        33 => {
            let got = no_panic("build", || builder().build(chains::<2>(0)).map(drop))?;
            expect_error(got, Error::Zero { name: "chains" })
        }
        34 => {
            let got = no_panic("build", || {
                Builder::new(Rastrigin, hrla, 4.0, Point::new([]).unwrap())
                    .build(vec![Chain::<f64, 0>::new(); n])
                    .map(drop)
            })?;
            expect_error(
                got,
                Error::Zero {
                    name: "dimension D",
                },
            )
        }
        35 => {
            let got = no_panic("build", || {
                builder().stride(0).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(got, Error::Zero { name: "stride" })
        }
        36 => {
            let stop = Stop::new().steps(0).evaluations(seed | (1 << 40));
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(
                got,
                Error::Zero {
                    name: "step budget",
                },
            )
        }
        37 => {
            let stop = Stop::new().evaluations(0).target(t);
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(
                got,
                Error::Zero {
                    name: "evaluation budget",
                },
            )
        }
        38 => {
            let n = n + 1;
            let budget = 1 + seed % (n as u64 - 1);
            let stop = Stop::new().evaluations(budget);
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(got, Error::Budget { budget, chains: n })
        }
        39 => {
            let target = not_finite(v);
            let stop = Stop::new().target(target).steps(10);
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(
                got,
                Error::NotFinite {
                    name: "target",
                    value: target,
                },
            )
        }
        40 => {
            let stop = Stop::new().stall(0, t);
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(
                got,
                Error::Zero {
                    name: "stall window",
                },
            )
        }
        41 => {
            let tolerance = if v.is_finite() {
                -v.abs() - f64::MIN_POSITIVE
            } else {
                v
            };
            let stop = Stop::new().stall(1 + seed % 100, tolerance);
            let got = no_panic("build", || {
                builder().stop(stop).build(chains::<2>(n)).map(drop)
            })?;
            expect_error(
                got,
                Error::Negative {
                    name: "stall tolerance",
                    value: tolerance,
                },
            )
        }
        42 => {
            let length = 2 + seed % 1000;
            let steps = 1 + (t * (length - 1) as f64) as u64 % (length - 1);
            let schedule = Linear::new(0.5, 4.0, length).unwrap();
            let got = no_panic("build", || {
                Builder::new(Rastrigin, hrla, schedule, Point::new([1.0; 2]).unwrap())
                    .stop(Stop::new().steps(steps))
                    .build(chains::<2>(n))
                    .map(drop)
            })?;
            expect_error(
                got,
                Error::ScheduleLongerThanRun {
                    schedule: length,
                    steps,
                },
            )
        }
        43 => {
            let mut opt = builder().build(chains::<2>(n)).unwrap();
            let got = no_panic("run", || opt.run())?;
            expect_error(got, Error::NoStoppingRule)?;
            prop_assert_eq!(opt.iteration(), 0);
            prop_assert_eq!(opt.evaluations(), n as u64);
            Ok(())
        }
        44 => {
            // NaN beyond |x| = 6, an outward slope from 3 to 6: every chain
            // starts on the slope and leaves within a few dozen steps.
            let cliff = Cliff::NAN;
            let start = Gaussian::new([4.5], 0.5 * t).unwrap();
            let mut opt = Builder::new(cliff, hrla, 4.0, start)
                .seed(seed)
                .stop(Stop::new().steps(10_000))
                .build(vec![Chain::new(); n])
                .unwrap();
            let want = Error::AllDiverged { chains: n };
            expect_error(no_panic("run", || opt.run())?, want)?;
            prop_assert!(opt.iteration() < 10_000);
            let k = opt.iteration();
            expect_error(no_panic("step", || opt.step().map(|_| ()))?, want)?;
            prop_assert_eq!(opt.iteration(), k);
            Ok(())
        }
        45 => {
            let falling = FnPotential::new(|x: &[f64; 1], g: &mut [f64; 1]| {
                g[0] = -x[0].exp();
                -x[0].exp()
            });
            let start = Gaussian::new([2.0], t).unwrap();
            let mut opt = Builder::new(falling, hrla, 4.0, start)
                .seed(seed)
                .stop(Stop::new().steps(100_000))
                .build(vec![Chain::new(); n])
                .unwrap();
            match no_panic("run", || opt.run())? {
                Err(Error::UnboundedBelow { chain, value }) => {
                    prop_assert!(chain < n);
                    prop_assert!(value < -f64::MAX.sqrt(), "{}", value);
                    prop_assert_eq!(opt.chains()[chain].value().to_bits(), value.to_bits());
                    Ok(())
                }
                other => Err(TestCaseError::fail(format!(
                    "expected UnboundedBelow, got {other:?}"
                ))),
            }
        }
        _ => unreachable!("kind {kind}"),
    }
}

proptest! {
    #![proptest_config(config(30 * KINDS as u32, SEED))]

    #[test]
    fn every_bad_input_is_a_typed_error(c in case()) {
        check(c)?;
    }
}

/// Every kind, at least once, from fixed hostile values (so that no kind
/// depends on the proptest draw to be exercised).
#[test]
fn every_kind_is_checked() {
    let values = [f64::NAN, -1.0, 0.0, f64::INFINITY, 1e300, -5e-324];
    for kind in 0..KINDS {
        for (i, &v) in values.iter().enumerate() {
            let c = Case {
                kind,
                v,
                w: values[(i + 1) % values.len()],
                t: 0.37,
                n: 1 + i % 5,
                seed: 0x5eed + i as u64,
            };
            if let Err(e) = check(c) {
                panic!("kind {} ({c:?}): {e}", kind + 1);
            }
        }
    }
}

/// A start made for another dimension than the chains' is refused before
/// any point is drawn, on the const path as on the flat one: the start's
/// own dimension is checked against the chains', so a `Point` of 3
/// coordinates never fills chains of 5.
#[test]
fn a_start_of_another_dimension_is_refused() {
    fn build<const D: usize>(start: impl Start<f64>) -> Result<u64, Error> {
        Builder::new(Rastrigin, Hrla::paper(0.01).unwrap(), 4.0, start)
            .stop(Stop::new().steps(10))
            .build(chains::<D>(4))
            .map(|o| o.iteration())
    }
    let length = |expected, got| {
        Err(Error::Length {
            name: "start",
            expected,
            got,
        })
    };
    assert_eq!(build::<5>(Point::new([1.0; 3]).unwrap()), length(5, 3));
    assert_eq!(
        build::<2>(Gaussian::new([0.0; 7], 1.0).unwrap()),
        length(2, 7)
    );
}
