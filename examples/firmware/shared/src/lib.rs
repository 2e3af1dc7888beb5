//! The computation of the firmware example, shared word for word by the
//! firmware (`examples/firmware/qemu`, on Cortex-M and RISC-V cores), the
//! host (`hrla-embedded-host`) and
//! wasm in Node (`examples/firmware/wasm`), so that their outputs can be
//! compared byte for byte.
//!
//! [`run`] performs Algorithm 1 on 2-D Rastrigin with HRLA, N = 16 chains,
//! the paper's parameters (`a = 4`, `b = 10`, `alpha = beta = 1`,
//! `h = 0.01`), starting from `N(3·1, 10 I)`, for [`STEPS`] steps, each
//! chain drawing from its own generator `R` (`Xoshiro128PlusPlus` by
//! default, the 32-bit cores' choice; `Xoshiro256PlusPlus`, the kernel's
//! default, for comparison), seeded from [`SEED`] and its index
//! (`hrla::chain_seed`). The chains live in storage the caller
//! owns, without allocation: [`chains`] makes an array of them (on the
//! stack, as the host and wasm do), and the firmware keeps them in a
//! `static` `hrla::heapless::Vec`. [`report`] writes its result as
//! hexadecimal IEEE bit patterns through a byte [`Sink`], with a formatter
//! written here rather than `core::fmt`: formatting floats with `core::fmt`
//! costs kilobytes of flash (measured in `docs/EMBEDDED.md`), and bit
//! patterns are what a bit-exact comparison needs anyway.
//!
//! # Output
//!
//! Four lines per float type `T` (`f32` or `f64`), the bit patterns printed
//! as lower-case hex with all digits (8 for `f32`, 16 for `f64`):
//!
//! ```text
//! T best.value <bits of the global running best U>
//! T best.x <bits of x_1> <bits of x_2>
//! T best.iteration <the iterate k of the best, 16 hex digits>
//! T chains.fnv1a <checksum of the final chains, 16 hex digits>
//! ```
//!
//! The checksum is 64-bit FNV-1a over, chain after chain, the IEEE bit
//! patterns of `x_1, x_2, y_1, y_2, U(x)` of the final state, each
//! zero-extended to 64 bits (as [`Float::to_bits_u64`] gives it) and fed as
//! eight little-endian bytes.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

use hrla::rand_core::{Rng, SeedableRng};
use hrla::{
    Builder, Chain, Chains, Error, Float, Gaussian, Hrla, Optimizer, Rastrigin, Report, Stop,
};
pub use rand_xoshiro::{Xoshiro128PlusPlus, Xoshiro256PlusPlus};

/// The dimension of the Rastrigin potential.
pub const D: usize = 2;
/// The number of chains.
pub const N: usize = 16;
/// The number of HRLA steps.
pub const STEPS: u64 = 2_000;
/// The seed of the run: chain `c` draws from
/// `R::seed_from_u64(hrla::chain_seed(SEED, c))`.
pub const SEED: u64 = 2025;

/// One chain of the example: 2-D, with a 32-bit generator by default (the
/// f32 sampler's `next_u64` for a pair of normals is two `next_u32` there).
pub type DemoChain<F, R = Xoshiro128PlusPlus> = Chain<F, D, R>;

/// The optimiser the example runs, over chains it borrows from the caller
/// (it holds no array of chains itself).
pub type Demo<'a, F, R = Xoshiro128PlusPlus> =
    Optimizer<F, Rastrigin, Hrla<F>, F, Chains<F, &'a mut [DemoChain<F, R>], D, R>>;

/// A per-chain generator the example can run with: its name in the
/// variants' file names and on the host's command line.
pub trait Generator: Rng + SeedableRng + 'static {
    /// `"xoshiro128"` or `"xoshiro256"`.
    const NAME: &'static str;
}

impl Generator for Xoshiro128PlusPlus {
    const NAME: &'static str = "xoshiro128";
}

impl Generator for Xoshiro256PlusPlus {
    const NAME: &'static str = "xoshiro256";
}

/// [`N`] empty chains in an array, to be filled by [`run`]: storage without
/// allocation, wherever the caller puts it.
pub fn chains<F: Float, R: Generator>() -> [DemoChain<F, R>; N] {
    core::array::from_fn(|_| Chain::default())
}

/// Where [`report`] writes its lines: semihosting on the firmware, stdout on
/// the host, a buffer in wasm.
pub trait Sink {
    /// Writes the bytes as they are.
    fn write(&mut self, bytes: &[u8]);
}

/// Builds the optimiser over `chains` (the example uses [`N`] of them; their
/// contents are overwritten) for `seed` and runs `steps` steps of
/// Algorithm 1.
///
/// Generic over the float type so that the f32 and f64 runs are the same
/// code; the seed is a parameter so that tests can try several.
pub fn run<F: Float, R: Generator>(
    chains: &mut [DemoChain<F, R>],
    seed: u64,
    steps: u64,
) -> Result<(Demo<'_, F, R>, Report<F>), Error> {
    let sampler = Hrla::paper(F::from_f64(0.01))?;
    let start = Gaussian::new([F::from_f64(3.0); D], F::from_f64(10.0).sqrt())?;
    let a = F::from_f64(4.0);
    let mut opt = Builder::new(Rastrigin, sampler, a, start)
        .seed(seed)
        .stop(Stop::new().steps(steps))
        .build(chains)?;
    let report = opt.run()?;
    Ok((opt, report))
}

/// 64-bit FNV-1a of the final chain states (see the crate docs for the
/// exact byte sequence).
pub fn checksum<F: Float, R: Generator>(opt: &Demo<'_, F, R>) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h = OFFSET;
    for chain in opt.chains() {
        let words = chain.x().iter().chain(chain.y()).copied();
        for v in words.chain(core::iter::once(chain.value())) {
            for byte in v.to_bits_u64().to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(PRIME);
            }
        }
    }
    h
}

/// The lower-case hex digits of the low `digits` nibbles of `v` (at most 16),
/// most significant first, in a fixed buffer: no `core::fmt`.
pub fn hex(v: u64, digits: usize) -> ([u8; 16], usize) {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let digits = digits.min(16);
    let mut out = [0u8; 16];
    for (i, slot) in out[..digits].iter_mut().enumerate() {
        let shift = 4 * (digits - 1 - i);
        *slot = DIGITS[((v >> shift) & 0xf) as usize];
    }
    (out, digits)
}

/// The decimal digits of `v`, most significant first, in a fixed buffer: no
/// `core::fmt` (for the firmware's human-readable diagnostics).
pub fn dec(mut v: u64) -> ([u8; 20], usize) {
    let mut rev = [0u8; 20];
    let mut n = 0;
    loop {
        rev[n] = b'0' + (v % 10) as u8;
        n += 1;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    let mut out = [0u8; 20];
    for i in 0..n {
        out[i] = rev[n - 1 - i];
    }
    (out, n)
}

/// The name of the float type (`b"f32"` or `b"f64"`) and the number of hex
/// digits of its bit pattern.
pub fn float_name<F: Float>() -> (&'static [u8], usize) {
    if core::mem::size_of::<F>() == 4 {
        (b"f32", 8)
    } else {
        (b"f64", 16)
    }
}

/// Writes the four lines of the run (see the crate docs) to `out`.
pub fn report<F: Float, R: Generator>(opt: &Demo<'_, F, R>, out: &mut impl Sink) {
    let (name, digits) = float_name::<F>();
    let mut field = |label: &[u8], values: &[(u64, usize)]| {
        out.write(name);
        out.write(b" ");
        out.write(label);
        for &(v, n) in values {
            let (buf, len) = hex(v, n);
            out.write(b" ");
            out.write(&buf[..len]);
        }
        out.write(b"\n");
    };
    let best = opt.best();
    field(b"best.value", &[(best.value.to_bits_u64(), digits)]);
    field(
        b"best.x",
        &[
            (best.x[0].to_bits_u64(), digits),
            (best.x[1].to_bits_u64(), digits),
        ],
    );
    field(b"best.iteration", &[(best.iteration, 16)]);
    field(b"chains.fnv1a", &[(checksum(opt), 16)]);
}

/// Runs the example at [`SEED`] for [`STEPS`] steps with generator `R`,
/// its [`N`] chains in an array on the stack, and writes its report; an
/// error (impossible with these constants) is written as a line.
pub fn run_and_report<F: Float, R: Generator>(out: &mut impl Sink) {
    let mut chains = chains::<F, R>();
    match run::<F, R>(&mut chains, SEED, STEPS) {
        Ok((opt, _)) => report(&opt, out),
        Err(_) => {
            let (name, _) = float_name::<F>();
            out.write(name);
            out.write(b" error\n");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_prints_every_digit() {
        let (buf, n) = hex(0x00ab_0001, 8);
        assert_eq!(&buf[..n], b"00ab0001");
        let (buf, n) = hex(u64::MAX, 16);
        assert_eq!(&buf[..n], b"ffffffffffffffff");
        let (buf, n) = hex(0x1234, 2);
        assert_eq!(&buf[..n], b"34");
    }

    #[test]
    fn dec_prints_like_display() {
        for v in [0, 7, 10, 65_535, 1 << 40, u64::MAX] {
            let (buf, n) = dec(v);
            let expected = v.to_string();
            assert_eq!(&buf[..n], expected.as_bytes());
        }
    }
}
