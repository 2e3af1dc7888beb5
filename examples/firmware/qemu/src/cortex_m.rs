//! What differs on the Cortex-M cores: the entry point is cortex-m-rt's,
//! the clock is SysTick, the stack is painted by cortex-m-rt's
//! `paint-stack` before `main`.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;

pub use cortex_m_rt::entry;

/// SysTick reloads every 2^24 ticks; its handler counts the wraps.
const RELOAD: u32 = 0x00ff_ffff;
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// The clock, SysTick scaled to instructions: QEMU emulates no DWT cycle
/// counter. Under `-icount shift=0` every instruction takes 1 ns of
/// virtual time, so SysTick's ticks are proportional to instructions, by a
/// ratio that [`Clock::start`] measures on a loop of known length; on
/// hardware, where a tick is a core cycle, the same scale gives the cycles
/// in units of that loop's instructions.
pub struct Clock {
    /// Ticks of [`calibration_loop`], which runs exactly [`CALIBRATION`]
    /// instructions.
    calibration: u64,
}

/// Instructions executed by [`calibration_loop`].
const CALIBRATION: u64 = 1 << 24;

impl Clock {
    /// Starts SysTick and calibrates it against a loop of known length.
    pub fn start() -> Option<Self> {
        let mut cp = cortex_m::Peripherals::take()?;
        cp.SYST.set_clock_source(SystClkSource::Core);
        cp.SYST.set_reload(RELOAD);
        cp.SYST.enable_interrupt();
        cp.SYST.enable_counter();
        // The current value reads 0 until the counter has loaded the reload
        // value (under QEMU, for a while): a reading then would be a
        // phantom wrap.
        while SYST::get_current() == 0 {}
        let t0 = ticks();
        calibration_loop();
        let calibration = (ticks() - t0).max(1);
        Some(Self { calibration })
    }

    /// Instructions since SysTick started, to within one tick (40
    /// instructions on `mps2-an386`, 83 on `lm3s6965evb`).
    pub fn now(&mut self) -> u64 {
        ticks() * CALIBRATION / self.calibration
    }

    /// The ticks of the calibration loop, for the diagnostics.
    pub fn calibration(&self) -> u64 {
        self.calibration
    }
}

/// Ticks since SysTick started (it counts down, so the current value is
/// inverted).
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

unsafe extern "C" {
    // Bounds of the stack from cortex-m-rt's link.x: it grows down from
    // `_stack_start` towards `_stack_end` (the end of static RAM), which
    // `paint-stack` filled with the paint before `main`.
    static _stack_start: u32;
    static _stack_end: u32;
}

/// The stack's bounds, `(bottom, top)`, already painted.
pub fn stack() -> (usize, usize) {
    (
        &raw const _stack_end as usize,
        &raw const _stack_start as usize,
    )
}
