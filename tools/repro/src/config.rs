//! What one configuration of a protocol is: the sampler, dimension, step
//! size, chains, steps, temperature and start of a run ([`RunSpec`]), what
//! it records, and the checks that it is one the kernel accepts.

use hrla::{AnySampler, AnySchedule, Constant, Linear, Sampler, SamplerKind};

use crate::error::ReproError;
use crate::peers::{AnyPeer, DEFAULT_WALK, PeerKind, RandomWalk, Scope};
use crate::stats::grid_points;

/// The name of a sampler in tables and legends: `HRLA`, `ULA`, `OLA`.
pub fn sampler_label(kind: SamplerKind) -> String {
    kind.name().to_ascii_uppercase()
}

/// What moves the samples of a run: a kernel sampler (with the run's `h`
/// and temperature) or one of T3's peers (with its own schedule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// The kernel's HRLA, ULA or OLA.
    Kernel(SamplerKind),
    /// A simulated-annealing peer and its proposal.
    Peer {
        /// The method.
        kind: PeerKind,
        /// The random-walk proposal.
        walk: RandomWalk,
    },
}

impl Method {
    /// `HRLA`, `ULA`, `OLA`, `SA`, ..., with what differs from the default
    /// proposal (`SA coordinate sd=0.5`).
    pub fn label(self) -> String {
        match self {
            Method::Kernel(kind) => sampler_label(kind),
            Method::Peer { kind, walk } => {
                let mut label = kind.label().to_string();
                if walk.scope == Scope::Coordinate {
                    label.push_str(" coordinate");
                }
                if walk.sd != DEFAULT_WALK.sd {
                    label.push_str(&format!(" sd={}", walk.sd));
                }
                label
            }
        }
    }

    /// The peer, if the method is one.
    pub fn peer(self) -> Option<AnyPeer> {
        match self {
            Method::Kernel(_) => None,
            Method::Peer { kind, walk } => Some(kind.peer(walk)),
        }
    }

    /// Whether each evaluation is of `U` and `∇U` (the kernel's samplers)
    /// rather than of `U` alone (the peers).
    pub fn uses_gradient(self) -> bool {
        matches!(self, Method::Kernel(_))
    }
}

/// The inverse temperature along a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Temperature {
    /// A constant `a`.
    Constant(f64),
    /// The paper's linear annealing from `low` to `high` over the `K` steps.
    Linear {
        /// `a_low` (0.1 in the paper).
        low: f64,
        /// `a_high`.
        high: f64,
    },
}

impl Temperature {
    /// `a`, or `a_high` when annealing: the value that labels a curve.
    pub fn label_value(self) -> f64 {
        match self {
            Temperature::Constant(a) => a,
            Temperature::Linear { high, .. } => high,
        }
    }

    /// The symbol of [`label_value`](Temperature::label_value): `a` or
    /// `a_high`.
    pub fn label_name(self) -> &'static str {
        match self {
            Temperature::Constant(_) => "a",
            Temperature::Linear { .. } => "a_high",
        }
    }

    /// The kernel's schedule over `steps` iterations.
    pub fn schedule(self, steps: u64) -> Result<AnySchedule<f64>, hrla::Error> {
        Ok(match self {
            Temperature::Constant(a) => AnySchedule::Constant(Constant::new(a)?),
            Temperature::Linear { low, high } => {
                AnySchedule::Linear(Linear::new(low, high, steps)?)
            }
        })
    }
}

/// The initial positions (velocities start at 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StartSpec {
    /// `x_0 ~ N(centre · 1, variance · I)`, independently per chain.
    Gaussian {
        /// Every coordinate of the mean.
        centre: f64,
        /// The variance of each coordinate.
        variance: f64,
    },
    /// Every chain at `value · 1`.
    Point(f64),
}

impl StartSpec {
    /// Short label: `N(3,10I)` or `(1,...,1)`.
    pub fn label(self) -> String {
        match self {
            StartSpec::Gaussian { centre, variance } => format!("N({centre}·1, {variance} I)"),
            StartSpec::Point(v) => format!("({v}, ..., {v})"),
        }
    }
}

/// Everything that defines one configuration of a protocol. The potential
/// is the paper's Rastrigin (`U* = 0`), the sampler parameters the paper's
/// (`alpha = beta = 1`, `b = 10`).
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// The sampler or peer.
    pub method: Method,
    /// The dimension `d`, any `d >= 1`.
    pub d: usize,
    /// The step size `h` (kernel samplers only).
    pub h: f64,
    /// The number of chains `N`.
    pub chains: usize,
    /// The number of steps `K`.
    pub steps: u64,
    /// Constant `a` or linear annealing (kernel samplers only: a peer
    /// follows its own schedule).
    pub temperature: Temperature,
    /// The initial distribution.
    pub start: StartSpec,
    /// The stride `s` of the running best.
    pub stride: u64,
    /// The iterates at which the running best is reported, increasing,
    /// each in `1..=K` (usually just `K`).
    pub checkpoints: Vec<u64>,
    /// The tolerances of the empirical probability curves.
    pub eps: Vec<f64>,
    /// The curve grid: the probability is recorded at `k = 0, r, 2r, ...`
    /// (`None`: no curves).
    pub curve_every: Option<u64>,
}

impl RunSpec {
    /// Length of the per-configuration count buffer: one counter per
    /// tolerance and grid iterate.
    pub fn count_len(&self) -> usize {
        self.eps.len() * grid_points(self.steps, self.curve_every)
    }

    /// `N K`: the chain-steps of one run (at most 2^53 in a plan, see
    /// [`limits`](crate::limits)).
    pub fn chain_steps(&self) -> u64 {
        self.chains as u64 * self.steps
    }

    /// The short name of the configuration in tables and legends:
    /// `HRLA a_high=4 (1,...,1)`, `SA (1,...,1)`, `CSA coordinate sd=1
    /// N(3·1, 10 I)`.
    pub fn label(&self) -> String {
        let start = match self.start {
            StartSpec::Point(v) => format!("({v},...,{v})"),
            g @ StartSpec::Gaussian { .. } => g.label(),
        };
        let t = self.temperature;
        match self.method {
            Method::Peer { .. } => format!("{} {start}", self.method.label()),
            Method::Kernel(_) => format!(
                "{} {}={} {start}",
                self.method.label(),
                t.label_name(),
                t.label_value()
            ),
        }
    }

    /// The configuration as an error message names it: its
    /// [`label`](RunSpec::label) with its dimension, chains and steps.
    pub fn name(&self) -> String {
        format!(
            "{} (d = {}, N = {}, K = {})",
            self.label(),
            self.d,
            self.chains,
            self.steps
        )
    }

    /// Evaluations one run makes up to iterate `k`: `N` at the start and
    /// `N` per iteration, for the kernel (each of `U` and `∇U`) and the
    /// peers (of `U`) alike; a test checks it against the counts the runs
    /// report.
    pub fn evaluations_to(&self, k: u64) -> u64 {
        self.chains as u64 * (k + 1)
    }

    /// The kernel's schedule over the run and its sampler (a peer's run has
    /// neither).
    pub fn kernel_setup(&self) -> Result<(AnySchedule<f64>, AnySampler<f64>), hrla::Error> {
        let kind = match self.method {
            Method::Kernel(kind) => kind,
            Method::Peer { .. } => {
                return Err(hrla::Error::Unknown {
                    what: "kernel sampler",
                    expected: " hrla ula ola",
                });
            }
        };
        let schedule = self.temperature.schedule(self.steps)?;
        let sampler = AnySampler::paper(kind, self.h)?;
        Ok((schedule, sampler))
    }

    /// Checks every parameter once, before any run starts, so that workers
    /// never meet an error the user could have been told about up front.
    pub fn validate(&self) -> Result<(), ReproError> {
        if self.d == 0 {
            return Err(ReproError::Flag {
                flag: "--d",
                reason: "d = 0: a run needs at least one coordinate".to_string(),
            });
        }
        let bad = |what: &str| Err(ReproError::Usage(what.to_string()));
        if self.chains == 0 {
            return bad("N must be at least 1");
        }
        if self.steps == 0 {
            return bad("K must be at least 1");
        }
        if self.stride == 0 || self.curve_every == Some(0) {
            return bad("the stride and the curve grid step must be at least 1");
        }
        if self.checkpoints.is_empty()
            || !self.checkpoints.windows(2).all(|w| w[0] < w[1])
            || !self
                .checkpoints
                .iter()
                .all(|&c| (1..=self.steps).contains(&c))
        {
            return Err(ReproError::Usage(format!(
                "checkpoints {:?} must increase within 1..=K = {}",
                self.checkpoints, self.steps
            )));
        }
        // The running best at k is the min over k = s, 2s, ... <= k: with a
        // stride beyond the first checkpoint it is over no iterate.
        if self.stride > self.checkpoints[0] {
            return Err(ReproError::Flag {
                flag: "--stride",
                reason: format!(
                    "a stride of {} leaves no iterate s, 2s, ... <= k = {} for the running best \
                     at the first checkpoint; it must be at most {1}",
                    self.stride, self.checkpoints[0]
                ),
            });
        }
        if self.eps.iter().any(|e| !e.is_finite()) {
            return bad("tolerances must be finite");
        }
        let start = |flag, reason: String| Err(ReproError::Flag { flag, reason });
        match self.start {
            StartSpec::Gaussian { variance, .. } if !(variance.is_finite() && variance >= 0.0) => {
                return start(
                    "--start-var",
                    format!("the start's variance must be finite and >= 0, got {variance}"),
                );
            }
            StartSpec::Gaussian { centre, .. } if !centre.is_finite() => {
                return start(
                    "--start-centre",
                    format!("the start's centre must be finite, got {centre}"),
                );
            }
            StartSpec::Point(v) if !v.is_finite() => {
                return start(
                    "--start-point",
                    format!("the start point's coordinates must be finite, got {v}"),
                );
            }
            _ => {}
        }
        if let Method::Peer { walk, .. } = self.method {
            if !(walk.sd.is_finite() && walk.sd > 0.0) {
                return bad("the peers' proposal SD must be finite and > 0");
            }
            return Ok(());
        }
        let (schedule, sampler) = self.kernel_setup()?;
        // Every a_k of a linear schedule lies between its ends, and the
        // coefficients are monotone in a, so checking both ends suffices.
        sampler.at(hrla::Schedule::inverse_temperature(&schedule, 0))?;
        sampler.at(self.temperature.label_value())?;
        Ok(())
    }
}
