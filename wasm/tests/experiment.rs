//! The page's d-dimensional comparison ([`hrla_wasm::Experiment`]) is the
//! kernel's run and the reproduction tool's statistic: its record equals,
//! bit for bit, the same runs built on the kernel's optimiser directly (no
//! run-time layer), and with the tool's seed its hit counts are the ones
//! `repro e2` wrote to `docs/repro/e2/curves.csv`.

use hrla::rand_core::{Rng, SeedableRng};
use hrla::{
    AnySampler, AnySchedule, Builder, Constant, FlatChains, FromFn, Rastrigin, StandardNormal,
    splitmix64,
};
use hrla_wasm::{Experiment, ExperimentSettings, ROW, SAMPLERS};
use rand_xoshiro::Xoshiro256PlusPlus as Generator;

type Chains = FlatChains<f64, Generator, Vec<f64>, Vec<u64>, Vec<bool>, Vec<Generator>>;

/// The record of `s` computed over the kernel's optimiser, as the
/// reproduction tool's `KernelRun` builds a run.
fn direct_record(s: &ExperimentSettings, steps: u64) -> Vec<f64> {
    let (m, n, d) = (s.runs, s.chains, s.dim);
    let mut record = vec![0.0; (steps as usize + 1) * ROW];
    let k_sampler = SAMPLERS.len();
    for (si, &kind) in SAMPLERS.iter().enumerate() {
        let mut running = vec![f64::INFINITY; m];
        let mut opts: Vec<_> = (0..m)
            .map(|i| {
                let chains = Chains::new(
                    d,
                    vec![0.0; Chains::floats(n, d)],
                    vec![0; n],
                    vec![false; n],
                    vec![Generator::seed_from_u64(0); n],
                )
                .unwrap();
                let std_dev = 10f64.sqrt();
                let start = FromFn(move |_c: usize, rng: &mut dyn Rng, x: &mut [f64]| {
                    for xi in x.iter_mut() {
                        *xi = 3.0 + std_dev * f64::standard_normal(rng);
                    }
                });
                Builder::new(
                    Rastrigin,
                    AnySampler::paper(kind, s.h).unwrap(),
                    AnySchedule::Constant(Constant::new(s.a).unwrap()),
                    start,
                )
                .seed(s.seed ^ splitmix64(i as u64))
                .build(chains)
                .unwrap()
            })
            .collect();
        for k in 0..=steps {
            let mut hits = 0.0;
            for (i, opt) in opts.iter_mut().enumerate() {
                if k > 0 {
                    match opt.step() {
                        Ok(_) | Err(hrla::Error::AllDiverged { .. }) => {}
                        Err(e) => panic!("{e}"),
                    }
                }
                let now = opt.current_best().map_or(f64::INFINITY, |(_, v)| v);
                if now <= s.eps {
                    hits += 1.0;
                }
                if k > 0 {
                    running[i] = running[i].min(now);
                }
            }
            let row = k as usize * ROW;
            record[row + si] = hits;
            record[row + k_sampler + si] = if k == 0 {
                f64::NAN
            } else {
                running.iter().sum::<f64>() / m as f64
            };
        }
    }
    record
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn the_record_is_the_kernels_runs_bit_for_bit() {
    for (dim, runs, chains, a, eps) in [
        (7, 3, 4, 2.0, 40.0),
        (10, 4, 5, 4.0, 60.0),
        (1, 2, 3, 1.0, 2.0),
    ] {
        let s = ExperimentSettings {
            dim,
            runs,
            chains,
            a,
            eps,
            steps: 400,
            seed: 99,
            ..Default::default()
        };
        let mut e = Experiment::new(s).unwrap();
        // Driven in uneven chunks, as the page's frames drive it.
        for chunk in [1, 7, 92, 300] {
            e.step_n(chunk).unwrap();
        }
        let direct = direct_record(&s, 400);
        assert_eq!(bits(e.record()), bits(&direct), "d = {dim}");
        // Some hits, not all, so that the counts are tested.
        let hits: f64 = e.record().chunks(ROW).map(|r| r[0] + r[1] + r[2]).sum();
        assert!(hits > 0.0, "d = {dim}: no hits");
    }
}

/// The hit counts `repro e2` recorded for `sampler` at `(a, eps)`, by `k`.
fn repro_hits(sampler: &str, a: &str, eps: &str) -> Vec<(u64, f64)> {
    let csv = include_str!("../../docs/repro/e2/curves.csv");
    csv.lines()
        .filter_map(|line| {
            // protocol,sampler,d,h,N,K,schedule,a,"start, with a comma",eps,k,hits,M,probability
            let f: Vec<&str> = line.split(',').collect();
            (f.len() == 15 && f[1] == sampler && f[2] == "10" && f[7] == a && f[10] == eps)
                .then(|| (f[11].parse().unwrap(), f[12].parse().unwrap()))
        })
        .collect()
}

#[test]
fn the_tools_seed_gives_the_tools_e2_counts() {
    // The paper's E2 panel (a = 4, eps = 2) with the tool's base seed, the
    // first 2 800 of its 14 000 iterates: the three curves part there
    // (ULA leads, then HRLA and OLA overtake it).
    let s = ExperimentSettings::default();
    assert_eq!(
        (s.dim, s.runs, s.chains, s.a, s.h, s.eps, s.steps, s.seed),
        (10, 100, 10, 4.0, 0.01, 2.0, 14_000, 2025)
    );
    let upto = 2_800;
    let mut e = Experiment::new(s).unwrap();
    e.step_n(upto).unwrap();
    for (si, name) in ["HRLA", "ULA", "OLA"].into_iter().enumerate() {
        let want = repro_hits(name, "4", "2");
        assert_eq!(want.len(), 501, "{name}: the tool's curve");
        let mut compared = 0;
        let mut nonzero = 0;
        for &(k, hits) in want.iter().filter(|(k, _)| *k <= upto) {
            assert_eq!(e.record()[k as usize * ROW + si], hits, "{name} at k = {k}");
            compared += 1;
            nonzero += usize::from(hits > 0.0);
        }
        assert_eq!(compared, 101);
        assert!(nonzero > 5, "{name}: {nonzero} nonzero counts");
    }
}
