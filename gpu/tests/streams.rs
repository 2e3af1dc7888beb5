//! The device's streams are the kernel's: the same generator words, the
//! same Ziggurat, the same normals, bit for bit, in f32 and (where the
//! adapter has it) f64.

mod common;

use hrla::{Float, chain_seed};
use hrla_gpu::Precision;
use rand_xoshiro::Xoshiro128PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// The CPU's draws of chain `c`, as `Gpu::normals` lays them out.
fn cpu_normals<F: Float>(seed: u64, chains: usize, count: usize, pairs: bool) -> Vec<F> {
    let mut out = Vec::new();
    for c in 0..chains {
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c as u64));
        for _ in 0..count {
            if pairs {
                let (a, b) = F::standard_normal_pair(&mut rng);
                out.extend([a, b]);
            } else {
                out.push(F::standard_normal(&mut rng));
            }
        }
    }
    out
}

/// Draws of `cpu_normals` that took the tail (beyond R), and those that
/// took more than their first word (tail, wedges and redraws).
fn slow_draws<F: Float>(seed: u64, chains: usize, count: usize) -> (usize, usize) {
    let (mut tail, mut slow) = (0, 0);
    for c in 0..chains {
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c as u64));
        for _ in 0..count {
            let mut fast = rng.clone();
            // One word in f32, two in f64.
            fast.next_u32();
            if F::MANTISSA_DIGITS > 24 {
                fast.next_u32();
            }
            let z = F::standard_normal(&mut rng).to_f64();
            tail += usize::from(z.abs() > 3.654_153);
            slow += usize::from(rng != fast);
        }
    }
    (tail, slow)
}

fn same_bits<F: Float>(seed: u64, chains: usize, count: usize, pairs: bool) {
    let gpu = common::gpu();
    let precision = if F::MANTISSA_DIGITS > 24 {
        Precision::F64
    } else {
        Precision::F32
    };
    let device: Vec<F> = gpu
        .normals(seed, chains, count as u32, pairs, precision)
        .expect("normals")
        .into_iter()
        .map(F::from_f64)
        .collect();
    let cpu = cpu_normals::<F>(seed, chains, count, pairs);
    assert_eq!(device.len(), cpu.len());
    let width = count * if pairs { 2 } else { 1 };
    let differ: Vec<usize> = (0..cpu.len())
        .filter(|&j| device[j].to_bits_u64() != cpu[j].to_bits_u64())
        .collect();
    if let Some(&j) = differ.first() {
        panic!(
            "{} of {} draws differ; the first: chain {}, draw {}: device {:?}, CPU {:?}",
            differ.len(),
            cpu.len(),
            j / width,
            j % width,
            device[j],
            cpu[j]
        );
    }
}

/// 4096 chains x 256 draws: 274 of them reach the tail (Marsaglia's
/// method, with `logf`) and 15,522 leave the fast path (wedges, with
/// `expf`, and redraws), so every branch of the Ziggurat is compared, not
/// only the fast path (counted on the CPU, and asserted).
#[test]
fn single_normals_are_the_kernels() {
    let (tail, slow) = slow_draws::<f32>(7, 4096, 256);
    assert!(tail > 100 && slow > 1000, "tail {tail}, slow {slow}");
    same_bits::<f32>(7, 4096, 256, false);
}

#[test]
fn pairs_are_the_kernels() {
    same_bits::<f32>(11, 4096, 128, true);
}

/// The f64 Ziggurat (a 64-bit word per attempt, two of the generator's)
/// with fdlibm's `exp` and `log` in its rare branches.
#[test]
fn f64_normals_are_the_kernels() {
    if !common::gpu().supports_f64() {
        eprintln!("the adapter has no SHADER_F64: the f64 streams do not apply");
        return;
    }
    let (tail, slow) = slow_draws::<f64>(13, 4096, 256);
    assert!(tail > 100 && slow > 1000, "tail {tail}, slow {slow}");
    same_bits::<f64>(13, 4096, 256, false);
    same_bits::<f64>(17, 4096, 128, true);
}
