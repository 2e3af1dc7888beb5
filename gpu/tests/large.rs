//! More chains than one dispatch dimension holds (65,535 workgroups of 64):
//! the two-dimensional dispatch reaches every chain, and the reductions
//! see them all.

mod common;

use hrla::Hrla;
use hrla_gpu::{DevicePotential, EnsembleBuilder, Start};

#[test]
fn every_chain_of_a_two_dimensional_dispatch_steps_and_counts() {
    let n = 65_535 * 64 + 1000;
    let mut ensemble = EnsembleBuilder::new(
        DevicePotential::quadratic(1.0, vec![0.0]).unwrap(),
        Hrla::paper(0.01).unwrap(),
        1.0,
        Start::gaussian(vec![0.0], 1.0).unwrap(),
    )
    .chains(n)
    .seed(3)
    .build(common::gpu())
    .unwrap();
    ensemble.run(2).unwrap();
    let chains = ensemble.snapshot().unwrap();
    // Every chain moved (a start at exactly its later point has
    // probability 0) and its velocity is no longer the initial 0.
    let still = chains.iter().filter(|c| c.y[0] == 0.0).count();
    assert_eq!(still, 0);
    // The best is the lowest running best over all of them, the last
    // chains included.
    let (c, low) = chains
        .iter()
        .enumerate()
        .min_by(|a, b| {
            a.1.best_value
                .total_cmp(&b.1.best_value)
                .then(a.1.best_iteration.cmp(&b.1.best_iteration))
        })
        .map(|(c, ch)| (c, ch.best_value))
        .unwrap();
    let best = ensemble.best().unwrap();
    assert_eq!((best.chain, best.value), (c, low));
    // Runs of 8 chains: the device's count is the host's.
    let eps = 1e-3;
    let p = ensemble.probability(8, 0.0, &[eps]).unwrap()[0];
    let hits = chains
        .chunks(8)
        .filter(|run| run.iter().any(|ch| ch.value <= f64::from(eps as f32)))
        .count();
    assert_eq!(p.current, hits as f64 / (n / 8) as f64);
    assert!(hits > 0);
}
