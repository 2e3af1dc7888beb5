// Exact standard normals in f32: the kernel's 256-layer Ziggurat (ZIGNOR),
// word for word as `hrla`'s `f32::standard_normal` and
// `f32::standard_normal_pair` draw them from a `Xoshiro128PlusPlus`, with
// fdlibm's `expf` and `logf` (those of the `libm` crate) for the rare
// branches.
//
// Every product that an addition takes goes through `mul`, and every sum
// of terms that a constant is then added to through `rounded`, which keep
// them rounded where the host asks for IEEE arithmetic (see `shader.rs`).
//
// Needs, from the module that includes it: `tables` (a read-only storage
// array of f32 holding the layer edges X at [0, 257) and the densities F
// at [257, 514)), `ZIG_R` (the start of the tail, in f32) and the `EXPF_*`,
// `LOGF_*` constants (fdlibm's, exact in hexadecimal).

fn zig_x(i: u32) -> f32 {
    return tables[i];
}

fn zig_f(i: u32) -> f32 {
    return tables[257u + i];
}

// A word's uniform on [-1, 1): the top 23 bits as a mantissa in [2, 4).
fn zig_uniform(bits: u32) -> f32 {
    return bitcast<f32>((bits >> 9u) | 0x40000000u) - 3.0;
}

// Uniform on [0, 1) and on (0, 1), as the kernel's `uniform32`, `open32`
// (integers below 2^24 and powers of two: every operation is exact).
fn uniform01() -> f32 {
    return f32(next_u32() >> 8u) * 5.9604644775390625e-8;
}

fn open01() -> f32 {
    return (f32(next_u32() >> 9u) + 0.5) * 1.1920928955078125e-7;
}

// fdlibm's expf (FreeBSD e_expf.c, as in the libm crate) for the arguments
// the wedge test gives it: -x^2/2 with |x| < 3.92, so no overflow, no
// underflow, and `ldexp` is exactly its `scalbnf`.
fn expf_(x_in: f32) -> f32 {
    var x = x_in;
    let hx = bitcast<u32>(x) & 0x7fffffffu;
    let sign = bitcast<u32>(x) >> 31u;
    var k = 0i;
    var hi = 0.0;
    var lo = 0.0;
    if hx > 0x3eb17218u {
        if hx > 0x3f851592u {
            let half = select(0.5, -0.5, sign == 1u);
            k = i32(mul(EXPF_INV_LN2, x) + half);
        } else {
            k = 1i - i32(sign) - i32(sign);
        }
        let kf = f32(k);
        hi = x - kf * EXPF_LN2_HI;
        lo = kf * EXPF_LN2_LO;
        x = hi - lo;
    } else if hx > 0x39000000u {
        hi = x;
    } else {
        return 1.0 + x;
    }
    let xx = x * x;
    let c = x - mul(xx, EXPF_P1 + mul(xx, EXPF_P2));
    let y = 1.0 + rounded(x * c / (2.0 - c) - lo + hi);
    if k == 0i {
        return y;
    }
    return ldexp(y, k);
}

// fdlibm's logf (FreeBSD e_logf.c, as in the libm crate) for the normal
// positive arguments `open01` gives it (at least 2^-24).
fn logf_(x_in: f32) -> f32 {
    var ix = bitcast<u32>(x_in);
    if ix == 0x3f800000u {
        return 0.0;
    }
    ix += 0x3f800000u - 0x3f3504f3u;
    let k = i32(ix >> 23u) - 0x7fi;
    ix = (ix & 0x007fffffu) + 0x3f3504f3u;
    let x = bitcast<f32>(ix);
    let f = x - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = mul(w, LOGF_LG2 + mul(w, LOGF_LG4));
    let t2 = mul(z, LOGF_LG1 + mul(w, LOGF_LG3));
    let r = t2 + t1;
    let hfsq = mul(0.5 * f, f);
    let dk = f32(k);
    return mul(s, hfsq + r) + mul(dk, LOGF_LN2_LO) - hfsq + f + mul(dk, LOGF_LN2_HI);
}

// The base layer's tail, the wedges and the redraws after a rejection:
// `ziggurat_slow` of the kernel. The wedge test is the `exp` comparison
// itself (the kernel's squeeze only skips `exp` where it agrees with it).
fn normal_slow(i_in: u32, u_in: f32, x_in: f32) -> f32 {
    var i = i_in;
    var u = u_in;
    var x = x_in;
    loop {
        if i == 0u {
            loop {
                let t = logf_(open01()) / ZIG_R;
                let s = logf_(open01());
                if -(s + s) >= t * t {
                    return select(ZIG_R - t, t - ZIG_R, u < 0.0);
                }
            }
        }
        let y = zig_f(i + 1u) + mul(zig_f(i) - zig_f(i + 1u), uniform01());
        if y < expf_(-x * x * 0.5) {
            return x;
        }
        let bits = next_u32();
        i = bits & 0xffu;
        u = zig_uniform(bits);
        x = u * zig_x(i);
        if abs(x) < zig_x(i + 1u) {
            return x;
        }
    }
    return 0.0;
}

// The Ziggurat from its first word: the fast path (about 99% of draws: a
// multiply and a compare), else the slow path drawing further words.
fn normal_from(bits: u32) -> f32 {
    let i = bits & 0xffu;
    let u = zig_uniform(bits);
    let x = u * zig_x(i);
    if abs(x) < zig_x(i + 1u) {
        return x;
    }
    return normal_slow(i, u, x);
}

// `f32::standard_normal`: one word, then the slow path's.
fn normal() -> f32 {
    return normal_from(next_u32());
}

// `f32::standard_normal_pair` of a 32-bit generator: its `next_u64` is two
// words, low first; the first normal's further words come before the
// second's.
fn normal_pair() -> vec2<f32> {
    let lo = next_u32();
    let hi = next_u32();
    let z1 = normal_from(lo);
    let z2 = normal_from(hi);
    return vec2<f32>(z1, z2);
}
