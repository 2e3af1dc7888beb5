//! The device's streams are the kernel's: the same generator words, the
//! same Ziggurat, the same normals, bit for bit.

mod common;

use hrla::{StandardNormal, chain_seed};
use rand_xoshiro::Xoshiro128PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// The CPU's draws of chain `c`, as `Gpu::normals` lays them out.
fn cpu_normals(seed: u64, chains: usize, count: usize, pairs: bool) -> Vec<f32> {
    let mut out = Vec::new();
    for c in 0..chains {
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c as u64));
        for _ in 0..count {
            if pairs {
                let (a, b) = f32::standard_normal_pair(&mut rng);
                out.extend([a, b]);
            } else {
                out.push(f32::standard_normal(&mut rng));
            }
        }
    }
    out
}

/// Draws of `cpu_normals` that took the tail (beyond R), and those that
/// took more than their first word (tail, wedges and redraws).
fn slow_draws(seed: u64, chains: usize, count: usize) -> (usize, usize) {
    let (mut tail, mut slow) = (0, 0);
    for c in 0..chains {
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c as u64));
        for _ in 0..count {
            let mut fast = rng.clone();
            fast.next_u32();
            let z = f32::standard_normal(&mut rng);
            tail += usize::from(z.abs() > 3.654_153);
            slow += usize::from(rng != fast);
        }
    }
    (tail, slow)
}

fn same_bits(seed: u64, chains: usize, count: usize, pairs: bool) {
    let gpu = common::gpu();
    let device = gpu
        .normals(seed, chains, count as u32, pairs)
        .expect("normals");
    let cpu = cpu_normals(seed, chains, count, pairs);
    assert_eq!(device.len(), cpu.len());
    let width = count * if pairs { 2 } else { 1 };
    let differ: Vec<usize> = (0..cpu.len())
        .filter(|&j| device[j].to_bits() != cpu[j].to_bits())
        .collect();
    if let Some(&j) = differ.first() {
        panic!(
            "{} of {} draws differ; the first: chain {}, draw {}: device {:e}, CPU {:e}",
            differ.len(),
            cpu.len(),
            j / width,
            j % width,
            device[j],
            cpu[j]
        );
    }
}

/// 4096 chains x 256 draws: about 270 of them reach the tail (Marsaglia's
/// method, with `logf`) and about 2,500 the wedges (with `expf`), so every
/// branch of the Ziggurat is compared, not only the fast path.
#[test]
fn single_normals_are_the_kernels() {
    let (tail, slow) = slow_draws(7, 4096, 256);
    assert!(tail > 100 && slow > 1000, "tail {tail}, slow {slow}");
    same_bits(7, 4096, 256, false);
}

#[test]
fn pairs_are_the_kernels() {
    same_bits(11, 4096, 128, true);
}
