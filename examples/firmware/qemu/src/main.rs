//! Algorithm 1 on 2-D Rastrigin (HRLA, 16 chains, fixed seed) as Cortex-M3
//! firmware for QEMU's `lm3s6965evb`.
//!
//! It runs [`hrla_embedded::run`] in f32 and/or f64 (cargo features `f32`,
//! `f64`) over 16 chains kept in a `static` (an `hrla::heapless::Vec`, so
//! in `.bss`: their RAM is known at link time and off the stack), prints
//! the result lines of [`hrla_embedded::report`] through
//! semihosting (the host prints the same lines; `scripts/test-firmware.sh`
//! compares them byte for byte), then `#` diagnostic lines, and exits
//! through semihosting with status 0. A panic exits non-zero
//! (`panic-semihosting` with `exit`).
//!
//! Diagnostics:
//!
//! - `# calibration n`: SysTick ticks (core clock) of a loop of exactly 2^24
//!   instructions.
//! - `# T ticks n` and `# T instructions n`: the ticks spent in the run of
//!   type `T`, and the instructions they stand for. Under
//!   `qemu-system-arm -icount shift=0` every guest instruction takes 1 ns of
//!   virtual time, so ticks are proportional to instructions executed (QEMU
//!   emulates no DWT cycle counter, and this Debian build ships no TCG
//!   plugins); on real hardware the same lines count core cycles.
//! - `# stack.peak n`: the stack's high-water mark in bytes, read from the
//!   paint that cortex-m-rt's `paint-stack` feature lays between
//!   `_stack_end` and `_stack_start` before `main`.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hio};
use hrla::Float;
use hrla::heapless::Vec;
use hrla_embedded::{DemoChain, N, Sink};
use panic_semihosting as _;

/// Semihosting stdout as a byte sink.
struct Host(hio::HostStream);

impl Sink for Host {
    fn write(&mut self, bytes: &[u8]) {
        // Nothing useful can be done if the host refuses the write.
        let _ = self.0.write_all(bytes);
    }
}

impl Host {
    /// One `# label value` diagnostic line, `value` in decimal.
    fn diagnostic(&mut self, label: &[u8], value: u64) {
        let (buf, n) = hrla_embedded::dec(value);
        self.write(b"# ");
        self.write(label);
        self.write(b" ");
        self.write(&buf[..n]);
        self.write(b"\n");
    }
}

/// SysTick reloads every 2^24 ticks; its handler counts the wraps.
const RELOAD: u32 = 0x00ff_ffff;
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Ticks since SysTick started (it counts down, so invert the current value).
fn ticks() -> u64 {
    loop {
        let wraps = WRAPS.load(Ordering::Relaxed);
        let current = SYST::get_current();
        // A wrap between the two reads would pair a new count with an old
        // wrap number: read again.
        if WRAPS.load(Ordering::Relaxed) == wraps {
            return (u64::from(wraps) << 24) | u64::from(RELOAD - current);
        }
    }
}

/// Instructions executed by [`calibration_loop`].
const CALIBRATION: u64 = 1 << 24;

/// Executes exactly [`CALIBRATION`] instructions: `CALIBRATION / 2`
/// iterations of `subs` + `bne` (written out rather than `asm::delay`, whose
/// iteration count has changed between cortex-m releases).
fn calibration_loop() {
    let iterations = (CALIBRATION / 2) as u32;
    // SAFETY: only decrements a register it owns; touches no memory or stack.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {0}, #1",
            "bne 2b",
            inout(reg) iterations => _,
            options(nomem, nostack),
        );
    }
}

/// The paint value of cortex-m-rt's `paint-stack`.
const PAINT: u32 = 0xcccc_cccc;

unsafe extern "C" {
    // Bounds of the stack from cortex-m-rt's link.x: it grows down from
    // `_stack_start` towards `_stack_end` (the end of static RAM).
    static _stack_start: u32;
    static _stack_end: u32;
}

/// The deepest the stack has been since reset, in bytes: the distance from
/// the top of the stack to the lowest word no longer holding the paint.
fn stack_peak() -> u64 {
    let bottom = &raw const _stack_end as usize;
    let top = &raw const _stack_start as usize;
    let mut p = bottom;
    // SAFETY: every word in [bottom, top) is RAM reserved for the stack,
    // aligned to 4 bytes by link.x; reading it has no side effect.
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    (top - p) as u64
}

/// Runs the example in `F` over the chains in `storage` (filled to its
/// capacity, [`N`], with empty chains first), writes its result lines, its
/// tick count and the instructions these ticks stand for under
/// `-icount shift=0`.
fn run_one<F: Float>(host: &mut Host, calibration: u64, storage: &mut Vec<DemoChain<F>, N>) {
    let (name, _) = hrla_embedded::float_name::<F>();
    // One chain at a time: no array of chains is ever built on the stack.
    while storage.push(DemoChain::default()).is_ok() {}
    let t0 = ticks();
    let result = hrla_embedded::run::<F>(storage, hrla_embedded::SEED, hrla_embedded::STEPS);
    let t1 = ticks();
    let Ok((opt, _)) = result else {
        host.write(name);
        host.write(b" error\n");
        fail();
    };
    hrla_embedded::report(&opt, host);
    #[cfg(feature = "fmt")]
    {
        use core::fmt::Write;
        // Only here to measure what float formatting costs in flash.
        let b = opt.best();
        let _ = writeln!(host.0, "# fmt best {:?} at {:?}", b.value, b.x);
    }
    let mut label = [0u8; 16];
    label[..3].copy_from_slice(name);
    label[3..9].copy_from_slice(b" ticks");
    host.diagnostic(&label[..9], t1 - t0);
    label[3..].copy_from_slice(b" instructions");
    host.diagnostic(&label, (t1 - t0) * CALIBRATION / calibration.max(1));
}

#[entry]
fn main() -> ! {
    // The chains, in `.bss`: cortex-m-rt hands `main` a `&'static mut` to
    // each `static mut` declared here (safe: `main` runs once). Empty
    // `heapless::Vec`s are const, so nothing is built at start-up.
    #[cfg(feature = "f32")]
    static mut CHAINS_F32: Vec<DemoChain<f32>, N> = Vec::new();
    #[cfg(feature = "f64")]
    static mut CHAINS_F64: Vec<DemoChain<f64>, N> = Vec::new();

    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail();
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(RELOAD);
    cp.SYST.enable_interrupt();
    cp.SYST.enable_counter();
    // The current value reads 0 until the counter has loaded the reload
    // value (under QEMU, for a while): a reading then would be a phantom
    // wrap.
    while SYST::get_current() == 0 {}

    let Ok(stdout) = hio::hstdout() else {
        fail();
    };
    let mut host = Host(stdout);

    let t0 = ticks();
    calibration_loop();
    let calibration = ticks() - t0;
    host.diagnostic(b"calibration", calibration);

    #[cfg(feature = "f32")]
    run_one::<f32>(&mut host, calibration, CHAINS_F32);
    #[cfg(feature = "f64")]
    run_one::<f64>(&mut host, calibration, CHAINS_F64);

    host.diagnostic(b"stack.peak", stack_peak());
    host.diagnostic(b"stack.size", {
        let bottom = &raw const _stack_end as usize;
        let top = &raw const _stack_start as usize;
        (top - bottom) as u64
    });

    debug::exit(debug::EXIT_SUCCESS);
    park()
}

/// Exits with a failure status through semihosting.
fn fail() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    park()
}

/// Where the program ends when no debugger catches the semihosting exit (a
/// board running on its own): sleep forever.
fn park() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
