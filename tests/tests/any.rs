//! `AnySampler` and `AnySchedule` are pure delegation: the same numbers, bit
//! for bit, as the sampler or schedule they wrap.
//!
//! The wrappers exist so that a caller can pick a sampler or schedule at
//! run time; that choice must give exactly the run the concrete type gives,
//! so a wrong or missing forward (a swapped arm, a default method left in
//! place) is caught here rather than as a slightly different result.

use hrla::{
    AnySampler, AnySchedule, Constant, Geometric, Hrla, HrlaParams, Linear, Ola, OlaParams,
    Sampler, SamplerKind, Schedule, Ula, UlaParams,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

fn steps<S: Sampler<f64>>(mut s: S) -> Vec<u64> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let (mut x, mut y, g) = ([0.3, -1.2, 2.0], [0.0; 3], [1.0, -0.5, 0.25]);
    let mut out = Vec::new();
    for k in 0..50 {
        s.set_inverse_temperature(1.0 + k as f64 / 10.0).unwrap();
        s.step(&mut x, &mut y, &g, &mut rng);
        out.extend(x.iter().chain(&y).map(|v| v.to_bits()));
    }
    out
}

#[test]
fn any_sampler_is_the_sampler_it_wraps() {
    let (a, h) = (4.0, 0.01);
    for kind in SamplerKind::ALL {
        let any = AnySampler::paper(kind, a, h).unwrap();
        assert_eq!(any.kind(), kind);
        let direct = match kind {
            SamplerKind::Hrla => steps(Hrla::new(HrlaParams::paper(a, h)).unwrap()),
            SamplerKind::Ula => steps(Ula::new(UlaParams::paper(a, h)).unwrap()),
            SamplerKind::Ola => steps(Ola::new(OlaParams::paper(a, h)).unwrap()),
        };
        assert_eq!(steps(any), direct, "{}", kind.name());
        assert!(AnySampler::paper(kind, a, f64::NAN).is_err());
    }
}

#[test]
fn any_schedule_is_the_schedule_it_wraps() {
    let c = Constant::new(2.0).unwrap();
    let l = Linear::new(0.1, 4.0, 100).unwrap();
    let g = Geometric::new(0.1, 4.0, 100).unwrap();
    for k in [0, 1, 37, 99, 100, 1000] {
        let same = |any: AnySchedule<f64>, s: &dyn Fn(u64) -> f64| {
            assert_eq!(any.inverse_temperature(k).to_bits(), s(k).to_bits());
        };
        same(AnySchedule::Constant(c), &|k| c.inverse_temperature(k));
        same(AnySchedule::Linear(l), &|k| l.inverse_temperature(k));
        same(AnySchedule::Geometric(g), &|k| g.inverse_temperature(k));
    }
}
