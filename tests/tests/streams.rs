//! One random stream per chain: chain `c` of a run seeded with `seed`
//! draws its initial point and every step's normals from its own generator,
//! `R::seed_from_u64(chain_seed(seed, c))`, and from nothing else.
//!
//! - chain `c`'s whole trajectory (position, velocity, gradient, value,
//!   running best, generator state after every step) is bit-identical in a
//!   run of `N` chains, in a run of `c + 1` chains (the fewest that contain
//!   chain `c`) and in a run of more chains, for every `c`; for HRLA, ULA
//!   and OLA, f64 and f32, the default generator and `Xoshiro128PlusPlus`,
//!   with and without annealing;
//! - it is also what a replay by hand gives: the documented generator,
//!   the start's draws, then the sampler's kernel step after step;
//! - the kind of storage (`Vec`, array, `&mut [Chain]`, `heapless::Vec`)
//!   changes nothing, nor does the way the run is driven (`step`, `run`,
//!   `run_with` paused and resumed, in any mix);
//! - different seeds, and different chains of one seed, get different
//!   streams;
//! - `chain_seed` and `splitmix64` are pinned: SplitMix64's published first
//!   outputs, and two golden values of `chain_seed`.
//!
//! Before this design the chains shared one generator, so chain `c`'s
//! numbers depended on how many chains were stepped before it: adding a
//! chain changed every other chain's run.

use std::collections::HashSet;
use std::ops::ControlFlow;

use hrla::{
    Builder, Chain, Float, Gaussian, Hrla, Kernel, Linear, Ola, Potential, Rastrigin, Sampler,
    Schedule, Start, Stop, Termination, Ula, chain_seed, heapless, splitmix64,
};
use rand_xoshiro::rand_core::{Rng, SeedableRng};
use rand_xoshiro::{Xoshiro128PlusPlus, Xoshiro256PlusPlus};

const D: usize = 3;
const STEPS: u64 = 200;

/// One chain's observable state, as bits, with its generator's state.
fn chain_bits<F: Float, R: Rng + Clone>(c: &Chain<F, D, R>) -> Vec<u64> {
    let mut out = Vec::new();
    hrla_tests::bits::chain_bits(c, &mut out);
    out
}

/// The start of every run here: the paper's `N(3·1, 10 I)`.
fn start<F: Float>() -> Gaussian<F, D> {
    Gaussian::new([F::from_f64(3.0); D], F::from_f64(10f64.sqrt())).unwrap()
}

/// `trajectories[c][k]`: chain `c`'s state after `k` steps in a run of `n`
/// chains on 3-D Rastrigin.
fn trajectories<F, S, C, R>(sampler: S, schedule: C, seed: u64, n: usize) -> Vec<Vec<Vec<u64>>>
where
    F: Float,
    S: Sampler<F>,
    C: Schedule<F>,
    R: Rng + SeedableRng + Clone + 'static,
{
    let chains: Vec<Chain<F, D, R>> = (0..n).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(Rastrigin, sampler, schedule, start())
        .seed(seed)
        .stop(Stop::new().steps(STEPS))
        .build(chains)
        .unwrap();
    let mut out: Vec<Vec<Vec<u64>>> = opt.chains().iter().map(|c| vec![chain_bits(c)]).collect();
    for _ in 0..STEPS {
        opt.step().unwrap();
        for (t, c) in out.iter_mut().zip(opt.chains()) {
            t.push(chain_bits(c));
        }
    }
    out
}

/// Chain `c` of a run of `N` chains, of `c + 1` chains and of `2N + 3`
/// chains: the same bits at every step, for every `c`.
fn check_independence<F, S, C, R>(sampler: S, schedule: C, seed: u64)
where
    F: Float,
    S: Sampler<F> + Clone,
    C: Schedule<F> + Clone,
    R: Rng + SeedableRng + Clone + 'static,
{
    const N: usize = 8;
    let all = trajectories::<F, S, C, R>(sampler.clone(), schedule.clone(), seed, N);
    let more = trajectories::<F, S, C, R>(sampler.clone(), schedule.clone(), seed, 2 * N + 3);
    for c in 0..N {
        let fewest = trajectories::<F, S, C, R>(sampler.clone(), schedule.clone(), seed, c + 1);
        assert_eq!(fewest.len(), c + 1);
        assert_eq!(all[c].len(), STEPS as usize + 1);
        // The chain did move: equal trajectories are not equal constants.
        assert_ne!(all[c][0], all[c][STEPS as usize]);
        for k in 0..=STEPS as usize {
            assert_eq!(
                all[c][k],
                fewest[c][k],
                "chain {c}, iterate {k}: N = {N} vs {}",
                c + 1
            );
            assert_eq!(
                all[c][k],
                more[c][k],
                "chain {c}, iterate {k}: N = {N} vs {}",
                2 * N + 3
            );
        }
    }
    // Distinct chains of one run are distinct streams.
    let firsts: HashSet<&Vec<u64>> = more.iter().map(|t| &t[0]).collect();
    assert_eq!(firsts.len(), 2 * N + 3);
}

#[test]
fn chain_c_is_the_same_in_runs_of_any_size() {
    let linear = Linear::new(0.1, 4.0, STEPS).unwrap();
    check_independence::<f64, _, _, Xoshiro256PlusPlus>(Hrla::paper(0.01).unwrap(), linear, 7);
    check_independence::<f64, _, _, Xoshiro256PlusPlus>(Ula::paper(0.01).unwrap(), 4.0, 8);
    check_independence::<f64, _, _, Xoshiro128PlusPlus>(Ola::paper(0.01).unwrap(), 4.0, 9);
    let linear32 = Linear::new(0.1f32, 4.0, STEPS).unwrap();
    check_independence::<f32, _, _, Xoshiro128PlusPlus>(Hrla::paper(0.01).unwrap(), linear32, 10);
    check_independence::<f32, _, _, Xoshiro256PlusPlus>(Ola::paper(0.01).unwrap(), 2.0f32, 11);
    check_independence::<f32, _, _, Xoshiro256PlusPlus>(Hrla::paper(0.01).unwrap(), 2.0f32, 12);
}

/// Chain `c`, replayed by hand from the documented definition: a generator
/// `R::seed_from_u64(chain_seed(seed, c))`, the start's draws from it, the
/// potential there, then the kernel at `a_k` step after step with the same
/// generator. Compared with every chain of a run of 5.
fn check_replay<F, S, C, R>(sampler: S, schedule: C, seed: u64)
where
    F: Float,
    S: Sampler<F> + Clone,
    C: Schedule<F> + Clone,
    R: Rng + SeedableRng + Clone + 'static,
{
    let run = trajectories::<F, S, C, R>(sampler.clone(), schedule.clone(), seed, 5);
    for (c, traj) in run.iter().enumerate() {
        let mut rng = R::seed_from_u64(chain_seed(seed, c as u64));
        let (mut x, mut y, mut g) = ([F::ZERO; D], [F::ZERO; D], [F::ZERO; D]);
        start().initial_point(c, &mut rng, &mut x);
        let mut value = Rastrigin.value_and_gradient(&x, &mut g);
        let mut best = (x, value, 0u64);
        for k in 0..=STEPS {
            if k > 0 {
                let kernel = sampler.at(schedule.inverse_temperature(k - 1)).unwrap();
                kernel.step(&mut x, &mut y, &g, &mut rng);
                value = Rastrigin.value_and_gradient(&x, &mut g);
                if value < best.1 {
                    best = (x, value, k);
                }
            }
            let mut want = Vec::new();
            want.extend(x.iter().chain(&y).chain(&g).map(|v| v.to_bits_u64()));
            want.push(value.to_bits_u64());
            want.extend(best.0.iter().map(|v| v.to_bits_u64()));
            want.push(best.1.to_bits_u64());
            want.push(best.2);
            want.push(0);
            want.push(rng.clone().next_u64());
            assert_eq!(traj[k as usize], want, "chain {c} at iterate {k}");
        }
    }
}

#[test]
fn a_chain_is_its_documented_stream() {
    let linear = Linear::new(0.1, 4.0, STEPS).unwrap();
    check_replay::<f64, _, _, Xoshiro256PlusPlus>(Hrla::paper(0.01).unwrap(), linear, 3);
    check_replay::<f64, _, _, Xoshiro256PlusPlus>(Ola::paper(0.01).unwrap(), 4.0, 4);
    check_replay::<f32, _, _, Xoshiro128PlusPlus>(Ula::paper(0.01).unwrap(), 4.0f32, 5);
}

/// Every chain of a run, as bits.
fn all_bits<F: Float, R: Rng + Clone>(chains: &[Chain<F, D, R>]) -> Vec<Vec<u64>> {
    chains.iter().map(chain_bits).collect()
}

/// The same run in a `Vec`, an array, a `&mut` slice and a
/// `heapless::Vec`: the same bits.
#[test]
fn the_kind_of_storage_changes_nothing() {
    const N: usize = 6;
    let build = || Builder::new(Rastrigin, Hrla::paper(0.01).unwrap(), 4.0, start()).seed(21);
    let steps = |opt: &mut dyn FnMut() -> Result<(), hrla::Error>| {
        for _ in 0..STEPS {
            opt().unwrap();
        }
    };

    let mut by_vec = build().build(vec![Chain::new(); N]).unwrap();
    steps(&mut || by_vec.step().map(|_| ()));
    let want = all_bits(by_vec.chains());

    let mut by_array = build()
        .build(core::array::from_fn::<_, N, _>(|_| Chain::new()))
        .unwrap();
    steps(&mut || by_array.step().map(|_| ()));
    assert_eq!(all_bits(by_array.chains()), want);

    let mut storage = vec![Chain::new(); N];
    let mut by_slice = build().build(&mut storage[..]).unwrap();
    steps(&mut || by_slice.step().map(|_| ()));
    assert_eq!(all_bits(by_slice.chains()), want);
    // The caller's storage holds the final states.
    assert_eq!(all_bits(&storage), want);

    let chains: heapless::Vec<Chain<f64, D>, 8> = (0..N).map(|_| Chain::new()).collect();
    let mut by_heapless = build().build(chains).unwrap();
    steps(&mut || by_heapless.step().map(|_| ()));
    assert_eq!(all_bits(by_heapless.chains()), want);
    assert_eq!(all_bits(&by_heapless.into_chains().into_inner()), want);
}

/// `run()` to the budget, `step()` to the budget, and `run_with` paused by
/// its observer every 17 steps and resumed by `step` and `run_with` again
/// until `run()` finishes: the same bits for every chain, the same report.
#[test]
fn the_way_a_run_is_driven_changes_nothing() {
    const N: usize = 5;
    let build = || {
        Builder::new(
            Rastrigin,
            Hrla::paper(0.01).unwrap(),
            Linear::new(0.1, 4.0, STEPS).unwrap(),
            start(),
        )
        .seed(31)
        .build(vec![Chain::new(); N])
        .unwrap()
    };
    let mut by_run = build();
    let report = by_run.run().unwrap();
    assert_eq!(report.iterations, STEPS);
    assert_eq!(report.termination, Termination::Steps);
    let want = all_bits(by_run.chains());

    let mut by_step = build();
    for _ in 0..STEPS {
        by_step.step().unwrap();
    }
    assert_eq!(all_bits(by_step.chains()), want);
    assert_eq!(by_step.run().unwrap(), report);

    let mut by_mix = build();
    let mut pauses = 0;
    loop {
        let r = by_mix
            .run_with(hrla::Observe::EveryAndNewBest(1), |p| {
                if p.iteration % 17 == 0 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })
            .unwrap();
        if r.termination != Termination::Observer {
            assert_eq!(r, report);
            break;
        }
        pauses += 1;
        assert_eq!(r.iterations % 17, 0);
        // One step by hand between pauses (when the budget allows).
        if by_mix.termination().is_none() {
            by_mix.step().unwrap();
        }
    }
    assert_eq!(pauses, STEPS / 17);
    assert_eq!(all_bits(by_mix.chains()), want);
}

/// Different seeds: every chain's initial point and final state differ;
/// `chain_seed` is injective on a grid of seeds and chain indices.
#[test]
fn different_seeds_give_different_streams() {
    let hrla = Hrla::paper(0.01f64).unwrap();
    let a = trajectories::<f64, _, _, Xoshiro256PlusPlus>(hrla, 4.0, 100, 6);
    let b = trajectories::<f64, _, _, Xoshiro256PlusPlus>(hrla, 4.0, 101, 6);
    for c in 0..6 {
        assert_ne!(a[c][0], b[c][0], "chain {c}: same initial point");
        assert_ne!(a[c][STEPS as usize], b[c][STEPS as usize], "chain {c}");
        // Not a shifted copy of another chain of the other seed either.
        for (d, other) in b.iter().enumerate() {
            assert_ne!(a[c][0], other[0], "chain {c} of 100 is chain {d} of 101");
        }
    }
    let mut seen = HashSet::new();
    for seed in 0..64u64 {
        for c in 0..1000u64 {
            assert!(
                seen.insert(chain_seed(seed, c)),
                "collision at ({seed}, {c})"
            );
        }
    }
    // Neighbouring seeds are far apart: seeds 0 and 1 of chain 0 differ in
    // about half of their bits (SplitMix64 mixes), not in one.
    let diff = (chain_seed(0, 0) ^ chain_seed(1, 0)).count_ones();
    assert!((16..=48).contains(&diff), "{diff} bits differ");
}

/// SplitMix64 against its published outputs (Steele, Lea and Flood; the
/// generator seeded with 0 outputs `splitmix64(0)`, then
/// `splitmix64(0x9e3779b97f4a7c15)`), and `chain_seed` against its
/// definition and two golden values of the per-chain streams.
#[test]
fn chain_seed_is_pinned() {
    assert_eq!(splitmix64(0), 0xe220_a839_7b1d_cdaf);
    assert_eq!(splitmix64(0x9e37_79b9_7f4a_7c15), 0x6e78_9e6a_a1b9_65f4);
    for (seed, c) in [(0, 0), (1, 5), (20_241_017, 3), (u64::MAX, u64::MAX)] {
        assert_eq!(chain_seed(seed, c), splitmix64(splitmix64(seed) ^ c));
    }
    // The goldens: any change of the per-chain seeding changes them.
    println!(
        "chain_seed(0, 0) = {:#018x}, chain_seed(20_241_017, 3) = {:#018x}",
        chain_seed(0, 0),
        chain_seed(20_241_017, 3)
    );
    assert_eq!(chain_seed(0, 0), GOLDEN_CHAIN_SEED_0_0);
    assert_eq!(chain_seed(20_241_017, 3), GOLDEN_CHAIN_SEED_20241017_3);
}

// The goldens of the per-chain streams' seeding, printed by this test (and
// checked against an independent SplitMix64 in Python when recorded).
const GOLDEN_CHAIN_SEED_0_0: u64 = 0xa706_dd2f_4d19_7e6f;
const GOLDEN_CHAIN_SEED_20241017_3: u64 = 0x890f_5592_09ce_574b;
