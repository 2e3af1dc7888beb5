//! The settings [`Auto`](super::Auto) measures on the problem, and the
//! units they hold in: the centre of its ladder of temperatures, the
//! rungs, and the step size.
//!
//! Every constant of the method has a unit (a length, an energy, or
//! `length^2 / energy` for a step), and holds in the problem's own units:
//! those in which its box is as wide as the paper's Rastrigin's (`10.24`,
//! [`WIDTH`]) and its basins are as curved at their bottoms as that
//! function's minima (`2 + 4π^2`, [`CURVATURE`]). On that problem the
//! units are about those of `x` and `U`, and the constants are the paper's
//! own (`alpha = beta = 1`, `b = 10`); on `c U(x / s)` in `s` times the
//! box they are `s` times the length and `c` times the energy, so the run
//! makes the same decisions.

use crate::float::Float;

/// The convergence rule's tolerance, relative to the spread of `U` at the
/// initial points: a fall smaller than this is rounding.
pub(super) const CONVERGED: f64 = 1e-12;

/// How close to the best, relative to the spread of `U` at the initial
/// points, a chain's basin is the best's for the convergence rule.
pub(super) const AGREE: f64 = 1e-8;
/// The convergence rule also holds after a window over this many rounds
/// in which the best did not fall and every chain's basin was the best's.
pub(super) const AGREED_SHARE: u64 = 6;

/// The inverse temperatures `a` the exact step is tested for, in the
/// problem's units of energy (`a ε`).
pub(super) const A_RANGE: (f64, f64) = (1e-6, 1e6);
/// The steps `alpha h` the exact step is tested for (`alpha = 1`), in the
/// problem's units (`h ε / ℓ^2`).
pub(super) const H_RANGE: (f64, f64) = (1e-8, 50.0);
/// The widest side of the box in the problem's units: the paper's box
/// `[-5.12, 5.12]`.
const WIDTH: f64 = 10.24;
/// The median curvature at the basins' bottoms in the problem's units:
/// that of the paper's Rastrigin at its minima, `2 + 4π^2`.
const CURVATURE: f64 = 2.0 + 4.0 * core::f64::consts::PI * core::f64::consts::PI;

/// The problem's units of length `ℓ` and energy `ε`, in those of the box's
/// unit coordinates and of `U`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Units<F> {
    pub(super) length: F,
    pub(super) energy: F,
}

impl<F: Float> Units<F> {
    /// The units before the basins are measured: the length from the box
    /// (`widest` its widest side), the energy the spread of `values`, the
    /// values at the initial points (reordered), or 1 where they are all
    /// 0 (any energy then, since `c 0 = 0`).
    pub(super) fn start(widest: F, values: &mut [F]) -> Self {
        Self {
            length: widest / F::from_f64(WIDTH),
            energy: spread(values).unwrap_or(F::ONE),
        }
    }

    /// The units once the basins are measured: the energy at which the
    /// median positive `curvature` is [`CURVATURE`]; on a landscape flat at
    /// every probe, the spread of the basins' `values` (reordered), or the
    /// energy before the measurement.
    pub(super) fn measured(self, curvature: Option<F>, values: &mut [F]) -> Self {
        let length = self.length;
        let energy = match curvature {
            Some(k) => k * length * length / F::from_f64(CURVATURE),
            None => spread(values).unwrap_or(self.energy),
        };
        Self { length, energy }
    }

    /// A step `h` in these units (`h ε / ℓ^2`) in the box's unit
    /// coordinates and `U`'s.
    pub(super) fn step(&self, h: F) -> F {
        h * (self.length * self.length / self.energy)
    }
}

/// Values closer than this, relative to their size, are one value: their
/// difference is the rounding of the quenches that ended at them.
const SAME: f64 = 1e-9;

/// The spread of `values` (sorted in place): their interquartile range,
/// or `|median|` where they are one value; `None` where both are 0 or not
/// finite.
pub(super) fn spread<F: Float>(values: &mut [F]) -> Option<F> {
    sort(values);
    let n = values.len();
    let iqr = values[3 * n / 4] - values[n / 4];
    let median = values[n / 2].abs();
    if iqr.is_finite() && iqr > F::from_f64(SAME) * median {
        return Some(iqr);
    }
    (median.is_finite() && median > F::ZERO).then_some(median)
}

/// `a_0 = 1 / IQR` of the quenched values in units of `energy`: a basin
/// one quartile spread above another is `e` times less likely. Where the
/// basins have one value (one basin, or a convex problem), `1 / max(1,
/// |median|)`.
pub(super) fn centre<F: Float>(values: &mut [F], energy: F) -> F {
    sort(values);
    let n = values.len();
    let spread = (values[3 * n / 4] - values[n / 4]) / energy;
    let m = values[n / 2].abs() / energy;
    let size = if m > F::ONE { m } else { F::ONE };
    let a = if spread.is_finite() && spread > F::from_f64(SAME) * size {
        F::ONE / spread
    } else {
        F::ONE / size
    };
    clamp(a, A_RANGE)
}

/// Chain `c`'s rung of `n`: `a_0 exp(ladder (2c / (n - 1) - 1))`, the
/// hottest first (in the problem's units, as `a_0`).
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

/// The median of the positive finite `curvatures` (reordered), if any.
pub(super) fn median_curvature<F: Float>(curvatures: &mut [F]) -> Option<F> {
    let mut m = 0;
    for i in 0..curvatures.len() {
        let k = curvatures[i];
        if k.is_finite() && k > F::ZERO {
            curvatures[m] = k;
            m += 1;
        }
    }
    if m == 0 {
        return None;
    }
    sort(&mut curvatures[..m]);
    Some(curvatures[m / 2])
}

/// `h = scale / L` with `L` the median curvature measured, in the
/// problem's units (where `L` is [`CURVATURE`]), and never above the
/// `longest` step: on a landscape flat at the probes (no curvature
/// measured), that longest step.
pub(super) fn step<F: Float>(curvature: Option<F>, scale: F, longest: F) -> F {
    let h = match curvature {
        Some(_) => scale / F::from_f64(CURVATURE),
        None => longest,
    };
    clamp(if h < longest { h } else { longest }, H_RANGE)
}

/// The longest step, in the problem's units, in a box whose narrowest
/// side is `width` (in the same units): the one whose velocity term
/// `h |y|` (`|y| ~ 1/sqrt(b)` per coordinate) moves a tenth of it.
pub(super) fn longest<F: Float>(width: F) -> F {
    clamp(F::from_f64(0.1 * 10f64.sqrt()) * width, H_RANGE)
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
