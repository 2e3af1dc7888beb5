//! Prints the bit patterns of runs of the wrapper, natively, for the
//! bit-identity test: `web/tests/same-numbers.test.mjs` runs the same
//! cases in the wasm build under Node and compares the lines.
//!
//! Usage: `cargo run -p hrla-wasm --example trace -- wasm/tests/trace-cases.txt`

use std::process::ExitCode;

use hrla_wasm::{Optimizer, Settings, Summary, Temperature, parse_sampler};

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: trace CASES_FILE");
        return ExitCode::FAILURE;
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::FAILURE;
        }
    };
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match run(line) {
            Ok(out) => print!("{out}"),
            Err(e) => {
                eprintln!("{path}: `{line}`: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}

/// Runs one case line and renders its trace.
fn run(line: &str) -> Result<String, String> {
    let f: Vec<&str> = line.split_whitespace().collect();
    let [
        name,
        potential,
        sampler,
        a,
        h,
        chains,
        cx,
        cy,
        spread,
        seed,
        stop,
        steps,
    ] = f[..]
    else {
        return Err(format!("expected 12 fields, got {}", f.len()));
    };
    let num = |s: &str| s.parse::<f64>().map_err(|e| format!("`{s}`: {e}"));
    let int = |s: &str| s.parse::<u64>().map_err(|e| format!("`{s}`: {e}"));
    let temperature = match a.split(':').collect::<Vec<_>>()[..] {
        [a] => Temperature::Constant(num(a)?),
        [low, high, k] => Temperature::Linear {
            a_low: num(low)?,
            a_high: num(high)?,
            steps: int(k)?,
        },
        _ => return Err(format!("bad temperature `{a}`")),
    };
    // `-`, or a step budget and/or `@target`: `500`, `@0.01`, `500@0.01`.
    let (stop_steps, stop_target) = match stop.split_once('@') {
        _ if stop == "-" => (None, None),
        Some((k, t)) => ((!k.is_empty()).then(|| int(k)).transpose()?, Some(num(t)?)),
        None => (Some(int(stop)?), None),
    };
    let settings = Settings {
        landscape: potential
            .parse()
            .map_err(|e: hrla_wasm::UnknownLandscape| e.to_string())?,
        sampler: parse_sampler(sampler).map_err(|e| e.to_string())?,
        temperature,
        h: num(h)?,
        chains: int(chains)? as usize,
        centre: [num(cx)?, num(cy)?],
        spread: num(spread)?,
        seed: int(seed)?,
        stop_steps,
        stop_target,
        escape: None,
    };
    let mut opt = Optimizer::from_settings(&settings).map_err(|e| e.to_string())?;
    let steps = u32::try_from(int(steps)?).map_err(|e| e.to_string())?;
    opt.step_n(steps).map_err(|e| e.to_string())?;
    Ok(render(name, &opt))
}

/// The trace format, shared with the Node side: one line per quantity,
/// f64 as 16 hex digits of its bit pattern.
fn render(name: &str, opt: &Optimizer) -> String {
    let hex = |v: f64| format!("{:016x}", v.to_bits());
    let s = opt.summary();
    let mut out = format!(
        "{name} iteration {} stopped {}\n{name} best {} {} {} at {}\n",
        s[Summary::Iteration as usize],
        s[Summary::Termination as usize],
        hex(s[Summary::BestValue as usize]),
        hex(s[Summary::BestX0 as usize]),
        hex(s[Summary::BestX1 as usize]),
        s[Summary::BestIteration as usize],
    );
    for (c, x) in opt.positions().chunks(2).enumerate() {
        let y = &opt.velocities()[2 * c..2 * c + 2];
        out += &format!(
            "{name} chain {c} x {} {} y {} {} u {}\n",
            hex(x[0]),
            hex(x[1]),
            hex(y[0]),
            hex(y[1]),
            hex(opt.values()[c]),
        );
    }
    out
}
