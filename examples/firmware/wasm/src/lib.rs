//! The firmware example's computation ([`hrla_embedded`]) compiled to
//! WebAssembly: one exported function, [`report`], returns the very lines
//! that the Cortex-M3 firmware prints through semihosting and that
//! `hrla-embedded-host` prints on the host.
//!
//! `scripts/test-web.sh` builds it for `wasm32-unknown-unknown` (with and
//! without the `micromath` feature), binds it with
//! `wasm-bindgen --target nodejs`, and `web/tests/embedded.test.mjs`
//! compares its reports, byte for byte, with the host's and the firmware's.

#![deny(missing_docs)]
#![forbid(unsafe_code)]

use wasm_bindgen::prelude::*;

/// Collects the report's bytes (the report is ASCII).
struct Bytes(Vec<u8>);

impl hrla_embedded::Sink for Bytes {
    fn write(&mut self, bytes: &[u8]) {
        self.0.extend_from_slice(bytes);
    }
}

/// The four report lines of [`hrla_embedded::run_and_report`] in
/// `float_type` (`"f32"` or `"f64"`), each ending in `\n`.
///
/// # Errors
///
/// A JS `Error` for any other `float_type`.
#[wasm_bindgen]
pub fn report(float_type: &str) -> Result<String, JsError> {
    let mut out = Bytes(Vec::new());
    match float_type {
        "f32" => hrla_embedded::run_and_report::<f32>(&mut out),
        "f64" => hrla_embedded::run_and_report::<f64>(&mut out),
        other => {
            return Err(JsError::new(&format!(
                "unknown float type {other:?}: expected \"f32\" or \"f64\""
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
