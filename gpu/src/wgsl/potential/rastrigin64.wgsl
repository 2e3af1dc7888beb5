// Rastrigin in the paper's form, `U(x) = D + |x|^2 - sum_i cos(2π x_i)`,
// as `hrla::Rastrigin` computes it in f64: the reduction modulo 1/2, fdlibm's
// six-term minimax polynomials in two Horner halves, `1 - cos` as a square,
// and the terms summed in two partial sums (coordinate j into sum j mod 2).
// `round` is the kernel's magic-number rounding (to nearest, ties to even)
// for the `|x| < 2^49` it is used for. Beyond, Vulkan has no f64 `sin`:
// such a coordinate (never reached by a run that has not diverged) gives a
// NaN value, which stops its chain.
// Products that an addition takes go through `mul` (see `shader.rs`).

fn rastrigin_sin_omc(xi: Real) -> vec2<Real> {
    if !(abs(xi) < RASTRIGIN_FAST_LIMIT) {
        let nan = Real(bitcast<f32>(0x7fc00000u | params.zero));
        return vec2<Real>(nan, nan);
    }
    let n = round(2.0 * xi);
    let r = xi - 0.5 * n;
    let odd = n - 2.0 * round(0.5 * n);
    let t = mul(RASTRIGIN_PI, r);
    let z = t * t;
    let z3 = z * z * z;
    let ps = (mul(mul(RASTRIGIN_S2, z) + RASTRIGIN_S1, z) + RASTRIGIN_S0)
        + mul(z3, mul(mul(RASTRIGIN_S5, z) + RASTRIGIN_S4, z) + RASTRIGIN_S3);
    let pc = (mul(mul(RASTRIGIN_C2, z) + RASTRIGIN_C1, z) + RASTRIGIN_C0)
        + mul(z3, mul(mul(RASTRIGIN_C5, z) + RASTRIGIN_C4, z) + RASTRIGIN_C3);
    let sin_t = t + mul(t * z, ps);
    let cos_t = 1.0 - (0.5 * z - mul(z * z, pc));
    let two_sc = mul(sin_t + sin_t, cos_t);
    if odd == 0.0 {
        return vec2<Real>(two_sc, mul(sin_t + sin_t, sin_t));
    }
    return vec2<Real>(-two_sc, mul(cos_t + cos_t, cos_t));
}

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    var sums = vec2<Real>(0.0, 0.0);
    for (var j = 0u; j < D; j++) {
        let xj = (*x)[j];
        let so = rastrigin_sin_omc(xj);
        sums[j & 1u] += mul(xj, xj) + so.y;
        (*grad)[j] = 2.0 * xj + mul(RASTRIGIN_TAU, so.x);
    }
    return sums.x + sums.y;
}
