//! Shared helpers of the host-side tests.
