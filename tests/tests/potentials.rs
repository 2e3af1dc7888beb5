//! The built-in potentials (Rastrigin, Quadratic, DoubleWell,
//! Styblinski-Tang, Levy, Ackley): gradients against central differences,
//! the fused `value_and_gradient` against the separate evaluations, f32
//! Rastrigin against f64, and the known minima and minimisers.
//!
//! Every sampler step trusts `∇U`, and `KnownMinimum` is what benchmarks
//! and early stops compare against: a wrong derivative or a wrong minimum
//! would not crash anything, only make the optimiser quietly worse, so they
//! are checked against independent computations here.

use hrla::{
    Ackley, DoubleWell, KnownMinimum, Levy, Potential, Quadratic, Rastrigin, StyblinskiTang,
};
use hrla_tests::prop::config;
use proptest::prelude::*;

// Central differences with step e: (U(x + e) - U(x - e)) / 2e = U'(x) +
// U'''(xi) e^2 / 6, plus a rounding error of about |U| 2^-53 / e. With
// e = 1e-5 on the boxes below, |U'''| <= 300 (Rastrigin: 8 pi^3 = 248;
// Styblinski-Tang: 12 |x| <= 60; double well: 24 |x| <= 72; Levy: about 300)
// gives a truncation error <= 5e-9 and |U| <= 2500 a rounding error <= 3e-8:
// the tolerance 1e-6 + 1e-8 |g| is 30 times the worst case and still far
// below any real error in a derivative (which would be O(1)).
//
// Ackley has a cone-shaped kink at the origin, where its third derivative
// grows like 1/|x|^2: it is checked at |x| >= 0.1, where |U'''| <= 1010
// (measured: about 1010 in one dimension, from the cosine term, and 320 in
// four near |x| = 0.1), so the truncation error is <= 2e-8 (|U| <= 23).

const FD_STEP: f64 = 1e-5;

fn check_gradient<P: Potential<f64, DD>, const DD: usize>(
    p: &P,
    x: [f64; DD],
) -> Result<(), TestCaseError> {
    let mut g = [0.0; DD];
    p.gradient(&x, &mut g);
    let mut g2 = [0.0; DD];
    let v = p.value_and_gradient(&x, &mut g2);
    // The fused evaluation is the separate one, bit for bit.
    prop_assert_eq!(v.to_bits(), p.value(&x).to_bits());
    prop_assert_eq!(g.map(f64::to_bits), g2.map(f64::to_bits));
    for i in 0..DD {
        let (mut xp, mut xm) = (x, x);
        xp[i] += FD_STEP;
        xm[i] -= FD_STEP;
        let fd = (p.value(&xp) - p.value(&xm)) / (xp[i] - xm[i]);
        let tol = 1e-6 + 1e-8 * g[i].abs();
        prop_assert!(
            (fd - g[i]).abs() <= tol,
            "coordinate {}: gradient {} but central difference {} at {:?}",
            i,
            g[i],
            fd,
            x
        );
    }
    Ok(())
}

/// `global_minimum() <= U(x)`, up to the rounding of U (a few ulps of the
/// terms, far below 1e-9 here).
fn check_minimum<P: KnownMinimum<f64, DD>, const DD: usize>(
    p: &P,
    x: [f64; DD],
) -> Result<(), TestCaseError> {
    let m = p.global_minimum();
    prop_assert!(p.value(&x) >= m - 1e-9 * (1.0 + m.abs()), "U({:?}) < U*", x);
    Ok(())
}

fn box4(r: f64) -> impl Strategy<Value = [f64; 4]> {
    prop::array::uniform4(-r..r)
}

/// Fixed seed (reproducible failures).
const SEED: u64 = 0x6872_6c61;

proptest! {
    #![proptest_config(config(400, SEED))]

    #[test]
    fn rastrigin_gradient_and_minimum(x in box4(5.12)) {
        check_gradient(&Rastrigin, x)?;
        check_minimum(&Rastrigin, x)?;
    }

    #[test]
    fn quadratic_gradient_and_minimum(
        x in box4(5.0),
        k in 0.01f64..100.0,
        m in box4(3.0),
    ) {
        let q = Quadratic::new(k, m).unwrap();
        prop_assert_eq!(q.stiffness(), k);
        check_gradient(&q, x)?;
        check_minimum(&q, x)?;
    }

    #[test]
    fn double_well_gradient_and_minimum(x in box4(3.0)) {
        check_gradient(&DoubleWell, x)?;
        check_minimum(&DoubleWell, x)?;
    }

    #[test]
    fn styblinski_tang_gradient_and_minimum(x in box4(5.0)) {
        check_gradient(&StyblinskiTang, x)?;
        check_minimum(&StyblinskiTang, x)?;
    }

    /// On Ackley's usual domain [-32.768, 32.768]^D, and near the funnel,
    /// away from the kink at the origin.
    #[test]
    fn ackley_gradient_and_minimum(
        x in box4(32.768),
        near in box4(1.0),
        x1 in -32.768f64..32.768,
    ) {
        let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt();
        prop_assume!(norm(&x) >= 0.1 && norm(&near) >= 0.1 && x1.abs() >= 0.1);
        check_gradient(&Ackley, x)?;
        check_minimum(&Ackley, x)?;
        check_gradient(&Ackley, near)?;
        check_minimum(&Ackley, near)?;
        check_gradient(&Ackley, [x1])?;
        check_minimum(&Ackley, [x1])?;
    }

    #[test]
    fn levy_gradient_and_minimum(x in box4(10.0), x1 in -10.0f64..10.0) {
        check_gradient(&Levy, x)?;
        check_minimum(&Levy, x)?;
        // D = 1 has only the first and last terms.
        check_gradient(&Levy, [x1])?;
        check_minimum(&Levy, [x1])?;
    }

    /// f32 Rastrigin against the f64 one at the same (widened) point: the
    /// argument 2 pi x carries a relative rounding of about 2^-23
    /// (|2 pi x| <= 33, so up to 4e-6 absolute), which moves sin and cos by
    /// as much, hence the gradient by up to 2 pi * 4e-6 = 2.5e-5 and the
    /// value by 4 * 4e-6 = 1.6e-5; the squares and sums add a relative 2^-24
    /// per term (|U| <= 4 * 28.3). Tolerance 1e-4 + 1e-6 |.|.
    #[test]
    fn rastrigin_f32_matches_f64(x in prop::array::uniform4(-5.12f32..5.12)) {
        let x64 = x.map(f64::from);
        let mut g32 = [0.0f32; 4];
        let mut g64 = [0.0f64; 4];
        let v32 = Rastrigin.value_and_gradient(&x, &mut g32);
        let v64 = Rastrigin.value_and_gradient(&x64, &mut g64);
        prop_assert!((f64::from(v32) - v64).abs() <= 1e-4 + 1e-6 * v64.abs(),
            "value {} vs {}", v32, v64);
        for i in 0..4 {
            prop_assert!((f64::from(g32[i]) - g64[i]).abs() <= 1e-4 + 1e-6 * g64[i].abs(),
                "gradient {} vs {}", g32[i], g64[i]);
        }
        prop_assert!(v32 >= 0.0);
        // Central difference in f32 with e = 2^-6: truncation <= 248 e^2/6
        // = 1e-2, rounding <= |U| 2^-24 / e = 5e-4 for |U| <= 150.
        let e = 1.0 / 64.0f32;
        for i in 0..4 {
            let (mut xp, mut xm) = (x, x);
            xp[i] += e;
            xm[i] -= e;
            let fd = (Rastrigin.value(&xp) - Rastrigin.value(&xm)) / (xp[i] - xm[i]);
            prop_assert!((fd - g32[i]).abs() <= 2e-2 + 1e-4 * g32[i].abs(),
                "f32 FD {} vs gradient {}", fd, g32[i]);
        }
    }
}

/// `global_minimum()` is `U(global_minimiser())`, and the minimiser is a
/// stationary point. Exact where the value is computed exactly; Levy's
/// `sin^2(pi w_1)` at w_1 = 1 is sin(fl(pi))^2 = 1.5e-32, not 0, and
/// Styblinski-Tang's minimum is a rounded constant times D.
#[test]
fn known_minima_are_values_at_minimisers() {
    fn check<P: KnownMinimum<f64, DD>, const DD: usize>(p: &P, name: &str, tol: f64) {
        let x = p.global_minimiser();
        let m = p.global_minimum();
        let v = p.value(&x);
        assert!((v - m).abs() <= tol, "{name}: U(x*) = {v:e}, U* = {m:e}");
        let mut g = [0.0; DD];
        p.gradient(&x, &mut g);
        assert!(
            g.iter().all(|gi| gi.abs() <= 1e-12),
            "{name}: ∇U(x*) = {g:?}"
        );
    }
    check::<_, 10>(&Rastrigin, "Rastrigin", 0.0);
    check::<_, 1>(&Rastrigin, "Rastrigin", 0.0);
    check(
        &Quadratic::new(3.0, [1.0, -2.0, 0.5]).unwrap(),
        "Quadratic",
        0.0,
    );
    check::<_, 5>(&DoubleWell, "DoubleWell", 0.0);
    check::<_, 1>(&StyblinskiTang, "StyblinskiTang", 1e-13);
    check::<_, 10>(&StyblinskiTang, "StyblinskiTang", 1e-12);
    check::<_, 1>(&Levy, "Levy", 1e-30);
    check::<_, 10>(&Levy, "Levy", 1e-30);
    check::<_, 1>(&Ackley, "Ackley", 0.0);
    check::<_, 10>(&Ackley, "Ackley", 0.0);
    // Ackley at its kink: U(0) = 0 and the gradient returned is 0, exactly,
    // in f64 and f32.
    let mut g = [1.0f64; 4];
    assert_eq!(Ackley.value_and_gradient(&[0.0; 4], &mut g), 0.0);
    assert_eq!(g, [0.0; 4]);
    let mut g = [1.0f32; 3];
    assert_eq!(Ackley.value_and_gradient(&[0.0; 3], &mut g), 0.0);
    assert_eq!(g, [0.0; 3]);
    assert_eq!(KnownMinimum::<f32, 3>::global_minimum(&Ackley), 0.0);
    assert_eq!(KnownMinimum::<f64, 4>::global_minimiser(&Ackley), [0.0; 4]);
    // f32 Rastrigin: exactly 0 at 0.
    let v: f32 = Rastrigin.value(&[0.0f32; 4]);
    assert_eq!(v, 0.0);
    assert_eq!(KnownMinimum::<f32, 4>::global_minimum(&Rastrigin), 0.0);

    // Styblinski-Tang's constant is the root of 4x^3 - 32x + 5: Newton from
    // -2.9 in f64 lands within 2 ulps of it.
    let mut r = -2.9f64;
    for _ in 0..50 {
        r -= (4.0 * r * r * r - 32.0 * r + 5.0) / (12.0 * r * r - 32.0);
    }
    let x: [f64; 1] = StyblinskiTang.global_minimiser();
    assert!(
        (x[0] - r).abs() <= 2.0 * f64::EPSILON * 3.0,
        "{} vs {r}",
        x[0]
    );
    // And it is the global minimum of the 1-D function: scan [-5, 5].
    let m1 = KnownMinimum::<f64, 1>::global_minimum(&StyblinskiTang);
    for i in 0..=100_000 {
        let t = -5.0 + 1e-4 * i as f64;
        assert!(StyblinskiTang.value(&[t]) >= m1 - 1e-12);
    }
}
