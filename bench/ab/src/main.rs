//! Interleaved in-process A/B of `Optimizer::step` (see `run.sh`).
//!
//! Both kernels step the same problem (Rastrigin from the paper's start,
//! HRLA at h = 0.01, a = 4, 1000 chains, value and running best every
//! step). Each pair times a block of steps of one side then the other,
//! the order alternating, so a change of the machine's speed hits both
//! sides of a pair alike; the median of the pairs' ratios is the verdict.

use std::time::Instant;

use hrla::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

const CHAINS: usize = 1000;

macro_rules! swarm {
    ($k:ident, $f:ty, $d:expr, $kind:expr) => {{
        let start = $k::Gaussian::new([3.0 as $f; $d], (10.0 as $f).sqrt()).unwrap();
        let chains: Vec<$k::Chain<$f, $d>> = (0..CHAINS).map(|_| $k::Chain::new()).collect();
        let sampler = $k::AnySampler::<$f>::paper($kind, 0.01).unwrap();
        $k::Builder::new($k::Rastrigin, sampler, 4.0 as $f, start)
            .seed(1)
            .build(chains)
            .unwrap()
    }};
}

/// The same run over flat storage of a run-time dimension, the storage
/// leaked so that the optimiser can live as long as the bench.
macro_rules! flat_swarm {
    ($f:ty, $d:expr, $kind:expr) => {{
        let (n, d) = (CHAINS, $d);
        let floats = vec![0.0 as $f; hrla::FlatSlices::<$f, Xoshiro256PlusPlus>::floats(n, d)].leak();
        let iterations = vec![0u64; n].leak();
        let diverged = vec![false; n].leak();
        let rngs: &mut [Xoshiro256PlusPlus] =
            (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect::<Vec<_>>().leak();
        let chains = hrla::FlatChains::new(d, floats, iterations, diverged, rngs).unwrap();
        let start = hrla::Gaussian::new([3.0 as $f; $d], (10.0 as $f).sqrt()).unwrap();
        let sampler = hrla::AnySampler::<$f>::paper($kind, 0.01).unwrap();
        hrla::Builder::new(hrla::Rastrigin, sampler, 4.0 as $f, start)
            .seed(1)
            .build(chains)
            .unwrap()
    }};
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// ns per coordinate-step of `steps` steps of `step`.
fn time(steps: usize, coords: usize, mut step: impl FnMut()) -> f64 {
    let t = Instant::now();
    for _ in 0..steps {
        step();
    }
    t.elapsed().as_nanos() as f64 / (steps * coords) as f64
}

macro_rules! case {
    ($name:expr, $f:ty, $d:expr, $kind:ident, $pairs:expr) => {{
        // AB_CASES: a substring of the case names to run (default: all).
        if !$name.contains(std::env::var("AB_CASES").unwrap_or_default().as_str()) {
            return;
        }
        // AB_DYN=1: this tree's run-time-dimension path (new) against its
        // own const path (base), instead of the base commit.
        if std::env::var("AB_DYN").is_ok_and(|v| v == "1") {
            let mut new = flat_swarm!($f, $d, hrla::SamplerKind::$kind);
            let mut base = swarm!(hrla, $f, $d, hrla::SamplerKind::$kind);
            pairs!($name, $d, $pairs, new, base);
            return;
        }
        let mut new = swarm!(hrla, $f, $d, hrla::SamplerKind::$kind);
        let mut base = swarm!(hrla_base, $f, $d, hrla_base::SamplerKind::$kind);
        pairs!($name, $d, $pairs, new, base);
    }};
}

/// Times `$pairs` interleaved pairs of blocks of `$new.step()` and
/// `$base.step()`, and prints the medians.
macro_rules! pairs {
    ($name:expr, $d:expr, $pairs:expr, $new:ident, $base:ident) => {{
        let (new, base) = (&mut $new, &mut $base);
        let coords = CHAINS * $d;
        // About 2 ms a block.
        let steps = (200_000 / coords).max(1);
        for _ in 0..20 {
            new.step().unwrap();
            base.step().unwrap();
        }
        let (mut a, mut b, mut r) = (Vec::new(), Vec::new(), Vec::new());
        for p in 0..$pairs {
            let (x, y) = if p % 2 == 0 {
                let x = time(steps, coords, || _ = new.step().unwrap());
                (x, time(steps, coords, || _ = base.step().unwrap()))
            } else {
                let y = time(steps, coords, || _ = base.step().unwrap());
                (time(steps, coords, || _ = new.step().unwrap()), y)
            };
            a.push(x);
            b.push(y);
            r.push(x / y);
        }
        // The same trajectories on both sides: the comparison is fair.
        assert_eq!(new.best().value.to_bits(), base.best().value.to_bits(), "{}", $name);
        println!(
            "{:<22} new {:6.2}  base {:6.2}  ns/coord-step   new/base {:.3}",
            $name,
            median(&mut a),
            median(&mut b),
            median(&mut r)
        );
    }};
}

fn main() {
    let pairs: usize = std::env::args().nth(1).map_or(60, |s| s.parse().unwrap());
    let cases: [fn(usize); 11] = [
        |p| case!("f32 d2 hrla/best", f32, 2, Hrla, p),
        |p| case!("f32 d10 ola/best", f32, 10, Ola, p),
        |p| case!("f64 d10 hrla/best", f64, 10, Hrla, p),
        |p| case!("f32 d10 hrla/best", f32, 10, Hrla, p),
        |p| case!("f64 d32 hrla/best", f64, 32, Hrla, p),
        |p| case!("f32 d32 hrla/best", f32, 32, Hrla, p),
        |p| case!("f64 d100 hrla/best", f64, 100, Hrla, p),
        |p| case!("f32 d100 hrla/best", f32, 100, Hrla, p),
        |p| case!("f64 d2 hrla/best", f64, 2, Hrla, p),
        |p| case!("f64 d10 ola/best", f64, 10, Ola, p),
        |p| case!("f64 d10 ula/best", f64, 10, Ula, p),
    ];
    for case in cases {
        case(pairs);
    }
}
