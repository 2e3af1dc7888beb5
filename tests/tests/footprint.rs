//! The memory footprint quoted in the crate docs (`core/src/lib.rs`) and
//! the README.
//!
//! The optimiser is a fixed-size value meant for a microcontroller's stack
//! or a static; users size their memory by those figures, so a change of
//! layout must fail here until the docs say the new size.

use hrla::{Hrla, Optimizer, Rastrigin};
use std::mem::size_of;

#[test]
fn optimiser_sizes_match_the_docs() {
    let small = size_of::<Optimizer<f32, Rastrigin, Hrla<f32>, f32, 2, 16>>();
    let paper = size_of::<Optimizer<f64, Rastrigin, Hrla<f64>, f64, 10, 10>>();
    println!("D=2 N=16 f32: {small} bytes; D=10 N=10 f64: {paper} bytes");
    assert_eq!(small, 1112);
    assert_eq!(paper, 3952);
}
