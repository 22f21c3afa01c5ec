//! Accuracy against time (issue 3): per mode, the `f32` kernels against the integer kernels
//! at `F = 4, 8, 12` fractional position bits, in ns per sample, next to each one's measured
//! max and RMS error.
//!
//! Every variant samples the same 4096 positions (trilinear, `d = d′`, so no correction) of
//! the same smooth 32³ RGBA8 volume through its marcher's `sample` (float position in,
//! associated sample out: the integer path includes clamping and quantizing the position).
//! Errors are in U8.8 LSB (`1/65280` of full scale), the worst channel of `(C̃, α)`, against
//! the `f64` reference of the same mode on the straight voxels at the unquantized position;
//! they are printed before the timings (`ERR` lines). `Preweighted` reads `u8`
//! premultiplied voxels in both precisions, so its error includes the storage limit
//! (Wittenbrink §7); the integer `ExtinctionWeighted` uses 257-entry tables.

use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use std::hint::black_box;
use std::time::Duration;
use volsample::fixed_point::{
    premultiply_voxel, ExtinctionFx, ExtinctionTables, IntExtinction, IntSample, IntStop,
};
use volsample::render::IntRayMarcher;
use volsample::{
    ExtinctionF32, ExtinctionWeighted, FrontToBack, OpacityWeighted, Preweighted, RayMarcher,
    Sample, Separate, Step, StraightF32, StraightU8, Trilinear, Volume,
};
use volsample_host::reference::{mode as rm, RefFilter, RefVolume, RefVoxel};

const N: usize = 32;
const M: usize = 4096;
const LSB: f64 = 65280.0;

fn voxels() -> Vec<StraightU8> {
    let c = (N as f32 - 1.0) * 0.5;
    let mut v = Vec::with_capacity(N * N * N);
    for z in 0..N {
        for y in 0..N {
            for x in 0..N {
                let (fx, fy, fz) = (x as f32 - c, y as f32 - c, z as f32 - c);
                let r2 = (fx * fx + fy * fy + fz * fz) / (c * c);
                // A dense core, a faint shell and empty corners with bright color.
                let a = 255.0 * (-3.0 * r2).exp() * (0.6 + 0.4 * (0.7 * fx).sin());
                let col =
                    |k: f32| (127.5 + 127.5 * (0.3 * k * (fx + 2.0 * fy - fz) / c).sin()) as u8;
                v.push(StraightU8([
                    col(1.0),
                    col(2.0),
                    col(3.0),
                    a.clamp(0.0, 255.0) as u8,
                ]));
            }
        }
    }
    v
}

fn positions() -> Vec<[f32; 3]> {
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let mut u = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..M)
        .map(|_| [0; 3].map(|_: i32| u() * (N as f32 - 1.0)))
        .collect()
}

fn reference(v: &[StraightU8], mode: rm::RefMode, pos: &[[f32; 3]]) -> Vec<[f64; 4]> {
    let vol = RefVolume::new(
        [N; 3],
        v.iter()
            .map(|b| {
                let u = |n: u8| f64::from(n) / 255.0;
                RefVoxel::new([u(b.0[0]), u(b.0[1]), u(b.0[2])], u(b.0[3]))
            })
            .collect(),
        1.0,
    );
    pos.iter()
        .map(|p| {
            let s = rm::sample(
                rm::RefSource::Straight(&vol),
                mode,
                RefFilter::Trilinear,
                p.map(f64::from),
                1.0,
            );
            [s.color[0], s.color[1], s.color[2], s.alpha].map(|x| x * LSB)
        })
        .collect()
}

fn float_lsb(s: &Sample) -> [f64; 4] {
    [s.c[0], s.c[1], s.c[2], s.a].map(|x| f64::from(x) * LSB)
}

fn int_lsb(s: &IntSample) -> [f64; 4] {
    let [r, g, b] = s.c();
    [r, g, b, s.a()].map(f64::from)
}

/// Measures the errors (printed as an `ERR` line) and times one variant.
fn run<T>(
    group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    pos: &[[f32; 3]],
    want: &[[f64; 4]],
    sample: impl Fn([f32; 3]) -> T,
    lsb: impl Fn(&T) -> [f64; 4],
) {
    let (mut max, mut sq) = (0.0f64, 0.0f64);
    for (p, w) in pos.iter().zip(want) {
        for (g, w) in lsb(&sample(*p)).iter().zip(w) {
            let e = (g - w).abs();
            max = max.max(e);
            sq += e * e;
        }
    }
    let rms = (sq / (4 * pos.len()) as f64).sqrt();
    println!("ERR {id}: max {max:.3} LSB, rms {rms:.4} LSB");
    group.bench_function(id, |b| {
        b.iter(|| {
            for p in pos {
                black_box(sample(black_box(*p)));
            }
        })
    });
}

macro_rules! int_variants {
    ($group:expr, $name:expr, $pos:expr, $want:expr, $vol:expr, $mode:expr) => {{
        let step = Step::new(1.0).unwrap();
        let m4 =
            IntRayMarcher::<_, _, _, 4>::new($vol, $mode, Trilinear::new(), IntStop::NEVER, step)
                .unwrap();
        let m8 =
            IntRayMarcher::<_, _, _, 8>::new($vol, $mode, Trilinear::new(), IntStop::NEVER, step)
                .unwrap();
        let m12 =
            IntRayMarcher::<_, _, _, 12>::new($vol, $mode, Trilinear::new(), IntStop::NEVER, step)
                .unwrap();
        run(
            $group,
            &format!("{}/int-F4", $name),
            $pos,
            $want,
            |p| m4.sample(p),
            int_lsb,
        );
        run(
            $group,
            &format!("{}/int-F8", $name),
            $pos,
            $want,
            |p| m8.sample(p),
            int_lsb,
        );
        run(
            $group,
            &format!("{}/int-F12", $name),
            $pos,
            $want,
            |p| m12.sample(p),
            int_lsb,
        );
    }};
}

fn bench(c: &mut Criterion) {
    let v = voxels();
    let pos = positions();
    let assoc: Vec<_> = v.iter().map(|&s| premultiply_voxel(s)).collect();
    let ext_f32: Vec<_> = v
        .iter()
        .map(|b| {
            let u = |n: u8| f32::from(n) / 255.0;
            ExtinctionF32::from_straight(
                StraightF32 {
                    c: [u(b.0[0]), u(b.0[1]), u(b.0[2])],
                    a: u(b.0[3]),
                },
                1.0,
            )
        })
        .collect();
    let ext_fx: Vec<_> = v
        .iter()
        .map(|&s| ExtinctionFx::from_straight_u8(s))
        .collect();
    let tables = ExtinctionTables::<257>::new();
    let straight = Volume::new(&v, [N; 3]).unwrap();
    let assoc_vol = Volume::new(&assoc, [N; 3]).unwrap();
    let ext_f32_vol = Volume::new(&ext_f32, [N; 3]).unwrap();
    let ext_fx_vol = Volume::new(&ext_fx, [N; 3]).unwrap();
    let step = Step::new(1.0).unwrap();
    let mut group = c.benchmark_group("accuracy_vs_time");
    group
        .throughput(Throughput::Elements(M as u64))
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));

    let want = reference(&v, rm::RefMode::Separate, &pos);
    let fm = RayMarcher::new(
        straight,
        Separate,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    run(
        &mut group,
        "Separate/f32",
        &pos,
        &want,
        |p| fm.sample(p),
        float_lsb,
    );
    int_variants!(&mut group, "Separate", &pos, &want, straight, Separate);

    let want = reference(&v, rm::RefMode::OpacityWeighted, &pos);
    let fm = RayMarcher::new(
        straight,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    run(
        &mut group,
        "OpacityWeighted/f32",
        &pos,
        &want,
        |p| fm.sample(p),
        float_lsb,
    );
    int_variants!(
        &mut group,
        "OpacityWeighted",
        &pos,
        &want,
        straight,
        OpacityWeighted
    );

    let want = reference(&v, rm::RefMode::Preweighted, &pos);
    let fm = RayMarcher::new(
        assoc_vol,
        Preweighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    run(
        &mut group,
        "Preweighted/f32",
        &pos,
        &want,
        |p| fm.sample(p),
        float_lsb,
    );
    int_variants!(
        &mut group,
        "Preweighted",
        &pos,
        &want,
        assoc_vol,
        Preweighted
    );

    let want = reference(&v, rm::RefMode::ExtinctionWeighted, &pos);
    let fm = RayMarcher::new(
        ext_f32_vol,
        ExtinctionWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    run(
        &mut group,
        "ExtinctionWeighted/f32",
        &pos,
        &want,
        |p| fm.sample(p),
        float_lsb,
    );
    let mode = IntExtinction::new(&tables, 1.0).unwrap();
    int_variants!(
        &mut group,
        "ExtinctionWeighted",
        &pos,
        &want,
        ext_fx_vol,
        mode
    );
    group.finish();
}

criterion_group! {
    name = benches;
    // No plots: the report machine has no fonts, and the table is what we read.
    config = Criterion::default().without_plots();
    targets = bench
}

/// Volumes of 4 MiB and more in 2 MiB pages where Linux offers them, as the CLI allocates them
/// (`volsample_host::memory`).
#[global_allocator]
static ALLOCATOR: volsample_host::memory::HugePages = volsample_host::memory::HugePages;

criterion_main!(benches);
