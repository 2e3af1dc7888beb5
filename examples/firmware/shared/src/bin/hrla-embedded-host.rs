//! The firmware example's computation on the host: prints exactly the lines
//! the firmware prints (without its `#` diagnostics).
//!
//! Usage: `hrla-embedded-host [--rng xoshiro128|xoshiro256] [f32|f64]...`
//! (both float types when none is given; `xoshiro128`, the firmware's
//! default generator, when no `--rng` is).

use std::io::Write;

use hrla_embedded::{Generator, Xoshiro128PlusPlus, Xoshiro256PlusPlus, run_and_report};

struct Stdout(std::io::StdoutLock<'static>);

impl hrla_embedded::Sink for Stdout {
    fn write(&mut self, bytes: &[u8]) {
        // A closed stdout is not worth a panic message of its own.
        let _ = self.0.write_all(bytes);
    }
}

fn usage(message: &str) -> ! {
    eprintln!("{message}\nusage: hrla-embedded-host [--rng xoshiro128|xoshiro256] [f32|f64]...");
    std::process::exit(2);
}

fn report<R: Generator>(floats: &[String], out: &mut Stdout) {
    for float in floats {
        match float.as_str() {
            "f32" => run_and_report::<f32, R>(out),
            "f64" => run_and_report::<f64, R>(out),
            other => usage(&format!(
                "unknown float type {other:?}: expected f32 or f64"
            )),
        }
    }
}

fn main() {
    let mut out = Stdout(std::io::stdout().lock());
    let mut rng = Xoshiro128PlusPlus::NAME.to_string();
    let mut floats = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--rng" {
            rng = args.next().unwrap_or_else(|| usage("--rng needs a value"));
        } else {
            floats.push(arg);
        }
    }
    if floats.is_empty() {
        floats = vec!["f32".into(), "f64".into()];
    }
    match rng.as_str() {
        Xoshiro128PlusPlus::NAME => report::<Xoshiro128PlusPlus>(&floats, &mut out),
        Xoshiro256PlusPlus::NAME => report::<Xoshiro256PlusPlus>(&floats, &mut out),
        other => usage(&format!("unknown generator {other:?}")),
    }
}
