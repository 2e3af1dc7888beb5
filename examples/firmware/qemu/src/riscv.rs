//! What differs on the RISC-V core: the entry point is riscv-rt's, the
//! clock is the `minstret` instruction counter, and the stack is painted
//! here, since riscv-rt does not.

pub use riscv_rt::entry;

use crate::PAINT;

/// The `minstret` counter: instructions retired. QEMU derives it from its
/// instruction count under `-icount` (without, from the host's clock), so
/// there it is exact; on hardware it counts instructions too.
pub struct Clock;

impl Clock {
    /// Nothing to start: the counter runs from reset.
    pub fn start() -> Option<Self> {
        Some(Self)
    }

    /// Instructions retired since reset.
    pub fn now(&mut self) -> u64 {
        riscv::register::minstret::read64()
    }

    /// No calibration: the counter counts instructions.
    pub fn calibration(&self) -> u64 {
        0
    }
}

unsafe extern "C" {
    // Bounds of the stack from riscv-rt's link.x: it grows down from
    // `_stack_start` (the end of RAM) towards `__estack` (the end of the
    // empty heap, after static RAM).
    static _stack_start: u32;
    static __estack: u32;
}

/// The stack's bounds, `(bottom, top)`, after painting every word below
/// the caller's frame with [`PAINT`]. Call it first thing in `main`: what
/// ran before is above.
#[inline(never)]
pub fn stack() -> (usize, usize) {
    let bottom = &raw const __estack as usize;
    let top = &raw const _stack_start as usize;
    let sp: usize;
    // SAFETY: reads the stack pointer into a register; nothing else.
    unsafe { core::arch::asm!("mv {0}, sp", out(reg) sp, options(nomem, nostack)) };
    let mut p = bottom;
    while p + 4 <= sp {
        // SAFETY: [bottom, sp) is stack RAM below every live frame (RISC-V
        // has no red zone), 4-byte aligned by riscv-rt's link.x.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
    (bottom, top)
}
