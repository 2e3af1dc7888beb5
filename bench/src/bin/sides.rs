//! `Auto` in a box whose sides differ by orders of magnitude: 6-D
//! Rastrigin (`A = 10`) with each coordinate on its own side's scale,
//! `U(x) = R(z)`, `z_i = x_i / s_i - c_i` in the box `[-5.12 s_i, 5.12
//! s_i]`, its minimum 0 at `x_i = s_i c_i`. Runs solved (`U < 1e-6`) of
//! `--seeds` (default 20) at each budget, for sides all 1 (`s_i = 1`), all
//! `10^3` (the same box, a thousand times larger), spanning `10^2` and
//! spanning `10^6`.
//!
//! ```text
//! cargo run --release -p hrla-bench --bin sides -- [--seeds 20] [--budgets 10000,125000]
//! ```

use std::ops::ControlFlow;

use hrla::rand_core::SeedableRng;
use hrla::{Auto, AutoStorage, Bounds, FnPotential, Potential, Problem, Rastrigin};
use rand_xoshiro::Xoshiro256PlusPlus;

const CENTRE: [f64; 6] = [0.7, -1.3, 2.1, -0.4, 1.9, 0.2];

/// The best value of one run.
fn run(side: [f64; 6], budget: u64, seed: u64) -> f64 {
    let (d, m) = (6, 8);
    let p = FnPotential::slices(move |x: &[f64], g: &mut [f64]| {
        let z: [f64; 6] = std::array::from_fn(|i| x[i] / side[i] - CENTRE[i]);
        let mut gz = [0.0; 6];
        let v = Rastrigin.value_and_gradient(&z, &mut gz);
        for i in 0..6 {
            g[i] = gz[i] / side[i];
        }
        v
    });
    let bounds = Bounds::new(
        side.map(|s| -5.12 * s).to_vec(),
        side.map(|s| 5.12 * s).to_vec(),
    )
    .expect("a valid box");
    let n = Auto::<f64>::chains_for(budget);
    let mut floats = vec![0.0; AutoStorage::<f64, Xoshiro256PlusPlus>::floats(n, d, m)];
    let mut diverged = vec![false; n];
    let mut rngs: Vec<_> = (0..n)
        .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
        .collect();
    let mut storage =
        AutoStorage::new(d, m, &mut floats, &mut diverged, &mut rngs).expect("valid storage");
    Auto::default()
        .minimize_with(
            &Problem::new(&p, &bounds, budget).seed(seed),
            &mut storage,
            |_| ControlFlow::Continue(()),
        )
        .expect("a run")
        .value
}

fn list(args: &[String], flag: &str, default: &str) -> Vec<u64> {
    let value = args
        .windows(2)
        .find(|w| w[0] == flag)
        .map_or(default, |w| w[1].as_str());
    value
        .split(',')
        .map(|v| v.parse().expect("a number"))
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seeds = list(&args, "--seeds", "20")[0];
    let budgets = list(&args, "--budgets", "10000,125000");
    let boxes: [(&str, [f64; 6]); 4] = [
        ("unit", [1.0; 6]),
        ("all 1e3", [1e3; 6]),
        ("1e2", [0.1, 1.0, 10.0, 0.3, 3.0, 9.9]),
        ("1e6", [1e-3, 1.0, 1e3, 0.1, 10.0, 999.0]),
    ];
    println!("| sides | B | solved | median best U |");
    println!("|---|---:|---:|---:|");
    for (name, side) in boxes {
        for &budget in &budgets {
            let mut best: Vec<f64> = (0..seeds).map(|s| run(side, budget, s)).collect();
            let solved = best.iter().filter(|&&v| v < 1e-6).count();
            best.sort_by(f64::total_cmp);
            println!(
                "| {name} | {budget} | {solved}/{seeds} | {:.3e} |",
                best[best.len() / 2]
            );
        }
    }
}
