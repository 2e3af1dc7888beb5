//! The quality benchmark's problems, the same as `bench/quality/functions.py`
//! (the peers' side): analytic value and gradient, known minimum, a box
//! from which starts are drawn uniformly.

use hrla::{Ackley, FnPotential, Levy, Potential, Rastrigin, StyblinskiTang};

/// What [`for_each`] hands each problem to: name, potential, `U*`, box.
pub type Visit<'a, const D: usize> = dyn FnMut(&str, &dyn Potential<f64, D>, f64, (f64, f64)) + 'a;

/// Rastrigin with `A = 10`: `10 D + sum (x^2 - 10 cos 2πx)`.
pub fn rastrigin10<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let tau = std::f64::consts::TAU;
    let mut u = 10.0 * D as f64;
    for (gi, &xi) in g.iter_mut().zip(x) {
        u += xi * xi - 10.0 * (tau * xi).cos();
        *gi = 2.0 * xi + 10.0 * tau * (tau * xi).sin();
    }
    u
}

/// Rosenbrock: `sum 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2`.
pub fn rosenbrock<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    g.fill(0.0);
    let mut u = 0.0;
    for i in 0..D.saturating_sub(1) {
        let a = x[i + 1] - x[i] * x[i];
        let b = 1.0 - x[i];
        u += 100.0 * a * a + b * b;
        g[i] += -400.0 * x[i] * a - 2.0 * b;
        g[i + 1] += 200.0 * a;
    }
    u
}

/// Griewank: `1 + sum x^2 / 4000 - prod cos(x_i / sqrt(i))`.
pub fn griewank<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let c: Vec<f64> = (0..D)
        .map(|i| (x[i] / ((i + 1) as f64).sqrt()).cos())
        .collect();
    let mut prefix = vec![1.0; D + 1];
    for i in 0..D {
        prefix[i + 1] = prefix[i] * c[i];
    }
    let mut suffix = 1.0;
    let mut u = 1.0 - prefix[D];
    for i in (0..D).rev() {
        let r = ((i + 1) as f64).sqrt();
        let others = prefix[i] * suffix;
        g[i] = x[i] / 2000.0 + others * (x[i] / r).sin() / r;
        suffix *= c[i];
        u += x[i] * x[i] / 4000.0;
    }
    u
}

/// Zakharov: `s1 + s2^2 + s2^4`, `s1 = sum x^2`, `s2 = sum i x_i / 2`.
pub fn zakharov<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let s1: f64 = x.iter().map(|v| v * v).sum();
    let s2: f64 = x
        .iter()
        .enumerate()
        .map(|(i, v)| 0.5 * (i + 1) as f64 * v)
        .sum();
    let d = 2.0 * s2 + 4.0 * s2 * s2 * s2;
    for (i, (gi, &xi)) in g.iter_mut().zip(x).enumerate() {
        *gi = 2.0 * xi + d * 0.5 * (i + 1) as f64;
    }
    s1 + s2 * s2 + s2 * s2 * s2 * s2
}

/// The Lennard-Jones cluster of 7 atoms in 3-D (coordinates `x[3i..3i+3]`),
/// `sum_{i<j} 4 (r^-12 - r^-6)`; `U* = -16.505384168012217`, the pentagonal
/// bipyramid refined by Newton's method (`bench/quality/functions.py`),
/// which Wales and Doye (1997) give as -16.505384.
pub fn lj7(x: &[f64; 21], g: &mut [f64; 21]) -> f64 {
    g.fill(0.0);
    let mut u = 0.0;
    for i in 0..7 {
        for j in i + 1..7 {
            let d = [
                x[3 * i] - x[3 * j],
                x[3 * i + 1] - x[3 * j + 1],
                x[3 * i + 2] - x[3 * j + 2],
            ];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let ir6 = 1.0 / (r2 * r2 * r2);
            u += 4.0 * (ir6 * ir6 - ir6);
            // dU/dr2 = 4 (-6 r^-14 + 3 r^-8)
            let du = 4.0 * (-6.0 * ir6 * ir6 + 3.0 * ir6) / r2;
            for k in 0..3 {
                g[3 * i + k] += 2.0 * du * d[k];
                g[3 * j + k] -= 2.0 * du * d[k];
            }
        }
    }
    u
}

/// Styblinski–Tang's minimum per coordinate.
const STYBLINSKI_TANG: f64 = -39.166_165_703_771_42;

/// Runs `f` on every problem of dimension `D` whose name `keep` accepts.
pub fn for_each<const D: usize>(keep: &dyn Fn(&str) -> bool, f: &mut Visit<'_, D>) {
    let d = D as f64;
    macro_rules! run {
        ($name:expr, $p:expr, $min:expr, $b:expr) => {
            if keep($name) {
                f($name, &$p, $min, $b);
            }
        };
    }
    run!("rastrigin_paper", Rastrigin, 0.0, (-5.12, 5.12));
    run!(
        "rastrigin",
        FnPotential::new(rastrigin10::<D>),
        0.0,
        (-5.12, 5.12)
    );
    run!("ackley", Ackley, 0.0, (-32.768, 32.768));
    run!("levy", Levy, 0.0, (-10.0, 10.0));
    run!(
        "rosenbrock",
        FnPotential::new(rosenbrock::<D>),
        0.0,
        (-5.0, 10.0)
    );
    run!(
        "styblinski_tang",
        StyblinskiTang,
        STYBLINSKI_TANG * d,
        (-5.0, 5.0)
    );
    run!(
        "griewank",
        FnPotential::new(griewank::<D>),
        0.0,
        (-600.0, 600.0)
    );
    run!(
        "zakharov",
        FnPotential::new(zakharov::<D>),
        0.0,
        (-5.0, 10.0)
    );
}

/// The problems of dimension 21: the Lennard-Jones cluster of 7 atoms.
pub fn for_each_21(keep: &dyn Fn(&str) -> bool, f: &mut Visit<'_, 21>) {
    if keep("lj7") {
        f(
            "lj7",
            &FnPotential::new(lj7),
            -16.505_384_168_012_217,
            (-1.5, 1.5),
        );
    }
}
