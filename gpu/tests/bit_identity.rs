//! On a device that rounds every operation as IEEE 754 does (no fused
//! multiply-add, correctly rounded division; lavapipe is one), the
//! backend's chains are the CPU kernel's, bit for bit: after K steps in
//! f32 (and in f64 where the adapter has it), every chain's position,
//! velocity, value, running best and generator state equal those of
//! `hrla::Optimizer` over `Chain<F, D, Xoshiro128PlusPlus>` with the same
//! seed.
//!
//! The device is given the sampler's coefficients in the CPU's own float
//! type, so that the comparison is of the device's arithmetic alone.

mod common;

use hrla::{
    AnySampler, Builder, Chain, DoubleWell, Float, Gaussian, Hrla, Linear, Ola, Potential,
    Quadratic, Rastrigin, Sampler, SamplerKind, Schedule, Stop, StyblinskiTang, Ula,
};
use hrla_gpu::{ChainSnapshot, DeviceKernel, DevicePotential, EnsembleBuilder, Precision, Start};
use rand_xoshiro::Xoshiro128PlusPlus;

const D: usize = 10;
const SEED: u64 = 2024;

/// Runs both for `steps` steps; returns the first chain that differs and
/// what differs, if any.
fn compare<F, P, S, C>(
    cpu_potential: P,
    device_potential: DevicePotential,
    sampler: S,
    schedule: C,
    chains: usize,
    steps: u64,
) -> Option<String>
where
    F: Float,
    P: Potential<F, D> + Clone,
    S: Sampler<F> + Copy + 'static,
    S::Kernel: DeviceKernel,
    C: Schedule<F> + Copy + 'static,
{
    let sd = F::from_f64(10.0).sqrt();
    let mut cpu: Vec<Chain<F, D, Xoshiro128PlusPlus>> =
        (0..chains).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(
        cpu_potential,
        sampler,
        schedule,
        Gaussian::new([F::from_f64(3.0); D], sd).unwrap(),
    )
    .seed(SEED)
    .stop(Stop::new().steps(steps.max(1)))
    .build(&mut cpu)
    .unwrap();
    for _ in 0..steps {
        opt.step().unwrap();
    }
    let mut ensemble = EnsembleBuilder::new(
        device_potential,
        sampler,
        schedule,
        Start::gaussian(vec![3.0; D], sd.to_f64()).unwrap(),
    )
    .chains(chains)
    .seed(SEED)
    .steps_per_dispatch(64)
    .precision(precision::<F>())
    .build(common::gpu())
    .unwrap();
    ensemble.run(steps).unwrap();
    let device = ensemble.snapshot().unwrap();
    cpu.iter()
        .zip(&device)
        .enumerate()
        .find_map(|(c, (a, b))| differs(a, b).map(|what| format!("chain {c}: {what}")))
}

/// The device's float type for the CPU's `F`.
fn precision<F: Float>() -> Precision {
    if F::MANTISSA_DIGITS > 24 {
        Precision::F64
    } else {
        Precision::F32
    }
}

/// Bits of CPU floats, or of device values (f64, widened from f32 in f32).
fn bits<F: Float>(v: &[F]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits_u64()).collect()
}

fn device_bits<F: Float>(v: &[f64]) -> Vec<u64> {
    v.iter().map(|&x| F::from_f64(x).to_bits_u64()).collect()
}

fn differs<F: Float>(a: &Chain<F, D, Xoshiro128PlusPlus>, b: &ChainSnapshot) -> Option<String> {
    let checks = [
        ("x", bits(a.x()) == device_bits::<F>(&b.x)),
        ("y", bits(a.y()) == device_bits::<F>(&b.y)),
        ("value", bits(&[a.value()]) == device_bits::<F>(&[b.value])),
        (
            "best value",
            bits(&[a.best().value]) == device_bits::<F>(&[b.best_value]),
        ),
        ("best x", bits(a.best().x) == device_bits::<F>(&b.best_x)),
        ("best iteration", a.best().iteration == b.best_iteration),
        ("diverged", a.is_diverged() == b.diverged),
        ("generator", *a.rng() == b.rng),
    ];
    checks.iter().find(|c| !c.1).map(|c| {
        format!(
            "{} differs: CPU (x, y) = {:?}, device {:?}",
            c.0,
            (a.x(), a.y()),
            (&b.x, &b.y)
        )
    })
}

/// The first iterate at which the two differ (for the failure message).
fn first_difference<F, P, S, C>(
    p: P,
    dp: DevicePotential,
    s: S,
    c: C,
    chains: usize,
    steps: u64,
) -> String
where
    F: Float,
    P: Potential<F, D> + Clone,
    S: Sampler<F> + Copy + 'static,
    S::Kernel: DeviceKernel,
    C: Schedule<F> + Copy + 'static,
{
    let mut k = 0;
    while k <= steps {
        if let Some(what) = compare(p.clone(), dp.clone(), s, c, chains, k) {
            return format!("first at iterate {k}: {what}");
        }
        k += 1.max(k / 4);
    }
    "none found".to_string()
}

fn assert_same<F, P, S, C>(p: P, dp: DevicePotential, s: S, c: C)
where
    F: Float,
    P: Potential<F, D> + Clone,
    S: Sampler<F> + Copy + 'static,
    S::Kernel: DeviceKernel,
    C: Schedule<F> + Copy + 'static,
{
    // 512 chains x 200 steps x 10 coordinates: about 2 million normals,
    // some 500 of them from the Ziggurat's tail.
    let (chains, steps) = (512, 200);
    if let Some(what) = compare(p.clone(), dp.clone(), s, c, chains, steps) {
        panic!(
            "after {steps} steps, {what}\n{}",
            first_difference(p, dp, s, c, chains, steps)
        );
    }
}

#[test]
fn hrla_on_rastrigin() {
    assert_same(
        Rastrigin,
        DevicePotential::Rastrigin,
        Hrla::paper(0.01f32).unwrap(),
        4.0f32,
    );
}

#[test]
fn annealed_hrla_on_rastrigin() {
    let schedule = Linear::new(0.1f32, 4.0, 200).unwrap();
    assert_same(
        Rastrigin,
        DevicePotential::Rastrigin,
        Hrla::paper(0.01f32).unwrap(),
        schedule,
    );
}

#[test]
fn ula_and_ola_on_rastrigin() {
    assert_same(
        Rastrigin,
        DevicePotential::Rastrigin,
        Ula::paper(0.01f32).unwrap(),
        3.0f32,
    );
    assert_same(
        Rastrigin,
        DevicePotential::Rastrigin,
        Ola::paper(0.01f32).unwrap(),
        3.0f32,
    );
}

#[test]
fn any_sampler_on_the_other_exact_potentials() {
    let quadratic = Quadratic::new(2.0f32, [0.5; D]).unwrap();
    let device_quadratic = DevicePotential::quadratic(2.0, vec![0.5; D]).unwrap();
    for kind in SamplerKind::ALL {
        let s = AnySampler::paper(kind, 0.01f32).unwrap();
        assert_same(quadratic, device_quadratic.clone(), s, 2.0f32);
        assert_same(DoubleWell, DevicePotential::DoubleWell, s, 2.0f32);
        assert_same(StyblinskiTang, DevicePotential::StyblinskiTang, s, 0.5f32);
    }
}

/// The same in f64, where the adapter has it (lavapipe has).
#[test]
fn f64_on_every_exact_potential() {
    if !common::gpu().supports_f64() {
        eprintln!("the adapter has no SHADER_F64: the f64 comparison does not apply");
        return;
    }
    let hrla = Hrla::paper(0.01f64).unwrap();
    assert_same(Rastrigin, DevicePotential::Rastrigin, hrla, 4.0f64);
    let schedule = Linear::new(0.1f64, 4.0, 200).unwrap();
    assert_same(Rastrigin, DevicePotential::Rastrigin, hrla, schedule);
    let quadratic = Quadratic::new(2.0f64, [0.5; D]).unwrap();
    let device_quadratic = DevicePotential::quadratic(2.0, vec![0.5; D]).unwrap();
    for kind in SamplerKind::ALL {
        let s = AnySampler::paper(kind, 0.01f64).unwrap();
        assert_same(Rastrigin, DevicePotential::Rastrigin, s, 3.0f64);
        assert_same(quadratic, device_quadratic.clone(), s, 2.0f64);
        assert_same(DoubleWell, DevicePotential::DoubleWell, s, 2.0f64);
        assert_same(StyblinskiTang, DevicePotential::StyblinskiTang, s, 0.5f64);
    }
}
