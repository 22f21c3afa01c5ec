//! A stage the pipeline leaves out is left out exactly where it would be the identity: one
//! test per stage (issue "the main job", "Effects only where a scene calls for them").

use volsample::opacity::{correct, Corrected, Correction, Uncorrected};
use volsample::shade::{shade_in_place, Light};
use volsample::{
    FrontToBack, OpacityWeighted, Orthographic, RayMarcher, Sample, Step, StraightF32, Trilinear,
    Volume,
};
use volsample_host::scene::generate;
use volsample_host::scene::{Scene, VolumeData};
use volsample_host::tolerance as tol;

fn ball() -> (Vec<StraightF32>, [usize; 3]) {
    let s = generate::ball_in_air(12, generate::RED_AIR, "red");
    match s.data {
        VolumeData::Rgba(mut v) => {
            // Semi-transparent, so every stage has something to change.
            for x in &mut v {
                x.a *= 0.6;
            }
            (v, s.dims)
        }
        VolumeData::Scalar(_) => unreachable!("an RGBA scene"),
    }
}

fn render<O: volsample::composite::Order>(
    m: &RayMarcher<'_, StraightF32, OpacityWeighted, Trilinear, O>,
) -> Vec<Sample> {
    let mut img = vec![Sample::TRANSPARENT; 16 * 16];
    let cam =
        Orthographic::new([-10.0, 5.5, 5.7], [1.0, 0.1, 0.05], [0.0, 1.0, 0.0], 14.0).unwrap();
    m.render_into(&cam, 16, 16, &mut img).unwrap();
    img
}

/// Correction is skipped exactly when `d = d′`, where it is the identity: the pipeline picks
/// no correction, and forcing one with ratio 1 changes no sample by more than its bound.
#[test]
fn correction_skipped_exactly_at_reference_distance() {
    let (v, dims) = ball();
    let vol = Volume::new(&v, dims)
        .unwrap()
        .with_reference_distance(0.5)
        .unwrap();
    let same = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.5).unwrap(),
    )
    .unwrap();
    assert!(same.correction().is_none());
    let other = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.4).unwrap(),
    )
    .unwrap();
    assert_eq!(other.correction().map(|c| c.ratio()), Some(0.4 / 0.5));
    // The skipped stage would be the identity there.
    let forced = Corrected::new(1.0).unwrap();
    for k in 0..200 {
        let p = [k as f32 * 0.05, 5.0 + (k as f32 * 0.37).sin() * 4.0, 6.0];
        let s = same.sample(p);
        assert_eq!(Uncorrected.apply(s), s);
        let c = forced.apply(s);
        let err = (0..3)
            .map(|i| (c.c[i] - s.c[i]).abs())
            .fold((c.a - s.a).abs(), f32::max);
        assert!(f64::from(err) <= tol::CORRECTION_ABS, "{err}");
        assert_eq!(correct(s, 1.0).a, c.a);
    }
}

/// Early termination is skipped exactly at `A_stop = 1`, where it cannot change a pixel:
/// rendering with a threshold of 1 gives the same bits as no termination test.
#[test]
fn termination_skipped_exactly_at_threshold_one() {
    let (v, dims) = ball();
    let vol = Volume::new(&v, dims).unwrap();
    let step = Step::new(0.5).unwrap();
    let never = render(
        &RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap(),
    );
    let at_one = render(
        &RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::with_threshold(1.0).unwrap(),
            step,
        )
        .unwrap(),
    );
    assert_eq!(never, at_one);
    // And below 1 it does act (so the comparison above could have failed).
    let early = render(
        &RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::with_threshold(0.3).unwrap(),
            step,
        )
        .unwrap(),
    );
    assert_ne!(never, early);
}

/// The background is skipped (transparent) exactly where compositing over it is the identity.
#[test]
fn transparent_background_is_the_identity() {
    let (v, dims) = ball();
    let vol = Volume::new(&v, dims).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.5).unwrap(),
    )
    .unwrap();
    let plain = render(&m);
    let explicit = render(&m.with_background(Sample::TRANSPARENT).unwrap());
    assert_eq!(plain, explicit);
    let black = render(&m.with_background(generate::BLACK_BG).unwrap());
    assert_ne!(plain, black);
}

/// Shading is skipped without a light, exactly where it would be the identity: the unlit
/// light (`k_a = 1`, `k_d = 0`) leaves every voxel bit-identical.
#[test]
fn shading_skipped_without_light_is_the_identity() {
    let torus = generate::torus(16);
    let VolumeData::Scalar(s) = &torus.data else {
        unreachable!("a scalar scene")
    };
    let sv = Volume::new(s, torus.dims).unwrap();
    let mut unlit_scene: Scene = torus.clone();
    unlit_scene.light = None;
    let unlit = unlit_scene.prepare().unwrap().rgba;
    let mut shaded = unlit.clone();
    shade_in_place(&sv, &Light::UNLIT, &mut shaded).unwrap();
    assert_eq!(unlit, shaded);
    // A real light does change colors (the comparison could fail).
    let lit = torus.prepare().unwrap().rgba;
    assert_ne!(unlit, lit);
    assert!(torus.effects().shading && !unlit_scene.effects().shading);
}

/// Classification is skipped for RGBA data, which then passes through bit-identical; scalar
/// data is classified.
#[test]
fn classification_only_for_scalar_data() {
    let s = generate::ball_in_air(8, generate::RED_AIR, "red");
    let VolumeData::Rgba(v) = &s.data else {
        unreachable!("an RGBA scene")
    };
    assert_eq!(&s.prepare().unwrap().rgba, v);
    assert!(!s.effects().classification);
    assert!(generate::torus(8).effects().classification);
}
