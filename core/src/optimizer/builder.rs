//! Assembling a run: the required pieces, the optional settings, and the
//! checks that make a built optimiser one that can run.

use rand_core::{Rng, SeedableRng};

use super::algorithm::Optimizer;
use super::chain::Chain;
use super::stop::Stop;
use super::stream::chain_seed;
use super::sweep::all_finite;
use crate::domain::{Domain, Unbounded};
use crate::error::Error;
use crate::float::Float;
use crate::potential::Potential;
use crate::sampler::Sampler;
use crate::schedule::Schedule;
use crate::start::Start;

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

    /// Seeds each chain's generator, draws its initial point from the start
    /// (zero velocity), evaluates the potential there, and checks the
    /// settings: as many chains as `chains` holds.
    ///
    /// Errors: [`Error::Zero`] for no chains, a dimension `D = 0`, a zero
    /// stride or budget or stall window; [`Error::Budget`] for an evaluation
    /// budget below the number of chains; [`Error::ScheduleLongerThanRun`]
    /// for a step budget that would cut the schedule short; the sampler's
    /// error if it refuses `a_0`; [`Error::NonFiniteStart`] if an initial
    /// point, its value or its gradient is not finite.
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
        if n == 0 {
            return Err(Error::Zero { name: "chains" });
        }
        if D == 0 {
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
        let kernel = self.sampler.at(self.schedule.inverse_temperature(0))?;
        let mut best = 0;
        for (c, chain) in chains.as_mut().iter_mut().enumerate() {
            chain.rng = R::seed_from_u64(chain_seed(self.seed, c as u64));
            self.start.initial_point(c, &mut chain.rng, &mut chain.x);
            chain.y = [F::ZERO; D];
            self.domain.confine(&mut chain.x, &mut chain.y);
            let value = self.potential.value_and_gradient(&chain.x, &mut chain.grad);
            let what = if !all_finite(&chain.x) {
                Some("position")
            } else if !value.is_finite() {
                Some("value")
            } else if !all_finite(&chain.grad) {
                Some("gradient")
            } else {
                None
            };
            if let Some(what) = what {
                return Err(Error::NonFiniteStart { chain: c, what });
            }
            chain.value = value;
            chain.best.x = chain.x;
            chain.best.value = value;
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
            self.stride,
            self.stop,
        ))
    }
}
