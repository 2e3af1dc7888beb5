// The isotropic quadratic `U(x) = (k/2) |x - m|^2`, as `hrla::Quadratic`
// computes it: the sum of `(k r) r`, halved.

fn value_and_gradient(x: ptr<function, Point>, grad: ptr<function, Point>) -> Real {
    var kr2 = Real(0.0);
    for (var i = 0u; i < D; i++) {
        let r = (*x)[i] - QUADRATIC_CENTRE[i];
        let g = mul(QUADRATIC_STIFFNESS, r);
        (*grad)[i] = g;
        kr2 += mul(g, r);
    }
    return 0.5 * kr2;
}
