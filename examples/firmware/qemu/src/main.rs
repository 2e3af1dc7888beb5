//! Algorithm 1 on 2-D Rastrigin (HRLA, 16 chains, fixed seed) as firmware
//! for three cores under QEMU: a Cortex-M3 (`thumbv7m-none-eabi`,
//! `lm3s6965evb`), a Cortex-M4F with its FPU (`thumbv7em-none-eabihf`,
//! `mps2-an386`) and an RV32IMAC (`riscv32imac-unknown-none-elf`, `virt`).
//!
//! It is the embedding guide of `docs/EMBEDDED.md`, which quotes the part
//! between the `guide` markers word for word (`scripts/test-firmware.sh`
//! checks it): the chains in a `static`, the optimiser built over them, one
//! step per control-loop tick, each timed against the tick's budget. Then
//! it prints the result lines of [`hrla_embedded::report`] through
//! semihosting (the host prints the same lines from
//! [`hrla_embedded::run`]; `scripts/test-firmware.sh` compares them byte
//! for byte), then `#` diagnostic lines, and exits through semihosting with
//! status 0. An error exits with status 1, a panic with 101.
//!
//! Cargo features: `f32` or `f64` (exactly one: the float type),
//! `xoshiro256` (one `Xoshiro256PlusPlus` per chain instead of
//! `Xoshiro128PlusPlus`), `micromath` (the kernel's), `fmt` (prints the
//! best point a second time through `core::fmt`, only to measure what that
//! costs in flash).
//!
//! Diagnostics, `T` the float type:
//!
//! - `# calibration n`: on the Cortex-M cores, SysTick ticks of a loop of
//!   exactly 2^24 instructions (0 on RISC-V, whose counter counts
//!   instructions).
//! - `# T steps.instructions n`: instructions spent in the 2 000 calls of
//!   `opt.step()`, the clock's own reads taken out; `# T chain-step.instructions n`
//!   the same per chain and step, rounded; `# T step.worst n` the longest
//!   step; `# T budget.overruns n` the steps over the tick's budget.
//!   Under QEMU `-icount shift=0` every guest instruction takes 1 ns of
//!   virtual time, so the clock counts instructions, deterministically:
//!   `minstret` on RISC-V, exact; SysTick scaled by the calibration on the
//!   Cortex-M cores, to within a tick per reading.
//! - `# stack.peak n`, `# stack.size n`: the stack's high-water mark and
//!   size in bytes, from the paint laid below the stack before `main` runs
//!   the example.
#![no_std]
#![no_main]

#[cfg(all(feature = "f32", feature = "f64"))]
compile_error!("choose one float type: feature `f32` or `f64`, not both");
#[cfg(not(any(feature = "f32", feature = "f64")))]
compile_error!("choose a float type: feature `f32` or `f64`");

#[cfg(target_arch = "arm")]
#[path = "cortex_m.rs"]
mod platform;
#[cfg(target_arch = "riscv32")]
#[path = "riscv.rs"]
mod platform;

use hrla::heapless::Vec;
use hrla::{Builder, Chain, Error, Float, Gaussian, Hrla, Rastrigin};
use hrla_embedded::{Demo, Sink};
use platform::Clock;
use semihosting::io::{self, Write};
use semihosting::process;
use static_cell::ConstStaticCell;

/// The float type of this build.
#[cfg(feature = "f32")]
type Real = f32;
/// The float type of this build.
#[cfg(all(feature = "f64", not(feature = "f32")))]
type Real = f64;

/// Each chain's generator.
#[cfg(not(feature = "xoshiro256"))]
type Rng = hrla_embedded::Xoshiro128PlusPlus;
/// Each chain's generator.
#[cfg(feature = "xoshiro256")]
type Rng = hrla_embedded::Xoshiro256PlusPlus;

/// The paint below the stack: a word still holding it was never written.
pub(crate) const PAINT: u32 = 0xcccc_cccc;

/// Semihosting stdout as a byte sink.
struct Console(io::Stdout);

impl Sink for Console {
    fn write(&mut self, bytes: &[u8]) {
        // Nothing useful can be done if the host refuses the write.
        let _ = self.0.write_all(bytes);
    }
}

impl Console {
    /// One `# label value` diagnostic line, `value` in decimal.
    fn diagnostic(&mut self, label: &[&[u8]], value: u64) {
        let (buf, n) = hrla_embedded::dec(value);
        self.write(b"#");
        for part in label {
            self.write(b" ");
            self.write(part);
        }
        self.write(b" ");
        self.write(&buf[..n]);
        self.write(b"\n");
    }
}

/// How the steps fitted in their ticks, in clock counts (instructions
/// under QEMU).
#[derive(Default)]
struct Timing {
    steps: u64,
    total: u64,
    worst: u64,
    overruns: u64,
}

impl Timing {
    fn add(&mut self, spent: u64, budget: u64) {
        self.steps += 1;
        self.total += spent;
        self.worst = self.worst.max(spent);
        // On hardware: log it, step every other tick, or use fewer chains.
        self.overruns += u64::from(spent > budget);
    }
}

// guide: begin
/// The chains: 16 of 2-D Rastrigin, in static RAM (`.bss`), where the
/// linker counts them; `ConstStaticCell` hands them out once, as
/// `&'static mut`, whatever the runtime.
static CHAINS: ConstStaticCell<Vec<Chain<Real, 2, Rng>, 16>> = ConstStaticCell::new(Vec::new());

/// What the optimiser may spend in one tick of the control loop, in clock
/// counts: half a tick of a 1 kHz loop on a 168 MHz core.
const BUDGET: u64 = 84_000;

/// Algorithm 1 with one step per control-loop tick, for `ticks` ticks.
fn control_loop(
    clock: &mut Clock,
    seed: u64,
    ticks: u64,
) -> Result<(Demo<'static, Real, Rng>, Timing), Error> {
    let chains = CHAINS.take();
    // One chain at a time: no array of chains is ever built on the stack.
    while chains.push(Chain::default()).is_ok() {}
    let mut opt = Builder::new(
        Rastrigin, // or FnPotential::new(|x, g| { ...; u }): value and gradient
        Hrla::paper(0.01)?,
        4.0,                                         // the inverse temperature a
        Gaussian::new([3.0; 2], Float::sqrt(10.0))?, // the start, N(3·1, 10 I)
    )
    .seed(seed) // fixed, or drawn from the hardware RNG at start-up
    .build(chains.as_mut_slice())?;

    let mut timing = Timing::default();
    for _ in 0..ticks {
        // A real loop waits for its timer here and runs its controller.
        let t0 = clock.now();
        opt.step()?; // every chain, one step
        timing.add(clock.now() - t0, BUDGET);
        let _set_point = opt.best().x; // the best point so far, for the controller
    }
    Ok((opt, timing))
}
// guide: end

#[platform::entry]
fn main() -> ! {
    // First: on RISC-V this paints the stack below this frame.
    let (bottom, top) = platform::stack();
    let Some(mut clock) = Clock::start() else {
        fail();
    };
    let Ok(stdout) = io::stdout() else {
        fail();
    };
    let mut out = Console(stdout);
    out.diagnostic(&[b"calibration"], clock.calibration());
    // What one reading of the clock costs, taken out of every step's.
    let t0 = clock.now();
    let overhead = clock.now() - t0;

    let (name, _) = hrla_embedded::float_name::<Real>();
    let Ok((opt, timing)) = control_loop(&mut clock, hrla_embedded::SEED, hrla_embedded::STEPS)
    else {
        out.write(name);
        out.write(b" error\n");
        fail();
    };
    hrla_embedded::report(&opt, &mut out);
    #[cfg(feature = "fmt")]
    {
        use core::fmt::Write as _;
        /// `core::fmt` over the console.
        struct Fmt<'a>(&'a mut Console);
        impl core::fmt::Write for Fmt<'_> {
            fn write_str(&mut self, s: &str) -> core::fmt::Result {
                self.0.write(s.as_bytes());
                Ok(())
            }
        }
        let b = opt.best();
        let _ = writeln!(Fmt(&mut out), "# fmt best {:?} at {:?}", b.value, b.x);
    }

    let spent = timing.total - timing.steps * overhead;
    let chain_steps = hrla_embedded::N as u64 * timing.steps;
    out.diagnostic(&[name, b"steps.instructions"], spent);
    out.diagnostic(
        &[name, b"chain-step.instructions"],
        (spent + chain_steps / 2) / chain_steps,
    );
    out.diagnostic(&[name, b"step.worst"], timing.worst);
    out.diagnostic(&[name, b"budget.overruns"], timing.overruns);
    out.diagnostic(&[b"stack.peak"], stack_peak(bottom, top));
    out.diagnostic(&[b"stack.size"], (top - bottom) as u64);
    process::exit(0)
}

/// The deepest the stack has been, in bytes: the distance from its top to
/// the lowest word no longer holding the paint.
fn stack_peak(bottom: usize, top: usize) -> u64 {
    let mut p = bottom;
    // SAFETY: every word in [bottom, top) is RAM reserved for the stack,
    // 4-byte aligned by the runtime's link.x; reading it has no side effect.
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    (top - p) as u64
}

/// Prints where the panic happened and exits with status 101: the
/// location, not the message, which only `core::fmt` can print (about
/// 2.5 KiB of flash).
#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    if let Ok(stdout) = io::stdout() {
        let mut out = Console(stdout);
        out.write(b"panicked");
        if let Some(at) = info.location() {
            out.write(b" at ");
            out.write(at.file().as_bytes());
            let (line, n) = hrla_embedded::dec(u64::from(at.line()));
            out.write(b":");
            out.write(&line[..n]);
        }
        out.write(b"\n");
    }
    process::exit(101)
}

/// Exits with a failure status through semihosting.
fn fail() -> ! {
    process::exit(1)
}
