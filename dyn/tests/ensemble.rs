//! The gradient-free ensemble through its public API: the functions it
//! is built for, its convergence rule, its bad inputs and its invariances.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use hrla_dyn::{Ensemble, EnsembleEnd, EnsembleRules, EnsembleSolution, Error, Progress};

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// Rastrigin's function: minimum 0 at the origin, a local minimum in
/// every cell of the integer lattice.
fn rastrigin(x: &[f64]) -> f64 {
    let s: f64 = x.iter().map(|t| t * t - 10.0 * (2.0 * PI * t).cos()).sum();
    10.0 * x.len() as f64 + s
}

fn run(
    f: impl Fn(&[f64]) -> f64,
    d: usize,
    budget: u64,
    seed: u64,
    settings: Ensemble,
) -> EnsembleSolution {
    let lo = vec![-5.0; d];
    let hi = vec![5.0; d];
    let values = |x: &[f64], d: usize, out: &mut [f64]| {
        for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
            *o = f(row);
        }
        Ok(())
    };
    settings
        .minimize(
            &lo,
            &hi,
            budget,
            seed,
            EnsembleRules::default(),
            values,
            |_: &Progress<'_>| ControlFlow::Continue(()),
        )
        .unwrap()
}

#[test]
fn a_rotated_ellipsoid_is_solved_and_the_run_converges_by_itself() {
    // Condition 1e4, rotated: what the whitened frame is for.
    let f = |x: &[f64]| {
        let (u, v) = (
            (x[0] + x[1]) / 2f64.sqrt() - 1.0,
            (x[0] - x[1]) / 2f64.sqrt() + 0.5,
        );
        u * u + 1e4 * v * v + x[2..].iter().map(|t| (t - 0.3) * (t - 0.3)).sum::<f64>()
    };
    let s = run(f, 5, 100_000, 1, Ensemble::default());
    assert!(s.value < 1e-10, "{s:?}");
    assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    assert!(s.evaluations < 100_000);
    // On one basin the first two restarts agree, the second with the
    // first's population (`P = 21` parameters at d = 5: 22 particles),
    // not twice it.
    assert_eq!((s.restarts, s.population), (1, 22), "{s:?}");
}

#[test]
fn one_restart_at_an_earlier_phases_point_converges() {
    // The ellipsoid's minimum handed over as an earlier phase's best
    // point: the first large restart that agrees there ends the run,
    // where alone it needs a second. A point elsewhere is no evidence.
    let f = |x: &[f64]| {
        let (u, v) = (x[0] + x[1] - 1.0, x[0] - x[1] + 0.5);
        u * u + 1e4 * v * v + x[2..].iter().map(|t| (t - 0.3) * (t - 0.3)).sum::<f64>()
    };
    let (lo, hi) = ([-5.0; 4], [5.0; 4]);
    let values = |x: &[f64], d: usize, out: &mut [f64]| {
        for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
            *o = f(row);
        }
        Ok(())
    };
    let go = |_: &Progress<'_>| ControlFlow::Continue(());
    let solve = |known_at: &[f64]| {
        let rules = EnsembleRules {
            known_at,
            ..EnsembleRules::default()
        };
        Ensemble::default()
            .minimize(&lo, &hi, 100_000, 1, rules, values, go)
            .unwrap()
    };
    let alone = solve(&[]);
    let handed = solve(&[0.25, 0.75, 0.3, 0.3]);
    let elsewhere = solve(&[0.25, 0.75, 0.3, 1.3]);
    for s in [&alone, &handed, &elsewhere] {
        assert!(s.value < 1e-10, "{s:?}");
        assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    }
    assert_eq!((alone.restarts, handed.restarts), (1, 0));
    assert!(handed.evaluations < alone.evaluations);
    assert_eq!(elsewhere, alone);
}

#[test]
fn restarts_that_agree_above_an_earlier_phases_best_do_not_converge() {
    // A slope to the corner (-5, -5) with a narrow well at (3, 3) that the
    // restarts do not find: alone, they agree at the corner and the run
    // converges there. Handed the well as an earlier phase's best, their
    // agreements lie above it and are no evidence: the run goes on.
    let f = |x: &[f64]| {
        let r2 = (x[0] - 3.0).powi(2) + (x[1] - 3.0).powi(2);
        x[0] + x[1] - 30.0 * (-r2 / (2.0 * 0.05 * 0.05)).exp()
    };
    let (lo, hi) = ([-5.0; 2], [5.0; 2]);
    let values = |x: &[f64], d: usize, out: &mut [f64]| {
        for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
            *o = f(row);
        }
        Ok(())
    };
    let go = |_: &Progress<'_>| ControlFlow::Continue(());
    let solve = |rules: EnsembleRules| {
        Ensemble::default()
            .minimize(&lo, &hi, 20_000, 1, rules, values, go)
            .unwrap()
    };
    let alone = solve(EnsembleRules::default());
    assert_eq!(alone.end, EnsembleEnd::Converged, "{alone:?}");
    assert_eq!(
        (alone.value, alone.x.as_slice()),
        (-10.0, &[-5.0, -5.0][..])
    );
    let well = [3.0, 3.0];
    let handed = solve(EnsembleRules {
        known: f(&well),
        known_at: &well,
        ..EnsembleRules::default()
    });
    assert_ne!(handed.end, EnsembleEnd::Converged, "{handed:?}");
    assert_eq!(handed.evaluations, 20_000, "{handed:?}");
}

#[test]
fn an_ill_conditioned_bowl_is_travelled_to_its_minimum() {
    // A discus of condition 1e6 at d = 10, rotated by a reflection and
    // centred off the origin: the ensemble contracts across the stiff
    // direction long before it reaches the minimum, so it must widen
    // while its mean travels.
    let d = 10;
    let f = |x: &[f64]| {
        let c = |i: usize| 3.0 - 0.6 * i as f64;
        let u: Vec<f64> = (0..d).map(|i| x[i] - c(i)).collect();
        let w = 1.0 / (d as f64).sqrt();
        let along = u.iter().sum::<f64>() * w;
        let y: Vec<f64> = u.iter().map(|ui| ui - 2.0 * along * w).collect();
        1e6 * y[0] * y[0] + y[1..].iter().map(|t| t * t).sum::<f64>()
    };
    let s = run(f, d, 60_000, 1, Ensemble::default());
    assert!(s.value < 1e-8, "{s:?}");
}

#[test]
fn local_restarts_find_a_weierstrass_minimum() {
    // Weierstrass's function (bbob's f16 unrotated, shifted): rugged at
    // every scale and periodic, with no bowl for a large ensemble's
    // model to follow. Its minima, 0, are reached by 7 of these 10
    // seeds with local restarts and by 1 without them.
    let d = 5;
    let term = |t: f64| {
        (0..12)
            .map(|k| 0.5f64.powi(k) * (2.0 * PI * 3f64.powi(k) * (t + 0.5)).cos())
            .sum::<f64>()
    };
    let f0 = term(0.0);
    let f = |x: &[f64]| {
        let s = x.iter().map(|&t| term(t - 0.37) - f0).sum::<f64>() / d as f64;
        10.0 * s * s * s
    };
    let reached = (1..=10)
        .filter(|&seed| run(f, d, 50_000, seed, Ensemble::default()).value < 1e-2)
        .count();
    assert!(reached >= 6, "{reached} of 10");
}

#[test]
fn a_search_around_the_best_point_finishes_its_basin() {
    // Schwefel's function, deceptive: its minimum lies near a corner,
    // far from the next best basins, so a large restart's best point
    // there is a lucky draw and the restart converges elsewhere. The
    // local restarts around the best point finish that basin.
    let schwefel = |x: &[f64]| {
        let s: f64 = x
            .iter()
            .map(|t| 100.0 * t * (100.0 * t.abs()).sqrt().sin())
            .sum();
        418.982_887_272_433_8 * x.len() as f64 - s
    };
    let reached = (1..=30)
        .filter(|&seed| run(schwefel, 2, 20_000, seed, Ensemble::default()).value < 1e-6)
        .count();
    // 27 of these 30 seeds reach the minimum, 7 without the searches
    // around the best point; 16 is more than three binomial standard
    // errors below 27 (1.6) and above 7 (2.3).
    assert!(reached >= 16, "{reached} of 30");
}

#[test]
fn a_narrow_valley_oblique_to_the_box_is_solved() {
    // A discus (condition 1e6) whose stiff axis is oblique to the box's
    // axes and whose minimum is off centre, so the ensemble meets the
    // walls while it narrows across the valley (module docs, "The
    // box's walls").
    let d = 10;
    let norm = (0..d)
        .map(|k| ((1 + k % 3) * (1 + k % 3)) as f64)
        .sum::<f64>()
        .sqrt();
    let axis: Vec<f64> = (0..d)
        .map(|k| if k % 2 == 0 { 1.0 } else { -1.0 } * (1 + k % 3) as f64 / norm)
        .collect();
    let centre: Vec<f64> = (0..d).map(|k| 3.0 * (1.7 * k as f64 + 0.5).sin()).collect();
    let discus = |x: &[f64]| {
        let y: Vec<f64> = x.iter().zip(&centre).map(|(x, c)| x - c).collect();
        1e6 * dot(&axis, &y).powi(2) + dot(&y, &y)
    };
    let reached = (1..=30)
        .filter(|&seed| run(discus, d, 20_000, seed, Ensemble::default()).value < 1e-8)
        .count();
    // All 30 of these seeds reach 1e-8, 13 with clipping alone; 22 is
    // three binomial standard errors (2.7) above 13.
    assert!(reached >= 22, "{reached} of 30");
}

#[test]
fn restarts_that_agree_on_symmetric_local_minima_do_not_converge() {
    // Rastrigin's function has 2 d local minima of value 0.995 around
    // its minimum, 0. Two restarts that end on two of them agree on
    // the value. 2 of these 30 seeds end there as converged and 27
    // reach 0. Were two restarts of any kind enough (and the walls
    // clipped alone), 8 would end there and 20 reach 0.
    let d = 4;
    let runs: Vec<_> = (1..=30)
        .map(|seed| run(rastrigin, d, 80_000, seed, Ensemble::default()))
        .collect();
    let wrong = runs
        .iter()
        .filter(|s| s.end == EnsembleEnd::Converged && s.value > 1e-6);
    let reached = runs.iter().filter(|s| s.value < 1e-6).count();
    assert!(wrong.count() <= 4, "{runs:?}");
    assert!(reached >= 22, "{reached} of 30");
}

#[test]
fn a_separable_function_is_solved_by_the_coordinate_scans() {
    // The 10-D Rastrigin (scipy's `dual_annealing` docstring example,
    // here in [-5, 5]^10): the restarts end with a few coordinates in a
    // neighbouring cell: without the scans these seeds end at 2.98, 3.98
    // and 2.98 after 20 000 calls. A scan along the axes from the best
    // point moves each coordinate to its own cell's floor.
    let d = 10;
    for seed in 1..=3 {
        let s = run(rastrigin, d, 20_000, seed, Ensemble::default());
        assert!(s.value < 1e-8, "{s:?}");
    }
}

#[test]
fn a_function_with_several_global_minima_converges() {
    // (x_i^2 - 1)^2 summed has its minimum, 0, at the 2^d corners of
    // [-1, 1]^d: restarts agree on the value at different points, and
    // the third that does ends the run.
    let f = |x: &[f64]| x.iter().map(|t| (t * t - 1.0).powi(2)).sum::<f64>();
    for seed in 1..=5 {
        let s = run(f, 3, 100_000, seed, Ensemble::default());
        assert!(s.value < 1e-12, "{s:?}");
        assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    }
}

#[test]
fn a_minimum_of_value_zero_at_a_cusp_converges() {
    // Ackley's f is 0 at its minimum and grows like |x| there: the
    // restarts end when their positions agree, their values still
    // spread far beyond 1e-12 of their mean, and must agree to that
    // spread.
    let ackley = |x: &[f64]| {
        let n = x.len() as f64;
        let (sq, cos) = x.iter().fold((0.0, 0.0), |(s, c), t| {
            (s + t * t, c + (2.0 * core::f64::consts::PI * t).cos())
        });
        -20.0 * (-0.2 * (sq / n).sqrt()).exp() - (cos / n).exp() + 20.0 + core::f64::consts::E
    };
    let s = run(ackley, 10, 150_000, 1, Ensemble::default());
    assert!(s.value < 1e-9, "{s:?}");
    assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
}

#[test]
fn a_minimum_on_the_boxs_boundary_converges() {
    // A slope's minimum is the box's corner, a bowl centred outside the
    // box in one coordinate has it on a face: the clipping pins the
    // particles that reach it there, and the restarts agree. Were the
    // particles on a wall that most of them hold to stop on their
    // paths rather than slide along it, the face's runs at d = 4
    // would freeze there and spend their budget.
    let slope = |x: &[f64]| x.iter().sum::<f64>();
    let s = run(slope, 5, 50_000, 1, Ensemble::default());
    assert_eq!(s.x, vec![-5.0; 5]);
    assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    let face =
        |x: &[f64]| (x[0] - 7.0).powi(2) + x[1..].iter().map(|t| (t - 0.3).powi(2)).sum::<f64>();
    for (d, seed) in [(5, 1), (4, 1), (4, 2), (4, 3)] {
        let s = run(face, d, 50_000, seed, Ensemble::default());
        assert_eq!(s.x[0], 5.0, "{s:?}");
        assert!((s.value - 4.0).abs() < 1e-9, "{s:?}");
        assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    }
}

#[test]
fn the_same_seed_gives_the_same_bits_and_a_longer_budget_extends_a_run() {
    let f = |x: &[f64]| {
        x.iter()
            .map(|t| t * t - 10.0 * (2.0 * core::f64::consts::PI * t).cos() + 10.0)
            .sum::<f64>()
    };
    let settings = Ensemble {
        converge: false,
        ..Ensemble::default()
    };
    let a = run(f, 4, 3_000, 9, settings);
    let b = run(f, 4, 3_000, 9, settings);
    assert_eq!(a, b);
    assert_eq!(a.evaluations, 3_000);
    assert_eq!(a.end, EnsembleEnd::Budget);
    // Nothing but the stop depends on the budget: the longer run's best
    // is at least as low.
    let c = run(f, 4, 6_000, 9, settings);
    assert!(c.value <= a.value);
    assert_ne!(run(f, 4, 3_000, 10, settings), a);
}

#[test]
fn bad_input_is_refused_and_a_failed_run_is_never_a_result() {
    let e = Ensemble::default();
    let none = EnsembleRules::default();
    let ok = |_: &[f64], _: usize, out: &mut [f64]| {
        out.fill(1.0);
        Ok(())
    };
    let go = |_: &Progress<'_>| ControlFlow::Continue(());
    assert!(e.minimize(&[0.0], &[0.0], 10, 0, none, ok, go).is_err());
    assert!(
        e.minimize(&[0.0, 0.0], &[1.0], 10, 0, none, ok, go)
            .is_err()
    );
    assert!(
        e.minimize(&[f64::NAN], &[1.0], 10, 0, none, ok, go)
            .is_err()
    );
    assert!(e.minimize(&[0.0], &[1.0], 0, 0, none, ok, go).is_err());
    assert!(
        e.minimize(&[0.0; 21], &[1.0; 21], 10, 0, none, ok, go)
            .is_err()
    );
    for bad in [
        Ensemble {
            spread: f64::NAN,
            ..e
        },
        Ensemble { cool: 0.5, ..e },
        Ensemble { cool_every: 0, ..e },
        Ensemble {
            population: 0.0,
            ..e
        },
    ] {
        assert!(bad.minimize(&[0.0], &[1.0], 10, 0, none, ok, go).is_err());
    }
    for known_at in [&[0.5, 0.5][..], &[f64::NAN]] {
        let rules = EnsembleRules { known_at, ..none };
        assert!(e.minimize(&[0.0], &[1.0], 10, 0, rules, ok, go).is_err());
    }
    let nan = |_: &[f64], _: usize, out: &mut [f64]| {
        out.fill(f64::NAN);
        Ok(())
    };
    assert!(matches!(
        e.minimize(&[0.0], &[1.0], 500, 0, none, nan, go),
        Err(Error::Kernel(hrla::Error::AllDiverged { .. }))
    ));
    let downhill = |x: &[f64], d: usize, out: &mut [f64]| {
        for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
            *o = if row[0] > 0.99 { -1e300 } else { -row[0] };
        }
        Ok(())
    };
    assert!(matches!(
        e.minimize(&[0.0], &[1.0], 500, 0, none, downhill, go),
        Err(Error::Kernel(hrla::Error::UnboundedBelow { .. }))
    ));
    let failing = |_: &[f64], _: usize, _: &mut [f64]| Err("no".into());
    assert!(matches!(
        e.minimize(&[0.0], &[1.0], 500, 0, none, failing, go),
        Err(Error::User(_))
    ));
    // A constant function: every restart agrees at once, each at another
    // point, so the third large one converges the run without spending
    // its budget: 205 calls, of which 52 in restarts (large ones of 8, 8
    // and 16 particles, a local one of 20) and 153 in one coordinate scan
    // after the second (64 points and two golden sections; module docs,
    // "Coordinate scans").
    let s = e.minimize(&[0.0], &[1.0], 10_000, 0, none, ok, go).unwrap();
    assert_eq!((s.value, s.end), (1.0, EnsembleEnd::Converged));
    assert!(s.evaluations < 250, "{s:?}");
}

#[test]
fn the_observer_sees_every_generation_and_can_stop_the_run() {
    let mut seen = Vec::new();
    let s = Ensemble::default()
        .minimize(
            &[-1.0; 2],
            &[1.0; 2],
            10_000,
            4,
            EnsembleRules::default(),
            |x: &[f64], d: usize, out: &mut [f64]| {
                for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
                    *o = dot(row, row);
                }
                Ok(())
            },
            |p: &Progress<'_>| {
                seen.push((p.iteration, p.evaluations, p.value));
                if p.iteration == 5 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
    assert_eq!(s.end, EnsembleEnd::Observer);
    assert_eq!(seen.len(), 5);
    assert!(seen.windows(2).all(|w| w[1].2 <= w[0].2 && w[1].1 > w[0].1));
    assert_eq!(
        (s.generations, s.evaluations, s.value),
        (seen[4].0, seen[4].1, seen[4].2)
    );
}

#[test]
fn a_particle_that_did_not_move_is_not_evaluated_again() {
    // A slope's minimum is the box's corner, where the particles that
    // reach it stay, clipped: each keeps its value, and the generations
    // that follow ask `U` only at the particles that moved.
    let mut asked = 0_u64;
    let mut generations = Vec::new();
    let s = Ensemble::default()
        .minimize(
            &[-5.0; 3],
            &[5.0; 3],
            50_000,
            1,
            EnsembleRules::default(),
            |x: &[f64], d: usize, out: &mut [f64]| {
                for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
                    *o = row.iter().sum::<f64>();
                }
                asked += (x.len() / d) as u64;
                Ok(())
            },
            |p: &Progress<'_>| {
                generations.push((p.evaluations, p.chains as u64));
                ControlFlow::Continue(())
            },
        )
        .unwrap();
    assert_eq!(s.x, vec![-5.0; 3]);
    assert_eq!(s.end, EnsembleEnd::Converged, "{s:?}");
    assert_eq!(asked, s.evaluations);
    // Some generations asked fewer points than they have particles.
    let short = generations
        .windows(2)
        .filter(|w| w[1].0 - w[0].0 < w[1].1)
        .count();
    assert!(short > 0, "{generations:?}");
    let total: u64 = generations.iter().map(|g| g.1).sum();
    assert!(s.evaluations < total, "{} of {total}", s.evaluations);
}

#[test]
fn the_callers_rules_end_the_run_counting_the_earlier_phase() {
    let bowl = |x: &[f64], d: usize, out: &mut [f64]| {
        for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
            *o = dot(row, row);
        }
        Ok(())
    };
    let go = |_: &Progress<'_>| ControlFlow::Continue(());
    let e = Ensemble::default();
    let end = |rules| {
        let s = e
            .minimize(&[-1.0; 3], &[1.0; 3], 100_000, 2, rules, bowl, go)
            .unwrap();
        (s.end, s.generations)
    };
    let none = EnsembleRules::default();
    // A target an earlier phase already met ends the run at its first look.
    let known = EnsembleRules {
        target: Some(0.5),
        known: 0.25,
        ..none
    };
    assert_eq!(end(known), (EnsembleEnd::Target, 1));
    assert_eq!(
        end(EnsembleRules {
            target: Some(1e-6),
            ..none
        })
        .0,
        EnsembleEnd::Target
    );
    // No fall exceeds inf: stalled once the window is done, counting
    // the earlier phase's iterations.
    let stall = |window, elapsed| EnsembleRules {
        stall: Some((window, f64::INFINITY)),
        elapsed,
        ..none
    };
    assert_eq!(end(stall(1, 0)), (EnsembleEnd::Stalled, 1));
    assert_eq!(end(stall(3, 0)), (EnsembleEnd::Stalled, 3));
    assert_eq!(end(stall(3, 2)), (EnsembleEnd::Stalled, 1));
    // A tolerance of 0 on a bowl: the best falls every generation
    // until rounding, so the run does not stall early.
    let strict = EnsembleRules {
        stall: Some((5, 0.0)),
        ..none
    };
    assert!(end(strict).1 > 20);
    let cap = EnsembleRules {
        iterations: Some(7),
        elapsed: 4,
        ..none
    };
    assert_eq!(end(cap), (EnsembleEnd::Iterations, 3));
}

#[test]
fn decisions_are_invariant_to_the_units_of_u_and_of_the_box() {
    // U enters only through its ranks and through tolerances relative
    // to its own spread and size: U times c gives the same points, bit
    // for bit, and c times the values. A box scaled by a power of two
    // scales every position exactly, so the same decisions again.
    let rastrigin = |x: &[f64]| {
        7.5 + x
            .iter()
            .map(|t| {
                let u = t - 0.7;
                u * u - 10.0 * (2.0 * core::f64::consts::PI * u).cos() + 10.0
            })
            .sum::<f64>()
    };
    let go = |_: &Progress<'_>| ControlFlow::Continue(());
    let solve = |c: f64, s: f64| {
        let values = |x: &[f64], d: usize, out: &mut [f64]| {
            for (row, o) in x.chunks_exact(d).zip(out.iter_mut()) {
                let unscaled: Vec<f64> = row.iter().map(|v| v / s).collect();
                *o = c * rastrigin(&unscaled);
            }
            Ok(())
        };
        let (lo, hi) = ([-5.0 * s; 3], [5.0 * s; 3]);
        Ensemble::default()
            .minimize(&lo, &hi, 40_000, 10, EnsembleRules::default(), values, go)
            .unwrap()
    };
    let base = solve(1.0, 1.0);
    assert_eq!(base.end, EnsembleEnd::Converged, "{base:?}");
    for c in [1e-14, 1e-3, 1e14] {
        let other = solve(c, 1.0);
        assert_eq!(
            (&other.x, other.evaluations, other.end),
            (&base.x, base.evaluations, base.end)
        );
        assert!((other.value / c - base.value).abs() <= 1e-12 * base.value);
    }
    for s in [2f64.powi(-34), 2f64.powi(33)] {
        let other = solve(1.0, s);
        let x: Vec<f64> = other.x.iter().map(|v| v / s).collect();
        assert_eq!(
            (&x, other.evaluations, other.value),
            (&base.x, base.evaluations, base.value)
        );
    }
}
