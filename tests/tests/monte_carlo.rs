//! Monte Carlo check of one step: from a fixed state `(x, y, g)`, the
//! empirical law of `(x', y')` over 10^6 draws has the closed-form mean and
//! covariance that `moments()` reports, for HRLA, ULA and OLA in f32 and f64.
//!
//! `moments.rs` checks the closed-form moments themselves; this checks that
//! `step` really draws from them (the noise factor and the normals that
//! feed it), which no closed-form test can see.
//!
//! Every comparison is a z-score against the estimator's standard error,
//! and every test requires `|z| < 5`. With 5 statistics per HRLA or ULA
//! case and 2 per OLA case (whose velocity is checked exactly instead), 18
//! cases give 72 z-scores; a correct kernel fails with probability about
//! 72 · 5.7e-7 = 4e-5 per seed. The seeds are fixed, so the outcome is
//! deterministic. A 5-SE band at n = 10^6 resolves a relative error of
//! 5 · sqrt(2/n) = 0.7% in a variance and 5e-3 standard deviations in a
//! mean.
//!
//! Standard errors:
//! - mean: `sqrt(var / n)`;
//! - variance: `sqrt((m4 - var^2) / n)` with `m4` the sample's fourth
//!   central moment (no Gaussian assumption);
//! - covariance: `sqrt((var_x var_y + cov^2) / n)`, exact for Gaussian
//!   pairs, evaluated at the closed-form values.

use std::time::Instant;

use hrla::{Float, Hrla, HrlaParams, Kernel, Ola, OlaParams, Sampler, StepMoments, Ula, UlaParams};
use hrla_tests::stats::{Summary, covariance, se_covariance, z_score};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// Coordinates per step: each is an independent draw from the same state.
const D: usize = 8;
/// Steps per case: `D * STEPS = 10^6` draws.
const STEPS: usize = 125_000;
/// Rejection threshold in standard errors.
const Z_MAX: f64 = 5.0;

/// One parameter set: `(a, b, alpha, beta, h)` and the state `(x, y, g)`.
#[derive(Clone, Copy, Debug)]
struct Case {
    name: &'static str,
    a: f64,
    b: f64,
    alpha: f64,
    beta: f64,
    h: f64,
    x: f64,
    y: f64,
    g: f64,
}

impl Case {
    /// The state `(x, y, g)` in `F`.
    fn state<F: Float>(&self) -> (F, F, F) {
        (
            F::from_f64(self.x),
            F::from_f64(self.y),
            F::from_f64(self.g),
        )
    }
}

const CASES: [Case; 3] = [
    // The paper's setting (alpha h = 0.01).
    Case {
        name: "paper",
        a: 4.0,
        b: 10.0,
        alpha: 1.0,
        beta: 1.0,
        h: 0.01,
        x: 0.7,
        y: -0.3,
        g: 1.5,
    },
    // A large step: alpha h = 2.
    Case {
        name: "large",
        a: 2.0,
        b: 3.0,
        alpha: 2.0,
        beta: 0.5,
        h: 1.0,
        x: -1.2,
        y: 0.8,
        g: -0.6,
    },
    // A very large step, alpha h = 5, and a hot, light velocity.
    Case {
        name: "very large",
        a: 0.5,
        b: 0.25,
        alpha: 0.5,
        beta: 2.0,
        h: 10.0,
        x: 2.0,
        y: 1.0,
        g: 0.3,
    },
];

/// The z-scores of one case.
#[derive(Debug)]
struct Zs {
    mean_x: f64,
    mean_y: f64,
    var_x: f64,
    var_y: f64,
    cov: f64,
}

impl Zs {
    fn max_abs(&self) -> f64 {
        [self.mean_x, self.mean_y, self.var_x, self.var_y, self.cov]
            .iter()
            .fold(0.0, |m: f64, z| m.max(z.abs()))
    }
}

/// Draws 10^6 one-step moves of `kernel` from `(x, y, g)` and returns the
/// z-scores of the empirical moments against `m`. For a sampler without a
/// velocity (`velocity = false`) it instead asserts that `y` is returned
/// bit for bit and that `m` says so.
fn one_step_zs<F: Float, K: Kernel<F>>(
    kernel: &K,
    m: StepMoments<F>,
    (x, y, g): (F, F, F),
    velocity: bool,
    seed: u64,
) -> Zs {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let n = D * STEPS;
    let mut xs = Vec::with_capacity(n);
    let mut ys = Vec::with_capacity(n);
    let grad = [g; D];
    for _ in 0..STEPS {
        let mut xv = [x; D];
        let mut yv = [y; D];
        kernel.step(&mut xv, &mut yv, &grad, &mut rng);
        xs.extend(xv.iter().map(|v| v.to_f64()));
        ys.extend(yv.iter().map(|v| v.to_f64()));
    }
    let mean_x = m.mean_x.to_f64();
    let mean_y = m.mean_y.to_f64();
    let var_x = m.var_x.to_f64();
    let var_y = m.var_y.to_f64();
    let cov_xy = m.cov_xy.to_f64();

    let sx = Summary::of(&xs);
    let z_mean_x = z_score(sx.mean, mean_x, sx.se_mean());
    let z_var_x = z_score(sx.var, var_x, sx.se_var());
    if !velocity {
        // OLA carries y unchanged: every draw, exactly, and so do its moments.
        assert!(ys.iter().all(|&v| v.to_bits() == y.to_f64().to_bits()));
        assert_eq!(mean_y, y.to_f64());
        assert_eq!((var_y, cov_xy), (0.0, 0.0));
        return Zs {
            mean_x: z_mean_x,
            mean_y: 0.0,
            var_x: z_var_x,
            var_y: 0.0,
            cov: 0.0,
        };
    }
    let sy = Summary::of(&ys);
    let cov = covariance(&xs, &ys);
    Zs {
        mean_x: z_mean_x,
        mean_y: z_score(sy.mean, mean_y, sy.se_mean()),
        var_x: z_var_x,
        var_y: z_score(sy.var, var_y, sy.se_var()),
        cov: z_score(cov, cov_xy, se_covariance(var_x, var_y, cov_xy, n)),
    }
}

/// Runs every case for HRLA, ULA and OLA in the float type `F`.
fn check_all<F: Float>(label: &str, seed0: u64) {
    let start = Instant::now();
    let mut tally = Tally {
        label,
        worst: 0.0,
        failures: Vec::new(),
    };
    for (i, c) in CASES.iter().enumerate() {
        let f = F::from_f64;
        let (x, y, g) = c.state();
        let seed = seed0 + 10 * i as u64;

        let hrla = Hrla::new(HrlaParams {
            b: f(c.b),
            alpha: f(c.alpha),
            beta: f(c.beta),
            h: f(c.h),
        })
        .unwrap()
        .at(f(c.a))
        .unwrap();
        tally.check("HRLA", &hrla, hrla.moments(x, y, g), c, true, seed);

        let ula = Ula::new(UlaParams {
            b: f(c.b),
            alpha: f(c.alpha),
            h: f(c.h),
        })
        .unwrap()
        .at(f(c.a))
        .unwrap();
        tally.check("ULA", &ula, ula.moments(x, y, g), c, true, seed + 1);

        // A single OLA step is Gaussian for any (alpha, h), stable or not.
        let ola = Ola::new(OlaParams {
            alpha: f(c.alpha),
            h: f(c.h),
        })
        .unwrap()
        .at(f(c.a))
        .unwrap();
        tally.check("OLA", &ola, ola.moments(x, y, g), c, false, seed + 2);
    }
    let Tally {
        worst, failures, ..
    } = tally;
    println!(
        "{label}: worst |z| = {worst:.2} over all cases, {:.2?}",
        start.elapsed()
    );
    assert!(failures.is_empty(), "|z| >= {Z_MAX}: {failures:#?}");
}

/// The worst |z| and the failures over the cases of one float type: every
/// case is printed, so that a near miss shows before it becomes a failure.
struct Tally<'a> {
    label: &'a str,
    worst: f64,
    failures: Vec<String>,
}

impl Tally<'_> {
    /// One case of one sampler: its z-scores (see `one_step_zs`), printed
    /// and counted.
    fn check<F: Float, K: Kernel<F>>(
        &mut self,
        sampler_name: &str,
        kernel: &K,
        m: StepMoments<F>,
        c: &Case,
        velocity: bool,
        seed: u64,
    ) {
        let zs = one_step_zs(kernel, m, c.state(), velocity, seed);
        let label = self.label;
        println!(
            "{label} {sampler_name:4} {:10} var_x={:.4e} var_y={:.4e} cov={:.4e} | z: mean_x {:+.2} mean_y {:+.2} var_x {:+.2} var_y {:+.2} cov {:+.2}",
            c.name,
            m.var_x.to_f64(),
            m.var_y.to_f64(),
            m.cov_xy.to_f64(),
            zs.mean_x,
            zs.mean_y,
            zs.var_x,
            zs.var_y,
            zs.cov
        );
        self.worst = self.worst.max(zs.max_abs());
        if zs.max_abs() >= Z_MAX {
            self.failures
                .push(format!("{label} {sampler_name} {}: {zs:?}", c.name));
        }
    }
}

#[test]
fn one_step_moments_f64() {
    check_all::<f64>("f64", 0x6d63_0064);
}

#[test]
fn one_step_moments_f32() {
    check_all::<f32>("f32", 0x6d63_0032);
}
