//! The CLI renderer on a scan-like volume (issue "Real volumes rendered as their users
//! expect"): the 256³ CT-like head of `volsample phantom` (8-bit, a skull-like shell around
//! soft tissue, classified by its transfer function to RGBA8) rendered at 512 × 512,
//! `OpacityWeighted` trilinear, step 0.5 voxel, `A_stop` 0.99, the anterior view, through
//! `volsample_host::view::render::render` (the path of `volsample render`): one thread and
//! two, with and without empty-space skipping. Each row is one whole frame; criterion reports
//! its time (the target: ≤ 1.0 s on 2 cores, ≤ 1.9 s on one).
//!
//! `VOLSAMPLE_BENCH_QUICK=1` shortens the measurement.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use volsample::Sample;
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{Method, ModeChoice, Precision};
use volsample_host::scene::phantom::{ct_head, ct_transfer_function};
use volsample_host::view::render::{classify_u8, render, Settings, Voxels};
use volsample_host::view::{Affine, View};

fn bench(c: &mut Criterion) {
    let n = 256;
    let voxels = Voxels {
        dims: [n; 3],
        straight: classify_u8(&ct_head(n), &ct_transfer_function()).expect("valid TF"),
        post: None,
    };
    let size = [512, 512];
    let framed = View::default()
        .frame_image(&Affine::default(), voxels.dims, size)
        .expect("valid view");
    let method = Method {
        mode: ModeChoice::OpacityWeighted,
        precision: Precision::F32,
        filter: FilterKind::TrilinearSum,
    };
    let quick = std::env::var_os("VOLSAMPLE_BENCH_QUICK").is_some();
    let mut g = c.benchmark_group("ct_render");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(if quick { 3 } else { 20 }))
        .warm_up_time(Duration::from_secs(1));
    for threads in [1, 2] {
        for skip in [true, false] {
            let settings = Settings {
                size,
                step_mm: 0.5,
                unit_mm: 1.0,
                a_stop: 0.99,
                skip,
                threads,
                background: Sample {
                    c: [0.0; 3],
                    a: 1.0,
                },
                progress: false,
            };
            let name = format!(
                "ct256_512x512_ow_trilinear_{threads}thread{}",
                if skip { "_skip" } else { "" }
            );
            g.bench_function(&name, |b| {
                b.iter(|| render(&voxels, &framed, method, &settings).expect("renders"));
            });
        }
    }
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
