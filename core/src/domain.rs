//! Where the chains may go: all of `R^D`, or a box ([`Interval`], the same
//! interval in every coordinate, or [`Bounds`], one per coordinate).
//!
//! A box keeps the sampler well defined by reflection: a step that leaves
//! `[lo, hi]` in a coordinate is folded back into it, mirror-wise, and that
//! coordinate's velocity changes sign (specular reflection, which leaves
//! the restriction of the invariant law to the box unchanged for the
//! dynamics' continuous-time limit). The polish projects onto the box
//! instead (a point on a face is a valid minimiser there).

use core::marker::PhantomData;

use rand_core::Rng;

use crate::error::{Error, finite};
use crate::float::Float;
use crate::start::Start;

/// A domain for the chains, whether their dimension is in their type
/// ([`Chain`](crate::Chain)) or known at run time
/// ([`FlatChains`](crate::FlatChains)): every slice has the run's
/// dimension, and the same per-coordinate code serves both.
pub trait Domain<F: Float> {
    /// Brings a position just moved by a step back into the domain,
    /// adjusting the velocity to match.
    fn confine(&self, x: &mut [F], y: &mut [F]);
    /// The nearest point of the domain (for the polish's trial points).
    fn project(&self, x: &mut [F]);
    /// Zeroes the components of a search direction `d` that would leave
    /// the domain at once from `x` (coordinates on a face, pointing out),
    /// so that the polish searches along the faces it touches.
    fn feasible_direction(&self, x: &[F], d: &mut [F]);
    /// The dimension the domain was made for, if it has one (a box with a
    /// side per coordinate); a run of another dimension is refused.
    fn dimension(&self) -> Option<usize> {
        None
    }
}

impl<F: Float> Domain<F> for Unbounded {
    #[inline(always)]
    fn confine(&self, _x: &mut [F], _y: &mut [F]) {}
    #[inline(always)]
    fn project(&self, _x: &mut [F]) {}
    #[inline(always)]
    fn feasible_direction(&self, _x: &[F], _d: &mut [F]) {}
}

/// A domain behind a reference is the same domain (for large boxes kept
/// elsewhere).
impl<F: Float, B: Domain<F> + ?Sized> Domain<F> for &B {
    #[inline(always)]
    fn confine(&self, x: &mut [F], y: &mut [F]) {
        (**self).confine(x, y);
    }
    #[inline(always)]
    fn project(&self, x: &mut [F]) {
        (**self).project(x);
    }
    #[inline(always)]
    fn feasible_direction(&self, x: &[F], d: &mut [F]) {
        (**self).feasible_direction(x, d);
    }
    fn dimension(&self) -> Option<usize> {
        (**self).dimension()
    }
}

/// A box read side by side: `[lo_i, hi_i]` in coordinate `i`, each finite.
/// [`Auto`](crate::Auto) scales by it what it does per coordinate: its
/// dynamics, quenches and curvature probes run in the box's unit
/// coordinates (every side stretched to the widest), and its restarts are
/// uniform in the box. [`Interval`] (every side the same) and [`Bounds`]
/// implement it.
pub trait Sides<F: Float>: Domain<F> {
    /// The ends `(lo_i, hi_i)` of coordinate `i` (below the dimension).
    fn side(&self, i: usize) -> (F, F);

    /// A point uniform in the box: `lo_i + (hi_i - lo_i) u`, one
    /// `next_u64` per coordinate, as [`Interval`]'s and [`Bounds`]'
    /// [`Start`]s draw it.
    fn uniform<R: Rng + ?Sized>(&self, rng: &mut R, x: &mut [F]) {
        uniform_each(rng, x, |i| self.side(i).0, |i| self.side(i).1);
    }
}

impl<F: Float, B: Sides<F> + ?Sized> Sides<F> for &B {
    #[inline(always)]
    fn side(&self, i: usize) -> (F, F) {
        (**self).side(i)
    }
}

/// All of `R^D`: no constraint (the default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unbounded;

/// The box `[lo, hi]^D`, the same interval in every coordinate; also a
/// [`Start`]: uniform in the box, from each chain's own generator.
///
/// ```
/// use hrla::{Builder, Chain, Interval, Hrla, Rastrigin, Stop};
///
/// let mut chains: Vec<Chain<f64, 10>> = (0..50).map(|_| Chain::new()).collect();
/// let domain = Interval::new(-5.12, 5.12)?;
/// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, domain)
///     .domain(domain)
///     .stop(Stop::new().steps(1_000))
///     .build(&mut chains)?;
/// opt.run()?;
/// assert!(opt.chains().iter().all(|c| c.x().iter().all(|v| v.abs() <= 5.12)));
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<F> {
    lo: F,
    hi: F,
}

impl<F: Float> Interval<F> {
    /// `lo < hi`, both finite.
    pub fn new(lo: F, hi: F) -> Result<Self, Error> {
        finite("lo", lo)?;
        finite("hi", hi)?;
        if !(hi - lo > F::ZERO && (hi - lo).is_finite()) {
            return Err(Error::NotPositive {
                name: "hi - lo",
                value: (hi - lo).to_f64(),
            });
        }
        Ok(Self { lo, hi })
    }

    /// The lower end.
    pub fn lo(&self) -> F {
        self.lo
    }

    /// The upper end.
    pub fn hi(&self) -> F {
        self.hi
    }
}

/// Folds `v` into `[lo, hi]` by reflection at the ends; `true` when an odd
/// number of reflections reversed the direction. Non-finite `v` is left
/// alone (the chain then diverges as it would without a box).
#[inline(always)]
fn reflect<F: Float>(v: F, lo: F, hi: F) -> (F, bool) {
    if (v >= lo && v <= hi) || !v.is_finite() {
        return (v, false);
    }
    let w = hi - lo;
    // Position in the unfolded line, in periods of 2w.
    let t = v - lo;
    let period = w + w;
    if !(t.is_finite() && period.is_finite()) {
        return reflect_halved(v, lo, hi);
    }
    let periods = floor(t / period);
    let r = t - periods * period;
    let (out, flipped) = if r <= w {
        (lo + r, false)
    } else {
        (hi - (r - w), true)
    };
    // Rounding may leave the result a hair outside: clamp.
    (clamp(out, lo, hi), flipped)
}

/// [`reflect`] for a box or a distance so wide that `2 (hi - lo)` or
/// `v - lo` overflows: the same folding on halved values, which cannot
/// overflow (halving is exact away from subnormals, which such widths do
/// not meet). Kept apart so that ordinary boxes keep their bits.
#[cold]
fn reflect_halved<F: Float>(v: F, lo: F, hi: F) -> (F, bool) {
    let (v, lo2, hi2) = (v * F::HALF, lo * F::HALF, hi * F::HALF);
    let w = hi2 - lo2;
    let period = w + w;
    let t = v - lo2;
    let periods = floor(t / period);
    let r = t - periods * period;
    // An overflowing ratio (a tiny box, a huge distance) leaves `r`
    // infinite: the clamp brings it to an end.
    let (out, flipped) = if r <= w {
        (lo + (r + r), false)
    } else {
        (hi - ((r - w) + (r - w)), true)
    };
    (clamp(out, lo, hi), flipped)
}

#[inline(always)]
fn clamp<F: Float>(v: F, lo: F, hi: F) -> F {
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// `floor` through the float trait's operations (exact for the values
/// reflection meets: below `2^52` periods).
#[inline(always)]
fn floor<F: Float>(v: F) -> F {
    let magic = F::from_f64((1u64 << (F::MANTISSA_DIGITS - 1)) as f64);
    if v.abs() >= magic {
        return v;
    }
    let r = if v >= F::ZERO {
        (v + magic) - magic
    } else {
        -((-v + magic) - magic)
    };
    if r > v { r - F::ONE } else { r }
}

/// Reflects every coordinate of `x` into `[lo(i), hi(i)]`, flipping the
/// velocity where an odd number of reflections reversed it: the one
/// confinement of [`Interval`] and [`Bounds`].
#[inline(always)]
pub(crate) fn confine_each<F: Float>(
    x: &mut [F],
    y: &mut [F],
    lo: impl Fn(usize) -> F,
    hi: impl Fn(usize) -> F,
) {
    for (i, (xi, yi)) in x.iter_mut().zip(y.iter_mut()).enumerate() {
        let (v, flipped) = reflect(*xi, lo(i), hi(i));
        *xi = v;
        if flipped {
            *yi = -*yi;
        }
    }
}

#[inline(always)]
pub(crate) fn project_each<F: Float>(
    x: &mut [F],
    lo: impl Fn(usize) -> F,
    hi: impl Fn(usize) -> F,
) {
    for (i, xi) in x.iter_mut().enumerate() {
        if xi.is_finite() {
            *xi = clamp(*xi, lo(i), hi(i));
        }
    }
}

#[inline(always)]
pub(crate) fn feasible_each<F: Float>(
    x: &[F],
    d: &mut [F],
    lo: impl Fn(usize) -> F,
    hi: impl Fn(usize) -> F,
) {
    for (i, (&xi, di)) in x.iter().zip(d.iter_mut()).enumerate() {
        if (xi <= lo(i) && *di < F::ZERO) || (xi >= hi(i) && *di > F::ZERO) {
            *di = F::ZERO;
        }
    }
}

/// Uniform in the box: `lo + (hi - lo) u`, `u` from the top 53 (f64) or 24
/// (f32) bits of one `next_u64` per coordinate.
#[inline(always)]
fn uniform_each<F: Float, R: Rng + ?Sized>(
    rng: &mut R,
    x: &mut [F],
    lo: impl Fn(usize) -> F,
    hi: impl Fn(usize) -> F,
) {
    let bits = F::MANTISSA_DIGITS;
    let scale = F::from_f64(1.0 / (1u64 << bits) as f64);
    for (i, xi) in x.iter_mut().enumerate() {
        let u = F::from_u64(rng.next_u64() >> (64 - bits)) * scale;
        let (lo, hi) = (lo(i), hi(i));
        *xi = clamp(lo + (hi - lo) * u, lo, hi);
    }
}

impl<F: Float> Domain<F> for Interval<F> {
    #[inline(always)]
    fn confine(&self, x: &mut [F], y: &mut [F]) {
        confine_each(x, y, |_| self.lo, |_| self.hi);
    }

    #[inline(always)]
    fn project(&self, x: &mut [F]) {
        project_each(x, |_| self.lo, |_| self.hi);
    }

    fn feasible_direction(&self, x: &[F], d: &mut [F]) {
        feasible_each(x, d, |_| self.lo, |_| self.hi);
    }
}

impl<F: Float> Sides<F> for Interval<F> {
    #[inline(always)]
    fn side(&self, _i: usize) -> (F, F) {
        (self.lo, self.hi)
    }
}

impl<F: Float> Start<F> for Interval<F> {
    /// Uniform in the box: `lo + (hi - lo) u`, `u` from the top 53 (f64) or
    /// 24 (f32) bits of one `next_u64` per coordinate.
    fn initial_point<R: Rng + ?Sized>(&mut self, _chain: usize, rng: &mut R, x: &mut [F]) {
        uniform_each(rng, x, |_| self.lo, |_| self.hi);
    }
}

/// A box with its own interval `[lo_i, hi_i]` in every coordinate; also a
/// start, uniform in the box. The sides live in any `AsRef<[F]>`: arrays
/// on firmware, a slice or a `Vec` on a host.
///
/// Each coordinate reflects exactly as an [`Interval`] of its own sides
/// does, so a `Bounds` whose sides are all equal gives an `Interval`'s
/// bits.
///
/// ```
/// use hrla::{Bounds, Builder, Chain, Hrla, Rastrigin, Stop};
///
/// // Amplitude in [0, 10], centre in [0, 100], width in [0.1, 20].
/// let bounds = Bounds::new([0.0, 0.0, 0.1], [10.0, 100.0, 20.0])?;
/// let mut chains: Vec<Chain<f64, 3>> = (0..8).map(|_| Chain::new()).collect();
/// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, bounds)
///     .domain(bounds)
///     .stop(Stop::new().steps(500))
///     .build(&mut chains)?;
/// opt.run()?;
/// assert!(opt.chains().iter().all(|c| c.x()[1] >= 0.0 && c.x()[1] <= 100.0));
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds<F, S> {
    lo: S,
    hi: S,
    float: PhantomData<F>,
}

impl<F: Float, S: AsRef<[F]>> Bounds<F, S> {
    /// `lo_i < hi_i`, each finite with a finite width, and as many of
    /// each: [`Error::Length`] for sides of different lengths or none,
    /// [`Error::NotFinite`] for an end that is not finite,
    /// [`Error::NotPositive`] (`hi - lo`) for an empty or overflowing side.
    pub fn new(lo: S, hi: S) -> Result<Self, Error> {
        let (l, h) = (lo.as_ref(), hi.as_ref());
        if l.is_empty() {
            return Err(Error::Zero { name: "box sides" });
        }
        if h.len() != l.len() {
            return Err(Error::Length {
                name: "hi",
                expected: l.len(),
                got: h.len(),
            });
        }
        for (&a, &b) in l.iter().zip(h) {
            Interval::new(a, b)?;
        }
        Ok(Self {
            lo,
            hi,
            float: PhantomData,
        })
    }

    /// The lower ends.
    pub fn lo(&self) -> &[F] {
        self.lo.as_ref()
    }

    /// The upper ends.
    pub fn hi(&self) -> &[F] {
        self.hi.as_ref()
    }

    #[inline(always)]
    fn sides(&self) -> (&[F], &[F]) {
        (self.lo.as_ref(), self.hi.as_ref())
    }
}

impl<F: Float, S: AsRef<[F]>> Domain<F> for Bounds<F, S> {
    #[inline(always)]
    fn confine(&self, x: &mut [F], y: &mut [F]) {
        let (lo, hi) = self.sides();
        confine_each(x, y, |i| lo[i], |i| hi[i]);
    }

    #[inline(always)]
    fn project(&self, x: &mut [F]) {
        let (lo, hi) = self.sides();
        project_each(x, |i| lo[i], |i| hi[i]);
    }

    fn feasible_direction(&self, x: &[F], d: &mut [F]) {
        let (lo, hi) = self.sides();
        feasible_each(x, d, |i| lo[i], |i| hi[i]);
    }

    fn dimension(&self) -> Option<usize> {
        Some(self.lo.as_ref().len())
    }
}

impl<F: Float, S: AsRef<[F]>> Sides<F> for Bounds<F, S> {
    #[inline(always)]
    fn side(&self, i: usize) -> (F, F) {
        let (lo, hi) = self.sides();
        (lo[i], hi[i])
    }
}

impl<F: Float, S: AsRef<[F]>> Start<F> for Bounds<F, S> {
    /// Uniform in the box, as [`Interval`]'s start: one `next_u64` per
    /// coordinate.
    fn initial_point<R: Rng + ?Sized>(&mut self, _chain: usize, rng: &mut R, x: &mut [F]) {
        let (lo, hi) = self.sides();
        uniform_each(rng, x, |i| lo[i], |i| hi[i]);
    }

    fn dimension(&self) -> Option<usize> {
        Some(self.lo.as_ref().len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_folds_into_the_box() {
        let (lo, hi) = (-1.0f64, 3.0);
        // (input, output, flipped)
        for (v, want, flip) in [
            (0.5, 0.5, false),
            (3.5, 2.5, true),
            (-1.5, -0.5, true),
            (7.5, -0.5, false),
            (11.5, 2.5, true),
            (-9.5, -0.5, true),
        ] {
            let (got, flipped) = reflect(v, lo, hi);
            assert!((got - want).abs() < 1e-12, "{v}: {got} != {want}");
            assert_eq!(flipped, flip, "{v}");
        }
        assert!(reflect(f64::NAN, lo, hi).0.is_nan());
    }

    #[test]
    fn reflection_in_a_box_of_width_near_max_stays_finite() {
        let (lo, hi) = (-6e307f64, 6e307);
        // (input, output, flipped): 6.5e307 is 5e306 past hi.
        for (v, want, flip) in [
            (6.5e307, 5.5e307, true),
            (-6.5e307, -5.5e307, true),
            (f64::MAX, 6e307 - (f64::MAX - 6e307), true),
            (-f64::MAX, -6e307 + (f64::MAX - 6e307), true),
        ] {
            let (got, flipped) = reflect(v, lo, hi);
            assert!(
                (got - want).abs() <= 1e-15 * want.abs(),
                "{v}: {got} != {want}"
            );
            assert_eq!(flipped, flip, "{v}");
        }
        // Widest box: every finite input lands inside.
        let (lo, hi) = (-f64::MAX, f64::MAX);
        for v in [f64::MAX, -f64::MAX, 1e308, 0.0] {
            let (got, _) = reflect(v, lo, hi);
            assert!(got.is_finite() && got >= lo && got <= hi, "{v}: {got}");
        }
        // A tiny box far away: the ratio overflows, the result is an end.
        let (lo, hi) = (0.0f64, 1e-300);
        for v in [f64::MAX, -f64::MAX] {
            let (got, _) = reflect(v, lo, hi);
            assert!(got.is_finite() && got >= lo && got <= hi, "{v}: {got}");
        }
        let (got, flipped) = reflect(3e38f32, -1.5e38, 1.5e38);
        assert!((got - 0.0).abs() <= 1e32 && flipped, "{got}");
    }

    #[test]
    fn floor_matches_libm() {
        for v in [-3.5f64, -3.0, -0.2, 0.0, 0.2, 2.0, 2.7, 1e15, -1e15] {
            assert_eq!(floor(v), libm::floor(v), "{v}");
        }
    }
}
