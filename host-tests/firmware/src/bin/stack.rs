//! Stack image: the high-water mark of one ray, measured by painting.
//!
//! Before each ray the free stack below the current frame is filled with a pattern; the ray
//! runs in a never-inlined function; then the lowest word that no longer holds the pattern
//! gives the deepest stack use. Reported in bytes from the stack pointer at the call, so the
//! figure includes every frame the ray needs (its own, the kernels', compiler-builtins' soft
//! float on the Cortex-M3). Printed as `stack <name> <bytes>` lines.
#![no_std]
#![no_main]
// The one place with unsafe code: reading the stack bounds from the linker and writing and
// reading the painted words. Everything it touches is below the live stack frames.
#![allow(unsafe_code)]

use core::hint::black_box;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use volsample::fixed_point::{composite_front_to_back, IntCorrection, IntPos, IntSampler, IntStop};
use volsample::{
    BackToFront, ExtinctionF32, ExtinctionWeighted, FrontToBack, OpacityWeighted, Ray, RayMarcher,
    Step, StraightF32, StraightU8, Trilinear, TriquadraticBSpline, Volume,
};
use volsample_firmware::{exit, scene};

const PAINT: u32 = 0x5a5a_a5a5;

unsafe extern "C" {
    /// Lowest address of the stack region (cortex-m-rt's linker script).
    static _stack_end: u32;
}

fn stack_floor() -> usize {
    // Taking the address of an extern static is safe; nothing reads it.
    core::ptr::addr_of!(_stack_end) as usize
}

/// Paints from the stack floor up to 64 bytes below this function's own frame.
#[inline(never)]
fn paint() {
    let top = cortex_m::register::msp::read() as usize - 64;
    let mut p = stack_floor();
    while p < top {
        // SAFETY: `[floor, top)` is stack memory below every live frame, word aligned.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// The lowest address whose paint was overwritten.
#[inline(never)]
fn lowest_dirty() -> usize {
    let mut p = stack_floor();
    // SAFETY: reads of stack memory below every live frame, word aligned.
    while unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    p
}

fn measure(name: &str, ray: &dyn Fn()) -> usize {
    paint();
    let sp = cortex_m::register::msp::read() as usize;
    call(ray);
    let used = sp.saturating_sub(lowest_dirty());
    hprintln!("stack {} {}", name, used);
    used
}

/// The measured call, never inlined so that its frame starts at the measured stack pointer.
#[inline(never)]
fn call(ray: &dyn Fn()) {
    ray();
}

#[entry]
fn main() -> ! {
    // Everything but the ray itself is set up here, in main's frame, which is not measured.
    let voxels: [StraightU8; scene::N] = black_box(scene::voxels());
    let ext = voxels.map(|StraightU8([r, g, b, a])| {
        let c = [r, g, b].map(volsample::voxel::unorm8);
        ExtinctionF32::from_straight(
            StraightF32 {
                c,
                a: volsample::voxel::unorm8(a),
            },
            1.0,
        )
    });
    let (Ok(vol), Ok(evol)) = (
        Volume::new(&voxels, scene::DIMS),
        Volume::new(&ext, scene::DIMS),
    ) else {
        exit(false)
    };
    let Ok(corr) = IntCorrection::new(black_box(0.5)) else {
        exit(false)
    };
    let (o, d) = black_box(scene::RAY);
    let Ok(ray) = Ray::new(o, d) else { exit(false) };
    let marcher = |d: f32| {
        Step::new(black_box(d)).and_then(|s| {
            RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                s,
            )
        })
    };
    let (Ok(ow), Ok(ow_corr), Ok(ext_m)) = (
        marcher(1.0),
        marcher(0.5),
        Step::new(black_box(0.5)).and_then(|s| {
            RayMarcher::new(
                evol,
                ExtinctionWeighted,
                TriquadraticBSpline,
                BackToFront,
                s,
            )
        }),
    ) else {
        exit(false)
    };
    let int_s = IntSampler::new(vol, OpacityWeighted, Trilinear::new());
    let int_ray = |corr: Option<&IntCorrection>| {
        let (start, step, n) = black_box(scene::INT_RAY);
        let samples = (0..n).map(|k| {
            let raw = [0, 1, 2].map(|a| scene::int_coord(start, step, a, k));
            let s = int_s.sample(IntPos::<8>::from_raw(raw));
            corr.map_or(s, |c| c.apply(s))
        });
        black_box(composite_front_to_back(samples, IntStop::NEVER));
    };
    let all = [
        measure("int_ow_trilinear_f2b", &|| int_ray(None)),
        measure("int_ow_trilinear_f2b_corrected", &|| int_ray(Some(&corr))),
        measure("float_ow_trilinear_f2b", &|| {
            black_box(ow.cast(&ray));
        }),
        measure("float_ow_trilinear_f2b_corrected", &|| {
            black_box(ow_corr.cast(&ray));
        }),
        measure("float_ext_bspline2_b2f", &|| {
            black_box(ext_m.cast(&ray));
        }),
    ];
    exit(all.iter().all(|&u| u > 0))
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    exit(false)
}
