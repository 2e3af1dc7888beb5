//! The two cooling schedules of the peers, as inverse temperatures
//! `beta_k = 1 / T_k` at iterations `k = 1, 2, ...` (`beta_0 = 0`: the flat
//! law before the first iteration, so that the first reweighting of a
//! population is by `pi_1` itself).

/// SA's logarithmic schedule, `T_k = C / ln(k + 1)` with `C = 1`: the
/// cooling under which Haario and Saksman (1991) prove convergence in a
/// general state space (for `C` above the depth of the deepest non-global
/// basin), and the schedule of SMC-SA's and CSA's Boltzmann targets.
pub fn logarithmic(k: u64) -> f64 {
    libm::log((k + 1) as f64)
}

/// FSA's exponent `gamma` of Rubenthaler, Rydén and Wiktorsson (2009):
/// their theorem allows `gamma` in `(0, 1]`; 1 is the fastest cooling it
/// covers, and the one Guilmeau et al. use.
pub const FAST_GAMMA: f64 = 1.0;

/// FSA's fast schedule, `T_k = 1 / ((k + 1)^gamma ln((k + 1)^gamma))` with
/// `gamma =` [`FAST_GAMMA`].
pub fn fast(k: u64) -> f64 {
    let m = libm::pow((k + 1) as f64, FAST_GAMMA);
    m * libm::log(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_have_their_closed_forms() {
        assert_eq!(logarithmic(0), 0.0);
        assert_eq!(fast(0), 0.0);
        // T_1 = 1 / ln 2 and 1 / (2 ln 2); T_50 = 1 / ln 51, 1 / (51 ln 51).
        let ln2 = std::f64::consts::LN_2;
        assert!((logarithmic(1) - ln2).abs() < 1e-15);
        assert!((fast(1) - 2.0 * ln2).abs() < 1e-15);
        assert!((1.0 / logarithmic(50) - 0.254_335).abs() < 1e-6);
        assert!((1.0 / fast(50) - 0.004_987).abs() < 1e-6);
        assert!((1.0 / logarithmic(500) - 0.160_859).abs() < 1e-6);
        // Both cool monotonically, the fast one faster at every k >= 1.
        for k in 1..1000 {
            assert!(logarithmic(k + 1) > logarithmic(k));
            assert!(fast(k + 1) > fast(k));
            assert!(fast(k) > logarithmic(k));
        }
    }
}
