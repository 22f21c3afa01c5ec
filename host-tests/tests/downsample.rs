//! Downsampling and mipmap chains (`volsample::downsample`, Kraus & Bürger 2008 §4):
//! the paper's 2×2×2 example in closed form, constant volumes, layer structures, the range
//! invariants, and the core against the independent f64 reference
//! (`reference::downsample`) within the bounds of `tolerance::downsample`.

use proptest::prelude::*;
use volsample::downsample::{
    build_chain, chain_len, downsample_level, level_count, level_dims, level_offset,
    ExtinctionBased, Filter4, MipChain, MipLevel, OpacityBased,
};
use volsample::{
    AssociatedF32, Error, ExtinctionF32, ExtinctionWeighted, FrontToBack, Nearest, Orthographic,
    Preweighted, RayMarcher, Sample, Step, Trilinear, TriquadraticBSpline, Volume,
};
use volsample_host::reference::downsample as rd;
use volsample_host::reference::{self, RefAssoc, RefAssocVolume, RefExtinction, RefFilter};
use volsample_host::tolerance::downsample as tol;
use volsample_host::tolerance::EPS32;

/// The four named filters and their `a`.
fn named_filters() -> [(Filter4, f64); 4] {
    [
        (Filter4::box2(), 0.0),
        (Filter4::bspline(), 0.125),
        (Filter4::quadratic(), f64::from(0.2f32)),
        (Filter4::box4(), 0.25),
    ]
}

fn ext(tau: f32, c: [f32; 3]) -> ExtinctionF32 {
    ExtinctionF32 {
        c_tau: c.map(|c| c * tau),
        tau,
    }
}

fn to_ref_assoc(v: &AssociatedF32) -> RefAssoc {
    RefAssoc::new(v.c.map(f64::from), f64::from(v.a))
}

fn to_ref_ext(v: &ExtinctionF32) -> RefExtinction {
    RefExtinction {
        tau: f64::from(v.tau),
        color_tau: v.c_tau.map(f64::from),
    }
}

// ---------------------------------------------------------------------------------------------
// The paper's example (Kraus §4.1, figs. 2 and 3).

/// 2×2×2 voxels, the x = 0 layer at `τ = 4`, the x = 1 layer at `τ = 0`, fine distance 1.
///
/// Extinction-based: `τ̄ = (4 + 0)/2 = 2` per fine voxel, over the coarse voxel's length 2:
/// `α = 1 − e^(−2·2) = 1 − e^(−4)` — the transparency of the two layers it replaces,
/// `e^(−4)·e^0`.
///
/// Opacity-based: the fine opacities are `1 − e^(−4)` and 0, so `ᾱ = (1 − e^(−4))/2`, and the
/// correction to the doubled distance gives
/// `α′ = 1 − (1 − ᾱ)² = 1 − ((1 + e^(−4))/2)² ≈ 0.740758`, the paper's "≈ 0.74".
#[test]
fn paper_two_by_two_by_two_example() {
    let e4 = (-4.0f64).exp();
    let alpha_ext = 1.0 - e4;
    let alpha_op = 1.0 - ((1.0 + e4) / 2.0).powi(2);
    assert!((alpha_ext - 0.98168).abs() < 1e-5);
    assert!((alpha_op - 0.740758).abs() < 1e-6);

    let layer = |i: usize| i % 2 == 0;
    let white = [1.0f32; 3];
    let fine_ext: Vec<ExtinctionF32> = (0..8)
        .map(|i| ext(if layer(i) { 4.0 } else { 0.0 }, white))
        .collect();
    let a4 = -(-4.0f32).exp_m1();
    let fine_op: Vec<AssociatedF32> = (0..8)
        .map(|i| {
            let a = if layer(i) { a4 } else { 0.0 };
            AssociatedF32 { c: [a; 3], a }
        })
        .collect();

    for (filter, a) in named_filters() {
        // Every filter gives the same answer here: all taps of an axis of 2 clamp onto
        // the two voxels with total weight ½ each.
        let mut out = [ExtinctionF32::default(); 1];
        let lvl = downsample_level(
            ExtinctionBased,
            filter,
            &Volume::new(&fine_ext, [2, 2, 2]).unwrap(),
            &mut out,
        )
        .unwrap();
        let v = lvl.data()[0];
        assert_eq!(v.tau, 4.0, "a = {a}: τ′ per coarse voxel");
        let level = MipLevel::new(lvl, 1);
        // One coarse voxel is 2 fine voxels: a step of 2 fine voxels through its centre.
        let s = level.sample(
            &ExtinctionWeighted,
            Nearest,
            [0.5; 3],
            Step::new(2.0).unwrap(),
        );
        assert!((f64::from(s.a) - alpha_ext).abs() < 4.0 * EPS32, "{}", s.a);
        assert!((f64::from(s.c[0]) - alpha_ext).abs() < 4.0 * EPS32);

        let mut out = [AssociatedF32::default(); 1];
        let lvl = downsample_level(
            OpacityBased,
            filter,
            &Volume::new(&fine_op, [2, 2, 2]).unwrap(),
            &mut out,
        )
        .unwrap();
        let v = lvl.data()[0];
        assert!(
            (f64::from(v.a) - alpha_op).abs() < tol::OPACITY_PER_LEVEL,
            "{}",
            v.a
        );
        assert!((f64::from(v.c[0]) - alpha_op).abs() < tol::OPACITY_PER_LEVEL);
        // Its reference distance is one coarse voxel = 2 fine voxels: no correction at d = 2.
        let level = MipLevel::new(lvl, 1);
        assert_eq!(level.reference_distance_fine(), 2.0);
        let s = level.sample(&Preweighted, Nearest, [0.5; 3], Step::new(2.0).unwrap());
        assert_eq!(s.a, v.a);

        // And the f64 reference agrees with the closed forms.
        let (_, r) = rd::downsample_extinction(
            [2, 2, 2],
            &fine_ext.iter().map(to_ref_ext).collect::<Vec<_>>(),
            a,
        );
        assert!((-(-r[0].tau).exp_m1() - alpha_ext).abs() < 1e-15);
        let (_, r) = rd::downsample_opacity(
            [2, 2, 2],
            &fine_op.iter().map(to_ref_assoc).collect::<Vec<_>>(),
            a,
        );
        assert!((r[0].alpha - alpha_op).abs() < 2.0 * EPS32); // the f32 input 1 − e^(−4)
    }
}

// ---------------------------------------------------------------------------------------------
// Sizes and validation.

#[test]
fn level_sizes_match_the_reference_chain() {
    for dims in [
        [1, 1, 1],
        [2, 2, 2],
        [5, 4, 1],
        [7, 3, 9],
        [16, 1, 3],
        [33, 2, 17],
    ] {
        let count = level_count(dims);
        let mut d = dims;
        let mut total = 0;
        for l in 0..count {
            assert_eq!(level_dims(dims, l), d, "{dims:?} level {l}");
            if l > 0 {
                assert_eq!(level_offset(dims, l), total);
                total += d[0] * d[1] * d[2];
            }
            if l + 1 < count {
                assert_ne!(d, [1, 1, 1]);
            }
            d = rd::ref_level_dims(d);
        }
        assert_eq!(level_dims(dims, count - 1), [1, 1, 1]);
        assert_eq!(chain_len(dims), total);
    }
    assert_eq!(level_count([1 << 24, 1, 1]), 25);
    assert_eq!(level_dims([5, 1, 1], 200), [1, 1, 1]);
}

#[test]
fn bad_filters_and_buffers_are_rejected() {
    for a in [-0.01f32, 0.51, f32::NAN, f32::INFINITY] {
        assert_eq!(Filter4::new(a), Err(Error::InvalidDownsampleFilter));
    }
    assert_eq!(Filter4::new(0.5).unwrap().weights(), [0.5, 0.0, 0.0, 0.5]);
    assert_eq!(Filter4::new(0.2).unwrap(), Filter4::quadratic());
    let fine = [ext(1.0, [1.0; 3]); 27];
    let vol = Volume::new(&fine, [3, 3, 3]).unwrap();
    let mut small = [ExtinctionF32::default(); 7];
    assert_eq!(
        downsample_level(ExtinctionBased, Filter4::box4(), &vol, &mut small).unwrap_err(),
        Error::OutputLengthMismatch {
            expected: 8,
            actual: 7
        }
    );
    let mut chain = [ExtinctionF32::default(); 10];
    assert_eq!(
        build_chain(ExtinctionBased, Filter4::box4(), vol, &mut chain).unwrap_err(),
        Error::OutputLengthMismatch {
            expected: 9,
            actual: 10
        }
    );
    let e = Error::OutputLengthMismatch {
        expected: 9,
        actual: 10,
    };
    assert!(e.to_string().contains("needs 9"));
    // A single voxel has a chain of level 0 only.
    let one = [ext(1.0, [1.0; 3])];
    let c = build_chain(
        ExtinctionBased,
        Filter4::box4(),
        Volume::new(&one, [1, 1, 1]).unwrap(),
        &mut [],
    )
    .unwrap();
    assert_eq!(c.len(), 1);
    assert!(c.level(1).is_none());
}

// ---------------------------------------------------------------------------------------------
// Constant volumes.

/// A constant volume is constant at every level, for every filter and odd sizes: exactly
/// `τ_ℓ = 2^ℓ·τ` (the constant-exact filter form and the exact doubling), and
/// `α_ℓ = 1 − (1 − α)^(2^ℓ)` within the opacity chain bound.
#[test]
fn constant_volume_is_constant_at_every_level() {
    let dims = [7, 5, 3];
    let n = 7 * 5 * 3;
    for (filter, _) in named_filters() {
        for &(tau, c) in &[
            (0.0f32, [0.0f32; 3]),
            (0.37, [0.2, 0.9, 1.0]),
            (64.0, [1.0; 3]),
        ] {
            let fine = vec![ext(tau, c); n];
            let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
            let chain = build_chain(
                ExtinctionBased,
                filter,
                Volume::new(&fine, dims).unwrap(),
                &mut out,
            )
            .unwrap();
            for l in 1..chain.len() as u32 {
                let s = 2f32.powi(l as i32);
                let want = ExtinctionF32 {
                    c_tau: fine[0].c_tau.map(|x| x * s),
                    tau: tau * s,
                };
                for v in chain.level(l).unwrap().volume().data() {
                    assert_eq!(*v, want, "level {l}");
                }
            }
        }
        for &(a, c) in &[
            (0.0f32, [0.0f32; 3]),
            (0.3, [0.1, 0.2, 0.3]),
            (1.0, [0.5; 3]),
            (1e-30, [1e-30; 3]),
        ] {
            let fine = vec![AssociatedF32 { c, a }; n];
            let mut out = vec![AssociatedF32::default(); chain_len(dims)];
            let chain = build_chain(
                OpacityBased,
                filter,
                Volume::new(&fine, dims).unwrap(),
                &mut out,
            )
            .unwrap();
            for l in 1..chain.len() as u32 {
                let data = chain.level(l).unwrap().volume().data();
                let first = data[0];
                assert!(data.iter().all(|v| *v == first), "level {l} not uniform");
                let k = 2f64.powi(l as i32);
                let want_a = 1.0 - (1.0 - f64::from(a)).powf(k);
                // C̃ scales with α: C̃_ℓ = C̃·α_ℓ/α (→ C̃·2^ℓ as α → 0).
                let gain = if a > 0.0 { want_a / f64::from(a) } else { 0.0 };
                let bound = tol::opacity_chain(l);
                assert!(
                    (f64::from(first.a) - want_a).abs() <= bound,
                    "level {l}: {} vs {want_a}",
                    first.a
                );
                for (got, c) in first.c.iter().zip(c) {
                    let want = f64::from(c) * gain;
                    assert!(
                        (f64::from(*got) - want).abs() <= bound.max(want * bound),
                        "level {l}"
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Layer structures: the projection opacity along the layers' normal is kept by extinction-based
// downsampling and lost by opacity-based downsampling.

/// Layers along z (τ depends on z only), empty within 8 voxels of the z faces so that clamping
/// never reaches a layer. Then `Σ_Z τ′_Z = Σ_z τ_z` at every level for every `(a, b, b, a)`
/// filter (each fine layer gives weight `2(a + b) = 1` in total to the coarse layers, times the
/// doubling, halved by the coarse voxel count), so the axis-aligned projection opacity
/// `1 − e^(−Σ τ)` is kept. Rendered along z with `ExtinctionWeighted` trilinear sampling at
/// one sample on each level voxel centre it is kept too: the samples add up to `Σ_Z τ′_Z`,
/// the integral of the clamped piecewise-linear reconstruction over the volume box. The opacity-based chain loses opacity.
#[test]
fn layer_structure_keeps_projection_opacity() {
    let dims = [4, 3, 32];
    let taus: Vec<f32> = (0..32)
        .map(|z| {
            if (8..24).contains(&z) {
                0.02 + 0.06 * ((z * 7 % 5) as f32)
            } else {
                0.0
            }
        })
        .collect();
    let depth: f64 = taus.iter().map(|&t| f64::from(t)).sum();
    let exact = -(-depth).exp_m1();
    let fine: Vec<ExtinctionF32> = (0..dims[0] * dims[1] * dims[2])
        .map(|i| ext(taus[i / 12], [0.8, 0.5, 0.1]))
        .collect();
    let fine_op: Vec<AssociatedF32> = fine
        .iter()
        .map(|e| {
            let a = -(-e.tau).exp_m1();
            AssociatedF32 {
                c: [0.8 * a, 0.5 * a, 0.1 * a],
                a,
            }
        })
        .collect();
    for (filter, _) in named_filters() {
        let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
        let chain = build_chain(
            ExtinctionBased,
            filter,
            Volume::new(&fine, dims).unwrap(),
            &mut out,
        )
        .unwrap();
        let mut out_op = vec![AssociatedF32::default(); chain_len(dims)];
        let chain_op = build_chain(
            OpacityBased,
            filter,
            Volume::new(&fine_op, dims).unwrap(),
            &mut out_op,
        )
        .unwrap();
        for l in 1..=3u32 {
            let lvl = chain.level(l).unwrap().volume();
            let [nx, ny, nz] = lvl.dims();
            for y in 0..ny {
                for x in 0..nx {
                    let d: f64 = (0..nz)
                        .map(|z| f64::from(lvl.get(x, y, z).unwrap().tau))
                        .sum();
                    let got = -(-d).exp_m1();
                    assert!(
                        (got - exact).abs() < 1e-5,
                        "a = {}, level {l}: {got} vs {exact}",
                        filter.a()
                    );
                }
            }
            // Rendered: orthographic along z through the level volume, one sample per voxel.
            let marcher = RayMarcher::new(
                lvl,
                ExtinctionWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                Step::new(1.0).unwrap(),
            )
            .unwrap();
            let mut img = vec![Sample::TRANSPARENT; nx * ny];
            marcher
                .render_into(
                    &Orthographic::looking_down_z(lvl.dims()).unwrap(),
                    nx,
                    ny,
                    &mut img,
                )
                .unwrap();
            for px in &img {
                assert!(
                    (f64::from(px.a) - exact).abs() < 1e-5,
                    "level {l}, a = {}: rendered {} vs {exact}",
                    filter.a(),
                    px.a
                );
            }
            // Opacity-based: the composite of the coarse layers is below the exact opacity.
            let lo = chain_op.level(l).unwrap().volume();
            let t: f64 = (0..lo.dims()[2])
                .map(|z| 1.0 - f64::from(lo.get(0, 0, z).unwrap().a))
                .product();
            assert!(
                1.0 - t < exact - 1e-3,
                "opacity-based level {l} kept {} of {exact}",
                1.0 - t
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Random volumes against the reference; invariants.

fn assoc_voxel() -> impl Strategy<Value = AssociatedF32> {
    (
        prop_oneof![1 => Just(0.0f32), 1 => Just(1.0f32), 1 => 0.0f32..1e-6, 5 => 0.0f32..=1.0],
        [0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0],
    )
        .prop_map(|(a, c)| AssociatedF32 {
            c: c.map(|c| c * a),
            a,
        })
}

fn ext_voxel() -> impl Strategy<Value = ExtinctionF32> {
    (
        prop_oneof![1 => Just(0.0f32), 1 => Just(64.0f32), 5 => 0.0f32..=8.0],
        [0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0],
    )
        .prop_map(|(t, c)| ext(t, c))
}

fn filter_a() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(0.125),
        Just(0.2),
        Just(0.25),
        0.0f32..=0.5
    ]
}

prop_compose! {
    fn assoc_case()(dims in [1usize..=9, 1usize..=9, 1usize..=9])
        (v in prop::collection::vec(assoc_voxel(), dims[0] * dims[1] * dims[2]), dims in Just(dims))
        -> ([usize; 3], Vec<AssociatedF32>) { (dims, v) }
}

prop_compose! {
    fn ext_case()(dims in [1usize..=9, 1usize..=9, 1usize..=9])
        (v in prop::collection::vec(ext_voxel(), dims[0] * dims[1] * dims[2]), dims in Just(dims))
        -> ([usize; 3], Vec<ExtinctionF32>) { (dims, v) }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Every level of an opacity-based chain is valid (`0 ≤ C̃ ≤ α ≤ 1`, finite) and within
    /// `opacity_chain(ℓ)` of the f64 reference chain of the same stored input.
    #[test]
    fn opacity_chain_matches_reference((dims, fine) in assoc_case(), a in filter_a()) {
        let filter = Filter4::new(a).unwrap();
        let mut out = vec![AssociatedF32::default(); chain_len(dims)];
        let chain = build_chain(OpacityBased, filter, Volume::new(&fine, dims).unwrap(), &mut out).unwrap();
        let reference = rd::chain(dims, &fine.iter().map(to_ref_assoc).collect::<Vec<_>>(), f64::from(a), rd::downsample_opacity);
        prop_assert_eq!(chain.len(), reference.len());
        for (l, (rdims, rv)) in reference.iter().enumerate().skip(1) {
            let lvl = chain.level(l as u32).unwrap().volume();
            prop_assert_eq!(lvl.dims(), *rdims);
            let bound = tol::opacity_chain(l as u32);
            for (v, r) in lvl.data().iter().zip(rv) {
                prop_assert!(v.a.is_finite() && (0.0..=1.0).contains(&v.a));
                prop_assert!(v.c.iter().all(|&c| c.is_finite() && c >= 0.0 && c <= v.a));
                let err = to_ref_assoc(v).max_abs_diff(*r);
                prop_assert!(err <= bound, "level {}: err {:e} > {:e}", l, err, bound);
            }
        }
    }

    /// Every level of an extinction-based chain is valid (`0 ≤ C^τ ≤ τ`, finite) and within
    /// `extinction_chain(ℓ, τ_max)` of the f64 reference chain.
    #[test]
    fn extinction_chain_matches_reference((dims, fine) in ext_case(), a in filter_a()) {
        let filter = Filter4::new(a).unwrap();
        let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
        let chain = build_chain(ExtinctionBased, filter, Volume::new(&fine, dims).unwrap(), &mut out).unwrap();
        let reference = rd::chain(dims, &fine.iter().map(to_ref_ext).collect::<Vec<_>>(), f64::from(a), rd::downsample_extinction);
        let tau_max = fine.iter().fold(0.0f64, |m, v| m.max(f64::from(v.tau)));
        for (l, (_, rv)) in reference.iter().enumerate().skip(1) {
            let lvl = chain.level(l as u32).unwrap().volume();
            let bound = tol::extinction_chain(l as u32, tau_max);
            for (v, r) in lvl.data().iter().zip(rv) {
                prop_assert!(v.tau.is_finite() && v.tau >= 0.0);
                prop_assert!(v.c_tau.iter().all(|&c| c.is_finite() && c >= 0.0 && c <= v.tau));
                let err = (f64::from(v.tau) - r.tau).abs();
                let err = v.c_tau.iter().zip(r.color_tau).fold(err, |m, (c, rc)| m.max((f64::from(*c) - rc).abs()));
                prop_assert!(err <= bound, "level {}: err {:e} > {:e}", l, err, bound);
            }
        }
    }

    /// `MipLevel::sample` (trilinear and triquadratic B-spline, both methods) against the
    /// reference sample of the same level data at the same level position and level step.
    #[test]
    fn mip_level_sampling_matches_reference(
        (dims, fine) in ext_case(),
        pos in [-1.0f32..10.0, -1.0f32..10.0, -1.0f32..10.0],
        d in 0.25f32..4.0,
        l in 1u32..4,
        bspline in any::<bool>(),
    ) {
        let filter = Filter4::quadratic();
        let fine = fine.iter().map(|v| ExtinctionF32 { tau: v.tau.min(2.0), c_tau: v.c_tau.map(|c| c.min(2.0)) }).collect::<Vec<_>>();
        let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
        let chain: MipChain<'_, ExtinctionF32> = build_chain(ExtinctionBased, filter, Volume::new(&fine, dims).unwrap(), &mut out).unwrap();
        let fine_op: Vec<AssociatedF32> = fine.iter().map(|e| {
            let a = -(-e.tau).exp_m1();
            AssociatedF32 { c: e.c_tau.map(|c| if e.tau > 0.0 { (c / e.tau * a).min(a) } else { 0.0 }), a }
        }).collect();
        let mut out_op = vec![AssociatedF32::default(); chain_len(dims)];
        let chain_op = build_chain(OpacityBased, filter, Volume::new(&fine_op, dims).unwrap(), &mut out_op).unwrap();
        let Some(level) = chain.level(l) else { return Ok(()); };
        let level_op = chain_op.level(l).unwrap();
        let step = Step::new(d).unwrap();
        let (rf, s, s_op) = if bspline {
            (RefFilter::TriquadraticBSpline,
             level.sample(&ExtinctionWeighted, TriquadraticBSpline, pos, step),
             level_op.sample(&Preweighted, TriquadraticBSpline, pos, step))
        } else {
            (RefFilter::Trilinear,
             level.sample(&ExtinctionWeighted, Trilinear::new(), pos, step),
             level_op.sample(&Preweighted, Trilinear::new(), pos, step))
        };
        let q = level.to_level(pos).map(f64::from);
        let d_level = f64::from(d) / f64::from(level.scale());
        let vol = level.volume();
        let ch = |k: usize| -> Vec<f64> {
            vol.data().iter().map(|v| f64::from(if k < 3 { v.c_tau[k] } else { v.tau })).collect()
        };
        let e = RefExtinction {
            tau: reference::interpolate(vol.dims(), rf, q, &ch(3)),
            color_tau: [0, 1, 2].map(|k| reference::interpolate(vol.dims(), rf, q, &ch(k))),
        };
        let r = reference::extinction_sample(e, d_level);
        let err = volsample_host::float_checks::max_abs_diff(s, r);
        prop_assert!(err <= tol::MIP_SAMPLE, "extinction: {:e}", err);

        // Opacity-based: the uncorrected sample (a step of the level's reference distance)
        // against the reference, and the corrected one is exactly `correct` of it (the
        // correction itself is held to its own bound in `float_vs_reference`; near α = 1 it
        // amplifies the f32 rounding of α, so it is not compared against f64 here).
        let vo = level_op.volume();
        let rv = RefAssocVolume::new(vo.dims(), vo.data().iter().map(to_ref_assoc).collect(), f64::from(vo.reference_distance()));
        let d_ref_fine = level_op.reference_distance_fine();
        let (uncorrected, rf_op) = if bspline {
            (level_op.sample(&Preweighted, TriquadraticBSpline, pos, Step::new(d_ref_fine).unwrap()), RefFilter::TriquadraticBSpline)
        } else {
            (level_op.sample(&Preweighted, Trilinear::new(), pos, Step::new(d_ref_fine).unwrap()), RefFilter::Trilinear)
        };
        let r = reference::sample(reference::RefSource::Associated(&rv), reference::RefMode::Preweighted, rf_op, q, rv.d_ref);
        let err = volsample_host::float_checks::max_abs_diff(uncorrected, r);
        prop_assert!(err <= tol::MIP_SAMPLE, "opacity: {:e}", err);
        let ratio = (d / level_op.scale()) / vo.reference_distance();
        let want = if ratio == 1.0 { uncorrected } else { volsample::opacity::correct(uncorrected, ratio) };
        prop_assert_eq!(s_op, want);
    }
}

/// Extreme values stay in range: opaque voxels, subnormal opacities, `τ` at `MAX_TAU`
/// (saturating after doubling).
#[test]
fn extreme_values_stay_in_range() {
    let dims = [5, 4, 3];
    let n = 60;
    let fine: Vec<AssociatedF32> = (0..n)
        .map(|i| match i % 4 {
            0 => AssociatedF32 {
                c: [1.0; 3],
                a: 1.0,
            },
            1 => AssociatedF32 {
                c: [1e-45; 3],
                a: 1e-45,
            },
            2 => AssociatedF32 {
                c: [0.0; 3],
                a: 0.0,
            },
            _ => AssociatedF32 {
                c: [0.3, 0.0, 0.6],
                a: 0.6,
            },
        })
        .collect();
    let mut out = vec![AssociatedF32::default(); chain_len(dims)];
    let chain = build_chain(
        OpacityBased,
        Filter4::box4(),
        Volume::new(&fine, dims).unwrap(),
        &mut out,
    )
    .unwrap();
    for l in 0..chain.len() as u32 {
        for v in chain.level(l).unwrap().volume().data() {
            assert!((0.0..=1.0).contains(&v.a) && v.c.iter().all(|&c| (0.0..=v.a).contains(&c)));
        }
    }
    let big = volsample::voxel::MAX_TAU;
    let fine: Vec<ExtinctionF32> = (0..n)
        .map(|i| {
            if i % 2 == 0 {
                ext(big, [1.0; 3])
            } else {
                ext(0.0, [0.0; 3])
            }
        })
        .collect();
    let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
    let chain = build_chain(
        ExtinctionBased,
        Filter4::box2(),
        Volume::new(&fine, dims).unwrap(),
        &mut out,
    )
    .unwrap();
    let top = chain.level(chain.len() as u32 - 1).unwrap().volume().data()[0];
    assert_eq!(top.tau, big, "saturates at MAX_TAU");
    assert!(top.c_tau.iter().all(|&c| c <= top.tau));
}

/// `MipChain::level_for_footprint` picks `⌊log₂ f + ½⌋`, clamped.
#[test]
fn level_for_footprint() {
    let fine = vec![ext(1.0, [1.0; 3]); 64];
    let mut out = vec![ExtinctionF32::default(); chain_len([4, 4, 4])];
    let chain = build_chain(
        ExtinctionBased,
        Filter4::box4(),
        Volume::new(&fine, [4, 4, 4]).unwrap(),
        &mut out,
    )
    .unwrap();
    assert_eq!(chain.len(), 3);
    for (f, l) in [
        (0.5, 0),
        (1.0, 0),
        (1.4, 0),
        (1.5, 1),
        (2.0, 1),
        (3.0, 2),
        (100.0, 2),
        (f32::NAN, 0),
    ] {
        assert_eq!(chain.level_for_footprint(f).level(), l, "footprint {f}");
    }
    let lvl = chain.level(2).unwrap();
    assert_eq!(lvl.to_level([1.5; 3]), [0.0; 3]);
    assert_eq!(lvl.to_fine([0.0; 3]), [1.5; 3]);
    let _ = level_offset;
}

/// Deterministic sweep of random volumes recording the worst error of each chain level
/// against the f64 reference, as a fraction of its bound (printed with `--nocapture` for the
/// closing notes; asserted ≤ 1).
#[test]
fn worst_observed_errors() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 40) as f32) / (1u32 << 24) as f32
    };
    let (mut op_worst, mut op_ratio, mut ex_worst, mut ex_ratio) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for case in 0..200 {
        let dims = [2 + case % 9, 1 + (case / 3) % 8, 1 + (case / 7) % 9];
        let n = dims[0] * dims[1] * dims[2];
        let a = [0.0f32, 0.125, 0.2, 0.25, 0.5][case % 5];
        let filter = Filter4::new(a).unwrap();
        let fine_op: Vec<AssociatedF32> = (0..n)
            .map(|_| {
                let al = if rnd() < 0.2 { 1.0 } else { rnd() };
                AssociatedF32 {
                    c: [rnd() * al, rnd() * al, rnd() * al],
                    a: al,
                }
            })
            .collect();
        let fine_ex: Vec<ExtinctionF32> = (0..n)
            .map(|_| ext(8.0 * rnd(), [rnd(), rnd(), rnd()]))
            .collect();
        let mut out = vec![AssociatedF32::default(); chain_len(dims)];
        let chain = build_chain(
            OpacityBased,
            filter,
            Volume::new(&fine_op, dims).unwrap(),
            &mut out,
        )
        .unwrap();
        let r = rd::chain(
            dims,
            &fine_op.iter().map(to_ref_assoc).collect::<Vec<_>>(),
            f64::from(a),
            rd::downsample_opacity,
        );
        for (l, (_, rv)) in r.iter().enumerate().skip(1) {
            for (v, rv) in chain
                .level(l as u32)
                .unwrap()
                .volume()
                .data()
                .iter()
                .zip(rv)
            {
                let e = to_ref_assoc(v).max_abs_diff(*rv);
                op_worst = op_worst.max(e);
                op_ratio = op_ratio.max(e / tol::opacity_chain(l as u32));
            }
        }
        let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
        let chain = build_chain(
            ExtinctionBased,
            filter,
            Volume::new(&fine_ex, dims).unwrap(),
            &mut out,
        )
        .unwrap();
        let r = rd::chain(
            dims,
            &fine_ex.iter().map(to_ref_ext).collect::<Vec<_>>(),
            f64::from(a),
            rd::downsample_extinction,
        );
        let tau_max = fine_ex.iter().fold(0.0f64, |m, v| m.max(f64::from(v.tau)));
        for (l, (_, rv)) in r.iter().enumerate().skip(1) {
            for (v, rv) in chain
                .level(l as u32)
                .unwrap()
                .volume()
                .data()
                .iter()
                .zip(rv)
            {
                let e = v
                    .c_tau
                    .iter()
                    .zip(rv.color_tau)
                    .fold((f64::from(v.tau) - rv.tau).abs(), |m, (c, rc)| {
                        m.max((f64::from(*c) - rc).abs())
                    });
                let rel = e / (2f64.powi(l as i32) * tau_max);
                ex_worst = ex_worst.max(rel);
                ex_ratio = ex_ratio.max(e / tol::extinction_chain(l as u32, tau_max));
            }
        }
    }
    println!(
        "opacity-based chain: worst abs error {op_worst:.3e}; worst error/bound {op_ratio:.3}"
    );
    println!("extinction-based chain: worst error/(2^l tau_max) {ex_worst:.3e}; worst error/bound {ex_ratio:.3}");
    assert!(op_ratio <= 1.0 && ex_ratio <= 1.0);
}
