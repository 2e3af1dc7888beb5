//! The storage a caller lends [`Auto`](super::Auto) for a run at a
//! dimension known at run time.

use super::run::{self, Buffers, FlatChains};
use crate::error::{Error, check_lengths};
use crate::float::Float;
use crate::polish::LbfgsIn;

/// Storage for a run of [`Auto::minimize`](super::Auto::minimize)
/// with `n` chains of dimension `d` and L-BFGS memory `m`, lent by the
/// caller: one float array of [`floats(n, d, m)`](AutoStorage::floats), a
/// flag and a generator per chain. A run overwrites it all; the best
/// point of the last run stays readable ([`best`](AutoStorage::best)).
///
/// Layout of the floats, chain-major as [`FlatChains`](crate::FlatChains):
/// the basins `x`, the momenta `y`, the gradients (`n d` each), the values
/// (`n`), seven working points (`7 d`, the best first) and the L-BFGS
/// storage ([`LbfgsIn::floats`]`(d, m)`).
#[derive(Debug)]
pub struct AutoStorage<'a, F, R> {
    d: usize,
    m: usize,
    floats: &'a mut [F],
    diverged: &'a mut [bool],
    rngs: &'a mut [R],
}

impl<'a, F: Float, R> AutoStorage<'a, F, R> {
    /// The floats that `n` chains of dimension `d` with L-BFGS memory `m`
    /// take: `n (3 d + 1) + 7 d + 2 m d + 2 m + 5 d`, saturating at
    /// `usize::MAX`, a length no storage has.
    pub const fn floats(n: usize, d: usize, m: usize) -> usize {
        n.saturating_mul(d.saturating_mul(3).saturating_add(1))
            .saturating_add(run::buffer_floats(d))
            .saturating_add(LbfgsIn::<F>::floats(d, m))
    }

    /// `rngs.len()` chains of dimension `d >= 1`, L-BFGS memory `m >= 1`,
    /// over `floats` (length [`floats(n, d, m)`](AutoStorage::floats)) and
    /// `diverged` (length `n`). Errors: [`Error::Zero`] for no chain,
    /// `d = 0` or `m = 0`, [`Error::Length`] for an array of the wrong
    /// length.
    pub fn new(
        d: usize,
        m: usize,
        floats: &'a mut [F],
        diverged: &'a mut [bool],
        rngs: &'a mut [R],
    ) -> Result<Self, Error> {
        let n = rngs.len();
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if d == 0 {
            return Err(Error::Zero { name: "dimension" });
        }
        if m == 0 {
            return Err(Error::Zero {
                name: "L-BFGS memory",
            });
        }
        check_lengths([
            ("floats", Self::floats(n, d, m), floats.len()),
            ("diverged", n, diverged.len()),
        ])?;
        Ok(Self {
            d,
            m,
            floats,
            diverged,
            rngs,
        })
    }

    /// The number of chains.
    pub fn len(&self) -> usize {
        self.rngs.len()
    }

    /// Whether there is no chain (never: [`new`](AutoStorage::new) refuses
    /// none).
    pub fn is_empty(&self) -> bool {
        self.rngs.is_empty()
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.d
    }

    /// The chains' basins, `n d` floats, chain-major.
    pub fn positions(&self) -> &[F] {
        &self.floats[..self.len() * self.d]
    }

    /// `U` at the chains' basins, `n` floats.
    pub fn values(&self) -> &[F] {
        let nd = self.len() * self.d;
        &self.floats[3 * nd..3 * nd + self.len()]
    }

    /// The best point of the last run (zeros before any).
    pub fn best(&self) -> &[F] {
        let start = self.len() * (3 * self.d + 1);
        &self.floats[start..start + self.d]
    }

    /// The chains, the working points and the L-BFGS, cut from the storage.
    pub(super) fn parts(&mut self) -> Lent<'_, F, R> {
        let (n, d) = (self.rngs.len(), self.d);
        let (x, rest) = self.floats.split_at_mut(n * d);
        let (y, rest) = rest.split_at_mut(n * d);
        let (grad, rest) = rest.split_at_mut(n * d);
        let (value, rest) = rest.split_at_mut(n);
        let (buffers, lbfgs) = rest.split_at_mut(run::buffer_floats(d));
        Lent {
            chains: FlatChains {
                d,
                x,
                y,
                grad,
                value,
                diverged: self.diverged,
                rngs: self.rngs,
            },
            buffers: Buffers::new(d, buffers),
            lbfgs: LbfgsIn::new(d, self.m, lbfgs),
        }
    }
}

/// [`AutoStorage`] cut into what a run works on.
pub(super) struct Lent<'a, F, R> {
    pub(super) chains: FlatChains<'a, F, R>,
    pub(super) buffers: Buffers<'a, F>,
    pub(super) lbfgs: Result<LbfgsIn<'a, F>, Error>,
}
