//! The random pieces of a round: uniform numbers, directions, differential
//! moves and gradient-free trajectories.

use rand_core::Rng;

use crate::domain::{Domain, Sides};
use crate::float::Float;
use crate::sampler::Kernel;

/// Uniform in `[0, 1)`, from the top bits of one word.
pub(super) fn uniform<F: Float, R: Rng + ?Sized>(rng: &mut R) -> F {
    let bits = F::MANTISSA_DIGITS;
    F::from_u64(rng.next_u64() >> (64 - bits)) * F::from_f64(1.0 / (1u64 << bits) as f64)
}

/// Uniform in `0..n`.
pub(super) fn index<R: Rng + ?Sized>(rng: &mut R, n: usize) -> usize {
    (((rng.next_u64() >> 32) * n as u64) >> 32) as usize
}

/// A uniform direction into `v`: normalised standard normals (rotation
/// invariant).
pub(super) fn direction<F: Float, R: Rng + ?Sized>(rng: &mut R, v: &mut [F]) {
    let mut norm = F::ZERO;
    for vi in v.iter_mut() {
        *vi = F::standard_normal(rng);
        norm += *vi * *vi;
    }
    let norm = norm.sqrt();
    if norm > F::ZERO {
        for vi in v.iter_mut() {
            *vi = *vi / norm;
        }
    } else if let Some(v0) = v.first_mut() {
        *v0 = F::ONE;
    }
}

/// Two chains other than `c` of `n` (`n >= 3`), distinct, uniform.
pub(super) fn pair<R: Rng + ?Sized>(rng: &mut R, c: usize, n: usize) -> (usize, usize) {
    let i = (c + 1 + index(rng, n - 1)) % n;
    let mut j = (c + 1 + index(rng, n - 2)) % n;
    if j == i {
        j = (i + 1) % n;
        if j == c {
            j = (j + 1) % n;
        }
    }
    (i, j)
}

/// The factor `γ` of a differential move: uniform in `[0.5, 1]`.
pub(super) fn gamma<F: Float, R: Rng + ?Sized>(rng: &mut R) -> F {
    F::HALF + F::HALF * uniform::<F, R>(rng)
}

/// `x + γ (p - q)`, reflected into the box (`y` is scratch): a move of the
/// length and direction the chains' basins span, in each coordinate on
/// the scale the chains found there.
pub(super) fn differential<F: Float, B: Sides<F> + ?Sized>(
    x: &mut [F],
    p: &[F],
    q: &[F],
    gamma: F,
    domain: &B,
    y: &mut [F],
) {
    for ((xi, &pi), &qi) in x.iter_mut().zip(p).zip(q) {
        *xi += gamma * (pi - qi);
    }
    y.fill(F::ZERO);
    domain.confine(x, y);
}

/// `steps` steps of `kernel` with the gradient set to zero (`zero` is
/// scratch): the noise of a trajectory without the potential's drift.
pub(super) fn free<F: Float, K: Kernel<F>, B: Domain<F> + ?Sized, R: Rng + ?Sized>(
    kernel: &K,
    x: &mut [F],
    y: &mut [F],
    zero: &mut [F],
    steps: u64,
    domain: &B,
    rng: &mut R,
) {
    zero.fill(F::ZERO);
    for _ in 0..steps {
        kernel.step_slice(x, y, zero, rng);
        domain.confine(x, y);
    }
}
