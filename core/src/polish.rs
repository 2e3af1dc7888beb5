//! L-BFGS with a strong-Wolfe line search: the local minimiser that polishes
//! a point the chains found, to the precision of the float type.
//!
//! Limited-memory BFGS (Nocedal and Wright, *Numerical Optimization*,
//! algorithms 7.4 and 7.5) keeps the last `M` pairs `s = x' - x`,
//! `y = ∇U(x') - ∇U(x)` and applies the inverse-Hessian approximation they
//! define by the two-loop recursion, with the initial scaling
//! `s'y / y'y` of the latest pair. Steps come from a line search that
//! satisfies the strong Wolfe conditions (algorithms 3.5 and 3.6, with
//! safeguarded cubic interpolation), so every accepted pair has `s'y > 0`
//! and the approximation stays positive definite. All storage is the
//! [`Lbfgs`] value, which the caller owns: `2 M + 3` arrays of `D` floats.

use crate::domain::{Domain, Unbounded};
use crate::error::{Error, check_lengths, finite, floor};
use crate::float::Float;
use crate::potential::traits::{Potential, SlicePotential};

/// Sufficient decrease (Armijo) constant of the line search.
const C1: f64 = 1e-4;
/// Curvature constant of the strong Wolfe conditions (0.9: the usual
/// choice for quasi-Newton directions, few evaluations per iteration).
const C2: f64 = 0.9;
/// Trial steps of the bracketing phase before giving up.
const BRACKET_TRIALS: usize = 40;
/// Trial steps of the zoom phase before giving up.
const ZOOM_TRIALS: usize = 40;
/// A bracket's probe cut short by the domain whose slope is within this
/// share of the origin's found its path straight: the next probe goes to
/// the path's last wall (where the slope's secant still falls there).
const STRAIGHT: f64 = 0.1;
/// [`STRAIGHT`] for a probe the domain did not cut: a path linear to
/// the rounding of forward differences (`0.1` moved the ill-conditioned
/// quadratics of bbob, f2 and f10, off their course).
const LINEAR: f64 = 1e-5;

/// When [`Lbfgs::minimize`] stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolishSettings<F> {
    /// At most this many potential-and-gradient evaluations (the one at the
    /// start included).
    pub evaluations: u64,
    /// Converged when `max_j |dU/dx_j| <= gradient_tolerance`.
    pub gradient_tolerance: F,
    /// Converged when an iteration lowers `U` by no more than
    /// `value_tolerance * max(1, |U|)`.
    pub value_tolerance: F,
}

impl<F: Float> PolishSettings<F> {
    /// A budget of `evaluations`, and tolerances at the float type's
    /// precision: gradient `0` (never the reason alone), value
    /// `4 eps` (`eps` the machine epsilon), so that the polish ends when
    /// `U` stops falling in its last bits.
    pub fn new(evaluations: u64) -> Self {
        let eps = F::from_f64(if F::MANTISSA_DIGITS > 24 {
            f64::EPSILON
        } else {
            f32::EPSILON as f64
        });
        Self {
            evaluations,
            gradient_tolerance: F::ZERO,
            value_tolerance: F::from_f64(4.0) * eps,
        }
    }
}

/// The units a search measures its absolute constants in: its first step,
/// along `-∇U`, moves at most `length` in any coordinate and is at most
/// `step` (`length^2 / energy`: a step of unit curvature), and an
/// iteration that lowers `U` by no more than `value_tolerance * max(energy,
/// |U|)` ends it. The public searches run in units of 1, so that their
/// constants are those of the coordinates and values they are given;
/// `Auto` runs its quenches in the problem's own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scale<F> {
    pub(crate) length: F,
    pub(crate) energy: F,
    pub(crate) step: F,
    /// A direction is searched only where the first-order decrease its
    /// first step predicts exceeds `resolution` value tolerances: below,
    /// the search's comparisons of values would be decided by their
    /// rounding, and so would its length. The search ends there instead,
    /// converged ([`PolishEnd::Value`]). 0 searches every direction.
    pub(crate) resolution: F,
}

impl<F: Float> Scale<F> {
    /// The coordinates' and the values' own units, every direction searched.
    pub(crate) const ONE: Self = Self {
        length: F::ONE,
        energy: F::ONE,
        step: F::ONE,
        resolution: F::ZERO,
    };

    /// `value_tolerance * max(energy, |value|)`: a fall of `U` within its
    /// last bits at `value`.
    fn tolerance(&self, value_tolerance: F, value: F) -> F {
        let scale = if value.abs() > self.energy {
            value.abs()
        } else {
            self.energy
        };
        value_tolerance * scale
    }
}

/// Why a polish ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PolishEnd {
    /// The gradient fell within its tolerance.
    Gradient,
    /// An iteration lowered `U` by no more than the value tolerance.
    Value,
    /// The evaluation budget was spent.
    Budget,
    /// The line search found no step that lowers `U` enough: at the
    /// precision of the float type, the point is a local minimum (or the
    /// gradient is inconsistent with the value).
    LineSearch,
}

/// The outcome of a polish: the point itself is the `x` it was given,
/// updated in place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polished<F> {
    /// `U` at the final point.
    pub value: F,
    /// Evaluations used.
    pub evaluations: u64,
    /// Iterations (accepted steps).
    pub iterations: u64,
    /// Why it ended.
    pub end: PolishEnd,
}

/// L-BFGS with memory `M` in dimension `D`, and its working storage.
///
/// ```
/// use hrla::{Lbfgs, PolishEnd, PolishSettings, Rastrigin};
///
/// // From a point in the global basin of 10-D Rastrigin to its minimum.
/// let mut lbfgs: Lbfgs<f64, 10, 8> = Lbfgs::new();
/// let mut x = [0.3; 10];
/// let done = lbfgs.minimize(&Rastrigin, &mut x, PolishSettings::new(200))?;
/// assert!(done.value < 1e-20 && done.evaluations <= 20);
/// assert_ne!(done.end, PolishEnd::Budget);
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Lbfgs<F, const D: usize, const M: usize> {
    s: [[F; D]; M],
    y: [[F; D]; M],
    rho: [F; M],
    /// Pairs stored (up to `M`) and the slot of the next one.
    len: usize,
    next: usize,
    direction: [F; D],
    trial: [F; D],
    trial_grad: [F; D],
}

impl<F: Float, const D: usize, const M: usize> Default for Lbfgs<F, D, M> {
    /// Empty memory. A memory of `M = 0` pairs would not be L-BFGS: it does
    /// not compile.
    fn default() -> Self {
        const { assert!(M > 0, "L-BFGS needs a memory of at least one pair: M > 0") };
        Self {
            s: [[F::ZERO; D]; M],
            y: [[F::ZERO; D]; M],
            rho: [F::ZERO; M],
            len: 0,
            next: 0,
            direction: [F::ZERO; D],
            trial: [F::ZERO; D],
            trial_grad: [F::ZERO; D],
        }
    }
}

fn dot<F: Float>(a: &[F], b: &[F]) -> F {
    a.iter().zip(b).fold(F::ZERO, |acc, (&p, &q)| acc + p * q)
}

fn max_abs<F: Float>(v: &[F]) -> F {
    v.iter()
        .fold(F::ZERO, |m, &x| if x.abs() > m { x.abs() } else { m })
}

/// The minimiser of the cubic through `(a, fa, da)` and `(b, fb, db)`,
/// kept within the middle 80% of `[a, b]` (bisection when the cubic has no
/// usable minimiser there).
fn cubic_step<F: Float>(a: F, fa: F, da: F, b: F, fb: F, db: F) -> F {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let margin = F::from_f64(0.1) * (hi - lo);
    let d1 = da + db - F::from_f64(3.0) * (fa - fb) / (a - b);
    let disc = d1 * d1 - da * db;
    let mut t = (a + b) * F::HALF;
    if disc >= F::ZERO && disc.is_finite() {
        let d2 = disc.sqrt() * if b > a { F::ONE } else { -F::ONE };
        let denom = db - da + F::TWO * d2;
        if denom != F::ZERO {
            let c = b - (b - a) * ((db + d2 - d1) / denom);
            if c.is_finite() {
                t = c;
            }
        }
    }
    if t < lo + margin {
        lo + margin
    } else if t > hi - margin {
        hi - margin
    } else {
        t
    }
}

/// [`Error::UnboundedBelow`] for a value below the floor.
fn unbounded<F: Float>(value: F) -> Result<(), Error> {
    if value < floor() {
        Err(Error::UnboundedBelow {
            chain: 0,
            value: value.to_f64(),
        })
    } else {
        Ok(())
    }
}

/// A point of the line: step, value, directional derivative.
#[derive(Clone, Copy, Debug)]
struct LinePoint<F> {
    step: F,
    value: F,
    slope: F,
}

impl<F: Float> LinePoint<F> {
    /// A placeholder before the line search sets it.
    const ORIGIN: Self = Self {
        step: F::ZERO,
        value: F::ZERO,
        slope: F::ZERO,
    };
}

impl<F: Float, const D: usize, const M: usize> Lbfgs<F, D, M> {
    /// Empty memory. `M = 0` is refused at compile time:
    ///
    /// ```compile_fail
    /// let lbfgs: hrla::Lbfgs<f64, 2, 0> = hrla::Lbfgs::new();
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets the stored pairs (for a new start point).
    pub fn reset(&mut self) {
        self.len = 0;
        self.next = 0;
    }

    /// Minimises `U` from `x`, which ends at the best point found (never
    /// worse than the start): L-BFGS steps until a tolerance holds, the
    /// line search fails or the budget is spent.
    ///
    /// Errors: [`Error::Zero`] for a zero budget, [`Error::NotFinite`] if
    /// `x`, `U(x)` or `∇U(x)` is not finite, [`Error::UnboundedBelow`]
    /// (chain 0) if `U` falls to `-inf` or below `-sqrt(F::MAX)` at a point
    /// it evaluates (`x` is then the last point above it).
    pub fn minimize<P: Potential<F, D> + ?Sized>(
        &mut self,
        potential: &P,
        x: &mut [F; D],
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.minimize_in(potential, &Unbounded, x, settings)
    }

    /// [`minimize`](Lbfgs::minimize) within a domain: every trial point is
    /// projected onto it (so `x` is first projected too), which ends on a
    /// face where the minimum of the box lies there. Once the domain cuts
    /// a trial short, the next goes at least as far as the next coordinate's
    /// wall along the projected path, and to its last wall where the path
    /// is straight and still falling there (as does a trial on a linear
    /// path inside the domain); where every moving coordinate is on its
    /// wall the path ends there, and a zoom searches no further. A step
    /// too short to move any coordinate of `x` ends the search.
    pub fn minimize_in<P: Potential<F, D> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F; D],
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.quench(
            &Arrays::<_, D>(potential),
            &Arrays::<_, D>(domain),
            x,
            None,
            settings,
            Scale::ONE,
        )
    }
}

/// L-BFGS through the slice traits in the units `scale`, over either
/// storage: the one body behind each type's public `minimize_in`, and what
/// `Auto`'s quenches and polish call at any dimension.
pub(crate) trait Quencher<F: Float> {
    /// L-BFGS from `x` (of the storage's dimension, [`Error::Length`]
    /// otherwise) within `domain` in the units `scale`, `x` ending at the
    /// best point. `start`, where the caller has them: `U(x)` and the
    /// gradient at `x`, which the search then takes instead of evaluating
    /// them (its first evaluation saved); the gradient's buffer ends
    /// holding the gradient at the end point where the search succeeds.
    fn quench<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F],
        start: Option<(F, &mut [F])>,
        settings: PolishSettings<F>,
        scale: Scale<F>,
    ) -> Result<Polished<F>, Error>;
}

impl<F: Float, const D: usize, const M: usize> Quencher<F> for Lbfgs<F, D, M> {
    fn quench<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F],
        start: Option<(F, &mut [F])>,
        settings: PolishSettings<F>,
        scale: Scale<F>,
    ) -> Result<Polished<F>, Error> {
        check_lengths([("x", D, x.len())])?;
        let mut alpha = [F::ZERO; M];
        let mut grad = [F::ZERO; D];
        let mut memory = Memory {
            s: self.s.as_flattened_mut(),
            y: self.y.as_flattened_mut(),
            rho: &mut self.rho,
            alpha: &mut alpha,
            len: &mut self.len,
            next: &mut self.next,
            direction: &mut self.direction,
            trial: &mut self.trial,
            trial_grad: &mut self.trial_grad,
            grad: &mut grad,
            m: M,
            d: D,
        };
        memory.minimize_in(potential, domain, x, start, settings, scale)
    }
}

/// L-BFGS for a dimension `d` known at run time, in storage the caller
/// owns: the algorithm of [`Lbfgs`], with the same bits.
///
/// ```
/// use hrla::{LbfgsIn, PolishSettings, Rastrigin, Unbounded};
///
/// let (d, m) = (17, 8);
/// let mut storage = vec![0.0; LbfgsIn::<f64>::floats(d, m)];
/// let mut lbfgs = LbfgsIn::new(d, m, &mut storage)?;
/// let mut x = vec![0.3; d];
/// let done = lbfgs.minimize_in(&Rastrigin, &Unbounded, &mut x, PolishSettings::new(200))?;
/// assert!(done.value < 1e-20);
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Debug)]
pub struct LbfgsIn<'a, F> {
    storage: &'a mut [F],
    len: usize,
    next: usize,
    d: usize,
    m: usize,
}

impl<'a, F: Float> LbfgsIn<'a, F> {
    /// The floats of storage that memory `m` in dimension `d` needs:
    /// `2 m d + 2 m + 5 d` (the pairs, their weights, a direction, a trial
    /// point, its gradient, the current gradient, and a point for
    /// [`Optimizer::polish`](crate::Optimizer::polish)).
    /// Saturates at `usize::MAX`, a length no storage has.
    pub const fn floats(d: usize, m: usize) -> usize {
        let pairs = m.saturating_mul(d).saturating_mul(2);
        pairs
            .saturating_add(m.saturating_mul(2))
            .saturating_add(d.saturating_mul(5))
    }

    /// L-BFGS of memory `m >= 1` in dimension `d >= 1` over `storage`,
    /// whose length must be [`floats(d, m)`](LbfgsIn::floats)
    /// ([`Error::Zero`], [`Error::Length`] otherwise).
    pub fn new(d: usize, m: usize, storage: &'a mut [F]) -> Result<Self, Error> {
        if d == 0 {
            return Err(Error::Zero { name: "dimension" });
        }
        if m == 0 {
            return Err(Error::Zero {
                name: "L-BFGS memory",
            });
        }
        let expected = Self::floats(d, m);
        if storage.len() != expected {
            return Err(Error::Length {
                name: "L-BFGS storage",
                expected,
                got: storage.len(),
            });
        }
        Ok(Self {
            storage,
            len: 0,
            next: 0,
            d,
            m,
        })
    }

    /// The dimension.
    pub fn dimension(&self) -> usize {
        self.d
    }

    /// [`Lbfgs::minimize_in`] for `x` of length [`dimension`](LbfgsIn::dimension)
    /// ([`Error::Length`] otherwise).
    pub fn minimize_in<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F],
        settings: PolishSettings<F>,
    ) -> Result<Polished<F>, Error> {
        self.quench(potential, domain, x, None, settings, Scale::ONE)
    }

    /// Polishes a copy of `start` (of the storage's dimension) in the
    /// storage's own point, returned with the outcome.
    pub(crate) fn minimize_from<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        start: &[F],
        settings: PolishSettings<F>,
    ) -> (Result<Polished<F>, Error>, &[F]) {
        let (mut memory, point) = self.split();
        point.copy_from_slice(start);
        let done = memory.minimize_in(potential, domain, point, None, settings, Scale::ONE);
        (done, point)
    }

    /// The working memory, and the spare point.
    fn split(&mut self) -> (Memory<'_, F>, &mut [F]) {
        let (d, m) = (self.d, self.m);
        let (s, rest) = self.storage.split_at_mut(m * d);
        let (y, rest) = rest.split_at_mut(m * d);
        let (rho, rest) = rest.split_at_mut(m);
        let (alpha, rest) = rest.split_at_mut(m);
        let (direction, rest) = rest.split_at_mut(d);
        let (trial, rest) = rest.split_at_mut(d);
        let (trial_grad, rest) = rest.split_at_mut(d);
        let (grad, point) = rest.split_at_mut(d);
        let memory = Memory {
            s,
            y,
            rho,
            alpha,
            len: &mut self.len,
            next: &mut self.next,
            direction,
            trial,
            trial_grad,
            grad,
            m,
            d,
        };
        (memory, point)
    }
}

impl<F: Float> Quencher<F> for LbfgsIn<'_, F> {
    fn quench<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F],
        start: Option<(F, &mut [F])>,
        settings: PolishSettings<F>,
        scale: Scale<F>,
    ) -> Result<Polished<F>, Error> {
        check_lengths([("x", self.d, x.len())])?;
        let (mut memory, _) = self.split();
        memory.minimize_in(potential, domain, x, start, settings, scale)
    }
}

/// A potential or a domain on `[F; D]` seen through slices of length `D`.
pub(crate) struct Arrays<'a, T: ?Sized, const D: usize>(pub(crate) &'a T);

impl<F: Float, P: Potential<F, D> + ?Sized, const D: usize> SlicePotential<F> for Arrays<'_, P, D> {
    #[inline]
    fn value_and_gradient(&self, x: &[F], grad: &mut [F]) -> F {
        // Every slice the polish passes has length D: the fallback, an
        // infeasible point, is never taken.
        match (<&[F; D]>::try_from(x), <&mut [F; D]>::try_from(grad)) {
            (Ok(x), Ok(grad)) => self.0.value_and_gradient(x, grad),
            _ => F::INFINITY,
        }
    }
}

impl<F: Float, B: Domain<F> + ?Sized, const D: usize> Domain<F> for Arrays<'_, B, D> {
    fn confine(&self, x: &mut [F], y: &mut [F]) {
        if let (Ok(x), Ok(y)) = (<&mut [F; D]>::try_from(x), <&mut [F; D]>::try_from(y)) {
            self.0.confine(x, y);
        }
    }
    fn project(&self, x: &mut [F]) {
        if let Ok(x) = <&mut [F; D]>::try_from(x) {
            self.0.project(x);
        }
    }
    fn feasible_direction(&self, x: &[F], d: &mut [F]) {
        if let (Ok(x), Ok(d)) = (<&[F; D]>::try_from(x), <&mut [F; D]>::try_from(d)) {
            self.0.feasible_direction(x, d);
        }
    }
}

/// The working storage of one polish, as slices: an [`Lbfgs`]'s arrays or
/// an [`LbfgsIn`]'s storage. Pair `k` is `s[k d..(k + 1) d]`.
struct Memory<'a, F> {
    s: &'a mut [F],
    y: &'a mut [F],
    rho: &'a mut [F],
    alpha: &'a mut [F],
    len: &'a mut usize,
    next: &'a mut usize,
    direction: &'a mut [F],
    trial: &'a mut [F],
    trial_grad: &'a mut [F],
    grad: &'a mut [F],
    m: usize,
    d: usize,
}

impl<F: Float> Memory<'_, F> {
    /// Forgets the stored pairs (for a new start point).
    fn reset(&mut self) {
        *self.len = 0;
        *self.next = 0;
    }

    fn pair(v: &[F], k: usize, d: usize) -> &[F] {
        &v[k * d..(k + 1) * d]
    }

    /// `direction = -H grad` by the two-loop recursion.
    fn direction(&mut self) {
        let (m, d, len, next) = (self.m, self.d, *self.len, *self.next);
        let alpha = &mut *self.alpha;
        let (s, y) = (&*self.s, &*self.y);
        let q = &mut *self.direction;
        for (qi, &gi) in q.iter_mut().zip(&*self.grad) {
            *qi = -gi;
        }
        // Newest to oldest.
        for i in 0..len {
            let k = (next + m - 1 - i) % m;
            alpha[k] = self.rho[k] * dot(Self::pair(s, k, d), q);
            for (qj, &yj) in q.iter_mut().zip(Self::pair(y, k, d)) {
                *qj -= alpha[k] * yj;
            }
        }
        if len > 0 {
            let k = (next + m - 1) % m;
            let (sk, yk) = (Self::pair(s, k, d), Self::pair(y, k, d));
            let gamma = dot(sk, yk) / dot(yk, yk);
            for qj in q.iter_mut() {
                *qj *= gamma;
            }
        }
        // Oldest to newest.
        for i in (0..len).rev() {
            let k = (next + m - 1 - i) % m;
            let beta = self.rho[k] * dot(Self::pair(y, k, d), q);
            for (qj, &sj) in q.iter_mut().zip(Self::pair(s, k, d)) {
                *qj += (alpha[k] - beta) * sj;
            }
        }
    }

    /// `trial = x + step d`, projected onto the domain: the point a probe
    /// asks for.
    fn set_trial<B: Domain<F> + ?Sized>(&mut self, domain: &B, x: &[F], step: F) {
        for ((t, &xi), &di) in self.trial.iter_mut().zip(x).zip(&*self.direction) {
            *t = xi + step * di;
        }
        domain.project(self.trial);
    }

    /// The probe at `step` with `U(trial) = value` (its gradient in the
    /// trial buffer) as a point of the line: a non-finite value counts as
    /// `+inf`, except below the floor at a finite point (`-inf` included),
    /// kept as it is.
    fn line_point(&self, step: F, value: F) -> LinePoint<F> {
        // Along the path actually taken (the projection may have shortened
        // the step in some coordinates): the derivative in the direction.
        let slope = dot(self.trial_grad, self.direction);
        let unbounded = value < floor() && self.trial.iter().all(|t| t.is_finite());
        if unbounded || (value.is_finite() && slope.is_finite()) {
            LinePoint { step, value, slope }
        } else {
            LinePoint {
                step,
                value: F::INFINITY,
                slope: F::INFINITY,
            }
        }
    }

    /// Starts L-BFGS from `x` within the domain: the algorithm of every
    /// polish, by reverse communication. Each [`Next::Evaluate`] asks for
    /// `U` and `∇U` at the trial point, the gradient written into the
    /// trial gradient buffer and the value
    /// handed to [`tell`](Self::tell), until [`Next::Done`]. Between the
    /// calls the search is the [`Search`] and these buffers (and `x`, the
    /// current point, which ends at the best point found).
    pub(crate) fn begin<B: Domain<F> + ?Sized>(
        &mut self,
        domain: &B,
        x: &mut [F],
        settings: PolishSettings<F>,
        scale: Scale<F>,
    ) -> (Search<F>, Next<F>) {
        let mut search = Search {
            settings,
            scale,
            phase: Phase::Start,
            budget: 0,
            iterations: 0,
            value: F::ZERO,
            step: F::ZERO,
            f0: F::ZERO,
            d0: F::ZERO,
            prev: LinePoint::ORIGIN,
            lo: LinePoint::ORIGIN,
            hi: LinePoint::ORIGIN,
            trials: 0,
        };
        if settings.evaluations == 0 {
            search.phase = Phase::Done;
            let e = Error::Zero {
                name: "polish budget",
            };
            return (search, Next::Done(Err(e)));
        }
        if let Some(e) = x.iter().find_map(|&v| finite("x", v).err()) {
            search.phase = Phase::Done;
            return (search, Next::Done(Err(e)));
        }
        domain.project(x);
        self.reset();
        // U(x), evaluated at a copy of x: the same bits.
        self.trial.copy_from_slice(x);
        (search, Next::Evaluate)
    }

    /// `U` at the trial point (its gradient already in the trial gradient
    /// buffer): the search goes on to its next evaluation or its end.
    pub(crate) fn tell<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
        value: F,
    ) -> Next<F> {
        match s.phase {
            Phase::Start => self.started(s, domain, x, value, 1),
            Phase::Bracket => {
                let p = self.line_point(s.step, value);
                self.bracketed(s, domain, x, p)
            }
            Phase::Zoom => {
                let p = self.line_point(s.step, value);
                self.zoomed(s, domain, x, p)
            }
            Phase::Last => {
                let p = self.line_point(s.step, value);
                if s.armijo(&p) {
                    self.accept(s, domain, x, p)
                } else {
                    self.fail(s)
                }
            }
            Phase::Done => Next::Done(Ok(s.polished(PolishEnd::Budget))),
        }
    }

    /// `U(x) = value`, its gradient in the trial gradient buffer, at a
    /// cost of `spent` evaluations (0 where the caller knew them): the
    /// first iteration.
    fn started<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
        value: F,
        spent: u64,
    ) -> Next<F> {
        let checked = unbounded(value)
            .and_then(|()| finite("U(x)", value))
            .and_then(|v| {
                for &g in &*self.trial_grad {
                    finite("gradient", g)?;
                }
                Ok(v)
            });
        match checked {
            Ok(v) => {
                self.grad.copy_from_slice(self.trial_grad);
                s.value = v;
                s.budget = s.settings.evaluations - spent;
                self.iterate(s, domain, x)
            }
            Err(e) => Self::end(s, Err(e)),
        }
    }

    fn end(s: &mut Search<F>, result: Result<Polished<F>, Error>) -> Next<F> {
        s.phase = Phase::Done;
        Next::Done(result)
    }

    /// The top of an L-BFGS iteration: the convergence and budget checks,
    /// the direction, and the line search's first probe.
    fn iterate<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
    ) -> Next<F> {
        if max_abs(self.grad) <= s.settings.gradient_tolerance {
            return Self::end(s, Ok(s.polished(PolishEnd::Gradient)));
        }
        if s.budget == 0 {
            return Self::end(s, Ok(s.polished(PolishEnd::Budget)));
        }
        self.direction();
        domain.feasible_direction(x, self.direction);
        let mut slope = dot(self.grad, self.direction);
        if slope >= F::ZERO || !slope.is_finite() {
            // Not a descent direction (rounding in a stale memory, or
            // one the domain's faces cut): restart from steepest
            // descent.
            self.reset();
            self.direction();
            domain.feasible_direction(x, self.direction);
            slope = dot(self.grad, self.direction);
            if slope >= F::ZERO || !slope.is_finite() {
                return Self::end(s, Ok(s.polished(PolishEnd::Gradient)));
            }
        }
        // Unit steps for quasi-Newton directions; the first, along
        // -grad, is a step of unit curvature that moves x by at most one
        // length in any coordinate, both in the search's units.
        let first = if *self.len == 0 {
            let Scale { length, step, .. } = s.scale;
            let cap = length / max_abs(self.direction);
            if cap < step { cap } else { step }
        } else {
            F::ONE
        };
        let resolution = s.scale.resolution;
        if resolution > F::ZERO
            && -slope * first <= resolution * s.scale.tolerance(s.settings.value_tolerance, s.value)
        {
            return Self::end(s, Ok(s.polished(PolishEnd::Value)));
        }
        // A step satisfying the strong Wolfe conditions from (0, f0, d0):
        // first a bracket, doubling the step (or further, to a wall of the
        // domain: `bracketed`), then a zoom into it.
        s.f0 = s.value;
        s.d0 = slope;
        s.prev = LinePoint {
            step: F::ZERO,
            value: s.value,
            slope,
        };
        s.trials = 0;
        self.bracket_probe(s, domain, x, first)
    }

    /// The bracket's next probe at `step`, within the budget.
    fn bracket_probe<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &[F],
        step: F,
    ) -> Next<F> {
        if s.budget == 0 {
            return self.fail(s);
        }
        self.probe(s, domain, x, step, Phase::Bracket)
    }

    /// A bracket's probe `p` answered.
    fn bracketed<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
        p: LinePoint<F>,
    ) -> Next<F> {
        if p.value < floor() {
            return self.accept(s, domain, x, p);
        }
        if !s.armijo(&p) || (s.trials > 0 && p.value >= s.prev.value) {
            (s.lo, s.hi) = (s.prev, p);
            s.trials = 0;
            return self.zoom_probe(s, domain, x);
        }
        if s.curvature(&p) {
            return self.accept(s, domain, x, p);
        }
        if p.slope >= F::ZERO {
            (s.lo, s.hi) = (p, s.prev);
            s.trials = 0;
            return self.zoom_probe(s, domain, x);
        }
        let double = p.step * F::TWO;
        let path = self.path(domain, x, p.step);
        if path.cut && path.last == F::ZERO {
            // Every coordinate that moves is on its wall: the path goes
            // no further. The probe's point again, where `path` wrote.
            self.set_trial(domain, x, p.step);
            return self.accept(s, domain, x, p);
        }
        // Doubling crawls where the path's end is in sight: on a slope
        // towards a corner, along the walls in the coordinates the first
        // step barely moved. The probe's slope against the origin's tells
        // how straight the path is: straight to `LINEAR`, or cut short by a
        // wall and straight to `STRAIGHT`, with the slope's secant still
        // falling at the path's last wall, the next probe goes there; cut
        // short otherwise, to the next wall at least.
        let bend = (p.slope - s.d0).abs() / -s.d0;
        let falling = s.d0 + (p.slope - s.d0) * (path.last / p.step) < F::ZERO;
        let straight = if path.cut { STRAIGHT } else { LINEAR };
        let wall = if bend <= F::from_f64(straight) && falling && path.last.is_finite() {
            path.last
        } else if path.cut {
            path.next
        } else {
            double
        };
        let next = if wall.is_finite() && wall > double {
            wall
        } else {
            double
        };
        s.prev = p;
        s.trials += 1;
        if s.trials >= BRACKET_TRIALS {
            return self.fail(s);
        }
        self.bracket_probe(s, domain, x, next)
    }

    /// The projected path `x + t d` beyond the probe at `step`: whether
    /// the domain cut the probe short, and the steps at which the first
    /// and the last coordinate still moving reach their walls (`+inf`
    /// where one has none; none moving: `next = +inf`, `last = 0`).
    fn path<B: Domain<F> + ?Sized>(&mut self, domain: &B, x: &[F], step: F) -> Path<F> {
        // The probe's point, which the next probe overwrites (where the
        // probe is accepted instead, the caller sets it again): with a
        // full memory no pair's slot is free.
        let far = &mut *self.trial;
        // The largest float in each moving coordinate's direction, which
        // the projection brings to its wall (a non-finite one it keeps).
        for ((f, &xi), &di) in far.iter_mut().zip(x).zip(&*self.direction) {
            *f = if di > F::ZERO {
                F::MAX
            } else if di < F::ZERO {
                -F::MAX
            } else {
                xi
            };
        }
        domain.project(far);
        let mut path = Path {
            cut: false,
            next: F::INFINITY,
            last: F::ZERO,
        };
        for ((&f, &xi), &di) in far.iter().zip(x).zip(&*self.direction) {
            if di == F::ZERO {
                continue;
            }
            let t = if f.abs() == F::MAX {
                F::INFINITY
            } else {
                (f - xi) / di
            };
            if t > step {
                if t < path.next {
                    path.next = t;
                }
                if t > path.last {
                    path.last = t;
                }
            } else {
                path.cut = true;
            }
        }
        path
    }

    /// The zoom's next probe, inside the bracket `[lo, hi]`.
    fn zoom_probe<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &[F],
    ) -> Next<F> {
        if s.trials >= ZOOM_TRIALS {
            return self.last(s, domain, x);
        }
        if s.budget == 0 {
            return self.fail(s);
        }
        // Beyond the path's last wall every step is the same point, the
        // one the path ends at: an end of the bracket beyond it stands
        // there, so that no probe repeats it. Once, as the zoom begins:
        // its probes stay inside the bracket.
        let end = if s.trials == 0 {
            self.path(domain, x, F::ZERO).last
        } else {
            F::ZERO
        };
        if end > F::ZERO {
            for p in [&mut s.lo, &mut s.hi] {
                if p.step > end {
                    p.step = end;
                }
            }
        }
        let (lo, hi) = (s.lo, s.hi);
        let step = if hi.value.is_finite() {
            cubic_step(lo.step, lo.value, lo.slope, hi.step, hi.value, hi.slope)
        } else {
            (lo.step + hi.step) * F::HALF
        };
        if step == lo.step || step == hi.step {
            return self.last(s, domain, x);
        }
        self.probe(s, domain, x, step, Phase::Zoom)
    }

    /// One evaluation of the budget spent on the trial point `x + step d`,
    /// asked for in `phase`.
    fn probe<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &[F],
        step: F,
        phase: Phase,
    ) -> Next<F> {
        self.set_trial(domain, x, step);
        if *self.trial == *x {
            // A step too short to move any coordinate: the line holds
            // nothing below `x` that the floats can reach.
            return self.fail(s);
        }
        s.budget -= 1;
        s.step = step;
        s.phase = phase;
        Next::Evaluate
    }

    /// A zoom's probe `p` answered.
    fn zoomed<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
        p: LinePoint<F>,
    ) -> Next<F> {
        if p.value < floor() {
            return self.accept(s, domain, x, p);
        }
        if !s.armijo(&p) || p.value >= s.lo.value {
            s.hi = p;
        } else {
            if s.curvature(&p) {
                return self.accept(s, domain, x, p);
            }
            if p.slope * (s.hi.step - s.lo.step) >= F::ZERO {
                s.hi = s.lo;
            }
            s.lo = p;
        }
        s.trials += 1;
        self.zoom_probe(s, domain, x)
    }

    /// The bracket collapsed: the best point found, if it lowers U enough
    /// (its pair may still have s'y > 0), else a failed search.
    fn last<B: Domain<F> + ?Sized>(&mut self, s: &mut Search<F>, domain: &B, x: &[F]) -> Next<F> {
        if s.lo.step > F::ZERO && s.budget > 0 {
            return self.probe(s, domain, x, s.lo.step, Phase::Last);
        }
        self.fail(s)
    }

    /// No step was found: the budget is spent, or the line search failed.
    fn fail(&mut self, s: &mut Search<F>) -> Next<F> {
        let end = if s.budget == 0 {
            PolishEnd::Budget
        } else {
            PolishEnd::LineSearch
        };
        Self::end(s, Ok(s.polished(end)))
    }

    /// The line search's step `p` (its point and gradient in the trial
    /// buffers): the new pair, the move, and the value tolerance.
    fn accept<B: Domain<F> + ?Sized>(
        &mut self,
        s: &mut Search<F>,
        domain: &B,
        x: &mut [F],
        p: LinePoint<F>,
    ) -> Next<F> {
        if let Err(e) = unbounded(p.value) {
            return Self::end(s, Err(e));
        }
        // The new pair, kept when its curvature is positive; a pair that
        // is not kept writes nothing, since with a full memory its slot
        // still holds the oldest pair in use.
        let (k, d) = (*self.next, self.d);
        let sy = (0..d).fold(F::ZERO, |acc, j| {
            acc + (self.trial[j] - x[j]) * (self.trial_grad[j] - self.grad[j])
        });
        if sy > F::ZERO && sy.is_finite() {
            let sk = &mut self.s[k * d..(k + 1) * d];
            let yk = &mut self.y[k * d..(k + 1) * d];
            for j in 0..d {
                sk[j] = self.trial[j] - x[j];
                yk[j] = self.trial_grad[j] - self.grad[j];
            }
            self.rho[k] = F::ONE / sy;
            *self.next = (k + 1) % self.m;
            *self.len = (*self.len + 1).min(self.m);
        }
        let drop = s.value - p.value;
        x.copy_from_slice(self.trial);
        self.grad.copy_from_slice(self.trial_grad);
        s.value = p.value;
        s.iterations += 1;
        if drop <= s.scale.tolerance(s.settings.value_tolerance, s.value) {
            return Self::end(s, Ok(s.polished(PolishEnd::Value)));
        }
        self.iterate(s, domain, x)
    }

    /// L-BFGS from `x` within the domain, `potential` answering each of
    /// the search's requests at once.
    fn minimize_in<P: SlicePotential<F> + ?Sized, B: Domain<F> + ?Sized>(
        &mut self,
        potential: &P,
        domain: &B,
        x: &mut [F],
        start: Option<(F, &mut [F])>,
        settings: PolishSettings<F>,
        scale: Scale<F>,
    ) -> Result<Polished<F>, Error> {
        // The caller's value and gradient hold where the domain leaves `x`
        // where it is (a point it moves is evaluated there).
        let inside = start.is_some() && {
            self.trial.copy_from_slice(x);
            domain.project(self.trial);
            *self.trial == *x
        };
        let (mut search, mut next) = self.begin(domain, x, settings, scale);
        if let (Next::Evaluate, Some((value, grad)), true) = (next, &start, inside) {
            self.trial_grad.copy_from_slice(grad);
            next = self.started(&mut search, domain, x, *value, 0);
        }
        loop {
            match next {
                Next::Evaluate => {
                    let value = potential.value_and_gradient(self.trial, self.trial_grad);
                    next = self.tell(&mut search, domain, x, value);
                }
                Next::Done(result) => {
                    if let (Ok(_), Some((_, grad))) = (&result, start) {
                        grad.copy_from_slice(self.grad);
                    }
                    return result;
                }
            }
        }
    }
}

/// The projected path beyond a bracket's probe ([`Memory::path`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Path<F> {
    cut: bool,
    next: F,
    last: F,
}

/// What a search asks for next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Next<F> {
    /// `U` and `∇U` at the trial point.
    Evaluate,
    /// The search ended.
    Done(Result<Polished<F>, Error>),
}

/// The stage of a search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Waiting for `U(x)` at the start.
    Start,
    /// A probe of the bracketing phase.
    Bracket,
    /// A probe of the zoom.
    Zoom,
    /// The last probe, at the bracket's best step.
    Last,
    /// Ended.
    Done,
}

/// The scalars of an L-BFGS search between two evaluations (its vectors
/// are the [`Memory`]'s).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Search<F> {
    settings: PolishSettings<F>,
    scale: Scale<F>,
    phase: Phase,
    /// Evaluations left (the one in flight charged).
    budget: u64,
    iterations: u64,
    /// `U` at the current point.
    value: F,
    /// The step of the probe in flight.
    step: F,
    /// The line search's origin: value and slope.
    f0: F,
    d0: F,
    /// The bracket's previous point, and the zoom's ends.
    prev: LinePoint<F>,
    lo: LinePoint<F>,
    hi: LinePoint<F>,
    /// Probes of the current phase so far.
    trials: usize,
}

impl<F: Float> Search<F> {
    /// Sufficient decrease from the line search's origin.
    fn armijo(&self, p: &LinePoint<F>) -> bool {
        p.value <= self.f0 + F::from_f64(C1) * p.step * self.d0
    }

    /// The strong Wolfe curvature condition.
    fn curvature(&self, p: &LinePoint<F>) -> bool {
        p.slope.abs() <= -F::from_f64(C2) * self.d0
    }

    fn polished(&self, end: PolishEnd) -> Polished<F> {
        Polished {
            value: self.value,
            evaluations: self.settings.evaluations - self.budget,
            iterations: self.iterations,
            end,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step whose pair L-BFGS rejects (`s'y <= 0`, here on a full
    /// memory of one pair) leaves the kept pair and its `rho` as they
    /// were: the two-loop recursion reads them together.
    #[test]
    fn a_rejected_pair_leaves_a_full_memory_as_it_was() {
        let mut storage = [0.0_f64; LbfgsIn::<f64>::floats(2, 1)];
        let mut lbfgs = LbfgsIn::new(2, 1, &mut storage).unwrap();
        let (mut memory, _) = lbfgs.split();
        let mut x = [0.0, 0.0];
        let settings = PolishSettings::new(10);
        let (mut search, _) = memory.begin(&Unbounded, &mut x, settings, Scale::ONE);
        search.value = 1.0;
        memory.s.copy_from_slice(&[1.0, 0.0]);
        memory.y.copy_from_slice(&[2.0, 0.0]);
        memory.rho[0] = 0.5;
        (*memory.len, *memory.next) = (1, 0);
        memory.grad.copy_from_slice(&[1.0, 1.0]);
        // s = (0, 1), y = (0, -1): s'y = -1.
        memory.trial.copy_from_slice(&[0.0, 1.0]);
        memory.trial_grad.copy_from_slice(&[1.0, 0.0]);
        let step = LinePoint {
            step: 1.0,
            value: 0.5,
            slope: -1.0,
        };
        memory.accept(&mut search, &Unbounded, &mut x, step);
        assert_eq!(x, [0.0, 1.0]);
        assert_eq!((&*memory.s, &*memory.y), (&[1.0, 0.0][..], &[2.0, 0.0][..]));
        assert_eq!((memory.rho[0], *memory.len), (0.5, 1));
    }
}
