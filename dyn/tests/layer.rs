//! The layer runs the kernel's computation, bit for bit, whatever the front
//! end's way of describing it; and refuses what the kernel cannot run with
//! a typed error.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use hrla::{
    AnySampler, AnySchedule, Auto, Builder, Chain, Constant, Gaussian, Interval, Lbfgs, Potential,
    Rastrigin, SamplerKind, Stop, Termination,
};
use hrla_dyn::auto::{Problem, solve};
use hrla_dyn::{
    BatchFunction, BoxSpec, BuiltinKind, BuiltinSpec, Error, PotentialSpec, Settings, StartSpec,
    UserError,
};

fn settings(potential: PotentialSpec) -> Settings {
    Settings {
        potential,
        sampler: AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        schedule: AnySchedule::Constant(Constant::new(4.0).unwrap()),
        start: StartSpec::Isotropic {
            centre: 3.0,
            std_dev: 10f64.sqrt(),
        },
        domain: None,
        seed: 7,
        stride: 1,
        stop: Stop::new().steps(200),
        chains: 6,
        dim: Some(10),
        escape: None,
    }
}

fn rastrigin() -> PotentialSpec {
    PotentialSpec::Builtin(BuiltinSpec::Named(BuiltinKind::Rastrigin))
}

/// Rastrigin as a built-in, or as a user's batched function.
fn rastrigin_as(user: bool) -> PotentialSpec {
    if user {
        PotentialSpec::User(Arc::new(Batched(AtomicUsize::new(0))))
    } else {
        rastrigin()
    }
}

/// Rastrigin through the batch interface, counting its calls.
struct Batched(AtomicUsize);

impl BatchFunction for Batched {
    fn evaluate(
        &self,
        points: &[f64],
        d: usize,
        values: &mut [f64],
        grads: &mut [f64],
    ) -> Result<(), UserError> {
        self.0.fetch_add(1, Ordering::Relaxed);
        assert_eq!(d, 10);
        for ((x, v), g) in points
            .chunks_exact(d)
            .zip(values.iter_mut())
            .zip(grads.chunks_exact_mut(d))
        {
            let x: &[f64; 10] = x.try_into().unwrap();
            let g: &mut [f64; 10] = g.try_into().unwrap();
            *v = Rastrigin.value_and_gradient(x, g);
        }
        Ok(())
    }
}

/// The kernel's own run of the same settings, built by hand.
fn kernel_run() -> (hrla::Report<f64>, Vec<[f64; 10]>) {
    let chains: Vec<Chain<f64, 10>> = (0..6).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        AnySchedule::Constant(Constant::new(4.0).unwrap()),
        Gaussian::new([3.0; 10], 10f64.sqrt()).unwrap(),
    )
    .seed(7)
    .stop(Stop::new().steps(200))
    .build(chains)
    .unwrap();
    let report = opt.run().unwrap();
    (report, opt.chains().iter().map(|c| *c.x()).collect())
}

fn positions(engine: &hrla_dyn::Engine) -> Vec<[f64; 10]> {
    let l = engine.layout();
    assert_eq!((l.n, l.d), (6, 10));
    let x = engine.positions();
    x.chunks_exact(10).map(|r| r.try_into().unwrap()).collect()
}

#[test]
fn a_builtin_run_is_the_kernels_run() {
    let (report, x) = kernel_run();
    let mut engine = settings(rastrigin()).build().unwrap();
    let ours = engine
        .run(hrla::Observe::EveryAndNewBest(1000), &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(ours, report);
    assert_eq!(ours.termination, Termination::Steps);
    assert_eq!(positions(&engine), x);
}

/// A user's batched function gives the kernel's bits and is called once
/// per step for all live chains (plus once for the initial points).
#[test]
fn a_batched_function_gives_the_same_bits_in_one_call_per_step() {
    let (report, x) = kernel_run();
    let f = Arc::new(Batched(AtomicUsize::new(0)));
    let mut engine = settings(PotentialSpec::User(f.clone())).build().unwrap();
    assert!(engine.is_user());
    let ours = engine
        .run(hrla::Observe::EveryAndNewBest(1), &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(ours, report);
    assert_eq!(f.0.load(Ordering::Relaxed), 201);
    assert_eq!(positions(&engine), x);
}

#[test]
fn the_observer_ends_the_run() {
    for user in [false, true] {
        let mut engine = settings(rastrigin_as(user)).build().unwrap();
        let report = engine
            .run(hrla::Observe::EveryAndNewBest(1), &mut |p| {
                if p.iteration >= 10 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })
            .unwrap();
        assert_eq!(report.termination, Termination::Observer, "user {user}");
        assert_eq!(report.iterations, 10, "user {user}");
    }
}

/// The observer sees the best point of the run, borrowed: `U` there is
/// the best value, for the engine (a built-in and a user's function) and
/// for Auto.
#[test]
fn the_observer_sees_the_best_point() {
    let check = |p: &hrla_dyn::Progress<'_>| {
        let x: [f64; 10] = p.x.try_into().unwrap();
        assert_eq!(Rastrigin.value(&x), p.value, "{p:?}");
    };
    for user in [false, true] {
        let mut engine = settings(rastrigin_as(user)).build().unwrap();
        let mut calls = 0;
        engine
            .run(hrla::Observe::EveryAndNewBest(1), &mut |p| {
                check(p);
                calls += 1;
                ControlFlow::Continue(())
            })
            .unwrap();
        assert!(calls >= 200, "{calls}");
    }
    let problem = Problem {
        potential: rastrigin(),
        domain: BoxSpec::Uniform {
            lo: -5.12,
            hi: 5.12,
        },
        budget: 3_000,
        seed: 4,
        chains: Some(4),
        dim: Some(10),
        x0: None,
        target: None,
        stall: None,
        rounds: None,
        converge: None,
        soft: None,
    };
    let mut calls = 0;
    let s = solve(&Auto::default(), &problem, &mut |p| {
        check(p);
        calls += 1;
        ControlFlow::Continue(())
    })
    .unwrap();
    assert!(calls > 100, "{calls}");
    assert!(s.value.is_finite());
}

#[derive(Debug)]
struct Refused;

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("refused")
    }
}

impl std::error::Error for Refused {}

/// Fails from its `after`-th call on.
struct Failing(AtomicUsize, usize);

impl BatchFunction for Failing {
    fn evaluate(
        &self,
        points: &[f64],
        d: usize,
        values: &mut [f64],
        grads: &mut [f64],
    ) -> Result<(), UserError> {
        if self.0.fetch_add(1, Ordering::Relaxed) >= self.1 {
            return Err(Box::new(Refused));
        }
        Batched(AtomicUsize::new(0)).evaluate(points, d, values, grads)
    }
}

/// A user's error comes back as it was returned, and is never a report.
#[test]
fn a_failing_function_is_its_own_error() {
    let f = Arc::new(Failing(AtomicUsize::new(0), 5));
    let mut engine = settings(PotentialSpec::User(f.clone())).build().unwrap();
    let layout = engine.layout();
    let Err(Error::User(e)) = engine.run(hrla::Observe::EveryAndNewBest(1), &mut |_| {
        ControlFlow::Continue(())
    }) else {
        panic!("the function's error must end the run");
    };
    assert!(e.downcast_ref::<Refused>().is_some());
    // One call for the initial points, one per step: the sixth call is the
    // fifth step's, which moved the chains and then failed. The failed
    // call is undone: the run is as it was before it, so that going on
    // gives the bits of a run never interrupted.
    assert_eq!(f.0.load(Ordering::Relaxed), 6);
    assert_eq!(engine.iteration(), 0);
    let fresh = settings(rastrigin()).build().unwrap();
    assert_eq!(engine.positions(), fresh.positions());
    assert_eq!(engine.evaluations(), fresh.evaluations());
    // Put back in the same storage: a front end's views stay valid.
    assert_eq!(engine.layout(), layout);
    let f = Arc::new(Failing(AtomicUsize::new(0), 0));
    assert!(matches!(
        settings(PotentialSpec::User(f)).build().err(),
        Some(Error::User(_))
    ));
}

#[test]
fn what_the_kernel_cannot_run_is_a_typed_error() {
    let mut s = settings(rastrigin());
    s.dim = Some(17);
    assert_eq!(s.build().unwrap().dim(), 17);
    s.dim = Some(0);
    assert!(matches!(
        s.build().err(),
        Some(Error::Kernel(hrla::Error::Zero { .. }))
    ));
    s.dim = None;
    assert!(matches!(s.build().err(), Some(Error::NoDimension)));
    s.start = StartSpec::Point(vec![0.0; 3]);
    s.dim = Some(2);
    let e = s.build().err().unwrap();
    assert_eq!(e.to_string(), "dim has dimension 2 but the start has 3");
    // A box per coordinate: its pairs' number must be the run's D, each
    // pair checked by the kernel.
    let mut s = settings(rastrigin());
    let mut sides = vec![(-5.0, 5.0); 10];
    sides[3] = (1.0, 0.0);
    s.domain = Some(BoxSpec::PerCoordinate(sides));
    assert!(matches!(
        s.build().err(),
        Some(Error::Kernel(hrla::Error::NotPositive { .. }))
    ));
    s.domain = Some(BoxSpec::PerCoordinate(vec![(-5.0, 5.0); 3]));
    assert!(matches!(
        s.build().err(),
        Some(Error::DimensionMismatch { .. })
    ));
    s.domain = Some(BoxSpec::Uniform { lo: 1.0, hi: 0.0 });
    assert!(matches!(s.build().err(), Some(Error::Kernel(_))));
    let mut s = settings(rastrigin());
    s.chains = usize::MAX;
    assert!(matches!(
        s.build().err(),
        Some(Error::Memory {
            address_space: true,
            ..
        })
    ));
}

/// The layer's `Auto` is the kernel's, bit for bit, and a batched
/// function there gives the same bits.
/// Sides that differ by 10^6 between coordinates.
fn wide_and_narrow() -> Vec<(f64, f64)> {
    (0..10)
        .map(|i| {
            if i % 2 == 0 {
                (-1e3, 1e3)
            } else {
                (0.25, 0.25 + 2e-3)
            }
        })
        .collect()
}

/// A box per coordinate, as the domain and as the start, runs as the
/// kernel's [`hrla::Bounds`], bit for bit; every chain stays in its
/// coordinates' own sides; pairs that are all equal give an [`Interval`]'s
/// bits.
#[test]
fn a_box_per_coordinate_is_the_kernels_bounds() {
    let sides = wide_and_narrow();
    let mut s = settings(rastrigin());
    s.domain = Some(BoxSpec::PerCoordinate(sides.clone()));
    s.start = StartSpec::Box(BoxSpec::PerCoordinate(sides.clone()));
    let mut engine = s.build().unwrap();
    let report = engine
        .run(hrla::Observe::NewBest, &mut |_| ControlFlow::Continue(()))
        .unwrap();

    let lo: [f64; 10] = std::array::from_fn(|i| sides[i].0);
    let hi: [f64; 10] = std::array::from_fn(|i| sides[i].1);
    let bounds = hrla::Bounds::new(lo, hi).unwrap();
    let chains: Vec<Chain<f64, 10>> = (0..6).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        AnySchedule::Constant(Constant::new(4.0).unwrap()),
        bounds,
    )
    .domain(bounds)
    .seed(7)
    .stop(Stop::new().steps(200))
    .build(chains)
    .unwrap();
    let expected = opt.run().unwrap();
    assert_eq!(report.value.to_bits(), expected.value.to_bits());
    let mine = positions(&engine);
    let kernel: Vec<[f64; 10]> = opt.chains().iter().map(|c| *c.x()).collect();
    assert_eq!(mine, kernel);
    for x in &mine {
        for (i, &v) in x.iter().enumerate() {
            assert!(sides[i].0 <= v && v <= sides[i].1, "x_{i} = {v}");
        }
    }

    // Equal pairs: the interval's run.
    let mut pairs = settings(rastrigin());
    pairs.domain = Some(BoxSpec::PerCoordinate(vec![(-5.0, 5.0); 10]));
    pairs.start = StartSpec::Box(BoxSpec::PerCoordinate(vec![(-5.0, 5.0); 10]));
    let mut uniform = settings(rastrigin());
    uniform.domain = Some(BoxSpec::Uniform { lo: -5.0, hi: 5.0 });
    uniform.start = StartSpec::Box(BoxSpec::Uniform { lo: -5.0, hi: 5.0 });
    let (mut a, mut b) = (pairs.build().unwrap(), uniform.build().unwrap());
    a.step(50).unwrap();
    b.step(50).unwrap();
    assert_eq!(positions(&a), positions(&b));
}

/// Auto runs in a box per coordinate (sides that differ by 10^6 here):
/// every point it returns is inside, and equal pairs give the bits of one
/// interval.
#[test]
fn auto_runs_in_a_box_per_coordinate() {
    let problem = |domain| Problem {
        potential: rastrigin(),
        domain,
        budget: 2_000,
        seed: 1,
        chains: Some(4),
        dim: None,
        x0: None,
        target: None,
        stall: None,
        rounds: None,
        converge: None,
        soft: None,
    };
    let sides = wide_and_narrow();
    let found = solve(
        &Auto::default(),
        &problem(BoxSpec::PerCoordinate(sides.clone())),
        &mut |_| ControlFlow::Continue(()),
    )
    .unwrap();
    assert_eq!(found.x.len(), 10);
    for (x, (lo, hi)) in found.x.iter().zip(&sides) {
        assert!(lo <= x && x <= hi, "{x} outside [{lo}, {hi}]");
    }
    let equal = solve(
        &Auto::default(),
        &problem(BoxSpec::PerCoordinate(vec![(-5.0, 5.0); 10])),
        &mut |_| ControlFlow::Continue(()),
    )
    .unwrap();
    let mut uniform = problem(BoxSpec::Uniform { lo: -5.0, hi: 5.0 });
    uniform.dim = Some(10);
    let one = solve(&Auto::default(), &uniform, &mut |_| {
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(equal, one);
}

/// Auto at a dimension no table lists (17, 257) runs, and at 17 gives the
/// bits of the kernel's `Auto` over `Chain<f64, 17>` with the layer's
/// L-BFGS memory (two pairs a coordinate: 34).
#[test]
fn auto_runs_at_any_dimension() {
    let mut chains: Vec<Chain<f64, 17>> = (0..4).map(|_| Chain::new()).collect();
    let mut lbfgs: Lbfgs<f64, 17, 34> = Lbfgs::new();
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let kernel = Auto::default()
        .minimize(
            &hrla::Problem::new(&Rastrigin, &domain, 5_000).seed(2),
            (&mut chains[..], &mut lbfgs),
        )
        .unwrap();
    for d in [17, 257] {
        let problem = Problem {
            potential: rastrigin(),
            domain: domain.into(),
            budget: 5_000,
            seed: 2,
            chains: Some(4),
            dim: Some(d),
            x0: None,
            target: None,
            stall: None,
            rounds: None,
            converge: None,
            soft: None,
        };
        let s = solve(&Auto::default(), &problem, &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
        assert_eq!(s.x.len(), d);
        assert!(s.evaluations <= 5_000);
        if d == 17 {
            assert_eq!(s.x, kernel.x);
            assert_eq!(s.value.to_bits(), kernel.value.to_bits());
            assert_eq!(s.message, kernel.to_string());
        }
    }
}

/// `x0` is chain 0's start in the layer as in the kernel (the same bits
/// as `Auto::minimize` from `x0` over `Chain<f64, 17>` and 34 pairs of
/// L-BFGS memory), and its length fixes
/// the dimension like the box's does.
#[test]
fn auto_starts_chain_0_at_x0() {
    let mut chains: Vec<Chain<f64, 17>> = (0..4).map(|_| Chain::new()).collect();
    let mut lbfgs: Lbfgs<f64, 17, 34> = Lbfgs::new();
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let x0: [f64; 17] = std::array::from_fn(|i| 0.25 * i as f64 - 2.0);
    let kernel = Auto::default()
        .minimize_with(
            &hrla::Problem::new(&Rastrigin, &domain, 5_000)
                .seed(2)
                .x0(&x0),
            (&mut chains[..], &mut lbfgs),
            |_| ControlFlow::Continue(()),
        )
        .unwrap();
    let mut problem = Problem {
        potential: rastrigin(),
        domain: domain.into(),
        budget: 5_000,
        seed: 2,
        chains: Some(4),
        dim: None,
        x0: Some(x0.to_vec()),
        target: None,
        stall: None,
        rounds: None,
        converge: None,
        soft: None,
    };
    let s = solve(&Auto::default(), &problem, &mut |_| {
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(s.x, kernel.x);
    assert_eq!(s.value.to_bits(), kernel.value.to_bits());
    assert_eq!(s.message, kernel.to_string());
    problem.dim = Some(16);
    let got = solve(&Auto::default(), &problem, &mut |_| {
        ControlFlow::Continue(())
    });
    assert!(
        matches!(
            got,
            Err(Error::DimensionMismatch {
                other: "x0",
                other_dim: 17,
                ..
            })
        ),
        "{got:?}"
    );
}

#[test]
fn auto_is_the_kernels() {
    let mut chains: Vec<Chain<f64, 10>> = (0..8).map(|_| Chain::new()).collect();
    // The layer's memory at d = 10: two pairs a coordinate.
    let mut lbfgs: Lbfgs<f64, 10, 20> = Lbfgs::new();
    let domain = Interval::new(-5.12, 5.12).unwrap();
    let kernel = Auto::default()
        .minimize(
            &hrla::Problem::new(&Rastrigin, &domain, 20_000).seed(3),
            (&mut chains[..], &mut lbfgs),
        )
        .unwrap();
    for potential in [rastrigin_as(false), rastrigin_as(true)] {
        let problem = Problem {
            potential,
            domain: domain.into(),
            budget: 20_000,
            seed: 3,
            chains: Some(8),
            dim: Some(10),
            x0: None,
            target: None,
            stall: None,
            rounds: None,
            converge: None,
            soft: None,
        };
        let s = solve(&Auto::default(), &problem, &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
        assert_eq!(s.x, kernel.x);
        assert_eq!(s.value.to_bits(), kernel.value.to_bits());
        assert_eq!(s.evaluations, kernel.evaluations);
        assert_eq!(s.message, kernel.to_string());
    }
}

/// Rastrigin as a Rust function of one point.
struct Native;

impl hrla_dyn::PointFunction for Native {
    fn value_and_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let x: &[f64; 10] = x.try_into().unwrap();
        let g: &mut [f64; 10] = grad.try_into().unwrap();
        Rastrigin.value_and_gradient(x, g)
    }
}

#[test]
fn a_native_function_runs_as_a_builtin() {
    let (report, x) = kernel_run();
    let mut engine = settings(PotentialSpec::Native(Arc::new(Native)))
        .build()
        .unwrap();
    assert!(!engine.is_user());
    let ours = engine
        .run(hrla::Observe::EveryAndNewBest(1000), &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(ours, report);
    assert_eq!(positions(&engine), x);
}

/// A step far too long (h = 1): the chains grow geometrically with
/// finite values, so the kernel sees no divergence; with an escape radius
/// the run fails at the first step where every chain is beyond it, whether
/// stepped or run, and keeps failing.
#[test]
fn every_chain_beyond_the_escape_radius_fails_the_run() {
    let mut s = settings(rastrigin());
    s.sampler = AnySampler::paper(SamplerKind::Hrla, 1.0).unwrap();
    s.dim = Some(2);
    s.chains = 16;
    s.start = StartSpec::Gaussian {
        mean: vec![3.0, 3.0],
        std_dev: 0.5,
    };
    s.stop = Stop::new().steps(10_000);
    s.escape = Some(5000.0);
    let mut stepped = s.build().unwrap();
    let Err(Error::RanAway(away)) = stepped.step(10_000) else {
        panic!("the chains must run away");
    };
    let at = stepped.iteration();
    assert!(at > 1 && at < 1000, "failed at {at}");
    assert_eq!((away.chains, away.radius, away.diverged), (16, 5000.0, 0));
    assert!(away.farthest > 5000.0 && away.farthest.is_finite());
    for x in stepped.positions().chunks_exact(2) {
        assert!(x[0].hypot(x[1]) > 5000.0);
    }
    assert!(matches!(stepped.step(1), Err(Error::RanAway(a)) if a == away));
    let mut run = s.build().unwrap();
    let Err(Error::RanAway(same)) = run.run(hrla::Observe::EveryAndNewBest(1), &mut |_| {
        ControlFlow::Continue(())
    }) else {
        panic!("run must fail the same way");
    };
    assert_eq!((same, run.iteration()), (away, at));
    assert!(run.report_now().is_none());
    // Without a radius the same run goes on; a radius must be positive.
    s.escape = None;
    assert!(s.build().unwrap().step(at + 10).is_ok());
    s.escape = Some(-1.0);
    assert!(matches!(s.build().err(), Some(Error::Kernel(_))));
}

/// At a dimension outside the compiled table, the engine's run-time starts
/// (a Gaussian, a point) and quadratic give the kernel's const-generic
/// bits: the same draws, the same values, the same positions.
#[test]
fn a_run_at_d17_is_the_kernels_const_run() {
    const D: usize = 17;
    let centre: [f64; D] = std::array::from_fn(|i| 0.25 * i as f64 - 1.0);
    let mean: [f64; D] = std::array::from_fn(|i| 3.0 - 0.5 * i as f64);
    let point: [f64; D] = std::array::from_fn(|i| 0.1 * i as f64);
    let quadratic = BuiltinSpec::Quadratic {
        stiffness: 2.5,
        centre: centre.to_vec(),
    };
    let cases = [
        (
            rastrigin(),
            StartSpec::Gaussian {
                mean: mean.to_vec(),
                std_dev: 1.5,
            },
        ),
        (
            PotentialSpec::Builtin(quadratic),
            StartSpec::Point(point.to_vec()),
        ),
    ];
    for (i, (potential, start)) in cases.into_iter().enumerate() {
        let mut s = settings(potential);
        s.start = start;
        s.dim = Some(D);
        let mut engine = s.build().unwrap();
        let ours = engine
            .run(hrla::Observe::NewBest, &mut |_| ControlFlow::Continue(()))
            .unwrap();

        let chains: Vec<Chain<f64, D>> = (0..6).map(|_| Chain::new()).collect();
        let (sampler, schedule, stop) = (
            AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
            AnySchedule::Constant(Constant::new(4.0).unwrap()),
            Stop::new().steps(200),
        );
        let (expected, x): (hrla::Report<f64>, Vec<f64>) = if i == 0 {
            let start = Gaussian::new(mean, 1.5).unwrap();
            let mut opt = Builder::new(Rastrigin, sampler, schedule, start)
                .seed(7)
                .stop(stop)
                .build(chains)
                .unwrap();
            let r = opt.run().unwrap();
            (r, opt.chains().iter().flat_map(|c| *c.x()).collect())
        } else {
            let potential = hrla::Quadratic::new(2.5, centre).unwrap();
            let start = hrla::Point::new(point).unwrap();
            let mut opt = Builder::new(potential, sampler, schedule, start)
                .seed(7)
                .stop(stop)
                .build(chains)
                .unwrap();
            let r = opt.run().unwrap();
            (r, opt.chains().iter().flat_map(|c| *c.x()).collect())
        };
        assert_eq!(ours, expected, "case {i}");
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&engine.positions()), bits(&x), "case {i}");
    }
}
