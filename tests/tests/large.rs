//! Large runs on a small stack: `N = 100_000` chains of 10-D Rastrigin, and
//! `N = 10` chains of 10 000-D Rastrigin, built and stepped with HRLA on a
//! thread whose stack is 256 KiB.
//!
//! The earlier optimiser held its `N` chains by value (`[Chain; N]`), so
//! either run needed tens of megabytes of stack, and failed with a stack
//! overflow (an abort, not an error) long before any memory limit. Now the
//! caller owns the chains: the storage is a `Vec` allocated outside the
//! thread and moved in (a pointer), the start lives on the heap and is
//! passed as `&mut Gaussian`, and the optimiser itself holds no array of
//! size `D` or `N` (`footprint.rs` checks its size). A 10 000-D chain is
//! 320 KB by itself, more than the whole stack: the run can only work if
//! nothing of size `D` is built on it, or only transiently (one `[f64; D]`
//! is 80 KB).

use hrla::{Builder, Chain, Error, Gaussian, Hrla, Rastrigin, Stop};

/// The stack of the thread that builds and steps the runs.
const STACK: usize = 256 * 1024;

/// Steps taken in each run.
const STEPS: u64 = 3;

/// What a run reports back from its thread.
struct Outcome<const D: usize> {
    chains: Vec<Chain<f64, D>>,
    iteration: u64,
    evaluations: u64,
    initial_best: f64,
    best: f64,
}

/// Builds a run over `chains` (the storage, moved in) from a start behind
/// a reference, on a thread with a 256 KiB stack, steps it `STEPS` times,
/// and hands the storage back.
fn run_on_small_stack<const D: usize>(
    chains: Vec<Chain<f64, D>>,
    mut start: Box<Gaussian<f64, D>>,
) -> Outcome<D> {
    std::thread::Builder::new()
        .name(format!("hrla-large-{D}"))
        .stack_size(STACK)
        .spawn(move || -> Result<Outcome<D>, Error> {
            let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, &mut *start)
                .seed(2025)
                .stop(Stop::new().steps(STEPS))
                .build(chains)?;
            let initial_best = opt.best().value;
            for _ in 0..STEPS {
                opt.step()?;
            }
            let (iteration, evaluations, best) =
                (opt.iteration(), opt.evaluations(), opt.best().value);
            Ok(Outcome {
                chains: opt.into_chains().into_inner(),
                iteration,
                evaluations,
                initial_best,
                best,
            })
        })
        .expect("spawn")
        .join()
        .expect("the run's thread panicked (or overflowed its stack)")
        .expect("the run failed")
}

/// Every chain stepped: live, finite, moved away from its initial point
/// (its velocity, zero at the start, is not zero any more), and its best
/// is at most its current value.
fn check_chains<const D: usize>(out: &Outcome<D>, n: usize) {
    assert_eq!(out.chains.len(), n);
    assert_eq!(out.iteration, STEPS);
    // One evaluation per chain for the initial points, then one per chain
    // and step.
    assert_eq!(out.evaluations, n as u64 * (STEPS + 1));
    assert!(out.best.is_finite() && out.best <= out.initial_best);
    // The global best is the lowest of the chains' own: every chain was
    // looked at.
    let lowest = out
        .chains
        .iter()
        .map(|c| c.best().value)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(out.best, lowest);
    for (c, chain) in out.chains.iter().enumerate() {
        assert!(!chain.is_diverged(), "chain {c} diverged");
        assert!(
            chain.value().is_finite(),
            "chain {c}: U = {}",
            chain.value()
        );
        assert!(chain.x().iter().all(|v| v.is_finite()), "chain {c}");
        assert!(chain.gradient().iter().all(|v| v.is_finite()), "chain {c}");
        assert!(chain.y().iter().any(|&v| v != 0.0), "chain {c} never moved");
        // Stride 1: the current iterate is recorded, so the best is at most
        // its value.
        assert!(chain.best().value <= chain.value(), "chain {c}");
    }
}

#[test]
fn hundred_thousand_chains_on_a_small_stack() {
    const N: usize = 100_000;
    const D: usize = 10;
    let chains: Vec<Chain<f64, D>> = vec![Chain::new(); N];
    let start = Box::new(Gaussian::new([3.0; D], 10f64.sqrt()).unwrap());
    let out = run_on_small_stack(chains, start);
    check_chains(&out, N);
    println!("N = {N}: best {:.3}", out.best);
}

#[test]
fn ten_thousand_dimensions_on_a_small_stack() {
    const N: usize = 10;
    const D: usize = 10_000;
    // 320 KB per chain: made on this thread's larger stack, one at a time.
    let chains: Vec<Chain<f64, D>> = (0..N).map(|_| Chain::new()).collect();
    let start = Box::new(Gaussian::new([3.0; D], 1.0).unwrap());
    let out = run_on_small_stack(chains, start);
    check_chains(&out, N);
    // Every one of the 10 000 coordinates of every chain was drawn and
    // stepped: none is still at the start's mean.
    for chain in &out.chains {
        assert!(chain.x().iter().all(|&v| v != 3.0));
        assert_eq!(chain.best().x.len(), D);
    }
    println!("D = {D}: best {:.1}", out.best);
}
