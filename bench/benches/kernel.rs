//! Throughput of the kernel: chain-steps per second and nanoseconds per
//! coordinate-step (criterion's "elements" are coordinate-steps), against
//! the floor of unavoidable work measured in the same run.
//!
//! `cargo bench -p hrla-bench` runs everything; `cargo bench -p hrla-bench
//! -- 'd10/'` a subset. docs/PERFORMANCE.md holds the results.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hrla::{Float, SamplerKind};
use hrla_bench::{Bare, constant, optimizer, paper_kernel, rng, slow_linear};

/// The seed of every benchmark's optimiser and bare chains.
const SEED: u64 = 7;

fn float_name<F: Float>() -> &'static str {
    if core::mem::size_of::<F>() == 8 {
        "f64"
    } else {
        "f32"
    }
}

/// Algorithm 1 (value and running best every step), sampler alone (no
/// value), and the floor, for one (float, D).
fn throughput<F: Float, const D: usize>(c: &mut Criterion) {
    let mut g = c.benchmark_group(format!("{}/d{D}", float_name::<F>()));
    g.warm_up_time(Duration::from_millis(300));
    g.measurement_time(Duration::from_millis(1200));
    g.sample_size(20);
    for chains in [1usize, 10, 1000] {
        g.throughput(Throughput::Elements((chains * D) as u64));
        for method in SamplerKind::ALL {
            let mut opt = optimizer::<F, _, D>(method, constant::<F>(), chains, SEED);
            g.bench_function(
                BenchmarkId::new(format!("{}/best", method.name()), chains),
                |b| b.iter(|| opt.step().expect("valid").iteration),
            );
            let sampler = paper_kernel::<F>(method);
            let mut r = rng(SEED);
            let mut bare = Bare::<F, D>::new(chains, &mut r);
            g.bench_function(
                BenchmarkId::new(format!("{}/no-value", method.name()), chains),
                |b| b.iter(|| bare.step(&sampler, &mut r)),
            );
        }
        // HRLA with a = a_k changing every step: the cost of the per-step
        // refresh of the temperature-dependent coefficients.
        let mut opt = optimizer::<F, _, D>(SamplerKind::Hrla, slow_linear::<F>(), chains, SEED);
        g.bench_function(BenchmarkId::new("hrla/best-annealed", chains), |b| {
            b.iter(|| opt.step().expect("valid").iteration)
        });
        let mut r = rng(SEED);
        let mut bare = Bare::<F, D>::new(chains, &mut r);
        g.bench_function(BenchmarkId::new("floor/normals+value+grad", chains), |b| {
            b.iter(|| black_box(bare.floor(&mut r)))
        });
        let gens: [_; 4] = core::array::from_fn(|l| rng(SEED + l as u64));
        let mut lanes = hrla::Xoshiro256Lanes::load(gens.each_ref());
        g.bench_function(
            BenchmarkId::new("floor-lanes/normals+value+grad", chains),
            |b| b.iter(|| black_box(bare.floor_lanes(&mut lanes))),
        );
        g.bench_function(BenchmarkId::new("floor/normals", chains), |b| {
            b.iter(|| black_box(bare.normals(&mut r)))
        });
        g.bench_function(BenchmarkId::new("floor/value+grad", chains), |b| {
            b.iter(|| black_box(bare.value_and_gradient()))
        });
        g.bench_function(BenchmarkId::new("floor/random-bits", chains), |b| {
            b.iter(|| black_box(bare.bits(&mut r)))
        });
    }
    g.finish();
}

fn all(c: &mut Criterion) {
    throughput::<f64, 2>(c);
    throughput::<f64, 10>(c);
    throughput::<f64, 100>(c);
    throughput::<f32, 2>(c);
    throughput::<f32, 10>(c);
    throughput::<f32, 100>(c);
}

criterion_group!(benches, all);
criterion_main!(benches);
