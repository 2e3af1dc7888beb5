//! `hrla-repro`: the paper's experimental protocols (spec section 7), run
//! with the `hrla` kernel, written as tables (Markdown, CSV) and figures
//! (SVG).
//!
//! The binary `repro` has one subcommand per protocol (`e1`, `t1`, `e2`,
//! `e3`, `e4`, `e5`, `t2`, `t3`) and `all`; see `repro --help`.
//!
//! - [`protocol`]: the protocols' defaults and overrides, expanded into a
//!   [`Plan`](protocol::Plan) of configurations.
//! - [`config`]: one configuration of a protocol ([`RunSpec`](config::RunSpec))
//!   and its validation.
//! - [`kernel`]: the one place the tool meets the kernel's optimiser: a
//!   run of a kernel sampler at its run-time dimension (any `d >= 1`),
//!   its start and the bytes of its chains.
//! - [`engine`]: the run loop: one run of one configuration, the kernel's
//!   chains or a peer's population driven one iteration at a time.
//! - [`stats`]: the paper's running best (over the stride, without iterate
//!   0) and empirical probability (not running), streamed; the summary
//!   statistics and their conventions.
//! - [`peers`]: T3's simulated-annealing peers (SA, FSA, SMC-SA, CSA),
//!   run by the same loop and statistics as the kernel.
//! - [`seed`]: one seed per run index, from one base seed (the kernel then
//!   gives each chain its own stream).
//! - [`limits`]: how big a plan may be (what the tool counts exactly,
//!   what the machine's memory holds).
//! - [`exec`]: every run of a plan (or of one shard of it) in parallel
//!   (rayon).
//! - [`gpu`]: the same runs and statistics on a GPU (`--backend gpu`).
//! - [`split`] and [`shard`]: which runs a process does (`--shard i/n`),
//!   a shard's runs on disk, and the merge of all shards into the result
//!   of one process.
//! - [`output`] and [`plot`]: CSV, Markdown, metadata and SVG figures;
//!   [`compare`]: T3's table of HRLA beside its peers and their costs.
//! - [`error`]: the error type they all return.
//!
//! Modules import one way, from the bottom up: [`stats`], [`seed`],
//! [`peers`], [`split`]; [`error`]; [`config`]; [`kernel`]; [`engine`],
//! [`limits`]; [`protocol`]; [`exec`]; [`gpu`]; [`shard`]; [`compare`],
//! [`plot`], [`output`] (`tests/modules.rs` finds no cycle).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod compare;
pub mod config;
pub mod engine;
pub mod error;
pub mod exec;
pub mod gpu;
pub mod kernel;
pub mod limits;
pub mod output;
pub mod peers;
pub mod plot;
pub mod protocol;
pub mod seed;
pub mod shard;
pub mod split;
pub mod stats;

pub use error::ReproError;
