//! Ray-marching throughput (issue 9): nanoseconds per sample of the whole float and integer
//! pipelines, on the reference 256³ RGBA8 volume with coherent rays at step 0.5 voxel, plus an
//! in-cache 64³ volume and random-access sampling of 256³ (the memory-bound case).
//!
//! Every benchmark reports its throughput in samples (criterion's "elem/s"), so
//! `ns/sample = 1e9 / (elem/s)`; `host-tests/peers/run.sh` reads the medians back from
//! `target/criterion/ray_march/*/new/` and sets them beside the peers.
//!
//! The volume and the sample positions are integer-defined so that the peer script
//! (`host-tests/peers/peers.py`) rebuilds the same volume and the same rays:
//! voxel `(x, y, z)` is straight RGBA `(x mod 256, y mod 256, z mod 256, 4 + (7x + 13y + 29z)
//! mod 61)`; the ray of pixel `(i, j)` starts at `(n/16 + i + ¼, n/4 + j + ¼, −1)` along
//! `(0.12, 0.08, 1)` (normalised), for an `n/2 × n/2` grid of pixels. The opacities are
//! defined for the step (`d′ = d = 0.5`), so no opacity-correction stage runs: this measures
//! reconstruction plus compositing, the work the target names. Two rows vary it:
//! `ow_f32_u8_256_corrected_packets` (opacities for `d′ = 2d`, so every sample is corrected)
//! and `ow_f32_f32_256_packets` (the same voxels as 16-byte `StraightF32`). These rays lie one
//! voxel apart and start on one plane, so the eight lanes of a packet cross cells together (a
//! best case); `ow_f32_u8_256_camera_render_into` renders an orthographic camera's view of the
//! whole volume (256², rays 1.15 voxels apart, anchored on the image plane), as users do, and
//! `ow_f32_f32_256_corrected_camera_render_into` the same view of 16-byte voxels with every
//! sample corrected, as the report times its `f32` methods.
//!
//! Row width: 256 voxels of 16 bytes make rows of exactly 4 KiB and z-planes of 1 MiB, so the
//! tap rows of a step (two rows in each of about five planes) all fall into one set of a cache
//! indexed by the address bits below 4 KiB; an 8-way level-1 cache (AMD's Zen 3) cannot hold
//! them, and the 16-byte extinction `cast` row pays for it. The interleaved passes end with
//! `OpacityWeighted` and the 16-byte extinction march of the same rays through a volume 260
//! voxels wide (rows of 4 160 bytes), and print the second over the first.
//!
//! Empty space: the same volume cut to a ball in air, marched with and without empty-space
//! skipping (`volsample::skip`), and the grid's lookup cost where nothing is empty.
//!
//! Packets: the `_packets` rows and passes march the same rays with
//! [`RayMarcher::cast_rays`] (bit-identical per ray to `cast`), the others one at a time.
//! Every marcher runs in the instruction set `VOLSAMPLE_ISA` names (`baseline` or `avx2`),
//! else the best the CPU has (`volsample::Isa::detect`; the interleaved passes print which):
//! in the AVX2 instance the `OpacityWeighted`, `Separate` and extinction packets march eight
//! rays at a time in AVX2 lanes, `cast` eight consecutive samples of its ray, and so does
//! `render_into` (the `_render_into` row); the integer `OpacityWeighted` packets
//! (`IntRayMarcher::cast_rays`) march eight rays too. On x86-64 the integer
//! `OpacityWeighted` trilinear kernel is the SSE2 one in every build.
//!
//! Yardsticks: the `yardstick_` rows and the last three passes march the same samples with
//! loops that are not volsample (`volsample_host::yardstick`): a hand-tuned one (SSE2 on
//! x86-64, byte units, no per-tap checks, not bit-identical to the library), a naive one,
//! and the hand-tuned one across rays (`tuned_rays`: eight rays in AVX2 lanes with gathers
//! where the CPU has AVX2 and FMA, else one ray at a time; the pass's name says which ran).
//! They say what a hand-written kernel gets from the machine at hand, in the same run and
//! under the same load; the issue's ≤ 5 ns/sample target was set where a hand-tuned probe
//! ran at about 6 ns.
//!
//! Every row consumes all four channels of every pixel (a sum of `α` and `C̃`), so no
//! arithmetic can be dropped as unused.
//!
//! The volumes are allocated as the CLI allocates its own: by `volsample_host::memory`'s
//! `HugePages` (2 MiB pages where Linux offers them; every bench of this package does so).
//!
//! `VOLSAMPLE_BENCH_QUICK=1` shortens the measurement (for a quick look, not for the table);
//! `VOLSAMPLE_BENCH_ROUNDS=1` prints every interleaved round's ns/sample.

use std::cell::RefCell;
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use volsample::composite::Order;
use volsample::fixed_point::{IntSample, IntStop};
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::render::IntRayMarcher;
use volsample::skip::{Occupancy, Skipping};
use volsample::voxel::Voxel;
use volsample::{
    Camera, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack, Mode, OpacityWeighted,
    Orthographic, Perspective, Ray, RayMarcher, Sample, Separate, Step, StraightF32, StraightU8,
    Trilinear, Volume,
};
use volsample_host::yardstick;

/// The step, and the reference distance the opacities are defined for.
const D: f32 = 0.5;

/// Voxel `(x, y, z)` of the benchmark volume (mirrored in `peers.py`).
fn voxel(x: usize, y: usize, z: usize) -> StraightU8 {
    let a = 4 + (7 * x + 13 * y + 29 * z) % 61;
    StraightU8([x as u8, y as u8, z as u8, a as u8])
}

/// An `n³` volume, x fastest.
fn volume(n: usize) -> Vec<StraightU8> {
    volume_of([n; 3])
}

/// A volume of `[nx, ny, nz]` voxels, x fastest.
fn volume_of([nx, ny, nz]: [usize; 3]) -> Vec<StraightU8> {
    let mut v = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                v.push(voxel(x, y, z));
            }
        }
    }
    v
}

/// The 16-byte extinction form of RGBA8 voxels (`τ` for `d′ = D`).
fn extinction_of(v: &[StraightU8]) -> Vec<ExtinctionF32> {
    v.iter()
        .map(|v| {
            let [r, g, b, a] = v.0.map(|n| f32::from(n) / 255.0);
            ExtinctionF32::from_straight(StraightF32 { c: [r, g, b], a }, D)
        })
        .collect()
}

/// The coherent rays through an `n³` volume, in image order (mirrored in `peers.py`).
fn rays(n: usize) -> Vec<Ray> {
    let w = n / 2;
    let (x0, y0) = ((n / 16) as f32, (n / 4) as f32);
    let mut out = Vec::with_capacity(w * w);
    for j in 0..w {
        for i in 0..w {
            let o = [x0 + i as f32 + 0.25, y0 + j as f32 + 0.25, -1.0];
            out.push(Ray::new(o, [0.12, 0.08, 1.0]).unwrap());
        }
    }
    out
}

/// `count` random positions in `[0, 255)³`, from splitmix64 of the index (mirrored in
/// `peers.py`): each coordinate is `(h >> 40)·255/2²⁴`.
fn random_positions(count: usize) -> Vec<[f32; 3]> {
    let coord = |k: u64| {
        let mut z = k.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 * (255.0 / 16_777_216.0)
    };
    (0..count as u64)
        .map(|i| [coord(3 * i), coord(3 * i + 1), coord(3 * i + 2)])
        .collect()
}

/// A trilinear front-to-back marcher of `mode` at step `D`, in the instruction set `isa()`.
fn trilinear<'v, V: Voxel, M: Mode<V>>(
    vol: Volume<'v, V>,
    mode: M,
) -> RayMarcher<'v, V, M, Trilinear, FrontToBack> {
    RayMarcher::new(
        vol,
        mode,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(D).unwrap(),
    )
    .unwrap()
    .with_isa(isa())
}

/// The same-load ratios the targets name: each round renders every ray once with each
/// marcher, in turn, and the per-round time ratios against `OpacityWeighted` f32 are reduced
/// to their medians (criterion's medians come from different minutes, and the load on a
/// shared machine drifts between them).
fn interleaved_ratios(v256: &[StraightU8], rays: &[Ray]) {
    let step = Step::new(D).unwrap();
    let vol = Volume::new(v256, [256; 3])
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let ow = trilinear(vol, OpacityWeighted);
    let sep = trilinear(vol, Separate);
    let int_ow = IntRayMarcher::<_, _, _, 8>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        step,
    )
    .unwrap()
    .with_isa(isa());
    let ext = extinction_of(v256);
    let evol = Volume::new(&ext, [256; 3]).unwrap();
    let em = trilinear(evol, ExtinctionWeighted);
    // The same rays through a volume 260 voxels wide (the same voxels at each `(x, y, z)`):
    // rows of 4 160 bytes of 16-byte voxels instead of 4 096, so that the rows and z-planes a
    // step reads do not all fall into the same sets of a cache (the performance log,
    // 2026-12-07 (day)).
    let wide = [260, 256, 256];
    let v260 = volume_of(wide);
    let vol260 = Volume::new(&v260, wide)
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let ow260 = trilinear(vol260, OpacityWeighted);
    let ext260 = extinction_of(&v260);
    let em260 = trilinear(Volume::new(&ext260, wide).unwrap(), ExtinctionWeighted);
    let table = TauTable::new(D).unwrap();
    let em8 = trilinear(vol, ExtinctionWeightedU8::new(&table));
    let mut grid = vec![0u8; Occupancy::buffer_len([256; 3], 3)];
    let skip = ow.with_skipping(&mut grid, 3).unwrap();
    let n: u64 = rays.iter().map(|r| u64::from(ow.sample_range(r).1)).sum();
    let n260: u64 = rays
        .iter()
        .map(|r| u64::from(ow260.sample_range(r).1))
        .sum();
    assert_eq!(n260, n, "the rays leave both volumes through the same face");
    let time = |f: &dyn Fn() -> f32| {
        let t = std::time::Instant::now();
        black_box(f());
        t.elapsed().as_secs_f64()
    };
    let rounds = if quick() { 6 } else { 12 };
    let out = RefCell::new(vec![Sample::TRANSPARENT; rays.len()]);
    // The yardsticks march the same samples (volsample's sample ranges).
    let ranges: Vec<(f32, u32)> = rays.iter().map(|r| ow.sample_range(r)).collect();
    let yard = |f: yardstick::Kernel| {
        rays.iter()
            .zip(&ranges)
            .map(|(r, &(t, k))| f(v256, 256, r, t, k, D).iter().sum::<f32>())
            .sum()
    };
    let across = RefCell::new(vec![[0.0f32; 4]; rays.len()]);
    let yard_rays = || {
        let mut o = across.borrow_mut();
        yardstick::tuned_rays(v256, 256, rays, &ranges, D, &mut o);
        o.iter().map(|p| p.iter().sum::<f32>()).sum()
    };
    let rays_name = format!(
        "yardstick: hand-tuned, {} ray(s)/pass (not volsample)",
        yardstick::tuned_rays_lanes()
    );
    let int_out = RefCell::new(vec![IntSample::TRANSPARENT; rays.len()]);
    let passes: [(&str, &dyn Fn() -> f32); 16] = [
        ("OpacityWeighted f32", &|| {
            rays.iter().map(|r| all_channels(ow.cast(r))).sum()
        }),
        ("Separate f32", &|| {
            rays.iter().map(|r| all_channels(sep.cast(r))).sum()
        }),
        ("OpacityWeighted int F=8", &|| {
            rays.iter()
                .map(|r| all_channels_int(int_ow.cast(r)) as f32)
                .sum()
        }),
        (
            "ExtinctionWeighted f32 (exact exp), 16-byte voxels",
            &|| rays.iter().map(|r| all_channels(em.cast(r))).sum(),
        ),
        (
            "ExtinctionWeightedU8 (exact exp), RGBA8 + TauTable",
            &|| rays.iter().map(|r| all_channels(em8.cast(r))).sum(),
        ),
        (
            "OpacityWeighted f32 + skipping grid (nothing empty)",
            &|| rays.iter().map(|r| all_channels(skip.cast(r))).sum(),
        ),
        ("OpacityWeighted f32, packets (cast_rays)", &|| {
            packets(&ow, rays, &mut out.borrow_mut())
        }),
        ("Separate f32, packets", &|| {
            packets(&sep, rays, &mut out.borrow_mut())
        }),
        ("ExtinctionWeighted f32, packets", &|| {
            packets(&em, rays, &mut out.borrow_mut())
        }),
        ("ExtinctionWeightedU8, packets", &|| {
            packets(&em8, rays, &mut out.borrow_mut())
        }),
        ("OpacityWeighted int F=8, packets", &|| {
            let mut o = int_out.borrow_mut();
            int_ow.cast_rays(rays, &mut o).unwrap();
            o.iter().map(|p| all_channels_int(*p) as f32).sum()
        }),
        ("yardstick: hand-tuned loop (not volsample)", &|| {
            yard(yardstick::tuned)
        }),
        ("yardstick: naive loop (not volsample)", &|| {
            yard(yardstick::naive)
        }),
        (&rays_name, &yard_rays),
        ("OpacityWeighted f32, 260 × 256 × 256", &|| {
            rays.iter().map(|r| all_channels(ow260.cast(r))).sum()
        }),
        ("ExtinctionWeighted f32, 16-byte voxels, 260 wide", &|| {
            rays.iter().map(|r| all_channels(em260.cast(r))).sum()
        }),
    ];
    // Round `k` starts with pass `k mod (number of passes)`, so every pass takes every place in the order
    // equally often and an effect of the place (of the passes run just before) is spread
    // over all of them instead of falling on one.
    let mut per = vec![Vec::new(); passes.len()];
    for round in 0..rounds {
        let mut t = [0.0f64; 16];
        for k in 0..passes.len() {
            let i = (round + k) % passes.len();
            t[i] = time(passes[i].1);
        }
        if std::env::var_os("VOLSAMPLE_BENCH_ROUNDS").is_some() {
            println!(
                "  round {round:2}: {:?}",
                t.map(|x| (x * 1e9 / n as f64 * 10.0).round() / 10.0)
            );
        }
        for (p, x) in per.iter_mut().zip(t) {
            p.push(x);
        }
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    // Ratios against `OpacityWeighted` f32 one ray at a time (pass 0) and, for the packet
    // passes, against `OpacityWeighted` f32 in packets (pass 6); for the 260-wide extinction
    // pass (15), also against `OpacityWeighted` through the same volume (14).
    let ratio = |p: &[f64], base: &[f64]| median(p.iter().zip(base).map(|(a, b)| a / b).collect());
    println!("ray_march/interleaved: {rounds} rounds, 256³, {n} samples per pass");
    println!(
        "  instruction set: {} (of {:?}; VOLSAMPLE_ISA chooses)",
        ow.isa(),
        volsample::Isa::available()
    );
    for (k, ((name, _), p)) in passes.iter().zip(&per).enumerate() {
        let packed = if (6..11).contains(&k) {
            format!("   / OW f32 packets: {:.3}", ratio(p, &per[6]))
        } else if k == 15 {
            format!("   / OW f32 260 wide: {:.3}", ratio(p, &per[14]))
        } else {
            String::new()
        };
        println!(
            "  {name:52} {:7.2} ns/sample (median)   / OW f32: {:.3}{packed}",
            median(p.clone()) * 1e9 / n as f64,
            ratio(p, &per[0])
        );
    }
}

/// The sum of all four channels of a result. Every benchmark consumes the whole sample: a
/// loop that used only `a` (or `a` and one color) let the compiler drop the dead color
/// arithmetic, which made the kernels look 1.6× (`OpacityWeighted` f32) to 2.6× (extinction)
/// faster than they are.
fn all_channels(p: Sample) -> f32 {
    p.a + p.c[0] + p.c[1] + p.c[2]
}

/// Every ray of `rays` through `m` four at a time ([`RayMarcher::cast_rays`], the packet
/// kernels; bit-identical to `cast` per ray), into `out`: the sum of [`all_channels`].
fn packets<V: Voxel, M: Mode<V>, F: Filter, O: Order, S: Skipping>(
    m: &RayMarcher<'_, V, M, F, O, S>,
    rays: &[Ray],
    out: &mut [Sample],
) -> f32 {
    m.cast_rays(rays, out).unwrap();
    out.iter().map(|p| all_channels(*p)).sum()
}

/// [`all_channels`] of an integer sample.
fn all_channels_int(p: IntSample) -> u32 {
    let [r, g, b] = p.c();
    u32::from(p.a()) + u32::from(r) + u32::from(g) + u32::from(b)
}

/// The instruction set of every marcher here: `VOLSAMPLE_ISA`, else the best this CPU has.
fn isa() -> volsample::Isa {
    volsample_host::isa::from_env().unwrap()
}

fn quick() -> bool {
    std::env::var_os("VOLSAMPLE_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let step = Step::new(D).unwrap();
    let v256 = volume(256);
    let vol = Volume::new(&v256, [256; 3])
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let rays256 = rays(256);
    let ow = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
    .with_isa(isa());
    let n256: u64 = rays256
        .iter()
        .map(|r| u64::from(ow.sample_range(r).1))
        .sum();

    let mut g = c.benchmark_group("ray_march");
    g.sample_size(10);
    let t = if quick() { 2 } else { 8 };
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(t));

    g.throughput(Throughput::Elements(n256));
    g.bench_function("ow_f32_u8_256", |b| {
        b.iter(|| {
            let mut s = 0.0f32;
            for r in &rays256 {
                let p = ow.cast(r);
                s += all_channels(p);
            }
            black_box(s)
        })
    });

    // The same rays four at a time (the packet kernels, bit-identical per ray).
    let mut out = vec![Sample::TRANSPARENT; rays256.len()];
    g.bench_function("ow_f32_u8_256_packets", |b| {
        b.iter(|| black_box(packets(&ow, &rays256, &mut out)))
    });

    // With opacity correction: the voxels' opacities hold for `d′ = 2d` (the step is half the
    // unit distance, as the report's scenes and the CLI's default have it).
    let vol_d2 = vol.with_reference_distance(2.0 * D).unwrap();
    let ow_corrected = RayMarcher::new(
        vol_d2,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
    .with_isa(isa());
    assert!(ow_corrected.correction().is_some());
    g.bench_function("ow_f32_u8_256_corrected_packets", |b| {
        b.iter(|| black_box(packets(&ow_corrected, &rays256, &mut out)))
    });

    // The same voxels as 16-byte `StraightF32` (`n/255`), uncorrected.
    let v256f: Vec<StraightF32> = v256
        .iter()
        .map(|v| {
            let [r, g, b, a] = v.0.map(volsample::voxel::unorm8);
            StraightF32 { c: [r, g, b], a }
        })
        .collect();
    let volf = Volume::new(&v256f, [256; 3])
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let ow_f = RayMarcher::new(
        volf,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
    .with_isa(isa());
    g.bench_function("ow_f32_f32_256_packets", |b| {
        b.iter(|| black_box(packets(&ow_f, &rays256, &mut out)))
    });

    // What a camera gives: `render_into` of an orthographic view of the whole volume along the
    // rays' direction, 256² pixels 1.15 voxels apart, each ray's samples anchored at its
    // origin on the image plane. The rows above march rays exactly one voxel apart from one
    // plane (z = −1), so the eight lanes of a packet cross cells together: a best case.
    let cam = {
        let dir = [0.12f32, 0.08, 1.0];
        let len = dir.iter().map(|d| d * d).sum::<f32>().sqrt();
        let eye = dir.map(|d| 127.5 - d / len * 512.0);
        Orthographic::new(eye, dir, [0.0, -1.0, 0.0], 256.0 * 1.15).unwrap()
    };
    let n_cam: u64 = (0..256 * 256)
        .map(|k| u64::from(ow.sample_range(&cam.ray(k % 256, k / 256, 256, 256)).1))
        .sum();
    let mut cam_out = vec![Sample::TRANSPARENT; 256 * 256];
    g.throughput(Throughput::Elements(n_cam));
    g.bench_function("ow_f32_u8_256_camera_render_into", |b| {
        b.iter(|| {
            ow.render_into(&cam, 256, 256, &mut cam_out).unwrap();
            black_box(cam_out.iter().map(|&p| all_channels(p)).sum::<f32>())
        })
    });
    // What the report times its `f32` methods on: the same view of the same voxels as 16-byte
    // `StraightF32` with the opacities defined for `d′ = 2d` (every sample corrected), as the
    // report's timing scenes are stored and stepped.
    let ow_f_corrected = RayMarcher::new(
        volf.with_reference_distance(2.0 * D).unwrap(),
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
    .with_isa(isa());
    assert!(ow_f_corrected.correction().is_some());
    g.bench_function("ow_f32_f32_256_corrected_camera_render_into", |b| {
        b.iter(|| {
            ow_f_corrected
                .render_into(&cam, 256, 256, &mut cam_out)
                .unwrap();
            black_box(cam_out.iter().map(|&p| all_channels(p)).sum::<f32>())
        })
    });
    g.throughput(Throughput::Elements(n256));

    // The yardsticks (not volsample): the same samples by a hand-tuned and a naive loop.
    let ranges: Vec<(f32, u32)> = rays256.iter().map(|r| ow.sample_range(r)).collect();
    for (name, f) in [
        ("yardstick_tuned_256", yardstick::tuned as yardstick::Kernel),
        ("yardstick_naive_256", yardstick::naive),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for (r, &(t, k)) in rays256.iter().zip(&ranges) {
                    s += f(&v256, 256, r, t, k, D).iter().sum::<f32>();
                }
                black_box(s)
            })
        });
    }

    // The hand-tuned loop across rays (eight in AVX2 lanes where the CPU has them).
    let mut across = vec![[0.0f32; 4]; rays256.len()];
    g.bench_function("yardstick_tuned_rays_256", |b| {
        b.iter(|| {
            yardstick::tuned_rays(&v256, 256, &rays256, &ranges, D, &mut across);
            black_box(across.iter().map(|p| p.iter().sum::<f32>()).sum::<f32>())
        })
    });

    let sep = RayMarcher::new(vol, Separate, Trilinear::new(), FrontToBack::new(), step)
        .unwrap()
        .with_isa(isa());
    g.bench_function("separate_f32_u8_256", |b| {
        b.iter(|| {
            let mut s = 0.0f32;
            for r in &rays256 {
                let p = sep.cast(r);
                s += all_channels(p);
            }
            black_box(s)
        })
    });

    let int_ow = IntRayMarcher::<_, _, _, 8>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        step,
    )
    .unwrap()
    .with_isa(isa());
    g.bench_function("ow_int_f8_u8_256", |b| {
        b.iter(|| {
            let mut s = 0u32;
            for r in &rays256 {
                let p = int_ow.cast(r);
                s += all_channels_int(p);
            }
            black_box(s)
        })
    });
    let mut int_out = vec![IntSample::TRANSPARENT; rays256.len()];
    g.bench_function("ow_int_f8_u8_256_packets", |b| {
        b.iter(|| {
            int_ow.cast_rays(&rays256, &mut int_out).unwrap();
            black_box(int_out.iter().map(|p| all_channels_int(*p)).sum::<u32>())
        })
    });

    {
        // 256³ × 16 bytes: the extinction form of the same volume (τ for d′ = 0.5).
        let ext = extinction_of(&v256);
        let evol = Volume::new(&ext, [256; 3]).unwrap();
        let em = RayMarcher::new(
            evol,
            ExtinctionWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_isa(isa());
        g.bench_function("extinction_f32_exact_exp_256", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays256 {
                    let p = em.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
        g.bench_function("extinction_f32_exact_exp_256_packets", |b| {
            b.iter(|| black_box(packets(&em, &rays256, &mut out)))
        });
    }

    {
        // The same extinction sampling read from the 4-byte RGBA8 volume through a τ table
        // (bit-identical to the 16-byte volume above, `tests/extinction_u8.rs`).
        let table = TauTable::new(D).unwrap();
        let em8 = RayMarcher::new(
            vol,
            ExtinctionWeightedU8::new(&table),
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_isa(isa());
        g.bench_function("extinction_u8_exact_exp_256", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays256 {
                    let p = em8.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
    }

    {
        let v64 = volume(64);
        let vol64 = Volume::new(&v64, [64; 3])
            .unwrap()
            .with_reference_distance(D)
            .unwrap();
        let rays64 = rays(64);
        let ow64 = RayMarcher::new(
            vol64,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_isa(isa());
        let n64: u64 = rays64
            .iter()
            .map(|r| u64::from(ow64.sample_range(r).1))
            .sum();
        g.throughput(Throughput::Elements(n64));
        g.bench_function("ow_f32_u8_64_in_cache", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays64 {
                    let p = ow64.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
    }

    {
        // Empty space: the same volume cut to a ball of radius 0.3·n in transparent air, so
        // most samples of most rays fall in air. With and without an occupancy grid of 8³
        // bricks (bit-identical results, `tests/skipping.rs`); throughput counts every
        // sample position, skipped or not.
        let c = 127.5f32;
        let ball: Vec<StraightU8> = v256
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let (x, y, z) = (k % 256, (k / 256) % 256, k / 65536);
                let r2 = (x as f32 - c).powi(2) + (y as f32 - c).powi(2) + (z as f32 - c).powi(2);
                if r2 <= (0.3f32 * 256.0).powi(2) {
                    *v
                } else {
                    StraightU8([v.0[0], v.0[1], v.0[2], 0])
                }
            })
            .collect();
        let bvol = Volume::new(&ball, [256; 3])
            .unwrap()
            .with_reference_distance(D)
            .unwrap();
        let plain = RayMarcher::new(
            bvol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_isa(isa());
        let mut grid = vec![0u8; Occupancy::buffer_len([256; 3], 3)];
        let skip = plain.with_skipping(&mut grid, 3).unwrap();
        g.throughput(Throughput::Elements(n256));
        g.bench_function("ow_f32_u8_256_ball_no_skipping", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays256 {
                    let p = plain.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
        g.bench_function("ow_f32_u8_256_ball_skipping_8", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays256 {
                    let p = skip.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
        // The grid's cost on the full volume (nothing to skip): the lookup per sample.
        let mut full_grid = vec![0u8; Occupancy::buffer_len([256; 3], 3)];
        let ow_skip = ow.with_skipping(&mut full_grid, 3).unwrap();
        g.bench_function("ow_f32_u8_256_skipping_8_nothing_empty", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &rays256 {
                    let p = ow_skip.cast(r);
                    s += all_channels(p);
                }
                black_box(s)
            })
        });
    }

    {
        // Where packets do not pay: a 64×64 perspective view of a 32³ volume (rays in every
        // direction, in cache), one ray at a time and four at a time.
        let v32 = volume(32);
        let vol32 = Volume::new(&v32, [32; 3])
            .unwrap()
            .with_reference_distance(D)
            .unwrap();
        let ow32 = RayMarcher::new(
            vol32,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_isa(isa());
        let cam = Perspective::new(
            [40.0, 35.0, -30.0],
            [15.5, 15.5, 15.5],
            [0.0, 1.0, 0.0],
            0.8,
        )
        .unwrap();
        let prays: Vec<Ray> = (0..64 * 64)
            .map(|k| cam.ray(k % 64, k / 64, 64, 64))
            .collect();
        let np: u64 = prays
            .iter()
            .map(|r| u64::from(ow32.sample_range(r).1))
            .sum();
        g.throughput(Throughput::Elements(np));
        g.bench_function("ow_f32_u8_32_perspective", |b| {
            b.iter(|| {
                let mut s = 0.0f32;
                for r in &prays {
                    s += all_channels(ow32.cast(r));
                }
                black_box(s)
            })
        });
        let mut pout = vec![Sample::TRANSPARENT; prays.len()];
        g.bench_function("ow_f32_u8_32_perspective_packets", |b| {
            b.iter(|| black_box(packets(&ow32, &prays, &mut pout)))
        });
        // `render_into` of the same view (one ray at a time, or eight-ray packets where the
        // AVX2 kernel applies).
        g.bench_function("ow_f32_u8_32_perspective_render_into", |b| {
            b.iter(|| {
                ow32.render_into(&cam, 64, 64, &mut pout).unwrap();
                black_box(pout.iter().map(|&p| all_channels(p)).sum::<f32>())
            })
        });
    }

    let pos = random_positions(1 << 20);
    g.throughput(Throughput::Elements(pos.len() as u64));
    g.bench_function("ow_f32_u8_256_random_access", |b| {
        b.iter(|| {
            let mut s = 0.0f32;
            for p in &pos {
                let x = ow.sample(*p);
                s += all_channels(x);
            }
            black_box(s)
        })
    });
    // The batch form: the instruction set entered once, the cells ahead prefetched.
    let mut out = vec![Sample::TRANSPARENT; pos.len()];
    g.bench_function("ow_f32_u8_256_random_access_sample_into", |b| {
        b.iter(|| {
            ow.sample_into(&pos, &mut out).unwrap();
            black_box(out.iter().map(|&x| all_channels(x)).sum::<f32>())
        })
    });
    g.finish();
    interleaved_ratios(&v256, &rays256);
}

criterion_group! {
    name = benches;
    // No plots: they need system fonts, and the numbers are what this bench is for.
    config = Criterion::default().without_plots();
    targets = bench
}

/// Volumes of 4 MiB and more in 2 MiB pages where Linux offers them, as the CLI allocates them
/// (`volsample_host::memory`).
#[global_allocator]
static ALLOCATOR: volsample_host::memory::HugePages = volsample_host::memory::HugePages;

criterion_main!(benches);
