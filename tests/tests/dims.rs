//! Dimension at compile time or at run time: a run over `Chain<F, 17>`s
//! and over flat storage of dimension 17 gives the same bits
//! (positions, velocities, values, bests, evaluations, polish), for every
//! sampler, with and without a box; a box per coordinate keeps the uniform
//! law; the batch seam is called once per step.

use std::cell::Cell;
use std::ops::ControlFlow;

use hrla::{
    AnySampler, Auto, AutoStorage, BatchPotential, Bounds, Builder, Chain, Error, FlatChains,
    FlatSlices, FnPotential, Gaussian, Interval, Lbfgs, LbfgsIn, PolishSettings, Potential,
    Problem, Rastrigin, SamplerKind, SlicePotential, Stop, Unbounded,
};
use hrla::{Domain, Float};
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::{Xoshiro128PlusPlus, Xoshiro256PlusPlus};

const D: usize = 17;
/// 10 chains: two lockstep groups of four and two chains alone.
const N: usize = 10;

/// Rastrigin, infeasible (NaN) beyond `x_0 > 1`, past the bottom of a well: some initial points are
/// redrawn and some chains diverge along the way.
#[derive(Clone, Copy)]
struct Cliff;

impl<F: Float> SlicePotential<F> for Cliff {
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        let u = SlicePotential::value_and_gradient(&Rastrigin, x, grad);
        if x[0] > F::ONE {
            F::from_f64(f64::NAN)
        } else {
            u
        }
    }
}

impl<F: Float, const D: usize> Potential<F, D> for Cliff {
    fn value_and_gradient(&self, x: &[F; D], grad: &mut [F; D]) -> F {
        SlicePotential::value_and_gradient(self, x, grad)
    }
}

/// Everything a run leaves behind, as bits.
#[derive(Debug, PartialEq)]
struct Trace {
    x: Vec<u64>,
    y: Vec<u64>,
    grad: Vec<u64>,
    value: Vec<u64>,
    best_x: Vec<u64>,
    best_value: Vec<u64>,
    best_iteration: Vec<u64>,
    diverged: Vec<bool>,
    evaluations: u64,
    best_chain: usize,
    report: String,
    polished: String,
}

fn bits<F: Float>(v: &[F]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits_u64()).collect()
}

fn sides<F: Float>() -> ([F; D], [F; D]) {
    // Sides from 0.5 to 8.5 wide, around 0 and shifted.
    let lo = core::array::from_fn(|i| F::from_f64(-4.0 + 0.25 * i as f64));
    let hi = core::array::from_fn(|i| F::from_f64(-3.5 + 0.75 * i as f64));
    (lo, hi)
}

/// A run over `Chain<F, D, R>`s.
fn with_chains<F, P, B, R>(kind: SamplerKind, potential: P, domain: B) -> Trace
where
    F: Float,
    P: Potential<F, D> + SlicePotential<F>,
    B: Domain<F> + Copy,
    R: rand_xoshiro::rand_core::Rng + SeedableRng + Clone + 'static,
{
    let mut chains: Vec<Chain<F, D, R>> = (0..N).map(|_| Chain::default()).collect();
    let start = Gaussian::new([F::from_f64(1.0); D], F::from_f64(2.0)).unwrap();
    let sampler = AnySampler::paper(kind, F::from_f64(0.01)).unwrap();
    let mut opt = Builder::new(&potential, sampler, F::from_f64(2.0), start)
        .domain(domain)
        .seed(11)
        .stop(Stop::new().steps(300))
        .build(&mut chains)
        .unwrap();
    let report = opt
        .run()
        .map(|r| r.to_string())
        .unwrap_or_else(|e| e.to_string());
    let mut lbfgs: Lbfgs<F, D, 6> = Lbfgs::new();
    let chain = opt.best_chain();
    let polished = format!(
        "{:?}",
        opt.polish(chain, &mut lbfgs, PolishSettings::new(300))
    );
    let cs = opt.chains();
    Trace {
        x: cs.iter().flat_map(|c| bits(c.x())).collect(),
        y: cs.iter().flat_map(|c| bits(c.y())).collect(),
        grad: cs.iter().flat_map(|c| bits(c.gradient())).collect(),
        value: cs.iter().flat_map(|c| bits(&[c.value()])).collect(),
        best_x: cs.iter().flat_map(|c| bits(c.best().x)).collect(),
        best_value: cs.iter().flat_map(|c| bits(&[c.best().value])).collect(),
        best_iteration: cs.iter().map(|c| c.best().iteration).collect(),
        diverged: cs.iter().map(|c| c.is_diverged()).collect(),
        evaluations: opt.evaluations(),
        best_chain: opt.best_chain(),
        report,
        polished,
    }
}

/// The same run over flat storage of dimension `D`.
fn flat<F, P, B, R>(kind: SamplerKind, potential: P, domain: B) -> Trace
where
    F: Float,
    P: SlicePotential<F>,
    B: Domain<F> + Copy,
    R: rand_xoshiro::rand_core::Rng + SeedableRng + Clone + 'static,
{
    let d = D;
    let mut floats = vec![F::ZERO; FlatSlices::<F, R>::floats(N, d)];
    let (mut iterations, mut diverged) = (vec![0; N], vec![false; N]);
    let mut rngs: Vec<R> = (0..N).map(|_| R::seed_from_u64(0)).collect();
    let chains =
        FlatChains::new(d, &mut floats, &mut iterations, &mut diverged, &mut rngs).unwrap();
    let start = Gaussian::new([F::from_f64(1.0); D], F::from_f64(2.0)).unwrap();
    let sampler = AnySampler::paper(kind, F::from_f64(0.01)).unwrap();
    let mut opt = Builder::new(&potential, sampler, F::from_f64(2.0), start)
        .domain(domain)
        .seed(11)
        .stop(Stop::new().steps(300))
        .build(chains)
        .unwrap();
    let report = opt
        .run()
        .map(|r| r.to_string())
        .unwrap_or_else(|e| e.to_string());
    let mut storage = vec![F::ZERO; LbfgsIn::<F>::floats(d, 6)];
    let mut lbfgs = LbfgsIn::new(d, 6, &mut storage).unwrap();
    let chain = opt.best_chain();
    let polished = format!(
        "{:?}",
        opt.polish(chain, &mut lbfgs, PolishSettings::new(300))
    );
    let cs = opt.chains();
    Trace {
        x: bits(cs.positions()),
        y: (0..N).flat_map(|c| bits(cs.y(c))).collect(),
        grad: (0..N).flat_map(|c| bits(cs.gradient(c))).collect(),
        value: bits(cs.values()),
        best_x: bits(cs.best_positions()),
        best_value: bits(cs.best_values()),
        best_iteration: (0..N).map(|c| cs.best(c).iteration).collect(),
        diverged: (0..N).map(|c| cs.is_diverged(c)).collect(),
        evaluations: opt.evaluations(),
        best_chain: opt.best_chain(),
        report,
        polished,
    }
}

fn same_bits<F, P, B, R>(kind: SamplerKind, potential: P, domain: B, what: &str)
where
    F: Float,
    P: Potential<F, D> + SlicePotential<F> + Copy,
    B: Domain<F> + Copy,
    R: rand_xoshiro::rand_core::Rng + SeedableRng + Clone + 'static,
{
    let reference = with_chains::<F, P, B, R>(kind, potential, domain);
    assert_eq!(
        reference,
        flat::<F, P, B, R>(kind, potential, domain),
        "{kind} {what}: flat, d = {D}"
    );
}

/// The required identity: every sampler, with no box, a uniform box and a
/// box per coordinate, in f64 and f32, with the default generator (the
/// lockstep path where the target has vectors) and a 32-bit one (chain
/// after chain).
#[test]
fn dyn_and_const_give_the_bits_of_chains() {
    let (lo64, hi64) = sides::<f64>();
    let (lo32, hi32) = sides::<f32>();
    for kind in SamplerKind::ALL {
        same_bits::<f64, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, Unbounded, "f64 unbounded");
        let interval = Interval::new(-5.12, 5.12).unwrap();
        same_bits::<f64, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, interval, "f64 interval");
        let bounds = Bounds::new(lo64, hi64).unwrap();
        same_bits::<f64, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, bounds, "f64 bounds");
        same_bits::<f64, _, _, Xoshiro256PlusPlus>(kind, Cliff, Unbounded, "f64 cliff");
        same_bits::<f64, _, _, Xoshiro128PlusPlus>(kind, Rastrigin, bounds, "f64 xoshiro128");
        same_bits::<f32, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, Unbounded, "f32 unbounded");
        let bounds = Bounds::new(lo32, hi32).unwrap();
        same_bits::<f32, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, bounds, "f32 bounds");
        same_bits::<f32, _, _, Xoshiro256PlusPlus>(kind, Cliff, bounds, "f32 cliff");
    }
}

/// The cliff does what it is for: chains diverge there (so the identity
/// above covers frozen chains), and the run still reports.
#[test]
fn the_cliff_makes_chains_diverge() {
    let t = with_chains::<f64, _, _, Xoshiro256PlusPlus>(SamplerKind::Hrla, Cliff, Unbounded);
    let diverged = t.diverged.iter().filter(|&&d| d).count();
    assert!(diverged > 0 && diverged < N, "{:?}", t.diverged);
    // Initial points were redrawn: more evaluations than steps and chains.
    assert!(
        t.evaluations > (N as u64) + 300 * (N - diverged) as u64,
        "{}",
        t.evaluations
    );
}

/// An `Interval` is a `Bounds` with equal sides, bit for bit.
#[test]
fn an_interval_is_a_uniform_box() {
    let interval = Interval::new(-2.0, 3.0).unwrap();
    let bounds = Bounds::new([-2.0; D], [3.0; D]).unwrap();
    for kind in SamplerKind::ALL {
        let a = with_chains::<f64, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, interval);
        let b = with_chains::<f64, _, _, Xoshiro256PlusPlus>(kind, Rastrigin, bounds);
        assert_eq!(a, b, "{kind}");
    }
}

/// `U = 0` in 2-D.
fn flat2() -> FnPotential<impl Fn(&[f64; 2], &mut [f64; 2]) -> f64> {
    FnPotential::new(|_: &[f64; 2], g: &mut [f64; 2]| {
        *g = [0.0; 2];
        0.0
    })
}

/// Pearson's chi-square of `values` in 10 equal bins of `[lo, hi]`.
fn chi2(values: impl Iterator<Item = f64>, lo: f64, hi: f64, n: usize) -> (f64, [usize; 10]) {
    let mut bins = [0usize; 10];
    for v in values {
        bins[(((v - lo) / (hi - lo) * 10.0) as usize).min(9)] += 1;
    }
    let expected = n as f64 / 10.0;
    let chi2 = bins
        .iter()
        .map(|&o| (o as f64 - expected).powi(2) / expected)
        .sum();
    (chi2, bins)
}

/// On a flat potential in a box whose sides differ by a factor 10^6
/// (`[0, 10^-3] x [-500, 500]`), each sampler's chains end uniform in
/// each coordinate: 20 000 independent chains, 400 steps, 10 equal bins
/// per coordinate, Pearson's chi-square with 9 degrees of freedom against
/// 27.88, its 0.999 quantile (the seed is fixed; a correct sampler fails
/// about one seed in 500 over the two coordinates). The narrow side is
/// crossed many times per step (so its reflection folds many periods), the
/// wide one rarely. Every chain stays in the box at every step.
#[test]
fn a_box_per_coordinate_keeps_the_uniform_law() {
    let n = 20_000;
    let (lo, hi) = ([0.0, -500.0], [1e-3, 500.0]);
    for kind in SamplerKind::ALL {
        let bounds = Bounds::new(lo, hi).unwrap();
        let mut chains: Vec<Chain<f64, 2>> = (0..n).map(|_| Chain::new()).collect();
        let mut opt = Builder::new(flat2(), AnySampler::paper(kind, 0.05).unwrap(), 1.0, bounds)
            .domain(bounds)
            .seed(7)
            .build(&mut chains)
            .unwrap();
        for _ in 0..400 {
            opt.step().unwrap();
            assert!(
                opt.chains()
                    .iter()
                    .all(|c| (0..2).all(|i| c.x()[i] >= lo[i] && c.x()[i] <= hi[i]))
            );
        }
        for i in 0..2 {
            let (chi2, bins) = chi2(opt.chains().iter().map(|c| c.x()[i]), lo[i], hi[i], n);
            assert!(
                chi2 < 27.88,
                "{kind} coordinate {i}: chi2 = {chi2}, bins {bins:?}"
            );
        }
    }
}

/// The chi-square above can fail: chains started uniform in the box, then
/// moved without a domain, are no longer uniform in the narrow side.
#[test]
fn without_the_box_the_narrow_side_is_not_uniform() {
    let n = 20_000;
    let (lo, hi) = ([0.0, -500.0], [1e-3, 500.0]);
    let bounds = Bounds::new(lo, hi).unwrap();
    let mut chains: Vec<Chain<f64, 2>> = (0..n).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        flat2(),
        AnySampler::paper(SamplerKind::Hrla, 0.05).unwrap(),
        1.0,
        bounds,
    )
    .seed(7)
    .stop(Stop::new().steps(400))
    .build(&mut chains)
    .unwrap();
    opt.run().unwrap();
    let (chi2, _) = chi2(
        opt.chains().iter().map(|c| c.x()[0].clamp(lo[0], hi[0])),
        lo[0],
        hi[0],
        n,
    );
    assert!(chi2 > 27.88, "{chi2}");
}

/// A batch potential implemented directly (not through `SlicePotential`):
/// one call per step for all the chains, plus one at the start; the same
/// bits as the blanket implementation.
struct Batched {
    calls: Cell<u64>,
}

impl BatchPotential<f64> for Batched {
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[f64],
        grad: &mut [f64],
        value: &mut [f64],
        skip: &[bool],
    ) -> ControlFlow<()> {
        self.calls.set(self.calls.get() + 1);
        assert_eq!(
            (x.len(), grad.len(), skip.len()),
            (value.len() * d, value.len() * d, value.len())
        );
        for (i, (xi, gi)) in x.chunks_exact(d).zip(grad.chunks_exact_mut(d)).enumerate() {
            if !skip[i] {
                value[i] = SlicePotential::value_and_gradient(&Rastrigin, xi, gi);
            }
        }
        ControlFlow::Continue(())
    }
}

#[test]
fn the_batch_seam_is_one_call_per_step() {
    type Run<'a> = &'a dyn Fn(FlatSlices<'_, f64, Xoshiro256PlusPlus>) -> (Vec<u64>, u64);
    let run = |potential: Run<'_>| {
        let d = 23;
        let mut floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(N, d)];
        let (mut iterations, mut diverged) = (vec![0; N], vec![false; N]);
        let mut rngs: Vec<_> = (0..N)
            .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
            .collect();
        let chains = FlatChains::new(
            d,
            &mut floats[..],
            &mut iterations[..],
            &mut diverged[..],
            &mut rngs[..],
        )
        .unwrap();
        potential(chains)
    };
    let sampler = AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap();
    let start = Interval::new(-3.0, 3.0).unwrap();
    let calls = Cell::new(0);
    let a = run(&|chains| {
        let batched = Batched {
            calls: Cell::new(0),
        };
        let mut opt = Builder::new(batched, sampler, 2.0, start)
            .stop(Stop::new().steps(200))
            .build(chains)
            .unwrap();
        opt.run().unwrap();
        calls.set(opt.potential().calls.get());
        (bits(opt.chains().positions()), opt.evaluations())
    });
    assert_eq!(calls.get(), 201);
    let b = run(&|chains| {
        let mut opt = Builder::new(Rastrigin, sampler, 2.0, start)
            .stop(Stop::new().steps(200))
            .build(chains)
            .unwrap();
        opt.run().unwrap();
        (bits(opt.chains().positions()), opt.evaluations())
    });
    assert_eq!(a, b);
    assert_eq!(a.1, N as u64 * 201);
}

/// Bad boxes, storage and dimensions are typed errors.
#[test]
fn bad_shapes_are_refused() {
    assert!(matches!(
        Bounds::new([0.0, 1.0], [1.0, 1.0]),
        Err(Error::NotPositive {
            name: "hi - lo",
            ..
        })
    ));
    assert!(matches!(
        Bounds::new([0.0, f64::NAN], [1.0, 2.0]),
        Err(Error::NotFinite { name: "lo", .. })
    ));
    assert!(matches!(
        Bounds::new(&[0.0, 0.0][..], &[1.0][..]),
        Err(Error::Length {
            name: "hi",
            expected: 2,
            got: 1
        })
    ));
    assert!(matches!(
        Bounds::<f64, _>::new(&[][..], &[][..]),
        Err(Error::Zero { .. })
    ));
    assert!(matches!(
        Bounds::new([-f64::MAX, 0.0], [f64::MAX, 1.0]),
        Err(Error::NotPositive { .. })
    ));
    // A box of 3 sides for a run of 2 coordinates.
    let bounds = Bounds::new([0.0; 3], [1.0; 3]).unwrap();
    let mut chains: Vec<Chain<f64, 2>> = (0..4).map(|_| Chain::new()).collect();
    let built = Builder::new(
        Rastrigin,
        AnySampler::paper(SamplerKind::Ola, 0.01).unwrap(),
        1.0,
        Interval::new(0.0, 1.0).unwrap(),
    )
    .domain(bounds)
    .stop(Stop::new().steps(1))
    .build(&mut chains);
    assert!(matches!(
        built,
        Err(Error::Length {
            name: "box sides",
            expected: 2,
            got: 3
        })
    ));
    // Flat storage of the wrong size.
    let mut floats = vec![0.0f64; 10];
    let (mut it, mut dv) = (vec![0; 2], vec![false; 2]);
    let mut rngs: Vec<_> = (0..2)
        .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
        .collect();
    assert!(matches!(
        FlatChains::new(2, &mut floats, &mut it, &mut dv, &mut rngs),
        Err(Error::Length {
            name: "floats",
            expected: 20,
            got: 10
        })
    ));
    // A dimension whose storage size overflows: a typed error, not a
    // wrapped size or an overflow panic.
    for d in [usize::MAX / 4, usize::MAX / 2, usize::MAX] {
        let mut floats = vec![0.0f64; 20];
        assert!(
            matches!(
                FlatChains::new(d, &mut floats, &mut it, &mut dv, &mut rngs),
                Err(Error::Length {
                    name: "floats",
                    expected: usize::MAX,
                    got: 20
                })
            ),
            "{d}"
        );
    }
    let mut storage = vec![0.0f64; 7];
    for (d, m) in [
        (usize::MAX / 2, 1),
        (2, usize::MAX / 2),
        (usize::MAX, usize::MAX),
    ] {
        assert!(
            matches!(
                LbfgsIn::new(d, m, &mut storage),
                Err(Error::Length {
                    name: "L-BFGS storage",
                    expected: usize::MAX,
                    got: 7
                })
            ),
            "{d} {m}"
        );
    }
    assert!(matches!(
        LbfgsIn::new(2, 1, &mut storage),
        Err(Error::Length { .. })
    ));
    assert!(matches!(
        LbfgsIn::new(0, 1, &mut storage),
        Err(Error::Zero { .. })
    ));
}

/// Every built-in potential gives the same bits through `Potential<F, 17>`
/// and `SlicePotential<F>` (the same code), at points across its domain.
#[test]
fn built_ins_are_the_same_through_slices() {
    fn check<P: Potential<f64, D> + SlicePotential<f64>>(p: P, name: &str) {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200 {
            let x: [f64; D] = core::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
            });
            let (mut ga, mut gs) = ([0.0; D], [0.0; D]);
            let ua = Potential::value_and_gradient(&p, &x, &mut ga);
            let us = SlicePotential::value_and_gradient(&p, &x[..], &mut gs[..]);
            assert_eq!(ua.to_bits(), us.to_bits(), "{name}");
            assert_eq!(bits(&ga), bits(&gs), "{name}");
        }
    }
    check(Rastrigin, "rastrigin");
    check(hrla::Ackley, "ackley");
    check(hrla::Levy, "levy");
    check(hrla::DoubleWell, "double well");
    check(hrla::StyblinskiTang, "styblinski-tang");
    check(hrla::Quadratic::new(2.0, [1.0; D]).unwrap(), "quadratic");
}

/// The dimensions a run-time front end asks for, up to 10 000: a short run
/// at each ends with a finite best inside a box per coordinate, and the
/// polish lowers it.
#[test]
fn large_run_time_dimensions_run() {
    for d in [1, 24, 257, 10_000] {
        let n = 4;
        let mut floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(n, d)];
        let (mut iterations, mut diverged) = (vec![0; n], vec![false; n]);
        let mut rngs: Vec<_> = (0..n)
            .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
            .collect();
        let chains =
            FlatChains::new(d, &mut floats, &mut iterations, &mut diverged, &mut rngs).unwrap();
        let lo: Vec<f64> = (0..d).map(|i| -1.0 - (i % 7) as f64).collect();
        let hi: Vec<f64> = (0..d).map(|i| 1.0 + (i % 3) as f64).collect();
        let bounds = Bounds::new(&lo[..], &hi[..]).unwrap();
        let sampler = AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap();
        let mut opt = Builder::new(Rastrigin, sampler, 4.0, bounds)
            .domain(bounds)
            .seed(3)
            .stop(Stop::new().steps(20))
            .build(chains)
            .unwrap();
        let report = opt.run().unwrap();
        assert!(report.value.is_finite(), "{d}: {report}");
        let x = opt.chains().positions();
        assert!(
            x.chunks_exact(d)
                .all(|p| p.iter().enumerate().all(|(i, &v)| v >= lo[i] && v <= hi[i]))
        );
        let mut storage = vec![0.0; LbfgsIn::<f64>::floats(d, 5)];
        let mut lbfgs = LbfgsIn::new(d, 5, &mut storage).unwrap();
        let polished = opt
            .polish(opt.best_chain(), &mut lbfgs, PolishSettings::new(200))
            .unwrap();
        assert!(polished.value <= report.value, "{d}: {polished:?} {report}");
        assert!(
            opt.best()
                .x
                .iter()
                .enumerate()
                .all(|(i, &v)| v >= lo[i] && v <= hi[i])
        );
    }
}

/// The sampler every run between steps starts with, and the one
/// `set_sampler` gives it half-way.
fn sampler_pair(kind: SamplerKind) -> (AnySampler<f64>, AnySampler<f64>) {
    (
        AnySampler::paper(kind, 0.05).unwrap(),
        AnySampler::paper(kind, 0.02).unwrap(),
    )
}

/// Restart points: feasible, and beyond the cliff (`x_0 > 1`: the chain
/// diverges there).
const FEASIBLE: [f64; D] = [0.5; D];
const OVER_THE_CLIFF: [f64; D] = [2.0; D];

/// An evaluation budget that runs out among the quenches (HRLA has spent
/// 311 evaluations when they begin).
const BUDGET: u64 = 330;

/// What the runs between steps leave: every outcome of a quench, a
/// restart and a polish, in order, then the chains as bits.
#[derive(Debug, PartialEq)]
struct Between {
    outcomes: Vec<String>,
    x: Vec<u64>,
    y: Vec<u64>,
    grad: Vec<u64>,
    value: Vec<u64>,
    best_x: Vec<u64>,
    best_value: Vec<u64>,
    best_iteration: Vec<u64>,
    diverged: Vec<bool>,
    counters: (u64, u64, usize, usize),
    current_best: String,
    sampler_and_schedule: String,
}

/// The schedule of these runs: `a` grows, so that a sampler set
/// half-way takes its kernel at the current temperature.
fn schedule() -> hrla::Geometric<f64> {
    hrla::Geometric::new(1.0, 8.0, 400).unwrap()
}

/// 60 steps, a quench of every chain, restarts (one over the cliff, which
/// diverges its chain, and its quench, refused), `set_sampler`, 60 steps,
/// a polish: over `Chain<f64, 17>`s.
fn between_with_chains(kind: SamplerKind, budget: u64) -> Between {
    let (first, second) = sampler_pair(kind);
    let mut chains: Vec<Chain<f64, D>> = (0..N).map(|_| Chain::new()).collect();
    let start = Gaussian::new([0.5; D], 0.5).unwrap();
    let mut opt = Builder::new(Cliff, first, schedule(), start)
        .seed(13)
        .stop(Stop::new().evaluations(budget))
        .build(&mut chains)
        .unwrap();
    let mut outcomes = Vec::new();
    let mut lbfgs: Lbfgs<f64, D, 5> = Lbfgs::new();
    for _ in 0..60 {
        outcomes.push(format!("{:?}", opt.step()));
    }
    outcomes.push(format!("evaluations {}", opt.evaluations()));
    for c in 0..N {
        outcomes.push(format!(
            "{:?}",
            opt.quench(c, &mut lbfgs, PolishSettings::new(40))
        ));
    }
    for c in 0..N {
        outcomes.push(format!("{:?}", opt.restart(c, &FEASIBLE)));
    }
    outcomes.push(format!("diverged {}", opt.diverged_chains()));
    outcomes.push(format!("{:?}", opt.restart(3, &OVER_THE_CLIFF)));
    outcomes.push(format!(
        "{:?}",
        opt.quench(3, &mut lbfgs, PolishSettings::new(40))
    ));
    outcomes.push(format!("{:?}", opt.restart(N, &FEASIBLE)));
    outcomes.push(format!("{:?}", opt.set_sampler(second)));
    outcomes.push(format!("{:?}", opt.kernel()));
    for _ in 0..60 {
        outcomes.push(format!("{:?}", opt.step()));
    }
    let best = opt.best_chain();
    outcomes.push(format!(
        "{:?}",
        opt.polish(best, &mut lbfgs, PolishSettings::new(40))
    ));
    let cs = opt.chains();
    Between {
        outcomes,
        x: cs.iter().flat_map(|c| bits(c.x())).collect(),
        y: cs.iter().flat_map(|c| bits(c.y())).collect(),
        grad: cs.iter().flat_map(|c| bits(c.gradient())).collect(),
        value: cs.iter().flat_map(|c| bits(&[c.value()])).collect(),
        best_x: cs.iter().flat_map(|c| bits(c.best().x)).collect(),
        best_value: cs.iter().flat_map(|c| bits(&[c.best().value])).collect(),
        best_iteration: cs.iter().map(|c| c.best().iteration).collect(),
        diverged: cs.iter().map(|c| c.is_diverged()).collect(),
        counters: (
            opt.iteration(),
            opt.evaluations(),
            opt.diverged_chains(),
            opt.best_chain(),
        ),
        current_best: format!("{:?}", opt.current_best()),
        sampler_and_schedule: format!("{:?} {:?}", opt.sampler(), opt.schedule()),
    }
}

/// The same over flat storage (borrowed or owned) of dimension 17.
fn between_flat<Fs, Is, Ds, Rs>(
    kind: SamplerKind,
    budget: u64,
    chains: FlatChains<f64, Xoshiro256PlusPlus, Fs, Is, Ds, Rs>,
) -> Between
where
    Fs: hrla::FlatStorage<f64>,
    Is: hrla::FlatStorage<u64>,
    Ds: hrla::FlatStorage<bool>,
    Rs: hrla::FlatStorage<Xoshiro256PlusPlus>,
{
    let (first, second) = sampler_pair(kind);
    let start = Gaussian::new([0.5; D], 0.5).unwrap();
    let mut opt = Builder::new(Cliff, first, schedule(), start)
        .seed(13)
        .stop(Stop::new().evaluations(budget))
        .build(chains)
        .unwrap();
    let mut outcomes = Vec::new();
    let mut storage = vec![0.0; LbfgsIn::<f64>::floats(D, 5)];
    let mut lbfgs = LbfgsIn::new(D, 5, &mut storage).unwrap();
    for _ in 0..60 {
        outcomes.push(format!("{:?}", opt.step()));
    }
    outcomes.push(format!("evaluations {}", opt.evaluations()));
    for c in 0..N {
        outcomes.push(format!(
            "{:?}",
            opt.quench(c, &mut lbfgs, PolishSettings::new(40))
        ));
    }
    for c in 0..N {
        outcomes.push(format!("{:?}", opt.restart(c, &FEASIBLE)));
    }
    outcomes.push(format!("diverged {}", opt.diverged_chains()));
    outcomes.push(format!("{:?}", opt.restart(3, &OVER_THE_CLIFF)));
    outcomes.push(format!(
        "{:?}",
        opt.quench(3, &mut lbfgs, PolishSettings::new(40))
    ));
    outcomes.push(format!("{:?}", opt.restart(N, &FEASIBLE)));
    outcomes.push(format!("{:?}", opt.set_sampler(second)));
    outcomes.push(format!("{:?}", opt.kernel()));
    for _ in 0..60 {
        outcomes.push(format!("{:?}", opt.step()));
    }
    let best = opt.best_chain();
    outcomes.push(format!(
        "{:?}",
        opt.polish(best, &mut lbfgs, PolishSettings::new(40))
    ));
    let cs = opt.chains();
    Between {
        outcomes,
        x: bits(cs.positions()),
        y: (0..N).flat_map(|c| bits(cs.y(c))).collect(),
        grad: (0..N).flat_map(|c| bits(cs.gradient(c))).collect(),
        value: bits(cs.values()),
        best_x: bits(cs.best_positions()),
        best_value: bits(cs.best_values()),
        best_iteration: (0..N).map(|c| cs.best(c).iteration).collect(),
        diverged: (0..N).map(|c| cs.is_diverged(c)).collect(),
        counters: (
            opt.iteration(),
            opt.evaluations(),
            opt.diverged_chains(),
            opt.best_chain(),
        ),
        current_best: format!("{:?}", opt.current_best()),
        sampler_and_schedule: format!("{:?} {:?}", opt.sampler(), opt.schedule()),
    }
}

/// Owned arrays for `N` chains of dimension `D`.
type Owned =
    FlatChains<f64, Xoshiro256PlusPlus, Vec<f64>, Vec<u64>, Vec<bool>, Vec<Xoshiro256PlusPlus>>;

fn owned() -> Owned {
    FlatChains::new(
        D,
        vec![0.0; Owned::floats(N, D)],
        vec![0; N],
        vec![false; N],
        (0..N)
            .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
            .collect(),
    )
    .unwrap()
}

/// `quench`, `restart` (to a feasible point, over the cliff, a diverged
/// chain revived, an index out of range) and `set_sampler` between steps
/// give the same bits and outcomes over flat storage of dimension 17 as over `Chain<f64, 17>`,
/// on borrowed and on owned storage, for every sampler; with an
/// evaluation budget that runs out among the quenches, the clipped
/// searches and the refused restarts are the same too.
#[test]
fn between_steps_dyn_gives_the_bits_of_const() {
    for kind in SamplerKind::ALL {
        for budget in [u64::MAX, BUDGET] {
            let reference = between_with_chains(kind, budget);
            let mut floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(N, D)];
            let (mut iterations, mut diverged) = (vec![0; N], vec![false; N]);
            let mut rngs: Vec<_> = (0..N)
                .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
                .collect();
            let borrowed =
                FlatChains::new(D, &mut floats, &mut iterations, &mut diverged, &mut rngs).unwrap();
            assert_eq!(
                reference,
                between_flat(kind, budget, borrowed),
                "{kind} budget {budget}: borrowed"
            );
            assert_eq!(
                reference,
                between_flat(kind, budget, owned()),
                "{kind} budget {budget}: owned"
            );
        }
    }
}

/// The scenario above covers what it claims: quenches that lower a best,
/// a quench refused on a diverged chain, a diverged chain revived by a
/// restart, a restart over the cliff, a refused index; and, with the
/// budget, quenches clipped to nothing and restarts refused.
#[test]
fn between_steps_covers_its_cases() {
    let free = between_with_chains(SamplerKind::Hrla, u64::MAX);
    let text = free.outcomes.join("\n");
    assert!(text.contains("Ok(Polished"), "{text}");
    assert!(
        text.contains("the point of a diverged chain"),
        "a quench of a diverged chain: {text}"
    );
    assert!(text.contains("Index"), "{text}");
    assert!(free.diverged[3], "chain 3 over the cliff");
    // Chains diverged in the first steps (their quench was refused), and
    // the restarts at a feasible point revived every one.
    assert!(
        free.outcomes[61..61 + N]
            .iter()
            .any(|o| o.contains("diverged chain")),
        "{text}"
    );
    assert_eq!(free.outcomes[61 + 2 * N], "diverged 0", "{text}");
    let budgeted = between_with_chains(SamplerKind::Hrla, BUDGET);
    let text = budgeted.outcomes.join("\n");
    assert!(text.contains("evaluations: 0"), "{text}");
    assert!(text.contains("Ok(false)"), "{text}");
}

/// The run-time-D checks of the methods between steps: L-BFGS storage of
/// another dimension and a restart point of another length are typed
/// errors, and change nothing.
#[test]
fn between_steps_refuses_other_dimensions() {
    let start = Gaussian::new([0.0; D], 1.5).unwrap();
    let mut opt = Builder::new(
        Rastrigin,
        AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        2.0,
        start,
    )
    .seed(13)
    .build(owned())
    .unwrap();
    let before = bits(opt.chains().positions());
    let mut storage = vec![0.0; LbfgsIn::<f64>::floats(D + 1, 5)];
    let mut lbfgs = LbfgsIn::new(D + 1, 5, &mut storage).unwrap();
    assert!(matches!(
        opt.quench(0, &mut lbfgs, PolishSettings::new(10)),
        Err(Error::Length {
            name: "L-BFGS dimension",
            expected: D,
            got: 18
        })
    ));
    assert!(matches!(
        opt.restart(0, &[0.0; D - 1]),
        Err(Error::Length {
            name: "x",
            expected: D,
            got: 16
        })
    ));
    assert_eq!(opt.evaluations(), N as u64);
    assert_eq!(before, bits(opt.chains().positions()));
    // Nothing borrowed: the optimiser can be kept anywhere (a front end's
    // engine object, shared between threads), and gives its arrays back.
    fn keepable<T: Send + Sync + 'static>(t: T) -> T {
        t
    }
    let kept: Box<dyn std::any::Any> = Box::new(keepable(opt));
    let opt = kept
        .downcast::<hrla::Optimizer<
            _,
            Rastrigin,
            AnySampler<f64>,
            f64,
            FlatChains<
                f64,
                Xoshiro256PlusPlus,
                Vec<f64>,
                Vec<u64>,
                Vec<bool>,
                Vec<Xoshiro256PlusPlus>,
            >,
            Unbounded,
        >>()
        .unwrap();
    let (floats, ..) = opt.into_chains().into_storage();
    assert_eq!(bits(&floats[..N * D]), before);
}

/// Rastrigin through the batch seam for `answers` calls, then a stop (a
/// user's function that raised, say): every later call stops too.
struct StopsAfter {
    answers: u64,
    calls: Cell<u64>,
}

impl StopsAfter {
    fn new(answers: u64) -> Self {
        Self {
            answers,
            calls: Cell::new(0),
        }
    }
}

impl BatchPotential<f64> for StopsAfter {
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[f64],
        grad: &mut [f64],
        value: &mut [f64],
        skip: &[bool],
    ) -> ControlFlow<()> {
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() > self.answers {
            return ControlFlow::Break(());
        }
        Batched {
            calls: Cell::new(0),
        }
        .values_and_gradients(d, x, grad, value, skip)
    }
}

/// A potential that stops the run ends it with `Error::Stopped` wherever it
/// asks (the start, a step, a restart, a polish, `Auto`), never with a
/// result, and the run stays failed without calling it again.
#[test]
fn a_potential_that_stops_ends_the_run_as_stopped() {
    let d = 5;
    let (sampler, start) = (
        AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        Interval::new(-3.0, 3.0).unwrap(),
    );
    let build = |answers: u64| {
        let chains = FlatChains::new(
            d,
            vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(N, d)],
            vec![0; N],
            vec![false; N],
            vec![Xoshiro256PlusPlus::seed_from_u64(0); N],
        )
        .unwrap();
        Builder::new(StopsAfter::new(answers), sampler, 2.0, start)
            .stop(Stop::new().steps(100))
            .build(chains)
    };
    // At the start (one call for every chain's first point).
    assert!(matches!(build(0), Err(Error::Stopped)));
    // At a step: the third call (the start, a step, then the stop).
    let mut opt = build(2).unwrap();
    opt.step().unwrap();
    assert!(matches!(opt.step(), Err(Error::Stopped)));
    let calls = opt.potential().calls.get();
    assert_eq!(calls, 3);
    assert!(matches!(opt.step(), Err(Error::Stopped)));
    assert!(matches!(opt.run(), Err(Error::Stopped)));
    assert!(matches!(opt.restart(0, &[0.0; 5]), Err(Error::Stopped)));
    assert_eq!(opt.potential().calls.get(), calls, "no call after the stop");
    // A restart's evaluation, and a polish's.
    let mut opt = build(1).unwrap();
    assert!(matches!(opt.restart(0, &[0.5; 5]), Err(Error::Stopped)));
    let mut storage = vec![0.0; LbfgsIn::<f64>::floats(d, 4)];
    let mut lbfgs = LbfgsIn::new(d, 4, &mut storage).unwrap();
    let mut opt = build(3).unwrap();
    let settings = PolishSettings::new(50);
    assert!(matches!(
        opt.polish(0, &mut lbfgs, settings),
        Err(Error::Stopped)
    ));
    assert!(matches!(opt.step(), Err(Error::Stopped)));
    // Auto, at its first points and later in the run.
    let (m, n) = (4, 6);
    let box5 = Interval::new(-5.0, 5.0).unwrap();
    for answers in [0, 3, 40, 400] {
        let mut floats = vec![0.0; AutoStorage::<f64, Xoshiro256PlusPlus>::floats(n, d, m)];
        let (mut diverged, mut rngs) = (
            vec![false; n],
            vec![Xoshiro256PlusPlus::seed_from_u64(0); n],
        );
        let mut storage = AutoStorage::new(d, m, &mut floats, &mut diverged, &mut rngs).unwrap();
        let p = StopsAfter::new(answers);
        let found = Auto::default().minimize(&Problem::new(&p, &box5, 5_000).seed(1), &mut storage);
        assert!(matches!(found, Err(Error::Stopped)), "{answers}: {found:?}");
        assert_eq!(
            p.calls.get(),
            answers + 1,
            "{answers}: no call after the stop"
        );
    }
}
