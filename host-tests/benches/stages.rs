//! What each pipeline stage costs, and that a scene without a stage costs what the bare
//! kernel costs (issue "the main job": "a scene without a stage runs within 5% of the bare
//! kernel").
//!
//! All variants render the same 64×64 view of the same 48³ volume (a semi-transparent ball,
//! so every ray takes its full sample count) with `OpacityWeighted` trilinear front to back,
//! d = 0.5. Throughput is reported per sample.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use std::time::Instant;
use volsample::classify::{classify_transfer, Isosurface};
use volsample::shade::{shade_in_place, Light};
use volsample::{
    ExtinctionF32, ExtinctionWeighted, FrontToBack, OpacityWeighted, Orthographic, PostClassified,
    RayMarcher, Sample, Step, StraightF32, TransferFunction, Trilinear, Volume,
};
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{self, Method, ModeChoice, Precision};
use volsample_host::scene::{generate, Classification, Scene, VolumeData};

const N: usize = 48;
const W: usize = 64;
/// Alternating bare/pipeline frame pairs for the interleaved ratio.
const PAIRS: usize = 101;

fn volume() -> (Vec<f32>, Vec<StraightF32>, Vec<volsample::ControlPoint>) {
    let c = (N as f32 - 1.0) * 0.5;
    let mut s = Vec::new();
    for z in 0..N {
        for y in 0..N {
            for x in 0..N {
                let r = ((x as f32 - c).powi(2) + (y as f32 - c).powi(2) + (z as f32 - c).powi(2))
                    .sqrt();
                s.push((255.0 * (1.0 - r / (0.6 * N as f32))).clamp(0.0, 255.0));
            }
        }
    }
    let tf = vec![
        volsample::ControlPoint {
            s: 0.0,
            c: [0.2, 0.4, 1.0],
            a: 0.0,
        },
        volsample::ControlPoint {
            s: 255.0,
            c: [1.0, 0.9, 0.5],
            a: 0.05,
        },
    ];
    let t = TransferFunction::<8>::new(&tf).unwrap();
    let sv = Volume::new(&s, [N; 3]).unwrap();
    let mut rgba = vec![StraightF32::default(); s.len()];
    classify_transfer(&sv, &t, &mut rgba).unwrap();
    (s, rgba, tf)
}

fn samples_per_image<
    M: volsample::Mode<V>,
    V: volsample::voxel::Voxel,
    F: volsample::Filter,
    O: volsample::composite::Order,
>(
    m: &RayMarcher<'_, V, M, F, O>,
    cam: &Orthographic,
) -> u64 {
    (0..W * W)
        .map(|k| u64::from(m.sample_range(&cam.ray(k % W, k / W, W, W)).1))
        .sum()
}

use volsample::Camera;

fn bench(c: &mut Criterion) {
    let (scalars, rgba, tf_points) = volume();
    let cam =
        Orthographic::new([-30.0, 23.5, 23.5], [1.0, 0.05, 0.1], [0.0, 1.0, 0.0], 56.0).unwrap();
    let vol = Volume::new(&rgba, [N; 3]).unwrap();
    let half = Step::new(0.5).unwrap();
    let mut image = vec![Sample::TRANSPARENT; W * W];

    // The bare kernel: d = d' (no correction), no termination, no background.
    let vol_half = vol.with_reference_distance(0.5).unwrap();
    let bare = RayMarcher::new(
        vol_half,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        half,
    )
    .unwrap();
    let n = samples_per_image(&bare, &cam);
    let mut g = c.benchmark_group("stages");
    g.throughput(Throughput::Elements(n));
    g.sample_size(20);
    g.bench_function("bare kernel (OW trilinear, d = d')", |b| {
        b.iter(|| bare.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });

    // The same scene through the scene-driven pipeline (no stage called for).
    let scene = Scene {
        name: "bench".into(),
        description: String::new(),
        dims: [N; 3],
        data: VolumeData::Rgba(rgba.clone()),
        classification: Classification::None,
        light: None,
        step: 0.5,
        phase: 0.0,
        d_ref: 0.5,
        a_stop: 1.0,
        background: Sample::TRANSPARENT,
        camera: volsample_host::float_checks::CameraSpec::Orthographic(
            [-30.0, 23.5, 23.5],
            [1.0, 0.05, 0.1],
            [0.0, 1.0, 0.0],
            56.0,
        ),
        image: [W, W],
        continuous: None,
    };
    let prepared = scene.prepare().unwrap();
    let method = Method {
        mode: ModeChoice::OpacityWeighted,
        precision: Precision::F32,
        filter: FilterKind::TrilinearSum,
    };
    // The frame of a built pipeline (what a viewer pays per image), and building it (per
    // scene and method: conversion and validation of the voxels).
    g.bench_function("scene pipeline, no stage", |b| {
        pipeline::with_pipeline(&scene, &prepared, method, |p| {
            b.iter(|| p.frame(black_box(&mut image)).unwrap())
        })
        .unwrap()
    });

    // On a shared machine the load drifts between two criterion runs; alternate the two
    // frames instead and print the median of the per-pair ratios (one run, same load).
    pipeline::with_pipeline(&scene, &prepared, method, |p| {
        let mut ratios: Vec<f64> = (0..PAIRS)
            .map(|_| {
                let t = Instant::now();
                bare.render_into(&cam, W, W, black_box(&mut image)).unwrap();
                let t_bare = t.elapsed().as_secs_f64();
                let t = Instant::now();
                p.frame(black_box(&mut image)).unwrap();
                t.elapsed().as_secs_f64() / t_bare
            })
            .collect();
        ratios.sort_by(f64::total_cmp);
        println!(
            "stages/interleaved: pipeline (no stage) / bare kernel, median of {PAIRS} pairs: {:.4} \
             (quartiles {:.4} .. {:.4})",
            ratios[PAIRS / 2],
            ratios[PAIRS / 4],
            ratios[3 * PAIRS / 4]
        );
    })
    .unwrap();

    // + opacity correction (d = 0.5, d' = 1).
    let corr = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        half,
    )
    .unwrap();
    g.bench_function("+ opacity correction (d != d')", |b| {
        b.iter(|| corr.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });
    // + early-termination test (a threshold the rays never reach, so only the test costs).
    let term = RayMarcher::new(
        vol_half,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::with_threshold(0.9999).unwrap(),
        half,
    )
    .unwrap();
    g.bench_function("+ termination test (A_stop < 1)", |b| {
        b.iter(|| term.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });
    // + background.
    let bg = bare.with_background(generate::BLACK_BG).unwrap();
    g.bench_function("+ background", |b| {
        b.iter(|| bg.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });
    // exp: extinction-weighted instead of opacity-weighted.
    let ext: Vec<ExtinctionF32> = rgba
        .iter()
        .map(|&v| ExtinctionF32::from_straight(v, 0.5))
        .collect();
    let evol = Volume::new(&ext, [N; 3])
        .unwrap()
        .with_reference_distance(0.5)
        .unwrap();
    let em = RayMarcher::new(
        evol,
        ExtinctionWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        half,
    )
    .unwrap();
    g.bench_function("extinction mode (exp per sample)", |b| {
        b.iter(|| em.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });
    // Per-sample classification: post-classified scalars.
    let tf = TransferFunction::<8>::new(&tf_points).unwrap();
    let svol = Volume::new(&scalars, [N; 3])
        .unwrap()
        .with_reference_distance(0.5)
        .unwrap();
    let pc = RayMarcher::new(
        svol,
        PostClassified::new(&tf),
        Trilinear::new(),
        FrontToBack::new(),
        half,
    )
    .unwrap();
    g.bench_function("post-classification (TF per sample)", |b| {
        b.iter(|| pc.render_into(&cam, W, W, black_box(&mut image)).unwrap())
    });
    g.finish();

    // Building a pipeline, per voxel.
    let mut g = c.benchmark_group("pipeline build");
    g.throughput(Throughput::Elements((N * N * N) as u64));
    g.sample_size(10);
    g.bench_function("validate + choose stages (OW f32)", |b| {
        b.iter(|| pipeline::with_pipeline(&scene, &prepared, method, |p| black_box(p.image())))
    });
    g.finish();

    // Pre-passes, per voxel.
    let mut g = c.benchmark_group("pre-passes");
    g.throughput(Throughput::Elements((N * N * N) as u64));
    g.sample_size(10);
    let sv = Volume::new(&scalars, [N; 3]).unwrap();
    let mut out = vec![StraightF32::default(); scalars.len()];
    g.bench_function("classify (transfer function)", |b| {
        b.iter(|| classify_transfer(&sv, &tf, black_box(&mut out)).unwrap())
    });
    let iso = Isosurface::new(128.0, 0.8, 1.5).unwrap();
    g.bench_function("classify (Levoy isosurface)", |b| {
        b.iter(|| {
            volsample::classify::classify_isosurface(&sv, &iso, [1.0; 3], black_box(&mut out))
                .unwrap()
        })
    });
    let light = Light::new([1.0, 1.0, 1.0], 0.3, 0.7).unwrap();
    g.bench_function("shade (directional light)", |b| {
        b.iter(|| shade_in_place(&sv, &light, black_box(&mut out)).unwrap())
    });
    g.finish();
}

// No plots: criterion's plotters backend panics where no font is installed (as on CI's
// Debian image), after the first measurement.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}

/// Volumes of 4 MiB and more in 2 MiB pages where Linux offers them, as the CLI allocates them
/// (`volsample_host::memory`).
#[global_allocator]
static ALLOCATOR: volsample_host::memory::HugePages = volsample_host::memory::HugePages;

criterion_main!(benches);
