//! Proptest set-up shared by the property tests: a fixed seed, so that a
//! failure reproduces on every machine and every run, and no persistence
//! files, so that a failing run writes nothing into the source tree.

use proptest::test_runner::{Config, RngSeed};

/// `cases` cases drawn from `seed`.
pub fn config(cases: u32, seed: u64) -> Config {
    Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        ..Config::default()
    }
}
