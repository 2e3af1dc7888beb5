//! `hrla.Auto`: the kernel's default solver.

use std::ops::ControlFlow;

use hrla::{Auto, Parts};
use hrla_dyn::auto::{self, Problem};
use hrla_dyn::{Progress, termination_name};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::config;
use crate::errors::{guard, layer};
use crate::observer::{SIGNAL_WORK, observe, observer_of};
use crate::potential;

/// The default solver: Langevin basin hopping on a ladder of inverse
/// temperatures. Each chain holds a basin; a round moves it by `steps`
/// HRLA steps, quenches the end by L-BFGS and accepts by Metropolis
/// at its own `a`; neighbouring rungs exchange basins. `h = step_scale / L`
/// and the ladder's centre are measured on the quenched starts, and each
/// rung's step is then steered to accept `accept` of its proposals. The
/// best point is polished to a local minimum. Needs a box.
#[pyclass(frozen, module = "hrla", name = "Auto", get_all)]
#[derive(Clone)]
pub struct PyAuto {
    /// HRLA steps per round.
    pub steps: u64,
    /// `h = step_scale / L`, `L` the typical curvature at the basins.
    pub step_scale: f64,
    /// Half-width of the ladder of inverse temperatures in `ln a`.
    pub ladder: f64,
    /// Evaluations per quench, at most.
    pub quench: u64,
    /// Evaluations per quench of the initial points, at most.
    pub first_quench: u64,
    /// Rounds without a new best that make a stall (the convergence
    /// window is two).
    pub stall: u64,
    /// The acceptance rate each rung's step is steered to (0: fixed).
    pub accept: f64,
}

/// What `Auto.minimize` found.
#[pyclass(frozen, module = "hrla", name = "Solution", get_all)]
pub struct PySolution {
    /// The best point.
    pub x: Py<PyArray1<f64>>,
    /// `U(x)`.
    pub value: f64,
    /// Evaluations used, all included (at most the budget).
    pub evaluations: u64,
    /// Rounds of sampling done.
    pub rounds: u64,
    /// The step size chosen.
    pub step: f64,
    /// The inverse temperature at the end.
    pub inverse_temperature: f64,
    /// Chains run.
    pub chains: usize,
    /// Why it ended: `"Evaluations"` (the budget is spent).
    pub termination: &'static str,
    /// Chains whose last proposal met a point where `U` or its gradient
    /// is not finite (rejected: the chain stayed in its feasible basin).
    pub diverged_chains: usize,
    /// Whether every chain's last proposal was infeasible; not a failure,
    /// since `x` is feasible and polished either way.
    pub all_diverged: bool,
    /// The kernel's sentence for the solution.
    pub message: String,
}

#[pymethods]
impl PyAuto {
    #[new]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (*, steps = None, step_scale = None, ladder = None, quench = None, first_quench = None, stall = None, accept = None))]
    fn new(
        steps: Option<&Bound<'_, PyAny>>,
        step_scale: Option<f64>,
        ladder: Option<f64>,
        quench: Option<&Bound<'_, PyAny>>,
        first_quench: Option<&Bound<'_, PyAny>>,
        stall: Option<&Bound<'_, PyAny>>,
        accept: Option<f64>,
    ) -> PyResult<Self> {
        let d = Auto::<f64>::default();
        let steps = config::unsigned_opt(steps, "steps")?;
        let quench = config::unsigned_opt(quench, "quench")?;
        let first_quench = config::unsigned_opt(first_quench, "first_quench")?;
        let stall = config::unsigned_opt(stall, "stall")?;
        Ok(Self {
            steps: steps.unwrap_or(d.steps),
            step_scale: step_scale.unwrap_or(d.step_scale),
            ladder: ladder.unwrap_or(d.ladder),
            quench: quench.unwrap_or(d.quench),
            first_quench: first_quench.unwrap_or(d.first_quench),
            stall: stall.unwrap_or(d.stall),
            accept: accept.unwrap_or(d.accept),
        })
    }

    /// The convergence window measured best for these settings:
    /// two stalls, `2 stall` rounds.
    #[getter]
    fn converged_window(&self) -> u64 {
        self.stall.saturating_mul(2)
    }

    /// The number of chains measured best for an evaluation budget:
    /// `budget / 60 000` within `[4, 16]`.
    #[staticmethod]
    fn chains_for(budget: &Bound<'_, PyAny>) -> PyResult<usize> {
        Ok(Auto::<f64>::chains_for(config::unsigned(budget, "budget")?))
    }

    /// Minimises `potential` over the box `domain` within `budget`
    /// evaluations (all counted), with `chains` chains (default
    /// `chains_for(budget)`); chain `c` draws from the generator of
    /// `(seed, c)`. A Python potential is called with one row at a time.
    ///
    /// `x0` (a sequence of `D` floats, in the box) is chain 0's initial
    /// point instead of a uniform draw; where `potential` is not finite
    /// there, the run raises rather than redraw it.
    ///
    /// `observer(rounds, evaluations, best_value)`, when given, is called
    /// as the run goes (a Python potential's run: after every step of the
    /// chains, quench and the polish; a built-in's: at every new round and
    /// every new best); a true answer ends the run, whose termination is
    /// then `"Observer"`, and an exception ends it with that exception.
    /// With `with_x=True` it gets the best point too, a copy:
    /// `observer(rounds, evaluations, best_value, best_x)`.
    ///
    /// The run's own rules: `target` ends it once the best value is at or
    /// below it (termination `"Target"`); `stall=(window, tolerance)` ends
    /// the rounds once the best has not fallen by more than `tolerance`
    /// over `window` rounds (`"Stalled"`); `rounds` ends them after that
    /// many (`"Steps"`); `converge=window` ends them as converged once the
    /// best has not fallen, beyond rounding (relative to the spread of the
    /// initial values), over `window` rounds (`"Converged"`; `converged_window`
    /// is the measured default). A run ended by `stall`, `rounds` or
    /// `converge` still polishes its best point.
    ///
    /// `soft_budget`, below `budget`, is the budget the run plans within:
    /// the quench of its lowest initial point may go on past it to
    /// `budget`, and a run whose first quench did ends there
    /// (`"Evaluations"`); the default chains are those of `soft_budget`.
    #[pyo3(signature = (potential, domain, budget, seed = None, *, chains = None, dim = None, x0 = None, observer = None, with_x = false, target = None, stall = None, rounds = None, converge = None, soft_budget = None))]
    #[allow(clippy::too_many_arguments)]
    fn minimize(
        &self,
        py: Python<'_>,
        potential: &Bound<'_, PyAny>,
        domain: &Bound<'_, PyAny>,
        budget: &Bound<'_, PyAny>,
        seed: Option<&Bound<'_, PyAny>>,
        chains: Option<&Bound<'_, PyAny>>,
        dim: Option<&Bound<'_, PyAny>>,
        x0: Option<Vec<f64>>,
        observer: Option<&Bound<'_, PyAny>>,
        with_x: bool,
        target: Option<f64>,
        stall: Option<(u64, f64)>,
        rounds: Option<&Bound<'_, PyAny>>,
        converge: Option<&Bound<'_, PyAny>>,
        soft_budget: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PySolution> {
        guard(|| {
            let problem = Problem {
                potential: potential::from_py(potential)?,
                domain: config::domain(domain)?,
                budget: config::unsigned(budget, "budget")?,
                seed: config::unsigned_opt(seed, "seed")?.unwrap_or(0),
                chains: config::unsigned_opt(chains, "chains")?,
                dim: config::unsigned_opt(dim, "dim")?,
                x0,
                target,
                stall,
                rounds: config::unsigned_opt(rounds, "rounds")?,
                converge: config::unsigned_opt(converge, "converge")?,
                soft: config::unsigned_opt(soft_budget, "soft_budget")?,
            };
            self.solve(py, &problem, observer, with_x)
        })
    }
}

impl PyAuto {
    fn solve(
        &self,
        py: Python<'_>,
        problem: &Problem,
        observer: Option<&Bound<'_, PyAny>>,
        with_x: bool,
    ) -> PyResult<PySolution> {
        let observer = observer_of(observer)?;
        let user = auto::is_user(&problem.potential);
        let auto = Auto {
            steps: self.steps,
            step_scale: self.step_scale,
            ladder: self.ladder,
            quench: self.quench,
            first_quench: self.first_quench,
            stall: self.stall,
            accept: self.accept,
            parts: Parts::default(),
        };
        // Looks for Ctrl-C every `SIGNAL_WORK` coordinates evaluated
        // (counted, so where it looks is the same on every machine), and
        // at every look of a Python potential's run (whose calls cost far
        // more). A Python potential's own exception (Ctrl-C while it ran
        // included) needs no look: the layer ends the run at once with it.
        let mut checked = 0;
        let mut seen: Option<(u64, f64)> = None;
        let mut stopped: Option<PyErr> = None;
        let mut observe = |p: &Progress| {
            // The user's observer: whenever a Python potential has run (its
            // cost dwarfs the call), else at a new round or a new best.
            let news = seen.is_none_or(|(rounds, best)| p.iteration != rounds || p.value < best);
            if let Some(o) = &observer
                && (user || news)
            {
                seen = Some((p.iteration, p.value));
                let answer = Python::attach(|py| observe(py, o, p, with_x));
                match answer {
                    Ok(false) => {}
                    Ok(true) => return ControlFlow::Break(()),
                    Err(e) => {
                        stopped = Some(e);
                        return ControlFlow::Break(());
                    }
                }
            }
            let every = (SIGNAL_WORK / p.dim as u64).max(1);
            if !user && p.evaluations - checked < every {
                return ControlFlow::Continue(());
            }
            checked = p.evaluations;
            match Python::attach(|py| py.check_signals()) {
                Ok(()) => ControlFlow::Continue(()),
                Err(e) => {
                    stopped = Some(e);
                    ControlFlow::Break(())
                }
            }
        };
        let found = if user {
            auto::solve(&auto, problem, &mut observe)
        } else {
            py.detach(|| auto::solve(&auto, problem, &mut observe))
        };
        if let Some(e) = stopped {
            return Err(e);
        }
        let s = found.map_err(layer)?;
        Ok(PySolution {
            x: PyArray1::from_vec(py, s.x).unbind(),
            value: s.value,
            evaluations: s.evaluations,
            rounds: s.rounds,
            step: s.step,
            inverse_temperature: s.inverse_temperature,
            chains: s.chains,
            termination: termination_name(s.termination),
            diverged_chains: s.diverged_chains,
            all_diverged: s.all_diverged,
            message: s.message,
        })
    }
}

#[pymethods]
impl PySolution {
    fn __repr__(&self) -> String {
        format!(
            "Solution(value={:?}, evaluations={}, rounds={}, step={:?}, inverse_temperature={:?}, chains={}, \
             termination={:?}, diverged_chains={})",
            self.value,
            self.evaluations,
            self.rounds,
            self.step,
            self.inverse_temperature,
            self.chains,
            self.termination,
            self.diverged_chains,
        )
    }

    fn __str__(&self) -> String {
        self.message.clone()
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyAuto>()?;
    m.add_class::<PySolution>()
}
