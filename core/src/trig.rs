//! `sin(2πx)` and `1 - cos(2πx)` for a whole point at once: the trigonometry
//! of Rastrigin, fused and branch-free so that the compiler vectorises it.
//!
//! Reduction: `n = round(4x)` and `r = x - n/4` (exact: `n/4` is the
//! nearest quarter to `x`, a multiple of `ulp(x)`, and `|r| <= 1/8`), so
//! `2πx = nπ/2 + 2πr` with `|2πr| <= π/4`. There `sin(2πr)` and
//! `cos(2πr)` are their Taylor polynomials in `r` (coefficients
//! `(2π)^k / k!`, rounded once from 50-digit values), truncated where the
//! next term is below a tenth of an ulp; the quadrant `n mod 4` then swaps
//! and negates. `1 - cos(2πr)` comes from the cosine's series without its
//! constant term, so it keeps full relative accuracy near the integers. Only IEEE additions and multiplications are used, so the
//! result is bit-identical on every target. Arguments too large for the
//! rounding trick (`|x| >= 2^49` in f64, `2^20` in f32) or not finite take
//! [`Float::fast_sin_cos`] of the rounded `2πx` (libm, or micromath with
//! that feature in f32). The host test `trig.rs` bounds the error against a
//! double-double evaluation.

use crate::float::Float;

/// `(-1)^k (2π)^(2k+1) / (2k+1)!`, k = 0..8.
pub(crate) const SIN_2PI: [f64; 9] = [
    core::f64::consts::TAU,
    -41.34170224039976,
    81.60524927607506,
    -76.70585975306139,
    42.058693944897655,
    -15.09464257682299,
    3.819952584848282,
    -0.7181223017785006,
    0.10422916220813984,
];

/// `(-1)^k (2π)^(2k) / (2k)!`, k = 0..8.
pub(crate) const COS_2PI: [f64; 9] = [
    1.0,
    -19.739208802178716,
    64.9393940226683,
    -85.45681720669373,
    60.24464137187666,
    -26.4262567833744,
    7.903536371318469,
    -1.714390711088672,
    0.28200596845579123,
];

/// `sum_k coef[k] r2^k` by Horner's rule (`coef` non-empty).
#[inline(always)]
fn horner<F: Float>(coef: &[f64], r2: F) -> F {
    let (last, rest) = coef.split_last().expect("non-empty");
    rest.iter()
        .rev()
        .fold(F::from_f64(*last), |acc, &c| acc * r2 + F::from_f64(c))
}

/// Writes `sin(2π x_i)` into `s` and `1 - cos(2π x_i)` into `omc`, the
/// latter without cancellation near the integers (where Rastrigin's value
/// is small and must stay accurate).
#[inline(always)]
pub(crate) fn sin_omc_2pi<F: Float, const D: usize>(x: &[F; D], s: &mut [F; D], omc: &mut [F; D]) {
    let magic = F::ROUND_MAGIC;
    let quarter = F::from_f64(0.25);
    let four = F::from_f64(4.0);
    let (sin_terms, cos_terms) = F::TRIG_TERMS;
    let mut all_small = true;
    for ((&xi, si), oi) in x.iter().zip(s.iter_mut()).zip(omc.iter_mut()) {
        all_small &= xi.abs() < F::TRIG_FAST_LIMIT;
        // Round to nearest by the magic-number trick: exact for |4x| below
        // half the magic number, the fast-path limit.
        let n = (four * xi + magic) - magic;
        let r = xi - n * quarter;
        // q = n mod 4 in -2..=2, from m = round(n/4).
        let m = (n * quarter + magic) - magic;
        let q = n - four * m;
        let r2 = r * r;
        let sr = r * horner(&SIN_2PI[..sin_terms], r2);
        // cos(2πr) = 1 - omc_r, with omc_r = -r2 (c1 + c2 r2 + ...) free of
        // the cancellation of 1 - cos.
        let omc_r = -(r2 * horner(&COS_2PI[1..cos_terms], r2));
        let cr = F::ONE - omc_r;
        let (sin, omc) = if q == F::ZERO {
            (sr, omc_r)
        } else if q == F::ONE {
            (cr, F::ONE + sr)
        } else if q == -F::ONE {
            (-cr, F::ONE - sr)
        } else {
            // q = ±2: cos = -cr is near -1, so 1 - cos = 2 - omc_r is safe.
            (-sr, F::TWO - omc_r)
        };
        *si = sin;
        *oi = omc;
    }
    if !all_small {
        for ((&xi, si), oi) in x.iter().zip(s.iter_mut()).zip(omc.iter_mut()) {
            let small = xi.abs() < F::TRIG_FAST_LIMIT;
            if !small {
                let (sv, cv) = (F::from_f64(core::f64::consts::TAU) * xi).fast_sin_cos();
                *si = sv;
                *oi = one_minus_cos(sv, cv);
            }
        }
    }
}

/// `1 - cos t` from `(sin t, cos t)` without cancellation near `cos t = 1`.
#[inline(always)]
fn one_minus_cos<F: Float>(s: F, c: F) -> F {
    if c > F::ZERO {
        s * s / (F::ONE + c)
    } else {
        F::ONE - c
    }
}
