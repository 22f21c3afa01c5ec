//! Fuzz target `load_tf`: runs `volsample_host::parser_checks::run("load_tf", data)` (the stable
//! corpus-replay test runs the same function) and fails on a panic or a broken promise.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = volsample_host::parser_checks::run("load_tf", data) {
        panic!("load_tf: {e}");
    }
});
