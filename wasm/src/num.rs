//! How a number reads in a message.

use core::fmt;

/// A number as a person reads it: whole numbers in full up to `2^53`,
/// others in exponent form when very large or small (so that `1e308` is
/// not 309 digits).
pub(crate) struct Num(pub(crate) f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (v, a) = (self.0, self.0.abs());
        let plain = a == 0.0
            || !a.is_finite()
            || (v.fract() == 0.0 && a < 9_007_199_254_740_992.0)
            || (1e-4..1e6).contains(&a);
        if plain {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}
