//! The statistics of the paper's tables and figures, computed as spec
//! section 7 defines them, streamed so that memory does not grow with `K`.

/// Per-run observer of the best chain value `min_c U(x_k^c)` at each
/// iterate: keeps the paper's running best over the stride and counts, at
/// the iterates of the curve grid, whether the best chain is within each
/// tolerance.
///
/// - Running best at `K`: `min` over `k = s, 2s, ..., K` of the best chain
///   value. Iterate 0 (the initial points) is **not** included, unlike the
///   kernel's own running best, because the paper's tables exclude it.
///   It is also read at intermediate checkpoints `k_1 < k_2 < ... <= K`
///   (T3 reads one run of K = 500 at k = 50 and 500, as the authors' code
///   does): the value at `k_i` is the min over `k = s, 2s, ... <= k_i`.
/// - Empirical probability at `k`: the fraction of runs whose best chain at
///   iterate `k` has `U(x_k) - U* <= eps`. It is **not** running: a run that
///   was within `eps` at an earlier iterate but is not at `k` does not count
///   at `k`. The tracker adds 1 to `counts[e * points + j]` when the run is
///   within `eps[e]` at the grid iterate `k = j * every`; summing the counts
///   of all runs and dividing by `M` gives the curve.
#[derive(Debug)]
pub struct Tracker<'a> {
    stride: u64,
    every: Option<u64>,
    eps: &'a [f64],
    minimum: f64,
    running: f64,
    checkpoints: &'a [u64],
    at_checkpoints: Vec<f64>,
    counts: &'a mut [u32],
    points: usize,
}

impl<'a> Tracker<'a> {
    /// A tracker for a run of `steps` iterates with stride `stride >= 1`,
    /// a curve grid every `every` iterates (`None`: no curves), tolerances
    /// `eps` on `U - minimum`, adding into `counts`, whose length must be
    /// `eps.len() * grid_points(steps, every)`, and reading the running best
    /// at the increasing iterates `checkpoints` (each in `1..=steps`).
    ///
    /// # Panics
    /// If `stride` or `every` is 0, `counts` has the wrong length or the
    /// checkpoints are not increasing within `1..=steps`: programming
    /// errors (plans are validated), checked once per run.
    pub fn new(
        steps: u64,
        stride: u64,
        every: Option<u64>,
        checkpoints: &'a [u64],
        eps: &'a [f64],
        minimum: f64,
        counts: &'a mut [u32],
    ) -> Self {
        assert!(stride > 0, "stride must be >= 1");
        assert!(every != Some(0), "the curve grid step must be >= 1");
        assert!(
            checkpoints.windows(2).all(|w| w[0] < w[1])
                && checkpoints.iter().all(|&c| (1..=steps).contains(&c)),
            "checkpoints must increase within 1..=K"
        );
        let points = grid_points(steps, every);
        assert_eq!(
            counts.len(),
            eps.len() * points,
            "counts has the wrong length"
        );
        Self {
            stride,
            every,
            eps,
            minimum,
            running: f64::INFINITY,
            checkpoints,
            at_checkpoints: Vec::with_capacity(checkpoints.len()),
            counts,
            points,
        }
    }

    /// Whether iterate `k` is used (on the stride, the curve grid or a
    /// checkpoint), so the caller need not compute the best chain value at
    /// other iterates. Every wanted iterate must be observed, in order.
    pub fn wants(&self, k: u64) -> bool {
        (k > 0 && k.is_multiple_of(self.stride))
            || self.every.is_some_and(|r| k.is_multiple_of(r))
            || self.checkpoints.get(self.at_checkpoints.len()) == Some(&k)
    }

    /// Records `best_now = min_c U(x_k^c)` at iterate `k` (`+inf` when every
    /// chain has diverged). Iterates not [`wanted`](Tracker::wants) are
    /// ignored.
    pub fn observe(&mut self, k: u64, best_now: f64) {
        if k > 0 && k.is_multiple_of(self.stride) {
            self.running = self.running.min(best_now);
        }
        if self.checkpoints.get(self.at_checkpoints.len()) == Some(&k) {
            self.at_checkpoints.push(self.running);
        }
        if let Some(r) = self.every
            && k.is_multiple_of(r)
        {
            let j = (k / r) as usize;
            if j < self.points {
                let gap = best_now - self.minimum;
                for (e, &eps) in self.eps.iter().enumerate() {
                    if gap <= eps {
                        self.counts[e * self.points + j] += 1;
                    }
                }
            }
        }
    }

    /// The running best over `k = s, 2s, ...` so far (`+inf` before the
    /// first iterate on the stride).
    pub fn running_best(&self) -> f64 {
        self.running
    }

    /// The running best at each checkpoint passed so far.
    pub fn at_checkpoints(&self) -> &[f64] {
        &self.at_checkpoints
    }
}

/// The number of curve grid iterates `k = 0, r, 2r, ..., floor(K / r) r`
/// (0 when there is no grid).
pub fn grid_points(steps: u64, every: Option<u64>) -> usize {
    every.map_or(0, |r| (steps / r) as usize + 1)
}

/// Mean, median, standard deviation and standard error of a sample.
///
/// Convention: the **sample** standard deviation (divisor `M - 1`, the
/// default of most statistics packages; numpy's `std` uses `M`, so a table
/// made with numpy defaults is smaller by the factor `sqrt((M-1)/M)`, 0.5%
/// at `M = 100`). The standard error of the mean is `sd / sqrt(M)`. The
/// median of an even sample is the mean of the two middle values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    /// Sample size `M`.
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// Sample standard deviation (divisor `M - 1`; 0 when `M = 1`).
    pub sd: f64,
    /// Population standard deviation (divisor `M`, numpy's `std` default,
    /// which the authors' tables use), for comparison with the paper.
    pub sd_population: f64,
    /// Standard error of the mean, `sd / sqrt(M)`.
    pub se: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

impl Summary {
    /// The summary of no values: every statistic NaN.
    pub const EMPTY: Summary = Summary {
        n: 0,
        mean: f64::NAN,
        median: f64::NAN,
        sd: f64::NAN,
        sd_population: f64::NAN,
        se: f64::NAN,
        min: f64::NAN,
        max: f64::NAN,
    };

    /// The summary of `values` (in run order, so that the floating-point
    /// sums do not depend on the thread count); `None` when empty.
    ///
    /// Finite values give finite statistics: where the plain sums
    /// overflow (values near `f64::MAX`), they are taken again with every
    /// term scaled down first (the mean as the sum of `v / M`, the
    /// deviations over the largest of them); elsewhere the plain sums are
    /// the statistics, bit for bit.
    pub fn of(values: &[f64]) -> Option<Self> {
        let n = values.len();
        if n == 0 {
            return None;
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let ss: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
        let sd = if n > 1 {
            (ss / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        let plain = Self {
            n,
            mean,
            median,
            sd,
            sd_population: (ss / n as f64).sqrt(),
            se: sd / (n as f64).sqrt(),
            min: sorted[0],
            max: sorted[n - 1],
        };
        let finite = |s: &Self| {
            [s.mean, s.median, s.sd, s.sd_population, s.se]
                .iter()
                .all(|v| v.is_finite())
        };
        if finite(&plain) || !values.iter().all(|v| v.is_finite()) {
            return Some(plain);
        }
        Some(Self::scaled(values, &sorted))
    }

    /// [`Summary::of`] for finite values whose sums overflow: the mean as
    /// the sum of `v / M`, the deviations divided by the largest of them
    /// before squaring, the median's middle values halved before adding.
    fn scaled(values: &[f64], sorted: &[f64]) -> Self {
        let n = values.len();
        let mean = values.iter().map(|v| v / n as f64).sum::<f64>();
        let scale = values.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
        let ss_scaled: f64 = if scale > 0.0 {
            values.iter().map(|v| ((v - mean) / scale).powi(2)).sum()
        } else {
            0.0
        };
        let sd = if n > 1 {
            scale * (ss_scaled / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * sorted[n / 2 - 1] + 0.5 * sorted[n / 2]
        };
        Self {
            n,
            mean,
            median,
            sd,
            sd_population: scale * (ss_scaled / n as f64).sqrt(),
            se: sd / (n as f64).sqrt(),
            min: sorted[0],
            max: sorted[n - 1],
        }
    }
}

/// Why the running bests of a run at its checkpoints are not those of a
/// run: not finite (no iterate on the stride had a live chain), below the
/// potential's minimum, or larger than at an earlier checkpoint (a running
/// minimum never grows).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum BadRunningBest {
    /// Not a finite number.
    #[error(
        "the running best at k = {k} is {value}, not finite: no chain was alive at \
         any iterate on the stride up to k"
    )]
    NotFinite {
        /// The checkpoint.
        k: u64,
        /// The value.
        value: f64,
    },
    /// Below the potential's global minimum.
    #[error("the running best at k = {k} is {value}, below the potential's minimum {minimum}")]
    BelowMinimum {
        /// The checkpoint.
        k: u64,
        /// The value.
        value: f64,
        /// The potential's minimum.
        minimum: f64,
    },
    /// Larger than at the checkpoint before.
    #[error("the running best at k = {k} is {value}, larger than at the checkpoint before")]
    Increasing {
        /// The checkpoint.
        k: u64,
        /// The value.
        value: f64,
    },
}

/// Checks a run's running bests `values` at `checkpoints` (as many) on a
/// potential whose global minimum is `minimum`: every run made by the tool
/// passes unless it failed, and a merge takes nothing else.
pub fn check_running_best(
    values: &[f64],
    checkpoints: &[u64],
    minimum: f64,
) -> Result<(), BadRunningBest> {
    let mut before = f64::INFINITY;
    for (&value, &k) in values.iter().zip(checkpoints) {
        if !value.is_finite() {
            return Err(BadRunningBest::NotFinite { k, value });
        }
        if value < minimum {
            return Err(BadRunningBest::BelowMinimum { k, value, minimum });
        }
        if value > before {
            return Err(BadRunningBest::Increasing { k, value });
        }
        before = value;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Best chain values at iterates k = 0..=6.
    const SEQ: [f64; 7] = [0.5, 3.0, 1.0, 4.0, 0.8, 5.0, 9.0];

    fn feed(t: &mut Tracker<'_>) {
        for (k, &v) in SEQ.iter().enumerate() {
            if t.wants(k as u64) {
                t.observe(k as u64, v);
            }
        }
    }

    #[test]
    fn running_best_is_over_the_stride_and_excludes_iterate_0() {
        let eps = [];
        let mut none = [];
        // Stride 2: k = 2, 4, 6 -> min(1.0, 0.8, 9.0); k = 0 (0.5) is excluded.
        let mut t = Tracker::new(6, 2, None, &[], &eps, 0.0, &mut none);
        feed(&mut t);
        assert_eq!(t.running_best(), 0.8);
        // Stride 3: k = 3, 6 -> min(4.0, 9.0); the 0.8 at k = 4 is off the stride.
        let mut none = [];
        let mut t = Tracker::new(6, 3, None, &[], &eps, 0.0, &mut none);
        feed(&mut t);
        assert_eq!(t.running_best(), 4.0);
        // Stride 1: every iterate but 0.
        let mut none = [];
        let mut t = Tracker::new(6, 1, None, &[], &eps, 0.0, &mut none);
        feed(&mut t);
        assert_eq!(t.running_best(), 0.8);
    }

    #[test]
    fn running_best_at_checkpoints() {
        let eps = [];
        let mut none = [];
        // Stride 2, checkpoints k = 3 and 6: min over k = 2 (1.0); then
        // min over k = 2, 4, 6 (0.8).
        let mut t = Tracker::new(6, 2, None, &[3, 6], &eps, 0.0, &mut none);
        feed(&mut t);
        assert_eq!(t.at_checkpoints(), [1.0, 0.8]);
        // A checkpoint before the first stride iterate has no running best.
        let mut none = [];
        let mut t = Tracker::new(6, 4, None, &[1, 5], &eps, 0.0, &mut none);
        feed(&mut t);
        assert_eq!(t.at_checkpoints(), [f64::INFINITY, 0.8]);
    }

    #[test]
    fn empirical_probability_is_not_running() {
        let eps = [2.0, 4.5];
        let mut counts = [0u32; 14];
        let mut t = Tracker::new(6, 1, Some(1), &[], &eps, 0.0, &mut counts);
        feed(&mut t);
        // eps = 2: within at k = 0, 2, 4 only; once within, a later worse
        // iterate does not count.
        assert_eq!(counts[..7], [1, 0, 1, 0, 1, 0, 0]);
        // eps = 4.5: within at k = 0, 1, 2, 3, 4.
        assert_eq!(counts[7..], [1, 1, 1, 1, 1, 0, 0]);
    }

    #[test]
    fn probability_counts_on_a_coarse_grid_and_relative_to_the_minimum() {
        let eps = [2.0];
        // Grid every 2: k = 0, 2, 4, 6 -> 4 points; a minimum of 0.6 makes
        // the gaps 3.0 - 0.6 etc.
        let mut counts = [0u32; 4];
        let mut t = Tracker::new(6, 100, Some(2), &[], &eps, 0.6, &mut counts);
        feed(&mut t);
        // Gaps at k = 0, 2, 4, 6: -0.1, 0.4, 0.2, 8.4.
        // Stride 100 never hits within K = 6: no running best.
        assert_eq!(t.running_best(), f64::INFINITY);
        assert_eq!(counts, [1, 1, 1, 0]);
        // Accumulating a second run adds to the counts.
        let mut t = Tracker::new(6, 1, Some(2), &[], &eps, 0.6, &mut counts);
        feed(&mut t);
        assert_eq!(counts, [2, 2, 2, 0]);
    }

    #[test]
    fn diverged_runs_never_count() {
        let eps = [1e300];
        let mut counts = [0u32; 2];
        let mut t = Tracker::new(1, 1, Some(1), &[], &eps, 0.0, &mut counts);
        t.observe(0, f64::INFINITY);
        t.observe(1, f64::INFINITY);
        assert_eq!(t.running_best(), f64::INFINITY);
        assert_eq!(counts, [0, 0]);
    }

    #[test]
    fn summary_uses_the_sample_standard_deviation() {
        let s = Summary::of(&[4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.n, 4);
        assert_eq!(s.mean, 2.5);
        assert_eq!(s.median, 2.5);
        // Sum of squares 5, divisor M - 1 = 3.
        assert!((s.sd - (5.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.se - (5.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-15);
        assert!((s.sd_population - (5.0f64 / 4.0).sqrt()).abs() < 1e-15);
        assert_eq!((s.min, s.max), (1.0, 4.0));
        let odd = Summary::of(&[5.0, 1.0, 3.0]).unwrap();
        assert_eq!(odd.median, 3.0);
        assert_eq!(Summary::of(&[7.0]).unwrap().sd, 0.0);
        assert!(Summary::of(&[]).is_none());
    }

    /// Finite values near `f64::MAX` have finite statistics, the same as
    /// those of the values scaled down by a power of two (exact), scaled
    /// back up.
    #[test]
    fn summary_of_huge_values_is_finite() {
        let big = [f64::MAX, 0.5 * f64::MAX, f64::MAX, 0.0];
        let s = Summary::of(&big).unwrap();
        let small: Vec<f64> = big.iter().map(|v| v / 1024.0).collect();
        let t = Summary::of(&small).unwrap();
        for (x, y) in [
            (s.mean, t.mean),
            (s.median, t.median),
            (s.sd, t.sd),
            (s.sd_population, t.sd_population),
            (s.se, t.se),
        ] {
            assert!(x.is_finite());
            // A few roundings apart: relative 1e-15.
            assert!((x / 1024.0 - y).abs() <= 1e-15 * y, "{x} against {y}");
        }
        // Values the plain sums handle are summarised by them, bit for bit.
        let plain = Summary::of(&[4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!(plain.mean, 2.5);
    }

    #[test]
    fn running_bests_must_be_finite_non_negative_and_non_increasing() {
        let ks = [50, 500];
        assert_eq!(check_running_best(&[2.0, 1.0], &ks, 0.0), Ok(()));
        assert_eq!(check_running_best(&[0.0, 0.0], &ks, 0.0), Ok(()));
        assert!(matches!(
            check_running_best(&[f64::INFINITY, 1.0], &ks, 0.0),
            Err(BadRunningBest::NotFinite { k: 50, .. })
        ));
        assert!(matches!(
            check_running_best(&[2.0, f64::NAN], &ks, 0.0),
            Err(BadRunningBest::NotFinite { k: 500, .. })
        ));
        assert!(matches!(
            check_running_best(&[2.0, -1e-300], &ks, 0.0),
            Err(BadRunningBest::BelowMinimum { k: 500, .. })
        ));
        assert!(matches!(
            check_running_best(&[1.0, 2.0], &ks, 0.0),
            Err(BadRunningBest::Increasing { k: 500, .. })
        ));
    }

    #[test]
    fn grid_points_include_iterate_zero() {
        assert_eq!(grid_points(14_000, Some(28)), 501);
        assert_eq!(grid_points(10, Some(3)), 4);
        assert_eq!(grid_points(10, None), 0);
    }
}
