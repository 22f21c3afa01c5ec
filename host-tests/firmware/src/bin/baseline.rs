//! Size image: no kernel at all, only the runtime (vector table, reset, semihosting exit).
//! The size table subtracts nothing but shows this as the floor.
#![no_std]
#![no_main]

use cortex_m_rt::entry;

#[entry]
fn main() -> ! {
    volsample_firmware::exit(core::hint::black_box(true))
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::panic_trap()
}
