//! The panic check's own test: the minimal float scene plus one deliberately reachable
//! panic (an index that `black_box` hides from the optimiser). run.sh builds it and requires
//! the check to *find* the panic handler here; a check that passes this image is broken.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;

#[entry]
fn main() -> ! {
    let table = black_box([1u8, 2, 3, 4]);
    #[allow(clippy::indexing_slicing)]
    let x = table[black_box(7usize)];
    volsample_firmware::exit(black_box(x) == 0)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::panic_trap()
}
