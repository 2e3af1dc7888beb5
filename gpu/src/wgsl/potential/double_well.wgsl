// The separable double well `U(x) = sum_i (x_i^2 - 1)^2`, as
// `hrla::DoubleWell` computes it.

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    var u = Real(0.0);
    for (var i = 0u; i < D; i++) {
        let xi = (*x)[i];
        let w = mul(xi, xi) - 1.0;
        (*grad)[i] = 4.0 * xi * w;
        u += mul(w, w);
    }
    return u;
}
