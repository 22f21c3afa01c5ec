//! Group 5, input: every special `f32` of the edge-case generator (`±0`, subnormals, `±∞`,
//! NaN with and without payload, the range ends and one ulp either side) in every float
//! constructor — volumes of each voxel format, transfer functions, steps, phases, reference
//! distances, thresholds, backgrounds, rays, downsampling filters, ratios of the integer
//! path — gives a value when the documented domain contains it and the *matching* error
//! otherwise; plus zero-sized images in both marchers. The expectation is written from the
//! documented domain, independently of the constructors.
//!
//! Already covered elsewhere: one test per error variant and arbitrary bit patterns that must
//! not panic (`validation`), invalid integer voxels and ratios (`int_extinction`), bad
//! downsampling filters and buffers (`downsample`).

use proptest::prelude::*;
use volsample::downsample::Filter4;
use volsample::fixed_point::{IntPos, IntRatio, IntSample, IntStop};
use volsample::opacity::Corrected;
use volsample::render::IntRayMarcher;
use volsample::voxel::MAX_TAU;
use volsample::{
    AssociatedF32, ControlPoint, Error, ExtinctionF32, FrontToBack, OpacityWeighted, Orthographic,
    Ray, RayMarcher, Sample, Step, StraightF32, StraightU8, TransferFunction, Trilinear, Volume,
};
use volsample_host::edge_cases::{any_edge, specials};

use crate::common::Worst;

fn unit_ok(x: f32) -> bool {
    x.is_finite() && (0.0..=1.0).contains(&x)
}

/// The error a float voxel field `x` in `[0, hi]` must give at `index` (or `None`).
fn field_error(x: f32, hi: f32, index: usize) -> Option<Error> {
    if !x.is_finite() {
        Some(Error::NonFiniteVoxel { index })
    } else if !(0.0..=hi).contains(&x) {
        Some(Error::VoxelOutOfRange { index })
    } else {
        None
    }
}

fn check_value(x: f32) {
    let good = StraightF32 {
        c: [0.5; 3],
        a: 0.5,
    };
    // Straight voxels: each channel and the opacity, at index 2 of a 2×2×1 volume.
    for ch in 0..4 {
        let mut v = [good; 4];
        if ch < 3 {
            v[2].c[ch] = x
        } else {
            v[2].a = x
        }
        let want = field_error(x, 1.0, 2);
        assert_eq!(
            Volume::new(&v, [2, 2, 1]).err(),
            want,
            "straight ch{ch} = {x:e}"
        );
    }
    // Associated voxels: α first, then each channel, then C̃ ≤ α.
    for (c, a) in [(x, 1.0f32), (x, 0.25), (0.0, x), (0.5, x)] {
        let v = [AssociatedF32 {
            c: [0.0, c, 0.0],
            a,
        }];
        let want = field_error(a, 1.0, 0)
            .or(field_error(c, 1.0, 0))
            .or((c > a).then_some(Error::ColorExceedsOpacity { index: 0 }));
        assert_eq!(
            Volume::new(&v, [1, 1, 1]).err(),
            want,
            "associated c={c:e} a={a:e}"
        );
    }
    // Extinction voxels: τ and C^τ in [0, MAX_TAU], C^τ ≤ τ.
    for (c, t) in [(x, MAX_TAU), (x, 1.0), (0.0, x), (x, x)] {
        let v = [ExtinctionF32 {
            c_tau: [c, 0.0, 0.0],
            tau: t,
        }];
        let want = field_error(c, MAX_TAU, 0)
            .or(field_error(t, MAX_TAU, 0))
            .or((c > t).then_some(Error::ColorExceedsOpacity { index: 0 }));
        assert_eq!(
            Volume::new(&v, [1, 1, 1]).err(),
            want,
            "extinction c={c:e} τ={t:e}"
        );
    }
    // Scalars: any finite value.
    let s = [0.0f32, x];
    let want = (!x.is_finite()).then_some(Error::NonFiniteVoxel { index: 1 });
    assert_eq!(Volume::new(&s, [2, 1, 1]).err(), want, "scalar {x:e}");
    // Transfer functions: s finite, color and opacity in [0, 1].
    for field in 0..3 {
        let mut p = ControlPoint {
            s: 1.0,
            c: [0.5; 3],
            a: 0.5,
        };
        match field {
            0 => p.s = x,
            1 => p.c[1] = x,
            _ => p.a = x,
        }
        let ok = if field == 0 {
            x.is_finite()
        } else {
            unit_ok(x)
        };
        let got = TransferFunction::<2>::new(&[p]).err();
        assert_eq!(
            got,
            (!ok).then_some(Error::TransferFunctionValue),
            "tf field {field} = {x:e}"
        );
    }
    // Steps, phases, reference distances, thresholds.
    let pos = x.is_finite() && x > 0.0;
    assert_eq!(
        Step::new(x).err(),
        (!pos).then_some(Error::InvalidStep),
        "step {x:e}"
    );
    let phase_ok = (0.0..1.0).contains(&x);
    assert_eq!(
        Step::new(1.0).unwrap().with_phase(x).err(),
        (!phase_ok).then_some(Error::InvalidPhase),
        "phase {x:e}"
    );
    let v = [good];
    let vol = Volume::new(&v, [1, 1, 1]).unwrap();
    assert_eq!(
        vol.with_reference_distance(x).err(),
        (!pos).then_some(Error::InvalidReferenceDistance),
        "d′ {x:e}"
    );
    let t_ok = x > 0.0 && x <= 1.0;
    assert_eq!(
        FrontToBack::with_threshold(x).err(),
        (!t_ok).then_some(Error::InvalidThreshold),
        "A_stop {x:e}"
    );
    // Backgrounds: finite, 0 ≤ C ≤ A ≤ 1.
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(1.0).unwrap(),
    )
    .unwrap();
    for bg in [
        Sample {
            c: [x, 0.0, 0.0],
            a: 1.0,
        },
        Sample { c: [0.0; 3], a: x },
    ] {
        let ok = unit_ok(bg.a) && bg.c.iter().all(|&c| unit_ok(c) && c <= bg.a);
        assert_eq!(
            m.with_background(bg).err(),
            (!ok).then_some(Error::InvalidBackground),
            "background {bg:?}"
        );
    }
    // Rays: a finite origin and a finite non-zero direction (any magnitude) are valid.
    let r = Ray::new([x, 0.0, 0.0], [0.0, 0.0, 1.0]);
    assert_eq!(
        r.err(),
        (!x.is_finite()).then_some(Error::InvalidRay),
        "ray origin {x:e}"
    );
    for dir in [[x, 0.0, 0.0], [x, x, x], [x, 1.0, 0.0]] {
        let ok = dir.iter().all(|c| c.is_finite()) && dir.iter().any(|&c| c != 0.0);
        match Ray::new([0.0; 3], dir) {
            Ok(r) => {
                assert!(ok, "direction {dir:?} accepted");
                let len: f64 = r
                    .dir()
                    .iter()
                    .map(|&c| f64::from(c) * f64::from(c))
                    .sum::<f64>()
                    .sqrt();
                assert!(
                    (len - 1.0).abs() < 4e-7,
                    "direction {dir:?} normalised to length {len}"
                );
            }
            Err(e) => assert!(!ok && e == Error::InvalidRay, "direction {dir:?}: {e:?}"),
        }
    }
    // Downsampling filters, correction and integer ratios.
    let a_ok = x.is_finite() && (0.0..=0.5).contains(&x);
    assert_eq!(
        Filter4::new(x).err(),
        (!a_ok).then_some(Error::InvalidDownsampleFilter),
        "Filter4 {x:e}"
    );
    assert_eq!(Corrected::new(x).is_some(), pos, "Corrected {x:e}");
    let r_ok = pos && x < 4_294_967_296.0;
    assert_eq!(
        IntRatio::new(x).err(),
        (!r_ok).then_some(Error::InvalidStep),
        "IntRatio {x:e}"
    );
    // Integer positions: ⌊x·2^F + ½⌋ must lie in [0, 2^32).
    let raw = (f64::from(x) * 256.0 + 0.5).floor();
    let q_ok = (0.0..4_294_967_296.0).contains(&raw);
    assert_eq!(
        IntPos::<8>::quantize([x, 0.0, 0.0]).err(),
        (!q_ok).then_some(Error::InvalidPosition),
        "quantize {x:e}"
    );
}

/// Every special value of the generator in every constructor.
#[test]
fn every_special_value_in_every_constructor() {
    let mut w = Worst::new(
        "5 input: 29 special values × every constructor",
        "every float constructor",
        "mismatches",
    );
    let all = specials();
    assert_eq!(all.len(), 29);
    for &x in &all {
        w.exact(|| format!("x={x:e}"), || check_value(x));
    }
    w.report();
}

proptest! {
    /// The same around the edges and on arbitrary bit patterns.
    #[test]
    fn edge_values_in_every_constructor(x in any_edge()) {
        let mut w = Worst::new(
            "5 input: edge and arbitrary f32 × every constructor (fuzzed)",
            "every float constructor",
            "mismatches",
        );
        w.exact(|| format!("x={x:e}"), || check_value(x));
        w.report();
    }
}

/// Zero-sized images and bad steps in both marchers.
#[test]
fn zero_sized_images_and_bad_steps() {
    let mut w = Worst::new(
        "5 zero-sized images, d/d′ ≥ 2³² or overflowing",
        "RayMarcher/IntRayMarcher::{new, render_into}",
        "mismatches",
    );
    w.exact(
        || "images and steps".to_string(),
        zero_sized_images_and_bad_steps_body,
    );
    w.report();
}

fn zero_sized_images_and_bad_steps_body() {
    let v = [StraightU8([255; 4]); 8];
    let vol = Volume::new(&v, [2, 2, 2]).unwrap();
    let cam = Orthographic::looking_down_z([2, 2, 2]).unwrap();
    let step = Step::new(1.0).unwrap();
    let f = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    let i = IntRayMarcher::<_, _, _, 8>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        step,
    )
    .unwrap();
    for (w, h) in [(0, 0), (0, 3), (3, 0)] {
        assert_eq!(f.render_into(&cam, w, h, &mut []), Err(Error::EmptyImage));
        assert_eq!(i.render_into(&cam, w, h, &mut []), Err(Error::EmptyImage));
        let mut img = [Sample::TRANSPARENT; 4];
        assert_eq!(f.render_into(&cam, w, h, &mut img), Err(Error::EmptyImage));
        let mut img = [IntSample::TRANSPARENT; 4];
        assert_eq!(i.render_into(&cam, w, h, &mut img), Err(Error::EmptyImage));
    }
    // A step whose ratio d/d′ the integer path cannot represent (≥ 2^32) is a step error.
    let big = Step::new(1e10).unwrap();
    assert_eq!(
        IntRayMarcher::<_, _, _, 8>::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::NEVER,
            big
        )
        .err(),
        Some(Error::InvalidStep)
    );
    // A step so large against d′ → 0 that d/d′ overflows f32 is a step error in the float path.
    let tiny_ref = vol
        .with_reference_distance(volsample_host::edge_cases::MIN_SUBNORMAL)
        .unwrap();
    assert_eq!(
        RayMarcher::new(
            tiny_ref,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step
        )
        .err(),
        Some(Error::InvalidStep)
    );
}
