//! Size image: the full pipeline. Every float mode over every filter and compositing order
//! (with and without opacity correction, early termination and background), both cameras
//! rendering an image, every integer mode over both integer filters with table-driven
//! opacity correction and compositing, the integer ray marcher and the table-driven integer
//! extinction path. Inputs pass through `black_box`.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use volsample::composite::Order;
use volsample::fixed_point::{
    composite_front_to_back, premultiply_voxel, unpremultiply, ExtinctionFx, ExtinctionTables,
    IntCorrection, IntExtinction, IntFilter, IntMode, IntPos, IntSampler, IntStop,
};
use volsample::render::IntRayMarcher;
use volsample::voxel::Voxel;
use volsample::{
    AssociatedF32, BackToFront, ControlPoint, ExtinctionF32, ExtinctionWeighted, Filter,
    FrontToBack, Mode, Nearest, OpacityWeighted, Orthographic, Perspective, PostClassified,
    Preweighted, Ray, RayMarcher, Sample, Separate, Step, StraightF32, StraightU8,
    TransferFunction, Trilinear, TriquadraticBSpline, Volume,
};
use volsample_firmware::{exit, scene};

fn order<V: Voxel, M: Mode<V> + Copy, F: Filter, O: Order>(
    vol: Volume<'_, V>,
    mode: M,
    f: F,
    o: O,
    ray: &Ray,
) {
    let (d, phase) = black_box((0.5f32, 0.25f32));
    if let Ok(m) = Step::new(d)
        .and_then(|s| s.with_phase(phase))
        .and_then(|s| RayMarcher::new(vol, mode, f, o, s))
        .and_then(|m| {
            m.with_background(black_box(Sample {
                c: [0.1, 0.2, 0.3],
                a: 0.5,
            }))
        })
    {
        black_box(m.cast(ray));
        black_box(m.sample(black_box([1.5, 1.25, 0.75])));
    }
}

fn filter<V: Voxel, M: Mode<V> + Copy, F: Filter>(vol: Volume<'_, V>, mode: M, f: F, ray: &Ray) {
    order(vol, mode, f, FrontToBack::new(), ray);
    if let Ok(o) = FrontToBack::with_threshold(black_box(0.95)) {
        order(vol, mode, f, o, ray);
    }
    order(vol, mode, f, BackToFront, ray);
}

fn mode<V: Voxel, M: Mode<V> + Copy>(data: &[V], m: M, ray: &Ray) {
    let Ok(vol) = Volume::new(data, black_box(scene::DIMS))
        .and_then(|v| v.with_reference_distance(black_box(1.0)))
    else {
        exit(false)
    };
    filter(vol, m, Nearest, ray);
    filter(vol, m, Trilinear::new(), ray);
    filter(vol, m, Trilinear::tree(), ray);
    filter(vol, m, TriquadraticBSpline, ray);
}

fn int_mode<V: Voxel, M: IntMode<V>, Fl: IntFilter>(
    data: &[V],
    m: M,
    fl: Fl,
    corr: &IntCorrection,
) {
    let Ok(vol) = Volume::new(data, black_box(scene::DIMS)) else {
        exit(false)
    };
    let s = IntSampler::new(vol, m, fl);
    let (start, step, n) = black_box(scene::INT_RAY);
    let samples = (0..n).map(|k| {
        let raw = [0, 1, 2].map(|a| scene::int_coord(start, step, a, k));
        corr.apply(s.sample(IntPos::<8>::from_raw(raw)))
    });
    black_box(composite_front_to_back(samples, black_box(IntStop::NEVER)));
    if let Ok(p) = IntPos::<8>::quantize(black_box([1.5, 2.25, 0.125])) {
        black_box(s.sample(p));
    }
}

#[entry]
fn main() -> ! {
    let su8: [StraightU8; scene::N] = black_box(scene::voxels());
    let sf32 = su8.map(|StraightU8([r, g, b, a])| StraightF32 {
        c: [r, g, b].map(volsample::voxel::unorm8),
        a: volsample::voxel::unorm8(a),
    });
    let af32 = sf32.map(AssociatedF32::from_straight);
    let au8 = su8.map(premultiply_voxel);
    let ext = sf32.map(|v| ExtinctionF32::from_straight(v, black_box(1.0)));
    let s8 = su8.map(|v| v.0[3]);
    let (o, d) = black_box(scene::RAY);
    let Ok(ray) = Ray::new(o, d) else { exit(false) };
    let Ok(tf) = TransferFunction::<4>::new(black_box(&[
        ControlPoint {
            s: 0.0,
            c: [0.0; 3],
            a: 0.0,
        },
        ControlPoint {
            s: 128.0,
            c: [1.0, 0.5, 0.0],
            a: 0.5,
        },
        ControlPoint {
            s: 255.0,
            c: [1.0; 3],
            a: 1.0,
        },
    ])) else {
        exit(false)
    };

    mode(&su8, Separate, &ray);
    mode(&su8, OpacityWeighted, &ray);
    mode(&sf32, OpacityWeighted, &ray);
    mode(&au8, Preweighted, &ray);
    mode(&af32, Preweighted, &ray);
    mode(&ext, ExtinctionWeighted, &ray);
    mode(&s8, PostClassified::new(&tf), &ray);

    // Whole images through both cameras.
    let mut img = [Sample::TRANSPARENT; 16];
    if let Ok(m) = Volume::new(&su8, scene::DIMS).and_then(|v| {
        Step::new(black_box(0.5)).and_then(|s| {
            RayMarcher::new(v, OpacityWeighted, Trilinear::new(), FrontToBack::new(), s)
        })
    }) {
        if let Ok(cam) = Orthographic::looking_down_z(black_box(scene::DIMS)) {
            black_box(m.render_into(&cam, 4, 4, &mut img)).ok();
        }
        if let Ok(cam) =
            Perspective::new(black_box([6.0, 5.0, -4.0]), [1.5; 3], [0.0, 1.0, 0.0], 0.8)
        {
            black_box(m.render_into(&cam, 4, 4, &mut img)).ok();
        }
    }
    black_box(&img);

    // Every integer mode and filter, with opacity correction.
    let Ok(corr) = IntCorrection::new(black_box(0.5)) else {
        exit(false)
    };
    int_mode(&su8, OpacityWeighted, Nearest, &corr);
    int_mode(&su8, OpacityWeighted, Trilinear::new(), &corr);
    int_mode(&su8, Separate, Trilinear::new(), &corr);
    int_mode(&au8, Preweighted, Trilinear::new(), &corr);
    black_box(unpremultiply(black_box(17), black_box(3)));

    // The integer ray marcher (opacity-weighted, corrected, early termination) and the
    // table-driven integer extinction path.
    if let Ok(vol) = Volume::new(&su8, scene::DIMS) {
        if let Ok(m) = Step::new(black_box(0.5)).and_then(|s| {
            IntRayMarcher::<_, _, _, 8>::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                black_box(IntStop::NEVER),
                s,
            )
        }) {
            black_box(m.cast(&ray));
        }
    }
    let tables = ExtinctionTables::<257>::new();
    let fx = su8.map(ExtinctionFx::from_straight_u8);
    if let (Ok(vol), Ok(mode)) = (
        Volume::new(&fx, scene::DIMS),
        IntExtinction::new(&tables, black_box(1.0)),
    ) {
        if let Ok(m) = Step::new(black_box(1.0)).and_then(|s| {
            IntRayMarcher::<_, _, _, 8>::new(vol, mode, Trilinear::new(), IntStop::NEVER, s)
        }) {
            black_box(m.cast(&ray));
        }
    }
    exit(true)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    volsample_firmware::panic_trap()
}
