// Exact standard normals in f64: the kernel's 256-layer Ziggurat (ZIGNOR),
// word for word as `hrla`'s `f64::standard_normal` draws them from a
// `Xoshiro128PlusPlus` (each 64-bit word two `next_u32`, low first), with
// fdlibm's `exp` and `log` (those of the `libm` crate) for the rare
// branches. WGSL has no bits of an f64: the words' fields are taken apart
// as integers and assembled by exact arithmetic, and fdlibm's tests of the
// high word are comparisons with the f64 whose high word is the bound.
//
// Products that an addition takes go through `mul`, sums that a constant
// is added to through `rounded` (see `shader.rs`).
//
// Needs, from the module that includes it: `tables` (a read-only storage
// array of f64 holding the layer edges X at [0, 257) and the densities F
// at [257, 514)), `ZIG_R` and the `EXP_*`, `LOG_*` constants.

fn zig_x(i: u32) -> f64 {
    return tables[i];
}

fn zig_f(i: u32) -> f64 {
    return tables[257u + i];
}

// One 64-bit word: (low, high).
fn next_u64() -> vec2<u32> {
    let lo = next_u32();
    let hi = next_u32();
    return vec2<u32>(lo, hi);
}

// The word's top 52 bits as a mantissa in [2, 4), shifted to [-1, 1): the
// kernel's `split64`. Every operation is exact.
fn zig_uniform64(w: vec2<u32>) -> f64 {
    let m_hi = w.y >> 12u;
    let m_lo = (w.y << 20u) | (w.x >> 12u);
    let m = f64(m_hi) * 4294967296.0 + f64(m_lo);
    return (2.0 + m * EXP_2_M51) - 3.0;
}

// The word's top 53 bits as an integer, exactly.
fn top53(w: vec2<u32>) -> f64 {
    return f64(w.y) * 2097152.0 + f64(w.x >> 11u);
}

fn uniform01_64() -> f64 {
    return top53(next_u64()) * EXP_2_M53;
}

fn open01_64() -> f64 {
    return (top53(next_u64()) + 0.5) * EXP_2_M53;
}

// fdlibm's exp (FreeBSD e_exp.c, as in the libm crate) for the arguments
// the wedge test gives it: -x^2/2 with |x| < 3.92 (no overflow, no
// underflow, so `ldexp` is its `scalbn`).
fn exp64(x_in: f64) -> f64 {
    var x = x_in;
    let ax = abs(x);
    var k = 0i;
    var hi = f64(0.0);
    var lo = f64(0.0);
    if ax >= EXP_HALF_LN2_BOUND {
        if ax >= EXP_THREE_HALF_LN2_BOUND {
            let half = select(f64(0.5), f64(-0.5), x < 0.0);
            k = i32(mul(EXP_INVLN2, x) + half);
        } else {
            k = select(1i, -1i, x < 0.0);
        }
        let kf = f64(k);
        hi = x - kf * EXP_LN2HI;
        lo = kf * EXP_LN2LO;
        x = hi - lo;
    } else if ax >= EXP_TINY_BOUND {
        hi = x;
    } else {
        return 1.0 + x;
    }
    let xx = x * x;
    let p = EXP_P1 + mul(xx, EXP_P2 + mul(xx, EXP_P3 + mul(xx, EXP_P4 + mul(xx, EXP_P5))));
    let c = x - mul(xx, p);
    let y = 1.0 + rounded(rounded(x * c / (2.0 - c) - lo) + hi);
    if k == 0i {
        return y;
    }
    return ldexp(y, k);
}

// fdlibm's log (FreeBSD e_log.c, as in the libm crate) for what
// `open01_64` gives it: normal numbers in [2^-54, 1).
fn log64(x_in: f64) -> f64 {
    // x = 2^e f with f in [1, 2), found by comparisons (exact powers of 2).
    var e = -1i;
    while x_in < ldexp(f64(1.0), e) {
        e -= 1i;
    }
    var f = ldexp(x_in, -e);
    var k = e;
    // The reduction into [sqrt(2)/2, sqrt(2)): by the high word of f.
    if f >= LOG_REDUCE_BOUND {
        f = f * 0.5;
        k += 1i;
    }
    let g = f - 1.0;
    let hfsq = mul(0.5 * g, g);
    let s = g / (2.0 + g);
    let z = s * s;
    let w = z * z;
    let t1 = mul(w, LOG_LG2 + mul(w, LOG_LG4 + mul(w, LOG_LG6)));
    let t2 = mul(z, LOG_LG1 + mul(w, LOG_LG3 + mul(w, LOG_LG5 + mul(w, LOG_LG7))));
    let r = rounded(t2 + t1);
    let dk = f64(k);
    return rounded(rounded(rounded(mul(s, hfsq + r) + mul(dk, LOG_LN2_LO)) - hfsq) + g)
        + mul(dk, LOG_LN2_HI);
}

// The kernel's `ziggurat_slow` in f64, further words by `next_u64`.
fn normal_slow64(i_in: u32, u_in: f64, x_in: f64) -> f64 {
    var i = i_in;
    var u = u_in;
    var x = x_in;
    loop {
        if i == 0u {
            loop {
                let t = log64(open01_64()) / ZIG_R;
                let s = log64(open01_64());
                if -(s + s) >= t * t {
                    return select(ZIG_R - t, t - ZIG_R, u < 0.0);
                }
            }
        }
        let y = zig_f(i + 1u) + mul(zig_f(i) - zig_f(i + 1u), uniform01_64());
        if y < exp64(-x * x * 0.5) {
            return x;
        }
        let w = next_u64();
        i = w.x & 0xffu;
        u = zig_uniform64(w);
        x = u * zig_x(i);
        if abs(x) < zig_x(i + 1u) {
            return x;
        }
    }
    return 0.0;
}

// `f64::standard_normal`: one 64-bit word, then the slow path's.
fn normal() -> f64 {
    let w = next_u64();
    let i = w.x & 0xffu;
    let u = zig_uniform64(w);
    let x = u * zig_x(i);
    if abs(x) < zig_x(i + 1u) {
        return x;
    }
    return normal_slow64(i, u, x);
}

// `f64::standard_normal_pair`: two single draws.
fn normal_pair() -> vec2<f64> {
    let z1 = normal();
    let z2 = normal();
    return vec2<f64>(z1, z2);
}
