//! Shared helpers of the host-side tests.
pub mod dd;
pub mod hostile;
pub mod prop;
pub mod reference;
pub mod stats;
