//! Test potentials shared by several test files.

use hrla::Potential;

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
