//! The dimensions compiled in: the kernel's `D` is a const generic, so each
//! supported `D` is one instantiation, chosen at run time by [`with_dim!`].

/// Every `D` the module supports, in order: what `hrla.DIMENSIONS` lists.
pub const SUPPORTED: [usize; 20] = [
    1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 20, 32, 50, 100,
];

/// Evaluates `$body` with `$D` a `const usize` equal to `$d`, for every
/// `$d` in [`SUPPORTED`]; any other `$d` gives `DimensionError`. The list
/// here and [`SUPPORTED`] must agree (a test checks every entry).
macro_rules! with_dim {
    ($d:expr, $D:ident => $body:expr) => {
        with_dim!(@arms $d, $D, $body;
            1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 20 32 50 100)
    };
    (@arms $d:expr, $D:ident, $body:expr; $($n:literal)+) => {
        match $d {
            $( $n => {
                const $D: usize = $n;
                $body
            } )+
            other => Err($crate::errors::unsupported_dimension(other)),
        }
    };
}
pub(crate) use with_dim;
