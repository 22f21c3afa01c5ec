//! Chooses the memory map of the QEMU board for the target and passes the linker scripts.
//!
//! The board follows the target (`thumbv7em-none-eabihf`: mps2-an386, Cortex-M4F;
//! `thumbv7m-none-eabi`: mps2-an385, Cortex-M3) unless `VOLSAMPLE_FW_BOARD` names another
//! one with a `memory-<board>.x` here (run.sh uses `lm3s6965evb` for the small images: its
//! 256 KiB of flash cannot hold the suite or the every-kernel image).
//!
//! The board's map is copied to `$OUT_DIR/memory.x`, which cortex-m-rt's `link.x` includes.
//! There is deliberately no `memory.x` in the crate root: one there would be found first and
//! override the per-board choice.
use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory-mps2-an386.x");
    println!("cargo:rerun-if-changed=memory-lm3s6965evb.x");
    println!("cargo:rerun-if-changed=memory-mps2-an385.x");
    println!("cargo:rerun-if-env-changed=VOLSAMPLE_FW_BOARD");
    let target = env::var("TARGET").unwrap_or_default();
    let default = match target.as_str() {
        "thumbv7em-none-eabihf" | "thumbv7em-none-eabi" => "mps2-an386",
        "thumbv7m-none-eabi" => "mps2-an385",
        t if t.starts_with("thumb") => panic!("no QEMU board configured for target {t}"),
        // Host builds of the workspace (the suite's host runner, the C API) link nothing here.
        _ => return,
    };
    let board = env::var("VOLSAMPLE_FW_BOARD").unwrap_or_else(|_| default.to_string());
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy(format!("memory-{board}.x"), out.join("memory.x"))
        .expect("copy the board's memory map");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        println!("cargo:rustc-link-arg-bin=defmt_link=-Tdefmt.x");
    }
}
