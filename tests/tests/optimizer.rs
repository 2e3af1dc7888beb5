//! Algorithm 1 end to end, and the optimiser's contract: running-best
//! bookkeeping, early stop at a target, divergence (some chains, all
//! chains, and a potential unbounded below), the application of a
//! schedule, a schedule value the sampler refuses, and construction errors.
//!
//! The optimiser is the crate's entry point and its `Report` (with
//! `Optimizer::best`) is all a caller sees of a run: every field is
//! recomputed here independently from the chains' observable state, so
//! that a bookkeeping slip (a best taken at the wrong iterate, from a
//! diverged chain, or lost after an error) cannot hide behind a run that
//! still finds the minimum.

use hrla::{
    Builder, Chain, Error, FnSchedule, FromFn, Gaussian, Hrla, HrlaParams, Kernel, Linear, Ola,
    OlaParams, Optimizer, Point, Potential, Rastrigin, Sampler, Schedule, Stop, Termination, Ula,
    UlaParams,
};
use hrla_tests::fixtures::Cliff;
use hrla_tests::hostile::same_error;
use rand_xoshiro::rand_core::Rng;

/// `n` empty chains of the default generator.
fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    vec![Chain::new(); n]
}

/// HRLA with the paper's `b = 10`, `alpha = beta = 1`, `h = 0.01` (the
/// inverse temperature is the optimiser's schedule).
fn paper_hrla() -> Hrla<f64> {
    Hrla::new(HrlaParams {
        b: 10.0,
        alpha: 1.0,
        beta: 1.0,
        h: 0.01,
    })
    .unwrap()
}

// ---------------------------------------------------------------------------
// (a) Algorithm 1 works on the paper's problem.

/// One run of the paper's setting: 10-D Rastrigin, HRLA with a = 4, b = 10,
/// alpha = beta = 1, h = 0.01, N = 10 chains, K = 14000 steps, start
/// `N(3·1, 10 I)`. Returns the running best (stride 1, initial points
/// included).
fn paper_run(seed: u64) -> f64 {
    let start = Gaussian::new([3.0; 10], 10f64.sqrt()).unwrap();
    let mut opt = Builder::new(Rastrigin, paper_hrla(), 4.0, start)
        .seed(seed)
        .stop(Stop::new().steps(14_000))
        .build(chains::<10>(10))
        .unwrap();
    let report = opt.run().unwrap();
    assert_eq!(report.iterations, 14_000);
    assert_eq!(report.termination, Termination::Steps);
    assert_eq!(report.diverged_chains, 0);
    assert_eq!(report.chains, 10);
    assert_eq!(report.evaluations, 10 * 14_001);
    assert_eq!(report.value, opt.best().value);
    report.value
}

/// Measured on the current kernel, with one generator per chain (x86_64,
/// seeds 0..100): the running best is below 1 in 100 of 100 runs; mean
/// 0.106, median 0.105, best 0.037, worst 0.179 (0.9 s on two threads).
/// (With the earlier shared stream: 100 of 100, mean 0.107, median 0.109,
/// best 0.038, worst 0.157.)
/// The thresholds (95 runs below 1, mean below 0.25) leave room for a change
/// of random stream without hiding a broken sampler: a sampler that does not
/// reach the basin of `x* = 0` in 10 dimensions ends near `U >= 1` (the
/// nearest local minima, with one coordinate near ±1, have U ≈ 1).
#[test]
fn algorithm_1_solves_10d_rastrigin_with_paper_parameters() {
    const RUNS: u64 = 100;
    const THREADS: u64 = 2;
    let t0 = std::time::Instant::now();
    let mut bests: Vec<(u64, f64)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..THREADS)
            .map(|t| {
                s.spawn(move || {
                    (t..RUNS)
                        .step_by(THREADS as usize)
                        .map(|seed| (seed, paper_run(seed)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    bests.sort_by_key(|&(seed, _)| seed);
    assert_eq!(bests.len(), RUNS as usize);
    let values: Vec<f64> = bests.iter().map(|&(_, v)| v).collect();
    let successes = values.iter().filter(|&&v| v < 1.0).count();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut sorted = values.clone();
    sorted.sort_by(f64::total_cmp);
    println!(
        "Algorithm 1, 10-D Rastrigin: {successes}/{RUNS} runs below 1; mean {mean:.4}, \
         median {:.4}, min {:.4}, max {:.4}; {:.2} s",
        sorted[sorted.len() / 2],
        sorted[0],
        sorted[sorted.len() - 1],
        t0.elapsed().as_secs_f64()
    );
    assert!(values.iter().all(|v| v.is_finite() && *v >= 0.0));
    assert!(successes >= 95, "only {successes}/100 runs below 1");
    assert!(mean < 0.25, "mean running best {mean}");
}

// ---------------------------------------------------------------------------
// (b) Running-best bookkeeping, checked against an independent recomputation.

/// Steps a 2-D Rastrigin optimiser one step at a time and recomputes every
/// chain's running best (over iterates 0, s, 2s, ...) and the global best
/// from the chains' observable values.
fn check_bookkeeping(stride: u64, seed: u64) {
    const N: usize = 8;
    /// A best point, owned: the recomputation's own record.
    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Kept {
        x: [f64; 2],
        value: f64,
        iteration: u64,
    }
    impl Kept {
        fn of(b: hrla::Best<'_, f64>) -> Self {
            Kept {
                x: b.x.try_into().unwrap(),
                value: b.value,
                iteration: b.iteration,
            }
        }
    }
    const K: u64 = 400;
    let start = Gaussian::new([3.0; 2], 10f64.sqrt()).unwrap();
    let mut opt = Builder::new(Rastrigin, paper_hrla(), 2.0, start)
        .seed(seed)
        .stride(stride)
        .stop(Stop::new().steps(K))
        .build(chains::<2>(N))
        .unwrap();

    let mut mine: Vec<Kept> = opt
        .chains()
        .iter()
        .map(|c| Kept {
            x: *c.x(),
            value: c.value(),
            iteration: 0,
        })
        .collect();
    let initial_min = mine.iter().map(|b| b.value).fold(f64::INFINITY, f64::min);
    assert_eq!(opt.best().value, initial_min);
    let mut previous_best = opt.best().value;
    let mut improved_at_non_multiple = false;

    for k in 1..=K {
        opt.step().unwrap();
        assert_eq!(opt.iteration(), k);
        for (c, chain) in opt.chains().iter().enumerate() {
            assert!(!chain.is_diverged());
            if chain.value() < mine[c].value {
                if k % stride == 0 {
                    mine[c] = Kept {
                        x: *chain.x(),
                        value: chain.value(),
                        iteration: k,
                    };
                } else {
                    improved_at_non_multiple = true;
                }
            }
            assert_eq!(Kept::of(chain.best()), mine[c], "chain {c} at k = {k}");
        }
        let best = Kept::of(opt.best());
        let min_of_chains = mine.iter().map(|b| b.value).fold(f64::INFINITY, f64::min);
        assert_eq!(best.value, min_of_chains);
        assert!(mine.contains(&best), "global best is not a chain's best");
        assert_eq!(best.iteration % stride, 0);
        assert!(!best.value.is_nan());
        assert!(best.value <= initial_min);
        assert!(best.value <= previous_best, "running best went up");
        previous_best = best.value;
        // `current_best`: the first live chain with the lowest current value.
        let mut current = (0, opt.chains()[0].value());
        for (i, c) in opt.chains().iter().enumerate() {
            if c.value() < current.1 {
                current = (i, c.value());
            }
        }
        assert_eq!(opt.current_best(), Some(current));
        assert!(best.value <= current.1 || k % stride != 0);
    }
    // The budget is spent: `run` reports without a step.
    let report = opt.run().unwrap();
    let best = Kept::of(opt.best());
    assert_eq!(report.termination, Termination::Steps);
    assert_eq!(report.value, best.value);
    assert_eq!(report.found_at, best.iteration);
    assert_eq!(Kept::of(opt.chains()[report.chain].best()), best);
    assert_eq!(mine[report.chain], best);
    assert_eq!(report.iterations, K);
    assert_eq!(report.evaluations, N as u64 * (K + 1));
    assert_eq!(opt.evaluations(), report.evaluations);
    if stride > 1 {
        // With a stride, lower values visited between recorded iterates
        // were ignored (so the stride really filters something).
        assert!(improved_at_non_multiple);
    }
}

#[test]
fn running_best_bookkeeping_stride_1() {
    check_bookkeeping(1, 21);
}

#[test]
fn running_best_bookkeeping_stride_7() {
    check_bookkeeping(7, 22);
}

#[test]
fn running_best_bookkeeping_stride_100() {
    check_bookkeeping(100, 23);
}

/// The stride changes what is recorded, never the trajectory: the chains
/// of stride 1 and stride 10 runs from one seed coincide, and the stride-10
/// best is no better than the stride-1 best.
#[test]
fn stride_does_not_change_the_trajectory() {
    let make = |stride| {
        let start = Gaussian::new([3.0; 4], 10f64.sqrt()).unwrap();
        let mut opt = Builder::new(Rastrigin, paper_hrla(), 3.0, start)
            .seed(99)
            .stride(stride)
            .stop(Stop::new().steps(1000))
            .build(chains::<4>(6))
            .unwrap();
        let report = opt.run().unwrap();
        (report, opt.chains().to_vec())
    };
    let (r1, c1) = make(1);
    let (r10, c10) = make(10);
    for (a, b) in c1.iter().zip(&c10) {
        assert_eq!(a.x(), b.x());
        assert_eq!(a.y(), b.y());
        assert_eq!(a.value().to_bits(), b.value().to_bits());
    }
    assert!(r1.value <= r10.value);
    assert_eq!(r10.found_at % 10, 0);
    // Over 1000 steps the stride-1 best is strictly better (a measured fact
    // of this seed: it is unlikely that the minimum falls on a multiple of 10).
    assert!(r1.value < r10.value);
}

// ---------------------------------------------------------------------------
// (c) Early stop at a target.

#[test]
fn target_stops_the_run_early() {
    const BUDGET: u64 = 100_000;
    const TARGET: f64 = 0.05;
    let build = || {
        let start = Gaussian::new([3.0; 2], 10f64.sqrt()).unwrap();
        Builder::new(Rastrigin, paper_hrla(), 4.0, start)
            .seed(31)
            .stop(Stop::new().steps(BUDGET).target(TARGET))
            .build(chains::<2>(4))
            .unwrap()
    };
    let mut opt = build();
    assert!(
        opt.best().value > TARGET,
        "the start already meets the target"
    );
    assert_eq!(opt.termination(), None);
    let report = opt.run().unwrap();
    println!("target {TARGET} reached after {} steps", report.iterations);
    assert_eq!(report.termination, Termination::Target);
    assert_eq!(opt.termination(), Some(Termination::Target));
    assert!(report.value <= TARGET);
    assert!(report.iterations > 0 && report.iterations < BUDGET);
    assert_eq!(report.diverged_chains, 0);
    assert_eq!(report.evaluations, 4 * (report.iterations + 1));
    // Running again does nothing: the target is met.
    let again = opt.run().unwrap();
    assert_eq!(again, report);

    // Replay by hand: the run stopped at the first iterate whose best meets
    // the target.
    let mut replay = build();
    let mut k = 0;
    loop {
        replay.step().unwrap();
        k += 1;
        if replay.best().value <= TARGET {
            assert_eq!(replay.termination(), Some(Termination::Target));
            break;
        }
        assert_eq!(replay.termination(), None);
    }
    assert_eq!(k, report.iterations);
    assert_eq!(replay.run().unwrap(), report);
    assert_eq!(replay.best(), opt.best());
}

#[test]
fn target_already_met_runs_no_step() {
    let start = Point::new([0.0, 0.5]).unwrap();
    let mut opt = Builder::new(Rastrigin, paper_hrla(), 4.0, start)
        .seed(1)
        .stop(Stop::new().steps(1000).target(4.25))
        .build(chains::<2>(2))
        .unwrap();
    // U(0, 0.5) = 0.25 + 2 = 2.25 <= 4.25.
    assert_eq!(opt.termination(), Some(Termination::Target));
    let report = opt.run().unwrap();
    assert_eq!(report.termination, Termination::Target);
    assert_eq!(report.iterations, 0);
    assert_eq!(report.evaluations, 2);
    assert_eq!(report.value, 2.25);
    assert_eq!(report.found_at, 0);
}

// ---------------------------------------------------------------------------
// (d) Divergence.

/// The chains' generator states: the next output of a copy of each.
fn rng_states<const D: usize>(chains: &[Chain<f64, D>]) -> Vec<u64> {
    chains.iter().map(|c| c.rng().clone().next_u64()).collect()
}

/// Chains 0, 2, 4 start in the well, 1, 3, 5 on the slope: the latter leave
/// `|x| <= 6` within a few dozen steps and diverge; the former stay (at a = 4
/// the well's law is N(0, 1/4), and |x| = 3 is 6 standard deviations out).
fn check_partial_divergence(cliff: Cliff) {
    const N: usize = 6;
    let start = FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| {
        x.copy_from_slice(&if c.is_multiple_of(2) { [0.0] } else { [4.5] })
    });
    let mut opt = Builder::new(cliff, paper_hrla(), 4.0, start)
        .seed(41)
        .stop(Stop::new().steps(500))
        .build(chains::<1>(N))
        .unwrap();
    let mut evaluations = N as u64;
    // Per chain: (iterate of divergence, x, y, generator state) once diverged.
    type Frozen = Option<(u64, [f64; 1], [f64; 1], u64)>;
    let mut frozen: Vec<Frozen> = vec![None; N];
    for k in 1..=500u64 {
        let live = opt.chains().iter().filter(|c| !c.is_diverged()).count() as u64;
        assert_eq!(opt.step().map(|_| ()), Ok(()));
        evaluations += live;
        assert_eq!(opt.evaluations(), evaluations);
        let states = rng_states(opt.chains());
        for (c, chain) in opt.chains().iter().enumerate() {
            if chain.is_diverged() {
                match frozen[c] {
                    None => frozen[c] = Some((k, *chain.x(), *chain.y(), states[c])),
                    Some((_, x, y, state)) => {
                        // Frozen: no more moves, no more draws.
                        assert_eq!(x[0].to_bits(), chain.x()[0].to_bits());
                        assert_eq!(y[0].to_bits(), chain.y()[0].to_bits());
                        assert_eq!(state, states[c]);
                    }
                }
            }
        }
        assert_eq!(
            opt.diverged_chains(),
            frozen.iter().filter(|f| f.is_some()).count()
        );
        assert!(opt.best().value.is_finite());
    }
    let report = opt.run().unwrap();
    assert_eq!(report.iterations, 500);
    assert_eq!(report.termination, Termination::Steps);
    assert_eq!(report.diverged_chains, 3);
    assert_eq!(report.chains, N);
    for (c, chain) in opt.chains().iter().enumerate() {
        assert_eq!(chain.is_diverged(), c % 2 == 1, "chain {c}");
        if c % 2 == 1 {
            let (k, x, _, _) = frozen[c].unwrap();
            assert!(k < 100, "chain {c} diverged only at {k}");
            assert!(x[0].abs() > 6.0);
            // The value that stopped it is kept, the gradient is non-finite
            // or the value is.
            let v = chain.value();
            assert!(
                v.to_bits() == cliff.outside.to_bits() || (v.is_nan() && cliff.outside.is_nan())
            );
            assert!(!(v.is_finite() && chain.gradient()[0].is_finite()));
            // Its running best is a recorded slope value, never the outside.
            assert!(chain.best().value >= 70.0 && chain.best().value <= 85.0);
        } else {
            assert!(chain.best().value < 1.0);
        }
    }
    // The global best comes from a live chain, inside the well.
    let best = opt.best();
    assert!(report.value.is_finite());
    assert_eq!(report.value, best.value);
    assert!(best.x[0].abs() <= 3.0);
    assert!(!opt.chains()[report.chain].is_diverged());
    let live_min = opt
        .chains()
        .iter()
        .filter(|c| !c.is_diverged())
        .map(|c| c.best().value)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(report.value, live_min);
    // `current_best` ignores diverged chains.
    let (i, v) = opt.current_best().unwrap();
    assert_eq!(i % 2, 0);
    assert!(v.is_finite());
}

#[test]
fn nan_value_beyond_radius_freezes_chains() {
    check_partial_divergence(Cliff {
        outside: f64::NAN,
        outside_grad: f64::NAN,
    });
}

#[test]
fn infinite_gradient_beyond_radius_freezes_chains_with_finite_value() {
    // Beyond 6 the value is very low (-1000) but the gradient infinite: the
    // chain diverges and -1000 must not enter any best (nor does it look
    // unbounded: it is far above -sqrt(MAX)).
    check_partial_divergence(Cliff {
        outside: -1000.0,
        outside_grad: f64::INFINITY,
    });
}

/// A value of `-inf` beyond the radius used to freeze the chain like any
/// non-finite value; it now means the potential looks unbounded below, and
/// the step that meets it is `Err(UnboundedBelow)` naming the chain, not a
/// report: the first slope chain to leave, at the first step one does.
#[test]
fn negative_infinity_value_beyond_radius_is_unbounded_below() {
    let cliff = Cliff {
        outside: f64::NEG_INFINITY,
        outside_grad: 0.0,
    };
    let start = FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| {
        x.copy_from_slice(&if c.is_multiple_of(2) { [0.0] } else { [4.5] })
    });
    let mut opt = Builder::new(cliff, paper_hrla(), 4.0, start)
        .seed(41)
        .stop(Stop::new().steps(500))
        .build(chains::<1>(6))
        .unwrap();
    let mut k = 0;
    let err = loop {
        k += 1;
        assert!(k < 100, "no chain left the slope in 100 steps");
        if let Err(e) = opt.step() {
            break e;
        }
        assert!(opt.chains().iter().all(|c| c.x()[0].abs() <= 6.0));
    };
    let Error::UnboundedBelow { chain, value } = err else {
        panic!("expected UnboundedBelow, got {err:?}");
    };
    assert_eq!(value, f64::NEG_INFINITY);
    assert_eq!(chain % 2, 1, "a well chain cannot leave");
    // `chain` is the first (lowest index) chain outside.
    let outside: Vec<usize> = (0..6)
        .filter(|&c| opt.chains()[c].x()[0].abs() > 6.0)
        .collect();
    assert_eq!(outside.first(), Some(&chain));
    assert_eq!(opt.iteration(), k);
    assert_eq!(opt.chains()[chain].value(), f64::NEG_INFINITY);
    // No best is -inf.
    assert!(opt.best().value.is_finite());
    assert!(opt.chains()[chain].best().value.is_finite());
}

/// `U(x) = -sum x_i^4` pushes every chain to infinity in finite time.
#[derive(Debug)]
struct Explode;

impl Potential<f64, 2> for Explode {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        for (gi, xi) in g.iter_mut().zip(x) {
            *gi = -4.0 * xi * xi * xi;
        }
        -x.iter().map(|v| v * v * v * v).sum::<f64>()
    }
}

/// A blow-up of `U = -|x|^4` used to end in a report with every chain
/// diverged; it now ends in `Err(UnboundedBelow)` at the first step where
/// some chain's `U` falls below `-sqrt(f64::MAX)` (or to `-inf`), and the
/// best kept is finite and below the start.
#[test]
fn blow_up_is_unbounded_below() {
    const BUDGET: u64 = 1000;
    let start = Point::new([1.0, -1.0]).unwrap();
    let mut opt = Builder::new(Explode, paper_hrla(), 4.0, start)
        .seed(51)
        .stop(Stop::new().steps(BUDGET))
        .build(chains::<2>(4))
        .unwrap();
    let err = opt.run().unwrap_err();
    println!(
        "{err} after {} steps; best {:e}",
        opt.iteration(),
        opt.best().value
    );
    let Error::UnboundedBelow { chain, value } = err else {
        panic!("expected UnboundedBelow, got {err:?}");
    };
    let floor = -f64::MAX.sqrt();
    assert!(value < floor, "{value}");
    assert_eq!(opt.chains()[chain].value().to_bits(), value.to_bits());
    // The first chain below the floor is the one named.
    let first = opt.chains().iter().position(|c| c.value() < floor).unwrap();
    assert_eq!(first, chain);
    assert!(opt.iteration() < BUDGET);
    assert!(opt.best().value.is_finite());
    assert!(
        opt.best().value < -2.0,
        "the best should have moved down from U(x0) = -2"
    );
}

/// A 1-D well with a NaN gradient and value beyond `|x| = 6`: every chain
/// starts on the outward slope and leaves, so the run ends with
/// `Err(AllDiverged)` (a potential bounded below: no `UnboundedBelow`).
/// A fully diverged optimiser then refuses every step with the same
/// error, without drawing a random number, evaluating anything or moving
/// its iterate.
#[test]
fn all_chains_diverging_is_an_error() {
    const N: usize = 4;
    let cliff = Cliff {
        outside: f64::NAN,
        outside_grad: f64::NAN,
    };
    let start = Point::new([4.5]).unwrap();
    let mut opt = Builder::new(cliff, paper_hrla(), 4.0, start)
        .seed(52)
        .stop(Stop::new().steps(1000))
        .build(chains::<1>(N))
        .unwrap();
    let err = opt.run().unwrap_err();
    assert_eq!(err, Error::AllDiverged { chains: N });
    let k = opt.iteration();
    println!("all {N} chains diverged after {k} steps");
    assert!(k < 100);
    assert_eq!(opt.diverged_chains(), N);
    assert!(opt.current_best().is_none());
    assert_eq!(opt.termination(), None);
    for c in opt.chains() {
        assert!(c.is_diverged());
        assert!(c.value().is_nan());
        assert!(c.best().value.is_finite());
    }
    // The best is a recorded slope value, finite.
    assert!(opt.best().value.is_finite() && opt.best().value <= 85.0);
    let evaluations = opt.evaluations();
    let before = opt.chains().to_vec();
    let states = rng_states(opt.chains());
    for _ in 0..3 {
        assert_eq!(opt.step(), Err(Error::AllDiverged { chains: N }));
        assert_eq!(opt.run(), Err(Error::AllDiverged { chains: N }));
    }
    assert_eq!(opt.iteration(), k);
    assert_eq!(opt.evaluations(), evaluations);
    assert_eq!(rng_states(opt.chains()), states);
    for (a, b) in before.iter().zip(opt.chains()) {
        assert_eq!(a.x().map(f64::to_bits), b.x().map(f64::to_bits));
        assert_eq!(a.y().map(f64::to_bits), b.y().map(f64::to_bits));
    }
}

// ---------------------------------------------------------------------------
// (e) The optimiser applies the schedule.

/// The step from iterate k to k + 1 runs at a_k: before any step the
/// optimiser's kernel is at a_0; after j steps it is at a_{j-1}, its
/// coefficients are those of a fresh sampler's kernel at a_{j-1}, each
/// chain moved exactly as that fresh kernel moves it with the same random
/// numbers (a copy of its own generator), and the sampler itself (without
/// `a`) never changes.
fn check_schedule_is_applied<S>(make: impl Fn() -> S)
where
    S: Sampler<f64> + Clone + PartialEq + std::fmt::Debug,
    S::Kernel: PartialEq + std::fmt::Debug,
{
    let schedule = Linear::new(0.5, 3.0, 10).unwrap();
    let start = Gaussian::new([1.0; 3], 1.0).unwrap();
    let mut opt = Builder::new(Rastrigin, make(), schedule, start)
        .seed(61)
        .stop(Stop::new().steps(15))
        .build(chains::<3>(3))
        .unwrap();
    // Before any step the kernel is at the schedule's a_0.
    assert_eq!(opt.kernel().inverse_temperature(), 0.5);
    assert_eq!(opt.kernel(), &make().at(0.5).unwrap());
    for j in 1..=15u64 {
        let before: Vec<_> = opt.chains().to_vec();
        opt.step().unwrap();
        let a = schedule.inverse_temperature(j - 1);
        assert_eq!(opt.kernel().inverse_temperature().to_bits(), a.to_bits());
        assert_eq!(opt.sampler(), &make(), "the sampler changed at step {j}");
        let fresh = make().at(a).unwrap();
        assert_eq!(opt.kernel(), &fresh, "coefficients at step {j}");
        for (c, (old, new)) in before.iter().zip(opt.chains()).enumerate() {
            let (mut x, mut y) = (*old.x(), *old.y());
            let mut replay_rng = old.rng().clone();
            fresh.step(&mut x, &mut y, old.gradient(), &mut replay_rng);
            assert_eq!(x.map(f64::to_bits), new.x().map(f64::to_bits), "chain {c}");
            assert_eq!(y.map(f64::to_bits), new.y().map(f64::to_bits), "chain {c}");
            assert_eq!(&replay_rng, new.rng(), "chain {c}");
        }
    }
}

#[test]
fn optimiser_applies_the_schedule_to_each_sampler() {
    check_schedule_is_applied(paper_hrla);
    check_schedule_is_applied(|| Ula::new(UlaParams::paper(0.01)).unwrap());
    check_schedule_is_applied(|| Ola::new(OlaParams::paper(0.01)).unwrap());
}

// ---------------------------------------------------------------------------
// (f) A schedule value the sampler refuses.

type Owned<F> = hrla::Chains<F, Vec<Chain<F, 2>>, 2>;

fn state_of<F: hrla::Float, S: Sampler<F>, C: Schedule<F>>(
    opt: &Optimizer<F, Rastrigin, S, C, Owned<F>>,
) -> Vec<u64> {
    let mut bits = Vec::new();
    for c in opt.chains() {
        bits.extend(c.x().iter().chain(c.y()).map(|v| v.to_bits_u64()));
        bits.push(c.value().to_bits_u64());
        bits.push(c.rng().clone().next_u64());
    }
    let best = opt.best();
    bits.extend(best.x.iter().map(|v| v.to_bits_u64()));
    bits.push(best.value.to_bits_u64());
    bits.push(opt.kernel().inverse_temperature().to_bits_u64());
    bits.push(opt.iteration());
    bits.push(opt.evaluations());
    bits
}

/// The schedule gives 2.0 for k < 3 and `bad` from k = 3: the fourth step
/// fails with `expected`, leaving the state and every generator untouched,
/// and keeps failing.
fn check_bad_schedule_value(bad: f64, expected: impl Fn(&Error) -> bool) {
    let schedule = FnSchedule(move |k: u64| if k < 3 { 2.0 } else { bad });
    let start = Gaussian::new([2.0; 2], 1.0).unwrap();
    let mut opt = Builder::new(Rastrigin, paper_hrla(), schedule, start)
        .seed(71)
        .stop(Stop::new().steps(10))
        .build(vec![Chain::new(); 3])
        .unwrap();
    for _ in 0..3 {
        assert_eq!(opt.step().map(|_| ()), Ok(()));
    }
    let before = state_of(&opt);
    for _ in 0..2 {
        let err = opt.step().unwrap_err();
        assert!(expected(&err), "bad a = {bad}: got {err:?}");
        assert_eq!(state_of(&opt), before);
        assert_eq!(opt.iteration(), 3);
    }
    // `run` propagates the error too.
    let err = opt.run().unwrap_err();
    assert!(expected(&err));
    assert_eq!(state_of(&opt), before);
}

#[test]
fn bad_schedule_value_is_an_error_and_changes_nothing() {
    check_bad_schedule_value(
        f64::NAN,
        |e| matches!(e, Error::NotPositive { name: "a", value } if value.is_nan()),
    );
    check_bad_schedule_value(0.0, |e| {
        *e == Error::NotPositive {
            name: "a",
            value: 0.0,
        }
    });
    check_bad_schedule_value(-1.0, |e| {
        *e == Error::NotPositive {
            name: "a",
            value: -1.0,
        }
    });
    check_bad_schedule_value(f64::INFINITY, |e| {
        *e == Error::NotPositive {
            name: "a",
            value: f64::INFINITY,
        }
    });
    // Positive but outside [1e-6, 1e6]: 5e-324 used to be refused only
    // because sx2 = beta/a overflowed; 1e7 used to be accepted.
    for a in [5e-324, 1e7] {
        check_bad_schedule_value(a, |e| {
            *e == Error::OutOfRange {
                name: "a",
                value: a,
                min: 1e-6,
                max: 1e6,
            }
        });
    }
}

// ---------------------------------------------------------------------------
// (g) Construction errors.

/// The chain count is the storage's length: any positive length builds
/// (there is no capacity any more), an empty storage is `Zero`; a zero
/// stride and a non-finite target are refused by `build`.
#[test]
fn chain_count_and_setting_errors() {
    let start = Point::new([1.0, 2.0]).unwrap();
    let builder = || Builder::new(Rastrigin, paper_hrla(), 4.0, start).seed(81);
    assert_eq!(
        builder().build(chains::<2>(0)).map(|o| o.iteration()),
        Err(Error::Zero { name: "chains" })
    );
    for n in [1, 4, 5, 1000] {
        let opt = builder().build(chains::<2>(n)).unwrap();
        assert_eq!(opt.chains().len(), n);
        assert_eq!(opt.evaluations(), n as u64);
    }
    assert_eq!(
        builder()
            .stride(0)
            .build(chains::<2>(2))
            .map(|o| o.iteration()),
        Err(Error::Zero { name: "stride" })
    );
    let err = builder()
        .stop(Stop::new().target(f64::NAN))
        .build(chains::<2>(2))
        .map(|o| o.iteration())
        .unwrap_err();
    assert!(matches!(err, Error::NotFinite { name: "target", value } if value.is_nan()));
    assert_eq!(
        builder()
            .stop(Stop::new().target(f64::NEG_INFINITY))
            .build(chains::<2>(2))
            .map(|o| o.iteration()),
        Err(Error::NotFinite {
            name: "target",
            value: f64::NEG_INFINITY
        })
    );
}

/// The schedule's `a_0` is taken at construction: a value the sampler
/// refuses is the sampler's error, from `build`, whether the schedule is a
/// plain float or a function whose later values are fine.
#[test]
fn refused_initial_temperature_errors() {
    let start = Point::new([1.0, 2.0]).unwrap();
    let out_of_range = |a: f64| Error::OutOfRange {
        name: "a",
        value: a,
        min: 1e-6,
        max: 1e6,
    };
    let cases: [(f64, Error); 6] = [
        (
            0.0,
            Error::NotPositive {
                name: "a",
                value: 0.0,
            },
        ),
        (
            -1.0,
            Error::NotPositive {
                name: "a",
                value: -1.0,
            },
        ),
        (
            f64::INFINITY,
            Error::NotPositive {
                name: "a",
                value: f64::INFINITY,
            },
        ),
        (
            f64::NAN,
            Error::NotPositive {
                name: "a",
                value: f64::NAN,
            },
        ),
        // Positive but outside [1e-6, 1e6] (5e-324 used to be refused only
        // because sx2 = beta/a overflowed; 2e6 used to be accepted).
        (5e-324, out_of_range(5e-324)),
        (2e6, out_of_range(2e6)),
    ];
    for (a0, want) in cases {
        let plain = Builder::new(Rastrigin, paper_hrla(), a0, start)
            .build(chains::<2>(2))
            .map(|o| o.iteration());
        let schedule = FnSchedule(move |k: u64| if k == 0 { a0 } else { 4.0 });
        let by_fn = Builder::new(Rastrigin, paper_hrla(), schedule, start)
            .build(chains::<2>(2))
            .map(|o| o.iteration());
        for got in [plain, by_fn] {
            let err = got.unwrap_err();
            assert!(same_error(&err, &want), "a_0 = {a0}: {err:?}");
        }
    }
    // A bad value later in the schedule is not `build`'s concern: it is the
    // error of the step that uses it (see
    // `bad_schedule_value_is_an_error_and_changes_nothing`).
    let schedule = FnSchedule(|k: u64| if k == 0 { 4.0 } else { f64::NAN });
    let opt = Builder::new(Rastrigin, paper_hrla(), schedule, start)
        .build(chains::<2>(2))
        .unwrap();
    assert_eq!(opt.kernel().inverse_temperature(), 4.0);
}

/// Finite everywhere except a NaN gradient at the origin.
#[derive(Debug)]
struct NanGradientAtOrigin;

impl Potential<f64, 2> for NanGradientAtOrigin {
    fn value_and_gradient(&self, x: &[f64; 2], g: &mut [f64; 2]) -> f64 {
        *g = if *x == [0.0, 0.0] {
            [f64::NAN, 0.0]
        } else {
            [0.0; 2]
        };
        1.0
    }
}

/// `NonFiniteStart` names the first bad chain, what was not finite (its
/// `position`, its `value`, or its `gradient`) and how many points it drew:
/// these starts give the same bad point at every draw, so all of
/// `START_TRIES`.
#[test]
fn non_finite_start_errors() {
    let start_error = |chain, what| Error::NonFiniteStart {
        chain,
        what,
        tries: hrla::START_TRIES,
    };
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let start = FromFn(move |c: usize, _: &mut dyn Rng, x: &mut [f64]| {
            x.copy_from_slice(&{ if c == 2 { [0.0, bad] } else { [1.0, 1.0] } })
        });
        let got = Builder::new(Rastrigin, paper_hrla(), 4.0, start)
            .build(chains::<2>(4))
            .map(|o| o.iteration());
        assert_eq!(got, Err(start_error(2, "position")));
    }
    // A finite point where U overflows: (1e200)^2 = inf.
    let start = Point::new([1e200, 0.0]).unwrap();
    let got = Builder::new(Rastrigin, paper_hrla(), 4.0, start)
        .build(chains::<2>(3))
        .map(|o| o.iteration());
    assert_eq!(got, Err(start_error(0, "value")));
    // A finite value beside a NaN gradient.
    let start = FromFn(|c: usize, _: &mut dyn Rng, x: &mut [f64]| {
        x.copy_from_slice(&[1.0 - c as f64, 0.0])
    });
    let got = Builder::new(NanGradientAtOrigin, paper_hrla(), 4.0, start)
        .build(chains::<2>(3))
        .map(|o| o.iteration());
    assert_eq!(got, Err(start_error(1, "gradient")));
    // A huge but finite standard deviation sends x^2 to infinity.
    let start = Gaussian::new([0.0; 2], 1e300).unwrap();
    let got = Builder::new(Rastrigin, paper_hrla(), 4.0, start)
        .build(chains::<2>(3))
        .map(|o| o.iteration());
    assert_eq!(got, Err(start_error(0, "value")));
}
