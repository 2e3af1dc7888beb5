//! One timing of Algorithm 1's step, for scripts that interleave the crate
//! with its peers (`bench/peers/run.sh --hrla-cmd ...`): HRLA on 10-D
//! Rastrigin from the paper's start, 1000 chains, value and running best
//! every step, on the calling thread.
//!
//! ```text
//! cargo run --release -p hrla-bench --bin step -- [f64|f32] [steps]
//! ```
//!
//! Prints the ns per coordinate-step of `steps` steps (default 2000) after
//! 50 steps of warm-up, and nothing else.

use std::time::Instant;

use hrla::Float;
use hrla_bench::{Swarm, constant, optimizer};

const D: usize = 10;
const CHAINS: usize = 1000;

fn time<F: Float>(steps: usize) -> f64 {
    let mut opt: Swarm<F, F, D> = optimizer(hrla::SamplerKind::Hrla, constant::<F>(), CHAINS, 1);
    for _ in 0..50 {
        opt.step().expect("valid");
    }
    let t = Instant::now();
    for _ in 0..steps {
        opt.step().expect("valid");
    }
    t.elapsed().as_nanos() as f64 / (steps * CHAINS * D) as f64
}

fn main() {
    let mut args = std::env::args().skip(1);
    let float = args.next().unwrap_or_else(|| "f64".into());
    let steps: usize = args.next().map_or(2000, |s| s.parse().expect("steps"));
    let ns = match float.as_str() {
        "f64" => time::<f64>(steps),
        "f32" => time::<f32>(steps),
        other => {
            eprintln!("float must be f64 or f32, not {other}");
            std::process::exit(2);
        }
    };
    println!("{ns:.3}");
}
