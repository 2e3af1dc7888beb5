//! The dimensions compiled in for what the kernel types by its dimension:
//! [`hrla::Auto`] and the built-ins' known minima, one instantiation per
//! supported `D`, chosen at run time by `with_dim!`. This is the only
//! table of them (the [`Engine`](crate::Engine) runs any `d`).

use crate::Error;

/// Every `D` the layer supports, in order.
#[cfg(feature = "all-dimensions")]
pub const SUPPORTED: [usize; 20] = [
    1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 20, 32, 50, 100,
];

/// Every `D` the layer supports: without the feature `all-dimensions`,
/// the plane alone.
#[cfg(not(feature = "all-dimensions"))]
pub const SUPPORTED: [usize; 1] = [2];

/// Whether `d` is compiled in.
pub fn supported(d: usize) -> bool {
    SUPPORTED.contains(&d)
}

/// `d` when it is compiled in, else [`Error::Dimension`].
pub fn check(d: usize) -> Result<usize, Error> {
    if supported(d) {
        Ok(d)
    } else {
        Err(Error::Dimension(d))
    }
}

/// Evaluates `$body` with `$D` a `const usize` equal to `$d`, for every
/// `$d` in [`SUPPORTED`]; any other `$d` gives [`Error::Dimension`]. The
/// list here and [`SUPPORTED`] must agree (a test checks every entry).
macro_rules! with_dim {
    ($d:expr, $D:ident => $body:expr) => {{
        #[cfg(feature = "all-dimensions")]
        let done = with_dim!(@arms $d, $D, $body;
            1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 20 32 50 100);
        #[cfg(not(feature = "all-dimensions"))]
        let done = with_dim!(@arms $d, $D, $body; 2);
        done
    }};
    (@arms $d:expr, $D:ident, $body:expr; $($n:literal)+) => {
        match $d {
            $( $n => {
                const $D: usize = $n;
                $body
            } )+
            other => Err($crate::Error::Dimension(other)),
        }
    };
}
pub(crate) use with_dim;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_and_the_dispatch_agree() {
        for d in 0..=128 {
            let dispatched: Result<usize, Error> = with_dim!(d, D => Ok(D));
            match dispatched {
                Ok(got) => {
                    assert_eq!(got, d);
                    assert!(supported(d), "{d}");
                }
                Err(Error::Dimension(got)) => {
                    assert_eq!(got, d);
                    assert!(!supported(d), "{d}");
                }
                Err(e) => panic!("{e}"),
            }
        }
        assert!(matches!(check(17), Err(Error::Dimension(17))));
        assert_eq!(check(100).unwrap(), 100);
    }
}
