//! Test potentials shared by several test files.

use hrla::rand_core::SeedableRng;
use hrla::{AutoStorage, Float, Potential};
use rand_xoshiro::Xoshiro256PlusPlus;

/// A 1-D "cliff": `U = x^2/2` for `|x| <= 3`; for `3 < |x| <= 6` a slope
/// `U = 100 - 10 (|x| - 3)` that pushes outwards; beyond 6, `outside`
/// (value) and `outside_grad` (gradient). Chains started on the slope
/// leave it within a few dozen steps, so what the optimiser does with the
/// outside values (divergence, unboundedness) can be tested.
#[derive(Clone, Copy, Debug)]
pub struct Cliff {
    /// `U` beyond `|x| = 6`.
    pub outside: f64,
    /// `dU/dx` beyond `|x| = 6`.
    pub outside_grad: f64,
}

impl Cliff {
    /// NaN value and gradient beyond 6: every chain that leaves diverges.
    pub const NAN: Cliff = Cliff {
        outside: f64::NAN,
        outside_grad: f64::NAN,
    };
}

impl Potential<f64, 1> for Cliff {
    fn value_and_gradient(&self, x: &[f64; 1], g: &mut [f64; 1]) -> f64 {
        let r = x[0].abs();
        if r <= 3.0 {
            g[0] = x[0];
            0.5 * x[0] * x[0]
        } else if r <= 6.0 {
            g[0] = -10.0 * x[0].signum();
            100.0 - 10.0 * (r - 3.0)
        } else {
            g[0] = self.outside_grad;
            self.outside
        }
    }
}

/// The arrays of an [`AutoStorage`] of `n` chains of dimension `d` and
/// L-BFGS memory `m`, owned by the test, so that a flat run takes two
/// lines: `let mut arrays = AutoArrays::new(n, d, m);` then
/// `arrays.storage()`. The generators are seeded with 0: a run reseeds
/// every one from its own seed.
pub struct AutoArrays<F> {
    d: usize,
    m: usize,
    floats: Vec<F>,
    diverged: Vec<bool>,
    rngs: Vec<Xoshiro256PlusPlus>,
}

impl<F: Float> AutoArrays<F> {
    /// Zeroed arrays of the lengths that [`AutoStorage::new`] takes.
    pub fn new(n: usize, d: usize, m: usize) -> Self {
        Self {
            d,
            m,
            floats: vec![F::ZERO; AutoStorage::<F, Xoshiro256PlusPlus>::floats(n, d, m)],
            diverged: vec![false; n],
            rngs: (0..n)
                .map(|_| Xoshiro256PlusPlus::seed_from_u64(0))
                .collect(),
        }
    }

    /// The storage over these arrays.
    pub fn storage(&mut self) -> AutoStorage<'_, F, Xoshiro256PlusPlus> {
        AutoStorage::new(
            self.d,
            self.m,
            &mut self.floats,
            &mut self.diverged,
            &mut self.rngs,
        )
        .unwrap()
    }
}
