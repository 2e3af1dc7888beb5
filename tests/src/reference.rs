//! An independent evaluation of the exact OU step, sharing no formula with
//! the kernel: matrix exponentials (Van Loan's method for the covariance) in
//! double-double, with the step split into `2^j` small pieces that are
//! recombined by the semigroup property, so nothing cancels even at
//! `alpha h = 50`.

use crate::dd::{Dd, Mat, expm_small, matmul, transpose};

/// The step's mean as a linear map of `(x, y, g)`, and its covariance.
#[derive(Clone, Copy, Debug)]
pub struct Reference {
    /// `mean_x = x + c_xy y - c_xg g`.
    pub c_xy: Dd,
    /// See `c_xy`.
    pub c_xg: Dd,
    /// `mean_y = e y - c_yg g`.
    pub e: Dd,
    /// See `e`.
    pub c_yg: Dd,
    pub var_x: Dd,
    pub cov_xy: Dd,
    pub var_y: Dd,
}

impl Reference {
    /// `Sxx - Sxy^2 / Syy`, the square of the Cholesky factor's `xx`.
    pub fn schur(&self) -> Dd {
        self.var_x - self.cov_xy * self.cov_xy / self.var_y
    }
}

/// The exact one-step law of `dX = (-beta g + Y) dt + sqrt(2 sx2) dB`,
/// `dY = (-gamma g - alpha Y) dt + sqrt(2 sy2) dB'` over time `h`, with
/// `gamma = a/b`, `sx2 = beta/a`, `sy2 = alpha/b` (ULA: `beta = 0`).
pub fn ou_step(a: f64, b: f64, alpha: f64, beta: f64, h: f64) -> Reference {
    let (a, b, alpha, beta, h) = (
        Dd::new(a),
        Dd::new(b),
        Dd::new(alpha),
        Dd::new(beta),
        Dd::new(h),
    );
    let gamma = a / b;
    let sx2 = beta / a;
    let sy2 = alpha / b;

    // Split h into 2^j pieces with alpha tau <= 1/8.
    let mut j = 0;
    let mut tau = h;
    while (alpha * tau).hi > 0.125 {
        tau = tau * Dd::new(0.5);
        j += 1;
    }

    // Mean: the state (x, y, g) with g constant, d/dt = A_hat (x, y, g).
    let z = Dd::ZERO;
    let a_hat: Mat<3> = [[z, Dd::ONE, -beta], [z, -alpha, -gamma], [z, z, z]];
    let mut phi_hat = expm_small(&scale(&a_hat, tau));
    for _ in 0..j {
        phi_hat = matmul(&phi_hat, &phi_hat);
    }

    // Covariance over tau by Van Loan: exp([[-A, Q], [0, A^T]] tau) =
    // [[., E12], [0, E22]] with Phi = E22^T and Sigma = Phi E12.
    let two = Dd::new(2.0);
    let mut m: Mat<4> = [[z; 4]; 4];
    // -A with A = [[0, 1], [0, -alpha]].
    m[0][1] = -Dd::ONE;
    m[1][1] = alpha;
    // Q = diag(2 sx2, 2 sy2).
    m[0][2] = two * sx2;
    m[1][3] = two * sy2;
    // A^T.
    m[3][2] = Dd::ONE;
    m[3][3] = -alpha;
    let ev = expm_small(&scale(&m, tau));
    let mut phi: Mat<2> = [[ev[2][2], ev[3][2]], [ev[2][3], ev[3][3]]];
    let e12: Mat<2> = [[ev[0][2], ev[0][3]], [ev[1][2], ev[1][3]]];
    let mut sigma = matmul(&phi, &e12);
    // Sigma(2t) = Phi(t) Sigma(t) Phi(t)^T + Sigma(t), Phi(2t) = Phi(t)^2.
    for _ in 0..j {
        let pspt = matmul(&matmul(&phi, &sigma), &transpose(&phi));
        for r in 0..2 {
            for c in 0..2 {
                sigma[r][c] = pspt[r][c] + sigma[r][c];
            }
        }
        phi = matmul(&phi, &phi);
    }

    Reference {
        c_xy: phi_hat[0][1],
        c_xg: -phi_hat[0][2],
        e: phi_hat[1][1],
        c_yg: -phi_hat[1][2],
        var_x: sigma[0][0],
        cov_xy: (sigma[0][1] + sigma[1][0]) * Dd::new(0.5),
        var_y: sigma[1][1],
    }
}

fn scale<const N: usize>(m: &Mat<N>, s: Dd) -> Mat<N> {
    let mut out = *m;
    for row in out.iter_mut() {
        for v in row.iter_mut() {
            *v = *v * s;
        }
    }
    out
}
