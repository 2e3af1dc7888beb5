//! Initial points of the chains.

use rand_core::Rng;

use crate::error::{Error, finite};
use crate::float::Float;

/// Draws the initial position of each chain (the velocity starts at 0),
/// whether the chains' dimension is in their type ([`Chain`](crate::Chain))
/// or known at run time ([`FlatChains`](crate::FlatChains)): `x` is the
/// chain's position, of the run's dimension, and the draws are the same
/// either way.
pub trait Start<F: Float> {
    /// Writes the initial position of chain `chain` into `x`, drawing from
    /// that chain's own generator `rng`. Called again for the same chain,
    /// with the generator where the last call left it, when the point was
    /// infeasible.
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [F]);
    /// The dimension the start was made for, if it has one (a mean, a
    /// box); a run of another dimension is refused.
    fn dimension(&self) -> Option<usize> {
        None
    }
}

/// A start behind a mutable reference is the same start: it can then live
/// on the heap, or serve several runs.
impl<F: Float, S: Start<F> + ?Sized> Start<F> for &mut S {
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [F]) {
        (**self).initial_point(chain, rng, x);
    }
    fn dimension(&self) -> Option<usize> {
        (**self).dimension()
    }
}

/// Every chain starts at the same point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point<F, const D: usize>([F; D]);

impl<F: Float, const D: usize> Point<F, D> {
    /// A finite point.
    pub fn new(x: [F; D]) -> Result<Self, Error> {
        for &v in &x {
            finite("initial point", v)?;
        }
        Ok(Self(x))
    }
}

impl<F: Float, const D: usize> Start<F> for Point<F, D> {
    fn initial_point<R: Rng + ?Sized>(&mut self, _chain: usize, _rng: &mut R, x: &mut [F]) {
        x.copy_from_slice(&self.0);
    }
    fn dimension(&self) -> Option<usize> {
        Some(D)
    }
}

/// Independent isotropic Gaussian starts, `x_0 ~ N(m, s^2 I)`.
///
/// The paper's experiments start from `N(3·1, 10 I)`:
/// `Gaussian::new([3.0; 10], 10f64.sqrt())`. Coordinates are drawn in
/// order, from each chain's own generator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian<F, const D: usize> {
    mean: [F; D],
    std_dev: F,
}

impl<F: Float, const D: usize> Gaussian<F, D> {
    /// Finite mean `m` and finite standard deviation `s >= 0` (0 gives
    /// [`Point`]'s behaviour while still consuming normals).
    pub fn new(mean: [F; D], std_dev: F) -> Result<Self, Error> {
        for &m in &mean {
            finite("mean", m)?;
        }
        if !(std_dev.is_finite() && std_dev >= F::ZERO) {
            return Err(Error::Negative {
                name: "std_dev",
                value: std_dev.to_f64(),
            });
        }
        Ok(Self { mean, std_dev })
    }
}

impl<F: Float, const D: usize> Start<F> for Gaussian<F, D> {
    fn initial_point<R: Rng + ?Sized>(&mut self, _chain: usize, rng: &mut R, x: &mut [F]) {
        for (xi, &m) in x.iter_mut().zip(&self.mean) {
            *xi = m + self.std_dev * F::standard_normal(rng);
        }
    }
    fn dimension(&self) -> Option<usize> {
        Some(D)
    }
}

/// Initial points from a closure `(chain, rng, x)` that writes chain
/// `chain`'s initial point into `x` (of the run's dimension). A non-finite
/// point is infeasible: the optimiser calls the closure again for that
/// chain (see [`Builder::build`](crate::Builder::build)), and fails with
/// [`Error::NonFiniteStart`] when none of its tries is feasible.
#[derive(Clone, Copy, Debug)]
pub struct FromFn<G>(pub G);

impl<F: Float, G> Start<F> for FromFn<G>
where
    G: FnMut(usize, &mut dyn Rng, &mut [F]),
{
    fn initial_point<R: Rng + ?Sized>(&mut self, chain: usize, rng: &mut R, x: &mut [F]) {
        // `&mut R` is itself a sized `Rng`, so it coerces to `dyn Rng`.
        let mut rng = rng;
        (self.0)(chain, &mut rng, x);
    }
}
