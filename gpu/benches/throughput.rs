//! Throughput of the device's chains: one optimiser of N chains of HRLA on
//! 10-D Rastrigin (a constant a = 4, the value and running best at every
//! step), N from 10^4 to 10^6 (10^7 with `--chains 10000000` where the
//! device's memory allows), in both arithmetics, in f32 and, where the
//! adapter has it, f64.
//!
//! `cargo bench -p hrla-gpu --bench throughput [-- --chains N,N,.. --steps K
//! --precision f32|f64 --arithmetic ieee|fused]` (the last two pick one
//! row each; `bench/peers/gpu.sh` runs one configuration per call, between
//! JAX's repeats).
//!
//! Prints, per N: the wall time of K steps (after a warm-up run that
//! compiles and loads the pipeline), nanoseconds per coordinate-step
//! (time / (N K D)) and chain-steps per second. The time includes the
//! dispatches, the wait for the queue and the device-side failure census,
//! not the initialisation.

use std::time::Instant;

use hrla::Hrla;
use hrla_gpu::{Arithmetic, DevicePotential, EnsembleBuilder, Gpu, Precision, Start};

const D: usize = 10;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let chains: Vec<usize> = value("--chains")
        .unwrap_or_else(|| "10000,100000,1000000".to_string())
        .split(',')
        .map(|s| s.parse::<f64>().map(|v| v as usize))
        .collect::<Result<_, _>>()?;
    let steps: u64 = value("--steps").map_or(Ok(200), |s| s.parse())?;
    let only_precision = match value("--precision").as_deref() {
        None => None,
        Some("f32") => Some(Precision::F32),
        Some("f64") => Some(Precision::F64),
        Some(other) => return Err(format!("--precision {other}: f32 or f64").into()),
    };
    let only_arithmetic = match value("--arithmetic").as_deref() {
        None => None,
        Some("ieee") => Some(Arithmetic::Ieee),
        Some("fused") => Some(Arithmetic::Fused),
        Some(other) => return Err(format!("--arithmetic {other}: ieee or fused").into()),
    };
    let gpu = Gpu::new()?;
    if only_precision == Some(Precision::F64) && !gpu.supports_f64() {
        return Err(format!("f64: the adapter {} has no SHADER_F64", gpu.describe()).into());
    }
    println!("adapter: {}", gpu.describe());
    println!("HRLA, {D}-D Rastrigin, a = 4, {steps} steps, 100 steps per dispatch");
    println!(
        "{:>10} {:>5} {:>7} {:>10} {:>16} {:>18}",
        "chains", "float", "arith", "seconds", "ns/coord-step", "chain-steps/s"
    );
    let mut precisions = vec![Precision::F32];
    if gpu.supports_f64() {
        precisions.push(Precision::F64);
    }
    for &n in &chains {
        for (precision, arithmetic) in precisions
            .iter()
            .flat_map(|&p| [Arithmetic::Ieee, Arithmetic::Fused].map(move |a| (p, a)))
            .filter(|&(p, a)| {
                only_precision.is_none_or(|o| o == p) && only_arithmetic.is_none_or(|o| o == a)
            })
        {
            let mut ensemble = EnsembleBuilder::new(
                DevicePotential::Rastrigin,
                Hrla::paper(0.01)?,
                4.0,
                Start::paper(D),
            )
            .chains(n)
            .seed(1)
            .arithmetic(arithmetic)
            .precision(precision)
            .steps_per_dispatch(100)
            .build(&gpu)?;
            ensemble.run(2)?;
            let t = Instant::now();
            ensemble.run(steps)?;
            let s = t.elapsed().as_secs_f64();
            let chain_steps = n as f64 * steps as f64;
            println!(
                "{:>10} {:>5} {:>7} {:>10.3} {:>16.3} {:>18.3e}",
                n,
                format!("{precision:?}"),
                format!("{arithmetic:?}"),
                s,
                s * 1e9 / (chain_steps * D as f64),
                chain_steps / s
            );
            // The run did something: its best is finite and below the start's.
            let best = ensemble.best()?;
            assert!(best.value.is_finite() && best.value < 100.0, "{best:?}");
        }
    }
    Ok(())
}
