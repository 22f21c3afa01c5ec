//! Group 9, the pre-passes: classification (`classify`) and shading (`shade`) before
//! interpolation.
//!
//! * Input: every special `f32` in [`Isosurface::new`], [`Light::new`] and the classifier's
//!   color gives a value when the documented domain contains it and the matching error
//!   otherwise (`InvalidClassifier`, `InvalidLight` for a zero, NaN or `∞` direction,
//!   `VoxelOutOfRange`); output buffers of the wrong length give `LengthMismatch`. Every
//!   finite non-zero light direction, subnormal to `f32::MAX`, is a direction.
//! * Levoy's classifier on zero gradients (flat regions, `1×1×1` volumes, the flat axes of
//!   `1×N×1`), at the volume edges (one-sided differences), and on extreme scalars (values
//!   near `±f32::MAX`, whose differences overflow; subnormal steps, whose halved central
//!   difference is below `f32`'s resolution), against the f64 reference
//!   (`reference::levoy_opacities`) within `CLASSIFY_ISOSURFACE_ABS`.
//! * [`gradient`] on the same fields against `reference::central_gradient`.
//! * Shading: there is no f64 reference shader, so the expected color is derived here in
//!   closed form, `C·min(1, k_a + k_d·|n·L|)` with `n` from the f64 gradient and `|n·L| = 1`
//!   where it vanishes, within `shade_abs(k_a, k_d)`.
//! * Transfer-function classification on extreme scalars and control points (segments wider
//!   than `f32::MAX`, subnormal segments) against `RefTransferFunction::eval`.
//!
//! Fixed by these cases (see the CHANGELOG): the classifier's `r·|∇f|` and `|∇f|²`
//! overflowed or underflowed, and a central difference of values near `±f32::MAX`
//! overflowed, so the opacity was `α_v` or 0 where it should have fallen off; the shader's
//! `|∇f|²` did the same (a steep or a faint gradient read as flat, `|n·L| = 1`);
//! `Light::new` rejected finite directions such as `[1e20, 0, 0]` and `[1e-30, 0, 0]`; and a
//! transfer-function segment wider than `f32::MAX` evaluated to NaN.
//!
//! Already covered elsewhere: the classifier, gradient and light factor against the f64
//! forms on typical ranges (`scalar_functions`), NaN/∞ `f32` scalars rejected by
//! `Volume::new` (`input`), transfer functions on typical ranges (`scalar_functions`).

use proptest::prelude::*;
use volsample::classify::{classify_isosurface, classify_transfer, gradient, Isosurface};
use volsample::shade::{shade_in_place, Light};
use volsample::voxel::ScalarVoxel;
use volsample::{ControlPoint, Error, StraightF32, TransferFunction, Volume};
use volsample_host::edge_cases::{
    any_edge, next_down, next_up, specials, unit_edge, MAX_SUBNORMAL, MIN_SUBNORMAL,
};
use volsample_host::reference::{
    central_gradient, levoy_opacities, shade_factor, RefControlPoint, RefIsosurface,
    RefScalarVolume, RefTransferFunction,
};
use volsample_host::tolerance::{self as tol, hard_cases as hc};

use crate::common::Worst;

const MAX: f32 = f32::MAX;

// ---------------------------------------------------------------------------------------------
// Input.

/// The documented domain of each parameter, written independently of the constructors.
fn check_prepass_value(x: f32) {
    let fin = x.is_finite();
    let iso_err = |ok: bool| (!ok).then_some(Error::InvalidClassifier);
    assert_eq!(
        Isosurface::new(x, 0.5, 1.0).err(),
        iso_err(fin),
        "f_v={x:e}"
    );
    assert_eq!(
        Isosurface::new(0.0, x, 1.0).err(),
        iso_err(fin && (0.0..=1.0).contains(&x)),
        "α_v={x:e}"
    );
    assert_eq!(
        Isosurface::new(0.0, 0.5, x).err(),
        iso_err(fin && x > 0.0),
        "r={x:e}"
    );
    // Directions: valid iff finite and not all zero; a valid one is normalised, which the
    // factor along it shows (`k_a = 0`, `k_d = 1`: `|n·L| = 1` exactly in exact arithmetic).
    for (dir, along) in [
        ([x, 0.0, 0.0], [1.0f32, 0.0, 0.0]),
        ([x, x, x], [1.0, 1.0, 1.0]),
        ([0.0, -x, 0.0], [0.0, -1.0, 0.0]),
    ] {
        let ok = fin && x != 0.0;
        let light = Light::new(dir, 0.0, 1.0);
        assert_eq!(
            light.err(),
            (!ok).then_some(Error::InvalidLight),
            "dir={dir:?}"
        );
        if let Ok(l) = light {
            let f = f64::from(l.factor(along));
            assert!(
                (f - 1.0).abs() <= tol::LIGHT_FACTOR_ABS,
                "dir={dir:?}: factor along it {f}"
            );
        }
    }
    // A direction with one bad component among good ones.
    assert_eq!(
        Light::new([0.5, x, -1.0], 0.0, 1.0).err(),
        (!fin).then_some(Error::InvalidLight),
        "dir=[0.5, {x:e}, -1]"
    );
    let coef_ok = fin && x >= 0.0;
    for (ka, kd) in [(x, 0.5), (0.5, x)] {
        assert_eq!(
            Light::new([0.0, 0.0, 1.0], ka, kd).err(),
            (!coef_ok).then_some(Error::InvalidLight),
            "k_a={ka:e} k_d={kd:e}"
        );
    }
    // The classifier's color: in [0, 1] (NaN is not), else VoxelOutOfRange at index 0.
    let vol_data = [1.0f32, 2.0];
    let vol = Volume::new(&vol_data, [2, 1, 1]).unwrap();
    let iso = Isosurface::new(1.5, 1.0, 1.0).unwrap();
    let mut out = [StraightF32::default(); 2];
    let color_ok = fin && (0.0..=1.0).contains(&x);
    assert_eq!(
        classify_isosurface(&vol, &iso, [0.5, x, 0.0], &mut out).err(),
        (!color_ok).then_some(Error::VoxelOutOfRange { index: 0 }),
        "color {x:e}"
    );
}

/// Output buffers one voxel short or long, in all three passes.
fn check_lengths() {
    let data = [0.0f32, 1.0, 2.0, 3.0, 4.0, 5.0];
    let vol = Volume::new(&data, [3, 2, 1]).unwrap();
    let iso = Isosurface::new(2.0, 1.0, 1.0).unwrap();
    let tf = TransferFunction::<2>::new(&[ControlPoint {
        s: 0.0,
        c: [1.0; 3],
        a: 1.0,
    }])
    .unwrap();
    for len in [0usize, 5, 7] {
        let want = Some(Error::LengthMismatch {
            expected: 6,
            actual: len,
        });
        let mut out = vec![StraightF32::default(); len];
        assert_eq!(
            classify_isosurface(&vol, &iso, [1.0; 3], &mut out).err(),
            want
        );
        assert_eq!(classify_transfer(&vol, &tf, &mut out).err(), want);
        assert_eq!(shade_in_place(&vol, &Light::UNLIT, &mut out).err(), want);
    }
}

/// Every special value in every pre-pass parameter, and wrong output lengths.
#[test]
fn pre_pass_inputs_at_every_special_value() {
    let mut w = Worst::new(
        "9 pre-pass input: 29 specials × Isosurface/Light/color; lengths",
        "Isosurface::new, Light::new, classify_*, shade_in_place",
        "mismatches",
    );
    for x in specials() {
        w.exact(|| format!("x={x:e}"), || check_prepass_value(x));
    }
    w.exact(|| "output lengths".to_string(), check_lengths);
    w.report();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The same around the edges and on arbitrary bit patterns.
    #[test]
    fn pre_pass_inputs_fuzzed(x in any_edge()) {
        let mut w = Worst::new(
            "9 pre-pass input: edge and arbitrary f32 (fuzzed)",
            "Isosurface::new, Light::new, classify_isosurface",
            "mismatches",
        );
        w.exact(|| format!("x={x:e}"), || check_prepass_value(x));
        w.report();
    }
}

// ---------------------------------------------------------------------------------------------
// Fields.

/// Small scalar fields that stress the gradient: zero gradients, the edges, extreme values.
fn fields() -> Vec<([usize; 3], Vec<f32>)> {
    let ramp = |dims: [usize; 3], h: f32| {
        let n = dims.iter().product::<usize>();
        (dims, (0..n).map(|i| i as f32 * h).collect::<Vec<_>>())
    };
    vec![
        // 1×1×1: no gradient at all.
        ([1, 1, 1], vec![0.0]),
        ([1, 1, 1], vec![MAX]),
        ([1, 1, 1], vec![MIN_SUBNORMAL]),
        // Flat: zero gradient everywhere.
        ([3, 3, 3], vec![7.5; 27]),
        ([2, 2, 2], vec![-MAX; 8]),
        // A step between flat regions: zero gradient two voxels away from it.
        ([6, 1, 1], vec![0.0, 0.0, 0.0, 10.0, 10.0, 10.0]),
        // Ramps along y only (1×N×1): the flat x and z axes; one-sided at both ends.
        ramp([1, 7, 1], 1.0),
        ramp([1, 7, 1], MIN_SUBNORMAL),
        ramp([1, 5, 1], 1e-30),
        ramp([1, 5, 1], 1e30),
        ramp([1, 5, 1], MAX / 4.0),
        ramp([3, 2, 2], 2.5),
        // Central differences that overflow, one-sided ones beyond f32::MAX.
        ([3, 1, 1], vec![-MAX, 0.0, MAX]),
        ([4, 1, 1], vec![MAX, -MAX, MAX, -MAX]),
        ([2, 2, 2], vec![MAX, -MAX, -MAX, MAX, -MAX, MAX, MAX, -MAX]),
        (
            [3, 3, 1],
            vec![MAX, 0.0, -MAX, next_down(MAX), 1.0, -1e38, 3e38, -2e38, 0.0],
        ),
        // Subnormal fields: a central difference of 2⁻¹⁴⁹ halves to 2⁻¹⁵⁰.
        ([3, 1, 1], vec![0.0, 0.0, MIN_SUBNORMAL]),
        (
            [3, 3, 1],
            vec![
                0.0,
                MIN_SUBNORMAL,
                0.0,
                MIN_SUBNORMAL,
                MAX_SUBNORMAL,
                0.0,
                -MIN_SUBNORMAL,
                0.0,
                f32::MIN_POSITIVE,
            ],
        ),
        // Huge and tiny together: a faint gradient along one axis beside a steep one.
        (
            [2, 2, 1],
            vec![0.0, MIN_SUBNORMAL, 1e30, 1e30 + MIN_SUBNORMAL],
        ),
        ([2, 2, 1], vec![1e-30, 2e-30, MAX, MAX]),
    ]
}

/// Classifier parameters at the ends of their domains; the isovalue also takes each value
/// of the field and one ulp around it.
fn iso_params(field: &[f32]) -> Vec<(f32, f32, f32)> {
    let mut fvs = vec![0.0f32, 0.5, -MAX, MAX, MIN_SUBNORMAL];
    for &f in field.iter().take(4) {
        fvs.extend([f, next_up(f), next_down(f)]);
    }
    fvs.retain(|f| f.is_finite());
    let mut out = Vec::new();
    for (i, &f_v) in fvs.iter().enumerate() {
        for (j, alpha_v) in [1.0f32, 0.5, MIN_SUBNORMAL].into_iter().enumerate() {
            for (k, r) in [MIN_SUBNORMAL, 1e-30, 0.5, 1.0, 3.0, 1e30, MAX]
                .into_iter()
                .enumerate()
            {
                // Every f_v with every r; the opacities cycle.
                if (i + k) % 3 == j {
                    out.push((f_v, alpha_v, r));
                }
            }
        }
    }
    out
}

fn to_ref<V: ScalarVoxel>(dims: [usize; 3], data: &[V]) -> RefScalarVolume {
    RefScalarVolume::new(dims, data.iter().map(|v| v.scalar::<f64>()).collect(), 1.0)
}

/// Levoy's classifier over one field: `α` against the f64 reference, the color untouched.
fn classify_case<V: ScalarVoxel>(
    w: &mut Worst,
    dims: [usize; 3],
    data: &[V],
    (f_v, alpha_v, r): (f32, f32, f32),
) {
    let vol = Volume::new(data, dims).unwrap();
    let iso = Isosurface::new(f_v, alpha_v, r).unwrap();
    let color = [1.0, 0.25, 0.0];
    let mut out = vec![StraightF32::default(); data.len()];
    classify_isosurface(&vol, &iso, color, &mut out).unwrap();
    let want = levoy_opacities(
        &to_ref(dims, data),
        RefIsosurface {
            f_v: f64::from(f_v),
            alpha_v: f64::from(alpha_v),
            r: f64::from(r),
        },
    );
    for (i, (got, want)) in out.iter().zip(want).enumerate() {
        assert_eq!(got.c, color);
        assert!(
            got.a.is_finite() && (0.0..=1.0).contains(&got.a),
            "voxel {i}: {got:?}"
        );
        w.check(
            (f64::from(got.a) - want).abs(),
            hc::CLASSIFY_ISOSURFACE_ABS,
            || {
                format!(
                    "{dims:?} voxel {i} f_v={f_v:e} α_v={alpha_v:e} r={r:e}: α={} want {want}",
                    got.a
                )
            },
        );
    }
}

/// Levoy's classifier on zero gradients, at the edges and on extreme fields, every
/// classifier edge; `u8` and `u16` fields at their range ends too.
#[test]
fn levoy_classifier_at_the_edges() {
    let mut w = Worst::new(
        "9 Levoy α: ∇f=0, 1×1×1, 1×N×1, edges, ±MAX, subnormal fields",
        "classify_isosurface (gradient, ‖∇f‖, opacity)",
        "abs",
    );
    for (dims, field) in fields() {
        for p in iso_params(&field) {
            classify_case(&mut w, dims, &field, p);
        }
    }
    let bytes = [0u8, 255, 255, 0, 1, 254, 128, 0];
    let words = [0u16, 65535, 65535, 0, 1, 65534, 32768, 0];
    for p in [
        (255.0, 1.0, 1.0),
        (0.5, 0.5, 0.25),
        (65535.0, 1.0, 1e-30),
        (128.0, 1.0, MAX),
    ] {
        classify_case(&mut w, [2, 2, 2], &bytes, p);
        classify_case(&mut w, [8, 1, 1], &words, p);
    }
    w.report();
}

/// A finite scalar concentrated on the edges: specials and arbitrary bit patterns that are
/// finite, or small integers scaled by a power of ten (so that neighbours share a scale).
fn finite_scalar() -> impl Strategy<Value = f32> {
    prop_oneof![
        2 => any_edge().prop_filter("finite", |x| x.is_finite()),
        1 => (-4i32..=4, -40i32..=37).prop_map(|(k, e)| (f64::from(k) * 10f64.powi(e)) as f32),
    ]
}

/// A valid thickness `r > 0`: positive finite edges and arbitrary patterns.
fn thickness() -> impl Strategy<Value = f32> {
    any_edge()
        .prop_map(f32::abs)
        .prop_filter("positive finite", |x| x.is_finite() && *x > 0.0)
}

prop_compose! {
    /// A small field of edge scalars.
    fn field()(dims in [1usize..=4, 1usize..=4, 1usize..=3])
        (data in prop::collection::vec(finite_scalar(), dims[0] * dims[1] * dims[2]), dims in Just(dims))
        -> ([usize; 3], Vec<f32>) {
        (dims, data)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Levoy's classifier on fuzzed edge fields and parameters (the isovalue often one of the
    /// field's values, where the opacity is `α_v` whatever the gradient).
    #[test]
    fn levoy_classifier_fuzzed((dims, data) in field(), pick in 0usize..64, f in finite_scalar(), alpha_v in unit_edge(), r in thickness()) {
        let f_v = if pick < 32 { data[pick % data.len()] } else { f };
        let mut w = Worst::new(
            "9 Levoy α on fuzzed edge fields",
            "classify_isosurface (gradient, ‖∇f‖, opacity)",
            "abs",
        );
        classify_case(&mut w, dims, &data, (f_v, alpha_v, r));
        w.report();
    }
}

/// The public [`gradient`] on the same fields: each component one rounding of the exact
/// difference (a subnormal result within `2⁻¹⁵⁰`), `±∞` only where the exact one-sided
/// difference is beyond `f32`.
#[test]
fn gradient_at_the_edges() {
    let mut w = Worst::new(
        "9 ∇f components: 1×1×1, flat, edges, ±MAX, subnormal fields",
        "classify::gradient",
        "×budget",
    );
    for (dims, field) in fields() {
        let r = to_ref(dims, &field);
        let vol = Volume::new(&field, dims).unwrap();
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let got = gradient(&vol, x, y, z);
                    let want = central_gradient(dims, &r.scalars, [x, y, z]);
                    for k in 0..3 {
                        let at = || {
                            format!("{dims:?} ({x},{y},{z}) axis {k}: {} vs {}", got[k], want[k])
                        };
                        if (want[k] as f32).is_infinite() {
                            // Beyond f32: the kernel's value is the overflowed ±∞.
                            assert_eq!(got[k], want[k] as f32, "{}", at());
                            continue;
                        }
                        let budget = hc::GRADIENT_EDGE_REL * want[k].abs() + hc::SUBNORMAL_FLOOR;
                        w.check((f64::from(got[k]) - want[k]).abs() / budget, 1.0, at);
                    }
                }
            }
        }
    }
    w.report();
}

// ---------------------------------------------------------------------------------------------
// Shading.

fn lights() -> Vec<([f32; 3], f32, f32)> {
    let dirs = [
        [0.0f32, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 2.0, -3.0],
        [MIN_SUBNORMAL, 0.0, 0.0],
        [MAX, MAX, -MAX],
        [1e-30, 1e30, 0.0],
        [MAX_SUBNORMAL, -MIN_SUBNORMAL, MIN_SUBNORMAL],
    ];
    let coefs = [
        (0.0f32, 1.0f32),
        (0.25, 0.75),
        (0.0, 2.0),
        (1.0, 0.0),
        (MIN_SUBNORMAL, 0.5),
    ];
    let mut out = Vec::new();
    for (i, d) in dirs.into_iter().enumerate() {
        for (j, (ka, kd)) in coefs.into_iter().enumerate() {
            if (i + j) % 2 == 0 || j == 0 {
                out.push((d, ka, kd));
            }
        }
    }
    out
}

/// `shade_in_place` over one field with one light: each channel against the closed form,
/// the opacity untouched.
fn shade_case(w: &mut Worst, dims: [usize; 3], field: &[f32], (dir, ka, kd): ([f32; 3], f32, f32)) {
    let vol = Volume::new(field, dims).unwrap();
    let light = Light::new(dir, ka, kd).unwrap();
    let colors = [[1.0f32, 0.5, 0.0], [next_down(1.0), MIN_SUBNORMAL, 0.3]];
    let mut rgba: Vec<StraightF32> = (0..field.len())
        .map(|i| StraightF32 {
            c: colors[i % 2],
            a: 0.5,
        })
        .collect();
    shade_in_place(&vol, &light, &mut rgba).unwrap();
    let r = to_ref(dims, field);
    let bound = hc::shade_abs(f64::from(ka), f64::from(kd));
    for (i, got) in rgba.iter().enumerate() {
        assert_eq!(got.a, 0.5);
        let p = [
            i % dims[0],
            (i / dims[0]) % dims[1],
            i / (dims[0] * dims[1]),
        ];
        let k = shade_factor(central_gradient(dims, &r.scalars, p), dir, ka, kd);
        for (ch, (&c, &c0)) in got.c.iter().zip(colors[i % 2].iter()).enumerate() {
            assert!(c.is_finite() && (0.0..=1.0).contains(&c));
            let want = (f64::from(c0) * k).clamp(0.0, 1.0);
            w.check((f64::from(c) - want).abs(), bound, || {
                format!("{dims:?} {p:?} ch{ch} dir={dir:?} k_a={ka:e} k_d={kd:e}: {c} vs {want}")
            });
        }
    }
}

/// Shading on zero gradients, at the edges and on extreme fields, lights with subnormal and
/// `f32::MAX` directions.
#[test]
fn shading_at_the_edges() {
    let mut w = Worst::new(
        "9 shaded C: ∇f=0, 1×1×1, 1×N×1, edges, ±MAX, subnormal fields; extreme L",
        "shade_in_place (gradient, Light::factor)",
        "abs",
    );
    for (dims, field) in fields() {
        for l in lights() {
            shade_case(&mut w, dims, &field, l);
        }
    }
    w.report();
}

/// [`Light::factor`] on gradients given directly, subnormal to `f32::MAX` (`|g|²` out of
/// `f32` range either way) and non-finite (taken as vanishing).
#[test]
fn light_factor_at_extreme_gradients() {
    let mut w = Worst::new(
        "9 Light::factor, ‖g‖ from 2⁻¹⁴⁹ to 3·f32::MAX, ∞/NaN g",
        "Light::factor",
        "abs",
    );
    let gs = [
        [MAX, 0.0, 0.0],
        [MAX, MAX, MAX],
        [0.0, -MAX, 1.0],
        [MIN_SUBNORMAL, 0.0, 0.0],
        [MIN_SUBNORMAL, MIN_SUBNORMAL, 0.0],
        [1e20, 1e20, 0.0],
        [1e-25, 0.0, -1e-25],
        [MAX_SUBNORMAL, 1e-40, MIN_SUBNORMAL],
        [1e30, 1e-30, 0.0],
    ];
    for (dir, ka, kd) in lights() {
        let light = Light::new(dir, ka, kd).unwrap();
        let bound = tol::LIGHT_FACTOR_ABS * f64::from(kd).max(1.0);
        for g in gs {
            let got = f64::from(light.factor(g));
            let want = shade_factor(g.map(f64::from), dir, ka, kd);
            w.check((got - want).abs(), bound, || {
                format!("g={g:?} dir={dir:?} k_a={ka:e} k_d={kd:e}: {got} vs {want}")
            });
        }
        // Non-finite gradients count as vanishing: |n·L| = 1.
        for g in [[f32::INFINITY, 0.0, 0.0], [f32::NAN, 1.0, 0.0]] {
            let want = (f64::from(ka) + f64::from(kd)).min(1.0);
            let got = f64::from(light.factor(g));
            w.check((got - want).abs(), bound, || format!("g={g:?}"));
        }
    }
    w.report();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Shading of fuzzed edge fields with fuzzed lights.
    #[test]
    fn shading_fuzzed(
        (dims, data) in field(),
        dir in [finite_scalar(), finite_scalar(), finite_scalar()],
        ka in 0.0f32..=1.0,
        kd in prop_oneof![Just(0.0f32), Just(1.0f32), 0.0f32..=2.0],
    ) {
        prop_assume!(dir.iter().any(|&d| d != 0.0));
        let mut w = Worst::new(
            "9 shaded C on fuzzed edge fields and lights",
            "shade_in_place (gradient, Light::factor)",
            "abs",
        );
        shade_case(&mut w, dims, &data, (dir, ka, kd));
        w.report();
    }
}

// ---------------------------------------------------------------------------------------------
// Transfer-function classification.

/// Transfer functions whose segments are wider than `f32::MAX`, subnormal, or mixed.
fn transfer_functions() -> Vec<Vec<ControlPoint>> {
    let cp = |s: f32, c: f32, a: f32| ControlPoint {
        s,
        c: [c, 1.0 - c, 0.5],
        a,
    };
    vec![
        vec![cp(-MAX, 0.0, 0.0), cp(MAX, 1.0, 1.0)],
        vec![cp(-MAX, 1.0, 1.0), cp(0.0, 0.0, 0.0), cp(MAX, 1.0, 0.5)],
        vec![cp(0.0, 0.0, 0.0), cp(MIN_SUBNORMAL, 1.0, 1.0)],
        vec![
            cp(-1e30, 0.2, 0.1),
            cp(-1e-30, 0.9, 0.0),
            cp(1e-30, 0.1, 1.0),
            cp(1e30, 0.5, 0.5),
        ],
        vec![cp(next_down(MAX), 0.0, 0.0), cp(MAX, 1.0, 1.0)],
        vec![cp(0.0, 0.7, 0.3)],
    ]
}

fn to_ref_tf(points: &[ControlPoint]) -> RefTransferFunction {
    RefTransferFunction::new(
        points
            .iter()
            .map(|p| RefControlPoint::new(f64::from(p.s), p.c.map(f64::from), f64::from(p.a)))
            .collect(),
    )
}

/// The bound of `TransferFunction::eval` at `s`: `TF_EVAL_BASE + L·TF_EVAL_PER_SLOPE·m`,
/// `L` the slope of the segment holding `s` and `m` the largest of `|s|` and its ends.
fn tf_bound(points: &[ControlPoint], s: f32) -> f64 {
    let seg = points.windows(2).find(|p| p[0].s <= s && s < p[1].s);
    match seg {
        None => tol::TF_EVAL_BASE,
        Some(p) => {
            let width = f64::from(p[1].s) - f64::from(p[0].s);
            let dv = p[1]
                .c
                .iter()
                .zip(p[0].c.iter())
                .map(|(a, b)| f64::from((a - b).abs()))
                .fold(f64::from((p[1].a - p[0].a).abs()), f64::max);
            let m = f64::from(s.abs().max(p[0].s.abs()).max(p[1].s.abs()));
            tol::TF_EVAL_BASE + dv / width * tol::TF_EVAL_PER_SLOPE * m
        }
    }
}

fn transfer_case(w: &mut Worst, points: &[ControlPoint], scalars: &[f32]) {
    let tf = TransferFunction::<4>::new(points).unwrap();
    let rtf = to_ref_tf(points);
    let vol = Volume::new(scalars, [scalars.len(), 1, 1]).unwrap();
    let mut out = vec![StraightF32::default(); scalars.len()];
    classify_transfer(&vol, &tf, &mut out).unwrap();
    for (&s, got) in scalars.iter().zip(&out) {
        let want = rtf.eval(f64::from(s));
        let vals = got.c.iter().chain(std::iter::once(&got.a));
        assert!(
            vals.clone()
                .all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
            "s={s:e}: {got:?}"
        );
        let err = (0..3)
            .map(|k| (f64::from(got.c[k]) - want.color[k]).abs())
            .fold((f64::from(got.a) - want.alpha).abs(), f64::max);
        w.check(err, tf_bound(points, s), || {
            format!(
                "tf {:?} s={s:e}: {got:?}",
                points.iter().map(|p| p.s).collect::<Vec<_>>()
            )
        });
    }
}

/// Transfer-function classification of every finite special scalar (and the control points
/// and their neighbours) through segments wider than `f32::MAX`, subnormal segments and
/// mixed scales.
#[test]
fn transfer_classification_at_the_edges() {
    let mut w = Worst::new(
        "9 TF classification: segments > f32::MAX, subnormal, ±MAX scalars",
        "classify_transfer (TransferFunction::eval)",
        "abs",
    );
    for points in transfer_functions() {
        let mut scalars: Vec<f32> = specials().into_iter().filter(|x| x.is_finite()).collect();
        for p in &points {
            scalars.extend([p.s, next_up(p.s), next_down(p.s)]);
        }
        scalars.extend([1e38f32, -1e38, 0.25 * MAX, -0.75 * MAX]);
        scalars.retain(|x| x.is_finite());
        transfer_case(&mut w, &points, &scalars);
    }
    w.report();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Fuzzed edge control points and scalars.
    #[test]
    fn transfer_classification_fuzzed(
        mut ss in prop::collection::vec(finite_scalar(), 1..=4),
        vals in prop::collection::vec((unit_edge(), unit_edge()), 4),
        scalars in prop::collection::vec(finite_scalar(), 1..=16),
    ) {
        ss.sort_by(f32::total_cmp);
        ss.dedup_by(|a, b| a == b);
        let points: Vec<ControlPoint> = ss
            .iter()
            .zip(vals)
            .map(|(&s, (c, a))| ControlPoint { s, c: [c, 1.0 - c, a], a })
            .collect();
        let mut w = Worst::new(
            "9 TF classification on fuzzed edge points and scalars",
            "classify_transfer (TransferFunction::eval)",
            "abs",
        );
        transfer_case(&mut w, &points, &scalars);
        w.report();
    }
}
