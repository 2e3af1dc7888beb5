//! The SMC step of SMC-SA and CSA: the members are reweighted from one
//! Boltzmann target to the next, `w_n ∝ pi_k(x_n) / pi_{k-1}(x_n) =
//! exp(-(beta_k - beta_{k-1}) U(x_n))`, and `N` ancestors are drawn
//! multinomially from those weights (Zhou and Chen 2013).

use hrla::rand_core::Rng;

use super::moves::uniform;
use super::population::Population;

/// The normalised weights `exp(-dbeta U_n) / sum_m exp(-dbeta U_m)`, formed
/// relative to the smallest finite value so that none overflows; members
/// with a non-finite value weigh 0. All zero when no value is finite.
pub fn weights(values: &[f64], dbeta: f64) -> Vec<f64> {
    let min = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    let mut w: Vec<f64> = values
        .iter()
        .map(|&v| {
            if v.is_finite() {
                libm::exp(-dbeta * (v - min))
            } else {
                0.0
            }
        })
        .collect();
    let total: f64 = w.iter().sum();
    if total > 0.0 {
        for x in &mut w {
            *x /= total;
        }
    }
    w
}

/// `weights.len()` ancestors drawn independently with probabilities
/// `weights` (which need not be normalised: uniforms are scaled by their
/// sum), by binary search in the cumulative sums. `None` when the weights
/// do not sum to a positive finite number.
pub fn multinomial<R: Rng + ?Sized>(weights: &[f64], rng: &mut R) -> Option<Vec<usize>> {
    let mut cumulative = Vec::with_capacity(weights.len());
    let mut sum = 0.0;
    for &w in weights {
        sum += w;
        cumulative.push(sum);
    }
    if !(sum > 0.0 && sum.is_finite()) {
        return None;
    }
    let last = weights.len() - 1;
    Some(
        (0..weights.len())
            .map(|_| {
                let u = uniform(rng) * sum;
                // The first index whose cumulative weight exceeds u; rounding
                // can leave u at the total, which belongs to the last member.
                cumulative.partition_point(|&c| c <= u).min(last)
            })
            .collect(),
    )
}

impl Population {
    /// Reweights from inverse temperature `beta_k - dbeta` to `beta_k` and
    /// resamples (no evaluation of `U`: the values move with the members).
    /// Member slots keep their own streams; only positions and values are
    /// replaced by their ancestors'.
    pub fn resample(&mut self, dbeta: f64) {
        let w = weights(&self.values, dbeta);
        let Some(ancestors) = multinomial(&w, &mut self.resampler) else {
            return;
        };
        let d = self.d;
        self.xs = ancestors
            .iter()
            .flat_map(|&a| &self.xs[a * d..(a + 1) * d])
            .copied()
            .collect();
        self.values = ancestors.iter().map(|&a| self.values[a]).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hrla::rand_core::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn weights_sum_to_one_and_follow_the_boltzmann_ratio() {
        let values = [3.0, 1.0, 2.5, 1.0, 40.0, 7.0];
        for dbeta in [0.0, 0.01, 1.0, 30.0] {
            let w = weights(&values, dbeta);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for (i, &vi) in values.iter().enumerate() {
                for (j, &vj) in values.iter().enumerate() {
                    if w[j] > 1e-200 && w[i] > 1e-200 {
                        let ratio = (-dbeta * (vi - vj)).exp();
                        assert!((w[i] / w[j] - ratio).abs() <= 1e-12 * ratio);
                    }
                }
            }
        }
        // Equal values (or dbeta = 0): uniform weights.
        assert!(weights(&[5.0; 4], 2.0).iter().all(|&w| w == 0.25));
        // Values far too large for exp(-dbeta U) alone still weigh.
        let w = weights(&[1e6, 1e6 + 1.0], 1.0);
        assert!((w[0] - 1.0 / (1.0 + (-1.0f64).exp())).abs() < 1e-15);
        // A non-finite value weighs nothing.
        assert_eq!(
            weights(&[f64::NAN, 1.0, f64::INFINITY], 1.0),
            [0.0, 1.0, 0.0]
        );
    }

    /// Each ancestor is drawn with its weight: over 2 000 draws of 5
    /// ancestors, each index's count is within 5 standard errors of its
    /// binomial mean `n w_i` (sd `sqrt(n w_i (1 - w_i))`).
    #[test]
    fn multinomial_draws_ancestors_with_their_weights() {
        let w = [0.1, 0.4, 0.0, 0.3, 0.2];
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let mut counts = [0u32; 5];
        let rounds = 2000;
        for _ in 0..rounds {
            for a in multinomial(&w, &mut rng).unwrap() {
                counts[a] += 1;
            }
        }
        let n = f64::from(rounds * 5);
        for (i, &wi) in w.iter().enumerate() {
            let sd = (n * wi * (1.0 - wi)).sqrt();
            assert!(
                (f64::from(counts[i]) - n * wi).abs() <= 5.0 * sd + 1e-9,
                "{counts:?}"
            );
        }
        assert_eq!(counts[2], 0);
        assert!(multinomial(&[0.0, 0.0], &mut rng).is_none());
        assert!(multinomial(&[f64::NAN, 1.0], &mut rng).is_none());
    }
}
