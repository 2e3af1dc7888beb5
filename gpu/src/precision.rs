//! The float type the device computes in, and how a number of that type
//! is written into the WGSL program with its exact bits.

/// The float type the device computes in.
///
/// `F64` needs the adapter's `SHADER_F64` ([`Gpu::supports_f64`](crate::Gpu::supports_f64)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Precision {
    /// `f32`, with xoshiro128++ and the kernel's `f32` Ziggurat.
    #[default]
    F32,
    /// `f64`, with xoshiro128++ (two words per 64-bit draw, as the
    /// kernel's `f64` Ziggurat takes them from a 32-bit generator).
    F64,
}

impl Precision {
    /// Bytes of one float.
    #[cfg_attr(not(feature = "device"), allow(dead_code))]
    pub(crate) fn bytes(self) -> u64 {
        match self {
            Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// `v` as a WGSL literal of this type with the same value (rounded
    /// once to f32 for `F32`).
    pub(crate) fn literal(self, v: f64) -> String {
        match self {
            Self::F32 => f32_literal(v as f32),
            // An abstract float is an f64, and the shortest decimal that
            // reads back as `v` is `v`.
            Self::F64 => format!("{v:e}"),
        }
    }
}

/// `v` as a WGSL f32 literal with the same bits: hexadecimal for normal
/// numbers, so that no decimal rounding (single or double) intervenes.
pub(crate) fn f32_literal(v: f32) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0.0f"
        } else {
            "0.0f"
        }
        .to_string();
    }
    if !v.is_normal() {
        // Infinities, NaN and subnormals have no exact literal.
        return format!("bitcast<f32>({:#010x}u)", v.to_bits());
    }
    let bits = v.to_bits();
    let sign = if bits >> 31 == 1 { "-" } else { "" };
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    let mantissa = (bits & 0x7f_ffff) << 1;
    format!("{sign}0x1.{mantissa:06x}p{exponent}f")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_are_exact() {
        for v in [
            1.0f32,
            -2.5,
            0.1,
            core::f32::consts::PI,
            3.654_153,
            1e-30,
            6e37,
        ] {
            let s = f32_literal(v);
            let body = s.trim_end_matches('f');
            let (neg, body) = match body.strip_prefix('-') {
                Some(b) => (true, b),
                None => (false, body),
            };
            let (m, e) = body.trim_start_matches("0x1.").split_once('p').unwrap();
            let m = u32::from_str_radix(m, 16).unwrap() >> 1;
            let e: i32 = e.parse().unwrap();
            let bits = (u32::from(neg) << 31) | (((e + 127) as u32) << 23) | m;
            assert_eq!(f32::from_bits(bits), v, "{s}");
        }
    }

    #[test]
    fn f64_literals_read_back() {
        for v in [0.1, core::f64::consts::PI, -1.3e-300, 6.02e23, f64::MAX] {
            let s = Precision::F64.literal(v);
            assert_eq!(s.parse::<f64>().unwrap(), v, "{s}");
        }
    }
}
