//! The small dense linear algebra of the ensemble solver: row-major
//! `n x n` matrices of a few hundred rows at most, so plain loops in a
//! fixed order (the same bits on every target) rather than a dependency.

/// The lower Cholesky factor `L` of a symmetric positive definite `a`
/// (`n x n`, row-major; only its lower triangle is read), in place: the
/// upper triangle is zeroed. `false` when a pivot is not positive and
/// finite (`a` not positive definite to working precision).
pub(crate) fn cholesky(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let rest = &mut a[j * n..];
        let (row_j, below) = rest.split_at_mut(n);
        let s = row_j[j] - dot(&row_j[..j], &row_j[..j]);
        if !(s > 0.0 && s.is_finite()) {
            return false;
        }
        row_j[j] = s.sqrt();
        row_j[j + 1..].fill(0.0);
        for row_i in below.chunks_exact_mut(n) {
            row_i[j] = (row_i[j] - dot(&row_i[..j], &row_j[..j])) / row_j[j];
        }
    }
    true
}

/// `L y = b` for lower triangular `l` (`n x n`), `b` overwritten by `y`.
pub(crate) fn solve_lower(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + n];
        b[i] = (b[i] - dot(&row[..i], &b[..i])) / row[i];
    }
}

/// `L^T x = y` for lower triangular `l` (`n x n`), `b` overwritten by `x`.
pub(crate) fn solve_upper_transposed(l: &[f64], n: usize, b: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// The largest eigenvalue of the symmetric `a` (`n x n`, row-major), by
/// cyclic Jacobi rotations on a copy until the off-diagonal part is below
/// `1e-15` of the whole (a few sweeps at these sizes).
pub(crate) fn largest_eigenvalue(a: &[f64], n: usize) -> f64 {
    let mut m = a.to_vec();
    let total: f64 = m.iter().map(|v| v * v).sum();
    for _sweep in 0..64 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| m[i * n + j] * m[i * n + j])
            .sum();
        let rotated = off > 1e-30 * total;
        if !rotated {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = m[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (m[q * n + q] - m[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (m[k * n + p], m[k * n + q]);
                    m[k * n + p] = c * akp - s * akq;
                    m[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (m[p * n + k], m[q * n + k]);
                    m[p * n + k] = c * apk - s * aqk;
                    m[q * n + k] = s * apk + c * aqk;
                }
            }
        }
    }
    (0..n)
        .map(|i| m[i * n + i])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `sum_i a_i b_i`, in index order.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The standard normal quantile `Phi^-1(p)` for `0 < p < 1`: Acklam's
/// rational approximation (relative error below `1.2e-9`), then one step
/// of Halley's method on `Phi(x) = p` with libm's `erfc`, which brings it
/// to a few units of the last place.
pub(crate) fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.38357751867269e+02,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    const LOW: f64 = 0.02425;
    // The upper half by symmetry: `1 - p` is exact there, and the lower
    // tail's refinement does not cancel.
    if p > 0.5 {
        return -normal_quantile(1.0 - p);
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < LOW {
        tail(libm::sqrt(-2.0 * libm::log(p)))
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    let e = 0.5 * libm::erfc(-x / core::f64::consts::SQRT_2) - p;
    let u = e * libm::sqrt(2.0 * core::f64::consts::PI) * libm::exp(x * x / 2.0);
    x - u / (1.0 + x * u / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_a_known_system() {
        // a = [[4, 2, 0.4], [2, 5, 1], [0.4, 1, 3]], x = (1, -2, 0.5).
        let a = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3).map(|i| dot(&a[i * 3..i * 3 + 3], &x)).collect();
        let mut l = a;
        assert!(cholesky(&mut l, 3));
        assert_eq!((l[1], l[2], l[5]), (0.0, 0.0, 0.0));
        solve_lower(&l, 3, &mut b);
        solve_upper_transposed(&l, 3, &mut b);
        for (got, want) in b.iter().zip(x) {
            assert!((got - want).abs() < 1e-14, "{got} against {want}");
        }
    }

    #[test]
    fn cholesky_refuses_an_indefinite_matrix() {
        let mut a = [1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky(&mut a, 2));
        let mut nan = [f64::NAN, 0.0, 0.0, 1.0];
        assert!(!cholesky(&mut nan, 2));
    }

    #[test]
    fn largest_eigenvalue_of_known_matrices() {
        // [[2, 1], [1, 2]]: eigenvalues 1 and 3.
        assert!((largest_eigenvalue(&[2.0, 1.0, 1.0, 2.0], 2) - 3.0).abs() < 1e-14);
        // A rotation of diag(-5, 0.25, 7) has 7 on top.
        let (c, s) = (0.6_f64, 0.8_f64);
        let q = [c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0];
        let lam = [-5.0, 0.25, 7.0];
        let mut a = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                a[i * 3 + j] = (0..3).map(|k| q[i * 3 + k] * lam[k] * q[j * 3 + k]).sum();
            }
        }
        assert!((largest_eigenvalue(&a, 3) - 7.0).abs() < 1e-13);
        // All negative: the largest is the least negative.
        assert!((largest_eigenvalue(&[-1.0, 0.0, 0.0, -4.0], 2) + 1.0).abs() < 1e-15);
    }

    #[test]
    fn normal_quantile_matches_reference_values() {
        // Reference values: scipy.special.ndtri (Cephes).
        for (p, want) in [
            (0.5, 0.0),
            (0.975, 1.959963984540054),
            (0.025, -1.959963984540054),
            (1e-10, -6.361340902404056),
            (0.999999, 4.753424308817087),
            (0.3, -0.5244005127080409),
        ] {
            let got = normal_quantile(p);
            assert!(
                (got - want).abs() <= 4e-15 * want.abs().max(1.0),
                "Phi^-1({p}) = {got}, want {want}"
            );
        }
    }
}
