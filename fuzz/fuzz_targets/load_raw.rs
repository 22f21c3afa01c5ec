//! Fuzz target `load_raw`: runs `volsample_host::parser_checks::run("load_raw", data)` (the stable
//! corpus-replay test runs the same function) and fails on a panic or a broken promise.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = volsample_host::parser_checks::run("load_raw", data) {
        panic!("load_raw: {e}");
    }
});
