//! Chains stepped in lockstep give each chain exactly the numbers it gets
//! alone: the lane-wise normals ([`StandardNormal::standard_normal_lanes`],
//! `..._pair_lanes`) against the single-stream draws, and every sampler's
//! [`Kernel::step_lanes`] against [`Kernel::step`], in both float widths,
//! for point sizes below, at and beyond the kernel's block of 64
//! coordinates, through enough draws that the Ziggurat's slow path (about
//! 1% of draws) runs in every lane many times.

use hrla::{
    AnySampler, ChainState, Float, Hrla, Kernel, Ola, Sampler, SamplerKind, StandardNormal, Ula,
    Xoshiro256Lanes,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

const L: usize = 4;

fn generators() -> [Xoshiro256PlusPlus; L] {
    core::array::from_fn(|l| Xoshiro256PlusPlus::seed_from_u64(1000 + l as u64))
}

fn normals_match<F: Float + StandardNormal>() {
    let mut alone = generators();
    let mut lanes = Xoshiro256Lanes::load(alone.each_ref());
    // 200 000 draws per lane: about 2 000 go through the slow path each.
    for _ in 0..100_000 {
        let single = F::standard_normal_lanes(&mut lanes);
        let pairs = F::standard_normal_pair_lanes(&mut lanes);
        for l in 0..L {
            let z = F::standard_normal(&mut alone[l]);
            assert_eq!(single[l].to_f64().to_bits(), z.to_f64().to_bits());
            let (a, b) = F::standard_normal_pair(&mut alone[l]);
            assert_eq!(pairs[l].0.to_f64().to_bits(), a.to_f64().to_bits());
            assert_eq!(pairs[l].1.to_f64().to_bits(), b.to_f64().to_bits());
        }
    }
    let mut after = generators();
    lanes.store(after.each_mut());
    for l in 0..L {
        assert_eq!(after[l].next_u64(), alone[l].next_u64());
    }
}

#[test]
fn lane_normals_are_the_single_stream_normals() {
    normals_match::<f64>();
    normals_match::<f32>();
}

fn kernel_matches<F: Float, K: Kernel<F>, const D: usize>(kernel: K) {
    let mut alone = generators();
    let mut lanes = Xoshiro256Lanes::load(alone.each_ref());
    let point = |l: usize, i: usize, s: f64| F::from_f64(s * ((l * D + i) as f64 * 0.37).sin());
    let mut x: [[F; D]; L] = core::array::from_fn(|l| core::array::from_fn(|i| point(l, i, 2.0)));
    let mut y: [[F; D]; L] = core::array::from_fn(|l| core::array::from_fn(|i| point(l, i, 0.5)));
    let grad: [[F; D]; L] = core::array::from_fn(|l| core::array::from_fn(|i| point(l, i, 3.0)));
    let (mut xs, mut ys) = (x, y);
    for _ in 0..50 {
        let [x0, x1, x2, x3] = &mut x;
        let [y0, y1, y2, y3] = &mut y;
        let states = [(x0, y0), (x1, y1), (x2, y2), (x3, y3)];
        let mut l = 0;
        kernel.step_lanes(
            states.map(|(x, y)| {
                let s = ChainState {
                    x,
                    y,
                    grad: &grad[l],
                };
                l += 1;
                s
            }),
            &mut lanes,
        );
        for l in 0..L {
            kernel.step(&mut xs[l], &mut ys[l], &grad[l], &mut alone[l]);
        }
        for l in 0..L {
            for i in 0..D {
                assert_eq!(
                    x[l][i].to_f64().to_bits(),
                    xs[l][i].to_f64().to_bits(),
                    "x, lane {l}, {i}"
                );
                assert_eq!(
                    y[l][i].to_f64().to_bits(),
                    ys[l][i].to_f64().to_bits(),
                    "y, lane {l}, {i}"
                );
            }
        }
    }
}

fn kernels_match<F: Float, const D: usize>() {
    let a = F::from_f64(2.0);
    kernel_matches::<F, _, D>(Hrla::paper(F::from_f64(0.01)).unwrap().at(a).unwrap());
    kernel_matches::<F, _, D>(Ula::paper(F::from_f64(0.01)).unwrap().at(a).unwrap());
    kernel_matches::<F, _, D>(Ola::paper(F::from_f64(0.01)).unwrap().at(a).unwrap());
    let any = AnySampler::paper(SamplerKind::Hrla, F::from_f64(0.01)).unwrap();
    kernel_matches::<F, _, D>(any.at(a).unwrap());
}

#[test]
fn lockstep_steps_are_the_single_chain_steps() {
    kernels_match::<f64, 1>();
    kernels_match::<f64, 10>();
    kernels_match::<f64, 64>();
    kernels_match::<f64, 150>();
    kernels_match::<f32, 3>();
    kernels_match::<f32, 10>();
    kernels_match::<f32, 150>();
}

/// Chain `c`'s bits after a run, in runs of 1 to 9 chains: the groups of
/// four that the optimiser steps in lockstep, and the chains left over that
/// it steps alone, give every chain the same trajectory (in `f64` from
/// `D = 16`, below which `f64` chains step alone, and in `f32` at any `D`).
fn optimiser_matches<F: Float, const D: usize>() {
    use hrla::{Builder, Chain, Gaussian, Linear, Rastrigin, Stop};
    let run = |n: usize| {
        let mut chains: Vec<Chain<F, D>> = (0..n).map(|_| Chain::new()).collect();
        let start = Gaussian::new([F::from_f64(3.0); D], F::from_f64(3.0)).unwrap();
        let schedule = Linear::new(F::from_f64(1.0), F::from_f64(4.0), 200).unwrap();
        let mut opt = Builder::new(
            Rastrigin,
            Hrla::paper(F::from_f64(0.01)).unwrap(),
            schedule,
            start,
        )
        .seed(5)
        .stop(Stop::new().steps(200))
        .build(&mut chains)
        .unwrap();
        opt.run().unwrap();
        let mut out = Vec::new();
        for c in opt.chains() {
            let mut bits = Vec::new();
            hrla_tests::bits::chain_bits(c, &mut bits);
            out.push(bits);
        }
        out
    };
    let all = run(9);
    for n in 1..9 {
        assert_eq!(run(n)[..], all[..n], "{n} chains");
    }
}

#[test]
fn the_optimiser_gives_each_chain_its_own_trajectory_in_any_group() {
    optimiser_matches::<f64, 20>();
    optimiser_matches::<f64, 3>();
    optimiser_matches::<f32, 3>();
    optimiser_matches::<f32, 70>();
}

/// A group with a diverged chain steps its live chains one by one: the
/// same bits as in runs where those chains are grouped differently.
#[test]
fn groups_with_diverged_chains_give_the_same_bits() {
    use hrla::{Builder, Chain, FnPotential, Gaussian, Stop};
    // A bowl with a hole: NaN beyond x[0] = 4, which the chains' noise
    // reaches now and then.
    let holed = FnPotential::new(|x: &[f32; 3], g: &mut [f32; 3]| {
        let mut u = 0.0;
        for (xi, gi) in x.iter().zip(g.iter_mut()) {
            u += 0.5 * (xi - 3.0) * (xi - 3.0);
            *gi = xi - 3.0;
        }
        if x[0] > 4.0 { f32::NAN } else { u }
    });
    let run = |n: usize| {
        let mut chains: Vec<Chain<f32, 3>> = (0..n).map(|_| Chain::new()).collect();
        let start = Gaussian::new([3.0f32; 3], 0.2).unwrap();
        let mut opt = Builder::new(&holed, Ula::paper(0.1f32).unwrap(), 4.0f32, start)
            .seed(8)
            .stop(Stop::new().steps(300))
            .build(&mut chains)
            .unwrap();
        opt.run().unwrap();
        let diverged = opt.diverged_chains();
        let mut out = Vec::new();
        for c in opt.chains() {
            let mut bits = Vec::new();
            hrla_tests::bits::chain_bits(c, &mut bits);
            out.push(bits);
        }
        (out, diverged)
    };
    let (all, diverged) = run(13);
    assert!((1..13).contains(&diverged), "{diverged} of 13 diverged");
    for n in [5, 8, 11] {
        assert_eq!(run(n).0[..], all[..n], "{n} chains");
    }
}
