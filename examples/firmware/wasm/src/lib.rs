//! The firmware example's computation ([`hrla_embedded`]) compiled to
//! WebAssembly: one exported function, [`report`], returns the very lines
//! that the firmware prints under QEMU (Cortex-M3, Cortex-M4F, RISC-V) and
//! that `hrla-embedded-host` prints on the host.
//!
//! `scripts/test-web.sh` builds it for `wasm32-unknown-unknown` (with and
//! without the `micromath` feature), binds it with
//! `wasm-bindgen --target nodejs`, and `web/tests/embedded.test.mjs`
//! compares its reports, byte for byte, with the host's and the firmware's.

#![deny(missing_docs)]
#![forbid(unsafe_code)]

use hrla_embedded::{Generator, Sink, Xoshiro128PlusPlus, Xoshiro256PlusPlus, run_and_report};
use wasm_bindgen::prelude::*;

/// Collects the report's bytes (the report is ASCII).
struct Bytes(Vec<u8>);

impl Sink for Bytes {
    fn write(&mut self, bytes: &[u8]) {
        self.0.extend_from_slice(bytes);
    }
}

fn run<R: Generator>(float_type: &str, out: &mut Bytes) -> Result<(), JsError> {
    match float_type {
        "f32" => run_and_report::<f32, R>(out),
        "f64" => run_and_report::<f64, R>(out),
        other => {
            return Err(JsError::new(&format!(
                "unknown float type {other:?}: expected \"f32\" or \"f64\""
            )));
        }
    }
    Ok(())
}

/// The four report lines of [`hrla_embedded::run_and_report`] in
/// `float_type` (`"f32"` or `"f64"`) with one generator `rng` per chain
/// (`"xoshiro128"` or `"xoshiro256"`), each line ending in `\n`.
///
/// # Errors
///
/// A JS `Error` for any other `float_type` or `rng`.
#[wasm_bindgen]
pub fn report(float_type: &str, rng: &str) -> Result<String, JsError> {
    let mut out = Bytes(Vec::new());
    match rng {
        Xoshiro128PlusPlus::NAME => run::<Xoshiro128PlusPlus>(float_type, &mut out)?,
        Xoshiro256PlusPlus::NAME => run::<Xoshiro256PlusPlus>(float_type, &mut out)?,
        other => {
            return Err(JsError::new(&format!(
                "unknown generator {other:?}: expected \"xoshiro128\" or \"xoshiro256\""
            )));
        }
    }
    // The sink only ever receives ASCII: hex digits, labels, spaces, newlines.
    String::from_utf8(out.0).map_err(|e| JsError::new(&e.to_string()))
}

/// Whether this build has the kernel's `micromath` feature, so that the test
/// can check it loaded the module it meant to.
#[wasm_bindgen]
pub fn micromath() -> bool {
    cfg!(feature = "micromath")
}
