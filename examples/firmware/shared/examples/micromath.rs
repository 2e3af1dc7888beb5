//! What the `micromath` feature costs and buys, in numbers (docs/EMBEDDED.md).
//!
//! Run it twice and compare:
//!
//! ```sh
//! cargo run --release -p hrla-embedded --example micromath
//! cargo run --release -p hrla-embedded --example micromath --features micromath
//! ```
//!
//! Sections 1 and 2 call micromath and libm directly, so they print the same
//! in both builds. Sections 3 to 6 go through the kernel, whose f32 `fast_*`
//! functions the feature switches: the exp and ln of the normal sampler's
//! rare branches, and the sine and cosine of Levy and of Rastrigin's fallback
//! for `|x| >= 2^20` (Rastrigin's fused polynomial sine is the same in both
//! builds, so its row of section 3, hash included, must not change). (That
//! the OU step's coefficients and Rastrigin's f32 bits are untouched is a
//! test: `tests/embedded_run.rs`.)

use std::hint::black_box;
use std::time::Instant;

use hrla::{Float, Levy, Potential, Rastrigin, StandardNormal};
use hrla_embedded::{N, SEED, STEPS};
use micromath::F32Ext;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// Max absolute and relative error of `approx` against `exact` over `xs`.
struct Err {
    abs: f64,
    rel: f64,
    at: f32,
}

fn errors(
    xs: impl Iterator<Item = f32>,
    approx: impl Fn(f32) -> f32,
    exact: impl Fn(f64) -> f64,
) -> Err {
    let mut e = Err {
        abs: 0.0,
        rel: 0.0,
        at: 0.0,
    };
    for x in xs {
        let want = exact(f64::from(x));
        let got = f64::from(approx(x));
        let abs = (got - want).abs();
        if abs > e.abs {
            e.abs = abs;
            e.at = x;
        }
        if want != 0.0 {
            e.rel = e.rel.max(abs / want.abs());
        }
    }
    e
}

fn grid(lo: f32, hi: f32, n: usize) -> impl Iterator<Item = f32> {
    (0..=n).map(move |i| lo + (hi - lo) * (i as f32 / n as f32))
}

/// Every 31st f32 in [lo, hi) by bit pattern: all binades, dense.
fn bits_range(lo: f32, hi: f32) -> impl Iterator<Item = f32> {
    (lo.to_bits()..hi.to_bits()).step_by(31).map(f32::from_bits)
}

fn line(name: &str, mm: Err, lm: Err) {
    println!(
        "| {name} | {:.2e} | {:.2e} | {:.3e} | {:.2e} | {:.2e} |",
        mm.abs, mm.rel, mm.at, lm.abs, lm.rel
    );
}

fn approximations() {
    println!("## 1. micromath against libm (reference: f64 libm of the same f32 input)\n");
    println!(
        "| function, range | micromath max abs | micromath max rel | at | libm f32 max abs | libm f32 max rel |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    // Levy's arguments πw, πw + 1 and 2πw, w = 1 + (x - 1)/4, stay within
    // [-20π, 20π] for x in [-40, 40] (Rastrigin's sine no longer calls
    // micromath below |x| = 2^20).
    let t = 2.0 * std::f32::consts::PI * 10.0;
    line(
        "sin on [-20π, 20π] (Levy)",
        errors(grid(-t, t, 2_000_000), |x| F32Ext::sin_cos(x).0, libm::sin),
        errors(grid(-t, t, 2_000_000), libm::sinf, libm::sin),
    );
    line(
        "cos, same range",
        errors(grid(-t, t, 2_000_000), |x| F32Ext::sin_cos(x).1, libm::cos),
        errors(grid(-t, t, 2_000_000), libm::cosf, libm::cos),
    );
    // The Ziggurat's wedge test takes exp(-x^2/2) for |x| < R = 3.6541...
    let r2 = -0.5 * 3.654_152_9_f32 * 3.654_152_9;
    line(
        "exp on [-R²/2, 0] (Ziggurat wedge)",
        errors(grid(r2, 0.0, 2_000_000), F32Ext::exp, libm::exp),
        errors(grid(r2, 0.0, 2_000_000), libm::expf, libm::exp),
    );
    // The tail takes ln of uniforms in (0, 1): f32 uniforms are >= 2^-24.
    // Relative error is meaningless near 1, where ln vanishes.
    let lo = 2f32.powi(-24);
    line(
        "ln on [2^-24, 1/2) (Ziggurat tail)",
        errors(bits_range(lo, 0.5), F32Ext::ln, libm::log),
        errors(bits_range(lo, 0.5), libm::logf, libm::log),
    );
    line(
        "ln on [1/2, 1)",
        errors(bits_range(0.5, 1.0), F32Ext::ln, libm::log),
        errors(bits_range(0.5, 1.0), libm::logf, libm::log),
    );
    println!();
}

/// Section 2: how far the Ziggurat's output law moves when its wedge test
/// uses an approximate exp. A draw of layer i at abscissa x in the wedge is
/// accepted with probability (g(x) - f_{i+1}) / (f_i - f_{i+1}) for
/// g(x) = exp(-x²/2); so the output density below R is proportional to the
/// exp used (clamped to the layer, which only shrinks the change), and to
/// the exact density beyond R. This integrates |p_approx - p| / 2.
fn ziggurat_law() {
    println!("## 2. The normal sampler's law with an approximate exp (total variation)\n");
    let r = 3.654_152_885_361_009_f64;
    let tail = libm::erfc(r / std::f64::consts::SQRT_2) * (std::f64::consts::PI / 2.0).sqrt();
    let n = 2_000_000;
    let dx = 2.0 * r / n as f64;
    let tv = |exp: &dyn Fn(f32) -> f32| {
        let xs = (0..n).map(|i| -r + (i as f64 + 0.5) * dx);
        let (mut za, mut ze) = (tail, tail);
        for x in xs.clone() {
            za += f64::from(exp((-0.5 * x * x) as f32)) * dx;
            ze += libm::exp(-0.5 * x * x) * dx;
        }
        let mut d = 0.0;
        for x in xs {
            let a = f64::from(exp((-0.5 * x * x) as f32)) / za;
            let e = libm::exp(-0.5 * x * x) / ze;
            d += (a - e).abs() * dx;
        }
        0.5 * d + 0.5 * tail * (1.0 / za - 1.0 / ze).abs()
    };
    println!("| exp in the wedge test | total variation to N(0, 1) |");
    println!("|---|---:|");
    println!("| micromath | {:.2e} |", tv(&F32Ext::exp));
    println!("| libm expf | {:.2e} |", tv(&libm::expf));
    println!();
}

fn build() -> &'static str {
    if cfg!(feature = "micromath") {
        "with micromath"
    } else {
        "libm only"
    }
}

/// Section 3: the kernel's 2-D f32 Rastrigin and Levy against f64, the
/// first coordinate on a grid of [-6, 6], the second at its minimiser plus
/// 0.25; with an FNV-1a hash of the f32 bits of every value and gradient,
/// so that two builds can be compared at a glance.
fn potentials() {
    println!(
        "## 3. Potentials in f32 through the kernel ({}), against f64\n",
        build()
    );
    println!(
        "| potential | max abs error of U | max abs error of dU/dx_1 | max rel error of U, abs(x_1 - x*) < 0.05 | FNV-1a of the f32 bits |"
    );
    println!("|---|---:|---:|---:|---:|");
    fn one<P: Potential<f32, 2> + Potential<f64, 2>>(name: &str, p: P, min: f32) {
        let (mut du, mut dg, mut du_near) = (0f64, 0f64, 0f64);
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let mut feed = |v: f32| {
            for b in v.to_bits().to_le_bytes() {
                hash = (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for x in grid(-6.0, 6.0, 1_000_000) {
            let mut g = [0f32; 2];
            let u = p.value_and_gradient(&[x, min + 0.25], &mut g);
            let mut h = [0f64; 2];
            let v = p.value_and_gradient(&[f64::from(x), f64::from(min) + 0.25], &mut h);
            feed(u);
            feed(g[0]);
            feed(g[1]);
            du = du.max((f64::from(u) - v).abs());
            dg = dg.max((f64::from(g[0]) - h[0]).abs());
            if (x - min).abs() < 0.05 {
                // Near the minimum: the value's error relative to U itself.
                let u0 = Potential::<f32, 2>::value(&p, &[x, min]);
                let v0 = Potential::<f64, 2>::value(&p, &[f64::from(x), f64::from(min)]);
                if v0 > 0.0 {
                    du_near = du_near.max((f64::from(u0) - v0).abs() / v0);
                }
            }
        }
        println!("| {name} | {du:.2e} | {dg:.2e} | {du_near:.2e} | {hash:016x} |");
    }
    one("Rastrigin", Rastrigin, 0.0);
    one("Levy", Levy, 1.0);
    println!();
}

/// Section 4: 10^7 f32 normals from the kernel.
fn normals() {
    println!("## 4. 10^7 f32 normals from the kernel ({})\n", build());
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let n = 10_000_000usize;
    let (mut m1, mut m2, mut m4, mut beyond) = (0f64, 0f64, 0f64, 0usize);
    // 80 bins of width 0.1 on [-4, 4] plus two tails, for a chi-square.
    let mut bins = [0usize; 82];
    for _ in 0..n {
        let z = f64::from(f32::standard_normal(&mut rng));
        m1 += z;
        m2 += z * z;
        m4 += z * z * z * z;
        if z.abs() > 3.0 {
            beyond += 1;
        }
        let b = if z < -4.0 {
            0
        } else if z >= 4.0 {
            81
        } else {
            1 + (((z + 4.0) * 10.0) as usize).min(79)
        };
        bins[b] += 1;
    }
    let nf = n as f64;
    let cdf = |x: f64| 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
    let mut chi2 = 0.0;
    let mut worst = (0.0, 0.0, 0.0);
    for (b, &count) in bins.iter().enumerate() {
        let (lo, hi) = match b {
            0 => (f64::NEG_INFINITY, -4.0),
            81 => (4.0, f64::INFINITY),
            _ => (-4.0 + 0.1 * (b - 1) as f64, -4.0 + 0.1 * b as f64),
        };
        let p = if lo.is_infinite() {
            cdf(hi)
        } else if hi.is_infinite() {
            1.0 - cdf(lo)
        } else {
            cdf(hi) - cdf(lo)
        };
        let e = p * nf;
        let term = (count as f64 - e).powi(2) / e;
        chi2 += term;
        if term > worst.0 {
            worst = (term, lo, count as f64 / e - 1.0);
        }
    }
    let p3 = 2.0 * (1.0 - cdf(3.0));
    println!("| statistic | value | expected | standard error |");
    println!("|---|---:|---:|---:|");
    println!("| mean | {:.5} | 0 | {:.5} |", m1 / nf, (1.0 / nf).sqrt());
    println!(
        "| variance | {:.5} | 1 | {:.5} |",
        m2 / nf,
        (2.0 / nf).sqrt()
    );
    println!("| E z^4 | {:.4} | 3 | {:.4} |", m4 / nf, (96.0 / nf).sqrt());
    println!(
        "| P(abs(z) > 3) | {:.6} | {:.6} | {:.6} |",
        beyond as f64 / nf,
        p3,
        (p3 * (1.0 - p3) / nf).sqrt()
    );
    println!("| chi-square, 82 bins (81 d.f.; 99.9% quantile 124.8) | {chi2:.1} | 81 | 12.7 |");
    println!(
        "\nLargest chi-square term: {:.1}, the bin starting at {:.1} (observed/expected - 1 = {:+.4}).\n",
        worst.0, worst.1, worst.2
    );
}

/// Section 5: Algorithm 1 (the firmware's setting) over many seeds; the
/// best point's value is re-evaluated in f64, so an approximate U cannot
/// flatter it.
fn seeds() {
    println!(
        "## 5. Algorithm 1, 2-D Rastrigin, N = {N}, {STEPS} steps, seeds 0..64 ({})\n",
        build()
    );
    println!("| type | max over seeds of U(best) | median | seeds with U(best) < 0.01 |");
    println!("|---|---:|---:|---:|");
    fn one<F: Float>() {
        let mut vals: Vec<f64> = (0..64)
            .map(|seed| {
                let mut chains = hrla_embedded::chains::<F, hrla_embedded::Xoshiro128PlusPlus>();
                let (opt, _) =
                    hrla_embedded::run::<F, _>(&mut chains, seed, STEPS).expect("valid setting");
                let x: [f64; 2] = core::array::from_fn(|i| opt.best().x[i].to_f64());
                Rastrigin.value(&x)
            })
            .collect();
        vals.sort_by(f64::total_cmp);
        let good = vals.iter().filter(|&&v| v < 0.01).count();
        let name = if core::mem::size_of::<F>() == 4 {
            "f32"
        } else {
            "f64"
        };
        println!(
            "| {name} | {:.2e} | {:.2e} | {good}/64 |",
            vals[63], vals[32]
        );
    }
    one::<f32>();
    one::<f64>();
    println!();
}

/// Section 6: host speed of the firmware's computation, median of 101 runs.
fn speed() {
    println!(
        "## 6. Host speed of the firmware's run ({}), median of 101\n",
        build()
    );
    println!("| type | median ms per run | ns per chain-step |");
    println!("|---|---:|---:|");
    fn one<F: Float>() {
        let mut times: Vec<f64> = (0..101)
            .map(|_| {
                let mut chains = hrla_embedded::chains::<F, hrla_embedded::Xoshiro128PlusPlus>();
                let t = Instant::now();
                let r = hrla_embedded::run::<F, _>(&mut chains, black_box(SEED), black_box(STEPS));
                black_box(r.expect("valid setting"));
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let med = times[50];
        let name = if core::mem::size_of::<F>() == 4 {
            "f32"
        } else {
            "f64"
        };
        let per = med * 1e9 / (STEPS as f64 * N as f64);
        println!("| {name} | {:.3} | {per:.1} |", med * 1e3);
    }
    one::<f32>();
    one::<f64>();
    println!();
}

fn main() {
    approximations();
    ziggurat_law();
    potentials();
    normals();
    seeds();
    speed();
}
