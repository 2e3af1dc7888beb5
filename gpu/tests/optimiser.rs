//! Algorithm 1 on the device: its best and the empirical probability,
//! reduced on the device, against the CPU optimiser; the run's failures as
//! the CPU reports them; user potentials, and bad input as typed errors.

mod common;

use hrla::{Builder, Chain, FnPotential, FnSchedule, Gaussian, Hrla, Rastrigin, Stop};
use hrla_gpu::{DevicePotential, EnsembleBuilder, GpuError, Start};
use rand_xoshiro::Xoshiro128PlusPlus;

const D: usize = 10;
const SEED: u64 = 5;

fn cpu_run(chains: usize, steps: u64, stride: u64) -> Vec<Chain<f32, D, Xoshiro128PlusPlus>> {
    let mut cpu: Vec<Chain<f32, D, Xoshiro128PlusPlus>> =
        (0..chains).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01f32).unwrap(),
        4.0f32,
        Gaussian::new([3.0; D], 10f32.sqrt()).unwrap(),
    )
    .seed(SEED)
    .stride(stride)
    .stop(Stop::new().steps(steps))
    .build(&mut cpu)
    .unwrap();
    opt.run().unwrap();
    cpu
}

fn device_run(chains: usize, steps: u64, stride: u64) -> hrla_gpu::Ensemble<'static> {
    let mut ensemble = EnsembleBuilder::new(
        DevicePotential::Rastrigin,
        Hrla::paper(0.01f32).unwrap(),
        4.0f32,
        Start::gaussian(vec![3.0; D], f64::from(10f32.sqrt())).unwrap(),
    )
    .chains(chains)
    .seed(SEED)
    .stride(stride)
    .steps_per_dispatch(37)
    .build(common::gpu())
    .unwrap();
    ensemble.run(steps).unwrap();
    ensemble
}

/// The best over 5000 chains (several reduction passes) with a stride:
/// the CPU optimiser's chain, value, iterate and point.
#[test]
fn best_is_the_cpu_optimisers() {
    let (n, steps, stride) = (5000, 150, 10);
    let cpu = cpu_run(n, steps, stride);
    let device = device_run(n, steps, stride).best().unwrap();
    let (c, b) = cpu
        .iter()
        .enumerate()
        .map(|(c, ch)| (c, ch.best()))
        .min_by(|a, b| {
            a.1.value
                .total_cmp(&b.1.value)
                .then(a.1.iteration.cmp(&b.1.iteration))
        })
        .unwrap();
    assert_eq!(device.chain, c);
    assert_eq!(device.value.to_bits(), f64::from(b.value).to_bits());
    assert_eq!(device.iteration, b.iteration);
    assert_eq!(device.iteration % stride, 0);
    assert_eq!(
        device.x,
        b.x.iter().copied().map(f64::from).collect::<Vec<_>>()
    );
}

/// The empirical probability, counted on the device, against the count
/// over the CPU optimiser's chains, runs of 10 chains, several eps.
#[test]
fn probability_is_the_count_over_the_cpu_chains() {
    let (n, steps) = (4000, 100);
    let cpu = cpu_run(n, steps, 1);
    let eps = [0.5, 5.0, 10.0, 20.0, 40.0];
    let device = device_run(n, steps, 1).probability(10, 0.0, &eps).unwrap();
    for (p, &e) in device.iter().zip(&eps) {
        let (mut current, mut running) = (0, 0);
        for run in cpu.chunks(10) {
            let now = run.iter().map(|c| c.value()).fold(f32::INFINITY, f32::min);
            let best = run
                .iter()
                .map(|c| c.best().value)
                .fold(f32::INFINITY, f32::min);
            current += usize::from(now - 0.0 <= e as f32);
            running += usize::from(best - 0.0 <= e as f32);
        }
        assert_eq!(p.eps, e);
        assert_eq!(p.current, current as f64 / 400.0, "eps {e}");
        assert_eq!(p.running, running as f64 / 400.0, "eps {e}");
    }
    // Not all 0 or 1: the eps straddle the values.
    assert!(device.iter().any(|p| p.current > 0.0 && p.current < 1.0));
}

/// Runs with their own seeds: run `r` of an ensemble of three runs is the
/// CPU optimiser of that run's seed, chain for chain (so batching runs
/// changes none of them); each run's summary is the CPU chains'.
#[test]
fn runs_with_their_own_seeds_are_the_cpu_optimisers_of_those_seeds() {
    let (g, steps, stride) = (7, 60, 4);
    let seeds = [11u64, 2, 30];
    let cpu_of = |seed: u64| {
        let mut cpu: Vec<Chain<f32, D, Xoshiro128PlusPlus>> =
            (0..g).map(|_| Chain::default()).collect();
        let mut opt = Builder::new(
            Rastrigin,
            Hrla::paper(0.01f32).unwrap(),
            4.0f32,
            Gaussian::new([3.0; D], 10f32.sqrt()).unwrap(),
        )
        .seed(seed)
        .stride(stride)
        .stop(Stop::new().steps(steps))
        .build(&mut cpu)
        .unwrap();
        opt.run().unwrap();
        cpu
    };
    for start_in_best in [true, false] {
        let mut e = EnsembleBuilder::new(
            DevicePotential::Rastrigin,
            Hrla::paper(0.01f32).unwrap(),
            4.0f32,
            Start::gaussian(vec![3.0; D], f64::from(10f32.sqrt())).unwrap(),
        )
        .chains(g * seeds.len())
        .run_seeds(seeds.to_vec())
        .stride(stride)
        .start_in_best(start_in_best)
        .build(common::gpu())
        .unwrap();
        let before = e.group_bests(g).unwrap();
        for b in &before {
            assert!(b.current.is_finite());
            assert_eq!(b.running.is_finite(), start_in_best);
        }
        e.run(steps).unwrap();
        let device = e.snapshot().unwrap();
        let groups = e.group_bests(g).unwrap();
        assert_eq!(groups.len(), seeds.len());
        for (r, &seed) in seeds.iter().enumerate() {
            let cpu = cpu_of(seed);
            let mine = &device[r * g..(r + 1) * g];
            for (d, c) in mine.iter().zip(&cpu) {
                assert_eq!(d.x, c.x().map(f64::from).to_vec());
                // Without the start, a chain's running best is the CPU's
                // wherever the CPU's is not the start itself.
                if start_in_best || c.best().iteration > 0 {
                    assert_eq!(d.best_value, f64::from(c.best().value));
                } else {
                    assert!(d.best_value > f64::from(c.best().value));
                }
            }
            let now = cpu.iter().map(|c| c.value()).fold(f32::INFINITY, f32::min);
            assert_eq!(groups[r].current, f64::from(now));
            let running = mine
                .iter()
                .map(|c| c.best_value)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(groups[r].running, running);
            assert_eq!(groups[r].diverged, 0);
            assert_eq!(groups[r].evaluations, g as u64 * (steps + 1));
        }
    }
    let bad = EnsembleBuilder::new(
        DevicePotential::Rastrigin,
        Hrla::paper(0.01f32).unwrap(),
        4.0f32,
        Start::paper(D),
    )
    .chains(10)
    .run_seeds(vec![1, 2, 3])
    .build(common::gpu())
    .unwrap_err();
    assert!(
        matches!(bad, GpuError::Kernel(hrla::Error::Count { value: 3, .. })),
        "{bad}"
    );
}

/// A user's potential that is unbounded below: the same error, chain and
/// value as the CPU optimiser's.
#[test]
fn unbounded_below_is_reported_as_the_cpu_reports_it() {
    let cpu_potential = FnPotential::new(|x: &[f32; 2], g: &mut [f32; 2]| {
        *g = [-4.0 * x[0] * x[0] * x[0], 0.0];
        -(x[0] * x[0]) * (x[0] * x[0]) + x[1] * 0.0
    });
    let mut cpu: Vec<Chain<f32, 2, Xoshiro128PlusPlus>> =
        (0..300).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(
        cpu_potential,
        Hrla::paper(0.01f32).unwrap(),
        1.0f32,
        Gaussian::new([0.0; 2], 1.0).unwrap(),
    )
    .seed(9)
    .stop(Stop::new().steps(500))
    .build(&mut cpu)
    .unwrap();
    let cpu_error = opt.run().unwrap_err();
    let device_potential = DevicePotential::wgsl(
        "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
            let x0 = (*x)[0];
            (*grad)[0] = -4.0 * x0 * x0 * x0;
            (*grad)[1] = 0.0;
            return rounded(-(x0 * x0) * (x0 * x0)) + mul((*x)[1], 0.0);
        }",
    );
    let mut ensemble = EnsembleBuilder::new(
        device_potential,
        Hrla::paper(0.01f32).unwrap(),
        1.0f32,
        Start::gaussian(vec![0.0; 2], 1.0).unwrap(),
    )
    .chains(300)
    .seed(9)
    .build(common::gpu())
    .unwrap();
    let error = ensemble.run(500).unwrap_err();
    assert!(
        matches!(cpu_error, hrla::Error::UnboundedBelow { .. }),
        "{cpu_error}"
    );
    assert_eq!(error, GpuError::Kernel(cpu_error));
    // A failed run stays failed, and has no best to give.
    assert_eq!(ensemble.run(1).unwrap_err(), error);
    assert_eq!(ensemble.best().unwrap_err(), error);
}

/// A potential whose gradient is infinite everywhere but at the start:
/// every chain diverges at its first step, an error rather than a best.
#[test]
fn all_diverged_is_an_error() {
    let device_potential = DevicePotential::wgsl(
        "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
            (*grad)[0] = select(0.0, bitcast<f32>(0x7f800000u), (*x)[0] != 0.0);
            return (*x)[0] * (*x)[0];
        }",
    );
    let mut ensemble = EnsembleBuilder::new(
        device_potential,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Start::point(vec![0.0]).unwrap(),
    )
    .chains(100)
    .build(common::gpu())
    .unwrap();
    assert_eq!(
        ensemble.run(10).unwrap_err(),
        GpuError::Kernel(hrla::Error::AllDiverged { chains: 100 })
    );
}

#[test]
fn a_user_potential_that_does_not_compile_gives_the_compilers_message() {
    let broken = DevicePotential::wgsl(
        "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
            return (*x)[0] * undefined_name;
        }",
    );
    let err = EnsembleBuilder::new(
        broken,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Start::point(vec![0.0]).unwrap(),
    )
    .build(common::gpu())
    .unwrap_err();
    let GpuError::Shader(message) = &err else {
        panic!("not a shader error: {err}");
    };
    assert!(message.contains("undefined_name"), "{message}");
    // The line of the user's text, not of the whole program.
    assert!(message.contains(":2:"), "{message}");
    // A wrong signature is caught too.
    let wrong = DevicePotential::wgsl("fn value_and_gradient(x: f32) -> f32 { return x; }");
    let err = EnsembleBuilder::new(
        wrong,
        Hrla::paper(0.01).unwrap(),
        1.0,
        Start::point(vec![0.0]).unwrap(),
    )
    .build(common::gpu())
    .unwrap_err();
    assert!(matches!(err, GpuError::Shader(_)), "{err}");
    // The device is still usable after both.
    assert!(device_run(64, 1, 1).best().is_ok());
}

/// A user's WGSL quadratic, written as the built-in is, gives the built-in's
/// bits.
#[test]
fn a_user_potential_runs_like_a_builtin() {
    let user = DevicePotential::wgsl(
        "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
            var kr2 = 0.0;
            for (var i = 0u; i < D; i++) {
                let r = (*x)[i] - 0.5;
                let g = mul(2.0, r);
                (*grad)[i] = g;
                kr2 += mul(g, r);
            }
            return 0.5 * kr2;
        }",
    );
    let builtin = DevicePotential::quadratic(2.0, vec![0.5; 3]).unwrap();
    let states: Vec<_> = [user, builtin]
        .into_iter()
        .map(|p| {
            let mut e = EnsembleBuilder::new(
                p,
                Hrla::paper(0.01).unwrap(),
                2.0,
                Start::gaussian(vec![1.0; 3], 1.0).unwrap(),
            )
            .chains(256)
            .build(common::gpu())
            .unwrap();
            e.run(50).unwrap();
            e.snapshot().unwrap()
        })
        .collect();
    assert_eq!(states[0], states[1]);
}

/// A run past the device's last iterate is refused, on a fresh ensemble
/// and after steps alike, even where the count of iterates would pass
/// `u64::MAX`, and refusing it leaves the chains where they were.
#[test]
fn a_run_past_the_last_iterate_is_refused_fresh_or_not() {
    let mut ensemble = device_run(64, 0, 1);
    let refused = Err(GpuError::Kernel(hrla::Error::Count {
        name: "iterations",
        value: usize::MAX,
        max: u32::MAX as usize - 1,
    }));
    assert_eq!(ensemble.run(u64::MAX), refused);
    ensemble.run(10).unwrap();
    let before = ensemble.best().unwrap();
    assert_eq!(ensemble.run(u64::MAX), refused);
    assert_eq!(ensemble.run(u64::MAX - 5), refused);
    assert_eq!(ensemble.iteration(), 10);
    assert_eq!(ensemble.best().unwrap(), before);
}

#[test]
fn bad_input_is_a_typed_error() {
    let gpu = common::gpu();
    let build = |chains: usize, start: Start, potential: DevicePotential| {
        EnsembleBuilder::new(potential, Hrla::paper(0.01).unwrap(), 1.0, start)
            .chains(chains)
            .build(gpu)
            .map(drop)
    };
    let origin = || Start::point(vec![0.0; 3]).unwrap();
    assert_eq!(
        build(0, origin(), DevicePotential::Rastrigin),
        Err(GpuError::Kernel(hrla::Error::Zero { name: "chains" }))
    );
    assert_eq!(
        build(4, Start::point(vec![]).unwrap(), DevicePotential::Rastrigin),
        Err(GpuError::Kernel(hrla::Error::Zero {
            name: "dimension D"
        }))
    );
    for builder in [
        EnsembleBuilder::new(
            DevicePotential::Rastrigin,
            Hrla::paper(0.01).unwrap(),
            1.0,
            origin(),
        )
        .stride(0),
        EnsembleBuilder::new(
            DevicePotential::Rastrigin,
            Hrla::paper(0.01).unwrap(),
            1.0,
            origin(),
        )
        .steps_per_dispatch(0),
    ] {
        assert!(matches!(
            builder.build(gpu).map(drop),
            Err(GpuError::Kernel(hrla::Error::Zero { .. }))
        ));
    }
    assert!(matches!(
        build(
            4,
            origin(),
            DevicePotential::quadratic(1.0, vec![0.0; 2]).unwrap()
        ),
        Err(GpuError::Dimension {
            expected: 3,
            got: 2,
            ..
        })
    ));
    assert!(matches!(
        DevicePotential::quadratic(f64::NAN, vec![0.0]),
        Err(GpuError::Kernel(hrla::Error::NotPositive { .. }))
    ));
    assert!(matches!(
        Start::gaussian(vec![0.0], -1.0),
        Err(GpuError::Kernel(hrla::Error::Negative { .. }))
    ));
    assert!(matches!(
        Start::point(vec![f64::INFINITY]),
        Err(GpuError::Kernel(hrla::Error::NotFinite { .. }))
    ));
    // A start where the potential is not finite is drawn again from the
    // chain's generator, as the CPU's builder draws it: the same points
    // and evaluations; where every point is refused, the first chain after
    // START_TRIES points, as on the CPU.
    let wall_wgsl =
        "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
            (*grad)[0] = 1.0;
            return select((*x)[0], bitcast<f32>(0x7f800000u), (*x)[0] < WALL);
        }";
    let cpu_with_wall = |wall: f32, chains: usize| {
        let mut cpu: Vec<Chain<f32, 1, Xoshiro128PlusPlus>> =
            (0..chains).map(|_| Chain::default()).collect();
        let potential = FnPotential::new(move |x: &[f32; 1], g: &mut [f32; 1]| {
            g[0] = 1.0;
            if x[0] < wall { f32::INFINITY } else { x[0] }
        });
        Builder::new(
            potential,
            Hrla::paper(0.01f32).unwrap(),
            1.0f32,
            Gaussian::new([1.0], 1.0).unwrap(),
        )
        .build(&mut cpu)
        .map(|opt| opt.evaluations())
        .map(|evaluations| {
            (
                evaluations,
                cpu.iter().map(|c| c.x()[0]).collect::<Vec<_>>(),
            )
        })
    };
    let device_with_wall = |wall: f32, chains: usize| {
        let source = format!("const WALL: Real = {wall:?};\n{wall_wgsl}");
        EnsembleBuilder::new(
            DevicePotential::wgsl(&source),
            Hrla::paper(0.01f32).unwrap(),
            1.0f32,
            Start::gaussian(vec![1.0], 1.0).unwrap(),
        )
        .chains(chains)
        .build(gpu)
        .and_then(|e| {
            let g = e.group_bests(chains)?;
            let x = e
                .snapshot()?
                .iter()
                .map(|c| c.x[0] as f32)
                .collect::<Vec<_>>();
            Ok((g[0].evaluations, x))
        })
    };
    // About half of the first points are refused: redraws happen.
    let (evaluations, x) = cpu_with_wall(1.0, 64).unwrap();
    assert!(evaluations > 64 + 10, "{evaluations}");
    assert!(x.iter().all(|&v| v >= 1.0));
    assert_eq!(device_with_wall(1.0, 64).unwrap(), (evaluations, x));
    // No point is accepted (a standard normal beyond 1e6 never comes).
    let none = cpu_with_wall(1e6, 8).map(drop).unwrap_err();
    assert_eq!(
        none,
        hrla::Error::NonFiniteStart {
            chain: 0,
            what: "value",
            tries: hrla::START_TRIES,
        }
    );
    assert_eq!(
        device_with_wall(1e6, 8).map(drop),
        Err(GpuError::Kernel(none))
    );
    // A start below the floor ends the build at once, naming the first
    // such chain and its value, as on the CPU.
    let mut cpu: Vec<Chain<f32, 1, Xoshiro128PlusPlus>> =
        (0..4).map(|_| Chain::default()).collect();
    let abyss = FnPotential::new(|_: &[f32; 1], g: &mut [f32; 1]| {
        g[0] = 0.0;
        -1e30
    });
    let cpu_err = Builder::new(
        abyss,
        Hrla::paper(0.01f32).unwrap(),
        1.0f32,
        Gaussian::new([1.0], 1.0).unwrap(),
    )
    .build(&mut cpu)
    .map(drop)
    .unwrap_err();
    assert!(
        matches!(cpu_err, hrla::Error::UnboundedBelow { chain: 0, .. }),
        "{cpu_err}"
    );
    let device_err = EnsembleBuilder::new(
        DevicePotential::wgsl(
            "fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
                (*grad)[0] = 0.0;
                return -1e30;
            }",
        ),
        Hrla::paper(0.01f32).unwrap(),
        1.0f32,
        Start::gaussian(vec![1.0], 1.0).unwrap(),
    )
    .chains(4)
    .build(gpu)
    .map(drop);
    assert_eq!(device_err, Err(GpuError::Kernel(cpu_err)));
    // The sampler's own checks, at a_0 and along the schedule.
    assert!(matches!(
        EnsembleBuilder::new(
            DevicePotential::Rastrigin,
            Hrla::paper(0.01).unwrap(),
            -1.0,
            origin()
        )
        .build(gpu)
        .map(drop),
        Err(GpuError::Kernel(hrla::Error::NotPositive { name: "a", .. }))
    ));
    let mut e = device_run(40, 1, 1);
    assert!(matches!(
        e.probability(3, 0.0, &[1.0]),
        Err(GpuError::Kernel(hrla::Error::Count { .. }))
    ));
    assert!(matches!(
        e.probability(10, f64::NAN, &[1.0]),
        Err(GpuError::Kernel(hrla::Error::NotFinite { .. }))
    ));
    assert!(matches!(
        e.probability(10, 0.0, &[1.0; 65]),
        Err(GpuError::Kernel(hrla::Error::Count { .. }))
    ));
    assert!(e.run(0).is_ok());
    // f64 with a potential that needs the device's sin: refused, not run.
    if gpu.supports_f64() {
        assert!(matches!(
            EnsembleBuilder::new(
                DevicePotential::Ackley,
                Hrla::paper(0.01).unwrap(),
                1.0,
                origin()
            )
            .precision(hrla_gpu::Precision::F64)
            .build(gpu)
            .map(drop),
            Err(GpuError::Unsupported(_))
        ));
    }
    // A schedule that the sampler refuses from iterate 150: the chains
    // stop at iterate 150, where the CPU's stop, and step on from there.
    let schedule = FnSchedule(|k: u64| if k < 150 { 4.0 } else { -1.0 });
    let mut e = EnsembleBuilder::new(
        DevicePotential::Rastrigin,
        Hrla::paper(0.01).unwrap(),
        schedule,
        origin(),
    )
    .chains(8)
    .steps_per_dispatch(100)
    .build(gpu)
    .unwrap();
    assert!(matches!(
        e.run(300),
        Err(GpuError::Kernel(hrla::Error::NotPositive { name: "a", .. }))
    ));
    assert_eq!(e.iteration(), 150);
    // Positions of 2^21 chains of dimension 1024: 8 GiB in one binding,
    // beyond every device's limit.
    assert!(matches!(
        build(
            1 << 21,
            Start::point(vec![0.0; 1024]).unwrap(),
            DevicePotential::DoubleWell
        ),
        Err(GpuError::TooLarge { .. })
    ));
    assert!(matches!(
        build(
            4,
            Start::point(vec![0.0; 1025]).unwrap(),
            DevicePotential::DoubleWell
        ),
        Err(GpuError::Kernel(hrla::Error::Count {
            name: "dimension D",
            ..
        }))
    ));
}

/// In f64 (where the adapter has it): the best and the empirical
/// probability against the CPU's f64 optimiser, whose chains the device's
/// are bit for bit.
#[test]
fn best_and_probability_in_f64() {
    let gpu = common::gpu();
    if !gpu.supports_f64() {
        eprintln!("the adapter has no SHADER_F64: the f64 reductions do not apply");
        return;
    }
    let (n, steps, stride) = (3000, 120, 7);
    let mut cpu: Vec<Chain<f64, D, Xoshiro128PlusPlus>> =
        (0..n).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Gaussian::new([3.0; D], 10f64.sqrt()).unwrap(),
    )
    .seed(SEED)
    .stride(stride)
    .stop(Stop::new().steps(steps))
    .build(&mut cpu)
    .unwrap();
    opt.run().unwrap();
    let (c, b) = (opt.best_chain(), opt.best());
    let mut ensemble = EnsembleBuilder::new(
        DevicePotential::Rastrigin,
        Hrla::paper(0.01).unwrap(),
        4.0,
        Start::paper(D),
    )
    .chains(n)
    .seed(SEED)
    .stride(stride)
    .precision(hrla_gpu::Precision::F64)
    .build(gpu)
    .unwrap();
    ensemble.run(steps).unwrap();
    let best = ensemble.best().unwrap();
    assert_eq!(
        (best.chain, best.value.to_bits(), best.iteration, best.x),
        (c, b.value.to_bits(), b.iteration, b.x.to_vec())
    );
    let eps = [5.0, 10.0, 20.0];
    let device = ensemble.probability(10, 0.0, &eps).unwrap();
    for (p, &e) in device.iter().zip(&eps) {
        let hits = cpu
            .chunks(10)
            .filter(|run| run.iter().any(|ch| ch.value() <= e))
            .count();
        assert_eq!(p.current, hits as f64 / (n / 10) as f64, "eps {e}");
    }
}
