//! Potentials `U: R^D -> R` to minimise, and the built-in benchmarks.

use crate::error::{Error, finite, positive};
use crate::float::Float;
use crate::trig;

/// A smooth potential `U` on `R^D` with its gradient.
///
/// Implement [`Potential::value`] and [`Potential::gradient`]; override
/// [`Potential::value_and_gradient`] when the two share work (the optimiser
/// only calls that one, once per chain and step). A non-finite value or
/// gradient is allowed: the optimiser marks the chain as diverged.
pub trait Potential<F: Float, const D: usize> {
    /// `U(x)`.
    fn value(&self, x: &[F; D]) -> F;

    /// Writes `∇U(x)` into `grad`.
    fn gradient(&self, x: &[F; D], grad: &mut [F; D]);

    /// Writes `∇U(x)` into `grad` and returns `U(x)`.
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        self.gradient(x, grad);
        self.value(x)
    }
}

/// A potential whose global minimum is known: for tests and benchmarks.
pub trait KnownMinimum<F: Float, const D: usize>: Potential<F, D> {
    /// The global minimum `U*`.
    fn global_minimum(&self) -> F;
    /// A global minimiser `x*` (one of them, when there are several).
    fn global_minimiser(&self) -> [F; D];
}

/// `2π`, rounded once to `F`.
#[inline(always)]
fn tau<F: Float>() -> F {
    F::from_f64(core::f64::consts::TAU)
}

/// Rastrigin in the paper's form,
/// `U(x) = D + |x|^2 - sum_i cos(2π x_i)`, `∇U(x) = 2x + 2π sin(2π x)`.
///
/// Global minimum `U* = 0` at `x* = 0`; a local minimum near every integer
/// point. The value is computed as `sum_i x_i^2 + (1 - cos 2π x_i)` with the
/// bracket formed without cancellation (as `2 sin^2(πx_i)` or
/// `2 cos^2(πx_i)`), so it is accurate near the minimum even in f32. The sine
/// and `1 - cos` come from a vectorisable polynomial evaluation, one 128-bit
/// vector of coordinates at a time (256-bit with AVX), after an exact
/// reduction of `x` modulo 1/2 (within a few ulps of the exact values;
/// `Float::fast_sin_cos` only for `|x| >= 2^49`, or `2^20` in f32). The sum
/// runs in one partial sum per 128-bit lane, added pairwise at the end, so
/// the bits do not depend on the vector width.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rastrigin;

impl<F: Float, const D: usize> Potential<F, D> for Rastrigin {
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        self.value_and_gradient(x, grad);
    }

    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        // Constant choices, folded away: blocks of one 256-bit vector where
        // the target has them (AVX) and the point fills one, else of one
        // 128-bit vector, single coordinates without vectors (padding would
        // only waste work there). The sum's lanes are the same on every
        // target, so the value's bits are too.
        let l = trig::lanes::<F>();
        match (l, trig::VECTORS, trig::WIDE && D >= 2 * l) {
            (2, true, true) => rastrigin::<F, D, 4, 2>(x, grad),
            (2, true, false) => rastrigin::<F, D, 2, 2>(x, grad),
            (2, false, _) => rastrigin::<F, D, 1, 2>(x, grad),
            (_, true, true) => rastrigin::<F, D, 8, 4>(x, grad),
            (_, true, false) => rastrigin::<F, D, 4, 4>(x, grad),
            (_, false, _) => rastrigin::<F, D, 1, 4>(x, grad),
        }
    }
}

/// Rastrigin's value and gradient, `B` coordinates at a time (`B` is 1, `L`
/// or `2L`; a tail shorter than `B` goes by blocks of `min(B, L)`), the
/// value summed in `L` lanes.
#[inline(always)]
fn rastrigin<F: Float, const D: usize, const B: usize, const L: usize>(
    x: &[F; D],
    grad: &mut [F; D],
) -> F {
    let mut sum = Polynomial {
        lanes: [F::ZERO; L],
        all_small: true,
    };
    // With B = 2L, the tail past the last full block goes by blocks of L;
    // otherwise the blocks of B cover everything, a short tail padded.
    let head = if B > L { D / B * B } else { D };
    for_each_block::<F, B, _>(&x[..head], &mut grad[..head], 0, &mut sum);
    if head < D {
        for_each_block::<F, L, _>(&x[head..], &mut grad[head..], head, &mut sum);
    }
    if sum.all_small {
        sum_lanes(sum.lanes)
    } else {
        rastrigin_large::<F, D, L>(x, grad)
    }
}

/// [`rastrigin`] again, with the trigonometry of huge or non-finite
/// coordinates from [`Float::fast_sin_cos`]: out of line, so that it costs
/// the hot path neither code nor stack; by blocks of one coordinate, the
/// lanes' sums being the same for every block width.
#[cold]
#[inline(never)]
fn rastrigin_large<F: Float, const D: usize, const L: usize>(x: &[F; D], grad: &mut [F; D]) -> F {
    let mut sum = Fallback {
        lanes: [F::ZERO; L],
    };
    for_each_block::<F, 1, _>(x, grad, 0, &mut sum);
    sum_lanes(sum.lanes)
}

/// What to do with each block of [`for_each_block`]: a trait rather than a
/// closure, so that the block's work is always inlined into the loop (a
/// closure was sometimes left out of line, one call per block, 15% of a
/// step in the reproduction tool) and one visitor serves blocks of any width.
trait Visit<F> {
    /// Block of `W` coordinates, the first being coordinate `j0`.
    fn visit<const W: usize>(&mut self, j0: usize, x: &[F; W], grad: &mut [F; W]);
}

/// The polynomial path: gradients and lanes, and whether every coordinate
/// was in its range (else the caller starts again with [`Fallback`]).
struct Polynomial<F, const L: usize> {
    lanes: [F; L],
    all_small: bool,
}

impl<F: Float, const L: usize> Visit<F> for Polynomial<F, L> {
    #[inline(always)]
    fn visit<const W: usize>(&mut self, j0: usize, x: &[F; W], grad: &mut [F; W]) {
        self.all_small &= trig::all_small(x);
        let (s, omc) = trig::block(x);
        accumulate(j0, x, grad, &s, &omc, &mut self.lanes);
    }
}

/// The polynomial patched by `Float::fast_sin_cos` where out of its range.
struct Fallback<F, const L: usize> {
    lanes: [F; L],
}

impl<F: Float, const L: usize> Visit<F> for Fallback<F, L> {
    #[inline(always)]
    fn visit<const W: usize>(&mut self, j0: usize, x: &[F; W], grad: &mut [F; W]) {
        let (mut s, mut omc) = trig::block(x);
        trig::patch_large(x, &mut s, &mut omc);
        accumulate(j0, x, grad, &s, &omc, &mut self.lanes);
    }
}

/// Visits the blocks of `B` coordinates, `x[0]` being coordinate `first` of
/// the point, as fixed arrays (which the compiler vectorises); a short tail
/// is padded with zeros and its gradient copied back.
#[inline(always)]
fn for_each_block<F: Float, const B: usize, V: Visit<F>>(
    x: &[F],
    grad: &mut [F],
    first: usize,
    v: &mut V,
) {
    let mut xs = x.chunks_exact(B);
    let mut gs = grad.chunks_exact_mut(B);
    for (c, (xc, gc)) in (&mut xs).zip(&mut gs).enumerate() {
        let mut gb = [F::ZERO; B];
        v.visit(first + c * B, &core::array::from_fn(|k| xc[k]), &mut gb);
        gc.copy_from_slice(&gb);
    }
    let tail = xs.remainder();
    if !tail.is_empty() {
        let mut gb = [F::ZERO; B];
        v.visit(
            first + x.len() - tail.len(),
            &trig::pad::<F, B>(tail),
            &mut gb,
        );
        let gc = gs.into_remainder();
        gc.copy_from_slice(&gb[..gc.len()]);
    }
}

/// Gradients of a block, and its terms `x^2 + 1 - cos(2πx)` into one partial
/// sum per lane (coordinate `j` into lane `j mod L`), so that the additions
/// vectorise and do not wait on one another.
#[inline(always)]
fn accumulate<F: Float, const B: usize, const L: usize>(
    j0: usize,
    x: &[F; B],
    grad: &mut [F; B],
    s: &[F; B],
    omc: &[F; B],
    lanes: &mut [F; L],
) {
    for k in 0..B {
        // Padding adds x^2 + omc = 0 exactly.
        lanes[(j0 + k) % L] += x[k] * x[k] + omc[k];
        grad[k] = F::TWO * x[k] + tau::<F>() * s[k];
    }
}

/// The lanes summed pairwise (`L` a power of two).
#[inline(always)]
fn sum_lanes<F: Float, const L: usize>(mut lanes: [F; L]) -> F {
    let mut width = L;
    while width > 1 {
        width /= 2;
        for k in 0..width {
            lanes[k] = lanes[2 * k] + lanes[2 * k + 1];
        }
    }
    lanes[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    type Evaluation<F, const D: usize> = fn(&[F; D], &mut [F; D]) -> F;

    /// Blocks of one coordinate (targets without vectors), of a 128-bit
    /// vector and of a 256-bit one (AVX), and the fallback's loop, give the
    /// same bits, value and gradient, in every dimension: the cross-target
    /// bit-identity of Rastrigin rests on it.
    fn same_bits<F: Float, const D: usize, const L: usize, const L2: usize>() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..500 {
            let x: [F; D] = core::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                F::from_f64((state >> 11) as f64 / (1u64 << 53) as f64 * 12.0 - 6.0)
            });
            let mut g1 = [F::ZERO; D];
            let u1 = rastrigin::<F, D, 1, L>(&x, &mut g1);
            let widths: [Evaluation<F, D>; 3] = [
                rastrigin::<F, D, L, L>,
                rastrigin::<F, D, L2, L>,
                rastrigin_large::<F, D, L>,
            ];
            for run in widths {
                let mut g = [F::ZERO; D];
                assert_eq!(u1.to_bits_u64(), run(&x, &mut g).to_bits_u64());
                for (a, b) in g1.iter().zip(&g) {
                    assert_eq!(a.to_bits_u64(), b.to_bits_u64());
                }
            }
        }
    }

    #[test]
    fn block_width_does_not_change_bits() {
        same_bits::<f64, 1, 2, 4>();
        same_bits::<f64, 2, 2, 4>();
        same_bits::<f64, 3, 2, 4>();
        same_bits::<f64, 4, 2, 4>();
        same_bits::<f64, 5, 2, 4>();
        same_bits::<f64, 10, 2, 4>();
        same_bits::<f64, 17, 2, 4>();
        same_bits::<f32, 1, 4, 8>();
        same_bits::<f32, 2, 4, 8>();
        same_bits::<f32, 3, 4, 8>();
        same_bits::<f32, 8, 4, 8>();
        same_bits::<f32, 10, 4, 8>();
        same_bits::<f32, 17, 4, 8>();
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Rastrigin {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::ZERO; D]
    }
}

/// The isotropic quadratic `U(x) = (k/2) |x - m|^2` with stiffness `k > 0`.
///
/// Its Gibbs law `exp(-a U)` is `N(m, I / (a k))`, and every sampler's step
/// is linear in the state, so the moments of long runs can be checked
/// exactly. Global minimum `U* = 0` at `x* = m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadratic<F, const D: usize> {
    stiffness: F,
    centre: [F; D],
}

impl<F: Float, const D: usize> Quadratic<F, D> {
    /// `k` finite and > 0, `m` finite.
    pub fn new(stiffness: F, centre: [F; D]) -> Result<Self, Error> {
        let stiffness = positive("stiffness", stiffness)?;
        for &m in &centre {
            finite("centre", m)?;
        }
        Ok(Self { stiffness, centre })
    }

    /// The stiffness `k`.
    pub fn stiffness(&self) -> F {
        self.stiffness
    }
}

impl<F: Float, const D: usize> Potential<F, D> for Quadratic<F, D> {
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        for ((gi, &xi), &mi) in grad.iter_mut().zip(x).zip(&self.centre) {
            *gi = self.stiffness * (xi - mi);
        }
    }

    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        // Sum (k r) r rather than k |r|^2: with a tiny k and a huge r the
        // latter is 0 * inf = NaN, the former the finite true value.
        let mut kr2 = F::ZERO;
        for ((gi, &xi), &mi) in grad.iter_mut().zip(x).zip(&self.centre) {
            let r = xi - mi;
            *gi = self.stiffness * r;
            kr2 += *gi * r;
        }
        F::HALF * kr2
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Quadratic<F, D> {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        self.centre
    }
}

/// The separable double well `U(x) = sum_i (x_i^2 - 1)^2`,
/// `∇U(x) = 4 x (x^2 - 1)`.
///
/// `U* = 0` at the `2^D` points with every `x_i = ±1`; a saddle of height 1
/// per coordinate at `x_i = 0`. In one dimension its Gibbs law is a
/// two-humped density, the test case for the invariant-law test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DoubleWell;

impl<F: Float, const D: usize> Potential<F, D> for DoubleWell {
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        self.value_and_gradient(x, grad);
    }

    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        let mut u = F::ZERO;
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            let w = xi * xi - F::ONE;
            *gi = F::from_f64(4.0) * xi * w;
            u += w * w;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for DoubleWell {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    /// `(1, ..., 1)`, one of the `2^D` minimisers.
    fn global_minimiser(&self) -> [F; D] {
        [F::ONE; D]
    }
}

/// The root of `4x^3 - 32x + 5 = 0` in `(-3, -2.5)`: the Styblinski–Tang
/// minimiser of one coordinate (computed to 40 digits offline).
const STYBLINSKI_TANG_X: f64 = -2.903_534_027_771_177;
/// `(x^4 - 16x^2 + 5x) / 2` at that root.
const STYBLINSKI_TANG_U: f64 = -39.166_165_703_771_41;

/// Styblinski–Tang, `U(x) = (1/2) sum_i (x_i^4 - 16 x_i^2 + 5 x_i)`.
///
/// Global minimum `U* = -39.166165703771415 D` at
/// `x* = (-2.9035340277711771, ...)`; `2^D - 1` other local minima with a
/// coordinate near `+2.7468`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StyblinskiTang;

impl<F: Float, const D: usize> Potential<F, D> for StyblinskiTang {
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        self.value_and_gradient(x, grad);
    }

    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        let (c16, c5) = (F::from_f64(16.0), F::from_f64(5.0));
        let mut u = F::ZERO;
        for (&xi, gi) in x.iter().zip(grad.iter_mut()) {
            let x2 = xi * xi;
            *gi = F::TWO * xi * x2 - c16 * xi + F::from_f64(2.5);
            u += (x2 * x2 - c16 * x2 + c5 * xi) * F::HALF;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for StyblinskiTang {
    fn global_minimum(&self) -> F {
        F::from_f64(STYBLINSKI_TANG_U * D as f64)
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::from_f64(STYBLINSKI_TANG_X); D]
    }
}

/// Levy's function, with `w_i = 1 + (x_i - 1)/4`:
///
/// ```text
/// U(x) = sin^2(π w_1)
///      + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(π w_i + 1))
///      + (w_D - 1)^2 (1 + sin^2(2π w_D))
/// ```
///
/// Global minimum `U* = 0` at `x* = (1, ..., 1)`; many local minima.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Levy;

impl<F: Float, const D: usize> Potential<F, D> for Levy {
    fn value(&self, x: &[F; D]) -> F {
        let mut grad = [F::ZERO; D];
        self.value_and_gradient(x, &mut grad)
    }

    fn gradient(&self, x: &[F; D], grad: &mut [F; D]) {
        self.value_and_gradient(x, grad);
    }

    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        if D == 0 {
            return F::ZERO;
        }
        let quarter = F::from_f64(0.25);
        let ten = F::from_f64(10.0);
        let pi = F::PI;
        let w = |xi: F| F::ONE + (xi - F::ONE) * quarter;
        // dU/dx_i = dU/dw_i / 4.
        let (s1, c1) = (pi * w(x[0])).fast_sin_cos();
        let mut u = s1 * s1;
        grad.fill(F::ZERO);
        grad[0] = F::TWO * pi * s1 * c1 * quarter;
        for i in 0..D {
            let wi = w(x[i]);
            let d = wi - F::ONE;
            let (term, dterm) = if i + 1 < D {
                let (s, c) = (pi * wi + F::ONE).fast_sin_cos();
                let bracket = F::ONE + ten * s * s;
                (
                    d * d * bracket,
                    F::TWO * d * bracket + d * d * ten * F::TWO * s * c * pi,
                )
            } else {
                let (s, c) = (F::TWO * pi * wi).fast_sin_cos();
                let bracket = F::ONE + s * s;
                (
                    d * d * bracket,
                    F::TWO * d * bracket + d * d * F::TWO * s * c * F::TWO * pi,
                )
            };
            u += term;
            grad[i] += dterm * quarter;
        }
        u
    }
}

impl<F: Float, const D: usize> KnownMinimum<F, D> for Levy {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::ONE; D]
    }
}
