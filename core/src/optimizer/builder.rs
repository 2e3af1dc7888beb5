//! Assembling a run: the required pieces, the optional settings, and the
//! checks that make a built optimiser one that can run.

use rand_core::{Rng, SeedableRng};

use super::algorithm::Optimizer;
use super::chain::Chain;
use super::flat::{FlatChains, FlatOptimizer, FlatStorage, Parts};
use super::stop::Stop;
use super::stream::chain_seed;
use super::sweep::{Verdict, judge};
use crate::dim::Dim;
use crate::domain::{Domain, SliceDomain, Unbounded};
use crate::error::{Error, floor};
use crate::float::Float;
use crate::polish::Arrays;
use crate::potential::{BatchPotential, Potential, SlicePotential};
use crate::sampler::Sampler;
use crate::schedule::Schedule;
use crate::start::{SliceStart, Start};

/// The most points drawn for one chain's start: a point where the
/// potential or its gradient is not finite (a NaN, `+inf`) is infeasible,
/// and the chain draws again from the start law, up to this many times in
/// all. With a fraction `p` of the start law feasible, a chain fails with
/// probability `(1 - p)^100`: below `1e-4` for `p = 0.09`.
pub const START_TRIES: u32 = 100;

/// The settings of a run, before it has chains: a potential, a sampler, a
/// schedule (a plain `f32`/`f64` for a constant inverse temperature) and
/// a start; then, optionally, a seed, a stride and stopping rules. Every
/// setter is infallible; [`build`](Builder::build) checks everything.
///
/// ```
/// use hrla::{Builder, Chain, Gaussian, Hrla, Linear, Rastrigin};
///
/// // The paper's T1 setting: 10-D Rastrigin, linear annealing 0.1 -> 4
/// // over K = 14 000 steps (the schedule's length is the step budget).
/// let mut chains: Vec<Chain<f64, 10>> = (0..10).map(|_| Chain::new()).collect();
/// let mut opt = Builder::new(
///     Rastrigin,
///     Hrla::paper(0.01)?,
///     Linear::new(0.1, 4.0, 14_000)?,
///     Gaussian::new([3.0; 10], 10f64.sqrt())?,
/// )
/// .seed(1)
/// .build(&mut chains)?;
/// let report = opt.run()?;
/// assert_eq!(report.iterations, 14_000);
/// # Ok::<(), hrla::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Builder<F, P, S, C, St, B = Unbounded> {
    potential: P,
    domain: B,
    sampler: S,
    schedule: C,
    start: St,
    seed: u64,
    stride: u64,
    stop: Stop<F>,
}

impl<F: Float, P, S: Sampler<F>, C: Schedule<F>, St> Builder<F, P, S, C, St> {
    /// The required pieces; all of `R^D`, seed 0, stride 1, no stopping
    /// rule (a schedule with a length still gives a step budget).
    pub fn new(potential: P, sampler: S, schedule: C, start: St) -> Self {
        Self {
            potential,
            domain: Unbounded,
            sampler,
            schedule,
            start,
            seed: 0,
            stride: 1,
            stop: Stop::new(),
        }
    }

    /// Confines the chains to a domain, such as a box
    /// ([`Interval`](crate::Interval)): initial points and steps are
    /// reflected into it, and the polish stays in it.
    pub fn domain<B2>(self, domain: B2) -> Builder<F, P, S, C, St, B2> {
        Builder {
            potential: self.potential,
            domain,
            sampler: self.sampler,
            schedule: self.schedule,
            start: self.start,
            seed: self.seed,
            stride: self.stride,
            stop: self.stop,
        }
    }
}

impl<F: Float, P, S: Sampler<F>, C: Schedule<F>, St, B> Builder<F, P, S, C, St, B> {
    /// The run's seed: chain `c` draws from
    /// `R::seed_from_u64(chain_seed(seed, c))`.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Records the running best only at iterates that are multiples of
    /// `stride >= 1` (the paper's tables use 100 or 1).
    pub fn stride(mut self, stride: u64) -> Self {
        self.stride = stride;
        self
    }

    /// The stopping rules.
    pub fn stop(mut self, stop: Stop<F>) -> Self {
        self.stop = stop;
        self
    }

    /// The checks of every build, for `n` chains of dimension `d`; sets
    /// the step budget a schedule's length gives.
    fn check(&mut self, n: usize, d: usize) -> Result<(), Error> {
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if d == 0 {
            return Err(Error::Zero {
                name: "dimension D",
            });
        }
        if self.stride == 0 {
            return Err(Error::Zero { name: "stride" });
        }
        self.stop.validate()?;
        if let Some(budget) = self.stop.evaluations
            && budget < n as u64
        {
            return Err(Error::Budget { budget, chains: n });
        }
        if let Some(length) = self.schedule.length() {
            if length == 0 {
                return Err(Error::Zero {
                    name: "schedule length",
                });
            }
            match self.stop.steps {
                Some(steps) if steps < length => {
                    return Err(Error::ScheduleLongerThanRun {
                        schedule: length,
                        steps,
                    });
                }
                Some(_) => {}
                None => self.stop.steps = Some(length),
            }
        }
        Ok(())
    }

    /// Seeds each chain's generator, draws its initial point from the start
    /// (zero velocity), evaluates the potential there, and checks the
    /// settings: as many chains as `chains` holds.
    ///
    /// An initial point whose position, value or gradient is not finite is
    /// infeasible: the chain draws another from the start law (the next
    /// draws of its own generator), up to [`START_TRIES`] points in all and
    /// within the evaluation budget, which every point drawn counts in. A
    /// run whose initial points are all feasible draws each once.
    ///
    /// Errors: [`Error::Zero`] for no chains, a dimension `D = 0`, a zero
    /// stride or budget or stall window, or a schedule of length 0;
    /// [`Error::Budget`] for an evaluation budget below the number of
    /// chains; [`Error::ScheduleLongerThanRun`] for a step budget that
    /// would cut the schedule short; the sampler's error if it refuses
    /// `a_0`; [`Error::NonFiniteStart`] if a chain found no feasible
    /// initial point; [`Error::UnboundedBelow`] if the potential at an
    /// initial point is below `-sqrt(F::MAX)`; [`Error::Length`] for a
    /// box or a start made for another dimension.
    #[allow(clippy::type_complexity)] // the optimiser's own parameters, all inferred
    pub fn build<Store, const D: usize, R>(
        mut self,
        mut chains: Store,
    ) -> Result<Optimizer<F, P, S, C, Store, D, R, B>, Error>
    where
        P: Potential<F, D>,
        B: Domain<F, D>,
        St: Start<F, D>,
        Store: AsRef<[Chain<F, D, R>]> + AsMut<[Chain<F, D, R>]>,
        R: Rng + SeedableRng + 'static,
    {
        let n = chains.as_ref().len();
        self.check(n, D)?;
        for (name, dimension) in [
            ("box sides", self.domain.dimension()),
            ("start", self.start.dimension()),
        ] {
            if let Some(got) = dimension
                && got != D
            {
                return Err(Error::Length {
                    name,
                    expected: D,
                    got,
                });
            }
        }
        let kernel = self.sampler.at(self.schedule.inverse_temperature(0))?;
        let mut best = 0;
        // Redraws beyond one point per chain, within the evaluation budget.
        let mut spare = self.stop.evaluations.map_or(u64::MAX, |b| b - n as u64);
        let mut evaluations = 0;
        for (c, chain) in chains.as_mut().iter_mut().enumerate() {
            chain.rng = R::seed_from_u64(chain_seed(self.seed, c as u64));
            let (start, domain) = (&mut self.start, &self.domain);
            draw_start(
                c,
                chain,
                &self.potential,
                &mut spare,
                &mut evaluations,
                |rng, x, y| {
                    start.initial_point(c, rng, x);
                    *y = [F::ZERO; D];
                    domain.confine(x, y);
                },
            )?;
            chain.best.x = chain.x;
            chain.best.value = chain.value;
            chain.best.iteration = 0;
            chain.diverged = false;
        }
        for (c, chain) in chains.as_ref().iter().enumerate() {
            if chain.value < chains.as_ref()[best].value {
                best = c;
            }
        }
        Ok(Optimizer::assemble(
            self.potential,
            self.domain,
            self.sampler,
            kernel,
            self.schedule,
            chains,
            best,
            evaluations,
            self.stride,
            self.stop,
        ))
    }
}

impl<F: Float, P, S: Sampler<F>, C: Schedule<F>, St, B> Builder<F, P, S, C, St, B> {
    /// [`build`](Builder::build) for a dimension `dim` known at compile
    /// time ([`Const`](crate::Const)) or at run time ([`Dyn`](crate::Dyn)),
    /// over chains in flat storage: the same checks, the same draws and
    /// the same bits as over [`Chain`]s of that dimension. The initial
    /// points are evaluated in one batch (redraws one by one).
    ///
    /// ```
    /// use hrla::{Builder, Dyn, FlatChains, FlatSlices, Hrla, Interval, Rastrigin, Stop};
    /// use rand_core::SeedableRng;
    /// use rand_xoshiro::Xoshiro256PlusPlus;
    ///
    /// let (n, d) = (16, 21);
    /// let mut floats = vec![0.0; FlatSlices::<f64, Xoshiro256PlusPlus>::floats(n, d)];
    /// let (mut iterations, mut diverged) = (vec![0; n], vec![false; n]);
    /// let mut rngs: Vec<_> = (0..n).map(|_| Xoshiro256PlusPlus::seed_from_u64(0)).collect();
    /// let chains = FlatChains::new(d, &mut floats, &mut iterations, &mut diverged, &mut rngs)?;
    /// let domain = Interval::new(-5.12, 5.12)?;
    /// let mut opt = Builder::new(Rastrigin, Hrla::paper(0.01)?, 4.0, domain)
    ///     .domain(domain)
    ///     .stop(Stop::new().steps(1_000))
    ///     .build_flat(Dyn(d), chains)?;
    /// let report = opt.run()?;
    /// assert_eq!(opt.best().x.len(), d);
    /// # let _ = report;
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// Errors: those of [`build`](Builder::build), and
    /// [`Error::Length`] for storage, a box, a start or a potential of
    /// another dimension than `dim`.
    #[allow(clippy::type_complexity)] // the optimiser's own parameters, all inferred
    pub fn build_flat<Dm, R, Fs, Is, Ds, Rs>(
        mut self,
        dim: Dm,
        chains: FlatChains<F, R, Fs, Is, Ds, Rs>,
    ) -> Result<FlatOptimizer<F, P, S, C, Dm, R, B, Fs, Is, Ds, Rs>, Error>
    where
        Dm: Dim,
        P: BatchPotential<F>,
        B: SliceDomain<F>,
        St: SliceStart<F>,
        R: Rng + SeedableRng + 'static,
        Fs: FlatStorage<F>,
        Is: FlatStorage<u64>,
        Ds: FlatStorage<bool>,
        Rs: FlatStorage<R>,
    {
        let mut chains = chains;
        let (n, d) = (chains.len(), dim.value());
        self.check(n, d)?;
        for (name, dimension) in [
            ("chains", Some(chains.dim())),
            ("box sides", self.domain.dimension()),
            ("start", self.start.dimension()),
            ("potential", self.potential.batch_dimension()),
        ] {
            if let Some(got) = dimension
                && got != d
            {
                return Err(Error::Length {
                    name,
                    expected: d,
                    got,
                });
            }
        }
        let kernel = self.sampler.at(self.schedule.inverse_temperature(0))?;
        let mut spare = self.stop.evaluations.map_or(u64::MAX, |b| b - n as u64);
        let mut evaluations = n as u64;
        let Parts {
            x,
            y,
            grad,
            best_x,
            value,
            best_value,
            best_iteration,
            diverged,
            rng,
            ..
        } = chains.parts();
        for (c, ((x, y), rng)) in x
            .chunks_exact_mut(d)
            .zip(y.chunks_exact_mut(d))
            .zip(rng.iter_mut())
            .enumerate()
        {
            *rng = R::seed_from_u64(chain_seed(self.seed, c as u64));
            self.start.initial_point(c, rng, x);
            y.fill(F::ZERO);
            self.domain.confine(x, y);
        }
        diverged.fill(false);
        self.potential
            .values_and_gradients(d, x, grad, value, diverged);
        for c in 0..n {
            let span = c * d..(c + 1) * d;
            let mut tries = 1;
            loop {
                match judge(&x[span.clone()], value[c], &grad[span.clone()], floor()) {
                    Verdict::Feasible => break,
                    Verdict::Unbounded => {
                        return Err(Error::UnboundedBelow {
                            chain: c,
                            value: value[c].to_f64(),
                        });
                    }
                    Verdict::Infeasible(what) => {
                        if tries >= START_TRIES || spare == 0 {
                            return Err(Error::NonFiniteStart {
                                chain: c,
                                what,
                                tries,
                            });
                        }
                        spare -= 1;
                    }
                }
                let (xc, yc) = (&mut x[span.clone()], &mut y[span.clone()]);
                self.start.initial_point(c, &mut rng[c], xc);
                yc.fill(F::ZERO);
                self.domain.confine(xc, yc);
                self.potential.values_and_gradients(
                    d,
                    xc,
                    &mut grad[span.clone()],
                    &mut value[c..=c],
                    &[false],
                );
                evaluations += 1;
                tries += 1;
            }
        }
        best_x.copy_from_slice(x);
        best_value.copy_from_slice(value);
        best_iteration.fill(0);
        let mut best = 0;
        for c in 0..n {
            if value[c] < value[best] {
                best = c;
            }
        }
        Ok(FlatOptimizer::assemble(
            self.potential,
            self.domain,
            self.sampler,
            kernel,
            self.schedule,
            chains,
            dim,
            best,
            evaluations,
            self.stride,
            self.stop,
        ))
    }
}

/// Draws chain `c`'s initial point with `place` (which writes `x` and `y`
/// from the chain's generator) and evaluates it, drawing again where the
/// point is infeasible: [`draw_point`] on the chain's arrays.
pub(crate) fn draw_start<F, P, R, const D: usize>(
    c: usize,
    chain: &mut Chain<F, D, R>,
    potential: &P,
    spare: &mut u64,
    evaluations: &mut u64,
    mut place: impl FnMut(&mut R, &mut [F; D], &mut [F; D]),
) -> Result<(), Error>
where
    F: Float,
    P: Potential<F, D> + ?Sized,
{
    let Chain {
        x,
        y,
        grad,
        rng,
        value,
        ..
    } = chain;
    *value = draw_point(
        c,
        x,
        grad,
        rng,
        &Arrays::<_, D>(potential),
        spare,
        evaluations,
        |rng, x| {
            if let Ok(x) = <&mut [F; D]>::try_from(x) {
                place(rng, x, y);
            }
        },
    )?;
    Ok(())
}

/// Draws chain `c`'s initial point `x` with `place` (from the chain's
/// generator) and evaluates it into `grad`, drawing again where the point
/// is infeasible: up to [`START_TRIES`] points, each counted in
/// `evaluations`, the redraws within `spare`. Its value, or
/// [`Error::UnboundedBelow`] for a point below the floor,
/// [`Error::NonFiniteStart`] when no point was feasible.
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw_point<F, P, R>(
    c: usize,
    x: &mut [F],
    grad: &mut [F],
    rng: &mut R,
    potential: &P,
    spare: &mut u64,
    evaluations: &mut u64,
    mut place: impl FnMut(&mut R, &mut [F]),
) -> Result<F, Error>
where
    F: Float,
    P: SlicePotential<F> + ?Sized,
{
    let mut tries = 0;
    loop {
        place(rng, x);
        let value = potential.value_and_gradient(x, grad);
        *evaluations += 1;
        tries += 1;
        match judge(x, value, grad, floor()) {
            Verdict::Feasible => return Ok(value),
            Verdict::Unbounded => {
                return Err(Error::UnboundedBelow {
                    chain: c,
                    value: value.to_f64(),
                });
            }
            Verdict::Infeasible(what) => {
                if tries >= START_TRIES || *spare == 0 {
                    return Err(Error::NonFiniteStart {
                        chain: c,
                        what,
                        tries,
                    });
                }
                *spare -= 1;
            }
        }
    }
}
