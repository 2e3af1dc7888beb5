//! The memory footprint quoted in the crate docs (`core/src/lib.rs`) and
//! the README.
//!
//! The caller owns the chains and sizes their storage by these figures (an
//! array or a `heapless::Vec` on a microcontroller), so a change of layout
//! must fail here until the docs say the new size. The optimiser itself
//! holds no chain and no array of size `D` or `N`: its size does not grow
//! with either, which is what lets `D = 10_000` or `N = 100_000` run on a
//! small stack (`large.rs` runs them).

use hrla::{Chain, Gaussian, Hrla, Optimizer, Rastrigin};
use rand_xoshiro::{Xoshiro128PlusPlus, Xoshiro256PlusPlus};
use std::mem::size_of;

#[test]
fn chain_sizes_match_the_docs() {
    let small = size_of::<Chain<f32, 2, Xoshiro128PlusPlus>>();
    let paper = size_of::<Chain<f64, 10>>();
    println!("Chain<f32, 2, Xoshiro128PlusPlus>: {small} bytes; Chain<f64, 10>: {paper} bytes");
    assert_eq!(small, 72);
    assert_eq!(paper, 384);
    // The default generator is Xoshiro256PlusPlus.
    assert_eq!(paper, size_of::<Chain<f64, 10, Xoshiro256PlusPlus>>());
    // `4 D + 2` floats, an iteration counter, a flag and the generator:
    // the layout the docs describe, with nothing else of size D.
    assert_eq!(
        paper,
        (4 * 10 + 2) * 8 + 8 + size_of::<Xoshiro256PlusPlus>() + 8
    );
}

/// The optimiser for `D = 10_000` (with the chains behind a reference or in
/// a `Vec`) is the same small value as for `D = 2`: it holds no `[F; D]`.
#[test]
fn optimiser_holds_no_array_of_size_d() {
    type Big<St> = Optimizer<f64, Rastrigin, Hrla<f64>, f64, hrla::Chains<f64, St, 10_000>>;
    type Small<St> = Optimizer<f64, Rastrigin, Hrla<f64>, f64, hrla::Chains<f64, St, 2>>;
    let by_ref = size_of::<Big<&mut [Chain<f64, 10_000>]>>();
    let by_vec = size_of::<Big<Vec<Chain<f64, 10_000>>>>();
    println!("Optimizer, D = 10 000: {by_ref} bytes (&mut [Chain]), {by_vec} bytes (Vec<Chain>)");
    assert_eq!(by_ref, size_of::<Small<&mut [Chain<f64, 2>]>>());
    assert_eq!(by_vec, size_of::<Small<Vec<Chain<f64, 2>>>>());
    // One [f64; 10_000] is 80 000 bytes; the optimiser is a few hundred.
    assert!(by_ref < 1024, "{by_ref} bytes");
    assert!(by_vec < 1024, "{by_vec} bytes");
    // A start is the one piece of size D a run is given; behind a
    // reference it is a pointer.
    assert_eq!(size_of::<&mut Gaussian<f64, 10_000>>(), size_of::<usize>());
}
