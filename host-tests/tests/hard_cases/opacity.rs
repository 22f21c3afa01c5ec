//! Group 1, opacity: `α → 0` (the ratio `α_d/α` of the correction, un-premultiplying,
//! `C^τ·α/τ`), `α = 1` (`τ = ∞`, `ln 0`), and `α` one LSB from 0 and from 1 in `u8` storage.
//!
//! Already covered elsewhere and not repeated: the correction against the textbook formula
//! for `α ∈ [0, 1]`, `d/d′ ∈ [10⁻³, 10³]` (`float_vs_reference::correction_matches_reference`),
//! opaque material at `d/d′ ∈ [10⁻³, 1]` (`…::opaque_material_stays_exactly_opaque`), `φ`
//! and `integrate_step` on typical ranges (`scalar_functions`), every U8.8 opacity through
//! the integer correction at `d/d′ ∈ [10⁻³, 10³]` (`int_exhaustive`).

use proptest::prelude::*;
use volsample::opacity::correct;
use volsample::{
    ExtinctionF32, FrontToBack, OpacityWeighted, RayMarcher, Sample, Separate, Step, StraightF32,
    StraightU8, Trilinear, Volume,
};
use volsample_host::edge_cases::{self as edge, alpha_edges, ratio_edge, tiny, unit_edge};
use volsample_host::float_checks::{FilterKind, FloatCase, ModeKind};
use volsample_host::int_model::correction::exact_alpha;
use volsample_host::reference::RefAssoc;
use volsample_host::strategies::case_and_pos;
use volsample_host::tolerance::{self as tol, hard_cases as hc, EPS32};

use crate::common::{abs_err, assert_valid, rel_excess, Worst};

/// Ratios `d/d′` from `10⁻⁶` to `10⁶`, and the extremes `Corrected` accepts.
const RATIOS: [f32; 9] = [1e-6, 1e-3, 0.5, 1.0, 2.0, 1e3, 1e6, 1e30, 1e38];

/// The exact correction of an `f32` sample in `f64` (stable forms).
fn exact_correct(s: Sample, r: f32) -> RefAssoc {
    let (a, r) = (f64::from(s.a), f64::from(r));
    if a == 0.0 {
        return RefAssoc::TRANSPARENT;
    }
    let a_d = exact_alpha(a, r);
    RefAssoc::new(s.c.map(|c| f64::from(c) * (a_d / a)), a_d)
}

/// The exact correction of an `f64` sample (stable forms).
fn exact_correct_f64(s: RefAssoc, r: f64) -> RefAssoc {
    if s.alpha == 0.0 {
        return RefAssoc::TRANSPARENT;
    }
    let a_d = exact_alpha(s.alpha, r);
    RefAssoc::new(s.color.map(|c| c * (a_d / s.alpha)), a_d)
}

fn correction_case(w: &mut Worst, a: f32, straight: f32, r: f32) {
    let s = Sample::clamped([straight * a, 0.0, a], a);
    let got = correct(s, r);
    assert_valid(got, || format!("a={a:e} r={r:e}"));
    let want = exact_correct(s, r);
    let e = rel_excess(got, want, hc::CORRECTION_REL, 2.0 * hc::SUBNORMAL_FLOOR);
    w.check(e, 1.0, || format!("α={a:e} C={straight} r={r:e}"));
}

/// `α → 0` and `α → 1` through `correct`: `α_d` and `C̃_d` relative to their exact values
/// (`α_d/α → d/d′`), for every edge opacity and ratios `10⁻⁶ … 10³⁸`. Before the fix the
/// color of a dense sample vanished once `(d/d′)·(−ln(1 − α))` overflowed `f32` (`d′ → 0`).
#[test]
fn correction_keeps_relative_accuracy_at_the_ends() {
    let mut w = Worst::new(
        "1 correction α→0, α→1, d/d′ 1e-6…1e38 (budget ratio)",
        "opacity::correct",
        "×budget",
    );
    for a in alpha_edges() {
        for r in RATIOS {
            for c in [1.0, 0.5, 1.0 / 3.0] {
                correction_case(&mut w, a, c, r);
            }
        }
    }
    w.report();
}

proptest! {
    /// The same around the edges, fuzzed.
    #[test]
    fn correction_relative_accuracy_fuzzed(a in prop_oneof![tiny(), unit_edge()], r in ratio_edge(), c in 0.0f32..=1.0) {
        let mut w = Worst::new("1 correction fuzzed", "opacity::correct", "×budget");
        correction_case(&mut w, a, c, r);
        w.report();
    }
}

/// The straight color of a faint sample (`C̃/α`, [`Sample::straight_color`]): one rounding
/// of the exact quotient of the stored values, for every edge opacity.
#[test]
fn unpremultiplying_faint_samples() {
    let mut w = Worst::new("1 straight_color C̃/α, α→0", "Sample::straight_color", "rel");
    for a in alpha_edges().into_iter().filter(|&a| a > 0.0) {
        for c in [1.0f32, 0.75, 1.0 / 3.0, 1e-3] {
            let s = Sample::clamped([c * a, 0.0, a], a);
            let got = s.straight_color();
            let want = (f64::from(s.c[0]) / f64::from(s.a)).min(1.0);
            let e = (f64::from(got[0]) - want).abs() / want.max(f64::MIN_POSITIVE);
            w.check(e, EPS32 / 2.0, || format!("α={a:e} C={c}"));
            assert_eq!(got[2], 1.0, "α={a:e}: C̃ = α must give straight 1");
        }
    }
    w.report();
}

/// The scaled bound of a faint case: the modes' absolute bounds are for values in `[0, 1]`
/// and scale with the largest value (`tolerance::INTERP_PER_TAP`), plus the subnormal floor
/// once per operation with a subnormal result (a product and a sum per tap, four more),
/// magnified by the correction's gain or the step `d/d′`.
fn faint_bound(mode: ModeKind, filter: FilterKind, unit: &FloatCase, scale: f64, r: f64) -> f64 {
    let base = tol::sample_bound(mode, filter, unit, unit.d_ref);
    let corr = if mode == ModeKind::ExtinctionWeighted || r == 1.0 {
        0.0
    } else {
        hc::CORRECTION_REL
    };
    // Correction multiplies a faint sample by at most `r` (`α_d ≤ r·α`) and is
    // well conditioned there (slope `r(1 − α)^(r−1) ≤ r`).
    (base + corr) * scale * r.max(1.0)
        + hc::SUBNORMAL_FLOOR * (2.0 * filter.taps() as f64 + 4.0) * r.max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Every mode × filter on a volume whose opacities are all scaled down to `s ≤ 10⁻⁵`
    /// (down to subnormal): the error scales with `s` (relative accuracy is kept), at
    /// `d = d′` and with correction to `d = 10^±3·d′`.
    #[test]
    fn faint_volumes_keep_relative_accuracy((unit, pos) in case_and_pos(), s in tiny(), r in prop_oneof![Just(1.0f32), Just(1e-3f32), Just(1e3f32)]) {
        let mut case = unit.clone();
        for v in &mut case.voxels { v.a *= s; }
        for p in &mut case.tf { p.a *= s; }
        // Extinction: τ = −ln(1 − α)/d′ ≈ α/d′; its sample scales with s·d/d′.
        let d = case.d_ref * r;
        let mut w = Worst::new(
            "1 faint volumes α·s, s ≤ 1e-5 (fuzzed), d/d′=1,1e±3",
            "sample, 5 modes × 4 filters + correct",
            "abs",
        );
        for mode in ModeKind::ALL {
            for filter in FilterKind::ALL {
                let got = case.core_sample(mode, filter, pos, d);
                prop_assert!(got.is_valid(), "{mode:?} {filter:?} {got:?}");
                // The reference corrects with the textbook `1 − (1 − α)^r`, which loses faint
                // opacities (`1 − α` rounds to 1 below `α ≈ 10⁻¹⁶`): correct its uncorrected
                // sample with the stable form instead.
                let want = if mode == ModeKind::ExtinctionWeighted || r == 1.0 {
                    case.reference_sample(mode, filter, pos, d)
                } else {
                    let u = case.reference_sample(mode, filter, pos, case.d_ref);
                    exact_correct_f64(u, f64::from(r))
                };
                let bound = faint_bound(mode, filter, &unit, f64::from(s), f64::from(r));
                let err = abs_err(got, want);
                w.check(err, bound, || format!("{mode:?} {filter:?} s={s:e} r={r}: {got:?} vs {want:?}"));
            }
        }
        w.report();
    }
}

/// `α = 1` and its neighbours in extinction form: `τ = −ln(1 − α)/d′` is capped at
/// `MAX_OPTICAL_DEPTH/d′` and at `MAX_TAU`, for every `d′` down to the smallest subnormal
/// and up to `f32::MAX`; the voxel is finite, valid, and within 2 ulp of the capped value.
#[test]
fn opaque_voxels_to_extinction() {
    use volsample::voxel::{MAX_OPTICAL_DEPTH, MAX_TAU};
    let mut w = Worst::new(
        "1 ExtinctionF32::from_straight α→1, d′ edges",
        "ExtinctionF32::from_straight",
        "rel",
    );
    let d_refs = [
        edge::MIN_SUBNORMAL,
        f32::MIN_POSITIVE,
        1e-30,
        1e-6,
        1.0,
        1e6,
        1e30,
        f32::MAX,
    ];
    for a in alpha_edges() {
        for d_ref in d_refs {
            let e = ExtinctionF32::from_straight(
                StraightF32 {
                    c: [1.0, 0.5, 0.0],
                    a,
                },
                d_ref,
            );
            assert!(
                Volume::new(&[e], [1, 1, 1]).is_ok(),
                "α={a:e} d′={d_ref:e}: {e:?}"
            );
            let depth = (-(-f64::from(a)).ln_1p()).min(f64::from(MAX_OPTICAL_DEPTH));
            let want = (depth / f64::from(d_ref)).min(f64::from(MAX_TAU));
            let got = f64::from(e.tau);
            let floor = hc::SUBNORMAL_FLOOR;
            let err = (got - want).abs() / (want * tol::FROM_STRAIGHT_TAU_REL + floor);
            w.check(err, 1.0, || {
                format!("α={a:e} d′={d_ref:e} τ={got:e} want {want:e}")
            });
            assert!(e.c_tau[0] <= e.tau && e.c_tau[2] == 0.0);
        }
    }
    w.report();
}

/// All-opaque volumes stay exactly opaque with their exact color in every opacity-based mode
/// and filter at `d/d′ = 10^±6` (extends `opaque_material_stays_exactly_opaque`), and the
/// capped extinction gives `α = 1 − e^(−64·d/d′)` as documented.
#[test]
fn opaque_volumes_at_extreme_ratios() {
    let mut w = Worst::new(
        "1 all-opaque, d/d′=1e±6, every mode×filter",
        "RayMarcher::sample, 5 modes × 4 filters + correct",
        "abs",
    );
    for r in [1e-6f32, 1e-3, 1.0, 1e3, 1e6] {
        let case = FloatCase {
            dims: [3, 2, 2],
            voxels: vec![
                StraightF32 {
                    c: [1.0, 0.25, 0.0],
                    a: 1.0
                };
                12
            ],
            scalars: (0..12).map(|i| i as f32 * 20.0).collect(),
            tf: vec![
                volsample::ControlPoint {
                    s: 0.0,
                    c: [1.0, 0.25, 0.0],
                    a: 1.0,
                },
                volsample::ControlPoint {
                    s: 300.0,
                    c: [1.0, 0.25, 0.0],
                    a: 1.0,
                },
            ],
            d_ref: 1.0,
        };
        for pos in [
            [0.0, 0.0, 0.0],
            [0.5, 0.5, 0.5],
            [2.0, 1.0, 1.0],
            [1.3, 0.7, 0.2],
        ] {
            for mode in ModeKind::ALL {
                for filter in FilterKind::ALL {
                    let got = case.core_sample(mode, filter, pos, r);
                    assert_valid(got, || format!("{mode:?} {filter:?} r={r}"));
                    if mode != ModeKind::ExtinctionWeighted {
                        assert_eq!(got.a, 1.0, "{mode:?} {filter:?} r={r}");
                        assert_eq!(got.c, [1.0, 0.25, 0.0], "{mode:?} {filter:?} r={r}");
                    } else {
                        let want = case.reference_sample(mode, filter, pos, r);
                        let a = -(-64.0 * f64::from(r)).exp_m1();
                        assert!((want.alpha - a).abs() < 1e-15);
                        let bound = tol::sample_bound(mode, filter, &case, r);
                        w.check(abs_err(got, want), bound, || format!("{filter:?} r={r}"));
                    }
                }
            }
        }
    }
    w.report();
}

/// `α` one LSB from 0 (`1/255`) and from 1 (`254/255`) in `u8` storage, read by the float
/// kernels, corrected to `d/d′ = 10^±6`: uniform volumes, where the correction is well
/// conditioned, so the bound does not grow with the ratio.
#[test]
fn one_lsb_from_zero_and_one_float() {
    let mut w = Worst::new(
        "1 u8 α=1/255, 254/255, d/d′ 1e-6…1e6 (OW, Sep)",
        "RayMarcher::sample OW/Sep on StraightU8",
        "abs",
    );
    for a in [1u8, 2, 254, 253] {
        let v = [StraightU8([255, 128, 1, a]); 8];
        let vol = Volume::new(&v, [2, 2, 2]).unwrap();
        let af = f64::from(a) / 255.0;
        let straight = [255.0, 128.0, 1.0].map(|c: f64| c / 255.0);
        for r in [1e-6f32, 1e-3, 0.5, 2.0, 1e3, 1e6] {
            let step = Step::new(r).unwrap();
            let ow = RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                step,
            )
            .unwrap();
            let sep =
                RayMarcher::new(vol, Separate, Trilinear::new(), FrontToBack::new(), step).unwrap();
            let a_d = exact_alpha(af, f64::from(r));
            let want = RefAssoc::new(straight.map(|c| c * a_d), a_d);
            for pos in [[0.5f32, 0.5, 0.5], [0.0, 1.0, 0.25]] {
                for got in [ow.sample(pos), sep.sample(pos)] {
                    assert_valid(got, || format!("α={a} r={r}"));
                    // Interpolation of a constant (exact weights), then the correction.
                    let bound = hc::CORRECTION_REL + 10.0 * EPS32;
                    w.check(abs_err(got, want), bound, || format!("α={a}/255 r={r:e}"));
                }
            }
        }
    }
    w.report();
}
