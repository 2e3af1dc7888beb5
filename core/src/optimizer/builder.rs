//! Assembling a run: the required pieces, the optional settings, and the
//! checks that make a built optimiser one that can run.

use super::algorithm::Optimizer;
use super::executor::Serial;
use super::stop::Stop;
use super::store::{IntoStore, Origins, RunsOn, Starts, Steps, Store};
use crate::domain::Unbounded;
use crate::error::{Error, check_dimensions};
use crate::float::Float;
use crate::sampler::Sampler;
use crate::schedule::Schedule;

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
pub struct Builder<F, P, S, C, St, B = Unbounded, E = Serial> {
    potential: P,
    domain: B,
    sampler: S,
    schedule: C,
    start: St,
    seed: u64,
    stride: u64,
    stop: Stop<F>,
    executor: E,
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
            executor: Serial,
        }
    }
}

impl<F: Float, P, S: Sampler<F>, C: Schedule<F>, St, B, E> Builder<F, P, S, C, St, B, E> {
    /// Confines the chains to a domain, such as a box
    /// ([`Interval`](crate::Interval)): initial points and steps are
    /// reflected into it, and the polish stays in it.
    pub fn domain<B2>(self, domain: B2) -> Builder<F, P, S, C, St, B2, E> {
        self.with(|_, executor| (domain, executor))
    }

    /// Steps the chains of every step on `executor`, in parts, on threads
    /// if it has them (the `hrla-threads` crate's `Threads`), with the
    /// same bits as on the calling thread ([`Serial`], the default).
    pub fn executor<E2>(self, executor: E2) -> Builder<F, P, S, C, St, B, E2> {
        self.with(|domain, _| (domain, executor))
    }

    /// These settings with the domain and the executor `change` makes of
    /// theirs.
    fn with<B2, E2>(
        self,
        change: impl FnOnce(B, E) -> (B2, E2),
    ) -> Builder<F, P, S, C, St, B2, E2> {
        let (domain, executor) = change(self.domain, self.executor);
        Builder {
            potential: self.potential,
            domain,
            sampler: self.sampler,
            schedule: self.schedule,
            start: self.start,
            seed: self.seed,
            stride: self.stride,
            stop: self.stop,
            executor,
        }
    }

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
    /// `chains` is a container of [`Chain`](crate::Chain)s of a dimension
    /// `D` known at compile time (an array, a slice, a `heapless::Vec`, a
    /// `Vec`; the potential a [`Potential`](crate::Potential)), or
    /// [`FlatChains`](crate::FlatChains) of a dimension known at run time
    /// (the potential a [`BatchPotential`](crate::BatchPotential), the
    /// initial points evaluated in one batch): the same run gives the same
    /// bits over either.
    ///
    /// An initial point whose position, value or gradient is not finite is
    /// infeasible: the chain draws another from the start law (the next
    /// draws of its own generator), up to [`START_TRIES`](crate::START_TRIES) points in all and
    /// within the evaluation budget, which every point drawn counts in. A
    /// run whose initial points are all feasible draws each once.
    ///
    /// ```
    /// use hrla::{Builder, FlatChains, FlatSlices, Hrla, Interval, Rastrigin, Stop};
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
    ///     .build(chains)?;
    /// let report = opt.run()?;
    /// assert_eq!(opt.best().x.len(), d);
    /// # let _ = report;
    /// # Ok::<(), hrla::Error>(())
    /// ```
    ///
    /// Errors: [`Error::Zero`] for no chains, a dimension `D = 0`, a zero
    /// stride or budget or stall window, or a schedule of length 0;
    /// [`Error::Budget`] for an evaluation budget below the number of
    /// chains; [`Error::ScheduleLongerThanRun`] for a step budget that
    /// would cut the schedule short; the sampler's error if it refuses
    /// `a_0`; [`Error::NonFiniteStart`] if a chain found no feasible
    /// initial point; [`Error::UnboundedBelow`] if the potential at an
    /// initial point is below `-sqrt(F::MAX)`; [`Error::Length`] for a
    /// box, a start or a potential made for another dimension.
    #[allow(clippy::type_complexity)] // the optimiser's own parameters, all inferred
    pub fn build<T, Ch>(
        mut self,
        chains: Ch,
    ) -> Result<Optimizer<F, P, S, C, Ch::Store, B, E>, Error>
    where
        Ch: IntoStore<F, T>,
        Ch::Store: Starts<F, P, B, St> + Steps<F, P, B>,
        E: RunsOn<F, Ch::Store, S::Kernel, P, B>,
    {
        let mut chains = chains.into_store();
        let (n, d) = (chains.len(), chains.dim());
        self.check(n, d)?;
        let from = Origins {
            potential: &self.potential,
            domain: &self.domain,
            start: &mut self.start,
            seed: self.seed,
        };
        check_dimensions(d, chains.check(&from))?;
        let kernel = self.sampler.at(self.schedule.inverse_temperature(0))?;
        // Redraws beyond one point per chain, within the evaluation budget.
        let mut spare = self.stop.evaluations.map_or(u64::MAX, |b| b - n as u64);
        let evaluations = chains.start(from, &mut spare)?;
        Ok(Optimizer::assemble(
            self.potential,
            self.domain,
            self.sampler,
            kernel,
            self.schedule,
            chains,
            self.executor,
            evaluations,
            self.stride,
            self.stop,
        ))
    }
}
