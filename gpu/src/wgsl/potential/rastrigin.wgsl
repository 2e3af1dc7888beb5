// Rastrigin in the paper's form, `U(x) = D + |x|^2 - sum_i cos(2π x_i)`,
// as `hrla::Rastrigin` computes it in f32: the reduction modulo 1/2, fdlibm's
// minimax polynomials, `1 - cos` as a square, and the terms summed in four
// partial sums (coordinate j into sum j mod 4) added pairwise. `round` is
// the kernel's magic-number rounding (to nearest, ties to even) for the
// `|x| < 2^20` it is used for; beyond, the device's own `sin` and `cos`.
// Products that an addition takes go through `mul` (see `shader.rs`).

fn rastrigin_sin_omc(xi: f32) -> vec2<f32> {
    if !(abs(xi) < RASTRIGIN_FAST_LIMIT) {
        let t = RASTRIGIN_TAU * xi;
        let sv = sin(t);
        let cv = cos(t);
        return vec2<f32>(sv, select(1.0 - cv, sv * sv / (1.0 + cv), cv > 0.0));
    }
    let n = round(2.0 * xi);
    let r = xi - 0.5 * n;
    let odd = n - 2.0 * round(0.5 * n);
    let t = mul(RASTRIGIN_PI, r);
    let z = t * t;
    let ps = mul(mul(mul(RASTRIGIN_S3, z) + RASTRIGIN_S2, z) + RASTRIGIN_S1, z) + RASTRIGIN_S0;
    let pc = mul(mul(mul(RASTRIGIN_C3, z) + RASTRIGIN_C2, z) + RASTRIGIN_C1, z) + RASTRIGIN_C0;
    let sin_t = t + mul(t * z, ps);
    let cos_t = 1.0 - (0.5 * z - mul(z * z, pc));
    let two_sc = mul(sin_t + sin_t, cos_t);
    if odd == 0.0 {
        return vec2<f32>(two_sc, mul(sin_t + sin_t, sin_t));
    }
    return vec2<f32>(-two_sc, mul(cos_t + cos_t, cos_t));
}

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    var sums = vec4<f32>(0.0);
    for (var j = 0u; j < D; j++) {
        let xj = (*x)[j];
        let so = rastrigin_sin_omc(xj);
        sums[j & 3u] += mul(xj, xj) + so.y;
        (*grad)[j] = 2.0 * xj + mul(RASTRIGIN_TAU, so.x);
    }
    return (sums.x + sums.y) + (sums.z + sums.w);
}
