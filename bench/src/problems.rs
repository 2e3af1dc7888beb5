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

/// The Lennard-Jones cluster of `N` atoms in 3-D, `sum_{i<j} 4 (r^-12 - r^-6)`.
pub fn lj<const N: usize, const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    g.fill(0.0);
    let mut u = 0.0;
    for i in 0..N {
        for j in i + 1..N {
            let d = [
                x[3 * i] - x[3 * j],
                x[3 * i + 1] - x[3 * j + 1],
                x[3 * i + 2] - x[3 * j + 2],
            ];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let ir6 = 1.0 / (r2 * r2 * r2);
            u += 4.0 * (ir6 * ir6 - ir6);
            let du = 4.0 * (-6.0 * ir6 * ir6 + 3.0 * ir6) / r2;
            for k in 0..3 {
                g[3 * i + k] += 2.0 * du * d[k];
                g[3 * j + k] -= 2.0 * du * d[k];
            }
        }
    }
    u
}

/// LJ13's minimum, the Mackay icosahedron (Wales and Doye 1997).
pub const LJ13_MINIMUM: f64 = -44.326_801;

/// Plateau and valley, per coordinate: 1 on flat plateaus, narrow Gaussian
/// valleys (width 0.1) at the integers -4..4 down to 0, the one at 3 down
/// to -1; `U* = -D` at `(3, ..., 3)`. Between valleys the gradient is 0
/// to double precision.
pub fn plateau<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let w = 0.1;
    let mut u = D as f64;
    for (gi, &xi) in g.iter_mut().zip(x) {
        *gi = 0.0;
        for k in -4..=4 {
            let depth = if k == 3 { 2.0 } else { 1.0 };
            let z = (xi - f64::from(k)) / w;
            let e = depth * (-0.5 * z * z).exp();
            u -= e;
            *gi += e * z / w;
        }
    }
    u
}

/// Schwefel's deceptive function: `sum 418.98... - x sin sqrt|x|`; the best
/// basin per coordinate (`x = 420.97`) is far from the second best
/// (`x = -302.5`); `U* = 0` to rounding.
pub fn schwefel<const D: usize>(x: &[f64; D], g: &mut [f64; D]) -> f64 {
    let mut u = 0.0;
    for (gi, &xi) in g.iter_mut().zip(x) {
        let s = xi.abs().sqrt();
        let sn = s.sin();
        u += 418.982_887_272_433_74 - xi * sn;
        *gi = -(sn + 0.5 * s * s.cos());
    }
    u
}

/// The two-peak model `sum_k A_k exp(-(t - c_k)^2 / (2 w_k^2))` at `t`.
fn peaks(p: &[f64; 6], t: f64) -> f64 {
    (0..2)
        .map(|k| {
            let z = (t - p[3 * k + 1]) / p[3 * k + 2];
            p[3 * k] * (-0.5 * z * z).exp()
        })
        .sum()
}

/// A least-squares fit of two Gaussian peaks `(A, c, w)` to noiseless data
/// at `t = 0, 1, ..., 100` from `(5, 30, 3)` and `(2, 70, 10)`: parameters
/// on different scales in one box `[0.5, 100]`; `U* = 0`.
pub fn gauss_fit(x: &[f64; 6], g: &mut [f64; 6]) -> f64 {
    const TRUE: [f64; 6] = [5.0, 30.0, 3.0, 2.0, 70.0, 10.0];
    g.fill(0.0);
    let mut u = 0.0;
    for i in 0..=100 {
        let t = f64::from(i);
        let r = peaks(x, t) - peaks(&TRUE, t);
        u += r * r;
        for k in 0..2 {
            let (a, c, w) = (x[3 * k], x[3 * k + 1], x[3 * k + 2]);
            let z = (t - c) / w;
            let e = (-0.5 * z * z).exp();
            g[3 * k] += 2.0 * r * e;
            g[3 * k + 1] += 2.0 * r * a * e * z / w;
            g[3 * k + 2] += 2.0 * r * a * e * z * z / w;
        }
    }
    u
}

/// The committed rotation `Q` of the rotated problems
/// (`bench/quality/rotation10.txt`: numpy's `default_rng(12345)`, QR of a
/// standard normal 10 x 10 matrix), row-major.
pub fn rotation10() -> [[f64; 10]; 10] {
    let mut q = [[0.0; 10]; 10];
    let text = include_str!("../quality/rotation10.txt");
    for (row, line) in q.iter_mut().zip(text.lines()) {
        for (v, s) in row.iter_mut().zip(line.split_whitespace()) {
            *v = s.parse().expect("rotation10.txt holds numbers");
        }
    }
    q
}

/// `U(c + Q (x - c))` with `Q` [`rotation10`] and `c` the minimiser: the
/// problem rotated about its minimum, which stays where it was.
pub struct Rotated<'a, const D: usize> {
    /// The unrotated problem.
    pub inner: &'a dyn Potential<f64, D>,
    /// The centre of the rotation.
    pub centre: [f64; D],
    /// The rotation, row-major (`D x D`).
    pub q: Vec<f64>,
}

impl<const D: usize> Potential<f64, D> for Rotated<'_, D> {
    fn value_and_gradient(&self, x: &[f64; D], g: &mut [f64; D]) -> f64 {
        let mut z = self.centre;
        for (i, zi) in z.iter_mut().enumerate() {
            let row = &self.q[i * D..(i + 1) * D];
            for ((q, xj), cj) in row.iter().zip(x).zip(&self.centre) {
                *zi += q * (xj - cj);
            }
        }
        let mut gz = [0.0; D];
        let u = self.inner.value_and_gradient(&z, &mut gz);
        for (j, gj) in g.iter_mut().enumerate() {
            *gj = (0..D).map(|i| self.q[i * D + j] * gz[i]).sum();
        }
        u
    }
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
    if D != 10 {
        return;
    }
    // The problems run in d = 10 only: each textbook problem rotated about
    // its minimiser, then the plateaus and the deceptive landscape.
    let q: Vec<f64> = rotation10().iter().flatten().copied().collect();
    let mut rotated = |name: &str, inner: &dyn Potential<f64, D>, min: f64, b, centre: f64| {
        let name = format!("rot_{name}");
        if keep(&name) {
            let p = Rotated {
                inner,
                centre: [centre; D],
                q: q.clone(),
            };
            f(&name, &p, min, b);
        }
    };
    rotated("rastrigin_paper", &Rastrigin, 0.0, (-5.12, 5.12), 0.0);
    rotated(
        "rastrigin",
        &FnPotential::new(rastrigin10::<D>),
        0.0,
        (-5.12, 5.12),
        0.0,
    );
    rotated("ackley", &Ackley, 0.0, (-32.768, 32.768), 0.0);
    rotated("levy", &Levy, 0.0, (-10.0, 10.0), 1.0);
    rotated(
        "rosenbrock",
        &FnPotential::new(rosenbrock::<D>),
        0.0,
        (-5.0, 10.0),
        1.0,
    );
    rotated(
        "styblinski_tang",
        &StyblinskiTang,
        STYBLINSKI_TANG * d,
        (-5.0, 5.0),
        -2.903_534_027_771_178,
    );
    rotated(
        "griewank",
        &FnPotential::new(griewank::<D>),
        0.0,
        (-600.0, 600.0),
        0.0,
    );
    rotated(
        "zakharov",
        &FnPotential::new(zakharov::<D>),
        0.0,
        (-5.0, 10.0),
        0.0,
    );
    run!("plateau", FnPotential::new(plateau::<D>), -d, (-5.0, 5.0));
    run!(
        "schwefel",
        FnPotential::new(schwefel::<D>),
        0.0,
        (-500.0, 500.0)
    );
}

/// The problems of dimension 6: the two-peak least-squares fit.
pub fn for_each_6(keep: &dyn Fn(&str) -> bool, f: &mut Visit<'_, 6>) {
    if keep("gauss_fit") {
        f("gauss_fit", &FnPotential::new(gauss_fit), 0.0, (0.5, 100.0));
    }
}

/// The problems of dimension 39: the Lennard-Jones cluster of 13 atoms.
pub fn for_each_39(keep: &dyn Fn(&str) -> bool, f: &mut Visit<'_, 39>) {
    if keep("lj13") {
        f(
            "lj13",
            &FnPotential::new(lj::<13, 39>),
            LJ13_MINIMUM,
            (-2.0, 2.0),
        );
    }
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
