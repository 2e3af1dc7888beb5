//! `AnySampler` and `AnySchedule` are pure delegation: the same numbers, bit
//! for bit, as the sampler or schedule they wrap.
//!
//! The wrappers exist so that a caller can pick a sampler or schedule at
//! run time; that choice must give exactly the run the concrete type gives,
//! so a wrong or missing forward (a swapped arm, a default method left in
//! place) is caught here rather than as a slightly different result.

use hrla::{
    AnySampler, AnySchedule, Constant, Error, Geometric, Hrla, HrlaParams, Kernel, Linear, Ola,
    OlaParams, Sampler, SamplerKind, Schedule, Ula, UlaParams,
};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// 50 steps, each at its own inverse temperature, as bits: the positions
/// and velocities after every step, then every kernel's `a` and moments.
fn steps<S: Sampler<f64>>(s: S) -> Vec<u64> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let (mut x, mut y, g) = ([0.3, -1.2, 2.0], [0.0; 3], [1.0, -0.5, 0.25]);
    let mut out = Vec::new();
    for k in 0..50 {
        let kernel = s.at(1.0 + k as f64 / 10.0).unwrap();
        kernel.step(&mut x, &mut y, &g, &mut rng);
        out.extend(x.iter().chain(&y).map(|v| v.to_bits()));
        let m = kernel.moments(x[0], y[0], g[0]);
        out.extend(
            [
                kernel.inverse_temperature(),
                m.mean_x,
                m.mean_y,
                m.var_x,
                m.cov_xy,
                m.var_y,
            ]
            .map(f64::to_bits),
        );
    }
    out
}

#[test]
fn any_sampler_is_the_sampler_it_wraps() {
    let h = 0.01;
    for kind in SamplerKind::ALL {
        let any = AnySampler::paper(kind, h).unwrap();
        assert_eq!(any.kind(), kind);
        let direct = match kind {
            SamplerKind::Hrla => steps(Hrla::new(HrlaParams::paper(h)).unwrap()),
            SamplerKind::Ula => steps(Ula::new(UlaParams::paper(h)).unwrap()),
            SamplerKind::Ola => steps(Ola::new(OlaParams::paper(h)).unwrap()),
        };
        assert_eq!(steps(any), direct, "{}", kind.name());
        assert!(AnySampler::paper(kind, f64::NAN).is_err());
        // A refused temperature is the wrapped sampler's error.
        for a in [0.0, f64::INFINITY, 5e-324] {
            let direct = match kind {
                SamplerKind::Hrla => Hrla::paper(h).unwrap().at(a).map(|_| ()),
                SamplerKind::Ula => Ula::paper(h).unwrap().at(a).map(|_| ()),
                SamplerKind::Ola => Ola::paper(h).unwrap().at(a).map(|_| ()),
            };
            assert_eq!(any.at(a).map(|_| ()), direct, "{} at a = {a}", kind.name());
        }
    }
}

/// Sampler names: `Display` gives the lower-case name, `FromStr` takes it
/// back in any ASCII case, and an unknown name is `Error::Unknown` listing
/// the known ones.
#[test]
fn sampler_kind_names_round_trip() {
    let names: Vec<String> = SamplerKind::ALL.iter().map(|k| k.to_string()).collect();
    assert_eq!(names, ["hrla", "ula", "ola"]);
    for kind in SamplerKind::ALL {
        assert_eq!(kind.to_string(), kind.name());
        assert_eq!(kind.name().parse::<SamplerKind>(), Ok(kind));
        let upper = kind.name().to_ascii_uppercase();
        assert_eq!(upper.parse::<SamplerKind>(), Ok(kind));
    }
    assert_eq!("Ula".parse::<SamplerKind>(), Ok(SamplerKind::Ula));
    for bad in ["", " ola", "ola ", "hrla2", "mala"] {
        assert_eq!(
            bad.parse::<SamplerKind>(),
            Err(Error::Unknown {
                what: "sampler",
                expected: " hrla ula ola",
            }),
            "{bad:?}"
        );
    }
    let e = "mala".parse::<SamplerKind>().unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown sampler; expected one of: hrla ula ola"
    );
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
