//! The `defmt` feature of the core, linked with a logger (defmt-rtt): logs a sample, an
//! integer sample, a voxel and an error through the core's `defmt::Format` impls.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
// The logger, and the single-core critical section it locks with (cortex-m's impl).
use cortex_m as _;
use defmt_rtt as _;
use volsample::fixed_point::IntSample;
use volsample::{Error, Sample, StraightU8};

#[entry]
fn main() -> ! {
    let s = black_box(Sample {
        c: [0.25, 0.5, 0.125],
        a: 0.75,
    });
    let i = black_box(IntSample::TRANSPARENT);
    let v = black_box(StraightU8([1, 2, 3, 4]));
    // `println!` is not filtered by DEFMT_LOG (whose default keeps only `error!`).
    defmt::println!(
        "sample {} int {} voxel {} error {}",
        s,
        i,
        v,
        black_box(Error::InvalidStep)
    );
    volsample_firmware::exit(true)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::exit(false)
}
