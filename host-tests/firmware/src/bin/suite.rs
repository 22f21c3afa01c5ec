//! The firmware suite image: runs every case of `volsample-fw-suite` and prints its hex lines
//! to the host through semihosting, then exits QEMU (status 0 only if every line was written).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use volsample_firmware::{exit, Semihosting};

#[entry]
fn main() -> ! {
    let mut out = Semihosting::stdout();
    let summary = volsample_fw_suite::run(&mut out);
    exit(out.ok && !summary.overflow)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    exit(false)
}
