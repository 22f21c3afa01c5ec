//! The scene pipeline is the core's kernels and nothing else: its frames are bit-identical to
//! the core's float [`RayMarcher`] and integer [`IntRayMarcher`] on the same scene, with every
//! stage (correction, termination, background) in play, and it rejects what it cannot build.

use volsample::fixed_point::{ExtinctionFx, ExtinctionTables, IntExtinction, IntSample, IntStop};
use volsample::render::IntRayMarcher;
use volsample::{
    Camera, FrontToBack, Nearest, OpacityWeighted, Orthographic, Preweighted, RayMarcher, Sample,
    Separate, Step, Trilinear, Volume,
};
use volsample_host::float_checks::{CameraSpec, FilterKind};
use volsample_host::pipeline::{
    self, associated_u8, int_background, straight_u8, Method, ModeChoice, Precision,
    INT_EXTINCTION_TABLE, INT_FRAC_BITS,
};
use volsample_host::scene::generate::{self, RED_AIR};
use volsample_host::scene::{Prepared, Scene};

/// A semi-transparent ball in red air, stepped at `d = 0.4`, `d′ = 0.5` (correction), with
/// early termination at 0.9 and a black background: every stage is present.
fn scene() -> (Scene, Prepared) {
    let mut s = generate::ball_in_air(12, RED_AIR, "red");
    s.step = 0.4;
    s.d_ref = 0.5;
    s.a_stop = 0.9;
    s.background = generate::BLACK_BG;
    s.image = [12, 10];
    let p = s.prepare().expect("scene prepares");
    (s, p)
}

fn camera(s: &Scene) -> Orthographic {
    match s.camera {
        CameraSpec::Orthographic(e, d, u, x) => Orthographic::new(e, d, u, x).unwrap(),
        CameraSpec::Perspective(..) => panic!("the ball scene looks orthographically"),
    }
}

fn pipeline_frame(s: &Scene, p: &Prepared, m: Method) -> (Vec<Sample>, u64) {
    pipeline::with_pipeline(s, p, m, |f| {
        let [w, h] = f.image();
        let mut px = vec![Sample::TRANSPARENT; w * h];
        f.frame(&mut px).expect("frame renders");
        (px, f.samples())
    })
    .expect("pipeline builds")
}

/// Renders with the core marcher directly: pixels and the total sample count.
fn direct<R>(
    s: &Scene,
    cast: impl Fn(&volsample::Ray) -> (R, u32),
    to: impl Fn(R) -> Sample,
) -> (Vec<Sample>, u64) {
    let cam = camera(s);
    let [w, h] = s.image;
    let mut n = 0u64;
    let mut px = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let (r, k) = cast(&cam.ray(i, j, w, h));
            px.push(to(r));
            n += u64::from(k);
        }
    }
    (px, n)
}

fn method(mode: ModeChoice, precision: Precision, filter: FilterKind) -> Method {
    Method {
        mode,
        precision,
        filter,
    }
}

fn assert_same(a: &(Vec<Sample>, u64), b: &(Vec<Sample>, u64), what: &str) {
    assert_eq!(a.1, b.1, "{what}: sample counts");
    assert!(a.1 > 0, "{what}: the scene takes samples");
    for (k, (x, y)) in a.0.iter().zip(&b.0).enumerate() {
        assert_eq!(x, y, "{what}: pixel {k}");
    }
}

/// The scene's voxels `data` as a volume at the scene's reference distance.
fn scene_volume<'v, V: volsample::voxel::Voxel>(data: &'v [V], s: &Scene) -> Volume<'v, V> {
    Volume::new(data, s.dims)
        .unwrap()
        .with_reference_distance(s.d_ref)
        .unwrap()
}

/// The integer pipeline's stages for the scene: the step, the stop at `A_stop = 0.9` in U8.8
/// (round half up) and the U8.8 background.
fn int_stages(s: &Scene) -> (Step, IntStop, IntSample) {
    let step = Step::new(s.step).unwrap();
    let stop = IntStop::new((0.9f64 * 65280.0 + 0.5).floor() as u16).unwrap();
    (step, stop, int_background(s.background).unwrap())
}

/// The pipeline frame of `m` equals the core integer marcher's `cast` of every pixel's ray.
fn assert_int_frame(
    s: &Scene,
    p: &Prepared,
    cast: impl Fn(&volsample::Ray) -> (IntSample, u32),
    m: Method,
    what: &str,
) {
    let want = direct(s, cast, |x: IntSample| x.to_f32());
    assert_same(&pipeline_frame(s, p, m), &want, what);
}

/// The scene's voxels as the integer extinction mode reads them.
fn extinction_fx(straight: &[volsample::StraightU8]) -> Vec<ExtinctionFx> {
    straight
        .iter()
        .map(|&v| ExtinctionFx::from_straight_u8(v))
        .collect()
}

#[test]
fn float_frames_are_the_core_ray_marcher() {
    let (s, p) = scene();
    let vol = scene_volume(&p.rgba, &s);
    let step = Step::new(s.step).unwrap();
    let order = FrontToBack::with_threshold(s.a_stop).unwrap();
    let m = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), order, step)
        .unwrap()
        .with_background(s.background)
        .unwrap();
    assert!(m.correction().is_some());
    let want = direct(&s, |r| m.cast_counted(r), |x| x);
    let got = pipeline_frame(
        &s,
        &p,
        method(
            ModeChoice::OpacityWeighted,
            Precision::F32,
            FilterKind::TrilinearSum,
        ),
    );
    assert_same(&got, &want, "OW f32 trilinear");
    let m = RayMarcher::new(vol, Separate, Nearest, order, step)
        .unwrap()
        .with_background(s.background)
        .unwrap();
    let want = direct(&s, |r| m.cast_counted(r), |x| x);
    let got = pipeline_frame(
        &s,
        &p,
        method(ModeChoice::Separate, Precision::F32, FilterKind::Nearest),
    );
    assert_same(&got, &want, "Separate f32 nearest");
}

#[test]
fn integer_frames_are_the_core_int_ray_marcher() {
    let (s, p) = scene();
    let (step, stop, bg) = int_stages(&s);
    assert_eq!(bg, IntSample::new([0; 3], 65280).unwrap());

    let straight = straight_u8(&p.rgba);
    let vol = scene_volume(&straight, &s);
    let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        stop,
        step,
    )
    .unwrap()
    .with_background(bg);
    assert!(m.correction().is_some());
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(
            ModeChoice::OpacityWeighted,
            Precision::Int8,
            FilterKind::TrilinearSum,
        ),
        "OW int trilinear",
    );

    let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(vol, Separate, Nearest, stop, step)
        .unwrap()
        .with_background(bg);
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(ModeChoice::Separate, Precision::Int8, FilterKind::Nearest),
        "Separate int nearest",
    );

    let assoc = associated_u8(&p.rgba);
    let avol = scene_volume(&assoc, &s);
    let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(
        avol,
        Preweighted,
        Trilinear::new(),
        stop,
        step,
    )
    .unwrap()
    .with_background(bg);
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(
            ModeChoice::PreweightedU8,
            Precision::Int8,
            FilterKind::TrilinearSum,
        ),
        "Preweighted-u8 int trilinear",
    );

    let ext = extinction_fx(&straight);
    let evol = scene_volume(&ext, &s);
    let tables = ExtinctionTables::<INT_EXTINCTION_TABLE>::new();
    let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(
        evol,
        IntExtinction::new(&tables, 1.0).unwrap(),
        Trilinear::new(),
        stop,
        step,
    )
    .unwrap()
    .with_background(bg);
    // The extinction mode folds d/d′ into the optical depth: no separate correction.
    assert!(m.correction().is_none());
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(
            ModeChoice::ExtinctionWeighted,
            Precision::Int8,
            FilterKind::TrilinearSum,
        ),
        "Extinction int trilinear",
    );
}

/// The termination stage really ends rays early in the integer pipeline (so the equality
/// above covers it), and not at all without a threshold.
#[test]
fn integer_termination_shortens_rays() {
    let (mut s, p) = scene();
    let m = method(
        ModeChoice::OpacityWeighted,
        Precision::Int8,
        FilterKind::TrilinearSum,
    );
    for px in &mut s.image {
        *px = 8;
    }
    let early = pipeline_frame(&s, &p, m).1;
    s.a_stop = 1.0;
    let full = pipeline_frame(&s, &p, m).1;
    assert!(early < full, "{early} < {full}");
}

#[test]
fn pipeline_rejects_what_it_cannot_build() {
    let (s, p) = scene();
    for m in [
        method(
            ModeChoice::PostClassified,
            Precision::F32,
            FilterKind::TrilinearSum,
        ),
        method(
            ModeChoice::OpacityWeighted,
            Precision::Int8,
            FilterKind::BSpline,
        ),
        method(
            ModeChoice::Preweighted,
            Precision::Int8,
            FilterKind::Nearest,
        ),
    ] {
        assert!(!m.available(false), "{}", m.label());
        let r = pipeline::with_pipeline(&s, &p, m, |_| ());
        assert_eq!(r, Err(volsample::Error::InvalidClassifier), "{}", m.label());
    }
    let mut bad = s.clone();
    bad.step = 0.0;
    let m = method(
        ModeChoice::OpacityWeighted,
        Precision::Int8,
        FilterKind::Nearest,
    );
    assert!(matches!(
        pipeline::with_pipeline(&bad, &p, m, |_| ()),
        Err(volsample::Error::InvalidStep)
    ));
}

#[test]
fn frames_reject_a_wrong_pixel_buffer() {
    let (s, p) = scene();
    for precision in [Precision::F32, Precision::Int8] {
        let m = method(ModeChoice::OpacityWeighted, precision, FilterKind::Nearest);
        let r = pipeline::with_pipeline(&s, &p, m, |f| {
            let mut px = vec![Sample::TRANSPARENT; 3];
            f.frame(&mut px)
        })
        .unwrap();
        assert_eq!(
            r,
            Err(volsample::Error::ImageSizeMismatch {
                expected: 120,
                actual: 3
            })
        );
    }
}

/// Every method the report lists for a scene builds and renders finite pixels.
#[test]
fn every_listed_method_builds() {
    let (s, p) = scene();
    for m in Method::all(p.post.is_some(), true) {
        let (px, n) = pipeline_frame(&s, &p, m);
        assert!(n > 0, "{}", m.label());
        assert!(
            px.iter()
                .all(|x| x.a.is_finite() && x.c.iter().all(|c| c.is_finite())),
            "{}",
            m.label()
        );
    }
    assert!(Method::all(false, false)
        .iter()
        .any(|m| m.mode == ModeChoice::ExtinctionWeighted && m.precision == Precision::Int8));
}

/// The precision sweep's rows are the core's integer marcher at their bits and table sizes.
#[test]
fn sweep_frames_are_the_core_int_ray_marcher_at_their_bits_and_tables() {
    let (s, p) = scene();
    let (step, stop, bg) = int_stages(&s);
    let straight = straight_u8(&p.rgba);
    let vol = scene_volume(&straight, &s);
    let m = IntRayMarcher::<_, _, _, 4>::new(vol, OpacityWeighted, Trilinear::new(), stop, step)
        .unwrap()
        .with_background(bg);
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(
            ModeChoice::OpacityWeighted,
            Precision::IntBits(4),
            FilterKind::TrilinearSum,
        ),
        "OW int F=4 trilinear",
    );

    let ext = extinction_fx(&straight);
    let evol = scene_volume(&ext, &s);
    let tables = ExtinctionTables::<17>::new();
    let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(
        evol,
        IntExtinction::new(&tables, 1.0).unwrap(),
        Trilinear::new(),
        stop,
        step,
    )
    .unwrap()
    .with_background(bg);
    assert_int_frame(
        &s,
        &p,
        |r| m.cast_counted(r),
        method(
            ModeChoice::ExtinctionWeighted,
            Precision::IntTable(17),
            FilterKind::TrilinearSum,
        ),
        "Extinction int N=17 trilinear",
    );
}

/// RMS over pixels and channels of the displayed difference, in 8-bit levels.
fn rms_levels(a: &[Sample], b: &[Sample]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| f64::from(x.c[k] - y.c[k]) * 255.0))
        .map(|e| e * e)
        .sum();
    (sum / (3 * a.len()) as f64).sqrt()
}

/// Error against bits shows: the integer OW kernel comes closer to the f32 one with 12
/// fractional position bits than with 4, and the integer extinction kernel with 4097 table
/// nodes than with 17.
#[test]
fn more_bits_and_larger_tables_come_closer_to_f32() {
    let (mut s, _) = scene();
    s.image = [32, 32];
    let p = s.prepare().unwrap();
    let frame = |mode, precision| {
        pipeline_frame(&s, &p, method(mode, precision, FilterKind::TrilinearSum)).0
    };
    let ow = frame(ModeChoice::OpacityWeighted, Precision::F32);
    let (e4, e12) = (
        rms_levels(
            &frame(ModeChoice::OpacityWeighted, Precision::IntBits(4)),
            &ow,
        ),
        rms_levels(
            &frame(ModeChoice::OpacityWeighted, Precision::IntBits(12)),
            &ow,
        ),
    );
    assert!(e4 > e12, "F=4: {e4}, F=12: {e12} levels from f32");
    let ext = frame(ModeChoice::ExtinctionWeighted, Precision::F32);
    let (n17, n4097) = (
        rms_levels(
            &frame(ModeChoice::ExtinctionWeighted, Precision::IntTable(17)),
            &ext,
        ),
        rms_levels(
            &frame(ModeChoice::ExtinctionWeighted, Precision::IntTable(4097)),
            &ext,
        ),
    );
    assert!(n17 > n4097, "N=17: {n17}, N=4097: {n4097} levels from f32");
}

/// A scene without early termination (`a_stop = 1`): the pipeline's float marcher stops at
/// `A = 1` (one marcher type for every scene), and its image is the never-stopping marcher's
/// bit for bit, while it takes fewer samples where rays become opaque.
#[test]
fn float_frames_without_termination_are_the_never_stopping_marcher() {
    let (mut s, _) = scene();
    s.a_stop = 1.0;
    let p = s.prepare().expect("scene prepares");
    let vol = scene_volume(&p.rgba, &s);
    let step = Step::new(s.step).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
    .with_background(s.background)
    .unwrap();
    let want = direct(&s, |r| m.cast_counted(r), |x| x);
    let (px, n) = pipeline_frame(
        &s,
        &p,
        method(
            ModeChoice::OpacityWeighted,
            Precision::F32,
            FilterKind::TrilinearSum,
        ),
    );
    for (k, (a, b)) in px.iter().zip(&want.0).enumerate() {
        assert_eq!(
            (a.c.map(f32::to_bits), a.a.to_bits()),
            (b.c.map(f32::to_bits), b.a.to_bits()),
            "pixel {k}"
        );
    }
    // Some rays become opaque (`A = 1` exactly) and stop there: the threshold is reached.
    assert!(n < want.1, "samples {n} vs {} without stopping", want.1);
    assert!(px.iter().any(|q| q.a == 1.0));
}

/// `time_frames` renders the asked number of frames on one pipeline and counts the samples a
/// frame takes as a single frame does.
#[test]
fn time_frames_times_each_frame_and_counts_once() {
    let (s, p) = scene();
    let m = method(
        ModeChoice::OpacityWeighted,
        Precision::F32,
        FilterKind::TrilinearSum,
    );
    let (_, n) = pipeline_frame(&s, &p, m);
    let (seconds, samples) = pipeline::time_frames(&s, &p, m, 3).expect("frames render");
    assert_eq!(seconds.len(), 3);
    assert!(seconds.iter().all(|t| t.is_finite() && *t >= 0.0));
    assert_eq!(samples, n);
}
