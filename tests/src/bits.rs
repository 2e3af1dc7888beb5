//! A chain's whole observable state as bit patterns, for tests that
//! compare runs bit for bit.

use hrla::{Chain, Float};
use rand_xoshiro::rand_core::Rng;

/// Appends chain `c`'s position, velocity, gradient, value, best point,
/// best value and iteration, divergence flag, and its generator's state
/// (the next output of a copy, so the chain is not advanced).
pub fn chain_bits<F: Float, const D: usize, R: Rng + Clone>(
    c: &Chain<F, D, R>,
    out: &mut Vec<u64>,
) {
    out.extend(c.x().iter().map(|v| v.to_bits_u64()));
    out.extend(c.y().iter().map(|v| v.to_bits_u64()));
    out.extend(c.gradient().iter().map(|v| v.to_bits_u64()));
    out.push(c.value().to_bits_u64());
    out.extend(c.best().x.iter().map(|v| v.to_bits_u64()));
    out.push(c.best().value.to_bits_u64());
    out.push(c.best().iteration);
    out.push(u64::from(c.is_diverged()));
    out.push(c.rng().clone().next_u64());
}
