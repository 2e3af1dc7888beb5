//! The firmware example's computation on the host: prints exactly the lines
//! the firmware prints through semihosting (without its `#` diagnostics).
//!
//! Usage: `hrla-embedded-host [f32|f64]...` (both when none is given).

use std::io::Write;

struct Stdout(std::io::StdoutLock<'static>);

impl hrla_embedded::Sink for Stdout {
    fn write(&mut self, bytes: &[u8]) {
        // A closed stdout is not worth a panic message of its own.
        let _ = self.0.write_all(bytes);
    }
}

fn main() {
    let mut out = Stdout(std::io::stdout().lock());
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        args = vec!["f32".into(), "f64".into()];
    }
    for arg in &args {
        match arg.as_str() {
            "f32" => hrla_embedded::run_and_report::<f32>(&mut out),
            "f64" => hrla_embedded::run_and_report::<f64>(&mut out),
            other => {
                eprintln!("unknown float type {other:?}: expected f32 or f64");
                std::process::exit(2);
            }
        }
    }
}
