//! The baseline a visitor knows: plain gradient descent with random
//! restarts, `x <- x - h ∇U(x)` on the same landscape and from the same
//! initial points as the samplers (the kernel's Gaussian start, chain `c`
//! drawing from `chain_seed(seed, c)`), each chain starting afresh at a
//! point drawn uniformly over the view's box once it has stopped moving
//! (a local minimum reached), left the box, or failed (a non-finite value
//! or gradient).
//!
//! It is a multistart: restarts use the box, which the samplers are not
//! told, and in 2-D a basin covering 1% of the box is hit about once in a
//! hundred restarts. Its published values are each chain's best so far,
//! since its current point may be a fresh restart.

use hrla::rand_core::Rng;
use hrla::{KnownMinimum, Potential};
use rand_xoshiro::Xoshiro256PlusPlus;
use wasm_bindgen::prelude::*;

use crate::error::Error;
use crate::landscape::{GridError, Landscape};
use crate::read;
use crate::settings::Settings;
use crate::{MAX_STEPS, Optimizer, Summary, termination_code};

/// A move shorter than this share of the box's half-width is no move: the
/// chain has reached a local minimum (or a flat place) and restarts.
const STOPPED: f64 = 1e-6;

/// Gradient descent with random restarts on one landscape, with the
/// buffers JavaScript views (in the layout of [`crate::Optimizer`]'s).
#[wasm_bindgen]
#[derive(Clone, Debug)]
pub struct Descent {
    landscape: Landscape,
    h: f64,
    bounds: [f64; 4],
    /// Squared length of a move that counts as none.
    still2: f64,
    rngs: Vec<Xoshiro256PlusPlus>,
    x: Vec<[f64; 2]>,
    g: Vec<[f64; 2]>,
    iteration: u64,
    restarts: u64,
    best: (f64, [f64; 2], u64),
    seed: u64,
    positions: Vec<f64>,
    /// Zero: descent has no velocity (a buffer so that readers of the
    /// samplers' buffers read this one alike).
    velocities: Vec<f64>,
    /// Each chain's best value so far.
    values: Vec<f64>,
    summary: [f64; Summary::Len as usize],
}

impl Descent {
    /// Chains at the settings' initial points (`landscape`, `h`, `chains`,
    /// `centre`, `spread`, `seed`; the temperature and sampler play no
    /// part), restarting within `bounds = [x0, x1, y0, y1]`. Errors: a box
    /// that is not finite and increasing, and whatever the kernel refuses
    /// of the settings (they make a sampler's run first: the same checks,
    /// the same initial points).
    pub fn new(settings: &Settings, bounds: [f64; 4]) -> Result<Self, Error> {
        let [x0, x1, y0, y1] = bounds;
        if !(bounds.iter().all(|v| v.is_finite()) && x0 < x1 && y0 < y1) {
            return Err(GridError::Box(bounds).into());
        }
        // The kernel's own optimiser checks the settings and draws the
        // initial points: descent starts exactly where the samplers do, each
        // chain's generator where the kernel left it.
        let start = Optimizer::from_settings(settings)?;
        let landscape = settings.landscape.clone();
        let run = start.engine();
        let rngs = run.generators();
        let pairs =
            |v: Vec<f64>| -> Vec<[f64; 2]> { v.chunks_exact(2).map(|p| [p[0], p[1]]).collect() };
        let x = pairs(run.positions());
        let g = pairs(run.gradients());
        let values = run.values();
        let (bx, bv, _) = run.best();
        let best = (bv, [bx[0], bx[1]], 0);
        let n = x.len();
        let half = 0.5 * (x1 - x0).max(y1 - y0);
        let mut this = Self {
            landscape,
            h: settings.h,
            bounds,
            still2: (STOPPED * half).powi(2),
            rngs,
            x,
            g,
            iteration: 0,
            restarts: 0,
            best,
            seed: settings.seed,
            positions: vec![0.0; 2 * n],
            velocities: vec![0.0; 2 * n],
            values,
            summary: [0.0; Summary::Len as usize],
        };
        this.publish();
        Ok(this)
    }

    /// `steps` steps of every chain; returns them (descent never fails: a
    /// chain that cannot go on restarts).
    pub fn step_n(&mut self, steps: u32) -> u32 {
        for _ in 0..steps {
            self.iteration += 1;
            for c in 0..self.x.len() {
                self.step_chain(c);
            }
        }
        self.publish();
        steps
    }

    fn step_chain(&mut self, c: usize) {
        let [x0, x1, y0, y1] = self.bounds;
        let (x, g) = (self.x[c], self.g[c]);
        let next = [x[0] - self.h * g[0], x[1] - self.h * g[1]];
        let mut grad = [0.0; 2];
        let u = self.landscape.value_and_gradient(&next, &mut grad);
        let moved2 = (next[0] - x[0]).powi(2) + (next[1] - x[1]).powi(2);
        let inside = (x0..=x1).contains(&next[0]) && (y0..=y1).contains(&next[1]);
        let ok = u.is_finite() && grad.iter().all(|v| v.is_finite());
        if ok {
            self.x[c] = next;
            self.g[c] = grad;
            self.values[c] = self.values[c].min(u);
            if u < self.best.0 {
                self.best = (u, next, self.iteration);
            }
        }
        if !ok || !inside || moved2 <= self.still2 {
            self.restart(c);
        }
    }

    /// Chain `c` afresh, uniformly over the box (until a point with a
    /// finite value and gradient: at most 64 draws, else it stays).
    fn restart(&mut self, c: usize) {
        let [x0, x1, y0, y1] = self.bounds;
        for _ in 0..64 {
            let rng = &mut self.rngs[c];
            let p = [x0 + (x1 - x0) * unit(rng), y0 + (y1 - y0) * unit(rng)];
            let mut grad = [0.0; 2];
            let u = self.landscape.value_and_gradient(&p, &mut grad);
            if u.is_finite() && grad.iter().all(|v| v.is_finite()) {
                self.x[c] = p;
                self.g[c] = grad;
                self.values[c] = self.values[c].min(u);
                if u < self.best.0 {
                    self.best = (u, p, self.iteration);
                }
                self.restarts += 1;
                return;
            }
        }
    }

    /// Restarts so far.
    pub fn restarts(&self) -> u64 {
        self.restarts
    }

    /// Positions, `[x0, x1]` per chain.
    pub fn positions(&self) -> &[f64] {
        &self.positions
    }

    /// Each chain's best value so far.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The summary, indexed by [`Summary`] (`A` is NaN: there is no
    /// temperature; `Diverged` is 0: a chain that fails restarts).
    pub fn summary(&self) -> &[f64; Summary::Len as usize] {
        &self.summary
    }

    fn publish(&mut self) {
        for (c, p) in self.x.iter().enumerate() {
            self.positions[2 * c..2 * c + 2].copy_from_slice(p);
        }
        let (value, x, at) = self.best;
        self.summary = [
            self.iteration as f64,
            x[0],
            x[1],
            value,
            at as f64,
            f64::NAN,
            0.0,
            self.landscape.global_minimum(),
            termination_code(None),
        ];
    }
}

/// Exported to JavaScript.
#[wasm_bindgen]
impl Descent {
    /// Descent from a settings object (see [`Settings::from_js`]; its
    /// sampler and temperature play no part) restarting within `bounds`,
    /// an array `[x0, x1, y0, y1]`; throws an `Error` with a `field` when
    /// a setting is refused (`box` for the bounds).
    #[wasm_bindgen(constructor)]
    pub fn new_js(settings: &JsValue, bounds: &JsValue) -> Result<Descent, JsValue> {
        let make = || -> Result<Descent, Error> {
            let settings = Settings::from_js(settings)?;
            let b = read::four(bounds, "box")?;
            Descent::new(&settings, b)
        };
        make().map_err(|e| e.to_js())
    }

    /// `steps` more steps of every chain (a whole number from 0 to
    /// `2^32 - 1`, else an `Error` with `field` `"steps"`); returns them.
    pub fn advance(&mut self, steps: &JsValue) -> Result<u32, JsValue> {
        let steps = read::count(steps, "steps", 0, MAX_STEPS.into()).map_err(|e| e.to_js())?;
        Ok(self.step_n(u32::try_from(steps).unwrap_or(MAX_STEPS)))
    }

    /// Restarts so far.
    #[wasm_bindgen(js_name = restarts)]
    pub fn restarts_js(&self) -> f64 {
        self.restarts as f64
    }

    /// Descent never stops by a rule: always `undefined`.
    pub fn termination(&self) -> Option<String> {
        None
    }
}

export_run_buffers!(Descent);

/// A uniform draw in `[0, 1)` from the top 53 bits.
fn unit<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same initial points as the samplers'; a chain stuck in a local
    /// minimum restarts within the box; the best so far never rises; the
    /// same seed gives the same run.
    #[test]
    fn descent_starts_with_the_samplers_and_restarts_in_the_box() {
        let settings = Settings {
            chains: 64,
            spread: 0.5,
            ..Settings::default()
        };
        let bounds = [-5.0, 5.0, -5.0, 5.0];
        let mut d = Descent::new(&settings, bounds).unwrap();
        let opt = Optimizer::from_settings(&settings).unwrap();
        assert_eq!(d.positions(), opt.positions());
        assert_eq!(d.values(), opt.values());
        let mut last = d.summary()[Summary::BestValue as usize];
        let mut before = d.values().to_vec();
        for _ in 0..50 {
            d.step_n(20);
            let s = d.summary();
            assert!(s[Summary::BestValue as usize] <= last);
            last = s[Summary::BestValue as usize];
            for (now, was) in d.values().iter().zip(&before) {
                assert!(now <= was);
            }
            before = d.values().to_vec();
            for p in d.positions().chunks(2) {
                assert!(
                    (-5.0..=5.0).contains(&p[0]) && (-5.0..=5.0).contains(&p[1]),
                    "{p:?}"
                );
            }
        }
        assert!(d.restarts() > 64, "{} restarts in 1000 steps", d.restarts());
        // With restarts over the box, descent finds Rastrigin's global basin.
        assert!(last < 1e-6, "best {last}");
        let mut again = Descent::new(&settings, bounds).unwrap();
        again.step_n(1000);
        let bits = |s: &[f64]| s.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(again.summary()), bits(d.summary()));
        assert_eq!(again.positions(), d.positions());
    }

    #[test]
    fn bad_input_is_refused() {
        let d = Settings::default();
        assert!(matches!(
            Descent::new(&d, [1.0, 0.0, 0.0, 1.0]),
            Err(Error::Grid(_))
        ));
        let bad = [
            Settings {
                h: -1.0,
                ..d.clone()
            },
            Settings {
                chains: 0,
                ..d.clone()
            },
            Settings {
                spread: f64::NAN,
                ..d
            },
        ];
        for settings in &bad {
            assert!(Descent::new(settings, [0.0, 1.0, 0.0, 1.0]).is_err());
        }
    }
}
