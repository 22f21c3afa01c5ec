//! Fuzz target `vectors`: decodes the input exactly as `volsample_host::checks::run` does (the
//! stable corpus-replay test runs the same function): a `volsample vectors` request, written,
//! read back by the code and through the manifest, each case rerun through the kernel.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = volsample_host::checks::run("vectors", data) {
        panic!("vectors: {e}");
    }
});
