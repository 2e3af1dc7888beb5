//! A user's batched function behind the kernel's batch seam
//! ([`UserBatch`]): one call per step on the live chains' rows, the
//! kernel's bits, the rows of diverged chains never passed, and a failure
//! that ends the run as the function's own error.

use std::sync::{Arc, Mutex};

use hrla::{
    Builder, Chain, FlatChains, FlatSlices, FnPotential, Hrla, Interval, Potential, Rastrigin, Stop,
};
use hrla_dyn::{BatchFunction, Error, UserBatch, UserError};
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

const D: usize = 10;
const N: usize = 12;
const STEPS: u64 = 300;
/// Rastrigin, undefined (NaN) beyond this `x_0`: chains that step past it
/// diverge.
const EDGE: f64 = 1.2;

fn rastrigin_with_edge(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let u = Rastrigin.value_and_gradient(x, g);
    if x[0] > EDGE { f64::NAN } else { u }
}

/// [`rastrigin_with_edge`] on batches, recording each call's rows.
#[derive(Default)]
struct Recorded {
    calls: Mutex<Vec<Vec<[f64; D]>>>,
    fail_at_call: Option<usize>,
}

impl BatchFunction for Recorded {
    fn evaluate(
        &self,
        points: &[f64],
        d: usize,
        values: &mut [f64],
        grads: &mut [f64],
    ) -> Result<(), UserError> {
        assert_eq!(d, D);
        let mut calls = self.calls.lock().unwrap();
        if Some(calls.len()) == self.fail_at_call {
            return Err("the model's solver failed".into());
        }
        let rows: Vec<[f64; D]> = points
            .chunks_exact(D)
            .map(|r| r.try_into().unwrap())
            .collect();
        for ((x, v), g) in rows
            .iter()
            .zip(values.iter_mut())
            .zip(grads.chunks_exact_mut(D))
        {
            *v = rastrigin_with_edge(x, g.try_into().unwrap());
        }
        calls.push(rows);
        Ok(())
    }
}

fn sampler() -> Hrla<f64> {
    Hrla::paper(0.02).unwrap()
}

fn start() -> Interval<f64> {
    Interval::new(-1.0, 1.0).unwrap()
}

/// The const path's run of the same potential, one point at a time.
fn kernel_run() -> Vec<Chain<f64, D>> {
    let chains: Vec<Chain<f64, D>> = (0..N).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        FnPotential::new(rastrigin_with_edge),
        sampler(),
        4.0,
        start(),
    )
    .seed(5)
    .build(chains)
    .unwrap();
    for _ in 0..STEPS {
        opt.step().unwrap();
    }
    opt.chains().to_vec()
}

struct Storage {
    floats: Vec<f64>,
    iterations: Vec<u64>,
    diverged: Vec<bool>,
    rngs: Vec<Xoshiro256PlusPlus>,
}

impl Storage {
    fn new() -> Self {
        Self {
            floats: vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(N, D)],
            iterations: vec![0; N],
            diverged: vec![false; N],
            rngs: (0..N)
                .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
                .collect(),
        }
    }

    fn chains(&mut self) -> FlatSlices<'_, f64, Xoshiro256PlusPlus> {
        FlatChains::new(
            D,
            &mut self.floats[..],
            &mut self.iterations[..],
            &mut self.diverged[..],
            &mut self.rngs[..],
        )
        .unwrap()
    }
}

#[test]
fn one_call_per_step_on_the_live_rows_with_the_kernels_bits() {
    let function = Arc::new(Recorded::default());
    let mut storage = Storage::new();
    let mut opt = Builder::new(UserBatch::new(function.clone()), sampler(), 4.0, start())
        .seed(5)
        .stop(Stop::new().steps(STEPS))
        .build(storage.chains())
        .unwrap();
    let mut live_before = Vec::new();
    for _ in 0..STEPS {
        live_before.push(N - opt.diverged_chains());
        opt.step().unwrap();
        opt.potential().finish().unwrap();
    }
    let expected = kernel_run();
    let chains = opt.chains();
    for (c, k) in expected.iter().enumerate() {
        assert_eq!(chains.x(c), k.x(), "chain {c}");
        assert_eq!(chains.is_diverged(c), k.is_diverged(), "chain {c}");
        assert_eq!(chains.best(c).value.to_bits(), k.best().value.to_bits());
    }
    let diverged = opt.diverged_chains();
    // The edge matters here: some chains diverge, not all, so that both
    // the copy-free call and the gathered one ran.
    assert!(diverged > 0 && diverged < N, "{diverged} of {N} diverged");
    let calls = function.calls.lock().unwrap();
    // One call for the initial points (no start is beyond the edge), then
    // one per step, each with exactly the chains live before it.
    assert_eq!(calls.len() as u64, STEPS + 1);
    assert_eq!(calls[0].len(), N);
    for (k, (rows, live)) in calls[1..].iter().zip(&live_before).enumerate() {
        assert_eq!(rows.len(), *live, "step {k}");
        // A chain that has diverged is never passed again: every row but
        // the ones that cross at this very step is inside the edge.
        assert!(rows.iter().all(|r| r[0].is_finite()), "step {k}");
    }
    let rows: usize = calls.iter().map(Vec::len).sum();
    assert_eq!(rows as u64, opt.evaluations());
}

#[test]
fn a_failing_call_ends_the_run_with_its_error() {
    let function = Arc::new(Recorded {
        fail_at_call: Some(4),
        ..Recorded::default()
    });
    let mut storage = Storage::new();
    let mut opt = Builder::new(UserBatch::new(function.clone()), sampler(), 4.0, start())
        .seed(5)
        .build(storage.chains())
        .unwrap();
    for _ in 0..3 {
        opt.step().unwrap();
        opt.potential().finish().unwrap();
    }
    // The seam stops the run, and the function's error is the reason;
    // the run stays stopped without calling the function again.
    assert!(matches!(opt.step(), Err(hrla::Error::Stopped)));
    match opt.potential().finish() {
        Err(Error::User(e)) => assert_eq!(e.to_string(), "the model's solver failed"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(opt.step(), Err(hrla::Error::Stopped)));
    assert_eq!(function.calls.lock().unwrap().len(), 4);
}
