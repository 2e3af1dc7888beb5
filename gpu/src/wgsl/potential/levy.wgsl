// Levy's function, `w_i = 1 + (x_i - 1)/4`,
// `U(x) = sin^2(π w_1) + sum_{i<D} (w_i - 1)^2 (1 + 10 sin^2(π w_i + 1))
//        + (w_D - 1)^2 (1 + sin^2(2π w_D))`, as `hrla::Levy` writes it,
// with the device's own `sin` and `cos`: the same function, not the same
// bits.

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    let pi = LEVY_PI;
    let w1 = 1.0 + ((*x)[0] - 1.0) * 0.25;
    let s1 = sin(pi * w1);
    let c1 = cos(pi * w1);
    var u = s1 * s1;
    for (var i = 0u; i < D; i++) {
        (*grad)[i] = 0.0;
    }
    (*grad)[0] = 2.0 * pi * s1 * c1 * 0.25;
    for (var i = 0u; i < D; i++) {
        let wi = 1.0 + ((*x)[i] - 1.0) * 0.25;
        let d = wi - 1.0;
        var term: f32;
        var dterm: f32;
        if i + 1u < D {
            let s = sin(pi * wi + 1.0);
            let c = cos(pi * wi + 1.0);
            let bracket = 1.0 + 10.0 * s * s;
            term = d * d * bracket;
            dterm = 2.0 * d * bracket + d * d * 10.0 * 2.0 * s * c * pi;
        } else {
            let s = sin(2.0 * pi * wi);
            let c = cos(2.0 * pi * wi);
            let bracket = 1.0 + s * s;
            term = d * d * bracket;
            dterm = 2.0 * d * bracket + d * d * 2.0 * s * c * 2.0 * pi;
        }
        u += term;
        (*grad)[i] += dterm * 0.25;
    }
    return u;
}
