//! The report's numbers and verdicts: error statistics, the continuous truth, and verdicts
//! computed from the rows (checked against values worked out by hand).

use volsample::Isa;
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{Method, ModeChoice, Precision};
use volsample_host::report::{
    self, errors, group_verdict, Errors, Group, Machine, Report, Row, Timing, Truth,
};
use volsample_host::scene::continuous::{continuous_truth, rgba_at};
use volsample_host::scene::generate::{self, BLACK_AIR, RED_AIR};
use volsample_host::scene::VolumeData;

/// Error statistics agree with the hand-computed ones within this (f32 pixels, f64 sums).
const STATS_ABS: f64 = 1e-4;

#[test]
fn errors_are_rms_p99_and_the_share_over_eight_levels() {
    // 100 pixels: 90 exact, 9 off by 4 levels in red, 1 off by 20 levels in all three.
    let lv = |l: f32| l / 255.0;
    let truth = vec![[0.5f32; 3]; 100];
    let mut img = truth.clone();
    for p in img.iter_mut().skip(90).take(9) {
        p[0] += lv(4.0);
    }
    img[99] = [0.5 + lv(20.0); 3];
    let e = errors(&img, &truth);
    // RMS over 300 channel values: (9·16 + 3·400) / 300 = 4.48.
    assert!((e.rms - 4.48f64.sqrt()).abs() < STATS_ABS, "{e:?}");
    // Nearest rank: the 99th of 100 sorted pixel errors is the ninth 4-level pixel.
    assert!((e.p99 - 4.0).abs() < STATS_ABS, "{e:?}");
    // One pixel of 100 above 8 levels.
    assert!((e.over - 0.01).abs() < 1e-12, "{e:?}");
}

#[test]
fn every_generated_scene_has_a_continuous_definition_matching_its_voxels() {
    for scene in generate::paper_scenes(false) {
        assert!(scene.continuous.is_some(), "{}", scene.name);
        // The RGBA scenes' voxels are their definition at the voxel centres.
        if let VolumeData::Rgba(v) = &scene.data {
            let [n, _, _] = scene.dims;
            for (i, voxel) in v.iter().enumerate().step_by(7) {
                let p = [i % n, (i / n) % n, i / (n * n)].map(|c| c as f64);
                let at = rgba_at(&scene, p).unwrap();
                assert_eq!(at.alpha, f64::from(voxel.a), "{} at {p:?}", scene.name);
                if voxel.a > 0.0 {
                    assert_eq!(at.color, voxel.c.map(f64::from), "{} at {p:?}", scene.name);
                }
            }
        }
    }
}

#[test]
fn continuous_truth_of_the_ball_is_the_ball() {
    // An opaque white ball (centre (n−1)/2 + 0.27, radius 0.32·n) in transparent red air over
    // black, seen orthographically: a pixel whose ray passes the centre is white, one in the
    // image corner misses it (black), and no pixel is red (the air is transparent).
    for air in [RED_AIR, BLACK_AIR] {
        let mut scene = generate::ball_in_air(16, air, "t");
        scene.image = [17, 17];
        let truth = continuous_truth(&scene, 1.0 / 16.0).unwrap();
        let centre = truth[8 * 17 + 8];
        assert!(centre.iter().all(|&c| c > 0.999), "{centre:?}");
        assert_eq!(truth[0], [0.0; 3]);
        for p in &truth {
            assert!(
                (p[0] - p[1]).abs() < 1e-6 && (p[1] - p[2]).abs() < 1e-6,
                "{p:?}"
            );
        }
    }
}

#[test]
fn continuous_truth_of_the_phase_face_is_its_homogeneous_slab() {
    // The phase scene's face (α = 0.6 per voxel, straight grey 0.9) viewed along +z: a ray
    // through column x enters at z = 0.4n + 0.07x and leaves the box at z = n − ½, so its
    // color is 0.9·(1 − 0.4^L) with L that length (exact emission–absorption of a
    // homogeneous slab). Checked on the image's central row.
    let n = 16usize;
    let mut scene = generate::phase(n);
    let [w, h] = [33usize, 33];
    scene.image = [w, h];
    let truth = continuous_truth(&scene, 1.0 / 64.0).unwrap();
    let cam = report::ref_camera(&scene);
    let mut checked = 0;
    for i in 0..w {
        let ray = volsample_host::reference::camera_ray(&cam, w, h, i, h / 2);
        let p = ray.at(0.0);
        let x = p[0];
        let y = p[1];
        if !(0.0..=(n as f64 - 1.0)).contains(&x) || !(0.0..=(n as f64 - 1.0)).contains(&y) {
            continue;
        }
        let z0 = 0.4 * n as f64 + 0.07 * x;
        let len = (n as f64 - 0.5) - z0;
        let want = 0.9 * (1.0 - 0.4f64.powf(len));
        let got = f64::from(truth[(h / 2) * w + i][0]);
        // Midpoint substeps of 1/64 voxel: the entry is found within one substep.
        let tol = 0.9 * 0.4f64.powf(len - 1.0 / 64.0) - 0.9 * 0.4f64.powf(len) + 1e-6;
        assert!((got - want).abs() <= tol, "x = {x}: {got} vs {want}");
        checked += 1;
    }
    assert!(checked > 20, "{checked}");
}

fn method(mode: ModeChoice, filter: FilterKind) -> Method {
    Method {
        mode,
        precision: Precision::F32,
        filter,
    }
}

fn row(scene: &str, m: Method, rms: f64) -> Row {
    let e = Errors {
        rms,
        p99: 2.0 * rms,
        over: 0.0,
    };
    Row {
        scene: scene.into(),
        group: Group::Rgba,
        method: m,
        continuous: Some(e),
        field: e,
        from_f32: (m.precision != Precision::F32).then_some(Errors {
            rms: rms / 10.0,
            p99: rms / 5.0,
            over: 0.0,
        }),
        samples: 100,
    }
}

/// The time of `m` on a made-up timing scene of the RGBA group.
fn timing(m: Method, ns: f64) -> Timing {
    Timing {
        group: Group::Rgba,
        scene: "timing".into(),
        sizes: ([4; 3], [4, 4]),
        method: m,
        ns_per_sample: ns,
        samples: 1,
    }
}

fn test_machine() -> Machine {
    Machine {
        isa: Isa::BASELINE,
        threads: 1,
        cpu: "test".into(),
    }
}

#[test]
fn the_verdict_picks_the_cheapest_method_as_good_as_the_best() {
    let ow = method(ModeChoice::OpacityWeighted, FilterKind::TrilinearSum);
    let sep = method(ModeChoice::Separate, FilterKind::TrilinearSum);
    let ext = method(ModeChoice::ExtinctionWeighted, FilterKind::TrilinearSum);
    let bsp = method(ModeChoice::OpacityWeighted, FilterKind::BSpline);
    let near = method(ModeChoice::OpacityWeighted, FilterKind::Nearest);
    // Two scenes: mean RMS ow 2.0, ext 2.1 (as good: within 5 % or half a level), bspline 1.9 (the most
    // accurate), separate 6.0 (leaks in scene a only), nearest 9.0.
    let rows = vec![
        row("a", ow, 2.0),
        row("a", sep, 10.0),
        row("a", ext, 2.2),
        row("a", bsp, 1.8),
        row("a", near, 9.0),
        row("b", ow, 2.0),
        row("b", sep, 2.0),
        row("b", ext, 2.0),
        row("b", bsp, 2.0),
        row("b", near, 9.0),
    ];
    let r = Report {
        rows,
        timings: vec![
            timing(ow, 10.0),
            timing(sep, 9.0),
            timing(ext, 12.0),
            timing(bsp, 50.0),
            timing(near, 5.0),
        ],
        machine: test_machine(),
    };
    assert_eq!(r.truth_of(Group::Rgba), Truth::Continuous);
    let v = group_verdict(&r, Group::Rgba);
    // Best mean RMS 1.9 (bspline); as good: ≤ max(1.995, 2.4) = 2.4: ow (2.0), ext (2.1),
    // bspline. The cheapest of those is ow at 10 ns.
    assert!(
        v[0].contains("pick opacity-weighted/f32/trilinear"),
        "{v:?}"
    );
    // The ladder by time: nearest (5 ns, 9.0), separate (9 ns, 6.0), ow (10 ns, 2.0),
    // bspline (50 ns, 1.9); ext (12 ns, 2.1) is dominated by ow.
    assert!(
        v[1].contains("5.0 ns: opacity-weighted/f32/nearest (RMS 9.00)"),
        "{v:?}"
    );
    assert!(
        v[1].contains("9.0 ns: separate/f32/trilinear (RMS 6.00)"),
        "{v:?}"
    );
    assert!(
        v[1].contains("50.0 ns: opacity-weighted/f32/bspline (RMS 1.90)"),
        "{v:?}"
    );
    assert!(!v[1].contains("extinction"), "{v:?}");
    // Separate leaks in a (10 vs 2), not in b (2 vs 2).
    assert!(v[2].contains("Separate leaks in 1 of 2 scenes"), "{v:?}");
    assert!(v[2].contains("a 10.0 vs 2.0"), "{v:?}");
    assert!(report::leaks(10.0, 2.0) && !report::leaks(2.0, 2.0) && !report::leaks(2.9, 2.0));
}

/// The tiny preset end to end: both truths for every row, and the paper's finding against
/// the continuous truth: on the white ball in transparent red air, `Separate` trilinear leaks
/// the air's color and `OpacityWeighted` does not.
#[test]
fn the_report_finds_separate_leaking_into_the_red_air() {
    let opts = report::Options {
        scenes: generate::tiny_scenes(),
        timing: report::timing_scenes(12, 8),
        full: false,
        runs: 1,
        truth_step: 1.0 / 8.0,
        out: None,
        progress: false,
    };
    let r = report::run(&opts).unwrap();
    assert!(r.rows.iter().all(|row| row.continuous.is_some()));
    assert!(r.timings.iter().all(|t| t.ns_per_sample > 0.0));
    assert_eq!(r.groups(), vec![Group::Rgba, Group::Transfer]);
    let red = |mode| {
        r.rows
            .iter()
            .find(|x| x.scene == "red-12" && x.method == method(mode, FilterKind::TrilinearSum))
            .and_then(|x| x.continuous)
            .unwrap()
    };
    let (sep, ow) = (red(ModeChoice::Separate), red(ModeChoice::OpacityWeighted));
    assert!(report::leaks(sep.rms, ow.rms), "{sep:?} {ow:?}");
    let text = report::format_report(&r);
    assert!(text.contains("VERDICT, RGBA scenes"), "{text}");
    assert!(text.contains("Separate leaks"), "{text}");
    assert!(text.contains(&r.machine.line()), "{text}");
    // Precision as a dimension: the sweeps and the GPU texture unit have rows and lines, and
    // the texture unit is not timed.
    for p in [
        Precision::IntBits(4),
        Precision::IntBits(12),
        Precision::IntTable(17),
        Precision::IntTable(4097),
        Precision::Texture8,
    ] {
        assert!(r.rows.iter().any(|x| x.method.precision == p), "{p:?}");
    }
    assert!(r
        .timings
        .iter()
        .all(|t| t.method.precision != Precision::Texture8));
    // Every other precision is also compared with the f32 image of its mode and filter.
    for x in &r.rows {
        assert_eq!(
            x.from_f32.is_some(),
            x.method.precision != Precision::F32,
            "{} on {}",
            x.method.label(),
            x.scene
        );
    }
    assert!(r
        .timings
        .iter()
        .any(|t| t.method.precision == Precision::IntBits(12)));
    assert!(text.contains("by fractional position bits"), "{text}");
    assert!(text.contains("by table nodes"), "{text}");
    assert!(text.contains("GPU texture unit"), "{text}");
}

/// The precision lines are the summary's numbers, in order of bits.
#[test]
fn precision_lines_list_error_and_time_against_bits() {
    let at = |mode, precision| Method {
        mode,
        precision,
        filter: FilterKind::TrilinearSum,
    };
    let ow = |p| at(ModeChoice::OpacityWeighted, p);
    let rows = vec![
        row("a", ow(Precision::IntBits(12)), 2.5),
        row("a", ow(Precision::Int8), 3.0),
        row("a", ow(Precision::IntBits(4)), 6.0),
        row("a", ow(Precision::F32), 2.0),
        row("a", at(ModeChoice::Separate, Precision::Texture8), 5.0),
        row("a", at(ModeChoice::Separate, Precision::F32), 4.0),
    ];
    let r = Report {
        rows,
        timings: vec![
            timing(ow(Precision::IntBits(4)), 4.1),
            timing(ow(Precision::Int8), 4.0),
            timing(ow(Precision::IntBits(12)), 4.2),
            timing(ow(Precision::F32), 6.0),
            timing(at(ModeChoice::Separate, Precision::F32), 5.5),
        ],
        machine: test_machine(),
    };
    let l = report::precision_lines(&r, Group::Rgba);
    assert_eq!(l.len(), 2, "{l:?}");
    assert!(
        l[0].ends_with(
            "F=4: 0.60 from f32, RMS 6.00 at 4.1 ns; F=8: 0.30 from f32, RMS 3.00 at 4.0 ns; \
             F=12: 0.25 from f32, RMS 2.50 at 4.2 ns (f32: RMS 2.00 at 6.0 ns)"
        ),
        "{l:?}"
    );
    assert!(
        l[1].ends_with(
            "on straight RGBA8 (separate): 0.50 from f32, RMS 5.00; the f32 filter on f32 straight voxels: RMS 4.00"
        ),
        "{l:?}"
    );
    // Not timed: "-" in the tables.
    assert_eq!(report::time_cells(f64::NAN, 4.0), ("-".into(), "-".into()));
    assert_eq!(report::time_cells(6.0, 4.0), ("6.0".into(), "1.50x".into()));
}

/// The report counts a frame's samples by `sample_range` where no ray stops early: that is
/// `cast_counted`'s count for such rays, float and integer marchers alike.
#[test]
fn sample_range_is_the_count_of_a_ray_that_does_not_stop() {
    use volsample::{
        FrontToBack, IntRayMarcher, IntStop, OpacityWeighted, Ray, RayMarcher, Step, StraightU8,
        Trilinear, Volume,
    };
    let voxels: Vec<StraightU8> = (0..6 * 5 * 7)
        .map(|i| StraightU8([(i * 7) as u8, (i * 13) as u8, 90, (i * 29) as u8]))
        .collect();
    let vol = Volume::new(&voxels, [6, 5, 7]).unwrap();
    for d in [0.3f32, 0.5, 1.0, 1.7] {
        let step = Step::new(d).unwrap();
        let f = RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap();
        let i = IntRayMarcher::new(vol, OpacityWeighted, Trilinear::new(), IntStop::NEVER, step)
            .unwrap();
        let mut nonzero = 0;
        for k in 0..200 {
            let a = k as f32 * 0.137;
            let ray = Ray::new(
                [
                    3.0 + 9.0 * a.cos(),
                    2.0 + 9.0 * a.sin(),
                    -2.0 + (k % 11) as f32,
                ],
                [-a.cos(), -a.sin() + 0.1, 0.3 - (k % 5) as f32 * 0.1],
            )
            .unwrap();
            let n = f.sample_range(&ray).1;
            assert_eq!(f.cast_counted(&ray).1, n, "float, d = {d}, ray {k}");
            assert_eq!(
                i.cast_counted(&ray).1,
                i.sample_range(&ray).1,
                "int, d = {d}, ray {k}"
            );
            nonzero += usize::from(n > 0);
        }
        assert!(nonzero > 50, "{nonzero}");
    }
}

/// The error-against-time plot is written as a 1200 × 680 RGB PNG (drawn into memory, encoded
/// by the `png` crate) with a white background, each method's colour on it, and text.
#[test]
fn the_plot_png_holds_the_drawn_chart() {
    let summary = [
        (
            method(ModeChoice::OpacityWeighted, FilterKind::TrilinearSum),
            10.0,
            20.0,
            5.0,
            3,
        ),
        (
            method(ModeChoice::Separate, FilterKind::Nearest),
            30.0,
            60.0,
            2.0,
            3,
        ),
    ];
    let dir = std::env::temp_dir().join(format!("volsample-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plot.png");
    let r = volsample_host::plot::error_vs_time(&path, "test scenes", &summary);
    if !std::path::Path::new(volsample_host::plot::FONT).exists() {
        assert!(r.unwrap_err().contains("fonts-dejavu-core"));
        return;
    }
    r.unwrap();
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (1200, 680));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let px: Vec<[u8; 3]> = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let count = |c: [u8; 3]| px.iter().filter(|&&p| p == c).count();
    // Mostly the white background; OW's blue and Separate's red (plot.rs's colours) drawn.
    assert!(count([255, 255, 255]) > px.len() / 2);
    assert!(count([38, 139, 210]) > 20, "{}", count([38, 139, 210]));
    assert!(count([220, 50, 47]) > 20, "{}", count([220, 50, 47]));
    // Black text and axes.
    assert!(px.iter().filter(|p| p.iter().all(|&c| c < 64)).count() > 500);
}
