//! A potential that panics on one of rayon's threads in the middle of a
//! step leaves some chains stepped and others not: the panic reaches the
//! caller, and the optimiser refuses every later call with
//! `Error::Poisoned` instead of going on from a state that no serial run
//! has.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use hrla::{Builder, Chain, Error, Gaussian, Hrla, Potential, Stop};
use hrla_threads::Threads;

/// A quadratic that panics at its 100th call once armed.
#[derive(Default)]
struct Fragile {
    armed: AtomicBool,
    calls: AtomicU32,
}

impl Potential<f64, 2> for Fragile {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        if self.armed.load(Ordering::Relaxed) && self.calls.fetch_add(1, Ordering::Relaxed) == 99 {
            panic!("the potential failed");
        }
        *g = [2.0 * x[0], 2.0 * x[1]];
        x[0] * x[0] + x[1] * x[1]
    }
}

#[test]
fn a_panic_on_a_thread_poisons_the_optimiser() {
    let p = Fragile::default();
    let mut chains: Vec<Chain<f64, 2>> = (0..512).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        &p,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Gaussian::new([1.0; 2], 1.0).unwrap(),
    )
    .stop(Stop::new().steps(100))
    .executor(Threads::chains_per_part(16))
    .build(&mut chains)
    .unwrap();
    opt.step().unwrap();
    p.armed.store(true, Ordering::Relaxed);
    let panicked = catch_unwind(AssertUnwindSafe(|| opt.step().map(|_| ())));
    assert!(panicked.is_err(), "no panic");
    p.armed.store(false, Ordering::Relaxed);
    assert_eq!(opt.step().map(|_| ()), Err(Error::Poisoned));
    assert_eq!(opt.run(), Err(Error::Poisoned));
    // Nothing moved after the panic.
    let iteration = opt.iteration();
    assert_eq!(iteration, 1);
}
