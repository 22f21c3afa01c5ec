//! Fuzz target `downsample`: decodes the input exactly as `volsample_host::checks::run` does (the
//! stable corpus-replay test runs the same function) and fails on any broken bound.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = volsample_host::checks::run("downsample", data) {
        panic!("downsample: {e}");
    }
});
