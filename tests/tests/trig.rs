//! The fused `sin(2πx)` / `1 - cos(2πx)` of the built-in Rastrigin against an
//! independent double-double evaluation, through the public potential: the
//! gradient `2x + 2π sin(2πx)` and the value `x^2 + 1 - cos(2πx)` of 1-D
//! Rastrigin must be within a few ulps of the exact values at the given x.
//!
//! Rastrigin is the benchmark potential, and for speed its sine comes from
//! the kernel's own polynomial and argument reduction rather than libm:
//! its accuracy is checked against a reference that shares nothing with
//! it, over the paper's domain, near the zeros and far out.

use hrla::{Float, Potential, Rastrigin};
use hrla_tests::dd::Dd;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// 2π in double-double.
const TAU: Dd = Dd {
    hi: std::f64::consts::TAU,
    lo: 2.4492935982947064e-16,
};

/// `(sin(2πx), 1 - cos(2πx))` in double-double: exact reduction to
/// `r = x - k/4`, Taylor series in double-double, quadrant by `k mod 4`.
fn reference(x: f64) -> (Dd, Dd) {
    let k = (4.0 * x).round();
    let r = Dd::new(x) - Dd::new(k) * Dd::new(0.25);
    let t = TAU * r;
    let t2 = t * t;
    // sin t and 1 - cos t by their series (|t| <= π/4: 30 terms is plenty).
    let (mut s, mut term) = (t, t);
    let (mut omc, mut cterm) = (Dd::ZERO, Dd::ONE);
    for n in 1..30 {
        term = -(term * t2 / Dd::new(((2 * n) * (2 * n + 1)) as f64));
        s = s + term;
        cterm = -(cterm * t2 / Dd::new(((2 * n - 1) * (2 * n)) as f64));
        omc = omc - cterm;
    }
    let c = Dd::ONE - omc;
    match (k as i64).rem_euclid(4) {
        0 => (s, omc),
        1 => (c, Dd::ONE + s),
        2 => (-s, Dd::ONE + c),
        _ => (-c, Dd::ONE - s),
    }
}

/// `|got - want|` in units of `scale * epsilon / 2` (0 when both are
/// exactly 0), `epsilon` being the machine epsilon of `got`'s type.
fn ulps(got: f64, want: Dd, scale: f64, epsilon: f64) -> f64 {
    let err = (Dd::new(got) - want).to_f64();
    if err == 0.0 {
        0.0
    } else {
        (err / (scale * epsilon / 2.0)).abs()
    }
}

/// Points: uniform in [-6, 6] (the paper's domain and beyond), near the
/// integers and half-integers (where sine or 1 - cos vanish), and large.
fn points() -> Vec<f64> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let mut xs = Vec::new();
    for _ in 0..200_000 {
        xs.push(12.0 * u() - 6.0);
    }
    for k in -12..=12 {
        for e in [1e-1, 1e-3, 1e-6, 1e-9, 1e-12, 1e-15] {
            xs.push(k as f64 / 2.0 + e * (u() - 0.5));
        }
    }
    for _ in 0..10_000 {
        xs.push((u() - 0.5) * 2e6);
    }
    xs.extend([
        0.0,
        -0.0,
        0.125,
        0.375,
        1e-300,
        5e-324,
        2f64.powi(48) + 0.25,
    ]);
    xs
}

/// 1-D Rastrigin in `F` at every point of `points()` rounded to `F` and
/// below `limit` in magnitude, against the exact values at the rounded
/// point (widened exactly to f64): the gradient within 8 ulps (of `F`,
/// `epsilon` its machine epsilon) of `|2x| + |2π sin|`, the value within 8
/// ulps of `x^2 + (1 - cos)` (a sum of non-negative terms).
fn check_trig<F: Float>(label: &str, epsilon: f64, limit: f64) {
    let mut worst = (0.0f64, 0.0f64);
    for x in points() {
        let xf = F::from_f64(x);
        if xf.to_f64().abs() >= limit {
            continue;
        }
        let x = xf.to_f64();
        let (s, omc) = reference(x);
        let mut g = [F::ZERO];
        let u = Rastrigin.value_and_gradient(&[xf], &mut g);
        let g_want = Dd::new(2.0) * Dd::new(x) + TAU * s;
        let u_want = Dd::new(x) * Dd::new(x) + omc;
        let g_scale = (2.0 * x).abs() + (TAU * s).to_f64().abs();
        let eg = ulps(g[0].to_f64(), g_want, g_scale, epsilon);
        let eu = ulps(u.to_f64(), u_want, u_want.to_f64(), epsilon);
        assert!(eg <= 8.0, "{label} gradient at {x:e}: {eg:.1} ulp");
        assert!(eu <= 8.0, "{label} value at {x:e}: {eu:.1} ulp");
        worst = (worst.0.max(eg), worst.1.max(eu));
    }
    println!(
        "{label} worst: gradient {:.2} ulp, value {:.2} ulp",
        worst.0, worst.1
    );
}

/// f64, every point. Bound: fdlibm's polynomials are within 2^-58 of sin
/// and cos on [-π/4, π/4]; `t = π r` rounds once (under 1 ulp with π's own
/// rounding), Horner's rule adds about 1.5, the double-angle product `2 s c`
/// or square `2 w^2` 1.5 more; the final sums add 1 ulp each. Measured
/// worst: gradient 3.8 ulp, value 4.7 ulp.
#[test]
fn rastrigin_f64_trig_is_accurate() {
    check_trig::<f64>("f64", f64::EPSILON, f64::INFINITY);
}

/// f32: the same bounds in f32 ulps (measured worst: gradient 4.0, value
/// 5.8). The fast path ends at |x| = 2^20, beyond which libm's sincosf of
/// the rounded 2πx takes over (and the bound is relative to |2x|, which
/// then dominates): those points are left to
/// `huge_coordinates_take_the_fallback`.
#[test]
fn rastrigin_f32_trig_is_accurate() {
    check_trig::<f32>("f32", f64::from(f32::EPSILON), 1048576.0);
}

/// Coordinates beyond the polynomial's range (`|x| >= 2^49` in f64, `2^20`
/// in f32) take the cold fallback: finite results of the right size, and the
/// other coordinates of the same point keep exactly the bits they have in a
/// point without the huge one (the fallback patches only its coordinate).
#[test]
fn huge_coordinates_take_the_fallback() {
    fn check<F: Float>(huge: f64) {
        let f = F::from_f64;
        let x = [f(0.3), f(huge), f(-0.7), f(2.2), f(-huge)];
        let plain = [f(0.3), f(0.0), f(-0.7), f(2.2), f(0.0)];
        let (mut g, mut g_plain) = ([f(0.0); 5], [f(0.0); 5]);
        let u = Rastrigin.value_and_gradient(&x, &mut g);
        Rastrigin.value_and_gradient(&plain, &mut g_plain);
        for j in [0, 2, 3] {
            assert_eq!(
                g[j].to_bits_u64(),
                g_plain[j].to_bits_u64(),
                "coordinate {j}"
            );
        }
        for j in [1, 4] {
            let two_x = 2.0 * x[j].to_f64();
            assert!(
                (g[j].to_f64() - two_x).abs() <= 2.0 * two_x.abs() * 1e-6 + 6.3,
                "{huge:e}"
            );
        }
        let x2 = 2.0 * huge * huge;
        assert!(
            u.is_finite() && (u.to_f64() - x2).abs() <= x2 * 1e-6 + 10.0,
            "{huge:e}: {u:?}"
        );
    }
    for huge in [562949953421312.0, 1e20, 1e150] {
        check::<f64>(huge);
    }
    for huge in [1048576.0, 3e7, 1e18] {
        check::<f32>(huge);
    }
}
