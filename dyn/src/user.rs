//! A user's potential: a function evaluated on batches of points.
//!
//! The kernel's optimiser evaluates `U` once per live chain, right after
//! that chain's step. A user's function is instead called once per step for
//! all live chains: before each step the engine computes every live
//! chain's next position with the same kernel step, confinement and a copy
//! of the chain's generator (so the same bits as the step itself), calls
//! the function once on the `n x d` batch of them, and the optimiser's step
//! then reads the answers back in chain order ([`UserPotential`] in batch
//! mode, which answers a point from the batch only when it is, bit for
//! bit, the next point it was given, and checks at the end that every
//! answer was read). Outside steps (initial points excepted, which are
//! batched the same way, an infeasible one's redraws called alone) — the
//! polish, quenches, restarts, [`hrla::Auto`] — the function is called
//! with one row at a time.

use std::sync::{Arc, Mutex, MutexGuard};

use hrla::Potential;

use crate::Error;

/// A user function's own error, handed back as it was returned (a front
/// end downcasts it to its own type: a Python exception, say).
pub type UserError = Box<dyn std::error::Error + Send + Sync>;

/// A potential given as a function of a batch of points.
pub trait BatchFunction: Send + Sync {
    /// `U` and `∇U` at the `n` rows of `points` (`n x d`, row-major): fills
    /// `values` (`n`) and `grads` (`n x d`, row-major). An error ends the
    /// evaluation; the run then returns it.
    fn evaluate(
        &self,
        points: &[f64],
        d: usize,
        values: &mut [f64],
        grads: &mut [f64],
    ) -> Result<(), UserError>;
}

/// A [`BatchFunction`] as the kernel's [`Potential`] in dimension `D`.
pub struct UserPotential<const D: usize> {
    function: Arc<dyn BatchFunction>,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// The batch the next evaluations read, in order.
    batch: Option<Answers>,
    /// The first failure since the last [`UserPotential::finish`]: later
    /// evaluations return NaN without calling the function.
    error: Option<Error>,
}

/// The answers of one batched call, read in order.
struct Answers {
    points: Vec<f64>,
    values: Vec<f64>,
    grads: Vec<f64>,
    next: usize,
}

/// One call of `function` on the rows of `points`.
fn call(
    function: &dyn BatchFunction,
    points: &[f64],
    d: usize,
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let n = points.len() / d;
    let (mut values, mut grads) = (vec![0.0; n], vec![0.0; n * d]);
    function
        .evaluate(points, d, &mut values, &mut grads)
        .map_err(Error::User)?;
    Ok((values, grads))
}

impl<const D: usize> UserPotential<D> {
    /// `function` in dimension `D`.
    pub fn new(function: Arc<dyn BatchFunction>) -> Self {
        Self {
            function,
            state: Mutex::new(State::default()),
        }
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // A panic while the lock was held cannot leave the state invalid
        // (every field is replaced whole).
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Calls the function once on the rows of `points` (`n x D`) and
    /// keeps the answers for the next `n` evaluations, which must be at
    /// those points, in that order.
    pub fn load(&self, points: Vec<f64>) -> Result<(), Error> {
        let (values, grads) = call(&*self.function, &points, D)?;
        self.state().batch = Some(Answers {
            points,
            values,
            grads,
            next: 0,
        });
        Ok(())
    }

    /// Whether an evaluation failed since the last [`finish`](Self::finish)
    /// (the evaluations since return NaN without calling the function).
    pub fn failed(&self) -> bool {
        self.state().error.is_some()
    }

    /// Ends batch mode, checking that every answer was read; then returns
    /// the first error of any evaluation since the last call.
    pub fn finish(&self) -> Result<(), Error> {
        let mut state = self.state();
        if let Some(b) = state.batch.take()
            && b.next != b.values.len()
            && state.error.is_none()
        {
            state.error = Some(Error::Internal(format!(
                "hrla internal error: the step read {} of the {} batched answers",
                b.next,
                b.values.len()
            )));
        }
        state.error.take().map_or(Ok(()), Err)
    }
}

impl<const D: usize> Potential<f64, D> for UserPotential<D> {
    fn value_and_gradient(&self, x: &[f64; D], grad: &mut [f64; D]) -> f64 {
        let mut state = self.state();
        if state.error.is_some() {
            *grad = [f64::NAN; D];
            return f64::NAN;
        }
        if let Some(b) = state.batch.as_mut() {
            let row = b.next;
            let at = row * D..(row + 1) * D;
            let batched = b
                .points
                .get(at.clone())
                .is_some_and(|p| p.iter().zip(x).all(|(a, b)| a.to_bits() == b.to_bits()));
            if batched {
                b.next += 1;
                grad.copy_from_slice(&b.grads[at]);
                return b.values[row];
            }
            // A point the batch did not foresee: the redraw of an
            // infeasible initial point, which the builder evaluates
            // before the next chain's. Called alone, answered exactly.
        }
        drop(state);
        let answer = call(&*self.function, x, D).map(|(v, g)| {
            grad.copy_from_slice(&g);
            v[0]
        });
        state = self.state();
        answer.unwrap_or_else(|e| {
            state.error = Some(e);
            *grad = [f64::NAN; D];
            f64::NAN
        })
    }
}

/// A [`BatchFunction`] as the kernel's batch seam, [`BatchPotential`](hrla::BatchPotential):
/// the optimiser over flat storage ([`hrla::FlatOptimizer`]) hands it a
/// whole step's `(n, d)` block of points, and the function is called once
/// on the rows of the live chains, with no prediction of the step.
///
/// The rows of diverged chains (`skip`) are not passed: when every chain
/// is live the block goes to the function as it is, without a copy;
/// otherwise the live rows are gathered, and the answers written back to
/// their chains. After a failure (the function's error, or answers of the
/// wrong shape), every later evaluation is NaN without a call, so that the
/// run ends; [`UserBatch::finish`] returns the failure.
pub struct UserBatch {
    function: Arc<dyn BatchFunction>,
    state: Mutex<BatchState>,
}

#[derive(Default)]
struct BatchState {
    /// The live rows, when some chains are skipped.
    points: Vec<f64>,
    values: Vec<f64>,
    grads: Vec<f64>,
    /// The first failure since the last [`UserBatch::finish`].
    error: Option<Error>,
}

impl UserBatch {
    /// The batch seam for `function`.
    pub fn new(function: Arc<dyn BatchFunction>) -> Self {
        Self {
            function,
            state: Mutex::new(BatchState::default()),
        }
    }

    fn state(&self) -> MutexGuard<'_, BatchState> {
        // Every field is overwritten before it is read: a panic while the
        // lock was held leaves nothing to repair.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The first failure since the last call, if any.
    pub fn finish(&self) -> Result<(), Error> {
        self.state().error.take().map_or(Ok(()), Err)
    }
}

impl hrla::BatchPotential<f64> for UserBatch {
    fn values_and_gradients(
        &self,
        d: usize,
        x: &[f64],
        grad: &mut [f64],
        value: &mut [f64],
        skip: &[bool],
    ) {
        let mut state = self.state();
        let live = skip.iter().filter(|&&s| !s).count();
        if live == 0 {
            return;
        }
        let answered = if state.error.is_some() {
            Ok(())
        } else if live == skip.len() {
            self.function.evaluate(x, d, value, grad)
        } else {
            let BatchState {
                points,
                values,
                grads,
                ..
            } = &mut *state;
            points.clear();
            for (row, _) in x.chunks_exact(d).zip(skip).filter(|(_, s)| !**s) {
                points.extend_from_slice(row);
            }
            values.clear();
            values.resize(live, 0.0);
            grads.clear();
            grads.resize(live * d, 0.0);
            let answered = self.function.evaluate(points, d, values, grads);
            let rows = grad.chunks_exact_mut(d).zip(value.iter_mut()).zip(skip);
            let live_rows = rows.filter(|(_, s)| !**s);
            for (((g, v), _), (answer, a)) in live_rows.zip(grads.chunks_exact(d).zip(&*values)) {
                g.copy_from_slice(answer);
                *v = *a;
            }
            answered
        };
        if let Err(e) = answered {
            state.error.get_or_insert(Error::User(e));
        }
        if state.error.is_some() {
            // Every live chain diverges: the step ends the run, and the
            // engine reports the failure in place of the divergence.
            for (v, _) in value.iter_mut().zip(skip).filter(|(_, s)| !**s) {
                *v = f64::NAN;
            }
        }
    }
}
