//! The settings [`Auto`](super::Auto) measures on the problem: the centre
//! of its ladder of temperatures, the rungs, and the step size.

use crate::float::Float;

/// The convergence rule's tolerance, relative to the spread of `U` at the
/// initial points: a fall smaller than this is rounding.
pub const CONVERGED: f64 = 1e-12;

/// How close to the best, relative to the spread of `U` at the initial
/// points, a chain's basin is the best's for the convergence rule.
pub(super) const AGREE: f64 = 1e-8;
/// The convergence rule also holds after a window over this many rounds
/// in which the best did not fall and every chain's basin was the best's.
pub(super) const AGREED_SHARE: u64 = 6;

/// The inverse temperatures the exact step is tested for.
pub(super) const A_RANGE: (f64, f64) = (1e-6, 1e6);
/// The steps `alpha h` the exact step is tested for (`alpha = 1`).
pub(super) const H_RANGE: (f64, f64) = (1e-8, 50.0);

/// `a_0 = 1 / IQR` of the quenched values: a basin one quartile spread
/// above another is `e` times less likely. Where every basin has the same
/// value (one basin, or a convex problem), `1 / max(1, |median|)`.
pub(super) fn centre<F: Float>(values: &mut [F]) -> F {
    let spread = spread(values);
    let n = values.len();
    let a = if spread.is_finite() && spread > F::ZERO {
        F::ONE / spread
    } else {
        let m = values[n / 2].abs();
        F::ONE / if m > F::ONE { m } else { F::ONE }
    };
    clamp(a, A_RANGE)
}

/// The interquartile range of `values` (sorted in place), or zero where
/// it is not finite.
pub(super) fn spread<F: Float>(values: &mut [F]) -> F {
    sort(values);
    let n = values.len();
    let spread = values[3 * n / 4] - values[n / 4];
    if spread.is_finite() { spread } else { F::ZERO }
}

/// Chain `c`'s rung of `n`: `a_0 exp(ladder (2c / (n - 1) - 1))`, the
/// hottest first.
pub(super) fn rung<F: Float>(a0: F, ladder: F, c: usize, n: usize) -> F {
    clamp(a0 * (ladder * position(c, n)).exp(), A_RANGE)
}

/// Chain `c`'s place on a ladder of `n`: `2c / (n - 1) - 1`, from -1 (the
/// hottest) to 1 (the coldest); 0 for a single chain.
pub(super) fn position<F: Float>(c: usize, n: usize) -> F {
    if n < 2 {
        return F::ZERO;
    }
    F::from_u64(2 * c as u64) / F::from_u64(n as u64 - 1) - F::ONE
}

/// `h = scale / L` with `L` the median of the positive finite curvatures
/// measured, and never above the step whose velocity term `h |y|`
/// (`|y| ~ 1/sqrt(b)` per coordinate) moves a tenth of the box: on a
/// landscape flat at the probes (`L` zero, or the tail of a far well,
/// `1e-30`), that longest step.
pub(super) fn step<F: Float>(curvatures: &mut [F], scale: F, width: F) -> F {
    let longest = longest(width);
    let mut m = 0;
    for i in 0..curvatures.len() {
        let k = curvatures[i];
        if k.is_finite() && k > F::ZERO {
            curvatures[m] = k;
            m += 1;
        }
    }
    let h = if m == 0 {
        longest
    } else {
        sort(&mut curvatures[..m]);
        let h = scale / curvatures[m / 2];
        if h < longest { h } else { longest }
    };
    clamp(h, H_RANGE)
}

/// The longest step in a box whose narrowest side is `width` (unit
/// coordinates): the one whose velocity term `h |y|` (`|y| ~ 1/sqrt(b)`
/// per coordinate) moves a tenth of it.
pub(super) fn longest<F: Float>(width: F) -> F {
    F::from_f64(0.1 * 10f64.sqrt()) * width
}

pub(super) fn clamp<F: Float>(v: F, (lo, hi): (f64, f64)) -> F {
    let (lo, hi) = (F::from_f64(lo), F::from_f64(hi));
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// Insertion sort: a few dozen values, no allocation.
fn sort<F: Float>(v: &mut [F]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j] < v[j - 1] {
            v.swap(j, j - 1);
            j -= 1;
        }
    }
}
