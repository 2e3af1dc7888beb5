//! The random pieces of a round: uniform numbers, directions, points in
//! the box, differential moves and gradient-free trajectories.

use rand_core::Rng;

use crate::domain::{Domain, Interval};
use crate::float::Float;
use crate::sampler::Kernel;
use crate::start::Start;

/// Uniform in `[0, 1)`, from the top bits of one word.
pub(super) fn uniform<F: Float, R: Rng + ?Sized>(rng: &mut R) -> F {
    let bits = F::MANTISSA_DIGITS;
    F::from_u64(rng.next_u64() >> (64 - bits)) * F::from_f64(1.0 / (1u64 << bits) as f64)
}

/// Uniform in `0..n`.
pub(super) fn index<R: Rng + ?Sized>(rng: &mut R, n: usize) -> usize {
    (((rng.next_u64() >> 32) * n as u64) >> 32) as usize
}

/// Whether an event of probability `p` happens.
pub(super) fn chance<F: Float, R: Rng + ?Sized>(rng: &mut R, p: F) -> bool {
    uniform::<F, R>(rng) < p
}

/// A uniform direction: normalised standard normals (rotation invariant).
pub(super) fn direction<F: Float, R: Rng + ?Sized, const D: usize>(rng: &mut R) -> [F; D] {
    let mut v = [F::ZERO; D];
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
    } else if D > 0 {
        v[0] = F::ONE;
    }
    v
}

/// A point uniform in the box.
pub(super) fn anywhere<F: Float, R: Rng, const D: usize>(
    domain: Interval<F>,
    rng: &mut R,
    x: &mut [F; D],
) {
    let mut d = domain;
    d.initial_point(0, rng, x);
}

/// `x + γ (p - q)`, `γ` uniform in `[0.5, 1]`, reflected into the box: a
/// move of the length and direction the chains' basins span.
pub(super) fn differential<F: Float, R: Rng + ?Sized, const D: usize>(
    x: &mut [F; D],
    p: &[F; D],
    q: &[F; D],
    domain: Interval<F>,
    rng: &mut R,
) {
    let gamma = F::HALF + F::HALF * uniform::<F, R>(rng);
    let mut y = [F::ZERO; D];
    for ((xi, &pi), &qi) in x.iter_mut().zip(p).zip(q) {
        *xi += gamma * (pi - qi);
    }
    domain.confine(x, &mut y);
}

/// `steps` steps of `kernel` with the gradient set to zero: the noise of
/// a trajectory without the potential's drift.
pub(super) fn free<F: Float, K: Kernel<F>, R: Rng + ?Sized, const D: usize>(
    kernel: &K,
    x: &mut [F; D],
    y: &mut [F; D],
    steps: u64,
    domain: Interval<F>,
    rng: &mut R,
) {
    let zero = [F::ZERO; D];
    for _ in 0..steps {
        kernel.step(x, y, &zero, rng);
        domain.confine(x, y);
    }
}
