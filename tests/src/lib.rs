//! Shared helpers of the host-side tests.
pub mod dd;
pub mod reference;
pub mod stats;
