//! The law of the device's chains, whatever the device's arithmetic: on a
//! quadratic potential every sampler's step is linear in the state, so the
//! law after K steps from a Gaussian start is Gaussian with moments that
//! the host computes exactly from the kernel's one-step moments; and on
//! Rastrigin the device's values after K steps pass a two-sample test
//! against the CPU kernel's, with other seeds. Both in the IEEE arithmetic
//! and in the driver's fused one (on a GPU that fuses, only the law is
//! shared with the CPU, not the bits).

mod common;

use hrla::{AnySampler, Builder, Chain, Gaussian, Kernel, Rastrigin, Sampler, SamplerKind, Stop};
use hrla_gpu::{Arithmetic, DevicePotential, EnsembleBuilder, Precision, Start};

const D: usize = 4;
const STIFFNESS: f64 = 2.0;
const CENTRE: f64 = 0.5;
const A: f64 = 3.0;

/// A 2x2 symmetric matrix `[[xx, xy], [xy, yy]]` and a mean `(x, y)`: the
/// law of one coordinate's `(x, y)`.
#[derive(Clone, Copy, Debug)]
struct Law {
    mx: f64,
    my: f64,
    xx: f64,
    xy: f64,
    yy: f64,
}

/// The law after `steps` steps of one coordinate, from `x_0 ~ N(m0, s0^2)`,
/// `y_0 = 0`, by the exact recursion `s' = M s + c + noise`, with `M`, `c`
/// and the noise's covariance read from the kernel's moments (f64).
fn exact_law<K: Kernel<f64>>(kernel: &K, m0: f64, s0: f64, steps: u64) -> Law {
    let (k, m) = (STIFFNESS, CENTRE);
    // The mean is affine in (x, y, g), g = k (x - m).
    let at = |x: f64, y: f64| kernel.moments(x, y, k * (x - m));
    let base = at(0.0, 0.0);
    let dx = at(1.0, 0.0);
    let dy = at(0.0, 1.0);
    let mat = [
        [dx.mean_x - base.mean_x, dy.mean_x - base.mean_x],
        [dx.mean_y - base.mean_y, dy.mean_y - base.mean_y],
    ];
    let mut law = Law {
        mx: m0,
        my: 0.0,
        xx: s0 * s0,
        xy: 0.0,
        yy: 0.0,
    };
    for _ in 0..steps {
        let (a, b, c, d) = (mat[0][0], mat[0][1], mat[1][0], mat[1][1]);
        law = Law {
            mx: a * law.mx + b * law.my + base.mean_x,
            my: c * law.mx + d * law.my + base.mean_y,
            xx: a * a * law.xx + 2.0 * a * b * law.xy + b * b * law.yy + base.var_x,
            xy: a * c * law.xx + (a * d + b * c) * law.xy + b * d * law.yy + base.cov_xy,
            yy: c * c * law.xx + 2.0 * c * d * law.xy + d * d * law.yy + base.var_y,
        };
    }
    law
}

fn moments_match(kind: SamplerKind, arithmetic: Arithmetic, precision: Precision, seed: u64) {
    let (m0, s0, steps) = (3.0, 10f64.sqrt(), 300);
    let chains = 1 << 15;
    let sampler = AnySampler::paper(kind, 0.05).unwrap();
    let mut ensemble = EnsembleBuilder::new(
        DevicePotential::quadratic(STIFFNESS, vec![CENTRE; D]).unwrap(),
        sampler,
        A,
        Start::gaussian(vec![m0; D], s0).unwrap(),
    )
    .chains(chains)
    .seed(seed)
    .arithmetic(arithmetic)
    .precision(precision)
    .build(common::gpu())
    .unwrap();
    ensemble.run(steps).unwrap();
    let law = exact_law(&sampler.at(A).unwrap(), m0, s0, steps);
    let chains = ensemble.snapshot().unwrap();
    // Coordinates are independent with the same law: pool them.
    let xs: Vec<f64> = chains.iter().flat_map(|c| c.x.iter().copied()).collect();
    let ys: Vec<f64> = chains.iter().flat_map(|c| c.y.iter().copied()).collect();
    let n = xs.len() as f64;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
    let (mx, my) = (mean(&xs), mean(&ys));
    let var = |v: &[f64], m: f64| v.iter().map(|a| (a - m) * (a - m)).sum::<f64>() / (n - 1.0);
    let (vx, vy) = (var(&xs, mx), var(&ys, my));
    // Standard errors of a Gaussian sample: sigma / sqrt(n) for the mean,
    // sigma^2 sqrt(2 / (n - 1)) for the variance. Five of them: a false
    // alarm once in 1.7 million comparisons.
    let z = 5.0;
    let check = |what: &str, got: f64, want: f64, se: f64| {
        assert!(
            (got - want).abs() <= z * se,
            "{kind} {arithmetic:?} {precision:?}: {what} = {got}, exact {want}, {:.1} standard errors",
            (got - want) / se
        );
    };
    check("mean of x", mx, law.mx, (law.xx / n).sqrt());
    check(
        "variance of x",
        vx,
        law.xx,
        law.xx * (2.0 / (n - 1.0)).sqrt(),
    );
    if kind != SamplerKind::Ola {
        check("mean of y", my, law.my, (law.yy / n).sqrt());
        check(
            "variance of y",
            vy,
            law.yy,
            law.yy * (2.0 / (n - 1.0)).sqrt(),
        );
    }
}

#[test]
fn quadratic_moments_match_the_closed_form() {
    let mut precisions = vec![Precision::F32];
    if common::gpu().supports_f64() {
        precisions.push(Precision::F64);
    }
    for (i, kind) in SamplerKind::ALL.into_iter().enumerate() {
        for arithmetic in [Arithmetic::Ieee, Arithmetic::Fused] {
            for &precision in &precisions {
                moments_match(kind, arithmetic, precision, 100 + i as u64);
            }
        }
    }
}

/// The two-sample Kolmogorov–Smirnov distance between two samples.
fn ks(mut a: Vec<f64>, mut b: Vec<f64>) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0f64);
    while i < a.len() && j < b.len() {
        let v = a[i].min(b[j]);
        while i < a.len() && a[i] <= v {
            i += 1;
        }
        while j < b.len() && b[j] <= v {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// The device (f64 coefficients rounded once, either arithmetic) and the
/// CPU kernel (f64) with another seed: the values of 10-D Rastrigin after
/// 300 annealing-free steps of HRLA come from one law.
#[test]
fn rastrigin_values_match_the_cpu_kernel_in_law() {
    const DIM: usize = 10;
    let n = 4096;
    let steps = 300;
    let sampler = hrla::Hrla::paper(0.01).unwrap();
    let mut cpu: Vec<Chain<f64, DIM>> = (0..n).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        sampler,
        4.0,
        Gaussian::new([3.0; DIM], 10f64.sqrt()).unwrap(),
    )
    .seed(1)
    .stop(Stop::new().steps(steps))
    .build(&mut cpu)
    .unwrap();
    opt.run().unwrap();
    let cpu_values: Vec<f64> = cpu.iter().map(|c| c.value()).collect();
    for (arithmetic, seed) in [(Arithmetic::Ieee, 2), (Arithmetic::Fused, 3)] {
        let mut ensemble =
            EnsembleBuilder::new(DevicePotential::Rastrigin, sampler, 4.0, Start::paper(DIM))
                .chains(n)
                .seed(seed)
                .arithmetic(arithmetic)
                .build(common::gpu())
                .unwrap();
        ensemble.run(steps).unwrap();
        let device: Vec<f64> = ensemble
            .snapshot()
            .unwrap()
            .iter()
            .map(|c| c.value)
            .collect();
        // The KS critical value at level 1e-4 for two samples of n:
        // sqrt(-ln(1e-4 / 2) / 2) sqrt(2 / n) (the asymptotic law, accurate
        // at this n).
        let critical = (-(1e-4f64 / 2.0).ln() / 2.0).sqrt() * (2.0 / n as f64).sqrt();
        let d = ks(cpu_values.clone(), device);
        assert!(
            d < critical,
            "{arithmetic:?}: KS distance {d} >= {critical}"
        );
    }
}
