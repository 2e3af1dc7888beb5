//! Algorithm 1: run `N` independent chains and keep the best point seen.
//!
//! The chains live in storage the caller owns ([`Chain`]s in a slice, an
//! array, a `heapless::Vec`, a `Vec` or a boxed slice), so no number or
//! size of chains can overflow a stack. Each chain has its own random
//! generator, seeded from the run's seed and its index only
//! ([`chain_seed`]): chain `c`'s trajectory is a pure function of
//! `(seed, c)`, whatever order or number of chains are stepped with it.
//! [`Builder`] assembles a run, [`Stop`] says when it ends, and
//! [`Report`] says why it ended.

mod algorithm;
mod builder;
mod chain;
mod executor;
mod flat;
mod report;
mod stop;
mod store;
mod stream;
mod sweep;

pub use algorithm::Optimizer;
pub use builder::Builder;
pub use chain::{Chain, Chains};
pub use executor::{Executor, Serial, Split};
pub use flat::{FlatChains, FlatSlices, FlatStorage};
pub use report::{Observe, Progress, Report};
pub use store::{Best, Store};

pub use stop::{Stop, Termination};
pub use stream::{chain_seed, splitmix64};
pub use sweep::START_TRIES;
pub(crate) use sweep::{Verdict, draw_point, judge};
