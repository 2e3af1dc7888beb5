//! The built-in samplers chosen at run time, by name: for a user interface,
//! a command line, or one optimiser type that serves them all.
//!
//! [`SamplerKind`], [`AnySampler`] and [`AnyKernel`] are generated from the
//! one list at the bottom of this file; registering a new sampler is one
//! line there.

use core::fmt;
use core::str::FromStr;

use rand_core::Rng;

use super::hrla::Hrla;
use super::ola::{Ola, OlaKernel};
use super::ou::OuKernel;
use super::traits::{ChainState, Kernel, Sampler, StepMoments};
use super::ula::Ula;
use crate::error::Error;
use crate::float::Float;
use crate::lockstep::{LANES, Xoshiro256Lanes};

macro_rules! samplers {
    ($( $(#[$doc:meta])* $variant:ident($sampler:ident, $kernel:ident) = $name:literal ),+ $(,)?) => {
        /// The built-in samplers, by name.
        ///
        /// Parsed from and displayed as its lower-case name:
        ///
        /// ```
        /// use hrla::SamplerKind;
        ///
        /// let kind: SamplerKind = "ULA".parse()?;
        /// assert_eq!(kind, SamplerKind::Ula);
        /// assert_eq!(kind.to_string(), "ula");
        /// # Ok::<(), hrla::Error>(())
        /// ```
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum SamplerKind {
            $( $(#[$doc])* $variant, )+
        }

        impl SamplerKind {
            /// All of them, in the paper's order of presentation.
            pub const ALL: [SamplerKind; 0 $(+ { let _ = stringify!($variant); 1 })+] =
                [$(SamplerKind::$variant),+];

            /// Every name, each after a space.
            const NAMES: &'static str = concat!($(" ", $name),+);

            /// Lower-case name: `"hrla"`, `"ula"`, ...
            pub fn name(self) -> &'static str {
                match self {
                    $( SamplerKind::$variant => $name, )+
                }
            }
        }

        /// One of the built-in samplers, chosen at run time. The match per
        /// step is perfectly predicted and costs nothing measurable next to
        /// the normals of a step.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum AnySampler<F> {
            $( $(#[$doc])* $variant($sampler<F>), )+
        }

        /// The step of an [`AnySampler`] at one inverse temperature.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum AnyKernel<F> {
            $( $(#[$doc])* $variant($kernel<F>), )+
        }

        impl<F: Float> AnySampler<F> {
            /// `kind` in the paper's setting at step `h`.
            pub fn paper(kind: SamplerKind, h: F) -> Result<Self, Error> {
                Ok(match kind {
                    $( SamplerKind::$variant => Self::$variant($sampler::paper(h)?), )+
                })
            }

            /// Which sampler this is.
            pub fn kind(&self) -> SamplerKind {
                match self {
                    $( Self::$variant(_) => SamplerKind::$variant, )+
                }
            }
        }

        impl<F: Float> Sampler<F> for AnySampler<F> {
            type Kernel = AnyKernel<F>;

            fn at(&self, a: F) -> Result<AnyKernel<F>, Error> {
                Ok(match self {
                    $( Self::$variant(s) => AnyKernel::$variant(s.at(a)?), )+
                })
            }
        }

        impl<F: Float> Kernel<F> for AnyKernel<F> {
            fn inverse_temperature(&self) -> F {
                match self {
                    $( Self::$variant(k) => k.inverse_temperature(), )+
                }
            }

            fn moments(&self, x: F, y: F, g: F) -> StepMoments<F> {
                match self {
                    $( Self::$variant(k) => k.moments(x, y, g), )+
                }
            }

            #[inline]
            fn step<R: Rng + ?Sized, const D: usize>(
                &self,
                x: &mut [F; D],
                y: &mut [F; D],
                grad: &[F; D],
                rng: &mut R,
            ) {
                match self {
                    $( Self::$variant(k) => k.step(x, y, grad, rng), )+
                }
            }

            #[inline]
            fn step_slice<R: Rng + ?Sized>(&self, x: &mut [F], y: &mut [F], grad: &[F], rng: &mut R) {
                match self {
                    $( Self::$variant(k) => k.step_slice(x, y, grad, rng), )+
                }
            }

            #[inline]
            fn step_lanes_slice(&self, chains: [ChainState<'_, [F]>; LANES], rng: &mut Xoshiro256Lanes) {
                match self {
                    $( Self::$variant(k) => k.step_lanes_slice(chains, rng), )+
                }
            }

            #[inline]
            fn step_lanes<const D: usize>(
                &self,
                chains: [ChainState<'_, [F; D]>; LANES],
                rng: &mut Xoshiro256Lanes,
            ) {
                match self {
                    $( Self::$variant(k) => k.step_lanes(chains, rng), )+
                }
            }
        }
    };
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SamplerKind {
    type Err = Error;

    /// The name [`SamplerKind::name`] gives, in any ASCII case.
    fn from_str(s: &str) -> Result<Self, Error> {
        SamplerKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
            .ok_or(Error::Unknown {
                what: "sampler",
                expected: SamplerKind::NAMES,
            })
    }
}

samplers! {
    /// [`Hrla`], the paper's method.
    Hrla(Hrla, OuKernel) = "hrla",
    /// [`Ula`], the underdamped baseline.
    Ula(Ula, OuKernel) = "ula",
    /// [`Ola`], the overdamped baseline.
    Ola(Ola, OlaKernel) = "ola",
}
