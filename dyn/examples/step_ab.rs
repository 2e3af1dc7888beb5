//! Times the layer's step loop (what the page and Python run per step):
//! `step_ab D CHAINS STEPS [per]`, in ns per coordinate-step, for
//! interleaved A/B runs of two builds; `per`: a box whose sides differ
//! between coordinates (the kernel's `Bounds`), else one interval.
use hrla::{AnySampler, AnySchedule, Constant, SamplerKind, Stop};
use hrla_dyn::{BoxSpec, BuiltinKind, BuiltinSpec, PotentialSpec, Settings, StartSpec};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let d: usize = args[1].parse().unwrap();
    let chains: usize = args[2].parse().unwrap();
    let steps: u64 = args[3].parse().unwrap();
    let per: bool = args.get(4).is_some_and(|a| a == "per");
    let boxspec = if per {
        BoxSpec::PerCoordinate((0..d).map(|i| (-5.12 - i as f64 * 1e-9, 5.12)).collect())
    } else {
        BoxSpec::Uniform {
            lo: -5.12,
            hi: 5.12,
        }
    };
    let s = Settings {
        potential: PotentialSpec::Builtin(BuiltinSpec::Named(BuiltinKind::Rastrigin)),
        sampler: AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        schedule: AnySchedule::Constant(Constant::new(4.0).unwrap()),
        start: StartSpec::Box(boxspec.clone()),
        domain: Some(boxspec),
        seed: 1,
        stride: 1,
        stop: Stop::new(),
        chains,
        dim: Some(d),
        escape: None,
    };
    let mut e = s.build().unwrap();
    e.step(10).unwrap();
    let t = Instant::now();
    e.step(steps).unwrap();
    let ns = t.elapsed().as_nanos() as f64 / (steps as f64 * chains as f64 * d as f64);
    println!("{ns:.3} ns/coordinate-step value {}", e.best().1);
}
