// Ackley's function with the constants (20, 0.2, 2π), written without
// cancellation as `hrla::Ackley` is:
// `U(x) = 20 (1 - exp(-0.2 r)) + e (1 - exp(-q))`, `r = |x| / sqrt(D)`,
// `q = (1/D) sum_i 2 sin^2(π x_i)`. The device's own `sin`, `cos`, `exp`
// and `sqrt`: the same function, not the same bits.

// `e^v - 1` without cancellation near 0 (the device has no `expm1`).
fn ackley_expm1(v: f32) -> f32 {
    if abs(v) < 1e-2 {
        return v * (1.0 + v * (0.5 + v * (1.0 / 6.0 + v * (1.0 / 24.0 + v / 120.0))));
    }
    return exp(v) - 1.0;
}

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    let d = f32(D);
    var norm2 = 0.0;
    var omc = 0.0;
    for (var i = 0u; i < D; i++) {
        let xi = (*x)[i];
        let s = sin(ACKLEY_PI * xi);
        let c = cos(ACKLEY_PI * xi);
        norm2 += xi * xi;
        omc += 2.0 * s * s;
        (*grad)[i] = 2.0 * s * c;
    }
    let r = sqrt(norm2 / d);
    let q = omc / d;
    let outer = exp(-0.2 * r);
    let inner = exp(-q);
    let radial = select(0.0, 4.0 * outer / (d * r), r > 0.0);
    let wave = 2.0 * ACKLEY_PI * ACKLEY_E * inner / d;
    for (var i = 0u; i < D; i++) {
        (*grad)[i] = radial * (*x)[i] + wave * (*grad)[i];
    }
    return 20.0 * -ackley_expm1(-0.2 * r) + ACKLEY_E * -ackley_expm1(-q);
}
