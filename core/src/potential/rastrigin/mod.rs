//! Rastrigin's function in the paper's form, with its fused trigonometry
//! (the child module `trig`) and its block-wise evaluation.

mod trig;

use super::traits::{KnownMinimum, Potential, SlicePotential};
use crate::float::Float;
use crate::lanes;

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
    #[inline]
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        rastrigin_any(x, grad)
    }
}

impl<F: Float> SlicePotential<F> for Rastrigin {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        rastrigin_any(x, grad)
    }
}

/// Both impls' one body, always inlined: into the fixed-size one, the
/// length is a constant and every block loop unrolls (a call through the
/// slice impl measured 20% slower steps at d = 10 and 100).
#[inline(always)]
fn rastrigin_any<F: Float>(x: &[F], grad: &mut [F]) -> F {
    {
        // Blocks of one 256-bit vector where the target has them (AVX) and
        // the point fills one, else of one 128-bit vector, single
        // coordinates without vectors (padding would only waste work
        // there); constant choices for a fixed dimension. The sum's lanes
        // are the same on every target, so the value's bits are too.
        let l = lanes::lanes::<F>();
        match (l, lanes::VECTORS, lanes::WIDE && x.len() >= 2 * l) {
            (2, true, true) => rastrigin::<F, 4, 2>(x, grad),
            (2, true, false) => rastrigin::<F, 2, 2>(x, grad),
            (2, false, _) => rastrigin::<F, 1, 2>(x, grad),
            (_, true, true) => rastrigin::<F, 8, 4>(x, grad),
            (_, true, false) => rastrigin::<F, 4, 4>(x, grad),
            (_, false, _) => rastrigin::<F, 1, 4>(x, grad),
        }
    }
}

/// Rastrigin's value and gradient, `B` coordinates at a time (`B` is 1, `L`
/// or `2L`; a tail shorter than `B` goes by blocks of `min(B, L)`), the
/// value summed in `L` lanes.
#[inline(always)]
fn rastrigin<F: Float, const B: usize, const L: usize>(x: &[F], grad: &mut [F]) -> F {
    let d = x.len().min(grad.len());
    let (x, grad) = (&x[..d], &mut grad[..d]);
    let mut sum = Polynomial {
        lanes: [F::ZERO; L],
        all_small: true,
    };
    // With B = 2L, the tail past the last full block goes by blocks of L;
    // otherwise the blocks of B cover everything, a short tail padded.
    let head = if B > L { d / B * B } else { d };
    for_each_block::<F, B, _>(&x[..head], &mut grad[..head], 0, &mut sum);
    if head < d {
        for_each_block::<F, L, _>(&x[head..], &mut grad[head..], head, &mut sum);
    }
    if sum.all_small {
        sum_lanes(sum.lanes)
    } else {
        rastrigin_large::<F, L>(x, grad)
    }
}

/// [`rastrigin`] again, with the trigonometry of huge or non-finite
/// coordinates from [`Float::fast_sin_cos`]: out of line, so that it costs
/// the hot path neither code nor stack; by blocks of one coordinate, the
/// lanes' sums being the same for every block width.
#[cold]
#[inline(never)]
fn rastrigin_large<F: Float, const L: usize>(x: &[F], grad: &mut [F]) -> F {
    let mut sum = Fallback {
        lanes: [F::ZERO; L],
    };
    for_each_block::<F, 1, _>(x, grad, 0, &mut sum);
    sum_lanes(sum.lanes)
}

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

impl<F: Float, const D: usize> KnownMinimum<F, D> for Rastrigin {
    fn global_minimum(&self) -> F {
        F::ZERO
    }
    fn global_minimiser(&self) -> [F; D] {
        [F::ZERO; D]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Evaluation<F> = fn(&[F], &mut [F]) -> F;

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
            let u1 = rastrigin::<F, 1, L>(&x, &mut g1);
            let widths: [Evaluation<F>; 3] = [
                rastrigin::<F, L, L>,
                rastrigin::<F, L2, L>,
                rastrigin_large::<F, L>,
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
