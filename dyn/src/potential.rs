//! The kernel's built-in potentials, declared once.
//!
//! [`for_each_builtin!`](crate::for_each_builtin) holds the list of the
//! built-ins without parameters (the kernel's unit structs), each with its
//! name and its description; [`BuiltinKind`], [`Builtin`] and the front
//! ends' own lists (Python's classes, the page's menu through wasm) are
//! generated from it. Registering a parameter-free built-in is one entry
//! there. The one built-in with parameters, the quadratic bowl, is written
//! out beside the list.

use core::fmt;
use core::str::FromStr;

use hrla::{KnownMinimum, Potential, Quadratic, SlicePotential};

use crate::Error;

/// Calls `$callback! { ... }` with the list of the kernel's parameter-free
/// built-in potentials, in the order the page lists them: for each, its
/// description (doc comments), the kernel's type (its name is the
/// variant's and the Python class's) and its name as settings and the page
/// spell it.
///
/// ```
/// macro_rules! names {
///     ($( $(#[$doc:meta])* $variant:ident = $name:literal ),+ $(,)?) => {
///         [$($name),+]
///     };
/// }
/// let names = hrla_dyn::for_each_builtin!(names);
/// assert_eq!(names[0], "rastrigin");
/// ```
#[macro_export]
macro_rules! for_each_builtin {
    ($callback:ident) => {
        $callback! {
            /// Rastrigin in the paper's form: `U(x) = D + |x|^2 - sum_i cos(2π x_i)`,
            /// `∇U(x) = 2x + 2π sin(2π x)`; `U* = 0` at `x* = 0`.
            Rastrigin = "rastrigin",
            /// Ackley's function with `(20, 0.2, 2π)`; `U* = 0` at `x* = 0`.
            Ackley = "ackley",
            /// Levy's function, `w_i = 1 + (x_i - 1)/4`:
            /// `sin^2(π w_1) + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(π w_i + 1))
            /// + (w_D - 1)^2 (1 + sin^2(2π w_D))`; `U* = 0` at `x* = 1`.
            Levy = "levy",
            /// Styblinski–Tang, `U(x) = (1/2) sum_i (x_i^4 - 16 x_i^2 + 5 x_i)`;
            /// `U* ≈ -39.166 D` at `x_i ≈ -2.9035`.
            StyblinskiTang = "styblinski-tang",
            /// The separable double well `U(x) = sum_i (x_i^2 - 1)^2`; `U* = 0` at
            /// every `x_i = ±1`.
            DoubleWell = "double-well",
        }
    };
}

/// The name of the quadratic bowl, the built-in with parameters.
const QUADRATIC: &str = "quadratic";

macro_rules! define_builtins {
    ($( $(#[$doc:meta])* $variant:ident = $name:literal ),+ $(,)?) => {
        /// The kernel's built-in potentials, by name: parsed from and
        /// displayed as the name the settings use (`"styblinski-tang"`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum BuiltinKind {
            $( $(#[$doc])* $variant, )+
            /// The isotropic quadratic `U(x) = (k/2) |x - m|^2` (by name:
            /// `k = 1`, `m = 0`); `exp(-a U)` is `N(m, I/(a k))`.
            Quadratic,
        }

        impl BuiltinKind {
            /// All of them, in the order the page lists them.
            pub const ALL: [BuiltinKind; 1 $(+ { let _ = stringify!($variant); 1 })+] =
                [$(BuiltinKind::$variant,)+ BuiltinKind::Quadratic];

            /// Every name, in the order of [`BuiltinKind::ALL`].
            pub const NAMES: [&'static str; BuiltinKind::ALL.len()] = {
                let mut names = [""; BuiltinKind::ALL.len()];
                let mut i = 0;
                while i < names.len() {
                    names[i] = BuiltinKind::ALL[i].name();
                    i += 1;
                }
                names
            };

            /// The name settings use: `"rastrigin"`, `"double-well"`, ...
            pub const fn name(self) -> &'static str {
                match self {
                    $( BuiltinKind::$variant => $name, )+
                    BuiltinKind::Quadratic => QUADRATIC,
                }
            }

            /// The kernel's type name: `"Rastrigin"`, `"DoubleWell"`, ...
            pub const fn title(self) -> &'static str {
                match self {
                    $( BuiltinKind::$variant => stringify!($variant), )+
                    BuiltinKind::Quadratic => "Quadratic",
                }
            }
        }

        /// A built-in potential in dimension `D`, as one type: the match per
        /// evaluation is outside the loop over coordinates and perfectly
        /// predicted, and each arm is the kernel's own implementation, so
        /// the numbers are the kernel's, bit for bit.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Builtin<const D: usize> {
            $( $(#[$doc])* $variant(hrla::$variant), )+
            /// [`Quadratic`].
            Quadratic(Quadratic<f64, D>),
        }

        impl<const D: usize> Potential<f64, D> for Builtin<D> {
            #[inline]
            fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
                match self {
                    $( Self::$variant(p) => Potential::<f64, D>::value_and_gradient(p, x, grad), )+
                    Self::Quadratic(p) => Potential::<f64, D>::value_and_gradient(p, x, grad),
                }
            }
        }

        impl<const D: usize> KnownMinimum<f64, D> for Builtin<D> {
            fn global_minimum(&self) -> f64 {
                match self {
                    $( Self::$variant(p) => KnownMinimum::<f64, D>::global_minimum(p), )+
                    Self::Quadratic(p) => p.global_minimum(),
                }
            }

            fn global_minimiser(&self) -> [f64; D] {
                match self {
                    $( Self::$variant(p) => p.global_minimiser(), )+
                    Self::Quadratic(p) => p.global_minimiser(),
                }
            }
        }

        /// A built-in potential at a run-time dimension: each arm the
        /// kernel's own slice implementation, the quadratic restated over
        /// a `Vec` centre with the kernel's arithmetic (the same bits).
        #[derive(Clone, Debug, PartialEq)]
        pub(crate) enum DynBuiltin {
            $( $variant(hrla::$variant), )+
            Quadratic { stiffness: f64, centre: Vec<f64> },
        }

        impl SlicePotential<f64> for DynBuiltin {
            #[inline]
            fn value_and_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
                match self {
                    $( Self::$variant(p) => SlicePotential::value_and_gradient(p, x, grad), )+
                    Self::Quadratic { stiffness, centre } => {
                        // As `hrla::Quadratic`: the sum of (k r) r.
                        let mut kr2 = 0.0;
                        for ((gi, &xi), &mi) in grad.iter_mut().zip(x).zip(centre) {
                            let r = xi - mi;
                            *gi = stiffness * r;
                            kr2 += *gi * r;
                        }
                        0.5 * kr2
                    }
                }
            }

            fn dimension(&self) -> Option<usize> {
                match self {
                    Self::Quadratic { centre, .. } => Some(centre.len()),
                    _ => None,
                }
            }
        }

        impl DynBuiltin {
            /// The built-in `kind` in dimension `d` with its parameters by
            /// name (the quadratic: stiffness 1, centred at the origin).
            fn named(kind: BuiltinKind, d: usize) -> Self {
                match kind {
                    $( BuiltinKind::$variant => Self::$variant(hrla::$variant), )+
                    BuiltinKind::Quadratic => Self::Quadratic {
                        stiffness: 1.0,
                        centre: vec![0.0; d],
                    },
                }
            }
        }

        impl<const D: usize> Builtin<D> {
            /// The built-in `kind` with its parameters by name (the
            /// quadratic: stiffness 1, centred at the origin).
            pub fn named(kind: BuiltinKind) -> Self {
                match kind {
                    $( BuiltinKind::$variant => Self::$variant(hrla::$variant), )+
                    BuiltinKind::Quadratic => Self::Quadratic(
                        Quadratic::new(1.0, [0.0; D]).expect("the unit bowl is valid"),
                    ),
                }
            }

            /// Which built-in this is.
            pub fn kind(&self) -> BuiltinKind {
                match self {
                    $( Self::$variant(_) => BuiltinKind::$variant, )+
                    Self::Quadratic(_) => BuiltinKind::Quadratic,
                }
            }
        }
    };
}

crate::for_each_builtin!(define_builtins);

impl fmt::Display for BuiltinKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no built-in potential's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownPotential;

impl fmt::Display for UnknownPotential {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`potential` must be one of {}",
            BuiltinKind::NAMES.join(", ")
        )
    }
}

impl std::error::Error for UnknownPotential {}

impl FromStr for BuiltinKind {
    type Err = UnknownPotential;

    /// The name [`BuiltinKind::name`] gives, exactly.
    fn from_str(name: &str) -> Result<Self, UnknownPotential> {
        BuiltinKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or(UnknownPotential)
    }
}

/// A built-in potential whose dimension is not yet fixed.
#[derive(Clone, Debug, PartialEq)]
pub enum BuiltinSpec {
    /// A built-in with its parameters by name (the quadratic: stiffness 1,
    /// centred at the origin, in any dimension).
    Named(BuiltinKind),
    /// The quadratic `(k/2) |x - m|^2`; the centre's length fixes `D`.
    Quadratic {
        /// `k > 0`.
        stiffness: f64,
        /// `m`.
        centre: Vec<f64>,
    },
}

impl FromStr for BuiltinSpec {
    type Err = UnknownPotential;

    fn from_str(name: &str) -> Result<Self, UnknownPotential> {
        name.parse().map(Self::Named)
    }
}

impl BuiltinSpec {
    /// Which built-in it is.
    pub fn kind(&self) -> BuiltinKind {
        match self {
            Self::Named(k) => *k,
            Self::Quadratic { .. } => BuiltinKind::Quadratic,
        }
    }

    /// The dimension it fixes, if any.
    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Quadratic { centre, .. } => Some(centre.len()),
            Self::Named(_) => None,
        }
    }

    /// The kernel's potential in dimension `D`, its parameters checked by
    /// the kernel.
    pub fn build<const D: usize>(&self) -> Result<Builtin<D>, Error> {
        Ok(match self {
            Self::Named(kind) => Builtin::named(*kind),
            Self::Quadratic { stiffness, centre } => {
                let centre: [f64; D] = centre.as_slice().try_into().map_err(|_| Error::Length {
                    what: "the quadratic's centre",
                    len: centre.len(),
                    dim: D,
                })?;
                Builtin::Quadratic(Quadratic::new(*stiffness, centre)?)
            }
        })
    }

    /// Checks the parameters with the kernel's constructor, in the
    /// dimension the spec fixes (1 when it fixes none).
    pub fn check(&self) -> Result<(), Error> {
        self.at(self.dimension().unwrap_or(1)).map(drop)
    }

    /// The potential in dimension `d`, its parameters checked as the
    /// kernel's constructor checks them.
    pub(crate) fn at(&self, d: usize) -> Result<DynBuiltin, Error> {
        Ok(match self {
            Self::Named(kind) => DynBuiltin::named(*kind, d),
            Self::Quadratic { stiffness, centre } => {
                if centre.len() != d {
                    return Err(Error::Length {
                        what: "the quadratic's centre",
                        len: centre.len(),
                        dim: d,
                    });
                }
                // The kernel's checks of the stiffness, then of the centre.
                Quadratic::<f64, 1>::new(*stiffness, [0.0])?;
                if let Some(&value) = centre.iter().find(|m| !m.is_finite()) {
                    return Err(hrla::Error::NotFinite {
                        name: "centre",
                        value,
                    }
                    .into());
                }
                DynBuiltin::Quadratic {
                    stiffness: *stiffness,
                    centre: centre.clone(),
                }
            }
        })
    }

    /// `U` and `∇U` at the rows of `points` (`n x d`, row-major): `n`
    /// values and `n x d` gradients.
    pub fn evaluate(&self, d: usize, points: &[f64]) -> Result<(Vec<f64>, Vec<f64>), Error> {
        if d == 0 {
            return Err(hrla::Error::Zero { name: "dimension" }.into());
        }
        let p = self.at(d)?;
        let n = points.len() / d;
        let mut values = Vec::with_capacity(n);
        let mut grads = vec![0.0; n * d];
        for (row, g) in points.chunks_exact(d).zip(grads.chunks_exact_mut(d)) {
            values.push(SlicePotential::value_and_gradient(&p, row, g));
        }
        Ok((values, grads))
    }

    /// The global minimum `U*` and a global minimiser `x*` in dimension
    /// `d >= 1`. Every built-in's minimiser repeats one coordinate (the
    /// quadratic's is its centre) and its minimum is `d` times the
    /// one-dimensional one, so both come from the kernel's known minimum
    /// at `D = 1` (the bits of the kernel's at `D = d`: tested).
    pub fn minimum(&self, d: usize) -> Result<(f64, Vec<f64>), Error> {
        if d == 0 {
            return Err(hrla::Error::Zero { name: "dimension" }.into());
        }
        if let Self::Quadratic { centre, .. } = self {
            self.at(d)?;
            return Ok((0.0, centre.clone()));
        }
        let p = self.build::<1>()?;
        Ok((
            p.global_minimum() * d as f64,
            vec![p.global_minimiser()[0]; d],
        ))
    }
}

impl fmt::Display for BuiltinSpec {
    /// As a constructor call: `Rastrigin()`, `Quadratic(1, [0.0, 2.0])`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Quadratic { stiffness, centre } => {
                write!(f, "Quadratic({stiffness}, {centre:?})")
            }
            Self::Named(k) => write!(f, "{}()", k.title()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_minima_are_minima() {
        for kind in BuiltinKind::ALL {
            assert_eq!(kind.name().parse::<BuiltinKind>(), Ok(kind));
            assert_eq!(Builtin::<3>::named(kind).kind(), kind);
            let (u, x) = BuiltinSpec::Named(kind).minimum(3).unwrap();
            let (v, _) = BuiltinSpec::Named(kind).evaluate(3, &x).unwrap();
            assert!((v[0] - u).abs() < 1e-9, "{kind}: U(x*) = {} vs {u}", v[0]);
        }
        assert_eq!("sphere".parse::<BuiltinKind>(), Err(UnknownPotential));
        assert_eq!(
            UnknownPotential.to_string(),
            "`potential` must be one of rastrigin, ackley, levy, styblinski-tang, double-well, quadratic"
        );
        assert_eq!(BuiltinKind::ALL.len(), 6);
    }

    /// The known minima at a run-time `d` are the kernel's at `D = d`, bit
    /// for bit, in every dimension the kernel's tests use.
    #[test]
    fn minima_at_any_dimension_are_the_kernels() {
        fn at<const D: usize>() {
            for kind in BuiltinKind::ALL {
                let spec = match kind {
                    BuiltinKind::Quadratic => BuiltinSpec::Quadratic {
                        stiffness: 2.0,
                        centre: (0..D).map(|i| i as f64 - 1.5).collect(),
                    },
                    _ => BuiltinSpec::Named(kind),
                };
                let p = spec.build::<D>().unwrap();
                let (u, x) = spec.minimum(D).unwrap();
                assert_eq!(u.to_bits(), p.global_minimum().to_bits(), "{kind} {D}");
                assert_eq!(x, p.global_minimiser().to_vec(), "{kind} {D}");
            }
        }
        at::<1>();
        at::<2>();
        at::<3>();
        at::<7>();
        at::<17>();
        at::<20>();
        at::<50>();
        at::<100>();
        at::<257>();
    }

    /// The layer's evaluation is the kernel's, bit for bit.
    #[test]
    fn a_builtin_is_the_kernels_potential() {
        let x = [0.3, -1.7, 2.9];
        let (mut g1, mut g2) = ([0.0; 3], [0.0; 3]);
        let u1 = Builtin::<3>::named(BuiltinKind::Levy).value_and_gradient(&x, &mut g1);
        let u2 = hrla::Potential::value_and_gradient(&hrla::Levy, &x, &mut g2);
        assert_eq!(u1.to_bits(), u2.to_bits());
        assert_eq!(g1, g2);
        let (v, g) = BuiltinSpec::Named(BuiltinKind::Levy)
            .evaluate(3, &x)
            .unwrap();
        assert_eq!(v[0].to_bits(), u2.to_bits());
        assert_eq!(g, g2);
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        let q = BuiltinSpec::Quadratic {
            stiffness: -1.0,
            centre: vec![0.0; 2],
        };
        assert!(matches!(q.check(), Err(Error::Kernel(_))));
        let q = BuiltinSpec::Quadratic {
            stiffness: 1.0,
            centre: vec![0.0; 2],
        };
        assert!(q.check().is_ok());
        assert_eq!(
            q.build::<3>().unwrap_err().to_string(),
            "the quadratic's centre has 2 coordinates, the run 3"
        );
        assert!(matches!(
            BuiltinSpec::Named(BuiltinKind::Ackley).minimum(0),
            Err(Error::Kernel(hrla::Error::Zero { .. }))
        ));
        assert_eq!(q.to_string(), "Quadratic(1, [0.0, 0.0])");
        assert_eq!(
            BuiltinSpec::Named(BuiltinKind::DoubleWell).to_string(),
            "DoubleWell()"
        );
    }
}
