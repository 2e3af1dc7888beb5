//! The run-time-dimension optimiser on threads: 1, 2, 3 and 7 threads and
//! any part size give the bits of a serial run, for every sampler, with
//! chains that diverge.

use std::ops::ControlFlow;

use hrla::rand_core::SeedableRng;
use hrla::{
    AnySampler, Builder, FlatChains, FlatSlices, Float, Gaussian, Observe, Progress, Rastrigin,
    SamplerKind, SlicePotential, Stop,
};
use hrla_threads::Threads;
use rand_xoshiro::Xoshiro256PlusPlus;

const D: usize = 9;
const CHAINS: usize = 103;

/// Rastrigin, infeasible beyond `x_0 > 1`: some chains diverge.
struct Cliff;

impl SlicePotential<f64> for Cliff {
    fn value_and_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let u = Rastrigin.value_and_gradient(x, grad);
        if x[0] > 1.0 { f64::NAN } else { u }
    }
}

/// The run's chains and counters, as bits; `threads` None: serial;
/// `every` Some: with an observer called every `every` steps (and on each
/// improvement), whose sightings are in the summary.
fn run(kind: SamplerKind, threads: Option<Threads>, every: Option<u64>) -> (Vec<u64>, String) {
    let mut floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(CHAINS, D)];
    let (mut iterations, mut diverged) = (vec![0; CHAINS], vec![false; CHAINS]);
    let mut rngs: Vec<_> = (0..CHAINS)
        .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
        .collect();
    let chains =
        FlatChains::new(D, &mut floats, &mut iterations, &mut diverged, &mut rngs).unwrap();
    let builder = Builder::new(
        Cliff,
        AnySampler::paper(kind, 0.01).unwrap(),
        2.0,
        Gaussian::new([0.5; D], 1.0).unwrap(),
    )
    .seed(5)
    .stop(Stop::new().steps(150));
    let mut seen = Vec::new();
    let observer = |p: &Progress<'_, f64>| {
        seen.push((
            p.iteration,
            p.evaluations,
            p.best.value.to_bits(),
            p.improved,
            p.diverged_chains,
        ));
        ControlFlow::Continue(())
    };
    // Every step's chains and counters, whatever the executor's type.
    macro_rules! summary {
        ($opt:expr) => {{
            let mut opt = $opt.unwrap();
            let report = match every {
                None => opt.run(),
                Some(every) => opt.run_with(Observe::EveryAndNewBest(every), observer),
            };
            let summary = format!(
                "{report:?} {} {} {} {seen:?}",
                opt.evaluations(),
                opt.best_chain(),
                opt.diverged_chains()
            );
            (summary, opt.into_chains())
        }};
    }
    let (summary, c) = match threads {
        Some(t) => summary!(builder.executor(t).build(chains)),
        None => summary!(builder.build(chains)),
    };
    let mut bits: Vec<u64> = c.positions().iter().map(|v| v.to_bits_u64()).collect();
    bits.extend(c.best_positions().iter().map(|v| v.to_bits()));
    bits.extend(c.values().iter().map(|v| v.to_bits()));
    bits.extend((0..CHAINS).map(|i| u64::from(c.is_diverged(i))));
    (bits, summary)
}

#[test]
fn flat_runs_give_the_serial_bits_on_any_threads() {
    for kind in SamplerKind::ALL {
        let serial = run(kind, None, None);
        assert!(serial.1.contains("Ok("), "{}", serial.1);
        let diverged: u64 = serial.0[serial.0.len() - CHAINS..].iter().sum();
        assert!(
            diverged > 0,
            "no chain diverged: the test would not cover them"
        );
        for threads in [1, 2, 3, 7] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for part in [None, Some(4), Some(12), Some(5)] {
                let executor = part.map_or_else(Threads::new, Threads::chains_per_part);
                let parallel = pool.install(|| run(kind, Some(executor), None));
                assert_eq!(
                    serial, parallel,
                    "{kind}: {threads} threads, parts {part:?}"
                );
            }
        }
    }
}

/// `run_with` on threads gives the serial `run_with`'s bits and calls its observer
/// at the same steps with the same sightings, on any threads; the observer
/// is called (every 10 steps at least).
#[test]
fn flat_observed_runs_give_the_serial_bits_on_any_threads() {
    for kind in SamplerKind::ALL {
        let serial = run(kind, None, Some(10));
        assert_eq!(serial.0, run(kind, None, None).0, "{kind}: observed");
        assert!(serial.1.contains("(150, "), "{}", serial.1);
        for threads in [2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let parallel = pool.install(|| run(kind, Some(Threads::chains_per_part(5)), Some(10)));
            assert_eq!(serial, parallel, "{kind}: {threads} threads");
        }
    }
}
