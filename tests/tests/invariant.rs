//! The invariant law of the chains.
//!
//! The optimiser rests on chains at inverse temperature `a` sampling
//! `exp(-a U)`: this checks that end to end, and that the discretisation's
//! bias at a finite step `h` is the one the exact linear theory predicts
//! rather than an error of the kernel.
//!
//! (a) Quadratic potential `U = k x^2 / 2` in one dimension: every sampler's
//! step is a linear Gaussian map `s' = M s + N(0, C)` of the state
//! `s = (x, y)`, so the discrete chain's stationary covariance is the exact
//! solution of the discrete Lyapunov equation `Σ = M Σ M^T + C`. It is
//! compared with the Gibbs law (`Var x = 1/(a k)`, `Var y = 1/b`, no
//! correlation) as `h -> 0`, and with long Monte Carlo runs.
//!
//! (b) Double well `U = (x^2 - 1)^2`: a chi-square goodness-of-fit test of
//! many independent chains' final positions against `exp(-a U)`.

use std::time::Instant;

use hrla::{
    DoubleWell, Float, Hrla, HrlaParams, Kernel, Ola, OlaKernel, OlaParams, OuKernel, Potential,
    Quadratic, Sampler, Ula, UlaParams,
};
use hrla_tests::stats::{
    Mat2, Summary, chi_square, chi2_critical, chi2_sf, congruence, covariance, discrete_lyapunov,
    discrete_lyapunov_doubling, mat_mul, se_covariance, simpson, z_score,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// Rejection threshold for z-scores.
const Z_MAX: f64 = 5.0;

// --- (a) quadratic: the linear Gaussian chain ---------------------------------

/// Inverse temperatures and friction of part (a): the paper's `a = 4`,
/// `b = 10`, `alpha = beta = 1`, and stiffness `k = 1`.
const A: f64 = 4.0;
const B: f64 = 10.0;
const ALPHA: f64 = 1.0;
const BETA: f64 = 1.0;
const K: f64 = 1.0;

/// Which sampler, and in which float type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Hrla,
    Ula,
    Ola,
}

/// `s' = M s + N(0, C)` for the quadratic, read off `moments()`.
#[derive(Clone, Copy, Debug)]
struct LinearChain {
    m: Mat2,
    c: Mat2,
    /// OLA has no velocity: only `(0, 0)` entries are meaningful.
    velocity: bool,
}

impl LinearChain {
    /// The mean of a step is linear in `(x, y, g)`, and `g = k x`: the
    /// columns of M are the means from the unit states `(1, 0)` (with
    /// `g = k`) and `(0, 1)` (with `g = 0`). The covariance C does not
    /// depend on the state.
    fn from_moments<F: Float>(kernel: &impl Kernel<F>, velocity: bool) -> Self {
        let f = F::from_f64;
        let origin = kernel.moments(F::ZERO, F::ZERO, F::ZERO);
        assert_eq!((origin.mean_x, origin.mean_y), (F::ZERO, F::ZERO));
        let ex = kernel.moments(F::ONE, F::ZERO, f(K));
        let ey = kernel.moments(F::ZERO, F::ONE, F::ZERO);
        let m = [
            [ex.mean_x.to_f64(), ey.mean_x.to_f64()],
            [ex.mean_y.to_f64(), ey.mean_y.to_f64()],
        ];
        let c = [
            [origin.var_x.to_f64(), origin.cov_xy.to_f64()],
            [origin.cov_xy.to_f64(), origin.var_y.to_f64()],
        ];
        Self { m, c, velocity }
    }

    /// The exact stationary covariance of the chain.
    fn stationary(&self) -> Mat2 {
        if self.velocity {
            let s = discrete_lyapunov(&self.m, &self.c);
            // The same solution by the doubling iteration, as a guard on
            // the linear solve (agreement to 1e-12 relative).
            let d = discrete_lyapunov_doubling(&self.m, &self.c);
            for i in 0..2 {
                for j in 0..2 {
                    assert!((s[i][j] - d[i][j]).abs() <= 1e-12 * s[0][0].max(s[1][1]));
                }
            }
            s
        } else {
            let m = self.m[0][0];
            [[self.c[0][0] / (1.0 - m * m), 0.0], [0.0, 0.0]]
        }
    }

    /// `M^n Σ M^nT`: what is still missing from the covariance after `n`
    /// steps from the deterministic state `(0, 0)` (then the covariance is
    /// `Σ - M^n Σ M^nT`).
    fn deficit(&self, sigma: &Mat2, n: usize) -> Mat2 {
        let m = if self.velocity {
            self.m
        } else {
            [[self.m[0][0], 0.0], [0.0, 0.0]]
        };
        let mut p = [[1.0, 0.0], [0.0, 1.0]];
        for _ in 0..n {
            p = mat_mul(&m, &p);
        }
        congruence(&p, sigma)
    }
}

/// HRLA's step at `a = A`.
fn hrla<F: Float>(h: f64) -> OuKernel<F> {
    let f = F::from_f64;
    Hrla::new(HrlaParams {
        b: f(B),
        alpha: f(ALPHA),
        beta: f(BETA),
        h: f(h),
    })
    .unwrap()
    .at(f(A))
    .unwrap()
}

/// ULA's step at `a = A`.
fn ula<F: Float>(h: f64) -> OuKernel<F> {
    let f = F::from_f64;
    Ula::new(UlaParams {
        b: f(B),
        alpha: f(ALPHA),
        h: f(h),
    })
    .unwrap()
    .at(f(A))
    .unwrap()
}

/// OLA's step at `a = A`.
fn ola<F: Float>(h: f64) -> OlaKernel<F> {
    let f = F::from_f64;
    Ola::new(OlaParams {
        alpha: f(ALPHA),
        h: f(h),
    })
    .unwrap()
    .at(f(A))
    .unwrap()
}

fn linear_chain<F: Float>(kind: Kind, h: f64) -> LinearChain {
    match kind {
        Kind::Hrla => LinearChain::from_moments(&hrla::<F>(h), true),
        Kind::Ula => LinearChain::from_moments(&ula::<F>(h), true),
        Kind::Ola => LinearChain::from_moments(&ola::<F>(h), false),
    }
}

/// The discretisation bias of the stationary law shrinks linearly with h.
///
/// For each sampler, `bias(h) = |Var_h(x) a k - 1|` at h = 0.2, 0.1, 0.05,
/// 0.025 (and `|Var_h(y) b - 1|`, `|Cov_h| sqrt(a k b)` for HRLA and ULA).
/// The Lyapunov solution is exact up to rounding (~1e-14 relative, checked
/// against the doubling iteration), so these are deterministic numbers and
/// the tolerances below bound the *next term* of the expansion
/// `bias = c1 h + c2 h^2 + ...`, not noise. Measured (f64):
///
/// | h      | HRLA x   | ULA x    | OLA x    |
/// |--------|----------|----------|----------|
/// | 0.2    | 1.350e-1 | 4.161e-2 | 1.111e-1 |
/// | 0.1    | 6.354e-2 | 2.040e-2 | 5.263e-2 |
/// | 0.05   | 3.086e-2 | 1.010e-2 | 2.564e-2 |
/// | 0.025  | 1.521e-2 | 5.025e-3 | 1.266e-2 |
///
/// Successive ratios 2.13, 2.06, 2.03 (HRLA), 2.04, 2.02, 2.01 (ULA),
/// 2.11, 2.05, 2.03 (OLA): order 1 in h, the ratio tending to 2 as the
/// `c2 h` correction vanishes (`bias/h -> 0.60 (HRLA), 0.20 (ULA), 0.50
/// (OLA)` for these parameters). The test asserts monotone decrease and
/// an observed order `log2(ratio)` in [0.9, 1.2] at every halving. OLA's
/// chain is scalar, `Var_h = 1/(a k (1 - alpha h k / 2))`, so its bias is
/// exactly `h k / (2 - h k)`: checked to 1e-12.
#[test]
fn quadratic_discretisation_bias_is_first_order() {
    let hs = [0.2, 0.1, 0.05, 0.025];
    for kind in [Kind::Hrla, Kind::Ula, Kind::Ola] {
        let mut rows = Vec::new();
        for &h in &hs {
            let chain = linear_chain::<f64>(kind, h);
            let s = chain.stationary();
            let bx = (s[0][0] * A * K - 1.0).abs();
            let (by, bc) = if chain.velocity {
                (
                    (s[1][1] * B - 1.0).abs(),
                    s[0][1].abs() * (A * K * B).sqrt(),
                )
            } else {
                (0.0, 0.0)
            };
            if kind == Kind::Ola {
                let exact = h * ALPHA * K / (2.0 - h * ALPHA * K);
                assert!((bx / exact - 1.0).abs() < 1e-12, "OLA bias {bx} vs {exact}");
            }
            rows.push((h, bx, by, bc));
        }
        for w in rows.windows(2) {
            let (h0, bx0, by0, bc0) = w[0];
            let (h1, bx1, by1, bc1) = w[1];
            let order = (bx0 / bx1).log2();
            println!(
                "{kind:?}: h {h0} -> {h1}: x bias {bx0:.4e} -> {bx1:.4e} (order {order:.3}); \
                 y bias {by0:.4e} -> {by1:.4e}; corr {bc0:.3e} -> {bc1:.3e}; bias_x/h = {:.4}",
                bx1 / h1
            );
            assert!(bx1 < bx0, "{kind:?}: x bias does not decrease");
            assert!((0.9..1.2).contains(&order), "{kind:?}: order {order}");
            if kind != Kind::Ola {
                let order_y = (by0 / by1).log2();
                assert!(by1 < by0 && bc1 < bc0, "{kind:?}: y/cov bias");
                assert!((0.9..1.2).contains(&order_y), "{kind:?}: y order {order_y}");
            }
        }
    }
}

/// Runs `chains` independent 1-D chains (as the coordinates of a
/// `D`-dimensional separable quadratic, whose steps draw independent
/// normals per coordinate) for `steps` steps from `(0, 0)` and returns
/// their final `(x, y)`.
fn run_quadratic<F: Float, K: Kernel<F>, const D: usize>(
    kernel: &K,
    groups: usize,
    steps: usize,
    seed: u64,
) -> (Vec<f64>, Vec<f64>) {
    let potential = Quadratic::new(F::from_f64(K), [F::ZERO; D]).unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut xs = Vec::with_capacity(groups * D);
    let mut ys = Vec::with_capacity(groups * D);
    for _ in 0..groups {
        let mut x = [F::ZERO; D];
        let mut y = [F::ZERO; D];
        let mut g = [F::ZERO; D];
        for _ in 0..steps {
            potential.value_and_gradient(&x, &mut g);
            kernel.step(&mut x, &mut y, &g, &mut rng);
        }
        xs.extend(x.iter().map(|v| v.to_f64()));
        ys.extend(y.iter().map(|v| v.to_f64()));
    }
    (xs, ys)
}

/// Long runs reach the *discrete* chain's stationary law, not the Gibbs law.
///
/// 10^5 independent chains (1000 groups of 100 coordinates), each run
/// 30/h steps from `(0, 0)` at h = 0.2 (150 steps; slowest mode of these
/// chains decays like `exp(-0.5 t)`, ULA's). Only the final states are
/// used, so the samples are independent. The remaining transient,
/// `M^n Σ M^nT`, is computed exactly and asserted below 0.05 SE, so the
/// finite run length cannot bias the comparison.
///
/// Standard errors (n = 10^5): variance `sqrt((m4 - s^4)/n)` from the
/// sample (0.45% relative), mean `sqrt(var/n)`, covariance
/// `sqrt((Σxx Σyy + Σxy^2)/n)`. Each statistic must be within 5 SE of the
/// Lyapunov solution. The Gibbs values differ from it by 13.5% (HRLA),
/// 4.2% (ULA) and 11.1% (OLA) in `Var x`, i.e. 30, 9 and 25 SE: the test
/// also asserts that the Gibbs value is rejected (|z| > 5) whenever the
/// predicted distance exceeds 10 SE, which shows the comparison has the
/// power to tell the two laws apart.
#[test]
fn quadratic_long_runs_match_the_discrete_stationary_law() {
    const H: f64 = 0.2;
    const GROUPS: usize = 1000;
    const DIM: usize = 100;
    let steps = (30.0 / H) as usize;
    let cases: [(&str, Kind, bool); 4] = [
        ("HRLA f64", Kind::Hrla, false),
        ("ULA f64", Kind::Ula, false),
        ("OLA f64", Kind::Ola, false),
        ("HRLA f32", Kind::Hrla, true),
    ];
    let mut failures = Vec::new();
    for (i, &(label, kind, single)) in cases.iter().enumerate() {
        let start = Instant::now();
        let seed = 0x696e_7661 + i as u64;
        let chain = if single {
            linear_chain::<f32>(kind, H)
        } else {
            linear_chain::<f64>(kind, H)
        };
        let (xs, ys) = match (kind, single) {
            (Kind::Hrla, false) => run_quadratic::<f64, _, DIM>(&hrla(H), GROUPS, steps, seed),
            (Kind::Ula, false) => run_quadratic::<f64, _, DIM>(&ula(H), GROUPS, steps, seed),
            (Kind::Ola, false) => run_quadratic::<f64, _, DIM>(&ola(H), GROUPS, steps, seed),
            (Kind::Hrla, true) => {
                run_quadratic::<f32, _, DIM>(&hrla::<f32>(H), GROUPS, steps, seed)
            }
            _ => unreachable!(),
        };
        let n = xs.len();
        let sigma = chain.stationary();
        let deficit = chain.deficit(&sigma, steps);

        let sx = Summary::of(&xs);
        let se_vx = sx.se_var();
        assert!(
            deficit[0][0] < 0.05 * se_vx,
            "{label}: burn-in too short: {deficit:?}"
        );
        let gibbs_x = 1.0 / (A * K);
        let z_vx = z_score(sx.var, sigma[0][0], se_vx);
        let z_vx_gibbs = z_score(sx.var, gibbs_x, se_vx);
        let z_mx = z_score(sx.mean, 0.0, sx.se_mean());
        let mut zs = vec![("mean x", z_mx), ("var x", z_vx)];
        let mut line = format!(
            "{label}: n = {n}, {steps} steps; var x {:.5} (discrete {:.5}, z {z_vx:+.2}; Gibbs \
             {gibbs_x:.5}, z {z_vx_gibbs:+.1}); mean x z {z_mx:+.2}",
            sx.var, sigma[0][0]
        );
        let predicted_x = (sigma[0][0] - gibbs_x).abs() / se_vx;
        let mut gibbs = vec![("var x", predicted_x, z_vx_gibbs)];

        if chain.velocity {
            let sy = Summary::of(&ys);
            let se_vy = sy.se_var();
            assert!(
                deficit[1][1] < 0.05 * se_vy,
                "{label}: burn-in: {deficit:?}"
            );
            let gibbs_y = 1.0 / B;
            let z_vy = z_score(sy.var, sigma[1][1], se_vy);
            let z_vy_gibbs = z_score(sy.var, gibbs_y, se_vy);
            let z_my = z_score(sy.mean, 0.0, sy.se_mean());
            let cov = covariance(&xs, &ys);
            let se_c = se_covariance(sigma[0][0], sigma[1][1], sigma[0][1], n);
            assert!(
                deficit[0][1].abs() < 0.05 * se_c,
                "{label}: burn-in: {deficit:?}"
            );
            let z_c = z_score(cov, sigma[0][1], se_c);
            let z_c_gibbs = z_score(cov, 0.0, se_c);
            zs.extend([("mean y", z_my), ("var y", z_vy), ("cov", z_c)]);
            gibbs.push(("var y", (sigma[1][1] - gibbs_y).abs() / se_vy, z_vy_gibbs));
            gibbs.push(("cov", sigma[0][1].abs() / se_c, z_c_gibbs));
            line += &format!(
                "; var y {:.5} (discrete {:.5}, z {z_vy:+.2}; Gibbs {gibbs_y:.5}, z \
                 {z_vy_gibbs:+.1}); cov {cov:+.3e} (discrete {:+.3e}, z {z_c:+.2}; Gibbs 0, z \
                 {z_c_gibbs:+.1}); mean y z {z_my:+.2}",
                sy.var, sigma[1][1], sigma[0][1]
            );
        } else {
            // OLA leaves the velocity alone.
            assert!(ys.iter().all(|&y| y == 0.0));
        }
        println!("{line}; {:.2?}", start.elapsed());
        for (what, z) in zs {
            if z.abs() >= Z_MAX {
                failures.push(format!("{label}: {what}: z = {z:.2}"));
            }
        }
        for (what, predicted, z) in gibbs {
            if predicted > 10.0 && z.abs() <= Z_MAX {
                failures.push(format!(
                    "{label}: {what}: Gibbs law not rejected (z = {z:.2}, predicted {predicted:.1})"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

// --- (b) double well: chi-square against exp(-a U) ----------------------------

/// Inverse temperature of part (b): `exp(-2 U)` has two humps at ±1 and a
/// barrier of `a ΔU = 2` (density ratio e^-2 at the saddle).
const A_DW: f64 = 2.0;
/// Chains per test: 100 groups of 100 coordinates. `DoubleWell` is
/// separable and every step draws fresh normals per coordinate, so the
/// coordinates of one `D`-dimensional run are independent 1-D chains.
const DW_GROUPS: usize = 100;
const DW_DIM: usize = 100;
/// Number of bins of the chi-square test (about equiprobable).
const BINS: usize = 30;
/// Run lengths (time units): see [`check_double_well`] on mixing and
/// [`double_well_ula`] on the measured crossing rates.
const T_OVERDAMPED: f64 = 32.0;
const T_ULA: f64 = 100.0;

/// Final positions of independent 1-D double-well chains started at
/// `(x, y) = (1, 0)`, with barrier-crossing statistics.
struct DwRun {
    xs: Vec<f64>,
    /// Mean number of completed crossings per chain, counted with
    /// hysteresis: a chain changes side when it goes below -1/2 after last
    /// being above +1/2, or the reverse.
    crossings: f64,
    /// Share of chains that crossed at least once.
    crossed: f64,
}

fn run_double_well<K: Kernel<f64>>(kernel: &K, groups: usize, steps: usize, seed: u64) -> DwRun {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut xs = Vec::with_capacity(groups * DW_DIM);
    let (mut crossings, mut crossed) = (0u64, 0u64);
    for _ in 0..groups {
        let mut x = [1.0; DW_DIM];
        let mut y = [0.0; DW_DIM];
        let mut g = [0.0; DW_DIM];
        let mut positive = [true; DW_DIM];
        let mut count = [0u32; DW_DIM];
        for _ in 0..steps {
            DoubleWell.value_and_gradient(&x, &mut g);
            kernel.step(&mut x, &mut y, &g, &mut rng);
            for ((&xi, p), c) in x.iter().zip(&mut positive).zip(&mut count) {
                if (*p && xi < -0.5) || (!*p && xi > 0.5) {
                    *p = !*p;
                    *c += 1;
                }
            }
        }
        crossings += count.iter().map(|&c| u64::from(c)).sum::<u64>();
        crossed += count.iter().filter(|&&c| c > 0).count() as u64;
        xs.extend_from_slice(&x);
    }
    let n = xs.len() as f64;
    DwRun {
        xs,
        crossings: crossings as f64 / n,
        crossed: crossed as f64 / n,
    }
}

/// Bin edges (about equiprobable under `exp(-a U)`) and each bin's exact
/// probability, by Simpson's rule on the unnormalised density
/// `exp(-a (x^2 - 1)^2)` over [-3, 3] (the mass beyond is below e^-128).
///
/// The edges are interpolated quantiles of a tabulated CDF; they need not
/// be exact quantiles, because each bin's probability is then integrated
/// between the chosen edges with 2000 Simpson intervals (error ~1e-14).
fn gibbs_bins(a: f64) -> (Vec<f64>, Vec<f64>) {
    let density = |x: f64| (-a * (x * x - 1.0).powi(2)).exp();
    let l = 3.0;
    let z = simpson(density, -l, l, 60_000);
    // Tabulated CDF on a grid of 6000 cells (Simpson on each pair).
    let cells = 6000;
    let dx = 2.0 * l / cells as f64;
    let mut grid = vec![(-l, 0.0)];
    let mut acc = 0.0;
    for i in (0..cells).step_by(2) {
        let x0 = -l + i as f64 * dx;
        acc += simpson(density, x0, x0 + 2.0 * dx, 2) / z;
        grid.push((x0 + 2.0 * dx, acc));
    }
    let mut edges = vec![f64::NEG_INFINITY];
    for k in 1..BINS {
        let p = k as f64 / BINS as f64;
        let j = grid.partition_point(|&(_, c)| c < p);
        let ((x0, c0), (x1, c1)) = (grid[j - 1], grid[j]);
        edges.push(x0 + (x1 - x0) * (p - c0) / (c1 - c0));
    }
    edges.push(f64::INFINITY);
    let probs: Vec<f64> = edges
        .windows(2)
        .map(|w| simpson(density, w[0].max(-l), w[1].min(l), 2000) / z)
        .collect();
    assert!((probs.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    (edges, probs)
}

/// The chi-square statistic of the final positions against `exp(-a U)`.
fn double_well_chi_square(xs: &[f64], a: f64) -> f64 {
    let (edges, probs) = gibbs_bins(a);
    let mut counts = vec![0u64; BINS];
    for &x in xs {
        counts[edges.partition_point(|&e| e < x) - 1] += 1;
    }
    chi_square(&counts, &probs)
}

/// Runs one sampler and applies the chi-square test.
///
/// Level 0.001 with 30 bins, df = 29: the critical value is 58.30
/// (tables: chi2_{0.999}(29) = 58.301; recomputed here from the regularised
/// incomplete gamma function). 10^4 chains put ~333 expected counts in
/// each bin, far above the usual minimum of 5, so Pearson's statistic is
/// chi-square distributed to good accuracy.
///
/// Mixing. All chains start at x = +1, so until they have forgotten it,
/// P(x > 0) exceeds 1/2 by about `(1/2) exp(-2 κ t)`, κ the crossing rate
/// per unit time. The run length T is set so that this is below 1/10 of
/// the SE of P(x > 0) (`0.5/sqrt(n)`), i.e. `2 κ T > ln(10 sqrt(n)) ≈ 6.9`.
/// κ is measured (and printed) from the crossings, and the test asserts
/// `κ T >= 3.45` and that >= 95% of chains crossed at least once.
///
/// Discretisation bias. At step h the chain's stationary law differs
/// from `exp(-a U)` by a relative O(h) in each bin, which adds a
/// noncentrality `λ = n Σ p_i δ_i^2 ∝ n h^2` to the expected chi-square.
/// Measured with 10^5 chains by the ignored test
/// `double_well_bias_calibration` (same a, T and bins), as `chi2 - 29`,
/// whose SD is `sqrt(2 (29 + 2 λ))` (8 at λ = 0, 20 at λ = 80); in
/// brackets, an independent run with other seeds and T = 40 / 90:
///
/// | h      | HRLA        | OLA         | ULA (b=1, alpha=4) |
/// |--------|-------------|-------------|--------------------|
/// | 0.04   | 1595 (1538) | 1277 (1469) | 305 (243)          |
/// | 0.02   | 341 (334)   | 301 (248)   | 70 (73)            |
/// | 0.01   | 117 (80)    | 78 (46)     | 14 (23)            |
/// | 0.005  | 28 (17)     | 29 (10)     | -8 (~0)            |
///
/// λ falls by about 4 per halving of h (δ ∝ h), by about 3-4 for ULA.
/// Extrapolated to the tests' settings (n = 10^4, a tenth): HRLA and OLA
/// at h = 0.0025, λ ≈ 28/4/10 = 0.7; ULA at h = 0.005, λ ≈ 19/3/10 = 0.6
/// (from h = 0.01; at h = 0.005 it is already below the calibration's
/// noise). A noncentrality below 1 moves the expected statistic by less
/// than 0.13 of its null SD (sqrt(58) = 7.6) and raises the rejection
/// probability at the 0.001 critical value only to 0.0017 (noncentral
/// chi-square, λ = 1; 0.0015 at λ = 0.7): the bias is below the test's
/// resolution, and the test checks the sampler against the exact Gibbs
/// law.
fn check_double_well<K: Kernel<f64>>(label: &str, kernel: &K, h: f64, t: f64, seed: u64) {
    let start = Instant::now();
    let steps = (t / h).round() as usize;
    let run = run_double_well(kernel, DW_GROUPS, steps, seed);
    let n = run.xs.len();
    let chi2 = double_well_chi_square(&run.xs, A_DW);
    let df = BINS - 1;
    let critical = chi2_critical(0.001, df);
    assert!((critical - 58.301).abs() < 1e-3, "{critical}");
    let kappa = run.crossings / t;
    let positive = run.xs.iter().filter(|&&x| x > 0.0).count();
    let z_side = z_score(positive as f64, n as f64 / 2.0, (n as f64 / 4.0).sqrt());
    println!(
        "{label}: n = {n}, h = {h}, T = {t} ({steps} steps): {:.2} crossings per chain \
         (κ = {kappa:.3} per unit time, κT = {:.2}), {:.2}% crossed; P(x > 0) z = {z_side:+.2}; \
         chi2 = {chi2:.2} (df {df}, critical {critical:.2} at 0.001, p = {:.3}); {:.2?}",
        run.crossings,
        kappa * t,
        100.0 * run.crossed,
        chi2_sf(chi2, df),
        start.elapsed()
    );
    assert!(kappa * t >= 3.45, "{label}: too few crossings for mixing");
    assert!(run.crossed >= 0.95, "{label}: too few chains crossed");
    assert!(chi2 < critical, "{label}: chi2 = {chi2} rejects exp(-a U)");
}

/// HRLA with the paper's `b = 10`, `alpha = beta = 1`.
#[test]
fn double_well_hrla() {
    let hrla = Hrla::new(HrlaParams {
        b: 10.0,
        alpha: 1.0,
        beta: 1.0,
        h: 0.0025,
    })
    .unwrap()
    .at(A_DW)
    .unwrap();
    check_double_well("HRLA", &hrla, 0.0025, T_OVERDAMPED, 0x6477_0001);
}

/// OLA with `alpha = 1`.
#[test]
fn double_well_ola() {
    let ola = Ola::new(OlaParams {
        alpha: 1.0,
        h: 0.0025,
    })
    .unwrap()
    .at(A_DW)
    .unwrap();
    check_double_well("OLA", &ola, 0.0025, T_OVERDAMPED, 0x6477_0002);
}

/// ULA with `b = 1`, `alpha = 4` rather than the paper's `b = 10`: its
/// position moves only through the velocity, whose force is scaled by
/// `gamma = a/b`; at `b = 10` the chain crosses the barrier about ten times
/// more slowly than OLA (measured: 0.0125 crossings per unit time) and
/// would need ~10x the run. `b` and `alpha` do not change the x-marginal
/// `exp(-a U)`. Measured crossing rate here: 0.039 per unit time, hence
/// T = 100 (κT ≈ 3.9). HRLA and OLA cross at 0.12 per unit time, and run
/// T = 32 (κT ≈ 3.9).
#[test]
fn double_well_ula() {
    let ula = Ula::new(UlaParams {
        b: 1.0,
        alpha: 4.0,
        h: 0.005,
    })
    .unwrap()
    .at(A_DW)
    .unwrap();
    check_double_well("ULA", &ula, 0.005, T_ULA, 0x6477_0003);
}

/// Measures the discretisation bias quoted in [`check_double_well`]'s
/// table: 10^5 chains at larger steps, printing `chi2 - df` (an estimate of
/// the noncentrality λ, with SD about sqrt(2 df + 4 λ)). Slow (minutes):
/// run with `cargo test -p hrla-tests --test invariant -- --ignored`.
#[test]
#[ignore = "measurement for the docs, takes minutes"]
fn double_well_bias_calibration() {
    let df = (BINS - 1) as f64;
    for h in [0.04, 0.02, 0.01, 0.005] {
        let hrla = Hrla::new(HrlaParams {
            b: 10.0,
            alpha: 1.0,
            beta: 1.0,
            h,
        })
        .unwrap()
        .at(A_DW)
        .unwrap();
        let ola = Ola::new(OlaParams { alpha: 1.0, h })
            .unwrap()
            .at(A_DW)
            .unwrap();
        let ula = Ula::new(UlaParams {
            b: 1.0,
            alpha: 4.0,
            h,
        })
        .unwrap()
        .at(A_DW)
        .unwrap();
        let groups = 10 * DW_GROUPS;
        let lambda = |run: DwRun| double_well_chi_square(&run.xs, A_DW) - df;
        let l_hrla = lambda(run_double_well(
            &hrla,
            groups,
            (T_OVERDAMPED / h) as usize,
            11,
        ));
        let l_ola = lambda(run_double_well(
            &ola,
            groups,
            (T_OVERDAMPED / h) as usize,
            12,
        ));
        let l_ula = lambda(run_double_well(&ula, groups, (T_ULA / h) as usize, 13));
        println!(
            "h = {h}: n = {}: chi2 - df: HRLA {l_hrla:.1}, OLA {l_ola:.1}, ULA {l_ula:.1}",
            groups * DW_DIM
        );
    }
}
