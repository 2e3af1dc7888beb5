//! One optimiser's step on one thread against the same step on more, in
//! one process, interleaved (see `docs/PERFORMANCE.md`, Noise): HRLA on
//! 10-D Rastrigin, f64, value and running best every step, 1000 chains.
//!
//! ```text
//! cargo run --release -p hrla-bench --bin threads -- [pairs] [threads]
//! ```
//!
//! Each pair times a block of steps on the calling thread and a block on a
//! pool of `threads` (default 2), the order alternating; it prints the
//! median time per step of each and the median of the per-pair speed-ups,
//! and checks that both optimisers are still bit-identical.

use std::time::Instant;

use hrla::{AnySampler, Builder, Chain, Gaussian, Rastrigin, SamplerKind};
use hrla_threads::Threads;

const D: usize = 10;
const CHAINS: usize = 1000;
const STEPS: usize = 40;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let pairs: usize = args.next().map_or(60, |s| s.parse().expect("pairs"));
    let threads: usize = args.next().map_or(2, |s| s.parse().expect("threads"));
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    let part: usize = std::env::var("PART").map_or(0, |s| s.parse().expect("PART"));
    let builder = || {
        let start = Gaussian::new([3.0; D], 10f64.sqrt()).expect("valid");
        let sampler = AnySampler::paper(SamplerKind::Hrla, 0.01).expect("valid");
        Builder::new(Rastrigin, sampler, 4.0, start).seed(1)
    };
    let chains = || -> Vec<Chain<f64, D>> { (0..CHAINS).map(|_| Chain::new()).collect() };
    let mut serial = builder().build(chains()).expect("valid");
    let mut parallel = builder()
        .executor(Threads::chains_per_part(part))
        .build(chains())
        .expect("valid");
    fn time(mut step: impl FnMut()) -> f64 {
        let t = Instant::now();
        for _ in 0..STEPS {
            step();
        }
        t.elapsed().as_secs_f64() * 1e6 / STEPS as f64
    }
    let (mut a, mut b, mut r) = (Vec::new(), Vec::new(), Vec::new());
    for p in 0..pairs {
        let mut s = || time(|| _ = serial.step().expect("valid"));
        let mut m = || many.install(|| time(|| _ = parallel.step().expect("valid")));
        let (x, y) = if p % 2 == 0 {
            let x = s();
            (x, m())
        } else {
            let y = m();
            (s(), y)
        };
        a.push(x);
        b.push(y);
        r.push(x / y);
    }
    assert_eq!(serial.best(), parallel.best(), "threads changed the result");
    println!(
        "1 thread {:.1} µs/step, {threads} threads {:.1} µs/step, speed-up (median of {pairs} pairs) {:.2}x",
        median(&mut a),
        median(&mut b),
        median(&mut r)
    );
}
