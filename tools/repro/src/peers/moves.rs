//! The move every peer makes: a Gaussian random-walk proposal, of every
//! coordinate (`y = x + sd z`, `z ~ N(0, I)`) or of one coordinate drawn
//! uniformly, accepted with SA's Metropolis rule or FSA's slower-decaying
//! rule. Both accept every move that does not increase `U`.

use hrla::rand_core::Rng;
use hrla::{SlicePotential, StandardNormal};

use super::population::Population;

/// The probability of accepting a move that changes `U` by `delta` at
/// inverse temperature `beta`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Acceptance {
    /// `exp(-beta Δ+)`: reversible with respect to `exp(-beta U)` under a
    /// symmetric proposal.
    Metropolis,
    /// `q(beta Δ+)` with `q(u) = 1 / (1 + u)` (Rubenthaler, Rydén and
    /// Wiktorsson's choice): heavier-tailed than `exp(-u)`, so that uphill
    /// moves survive the fast cooling.
    Fast,
}

impl Acceptance {
    /// The acceptance probability in `[0, 1]`; a move to a NaN value is
    /// never accepted.
    pub fn probability(self, beta: f64, delta: f64) -> f64 {
        if delta.is_nan() {
            return 0.0;
        }
        if delta <= 0.0 {
            return 1.0;
        }
        let u = beta * delta;
        match self {
            Acceptance::Metropolis => libm::exp(-u),
            Acceptance::Fast => 1.0 / (1.0 + u),
        }
    }
}

/// Which coordinates a proposal moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Scope {
    /// Every coordinate: `y = x + sd z`, `z ~ N(0, I_d)`.
    Full,
    /// One coordinate `j`, uniform in `0..d`: `y_j = x_j + sd z`.
    Coordinate,
}

/// The symmetric Gaussian random-walk proposal of the peers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomWalk {
    /// The standard deviation of a moved coordinate's step.
    pub sd: f64,
    /// Which coordinates move.
    pub scope: Scope,
}

impl RandomWalk {
    /// Moves `y` (a copy of the current point, of `d` coordinates) in
    /// place: `d` normals for [`Scope::Full`], one uniform then one normal
    /// for [`Scope::Coordinate`].
    pub fn propose<R: Rng + ?Sized>(&self, rng: &mut R, y: &mut [f64]) {
        match self.scope {
            Scope::Full => {
                for yj in y.iter_mut() {
                    *yj += self.sd * f64::standard_normal(rng);
                }
            }
            Scope::Coordinate => {
                // uniform < 1, so j < d.
                let j = (uniform(rng) * y.len() as f64) as usize;
                y[j] += self.sd * f64::standard_normal(rng);
            }
        }
    }
}

/// A uniform draw in `[0, 1)` from the top 53 bits of one word.
pub fn uniform<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl Population {
    /// Member `i` proposes a `walk` step from its own stream (then draws
    /// one uniform if the move goes uphill) and moves there with
    /// probability `rule.probability(beta, U(y) - U(x))`. One evaluation.
    pub fn random_walk<P: SlicePotential<f64>>(
        &mut self,
        i: usize,
        potential: &P,
        walk: RandomWalk,
        beta: f64,
        rule: Acceptance,
    ) {
        let rng = &mut self.rngs[i];
        let x = &mut self.xs[i * self.d..(i + 1) * self.d];
        let y = &mut self.proposal;
        y.copy_from_slice(x);
        walk.propose(rng, y);
        let uy = potential.value_and_gradient(y, &mut self.gradient);
        self.evaluations += 1;
        let p = rule.probability(beta, uy - self.values[i]);
        if p >= 1.0 || uniform(rng) < p {
            x.copy_from_slice(y);
            self.values[i] = uy;
        }
    }

    /// Every member makes one [`random_walk`](Population::random_walk).
    pub fn move_all<P: SlicePotential<f64>>(
        &mut self,
        potential: &P,
        walk: RandomWalk,
        beta: f64,
        rule: Acceptance,
    ) {
        for i in 0..self.len() {
            self.random_walk(i, potential, walk, beta, rule);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hrla::{DoubleWell, Point};

    const WALK: RandomWalk = RandomWalk {
        sd: 0.8,
        scope: Scope::Full,
    };

    fn gibbs(beta: f64, x: f64) -> f64 {
        libm::exp(-beta * (x * x - 1.0) * (x * x - 1.0))
    }

    /// Detailed balance of the Metropolis rule at fixed temperature on the
    /// 1-D double well, exactly: `pi(x) a(x, y) = pi(y) a(y, x)` for every
    /// pair of a grid (the random-walk proposal is symmetric, so this is
    /// detailed balance of the kernel). The fast rule breaks it, which is
    /// why FSA needs its own convergence theory.
    #[test]
    fn metropolis_satisfies_detailed_balance_and_the_fast_rule_does_not() {
        let beta = 3.0;
        let u = |x: f64| (x * x - 1.0) * (x * x - 1.0);
        let grid: Vec<f64> = (0..41).map(|i| -2.0 + 0.1 * i as f64).collect();
        let mut fast_violation: f64 = 0.0;
        for &x in &grid {
            for &y in &grid {
                let flow = |rule: Acceptance| {
                    let xy = gibbs(beta, x) * rule.probability(beta, u(y) - u(x));
                    let yx = gibbs(beta, y) * rule.probability(beta, u(x) - u(y));
                    (xy - yx).abs() / xy.max(yx)
                };
                assert!(flow(Acceptance::Metropolis) < 1e-12, "x = {x}, y = {y}");
                fast_violation = fast_violation.max(flow(Acceptance::Fast));
            }
        }
        assert!(fast_violation > 0.5);
    }

    #[test]
    fn acceptance_rules_take_their_closed_forms() {
        for rule in [Acceptance::Metropolis, Acceptance::Fast] {
            assert_eq!(rule.probability(2.0, -1.0), 1.0);
            assert_eq!(rule.probability(2.0, 0.0), 1.0);
            assert_eq!(rule.probability(2.0, f64::NAN), 0.0);
            assert_eq!(rule.probability(2.0, f64::INFINITY), 0.0);
        }
        assert!((Acceptance::Metropolis.probability(2.0, 0.5) - (-1.0f64).exp()).abs() < 1e-15);
        assert_eq!(Acceptance::Fast.probability(2.0, 0.5), 0.5);
        // q(u) = 1 / (1 + u) >= exp(-u): the fast rule accepts more.
        for i in 1..100 {
            let d = 0.1 * i as f64;
            assert!(
                Acceptance::Fast.probability(1.0, d) > Acceptance::Metropolis.probability(1.0, d)
            );
        }
    }

    /// The random-walk Metropolis chain at fixed `beta` samples
    /// `exp(-beta U)`: on the 1-D double well at `beta = 2`, the fraction of
    /// time spent in `|x| < 0.5` matches the Gibbs probability (numerical
    /// quadrature). Tolerance: 4 standard errors from batch means (100
    /// batches of 4 000 steps, 50 chains), so a wrong sign or a wrong
    /// acceptance test (which shift it by far more) fails.
    #[test]
    fn metropolis_random_walk_samples_the_gibbs_law() {
        let beta = 2.0;
        let (lo, hi, n) = (-4.0f64, 4.0f64, 80_000);
        let dx = (hi - lo) / n as f64;
        let (mut inner, mut total) = (0.0, 0.0);
        for i in 0..n {
            let x = lo + (i as f64 + 0.5) * dx;
            let g = gibbs(beta, x);
            total += g;
            if x.abs() < 0.5 {
                inner += g;
            }
        }
        let exact = inner / total;
        let mut pop = Population::new(&DoubleWell, &mut Point::new([1.0]).unwrap(), 50, 1, 9);
        for _ in 0..1000 {
            pop.move_all(&DoubleWell, WALK, beta, Acceptance::Metropolis);
        }
        let batches = 100;
        let mut means = Vec::with_capacity(batches);
        for _ in 0..batches {
            let mut hits = 0u32;
            for _ in 0..4000 / 50 {
                pop.move_all(&DoubleWell, WALK, beta, Acceptance::Metropolis);
                hits += pop.positions().iter().filter(|x| x.abs() < 0.5).count() as u32;
            }
            means.push(f64::from(hits) / 4000.0);
        }
        let mean = means.iter().sum::<f64>() / batches as f64;
        let var = means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>() / (batches - 1) as f64;
        let se = (var / batches as f64).sqrt();
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "mean {mean}, exact {exact}, se {se}"
        );
        assert!(exact > 0.05 && exact < 0.5);
        assert_eq!(pop.evaluations(), 50 + 50 * (1000 + 100 * 80));
    }

    /// A coordinate proposal moves exactly one coordinate, each equally
    /// often: over 5 000 proposals in 5-D every coordinate is chosen within
    /// 5 binomial standard errors of 1 000 times; a full proposal moves all.
    #[test]
    fn coordinate_proposals_move_one_uniform_coordinate() {
        use hrla::rand_core::SeedableRng;
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(4);
        let mut chosen = [0u32; 5];
        let walk = RandomWalk {
            sd: 1.0,
            scope: Scope::Coordinate,
        };
        for _ in 0..5000 {
            let mut y = [0.0; 5];
            walk.propose(&mut rng, &mut y);
            let moved: Vec<usize> = (0..5).filter(|&j| y[j] != 0.0).collect();
            assert_eq!(moved.len(), 1);
            chosen[moved[0]] += 1;
        }
        let sd = (5000.0f64 * 0.2 * 0.8).sqrt();
        assert!(
            chosen
                .iter()
                .all(|&c| (f64::from(c) - 1000.0).abs() < 5.0 * sd),
            "{chosen:?}"
        );
        let mut y = [0.0; 5];
        RandomWalk {
            sd: 1.0,
            scope: Scope::Full,
        }
        .propose(&mut rng, &mut y);
        assert!(y.iter().all(|&v| v != 0.0));
    }
}
