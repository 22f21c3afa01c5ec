//! Size image: the minimal float scene. One ray of float `OpacityWeighted` trilinear samples
//! composited front to back with `d = d′` (no opacity correction, no early termination).
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use volsample::{
    FrontToBack, OpacityWeighted, Ray, RayMarcher, Step, StraightU8, Trilinear, Volume,
};
use volsample_firmware::{exit, scene};

#[entry]
fn main() -> ! {
    let voxels: [StraightU8; scene::N] = black_box(scene::voxels());
    let m = Volume::new(&voxels, black_box(scene::DIMS)).and_then(|v| {
        Step::new(black_box(1.0)).and_then(|s| {
            RayMarcher::new(v, OpacityWeighted, Trilinear::new(), FrontToBack::new(), s)
        })
    });
    let (o, d) = black_box(scene::RAY);
    match (m, Ray::new(o, d)) {
        (Ok(m), Ok(r)) => {
            black_box(m.cast(&r));
            exit(true)
        }
        _ => exit(false),
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::panic_trap()
}
