//! The CLI's renderer: threads and bands change nothing, the camera frames and orients
//! volumes as 3D Slicer does (RAS+, anterior view), physical spacing and unit distance keep
//! the look, and the core's row bands check their arguments.

use volsample::{
    ControlPoint, Error, FrontToBack, OpacityWeighted, RayMarcher, Sample, Step, StraightU8,
    Trilinear, Volume,
};
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{Method, ModeChoice, Precision};
use volsample_host::scene::phantom::{ct_head, ct_transfer_function};
use volsample_host::view::render::{classify_u8, render, Settings, Voxels};
use volsample_host::view::{Affine, Projection, View};

fn settings(size: [usize; 2], threads: usize) -> Settings {
    Settings {
        size,
        step_mm: 0.5,
        unit_mm: 1.0,
        a_stop: 0.99,
        skip: true,
        threads,
        background: Sample {
            c: [0.1, 0.2, 0.3],
            a: 1.0,
        },
        progress: false,
    }
}

fn ow(filter: FilterKind, precision: Precision) -> Method {
    Method {
        mode: ModeChoice::OpacityWeighted,
        precision,
        filter,
    }
}

fn ct(n: usize) -> Voxels {
    Voxels {
        dims: [n; 3],
        straight: classify_u8(&ct_head(n), &ct_transfer_function()).unwrap(),
        post: None,
    }
}

/// Every thread count, with and without skipping, in every instance, gives the image the
/// core's own `render_into` gives over the whole image.
#[test]
fn any_thread_count_gives_the_same_image() {
    let vox = ct(40);
    let size = [37, 29];
    let views = [
        View::default(),
        View {
            azimuth_deg: 35.0,
            elevation_deg: -20.0,
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            ..View::default()
        },
    ];
    for view in views {
        let framed = view
            .frame_image(&Affine::default(), vox.dims, size)
            .unwrap();
        for method in [
            ow(FilterKind::TrilinearSum, Precision::F32),
            ow(FilterKind::Nearest, Precision::F32),
            ow(FilterKind::TrilinearSum, Precision::Int8),
        ] {
            let one = render(&vox, &framed, method, &settings(size, 1)).unwrap();
            assert!(
                one.pixels.iter().any(|p| p.c[0] > 0.5),
                "the head is in view"
            );
            for threads in [2, 3] {
                for skip in [true, false] {
                    let s = Settings {
                        skip,
                        ..settings(size, threads)
                    };
                    let img = render(&vox, &framed, method, &s).unwrap();
                    assert_eq!(
                        img.pixels, one.pixels,
                        "{method:?} {threads} threads, skip {skip}"
                    );
                }
            }
        }
        // The core's whole-image render, one thread, no bands.
        let s = settings(size, 1);
        let vol = Volume::new(&vox.straight, vox.dims)
            .unwrap()
            .with_reference_distance(framed.index_length(s.unit_mm) as f32)
            .unwrap();
        let m = RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::with_threshold(s.a_stop).unwrap(),
            Step::new(framed.index_length(s.step_mm) as f32).unwrap(),
        )
        .unwrap()
        .with_background(s.background)
        .unwrap();
        let mut whole = vec![Sample::TRANSPARENT; size[0] * size[1]];
        m.render_into(&framed.voxel_camera(), size[0], size[1], &mut whole)
            .unwrap();
        let ours = render(
            &vox,
            &framed,
            ow(FilterKind::TrilinearSum, Precision::F32),
            &s,
        )
        .unwrap();
        assert_eq!(ours.pixels, whole);
    }
}

#[test]
fn row_bands_check_their_arguments() {
    let voxels = [StraightU8([255; 4]); 8];
    let vol = Volume::new(&voxels, [2, 2, 2]).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.5).unwrap(),
    )
    .unwrap();
    let cam = volsample::Orthographic::looking_down_z([2, 2, 2]).unwrap();
    let mut rows = [Sample::TRANSPARENT; 6];
    assert_eq!(m.render_rows_into(&cam, (3, 4), 2, &mut rows[..6]), Ok(()));
    assert!(rows.iter().all(|p| p.a > 0.0));
    assert_eq!(
        m.render_rows_into(&cam, (3, 4), 3, &mut rows),
        Err(Error::RowsOutsideImage {
            first: 3,
            rows: 2,
            height: 4
        })
    );
    assert_eq!(
        m.render_rows_into(&cam, (3, 4), usize::MAX, &mut rows),
        Err(Error::RowsOutsideImage {
            first: usize::MAX,
            rows: 2,
            height: 4
        })
    );
    assert!(matches!(
        m.render_rows_into(&cam, (4, 4), 0, &mut rows),
        Err(Error::ImageSizeMismatch { actual: 6, .. })
    ));
    assert_eq!(
        m.render_rows_into(&cam, (0, 4), 0, &mut rows),
        Err(Error::EmptyImage)
    );
}

/// An asymmetric phantom in RAS+ world space: opaque blobs at the patient's right (+x, red),
/// anterior (+y, green) and superior (+z, blue) of a faint core; `world(p)` gives its straight
/// RGBA at a world point (mm).
fn asymmetric(p: [f64; 3]) -> [u8; 4] {
    let blob = |c: [f64; 3]| {
        let d2: f64 = (0..3).map(|k| (p[k] - c[k]).powi(2)).sum();
        d2 < 3.0f64.powi(2)
    };
    if blob([7.0, 0.0, 0.0]) {
        [255, 0, 0, 255]
    } else if blob([0.0, 7.0, 0.0]) {
        [0, 255, 0, 255]
    } else if blob([0.0, 0.0, 7.0]) {
        [0, 0, 255, 255]
    } else {
        [0, 0, 0, 0]
    }
}

/// Voxelizes [`asymmetric`] on the grid of `dims` placed by `affine`.
fn voxelize(dims: [usize; 3], affine: &Affine) -> Voxels {
    let mut straight = Vec::with_capacity(dims.iter().product());
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let w = affine.point([i as f64, j as f64, k as f64]);
                straight.push(StraightU8(asymmetric(w)));
            }
        }
    }
    Voxels {
        dims,
        straight,
        post: None,
    }
}

/// Mean of a channel over the left/right and top/bottom halves of an image.
fn halves(img: &[Sample], [w, h]: [usize; 2], ch: usize) -> ([f64; 2], [f64; 2]) {
    let mut lr = [0.0; 2];
    let mut tb = [0.0; 2];
    for (n, p) in img.iter().enumerate() {
        let (i, j) = (n % w, n / w);
        lr[usize::from(i >= w / 2)] += f64::from(p.c[ch]);
        tb[usize::from(j >= h / 2)] += f64::from(p.c[ch]);
    }
    (lr, tb)
}

/// The anterior view shows the patient's right on the image's left and superior at the top;
/// a view from the right shows anterior on the image's right.
#[test]
fn default_view_is_anterior_head_up() {
    let n = 21;
    let affine = Affine::from_columns(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [-10.0, -10.0, -10.0],
    );
    let vox = voxelize([n; 3], &affine);
    let size = [40, 40];
    let s = Settings {
        a_stop: 1.0,
        background: Sample::TRANSPARENT,
        ..settings(size, 2)
    };
    let m = ow(FilterKind::TrilinearSum, Precision::F32);
    let front = render(
        &vox,
        &View::default()
            .frame_image(&affine, vox.dims, size)
            .unwrap(),
        m,
        &s,
    )
    .unwrap();
    let (red_lr, _) = halves(&front.pixels, size, 0);
    assert!(
        red_lr[0] > 10.0 * red_lr[1],
        "right blob on the image's left: {red_lr:?}"
    );
    let (_, blue_tb) = halves(&front.pixels, size, 2);
    assert!(
        blue_tb[0] > 10.0 * blue_tb[1],
        "superior blob at the top: {blue_tb:?}"
    );
    let from_right = View {
        azimuth_deg: 90.0,
        ..View::default()
    };
    let side = render(
        &vox,
        &from_right.frame_image(&affine, vox.dims, size).unwrap(),
        m,
        &s,
    )
    .unwrap();
    let (green_lr, _) = halves(&side.pixels, size, 1);
    assert!(
        green_lr[1] > 10.0 * green_lr[0],
        "anterior on the right seen from the right: {green_lr:?}"
    );
}

/// Largest difference of a channel (display levels of 1/255) between the images of one world
/// object stored in differently ordered grids (RAS, LPS, permuted axes): the grids sample
/// the same world points, so only rounding of the positions in `f32` differs.
const REORIENTED_MAX_DIFF: f32 = 2.0 / 255.0;

/// One world object stored as RAS, as LPS (x and y flipped) and with permuted axes (z, x, y
/// order): the same image from the same camera.
#[test]
fn storage_order_does_not_change_the_image() {
    let n = 21;
    let o = -10.0;
    let ras = Affine::from_columns([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [o; 3]);
    // Index i runs towards the left, j towards posterior: voxel 0 at (+10, +10, −10).
    let lps = Affine::from_columns(
        [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]],
        [-o, -o, o],
    );
    // Index i runs along z, j along x, k along y.
    let permuted =
        Affine::from_columns([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [o; 3]);
    let size = [48, 40];
    let s = Settings {
        a_stop: 1.0,
        ..settings(size, 2)
    };
    for view in [
        View::default(),
        View {
            azimuth_deg: 40.0,
            elevation_deg: 25.0,
            ..View::default()
        },
    ] {
        let images: Vec<Vec<Sample>> = [ras, lps, permuted]
            .iter()
            .map(|a| {
                let vox = voxelize([n; 3], a);
                let framed = view.frame_image(a, vox.dims, size).unwrap();
                render(
                    &vox,
                    &framed,
                    ow(FilterKind::TrilinearSum, Precision::F32),
                    &s,
                )
                .unwrap()
                .pixels
            })
            .collect();
        assert!(images[0].iter().any(|p| p.c.iter().any(|&c| c > 0.5)));
        for other in &images[1..] {
            let worst = images[0]
                .iter()
                .zip(other)
                .flat_map(|(a, b)| (0..3).map(move |k| (a.c[k] - b.c[k]).abs()))
                .fold(0.0f32, f32::max);
            assert!(worst <= REORIENTED_MAX_DIFF, "{view:?}: {worst}");
        }
    }
}

/// RMS difference (display units) between a volume with 1 × 2 × 1 mm voxels and the same
/// smooth object sampled at 1 × 1 × 1 mm, both rendered with opacities per millimetre: the
/// coarse grid's trilinear reconstruction of the smooth field along y differs from the fine
/// one by at most a few percent of the field's range, and the images by less than this.
const SPACING_RMS: f64 = 0.02;

fn smooth_field(p: [f64; 3]) -> f64 {
    // A soft ball of radius ~9 mm, opacity falling off smoothly.
    let r = (p[0] * p[0] + p[1] * p[1] + (p[2] * 1.2).powi(2)).sqrt();
    (1.0 - (r / 9.0).powi(2)).max(0.0)
}

fn field_volume(dims: [usize; 3], affine: &Affine) -> Voxels {
    let mut values = Vec::new();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let w = affine.point([i as f64, j as f64, k as f64]);
                values.push((smooth_field(w) * 255.0).round() as u8);
            }
        }
    }
    let tf = [
        ControlPoint {
            s: 0.0,
            c: [1.0, 0.8, 0.6],
            a: 0.0,
        },
        ControlPoint {
            s: 255.0,
            c: [1.0, 0.8, 0.6],
            a: 0.25,
        },
    ];
    Voxels {
        dims,
        straight: classify_u8(&values, &tf).unwrap(),
        post: None,
    }
}

#[test]
fn anisotropic_spacing_renders_undistorted() {
    // The same box, −13 to 13 mm along y: 26 voxels of 1 mm or 13 of 2 mm (and the same
    // framing, which follows the box).
    let fine_affine = Affine::from_columns(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [-12.0, -12.5, -12.0],
    );
    let coarse_affine = Affine::from_columns(
        [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]],
        [-12.0, -12.0, -12.0],
    );
    let fine = field_volume([25, 26, 25], &fine_affine);
    let coarse = field_volume([25, 13, 25], &coarse_affine);
    let size = [40, 40];
    let s = Settings {
        a_stop: 1.0,
        background: Sample::TRANSPARENT,
        ..settings(size, 2)
    };
    let m = ow(FilterKind::TrilinearSum, Precision::F32);
    // Seen from the front (along y, the coarse axis) and from the right (across it).
    for view in [
        View::default(),
        View {
            azimuth_deg: 90.0,
            ..View::default()
        },
    ] {
        let rms = |a: &[Sample], b: &[Sample]| {
            let sum: f64 = a
                .iter()
                .zip(b)
                .map(|(x, y)| f64::from(x.a - y.a).powi(2))
                .sum();
            (sum / a.len() as f64).sqrt()
        };
        let render_with = |vox: &Voxels, affine: &Affine, unit_mm: f64| {
            let framed = view.frame_image(affine, vox.dims, size).unwrap();
            render(vox, &framed, m, &Settings { unit_mm, ..s })
                .unwrap()
                .pixels
        };
        let f = render_with(&fine, &fine_affine, 1.0);
        let c = render_with(&coarse, &coarse_affine, 1.0);
        assert!(f.iter().any(|p| p.a > 0.3));
        let e = rms(&f, &c);
        assert!(e < SPACING_RMS, "{view:?}: {e}");
        // Opacities per coarse voxel instead of per millimetre: visibly different where the
        // rays run along the coarse axis, so the bound above is not loose.
        if view.azimuth_deg == 0.0 {
            let wrong = render_with(&coarse, &coarse_affine, 2.0);
            assert!(rms(&f, &wrong) > 3.0 * SPACING_RMS, "{}", rms(&f, &wrong));
        }
    }
}
