//! A user's potential: a function evaluated on batches of points.
//!
//! The optimiser over flat storage hands a step's points to the kernel's
//! batch seam as one `(n, d)` block, and [`hrla::Auto`] its points;
//! [`UserBatch`] calls the function once on the rows of the live chains.

use std::ops::ControlFlow;
use std::sync::{Arc, Mutex, MutexGuard};

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

/// A [`BatchFunction`] as the kernel's batch seam, [`BatchPotential`](hrla::BatchPotential):
/// the optimiser over flat storage ([`hrla::Optimizer`] over [`hrla::FlatChains`]) hands it a
/// whole step's `(n, d)` block of points, and the function is called once
/// on the rows of the live chains, with no prediction of the step.
///
/// The rows of diverged chains (`skip`) are not passed: when every chain
/// is live the block goes to the function as it is, without a copy;
/// otherwise the live rows are gathered, and the answers written back to
/// their chains. A failure (the function's error) stops the run (the seam
/// answers [`ControlFlow::Break`], and the kernel ends with
/// [`hrla::Error::Stopped`]); so does every later call, without calling
/// the function, until [`UserBatch::finish`] hands the failure over. A
/// clone shares the function and its state (a failure seen by one is seen
/// by all).
#[derive(Clone)]
pub struct UserBatch {
    function: Arc<dyn BatchFunction>,
    state: Arc<Mutex<BatchState>>,
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
            state: Arc::new(Mutex::new(BatchState::default())),
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
    ) -> ControlFlow<()> {
        let mut state = self.state();
        if state.error.is_some() {
            return ControlFlow::Break(());
        }
        let live = skip.iter().filter(|&&s| !s).count();
        if live == 0 {
            return ControlFlow::Continue(());
        }
        let answered = if live == skip.len() {
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
        match answered {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                state.error = Some(Error::User(e));
                ControlFlow::Break(())
            }
        }
    }
}
