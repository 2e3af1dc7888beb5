// Styblinski–Tang, `U(x) = (1/2) sum_i (x_i^4 - 16 x_i^2 + 5 x_i)`, as
// `hrla::StyblinskiTang` computes it.

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    var u = Real(0.0);
    for (var i = 0u; i < D; i++) {
        let xi = (*x)[i];
        let x2 = xi * xi;
        (*grad)[i] = rounded(mul(2.0 * xi, x2) - mul(16.0, xi)) + 2.5;
        u += mul(mul(x2, x2) - mul(16.0, x2) + mul(5.0, xi), 0.5);
    }
    return u;
}
