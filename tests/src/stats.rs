//! Statistics for the host-side tests: sample moments with their standard
//! errors, the normal and chi-square distributions, the Kolmogorov–Smirnov
//! statistic, Simpson quadrature and the stationary covariance of a linear
//! Gaussian chain.
//!
//! Everything is computed in `f64` from first principles (plus `libm`'s
//! `erfc` and `lgamma`), so the tests do not depend on the kernel's maths.

/// `Φ(x)`, the standard normal CDF, accurate in both tails.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / core::f64::consts::SQRT_2)
}

/// `1 - Φ(x)`, accurate for large `x`.
pub fn normal_sf(x: f64) -> f64 {
    0.5 * libm::erfc(x / core::f64::consts::SQRT_2)
}

/// Central moments of a sample, computed in two passes (mean first).
#[derive(Clone, Copy, Debug)]
pub struct Summary {
    /// Sample size.
    pub n: usize,
    /// Sample mean.
    pub mean: f64,
    /// Unbiased sample variance.
    pub var: f64,
    /// Third central moment (divided by `n`).
    pub m3: f64,
    /// Fourth central moment (divided by `n`).
    pub m4: f64,
}

impl Summary {
    /// Summarises `xs` (at least two values).
    pub fn of(xs: &[f64]) -> Self {
        let n = xs.len();
        assert!(n >= 2, "need at least two values");
        let nf = n as f64;
        let mean = xs.iter().sum::<f64>() / nf;
        let (mut s2, mut s3, mut s4) = (0.0, 0.0, 0.0);
        for &x in xs {
            let d = x - mean;
            let d2 = d * d;
            s2 += d2;
            s3 += d2 * d;
            s4 += d2 * d2;
        }
        Self {
            n,
            mean,
            var: s2 / (nf - 1.0),
            m3: s3 / nf,
            m4: s4 / nf,
        }
    }

    /// Standard error of the mean, `sqrt(var / n)`.
    pub fn se_mean(&self) -> f64 {
        (self.var / self.n as f64).sqrt()
    }

    /// Standard error of the sample variance from the sample's own fourth
    /// moment: `sqrt((m4 - var^2) / n)` (any distribution with a fourth
    /// moment; `sqrt(2/n) var` for a Gaussian).
    pub fn se_var(&self) -> f64 {
        ((self.m4 - self.var * self.var) / self.n as f64).sqrt()
    }

    /// Sample skewness `m3 / m2^(3/2)`.
    pub fn skewness(&self) -> f64 {
        self.m3 / self.var.powf(1.5)
    }

    /// Sample excess kurtosis `m4 / m2^2 - 3`.
    pub fn excess_kurtosis(&self) -> f64 {
        self.m4 / (self.var * self.var) - 3.0
    }
}

/// Sample covariance (unbiased) of two equally long samples.
pub fn covariance(xs: &[f64], ys: &[f64]) -> f64 {
    assert_eq!(xs.len(), ys.len());
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    xs.iter()
        .zip(ys)
        .map(|(&x, &y)| (x - mx) * (y - my))
        .sum::<f64>()
        / (n - 1.0)
}

/// Standard error of a sample covariance of `n` Gaussian pairs with
/// variances `vx`, `vy` and covariance `c`: `sqrt((vx vy + c^2) / n)`.
pub fn se_covariance(vx: f64, vy: f64, c: f64, n: usize) -> f64 {
    ((vx * vy + c * c) / n as f64).sqrt()
}

/// The z-score `(estimate - truth) / se`.
pub fn z_score(estimate: f64, truth: f64, se: f64) -> f64 {
    (estimate - truth) / se
}

/// Kolmogorov–Smirnov statistic `D = sup |F_n - F|` of a sample against a
/// continuous CDF. Sorts `xs` in place.
pub fn ks_statistic(xs: &mut [f64], cdf: impl Fn(f64) -> f64) -> f64 {
    xs.sort_unstable_by(f64::total_cmp);
    let n = xs.len() as f64;
    let mut d: f64 = 0.0;
    for (i, &x) in xs.iter().enumerate() {
        let f = cdf(x);
        d = d.max(f - i as f64 / n).max((i + 1) as f64 / n - f);
    }
    d
}

/// Asymptotic survival function of the Kolmogorov distribution,
/// `P(sqrt(n) D > t) = 2 sum_{k>=1} (-1)^(k-1) exp(-2 k^2 t^2)`.
pub fn kolmogorov_sf(t: f64) -> f64 {
    if t < 0.2 {
        return 1.0;
    }
    let mut s = 0.0;
    for k in 1..=100 {
        let kf = k as f64;
        let term = (-2.0 * kf * kf * t * t).exp();
        s += if k % 2 == 1 { term } else { -term };
        if term < 1e-300 {
            break;
        }
    }
    (2.0 * s).clamp(0.0, 1.0)
}

/// The `t` with `kolmogorov_sf(t) = alpha` (bisection).
pub fn kolmogorov_critical(alpha: f64) -> f64 {
    bisect(|t| kolmogorov_sf(t) - alpha, 0.3, 5.0)
}

/// Regularised upper incomplete gamma function `Q(s, x)`
/// (series for `x < s + 1`, Lentz continued fraction otherwise).
pub fn gamma_q(s: f64, x: f64) -> f64 {
    assert!(s > 0.0 && x >= 0.0);
    if x == 0.0 {
        return 1.0;
    }
    let log_prefactor = -x + s * x.ln() - libm::lgamma(s);
    if x < s + 1.0 {
        // P(s, x) = e^-x x^s / Gamma(s) * sum_n x^n / (s (s+1) ... (s+n)).
        let mut term = 1.0 / s;
        let mut sum = term;
        let mut ap = s;
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-17 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - s;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - s);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        h * log_prefactor.exp()
    }
}

/// `P(X > x)` for a chi-square variable with `df` degrees of freedom.
pub fn chi2_sf(x: f64, df: usize) -> f64 {
    gamma_q(df as f64 / 2.0, x / 2.0)
}

/// The critical value `c` with `chi2_sf(c, df) = alpha` (bisection).
pub fn chi2_critical(alpha: f64, df: usize) -> f64 {
    let hi = df as f64 + 20.0 * (2.0 * df as f64).sqrt() + 100.0;
    bisect(|x| alpha - chi2_sf(x, df), 0.0, hi)
}

/// A root of `f` in `[lo, hi]`, where `f(lo)` and `f(hi)` differ in sign.
pub fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let flo = f(lo);
    assert!(flo * f(hi) <= 0.0, "no sign change in [{lo}, {hi}]");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if (f(mid) < 0.0) == (flo < 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Composite Simpson rule for `∫_a^b f` with `n` (rounded up to even)
/// subintervals.
pub fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let n = n.max(2).next_multiple_of(2);
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        s += w * f(a + i as f64 * h);
    }
    s * h / 3.0
}

/// Pearson's chi-square statistic of observed counts against expected
/// probabilities (which must sum to 1) for `n = sum(observed)` draws.
pub fn chi_square(observed: &[u64], probabilities: &[f64]) -> f64 {
    assert_eq!(observed.len(), probabilities.len());
    let n = observed.iter().sum::<u64>() as f64;
    observed
        .iter()
        .zip(probabilities)
        .map(|(&o, &p)| {
            let e = n * p;
            (o as f64 - e).powi(2) / e
        })
        .sum()
}

/// A 2x2 matrix, row-major.
pub type Mat2 = [[f64; 2]; 2];

/// `A B`.
pub fn mat_mul(a: &Mat2, b: &Mat2) -> Mat2 {
    let mut c = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

/// `A S A^T`.
pub fn congruence(a: &Mat2, s: &Mat2) -> Mat2 {
    let at = [[a[0][0], a[1][0]], [a[0][1], a[1][1]]];
    mat_mul(&mat_mul(a, s), &at)
}

/// The stationary covariance of the chain `s' = M s + N(0, C)`: the
/// solution of the discrete Lyapunov equation `Σ = M Σ M^T + C`, solved as
/// a 3x3 linear system in `(Σ11, Σ12, Σ22)` by Gaussian elimination with
/// partial pivoting. `M` must have spectral radius < 1.
pub fn discrete_lyapunov(m: &Mat2, c: &Mat2) -> Mat2 {
    let [[m11, m12], [m21, m22]] = *m;
    // Rows: (I - K) (s11, s12, s22) = (c11, c12, c22).
    let mut a = [
        [1.0 - m11 * m11, -2.0 * m11 * m12, -m12 * m12, c[0][0]],
        [
            -m11 * m21,
            1.0 - (m11 * m22 + m12 * m21),
            -m12 * m22,
            c[0][1],
        ],
        [-m21 * m21, -2.0 * m21 * m22, 1.0 - m22 * m22, c[1][1]],
    ];
    for col in 0..3 {
        let pivot = (col..3)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap();
        a.swap(col, pivot);
        let pivot_row = a[col];
        for row in a.iter_mut().skip(col + 1) {
            let f = row[col] / pivot_row[col];
            for (r, p) in row.iter_mut().zip(pivot_row).skip(col) {
                *r -= f * p;
            }
        }
    }
    let mut s = [0.0; 3];
    for row in (0..3).rev() {
        let mut v = a[row][3];
        for k in row + 1..3 {
            v -= a[row][k] * s[k];
        }
        s[row] = v / a[row][row];
    }
    [[s[0], s[1]], [s[1], s[2]]]
}

/// The same solution by the doubling iteration
/// `Σ <- Σ + A Σ A^T`, `A <- A^2` (sums `sum_k M^k C M^kT`), as a check.
pub fn discrete_lyapunov_doubling(m: &Mat2, c: &Mat2) -> Mat2 {
    let mut s = *c;
    let mut a = *m;
    for _ in 0..64 {
        let t = congruence(&a, &s);
        for i in 0..2 {
            for j in 0..2 {
                s[i][j] += t[i][j];
            }
        }
        a = mat_mul(&a, &a);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_critical_values() {
        // Tables: chi2_{0.999}(29) = 58.301, chi2_{0.999}(1) = 10.828,
        // Kolmogorov 0.999 quantile 1.9495.
        assert!((chi2_critical(0.001, 29) - 58.301).abs() < 1e-3);
        assert!((chi2_critical(0.001, 1) - 10.828).abs() < 1e-3);
        assert!((chi2_critical(0.05, 100) - 124.342).abs() < 1e-3);
        assert!((kolmogorov_critical(0.001) - 1.9495).abs() < 1e-4);
    }

    #[test]
    fn normal_cdf_values() {
        assert!((normal_cdf(1.959_963_984_540_054) - 0.975).abs() < 1e-15);
        // 1 - Φ(5) = 2.866515718791939e-7.
        assert!((normal_sf(5.0) / 2.866_515_718_791_939e-7 - 1.0).abs() < 1e-13);
    }

    #[test]
    fn simpson_integrates_a_gaussian() {
        let z = simpson(|x| (-0.5 * x * x).exp(), -10.0, 10.0, 2000);
        assert!((z / (2.0 * core::f64::consts::PI).sqrt() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn lyapunov_solvers_agree() {
        let m = [[0.9, 0.05], [-0.2, 0.7]];
        let c = [[0.01, 0.002], [0.002, 0.03]];
        let a = discrete_lyapunov(&m, &c);
        let b = discrete_lyapunov_doubling(&m, &c);
        let r = congruence(&m, &a);
        for i in 0..2 {
            for j in 0..2 {
                assert!((a[i][j] - b[i][j]).abs() < 1e-15);
                assert!((a[i][j] - r[i][j] - c[i][j]).abs() < 1e-15);
            }
        }
    }
}
