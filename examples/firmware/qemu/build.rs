//! Puts the board's memory map where the linker looks for `memory.x` (the
//! runtime's `link.x` includes it by name, and the linker does not search
//! the crate root), and passes the runtime's linker script.

use std::{env, fs, path::PathBuf};

fn main() {
    let target = env::var("TARGET").expect("cargo sets TARGET");
    let (board, scripts): (&str, &[&str]) = if target.starts_with("thumbv7m-") {
        ("lm3s6965evb", &["-Tlink.x"])
    } else if target.starts_with("thumbv7em-") {
        ("mps2-an386", &["-Tlink.x"])
    } else if target.starts_with("riscv32") {
        // riscv-rt's link.x needs the region aliases of memory.x first.
        ("virt", &["-Tmemory.x", "-Tlink.x"])
    } else {
        panic!(
            "hrla-firmware builds for thumbv7m-none-eabi, thumbv7em-none-eabihf or riscv32imac-unknown-none-elf, not {target}"
        );
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let source = format!("memory/{board}.x");
    fs::copy(&source, out.join("memory.x")).expect("copy the memory map to OUT_DIR");
    println!("cargo:rustc-link-search={}", out.display());
    for script in scripts {
        println!("cargo:rustc-link-arg-bins={script}");
    }
    println!("cargo:rerun-if-changed={source}");
    println!("cargo:rerun-if-changed=build.rs");
}
