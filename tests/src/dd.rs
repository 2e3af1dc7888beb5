//! Double-double arithmetic (about 106 bits): enough headroom to serve as
//! the independent reference for f64 coefficients.
//!
//! Error-free transformations after Knuth (two-sum) and Dekker (two-product,
//! here through the fused multiply-add of `f64::mul_add`).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo` with `|lo| <= ulp(hi)/2`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };

    pub fn new(v: f64) -> Dd {
        Dd { hi: v, lo: 0.0 }
    }

    /// Rounded to the nearest f64.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    pub fn abs(self) -> Dd {
        if self.hi < 0.0 { -self } else { self }
    }

    /// `e^x` by argument halving and a Taylor series: `e^x = (e^(x/2^k))^(2^k)`.
    pub fn exp(self) -> Dd {
        let mut k = 0;
        let mut r = self;
        while r.hi.abs() > 1.0 / 64.0 {
            r = r * Dd::new(0.5);
            k += 1;
        }
        let mut term = Dd::ONE;
        let mut sum = Dd::ONE;
        for n in 1..40 {
            term = term * r / Dd::new(n as f64);
            sum = sum + term;
        }
        for _ in 0..k {
            sum = sum * sum;
        }
        sum
    }

    /// `sqrt(x)` by one Newton step from the f64 root (doubles the bits).
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::ZERO;
        }
        let r = Dd::new(self.hi.sqrt());
        (r + self / r) * Dd::new(0.5)
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, o: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, o: Dd) -> Dd {
        let p = self.hi * o.hi;
        let e = self.hi.mul_add(o.hi, -p);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    fn div(self, o: Dd) -> Dd {
        // Long division: two f64 quotient digits and a correction.
        let q1 = self.hi / o.hi;
        let r = self - o * Dd::new(q1);
        let q2 = r.hi / o.hi;
        let r = r - o * Dd::new(q2);
        let q3 = r.hi / o.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo } + Dd::new(q3)
    }
}

/// A square matrix in double-double.
pub type Mat<const N: usize> = [[Dd; N]; N];

pub fn identity<const N: usize>() -> Mat<N> {
    let mut m = [[Dd::ZERO; N]; N];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = Dd::ONE;
    }
    m
}

pub fn matmul<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> Mat<N> {
    let mut c = [[Dd::ZERO; N]; N];
    for i in 0..N {
        for j in 0..N {
            let mut s = Dd::ZERO;
            for k in 0..N {
                s = s + a[i][k] * b[k][j];
            }
            c[i][j] = s;
        }
    }
    c
}

pub fn transpose<const N: usize>(a: &Mat<N>) -> Mat<N> {
    let mut t = [[Dd::ZERO; N]; N];
    for i in 0..N {
        for j in 0..N {
            t[j][i] = a[i][j];
        }
    }
    t
}

/// `exp(m)` for a matrix of small norm (the caller scales): Taylor series
/// to 40 terms, exact to double-double precision for `|m| <= 1/4`.
pub fn expm_small<const N: usize>(m: &Mat<N>) -> Mat<N> {
    let mut sum = identity::<N>();
    let mut term = identity::<N>();
    for n in 1..40 {
        term = matmul(&term, m);
        for row in term.iter_mut() {
            for v in row.iter_mut() {
                *v = *v / Dd::new(n as f64);
            }
        }
        for i in 0..N {
            for j in 0..N {
                sum[i][j] = sum[i][j] + term[i][j];
            }
        }
    }
    sum
}
