//! The float kernels against the independent f64 reference, and the float properties of
//! the proof obligations of the kernels, as proptest properties. Every bound is a named constant
//! of `volsample_host::tolerance`.

use proptest::prelude::*;
use volsample::composite::{back_to_front, front_to_back};
use volsample::opacity::correct;
use volsample::Sample;
use volsample_host::float_checks::{max_abs_diff, FilterKind, ModeKind};
use volsample_host::reference::{self, RefAssoc};
use volsample_host::strategies::{case_and_pos, sample};
use volsample_host::tolerance as tol;

fn assoc(c: [f32; 3], a: f32) -> RefAssoc {
    RefAssoc::new(c.map(f64::from), f64::from(a))
}

proptest! {
    /// f32 against f64, every mode × filter, at `d = d′` (no opacity correction).
    #[test]
    fn sample_matches_reference_at_reference_distance((case, pos) in case_and_pos()) {
        for mode in ModeKind::ALL {
            for filter in FilterKind::ALL {
                let core = case.core_sample(mode, filter, pos, case.d_ref);
                let r = case.reference_sample(mode, filter, pos, case.d_ref);
                let bound = tol::sample_bound(mode, filter, &case, case.d_ref);
                let err = max_abs_diff(core, r);
                prop_assert!(err <= bound, "{mode:?} {filter:?}: error {err:e} > bound {bound:e}\ncore {core:?}\nref {r:?}");
            }
        }
    }

    /// Extinction-weighted sampling at any step (the step enters the integral; no correction).
    #[test]
    fn extinction_matches_reference_at_any_step(
        (case, pos) in case_and_pos(),
        d in prop_oneof![1e-3f32..0.1, 0.1f32..8.0],
    ) {
        for filter in FilterKind::ALL {
            let core = case.core_sample(ModeKind::ExtinctionWeighted, filter, pos, d);
            let r = case.reference_sample(ModeKind::ExtinctionWeighted, filter, pos, d);
            let bound = tol::sample_bound(ModeKind::ExtinctionWeighted, filter, &case, d);
            let err = max_abs_diff(core, r);
            prop_assert!(err <= bound, "{filter:?} d={d}: error {err:e} > {bound:e}");
        }
    }

    /// Opacity correction against the textbook formula, on identical inputs.
    #[test]
    fn correction_matches_reference(s in sample(), log_r in -3.0f64..3.0) {
        let r = 10f64.powf(log_r) as f32;
        let core = correct(s, r);
        let want = reference::opacity_correct(assoc(s.c, s.a), f64::from(r), 1.0);
        let err = max_abs_diff(core, want);
        let bound = tol::CORRECTION_ABS * f64::from(r.max(1.0));
        prop_assert!(err <= bound, "r={r} s={s:?}: error {err:e} > {bound:e}");
        prop_assert!(core.is_valid());
    }

    /// Whole samples with correction (`d ≠ d′`), opacities kept below 0.9 where
    /// `α ↦ 1 − (1 − α)^r` is well conditioned (its slope `r(1 − α)^(r−1)` is at most
    /// `r·10^(1−r)`); near `α = 1` the conditioning, not the kernel, limits any float result.
    #[test]
    fn corrected_sample_matches_reference(
        (mut case, pos) in case_and_pos(),
        ratio in 0.1f32..4.0,
    ) {
        for v in &mut case.voxels { v.a *= 0.9; }
        for p in &mut case.tf { p.a *= 0.9; }
        let d = case.d_ref * ratio;
        for mode in [ModeKind::Separate, ModeKind::OpacityWeighted, ModeKind::Preweighted, ModeKind::PostClassified] {
            for filter in FilterKind::ALL {
                let core = case.core_sample(mode, filter, pos, d);
                let r = case.reference_sample(mode, filter, pos, d);
                let slope = f64::from(ratio) * 10f64.powf(f64::from(1.0 - ratio).max(0.0));
                let bound = tol::sample_bound(mode, filter, &case, case.d_ref) * slope.max(1.0) * 2.0
                    + tol::CORRECTION_ABS * f64::from(ratio.max(1.0));
                let err = max_abs_diff(core, r);
                prop_assert!(err <= bound, "{mode:?} {filter:?} r={ratio}: error {err:e} > {bound:e}");
            }
        }
    }

    /// Every sample of every mode and filter is a valid associated color, at any step.
    #[test]
    fn samples_are_valid_associated_colors(
        (case, pos) in case_and_pos(),
        d in prop_oneof![Just(1.0f32), 1e-4f32..1e-2, 1e-2f32..100.0],
    ) {
        for mode in ModeKind::ALL {
            for filter in FilterKind::ALL {
                let s = case.core_sample(mode, filter, pos, d);
                prop_assert!(s.is_valid(), "{mode:?} {filter:?} d={d}: {s:?}");
            }
        }
    }

    /// The two trilinear evaluation orders agree, each being within its bound of the exact
    /// value (the bound scales with the largest stored value, e.g. `τ_max` for extinction).
    #[test]
    fn trilinear_orders_agree((case, pos) in case_and_pos()) {
        for mode in ModeKind::ALL {
            let a = case.core_sample(mode, FilterKind::TrilinearTree, pos, case.d_ref);
            let b = case.core_sample(mode, FilterKind::TrilinearSum, pos, case.d_ref);
            let err = max_abs_diff(a, assoc(b.c, b.a));
            let bound = 2.0 * tol::sample_bound(mode, FilterKind::TrilinearSum, &case, case.d_ref);
            prop_assert!(err <= bound, "{mode:?}: {err:e} > {bound:e}");
        }
    }

    /// `Preweighted` on float associated voxels equals `OpacityWeighted` on the straight ones.
    #[test]
    fn preweighted_equals_opacity_weighted_in_float((case, pos) in case_and_pos()) {
        for filter in FilterKind::ALL {
            let a = case.core_sample(ModeKind::Preweighted, filter, pos, case.d_ref);
            let b = case.core_sample(ModeKind::OpacityWeighted, filter, pos, case.d_ref);
            let err = max_abs_diff(a, assoc(b.c, b.a));
            prop_assert!(err <= tol::PREWEIGHTED_VS_OPACITY_WEIGHTED, "{filter:?}: {err:e}");
        }
    }

    /// Front to back equals back to front, and both match the reference compositor.
    #[test]
    fn front_to_back_equals_back_to_front(samples in prop::collection::vec(sample(), 0..64)) {
        let ftb = samples.iter().fold(Sample::TRANSPARENT, |acc, &s| front_to_back(acc, s));
        let btf = samples.iter().rev().fold(Sample::TRANSPARENT, |acc, &s| back_to_front(acc, s));
        let refs: Vec<RefAssoc> = samples.iter().map(|s| assoc(s.c, s.a)).collect();
        let want = reference::composite_front_to_back(&refs, 1.0);
        let bound = tol::COMPOSITE_STEP * samples.len().max(1) as f64;
        prop_assert!(max_abs_diff(ftb, assoc(btf.c, btf.a)) <= 2.0 * bound);
        prop_assert!(max_abs_diff(ftb, want) <= bound);
        prop_assert!(max_abs_diff(btf, want) <= bound);
        prop_assert!(ftb.is_valid() && btf.is_valid(), "{ftb:?} {btf:?}");
    }

    /// Correction with `d = d′` is the identity (up to rounding), and the pipeline then skips it.
    #[test]
    fn correction_at_reference_distance_is_identity(s in sample()) {
        let c = correct(s, 1.0);
        prop_assert!(max_abs_diff(c, assoc(s.c, s.a)) <= tol::CORRECTION_ABS);
    }

    /// In a homogeneous medium, correcting by `d1` and `d2` and compositing equals correcting
    /// by `d1 + d2`.
    #[test]
    fn correction_composes_in_homogeneous_medium(
        s in sample(), r1 in 0.01f32..4.0, r2 in 0.01f32..4.0,
    ) {
        let two = front_to_back(correct(s, r1), correct(s, r2));
        let one = correct(s, r1 + r2);
        let bound = 4.0 * tol::CORRECTION_ABS * f64::from((r1 + r2).max(1.0)) + 2.0 * tol::COMPOSITE_STEP;
        prop_assert!(max_abs_diff(two, assoc(one.c, one.a)) <= bound, "{two:?} vs {one:?}");
    }
}

proptest! {
    /// Inside opaque material (every tap `α = 1`) every opacity-based mode and filter gives
    /// `α = 1` exactly, even after correcting to a much shorter step: the filter weights form
    /// an exact partition of unity in `f32`. (Without it, the weighted sum gave `1 − 2ε`,
    /// which correction to `d = d′/10` turned into `α ≈ 0.78`.)
    #[test]
    fn opaque_material_stays_exactly_opaque(
        (mut case, pos) in case_and_pos(),
        ratio in prop_oneof![Just(1.0f32), 1e-3f32..1.0],
    ) {
        for v in &mut case.voxels { v.a = 1.0; }
        for p in &mut case.tf { p.a = 1.0; }
        let d = case.d_ref * ratio;
        for mode in [ModeKind::Separate, ModeKind::OpacityWeighted, ModeKind::Preweighted, ModeKind::PostClassified] {
            for filter in FilterKind::ALL {
                let s = case.core_sample(mode, filter, pos, d);
                prop_assert_eq!(s.a, 1.0, "{:?} {:?} r={}", mode, filter, ratio);
            }
        }
    }
}
