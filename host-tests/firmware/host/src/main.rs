//! Runs the volsample firmware suite on the host and prints the same lines the Cortex-M image
//! prints under QEMU; `run.sh` compares the two byte for byte.
#![forbid(unsafe_code)]

use std::io::Write;

struct Stdout(std::io::BufWriter<std::io::StdoutLock<'static>>, bool);

impl volsample_fw_suite::Out for Stdout {
    fn line(&mut self, s: &str) {
        self.1 &= writeln!(self.0, "{s}").is_ok();
    }
}

fn main() -> std::process::ExitCode {
    let mut out = Stdout(std::io::BufWriter::new(std::io::stdout().lock()), true);
    let summary = volsample_fw_suite::run(&mut out);
    let flushed = out.0.flush().is_ok() && out.1;
    if summary.overflow || !flushed {
        eprintln!(
            "volsample-fw-host: output failed (overflow: {})",
            summary.overflow
        );
        return std::process::ExitCode::FAILURE;
    }
    std::process::ExitCode::SUCCESS
}
