//! Whole images: `RayMarcher::render_into` against the reference renderer, for random volumes,
//! cameras (orthographic and perspective), steps, phases, backgrounds, termination and order;
//! and the extinction-weighted renderer against the ground-truth integral.

use proptest::prelude::*;
use volsample::Sample;
use volsample_host::float_checks::{
    max_abs_diff, CameraSpec, FilterKind, FloatCase, ModeKind, RenderSpec,
};
use volsample_host::reference::{self, RefRay};
use volsample_host::strategies::float_case;
use volsample_host::tolerance as tol;

fn unit_vec() -> impl Strategy<Value = [f32; 3]> {
    [-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0].prop_filter("not too short", |v| {
        v.iter().map(|x| x * x).sum::<f32>() > 0.1
    })
}

prop_compose! {
    fn render_spec(dims: [usize; 3])
        (dir in unit_vec(), up in unit_vec(), perspective in any::<bool>(),
         back in 2.0f32..6.0, extent in 2.0f32..8.0, fov in 0.3f32..1.5,
         step in prop_oneof![Just(1.0f32), 0.2f32..2.0], phase in 0.0f32..1.0,
         bg in (0.0f32..=1.0, 0.0f32..=1.0),
         a_stop in prop_oneof![Just(1.0f32), Just(0.95f32)], btf in any::<bool>())
        -> RenderSpec {
        let centre = dims.map(|n| n as f32 * 0.5 - 0.5);
        let len = dir.iter().map(|x| x * x).sum::<f32>().sqrt();
        let radius = dims.iter().map(|&n| (n * n) as f32).sum::<f32>().sqrt();
        let eye = [0, 1, 2].map(|k| centre[k] - dir[k] / len * (radius + back));
        let camera = if perspective {
            CameraSpec::Perspective(eye, centre, up, fov)
        } else {
            // The reference camera takes a unit direction (the core normalises its own).
            CameraSpec::Orthographic(eye, dir.map(|x| x / len), up, extent)
        };
        RenderSpec {
            camera, width: 4, height: 3, step, phase,
            background: Sample::clamped([bg.0 * bg.1; 3], bg.1),
            a_stop: if btf { 1.0 } else { a_stop },
            back_to_front: btf,
        }
    }
}

prop_compose! {
    fn case_and_spec()(case in float_case())(spec in render_spec(case.dims), case in Just(case))
        -> (FloatCase, RenderSpec) {
        (case, spec)
    }
}

fn camera_ok(spec: &RenderSpec) -> bool {
    match spec.camera {
        CameraSpec::Orthographic(eye, dir, up, extent) => {
            volsample::Orthographic::new(eye, dir, up, extent).is_ok()
        }
        CameraSpec::Perspective(eye, t, up, fov) => {
            volsample::Perspective::new(eye, t, up, fov).is_ok()
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Every mode × filter renders as the reference does, pixel by pixel.
    #[test]
    fn render_matches_reference((mut case, spec) in case_and_spec()) {
        prop_assume!(camera_ok(&spec));
        if spec.step != case.d_ref {
            // Keep opacity correction well conditioned (see corrected_sample_matches_reference).
            for v in &mut case.voxels { v.a *= 0.9; }
            for p in &mut case.tf { p.a *= 0.9; }
        }
        let mut compared = 0usize;
        let mut skipped = 0usize;
        for mode in ModeKind::ALL {
            for filter in FilterKind::ALL {
                let (c, s) = case.compare_render(mode, filter, &spec).map_err(TestCaseError::fail)?;
                compared += c;
                skipped += s;
            }
        }
        prop_assert!(skipped * 10 <= compared + skipped, "too many ambiguous pixels: {skipped}");
    }
}

/// In a homogeneous medium the extinction-weighted renderer is exact for any step: every
/// sample integrates a constant segment, and the partial last segment is absent from both.
/// The ground truth `1 − e^(−τL)` is over the sampled length `L = n·d`.
#[test]
fn extinction_homogeneous_medium_is_exact() {
    let n = 6usize;
    let v = volsample::StraightF32 {
        c: [0.2, 0.6, 1.0],
        a: 0.3,
    };
    let voxels = vec![v; n * n * n];
    let ext: Vec<_> = voxels
        .iter()
        .map(|&v| volsample::ExtinctionF32::from_straight(v, 1.0))
        .collect();
    let vol = volsample::Volume::new(&ext, [n; 3]).unwrap();
    for d in [0.1f32, 0.37, 1.0, 2.5] {
        let m = volsample::RayMarcher::new(
            vol,
            volsample::ExtinctionWeighted,
            volsample::Trilinear::new(),
            volsample::FrontToBack::new(),
            volsample::Step::new(d).unwrap(),
        )
        .unwrap();
        let ray = volsample::Ray::new([2.3, 1.7, -3.0], [0.0, 0.0, 1.0]).unwrap();
        let px = m.cast(&ray);
        // Box z ∈ [−0.5, 5.5] → t ∈ [2.5, 8.5); samples at k·d in that range.
        let first = (2.5 / f64::from(d)).ceil();
        let last = (8.5 / f64::from(d)).ceil();
        let length = (last - first) * f64::from(d);
        let tau = -(1.0 - f64::from(v.a)).ln();
        let alpha = 1.0 - (-tau * length).exp();
        assert!(
            (f64::from(px.a) - alpha).abs() < 1e-5,
            "d={d}: {} vs {alpha}",
            px.a
        );
        for k in 0..3 {
            let c = f64::from(v.c[k]) * alpha;
            assert!((f64::from(px.c[k]) - c).abs() < 1e-5, "d={d} channel {k}");
        }
    }
}

/// On a smooth volume, the extinction-weighted renderer converges to the ground truth at first
/// order in the step: the error at `d = 1/16` is below `EXTINCTION_TRUTH_PER_STEP · d`.
#[test]
fn extinction_converges_to_ground_truth() {
    let n = 8usize;
    let mut voxels = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let f = |t: usize| 0.5 + 0.5 * ((t as f32) * 0.7).sin();
                voxels.push(volsample::StraightF32 {
                    c: [f(x), f(y), f(z)],
                    a: 0.4 * f(x + y + z),
                });
            }
        }
    }
    let ext: Vec<_> = voxels
        .iter()
        .map(|&v| volsample::ExtinctionF32::from_straight(v, 1.0))
        .collect();
    let vol = volsample::Volume::new(&ext, [n; 3]).unwrap();
    let refvol = reference::RefVolume::new(
        [n; 3],
        voxels
            .iter()
            .map(|v| reference::RefVoxel::new(v.c.map(f64::from), f64::from(v.a)))
            .collect(),
        1.0,
    );
    let mut worst = [0.0f64; 2];
    for (slot, d) in [(0usize, 0.25f32), (1, 1.0 / 16.0)] {
        let m = volsample::RayMarcher::new(
            vol,
            volsample::ExtinctionWeighted,
            volsample::Trilinear::new(),
            volsample::FrontToBack::new(),
            volsample::Step::new(d).unwrap(),
        )
        .unwrap();
        for (ox, oy) in [(1.3f32, 2.1f32), (3.7, 5.2), (6.1, 0.4)] {
            let ray = volsample::Ray::new([ox, oy, -2.0], [0.1, 0.05, 1.0]).unwrap();
            let px = m.cast(&ray);
            let rr = RefRay::new([f64::from(ox), f64::from(oy), -2.0], {
                let l = (0.01f64 + 0.0025 + 1.0).sqrt();
                [0.1 / l, 0.05 / l, 1.0 / l]
            });
            // The sampled length ends up to one step before the box: integrate the truth over
            // exactly the sampled segments [t_k, t_k + d).
            let (t0, t1) = reference::clip_ray([n; 3], &rr).unwrap();
            let times = reference::sample_times(t0, t1, f64::from(d), 0.0);
            let start = times[0] - 0.5 * f64::from(d);
            let end = times[times.len() - 1] + 0.5 * f64::from(d);
            let truth = reference::integrate_segment(&rr, start, end, 1.0 / 256.0, |p| {
                reference::extinction_at(&refvol, reference::RefFilter::Trilinear, p)
            });
            worst[slot] = worst[slot].max(max_abs_diff(px, truth));
        }
    }
    let bound = tol::EXTINCTION_TRUTH_PER_STEP;
    assert!(
        worst[1] <= bound / 16.0,
        "d=1/16: {} > {}",
        worst[1],
        bound / 16.0
    );
    assert!(
        worst[0] <= bound / 4.0,
        "d=1/4: {} > {}",
        worst[0],
        bound / 4.0
    );
    assert!(worst[1] < worst[0], "no convergence: {worst:?}");
}
