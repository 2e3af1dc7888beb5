//! A run as plain values, before its dimension is fixed.

use std::ops::ControlFlow;
use std::sync::Arc;

use hrla::rand_core::Rng;
use hrla::{
    AnySampler, AnySchedule, BatchPotential, Constant, Domain, Geometric, Interval, Linear,
    SlicePotential, StandardNormal, Start, Stop,
};

use crate::Error;
use crate::potential::{BuiltinSpec, DynBuiltin};
use crate::user::{BatchFunction, UserBatch};

/// The potential of a run: a built-in, or a user's function.
#[derive(Clone)]
pub enum PotentialSpec {
    /// One of the kernel's built-ins, run with no foreign code in the loop.
    Builtin(BuiltinSpec),
    /// A user's function, called on batches of points.
    User(Arc<dyn BatchFunction>),
    /// A Rust function of one point, run like a built-in (no foreign
    /// runtime to call back into): a formula a front end reads, say.
    Native(Arc<dyn PointFunction>),
}

/// A potential given as a Rust function of one point.
pub trait PointFunction: Send + Sync {
    /// `U(x)`, with `∇U(x)` written to `grad`; `x.len() == grad.len()`,
    /// the run's dimension.
    fn value_and_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64;

    /// The dimension it fixes, if any.
    fn dimension(&self) -> Option<usize> {
        None
    }
}

impl PotentialSpec {
    /// The dimension it fixes, if any.
    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Builtin(b) => b.dimension(),
            Self::User(_) => None,
            Self::Native(f) => f.dimension(),
        }
    }

    pub(crate) fn build(&self, d: usize) -> Result<Pot, Error> {
        Ok(match self {
            Self::Builtin(b) => Pot::Builtin(b.at(d)?),
            Self::User(f) => Pot::User(UserBatch::new(f.clone())),
            Self::Native(f) => Pot::Native(f.clone()),
        })
    }
}

/// The potential of a run, as the kernel's batch seam: a built-in and a
/// Rust function one point at a time (the kernel's grouping), a user's
/// function once per step on every live chain.
#[derive(Clone)]
pub(crate) enum Pot {
    Builtin(DynBuiltin),
    User(UserBatch),
    Native(Arc<dyn PointFunction>),
}

impl BatchPotential<f64> for Pot {
    #[inline]
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[f64],
        grad: &mut [f64],
        value: &mut [f64],
        skip: &[bool],
    ) -> ControlFlow<()> {
        match self {
            Self::Builtin(p) => p.values_and_gradients(d, x, grad, value, skip),
            Self::User(p) => p.values_and_gradients(d, x, grad, value, skip),
            Self::Native(p) => {
                let points = x.chunks_exact(d).zip(grad.chunks_exact_mut(d));
                for (((x, grad), value), &skip) in points.zip(value.iter_mut()).zip(skip) {
                    if !skip {
                        *value = p.value_and_gradient(x, grad);
                    }
                }
                ControlFlow::Continue(())
            }
        }
    }

    fn batch_dimension(&self) -> Option<usize> {
        match self {
            Self::Builtin(p) => SlicePotential::dimension(p),
            Self::User(_) => None,
            Self::Native(p) => p.dimension(),
        }
    }

    fn chains_per_call(&self) -> Option<usize> {
        match self {
            Self::User(_) => None,
            Self::Builtin(_) | Self::Native(_) => Some(hrla::LANES),
        }
    }
}

impl Pot {
    /// The user function's first error since the last call, if any.
    pub(crate) fn finish(&self) -> Result<(), Error> {
        match self {
            Self::User(p) => p.finish(),
            Self::Builtin(_) | Self::Native(_) => Ok(()),
        }
    }
}

/// A box `lo_i <= x_i <= hi_i`, one interval per coordinate, or the same
/// interval in every coordinate (in any dimension).
#[derive(Clone, Debug, PartialEq)]
pub enum BoxSpec {
    /// `[lo, hi]` in every coordinate.
    Uniform {
        /// The lower end.
        lo: f64,
        /// The upper end.
        hi: f64,
    },
    /// `[lo_i, hi_i]` in coordinate `i`; their number fixes `D`.
    PerCoordinate(Vec<(f64, f64)>),
}

impl BoxSpec {
    /// The dimension it fixes, if any.
    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Uniform { .. } => None,
            Self::PerCoordinate(b) => Some(b.len()),
        }
    }

    /// The kernel's box: an [`Interval`] when every coordinate has the
    /// same sides (pairs that are all equal included), else the kernel's
    /// [`hrla::Bounds`], each side checked by the kernel. Both reflect
    /// each coordinate the same way, so equal pairs give an `Interval`'s
    /// bits either way.
    pub(crate) fn sides(&self) -> Result<Sides, Error> {
        let b = match self {
            Self::Uniform { lo, hi } => return Ok(Sides::Uniform(Interval::new(*lo, *hi)?)),
            Self::PerCoordinate(b) => b,
        };
        let Some(&(lo, hi)) = b.first() else {
            return Err(Error::Length {
                what: "the box",
                len: 0,
                dim: 1,
            });
        };
        if b.iter()
            .all(|&(l, h)| l.to_bits() == lo.to_bits() && h.to_bits() == hi.to_bits())
        {
            return Ok(Sides::Uniform(Interval::new(lo, hi)?));
        }
        let (lo, hi): (Vec<f64>, Vec<f64>) = b.iter().copied().unzip();
        Ok(Sides::PerCoordinate(hrla::Bounds::new(lo, hi)?))
    }
}

/// A checked box: one interval, or one per coordinate.
#[derive(Clone, Debug)]
pub(crate) enum Sides {
    Uniform(Interval<f64>),
    PerCoordinate(hrla::Bounds<f64, Vec<f64>>),
}

impl Domain<f64> for Sides {
    #[inline]
    fn confine(&self, x: &mut [f64], y: &mut [f64]) {
        match self {
            Self::Uniform(b) => b.confine(x, y),
            Self::PerCoordinate(b) => b.confine(x, y),
        }
    }
    #[inline]
    fn project(&self, x: &mut [f64]) {
        match self {
            Self::Uniform(b) => Domain::project(b, x),
            Self::PerCoordinate(b) => Domain::project(b, x),
        }
    }
    fn feasible_direction(&self, x: &[f64], d: &mut [f64]) {
        match self {
            Self::Uniform(b) => Domain::feasible_direction(b, x, d),
            Self::PerCoordinate(b) => Domain::feasible_direction(b, x, d),
        }
    }
    fn dimension(&self) -> Option<usize> {
        match self {
            Self::Uniform(_) => None,
            Self::PerCoordinate(b) => Domain::dimension(b),
        }
    }
}

impl hrla::Sides<f64> for Sides {
    #[inline]
    fn side(&self, i: usize) -> (f64, f64) {
        match self {
            Self::Uniform(b) => b.side(i),
            Self::PerCoordinate(b) => b.side(i),
        }
    }
}

impl From<Interval<f64>> for BoxSpec {
    fn from(i: Interval<f64>) -> Self {
        Self::Uniform {
            lo: i.lo(),
            hi: i.hi(),
        }
    }
}

/// The initial points of a run, before its dimension is fixed.
#[derive(Clone, Debug, PartialEq)]
pub enum StartSpec {
    /// Independent Gaussian starts `N(mean, std_dev^2 I)`; `mean` fixes `D`.
    Gaussian {
        /// The mean.
        mean: Vec<f64>,
        /// The standard deviation of each coordinate.
        std_dev: f64,
    },
    /// The same centre in every coordinate: `N(centre · 1, std_dev^2 I)`.
    Isotropic {
        /// Every coordinate of the mean.
        centre: f64,
        /// The standard deviation of each coordinate.
        std_dev: f64,
    },
    /// Every chain starts at this point; its length fixes `D`.
    Point(Vec<f64>),
    /// Uniform in the box.
    Box(BoxSpec),
}

impl StartSpec {
    /// The dimension it fixes, if any.
    pub fn dimension(&self) -> Option<usize> {
        match self {
            Self::Gaussian { mean, .. } => Some(mean.len()),
            Self::Point(x) => Some(x.len()),
            Self::Isotropic { .. } => None,
            Self::Box(b) => b.dimension(),
        }
    }

    /// The start in dimension `d`, checked as the kernel's constructors
    /// check theirs.
    pub(crate) fn at(&self, d: usize) -> Result<DynStart, Error> {
        let length = |v: &[f64]| -> Result<(), Error> {
            if v.len() == d {
                Ok(())
            } else {
                Err(Error::Length {
                    what: "the start",
                    len: v.len(),
                    dim: d,
                })
            }
        };
        Ok(match self {
            Self::Gaussian { mean, std_dev } => {
                length(mean)?;
                DynStart::gaussian(mean.clone(), *std_dev)?
            }
            Self::Isotropic { centre, std_dev } => DynStart::gaussian(vec![*centre; d], *std_dev)?,
            Self::Point(x) => {
                length(x)?;
                finite_all("initial point", x)?;
                DynStart::Point(x.clone())
            }
            Self::Box(b) => match b.sides()? {
                Sides::Uniform(i) => DynStart::Interval(i),
                Sides::PerCoordinate(b) => {
                    length(b.lo())?;
                    DynStart::Bounds(b)
                }
            },
        })
    }
}

/// The kernel's built-in starts in dimension `D`, as one type.
#[derive(Clone, Copy, Debug)]
pub enum AnyStart<const D: usize> {
    /// [`hrla::Gaussian`].
    Gaussian(hrla::Gaussian<f64, D>),
    /// [`hrla::Point`].
    Point(hrla::Point<f64, D>),
    /// Uniform in an [`Interval`] box.
    Interval(Interval<f64>),
    /// Uniform in a box with its own sides in every coordinate.
    Bounds(hrla::Bounds<f64, [f64; D]>),
}

impl<const D: usize> Start<f64> for AnyStart<D> {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [f64]) {
        match self {
            Self::Gaussian(s) => s.initial_point(chain, rng, x),
            Self::Point(s) => s.initial_point(chain, rng, x),
            Self::Interval(s) => s.initial_point(chain, rng, x),
            Self::Bounds(s) => s.initial_point(chain, rng, x),
        }
    }
}

/// [`hrla::Error::NotFinite`] for the first non-finite entry of `v`.
pub(crate) fn finite_all(name: &'static str, v: &[f64]) -> Result<(), hrla::Error> {
    match v.iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(hrla::Error::NotFinite { name, value }),
        None => Ok(()),
    }
}

/// The kernel's starts at a run-time dimension: [`hrla::Gaussian`] and
/// [`hrla::Point`] hold arrays of their `D`, so those two are restated
/// over `Vec`s here, drawing exactly as the kernel's do (the same normals,
/// coordinate after coordinate, from the chain's generator).
#[derive(Clone, Debug)]
pub(crate) enum DynStart {
    Gaussian { mean: Vec<f64>, std_dev: f64 },
    Point(Vec<f64>),
    Interval(Interval<f64>),
    Bounds(hrla::Bounds<f64, Vec<f64>>),
}

impl DynStart {
    /// Checked as [`hrla::Gaussian::new`] checks.
    fn gaussian(mean: Vec<f64>, std_dev: f64) -> Result<Self, hrla::Error> {
        finite_all("mean", &mean)?;
        if !(std_dev.is_finite() && std_dev >= 0.0) {
            return Err(hrla::Error::Negative {
                name: "std_dev",
                value: std_dev,
            });
        }
        Ok(Self::Gaussian { mean, std_dev })
    }
}

impl Start<f64> for DynStart {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [f64]) {
        match self {
            Self::Gaussian { mean, std_dev } => {
                for (xi, &m) in x.iter_mut().zip(mean.iter()) {
                    *xi = m + *std_dev * <f64 as StandardNormal>::standard_normal(rng);
                }
            }
            Self::Point(p) => x.copy_from_slice(p),
            Self::Interval(s) => s.initial_point(chain, rng, x),
            Self::Bounds(s) => s.initial_point(chain, rng, x),
        }
    }

    fn dimension(&self) -> Option<usize> {
        match self {
            Self::Gaussian { mean, .. } => Some(mean.len()),
            Self::Point(p) => Some(p.len()),
            Self::Interval(_) => None,
            Self::Bounds(b) => Start::<f64>::dimension(b),
        }
    }
}

/// Where the chains may go: all of `R^D`, a box with the same sides in
/// every coordinate, or a box with its own sides in each.
#[derive(Clone, Debug)]
pub(crate) enum Bounds {
    Unbounded,
    Box(Interval<f64>),
    PerCoordinate(hrla::Bounds<f64, Vec<f64>>),
}

impl Domain<f64> for Bounds {
    #[inline]
    fn confine(&self, x: &mut [f64], y: &mut [f64]) {
        match self {
            Self::Unbounded => {}
            Self::Box(b) => b.confine(x, y),
            Self::PerCoordinate(b) => b.confine(x, y),
        }
    }
    #[inline]
    fn project(&self, x: &mut [f64]) {
        match self {
            Self::Unbounded => {}
            Self::Box(b) => Domain::project(b, x),
            Self::PerCoordinate(b) => Domain::project(b, x),
        }
    }
    #[inline]
    fn feasible_direction(&self, x: &[f64], d: &mut [f64]) {
        match self {
            Self::Unbounded => {}
            Self::Box(b) => Domain::feasible_direction(b, x, d),
            Self::PerCoordinate(b) => Domain::feasible_direction(b, x, d),
        }
    }
    fn dimension(&self) -> Option<usize> {
        match self {
            Self::Unbounded | Self::Box(_) => None,
            Self::PerCoordinate(b) => Domain::dimension(b),
        }
    }
}

/// The inverse temperature along a run, by its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Temperature {
    /// A constant `a`.
    Constant(f64),
    /// Linear annealing `a_low -> a_high` over `steps` iterations, then
    /// `a_high`.
    Linear {
        /// `a_0`.
        a_low: f64,
        /// `a_K` and beyond.
        a_high: f64,
        /// `K`.
        steps: u64,
    },
    /// Geometric annealing `a_low (a_high / a_low)^(k / K)`, then `a_high`.
    Geometric {
        /// `a_0`.
        a_low: f64,
        /// `a_K` and beyond.
        a_high: f64,
        /// `K`.
        steps: u64,
    },
}

impl Temperature {
    /// The kernel's schedule, its parameters checked by the kernel.
    pub fn schedule(self) -> Result<AnySchedule<f64>, hrla::Error> {
        Ok(match self {
            Self::Constant(a) => AnySchedule::Constant(Constant::new(a)?),
            Self::Linear {
                a_low,
                a_high,
                steps,
            } => AnySchedule::Linear(Linear::new(a_low, a_high, steps)?),
            Self::Geometric {
                a_low,
                a_high,
                steps,
            } => AnySchedule::Geometric(Geometric::new(a_low, a_high, steps)?),
        })
    }
}

/// Everything that determines a run: the same settings give the same bits
/// on every target.
#[derive(Clone)]
pub struct Settings {
    /// The potential.
    pub potential: PotentialSpec,
    /// The sampler and its parameters.
    pub sampler: AnySampler<f64>,
    /// The inverse temperature along the run.
    pub schedule: AnySchedule<f64>,
    /// The initial points.
    pub start: StartSpec,
    /// The box the chains are reflected into (and the polish projected
    /// onto); none: all of `R^D`.
    pub domain: Option<BoxSpec>,
    /// The run's seed: chain `c` draws from
    /// `Xoshiro256PlusPlus::seed_from_u64(hrla::chain_seed(seed, c))`.
    pub seed: u64,
    /// The kernel's stride of the running best.
    pub stride: u64,
    /// The stopping rules (none: the run goes on until stopped).
    pub stop: Stop<f64>,
    /// The number of chains.
    pub chains: usize,
    /// The dimension, when no other setting fixes it.
    pub dim: Option<usize>,
    /// The escape radius `R`: a chain with `|x| > R` has run away, and the
    /// run fails ([`Error::RanAway`]) after the first step at which every
    /// chain has run away or diverged, one at least having run away (none:
    /// chains may wander anywhere finite).
    pub escape: Option<f64>,
}

impl Settings {
    /// The one dimension the settings fix: `dim`, the potential, the start
    /// and the box must agree.
    pub fn dimension(&self) -> Result<usize, Error> {
        dimension(&[
            ("dim", self.dim),
            ("the potential", self.potential.dimension()),
            ("the start", self.start.dimension()),
            ("the box", self.domain.as_ref().and_then(BoxSpec::dimension)),
        ])
    }

    /// The escape radius, squared, checked: finite and `> 0`.
    pub(crate) fn escape2(&self) -> Result<Option<f64>, Error> {
        self.escape
            .map(|r| {
                if r.is_finite() && r > 0.0 {
                    Ok(r * r)
                } else {
                    Err(hrla::Error::NotPositive {
                        name: "escape",
                        value: r,
                    }
                    .into())
                }
            })
            .transpose()
    }

    pub(crate) fn bounds(&self) -> Result<Bounds, Error> {
        Ok(
            match self.domain.as_ref().map(BoxSpec::sides).transpose()? {
                None => Bounds::Unbounded,
                Some(Sides::Uniform(i)) => Bounds::Box(i),
                Some(Sides::PerCoordinate(b)) => Bounds::PerCoordinate(b),
            },
        )
    }
}

/// The one dimension that every source that fixes one agrees on:
/// [`Error::DimensionMismatch`] when two differ, [`Error::NoDimension`]
/// when none fixes one.
pub fn dimension(sources: &[(&'static str, Option<usize>)]) -> Result<usize, Error> {
    let mut found: Option<(&'static str, usize)> = None;
    for &(name, d) in sources {
        match (found, d) {
            (None, Some(d)) => found = Some((name, d)),
            (Some((first, d0)), Some(d)) if d != d0 => {
                return Err(Error::DimensionMismatch {
                    first,
                    first_dim: d0,
                    other: name,
                    other_dim: d,
                });
            }
            _ => {}
        }
    }
    found.map(|(_, d)| d).ok_or(Error::NoDimension)
}
