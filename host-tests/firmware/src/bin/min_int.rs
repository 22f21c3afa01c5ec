//! Size image: the minimal integer scene. One ray of integer `OpacityWeighted` trilinear
//! samples (U8.8, 8 fractional position bits) composited front to back, no opacity
//! correction, no early termination. Inputs pass through `black_box`, so nothing is folded
//! away and every panic path of the kernels would stay linked (see run.sh's panic check).
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use volsample::fixed_point::{composite_front_to_back, IntPos, IntSampler, IntStop};
use volsample::{OpacityWeighted, StraightU8, Trilinear, Volume};
use volsample_firmware::{exit, scene};

#[entry]
fn main() -> ! {
    let voxels: [StraightU8; scene::N] = black_box(scene::voxels());
    let Ok(vol) = Volume::new(&voxels, black_box(scene::DIMS)) else {
        exit(false)
    };
    let s = IntSampler::new(vol, OpacityWeighted, Trilinear::new());
    let (start, step, n) = black_box(scene::INT_RAY);
    let samples = (0..n).map(|k| {
        let raw = [0, 1, 2].map(|a| scene::int_coord(start, step, a, k));
        s.sample(IntPos::<8>::from_raw(raw))
    });
    black_box(composite_front_to_back(samples, IntStop::NEVER));
    exit(true)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::panic_trap()
}
