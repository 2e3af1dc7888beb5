//! Shared helpers of the host-side tests: independent references
//! (double-double arithmetic, the exact OU step), statistics, and the
//! strategies and checks of the property tests. They live in the library so
//! that each test file holds only the tests of its one subject, and so that
//! a helper can carry unit tests of its own (as `stats` does).
pub mod bits;
pub mod dd;
pub mod fixtures;
pub mod hostile;
pub mod prop;
pub mod reference;
pub mod stats;
