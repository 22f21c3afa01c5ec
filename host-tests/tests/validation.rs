//! Bad input is an error value at construction, never a panic: one test per error variant,
//! and proptest over arbitrary bit patterns for every constructor.

use proptest::prelude::*;
use volsample::{
    AssociatedF32, ControlPoint, Error, ExtinctionF32, FrontToBack, OpacityWeighted, Orthographic,
    Perspective, Ray, RayMarcher, Sample, Step, StraightF32, StraightU8, TransferFunction,
    Trilinear, Volume,
};

const GOOD: StraightF32 = StraightF32 {
    c: [0.5; 3],
    a: 0.5,
};

#[test]
fn volume_errors_are_distinct_and_precise() {
    let v = [GOOD; 8];
    assert_eq!(Volume::new(&v, [2, 2, 2]).map(|v| v.dims()), Ok([2, 2, 2]));
    assert_eq!(
        Volume::new(&v, [2, 2, 3]).unwrap_err(),
        Error::LengthMismatch {
            expected: 12,
            actual: 8
        }
    );
    assert_eq!(
        Volume::new(&v, [2, 0, 4]).unwrap_err(),
        Error::ZeroDimension { axis: 1 }
    );
    assert_eq!(
        Volume::new(&v, [1 << 25, 1, 1]).unwrap_err(),
        Error::DimensionTooLarge
    );
    assert_eq!(
        Volume::new(&v, [1 << 24, 1 << 24, 1 << 24]).unwrap_err(),
        Error::DimensionTooLarge
    );
    let empty: [StraightF32; 0] = [];
    assert_eq!(
        Volume::new(&empty, [0, 1, 1]).unwrap_err(),
        Error::ZeroDimension { axis: 0 }
    );

    for (bad, want) in [
        (f32::NAN, Error::NonFiniteVoxel { index: 5 }),
        (f32::INFINITY, Error::NonFiniteVoxel { index: 5 }),
        (f32::NEG_INFINITY, Error::NonFiniteVoxel { index: 5 }),
        (-0.1, Error::VoxelOutOfRange { index: 5 }),
        (1.0001, Error::VoxelOutOfRange { index: 5 }),
    ] {
        let mut w = v;
        w[5].c[1] = bad;
        assert_eq!(Volume::new(&w, [2, 2, 2]).unwrap_err(), want, "color {bad}");
        let mut w = v;
        w[5].a = bad;
        assert_eq!(Volume::new(&w, [2, 2, 2]).unwrap_err(), want, "alpha {bad}");
    }
    // The first bad voxel is reported.
    let mut w = v;
    w[6].a = f32::NAN;
    w[3].a = 2.0;
    assert_eq!(
        Volume::new(&w, [2, 2, 2]).unwrap_err(),
        Error::VoxelOutOfRange { index: 3 }
    );

    let assoc = [AssociatedF32 {
        c: [0.6, 0.1, 0.1],
        a: 0.5,
    }];
    assert_eq!(
        Volume::new(&assoc, [1, 1, 1]).unwrap_err(),
        Error::ColorExceedsOpacity { index: 0 }
    );
    let u8s = [volsample::AssociatedU8([10, 200, 0, 100])];
    assert_eq!(
        Volume::new(&u8s, [1, 1, 1]).unwrap_err(),
        Error::ColorExceedsOpacity { index: 0 }
    );
    let ext = [ExtinctionF32 {
        c_tau: [2.0, 0.0, 0.0],
        tau: 1.0,
    }];
    assert_eq!(
        Volume::new(&ext, [1, 1, 1]).unwrap_err(),
        Error::ColorExceedsOpacity { index: 0 }
    );
    let ext = [ExtinctionF32 {
        c_tau: [0.0; 3],
        tau: f32::INFINITY,
    }];
    assert_eq!(
        Volume::new(&ext, [1, 1, 1]).unwrap_err(),
        Error::NonFiniteVoxel { index: 0 }
    );
    let ext = [ExtinctionF32 {
        c_tau: [0.0; 3],
        tau: 1e30,
    }];
    assert_eq!(
        Volume::new(&ext, [1, 1, 1]).unwrap_err(),
        Error::VoxelOutOfRange { index: 0 }
    );
    let scalars = [1.0f32, f32::NAN];
    assert_eq!(
        Volume::new(&scalars, [2, 1, 1]).unwrap_err(),
        Error::NonFiniteVoxel { index: 1 }
    );

    let vol = Volume::new(&v, [2, 2, 2]).unwrap();
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            vol.with_reference_distance(bad).unwrap_err(),
            Error::InvalidReferenceDistance
        );
    }
}

#[test]
fn step_threshold_background_errors() {
    for bad in [0.0, -0.5, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(Step::new(bad).unwrap_err(), Error::InvalidStep, "{bad}");
    }
    let s = Step::new(1.0).unwrap();
    for bad in [-0.1, 1.0, f32::NAN, 7.0] {
        assert_eq!(s.with_phase(bad).unwrap_err(), Error::InvalidPhase, "{bad}");
    }
    for bad in [0.0, -0.1, 1.01, f32::NAN] {
        assert_eq!(
            FrontToBack::with_threshold(bad).unwrap_err(),
            Error::InvalidThreshold,
            "{bad}"
        );
    }
    let v = [GOOD; 1];
    let vol = Volume::new(&v, [1, 1, 1]).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        s,
    )
    .unwrap();
    for bad in [
        Sample {
            c: [0.6, 0.0, 0.0],
            a: 0.5,
        },
        Sample {
            c: [0.0; 3],
            a: 1.5,
        },
        Sample {
            c: [f32::NAN, 0.0, 0.0],
            a: 0.5,
        },
        Sample {
            c: [-0.1, 0.0, 0.0],
            a: 0.5,
        },
    ] {
        assert_eq!(
            m.with_background(bad).unwrap_err(),
            Error::InvalidBackground
        );
    }
    // A step so small that a ray would take more than 2^24 samples.
    let big = vec![GOOD; 64 * 64 * 64];
    let vol = Volume::new(&big, [64, 64, 64]).unwrap();
    assert_eq!(
        RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            Step::new(1e-6).unwrap()
        )
        .unwrap_err(),
        Error::TooManySamples
    );
}

#[test]
fn transfer_function_errors() {
    let p = |s: f32, a: f32| ControlPoint { s, c: [0.5; 3], a };
    assert_eq!(
        TransferFunction::<4>::new(&[]).unwrap_err(),
        Error::TransferFunctionEmpty
    );
    assert_eq!(
        TransferFunction::<2>::new(&[p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0)]).unwrap_err(),
        Error::TransferFunctionFull
    );
    assert_eq!(
        TransferFunction::<4>::new(&[p(1.0, 0.0), p(1.0, 0.0)]).unwrap_err(),
        Error::TransferFunctionUnsorted
    );
    assert_eq!(
        TransferFunction::<4>::new(&[p(2.0, 0.0), p(1.0, 0.0)]).unwrap_err(),
        Error::TransferFunctionUnsorted
    );
    for bad in [
        p(f32::NAN, 0.5),
        p(0.0, f32::INFINITY),
        p(0.0, 1.5),
        p(0.0, -0.5),
    ] {
        assert_eq!(
            TransferFunction::<4>::new(&[bad]).unwrap_err(),
            Error::TransferFunctionValue
        );
    }
}

#[test]
fn camera_ray_image_errors() {
    let o = [0.0f32; 3];
    assert_eq!(Ray::new(o, [0.0; 3]).unwrap_err(), Error::InvalidRay);
    assert_eq!(
        Ray::new([f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap_err(),
        Error::InvalidRay
    );
    assert_eq!(
        Ray::new(o, [f32::INFINITY, 0.0, 0.0]).unwrap_err(),
        Error::InvalidRay
    );
    let z = [0.0, 0.0, 1.0];
    assert_eq!(
        Orthographic::new(o, z, z, 1.0).unwrap_err(),
        Error::InvalidCamera
    );
    assert_eq!(
        Orthographic::new(o, [0.0; 3], [0.0, 1.0, 0.0], 1.0).unwrap_err(),
        Error::InvalidCamera
    );
    assert_eq!(
        Orthographic::new(o, z, [0.0, 1.0, 0.0], 0.0).unwrap_err(),
        Error::InvalidCamera
    );
    assert_eq!(
        Orthographic::new([f32::NAN; 3], z, [0.0, 1.0, 0.0], 1.0).unwrap_err(),
        Error::InvalidCamera
    );
    assert_eq!(
        Perspective::new(o, o, [0.0, 1.0, 0.0], 1.0).unwrap_err(),
        Error::InvalidCamera
    );
    for fov in [0.0, 3.2, f32::NAN] {
        assert_eq!(
            Perspective::new(o, z, [0.0, 1.0, 0.0], fov).unwrap_err(),
            Error::InvalidCamera
        );
    }

    let v = [StraightU8([255; 4]); 8];
    let vol = Volume::new(&v, [2, 2, 2]).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(1.0).unwrap(),
    )
    .unwrap();
    let cam = Orthographic::looking_down_z([2, 2, 2]).unwrap();
    let mut img = [Sample::TRANSPARENT; 4];
    assert_eq!(
        m.render_into(&cam, 0, 4, &mut img).unwrap_err(),
        Error::EmptyImage
    );
    assert_eq!(
        m.render_into(&cam, 2, 0, &mut []).unwrap_err(),
        Error::EmptyImage
    );
    assert_eq!(
        m.render_into(&cam, 3, 2, &mut img).unwrap_err(),
        Error::ImageSizeMismatch {
            expected: 6,
            actual: 4
        }
    );
    assert_eq!(
        m.render_into(&cam, usize::MAX, 2, &mut img).unwrap_err(),
        Error::ImageSizeMismatch {
            expected: usize::MAX,
            actual: 4
        }
    );
    assert!(m.render_into(&cam, 2, 2, &mut img).is_ok());
}

#[test]
fn errors_display_and_implement_error() {
    let e: Box<dyn std::error::Error> = Box::new(Error::LengthMismatch {
        expected: 12,
        actual: 8,
    });
    assert_eq!(
        e.to_string(),
        "voxel slice holds 8 voxels but the dimensions need 12"
    );
    assert!(Error::InvalidStep.to_string().contains("step"));
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<u32>().prop_map(f32::from_bits),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(-0.0),
        Just(f32::MIN_POSITIVE / 2.0),
        Just(1.0),
        Just(f32::MAX)
    ]
}

proptest! {
    /// Any bit pattern in any constructor gives a value or an error, never a panic, and
    /// whatever is accepted renders valid pixels.
    #[test]
    fn constructors_never_panic_and_accepted_input_renders(
        vox in prop::collection::vec(([any_f32(), any_f32(), any_f32()], any_f32()), 1..9),
        dims in [0usize..3, 0usize..3, 0usize..3],
        d in any_f32(), phase in any_f32(), d_ref in any_f32(),
        eye in [any_f32(), any_f32(), any_f32()], dir in [any_f32(), any_f32(), any_f32()],
        extent in any_f32(), a_stop in any_f32(),
    ) {
        let voxels: Vec<StraightF32> = vox.iter().map(|&(c, a)| StraightF32 { c, a }).collect();
        let ext: Vec<ExtinctionF32> =
            vox.iter().map(|&(c, a)| ExtinctionF32 { c_tau: c, tau: a }).collect();
        let _ = Volume::new(&ext, dims);
        let Ok(vol) = Volume::new(&voxels, dims) else { return Ok(()) };
        let Ok(vol) = vol.with_reference_distance(d_ref) else { return Ok(()) };
        let Ok(step) = Step::new(d).and_then(|s| s.with_phase(phase)) else { return Ok(()) };
        let Ok(order) = FrontToBack::with_threshold(a_stop) else { return Ok(()) };
        let Ok(m) = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), order, step) else { return Ok(()) };
        let Ok(cam) = Orthographic::new(eye, dir, [0.0, 1.0, 0.0], extent) else { return Ok(()) };
        let mut img = [Sample::TRANSPARENT; 6];
        if m.render_into(&cam, 3, 2, &mut img).is_ok() {
            for p in img {
                prop_assert!(p.is_valid(), "{p:?}");
            }
        }
    }
}
