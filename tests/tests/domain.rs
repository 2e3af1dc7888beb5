//! Box domains: reflection keeps every chain in the box without changing
//! what the sampler samples there, the polish stays in the box and finds a
//! minimum on a face, and bad boxes are refused.

use hrla::{
    AnySampler, Builder, Chain, Error, FnPotential, Interval, Lbfgs, PolishEnd, PolishSettings,
    Potential, SamplerKind, Stop,
};

/// `U = 0`: the law restricted to a box is uniform there.
fn flat() -> FnPotential<impl Fn(&[f64; 1], &mut [f64; 1]) -> f64> {
    FnPotential::new(|_: &[f64; 1], g: &mut [f64; 1]| {
        g[0] = 0.0;
        0.0
    })
}

/// On a flat potential in `[0, 1]`, each sampler's chains end uniform in
/// the box: 20 000 independent chains, 10 equal bins, Pearson's chi-square
/// with 9 degrees of freedom against 27.88, its 0.999 quantile (a correct
/// sampler fails one seed in a thousand; this seed is fixed). Every chain
/// stays in the box at every step.
#[test]
fn reflection_gives_the_uniform_law_of_the_box() {
    let n = 20_000;
    for kind in SamplerKind::ALL {
        let box01 = Interval::new(0.0, 1.0).unwrap();
        let mut chains: Vec<Chain<f64, 1>> = (0..n).map(|_| Chain::new()).collect();
        let mut opt = Builder::new(flat(), AnySampler::paper(kind, 0.05).unwrap(), 1.0, box01)
            .domain(box01)
            .seed(7)
            .build(&mut chains)
            .unwrap();
        for _ in 0..400 {
            opt.step().unwrap();
            assert!(opt.chains().iter().all(|c| (0.0..=1.0).contains(&c.x()[0])));
        }
        let mut bins = [0usize; 10];
        for c in opt.chains() {
            bins[((c.x()[0] * 10.0) as usize).min(9)] += 1;
        }
        let expected = n as f64 / 10.0;
        let chi2: f64 = bins
            .iter()
            .map(|&o| (o as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 27.88, "{kind}: chi2 = {chi2}, bins {bins:?}");
    }
}

/// Without a domain the same chains leave `[0, 1]`: the test above would
/// fail if the reflection did nothing.
#[test]
fn without_a_domain_chains_leave_the_box() {
    let mut chains: Vec<Chain<f64, 1>> = (0..1000).map(|_| Chain::new()).collect();
    let mut opt = Builder::new(
        flat(),
        AnySampler::paper(SamplerKind::Hrla, 0.05).unwrap(),
        1.0,
        Interval::new(0.0, 1.0).unwrap(),
    )
    .stop(Stop::new().steps(400))
    .build(&mut chains)
    .unwrap();
    opt.run().unwrap();
    let outside = opt
        .chains()
        .iter()
        .filter(|c| !(0.0..=1.0).contains(&c.x()[0]))
        .count();
    assert!(outside > 500, "{outside}");
}

/// `U = |x - c|^2` with `c` outside the box: the polish ends on the nearest
/// point of the box, and never evaluates outside it.
#[test]
fn polish_in_a_box_ends_on_the_face() {
    let outside_calls = std::cell::Cell::new(0);
    let bowl = FnPotential::new(|x: &[f64; 3], g: &mut [f64; 3]| {
        if x.iter().any(|v| !(-1.0..=1.0).contains(v)) {
            outside_calls.set(outside_calls.get() + 1);
        }
        let c = [2.0, 0.5, -3.0];
        let mut u = 0.0;
        for i in 0..3 {
            g[i] = 2.0 * (x[i] - c[i]);
            u += (x[i] - c[i]) * (x[i] - c[i]);
        }
        u
    });
    let mut lbfgs: Lbfgs<f64, 3, 5> = Lbfgs::new();
    let mut x = [0.0; 3];
    let domain = Interval::new(-1.0, 1.0).unwrap();
    let done = lbfgs
        .minimize_in(&bowl, &domain, &mut x, PolishSettings::new(200))
        .unwrap();
    assert_eq!(outside_calls.get(), 0);
    assert!(
        (x[0] - 1.0).abs() < 1e-12 && (x[1] - 0.5).abs() < 1e-6 && (x[2] + 1.0).abs() < 1e-12,
        "{x:?}"
    );
    // U at (1, 0.5, -1) = 1 + 0 + 4.
    assert!((done.value - 5.0).abs() < 1e-9, "{done:?}");
    assert_ne!(done.end, PolishEnd::Budget);
    assert_eq!(bowl.value(&x), done.value);
}

/// A box needs finite `lo < hi`.
#[test]
fn bad_boxes_are_refused() {
    assert!(matches!(
        Interval::new(1.0, 1.0),
        Err(Error::NotPositive {
            name: "hi - lo",
            ..
        })
    ));
    assert!(matches!(
        Interval::new(2.0, 1.0),
        Err(Error::NotPositive { .. })
    ));
    assert!(matches!(
        Interval::new(f64::NAN, 1.0),
        Err(Error::NotFinite { name: "lo", .. })
    ));
    assert!(matches!(
        Interval::new(0.0, f64::INFINITY),
        Err(Error::NotFinite { name: "hi", .. })
    ));
    assert!(matches!(
        Interval::new(-f64::MAX, f64::MAX),
        Err(Error::NotPositive { .. })
    ));
}
