//! One random stream per chain, from the run's seed and the chain's index.

/// The SplitMix64 output function (Steele, Lea and Flood 2014): a bijection
/// of `u64` whose outputs for consecutive inputs look independent.
pub const fn splitmix64(z: u64) -> u64 {
    let z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of chain `chain`'s generator in a run seeded with `seed`:
/// `splitmix64(splitmix64(seed) ^ chain)`, passed to
/// [`SeedableRng::seed_from_u64`](rand_core::SeedableRng::seed_from_u64).
///
/// It depends on `(seed, chain)` only, so chain `c` runs the same whether
/// it is stepped alone, first, last, or beside any number of others; and
/// distinct chains of one run, or the same chain of runs with distinct
/// seeds, get distinct generator states.
///
/// ```
/// use hrla::chain_seed;
///
/// assert_ne!(chain_seed(1, 0), chain_seed(1, 1));
/// assert_ne!(chain_seed(1, 0), chain_seed(2, 0));
/// ```
pub const fn chain_seed(seed: u64, chain: u64) -> u64 {
    splitmix64(splitmix64(seed) ^ chain)
}
