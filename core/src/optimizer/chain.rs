//! The state of one chain, and the best point it has visited.

use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::float::Float;

/// A point with its potential and the iteration at which it was visited.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Best<F, const D: usize> {
    /// The position.
    pub x: [F; D],
    /// `U(x)`, finite for every point the optimiser records.
    pub value: F,
    /// The iterate index `k` (0 is the initial point).
    pub iteration: u64,
}

/// One chain: its state `(x, y)`, the potential and gradient at `x`, its
/// own running best, and its own random generator `R`.
///
/// Storage for the optimiser: make as many as the run has chains (their
/// contents are overwritten when the run is built), in whatever container
/// suits the target.
///
/// ```
/// use hrla::Chain;
///
/// // On a host: on the heap, any number.
/// let chains: Vec<Chain<f64, 10>> = (0..10_000).map(|_| Chain::new()).collect();
/// // On firmware: an array (or a `static`), with a 32-bit generator.
/// let small: [Chain<f32, 2, rand_xoshiro::Xoshiro128PlusPlus>; 16] =
///     core::array::from_fn(|_| Chain::default());
/// # assert_eq!(chains.len() + small.len(), 10_016);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Chain<F, const D: usize, R = Xoshiro256PlusPlus> {
    pub(crate) x: [F; D],
    pub(crate) y: [F; D],
    pub(crate) value: F,
    pub(crate) grad: [F; D],
    pub(crate) best: Best<F, D>,
    pub(crate) diverged: bool,
    pub(crate) rng: R,
}

impl<F: Float, const D: usize> Chain<F, D> {
    /// An empty chain with the default generator, `Xoshiro256PlusPlus`.
    pub fn new() -> Self {
        Self::default()
    }
}

impl<F: Float, const D: usize, R: SeedableRng> Default for Chain<F, D, R> {
    /// An empty chain, to be filled by [`Builder::build`](crate::Builder::build).
    fn default() -> Self {
        Self {
            x: [F::ZERO; D],
            y: [F::ZERO; D],
            value: F::INFINITY,
            grad: [F::ZERO; D],
            best: Best {
                x: [F::ZERO; D],
                value: F::INFINITY,
                iteration: 0,
            },
            diverged: false,
            rng: R::seed_from_u64(0),
        }
    }
}

impl<F: Float, const D: usize, R> Chain<F, D, R> {
    /// Current position `x_k`.
    pub fn x(&self) -> &[F; D] {
        &self.x
    }
    /// Current velocity `y_k` (zero throughout for samplers without one).
    pub fn y(&self) -> &[F; D] {
        &self.y
    }
    /// `U(x_k)`; for a diverged chain, the value at the step that stopped it
    /// (non-finite, or finite beside a non-finite position or gradient).
    pub fn value(&self) -> F {
        self.value
    }
    /// `∇U(x_k)`.
    pub fn gradient(&self) -> &[F; D] {
        &self.grad
    }
    /// The chain's running best over its recorded iterates.
    pub fn best(&self) -> &Best<F, D> {
        &self.best
    }
    /// `true` once the position, the potential or its gradient went
    /// non-finite: the chain is then frozen (no more steps, no more random
    /// draws) and excluded from the best.
    pub fn is_diverged(&self) -> bool {
        self.diverged
    }
    /// The chain's own generator, in its current state.
    pub fn rng(&self) -> &R {
        &self.rng
    }
}
