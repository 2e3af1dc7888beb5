//! A run gives the same bits on 1, 2, 3 and 7 threads, with any part size,
//! as on the calling thread alone: every chain's final state and running
//! best, the global best and its chain, the evaluation count and the
//! report, for each sampler, in f64 and f32, with chains that diverge and
//! with a failure (a potential unbounded below) that must be reported the
//! same way.

use hrla::{
    AnySampler, Builder, Chain, Float, FnPotential, Gaussian, Linear, Potential, Rastrigin,
    SamplerKind, Stop,
};
use hrla_threads::Threads;

const D: usize = 5;
const CHAINS: usize = 103;

/// Everything a run leaves, as bits.
fn fingerprint<F: Float>(chains: &[Chain<F, D>], report: &str, evaluations: u64) -> Vec<String> {
    let mut out: Vec<String> = chains
        .iter()
        .map(|c| {
            let bits = |v: &[F]| v.iter().map(|x| x.to_f64().to_bits()).collect::<Vec<_>>();
            format!(
                "{:?} {:?} {:?} {} {}",
                bits(c.x()),
                bits(c.y()),
                bits(c.best().x),
                c.best().value.to_f64().to_bits(),
                c.is_diverged()
            )
        })
        .collect();
    out.push(report.to_owned());
    out.push(evaluations.to_string());
    out
}

fn run<F: Float, P: Potential<F, D> + Sync>(
    potential: &P,
    kind: SamplerKind,
    h: f64,
    spread: f64,
    threads: Option<(usize, usize)>,
) -> Vec<String> {
    let mut chains: Vec<Chain<F, D>> = (0..CHAINS).map(|_| Chain::new()).collect();
    let start = Gaussian::new([F::from_f64(3.0); D], F::from_f64(spread)).unwrap();
    let schedule = Linear::new(F::from_f64(1.0), F::from_f64(4.0), 300).unwrap();
    let sampler = AnySampler::paper(kind, F::from_f64(h)).unwrap();
    let builder = Builder::new(potential, sampler, schedule, start)
        .seed(42)
        .stop(Stop::new().steps(300));
    let (report, evaluations) = match threads {
        None => {
            let mut opt = builder.build(&mut chains).unwrap();
            (opt.run(), opt.evaluations())
        }
        Some((n, part)) => {
            let mut opt = builder
                .executor(Threads::chains_per_part(part))
                .build(&mut chains)
                .unwrap();
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build();
            (pool.unwrap().install(|| opt.run()), opt.evaluations())
        }
    };
    let report = match report {
        Ok(r) => format!("{r:?}"),
        Err(e) => format!("error {e:?}"),
    };
    fingerprint(&chains, &report, evaluations)
}

fn check<F: Float, P: Potential<F, D> + Sync>(potential: &P, kind: SamplerKind, h: f64) {
    let serial = run::<F, P>(potential, kind, h, 3.0, None);
    for threads in [1, 2, 3, 7] {
        for part in [0, 1, 4, 10, 64] {
            let parallel = run::<F, P>(potential, kind, h, 3.0, Some((threads, part)));
            assert_eq!(serial, parallel, "{kind} {threads} threads, part {part}");
        }
    }
}

#[test]
fn any_thread_count_gives_the_serial_bits() {
    for kind in SamplerKind::ALL {
        check::<f64, _>(&Rastrigin, kind, 0.01);
        check::<f32, _>(&Rastrigin, kind, 0.01);
    }
}

#[test]
fn diverging_chains_and_failures_are_the_same_on_threads() {
    // A quadratic bowl with a hole: NaN beyond x[1] = 5, which the
    // chains' noise reaches now and then.
    let holed = FnPotential::new(|x: &[f64; D], g: &mut [f64; D]| {
        let mut u = 0.0;
        for (xi, gi) in x.iter().zip(g.iter_mut()) {
            u += 0.5 * (xi - 3.0) * (xi - 3.0);
            *gi = xi - 3.0;
        }
        if x[1] > 5.0 { f64::NAN } else { u }
    });
    let serial = run::<f64, _>(&holed, SamplerKind::Ula, 0.1, 0.3, None);
    let diverged = serial[..CHAINS]
        .iter()
        .filter(|c| c.ends_with("true"))
        .count();
    assert!(
        (1..CHAINS).contains(&diverged),
        "{diverged} of {CHAINS} chains diverged"
    );
    for threads in [2, 7] {
        assert_eq!(
            serial,
            run::<f64, _>(&holed, SamplerKind::Ula, 0.1, 0.3, Some((threads, 4)))
        );
    }
    // Unbounded below beyond x[0] = 4.5: the first such chain is reported.
    let pit = FnPotential::new(|x: &[f64; D], g: &mut [f64; D]| {
        let r = x[0];
        g.fill(0.0);
        if r > 4.5 {
            g[0] = -1.0;
            f64::NEG_INFINITY
        } else {
            g[0] = 2.0 * (r - 3.0);
            (r - 3.0) * (r - 3.0)
        }
    });
    let serial = run::<f64, _>(&pit, SamplerKind::Hrla, 0.5, 0.3, None);
    let report = &serial[CHAINS];
    assert!(report.starts_with("error UnboundedBelow"), "{report}");
    for threads in [2, 3, 7] {
        assert_eq!(
            serial,
            run::<f64, _>(&pit, SamplerKind::Hrla, 0.5, 0.3, Some((threads, 8)))
        );
    }
}
