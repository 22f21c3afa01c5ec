//! Group 6, integer limits: all-255 inputs at every `F ∈ 4..=12` in every integer mode and
//! filter and through the integer ray marcher; the widest accumulators (all depths at the
//! cap, weights `2^36`, the largest ratio); opacities one LSB from 0 and from 1; premultiplied
//! storage at `α_F = 1` through the samplers.
//!
//! Already covered elsewhere: all-255 and random extremes at `F = 4, 8, 12` bit-exact against
//! the models (`int_kernels`, `int_extinction`), every U8.8 opacity through the correction at
//! `d/d′ ∈ [10⁻³, 10³]` and every `(C, α_F)` pair of 8-bit premultiplication (`int_exhaustive`),
//! the compositor's `T·x ≤ 65280²` and early termination (`int_composite`).

use volsample::fixed_point::{
    premultiply_voxel, ExtinctionFx, ExtinctionTables, IntCorrection, IntExtinction, IntPos,
    IntSample, IntSampler, IntStop, ONE,
};
use volsample::render::IntRayMarcher;
use volsample::{
    AssociatedU8, Nearest, OpacityWeighted, Orthographic, Preweighted, Separate, Step, StraightU8,
    Trilinear, Volume,
};
use volsample_host::int_model::{self, correction as cm, extinction as em, sample as sm};
use volsample_host::tolerance::integer as itol;

use crate::common::Worst;

/// Ratios from below the `IntRatio` resolution (`2⁻³³`) to just below its limit `2³²`.
const RATIOS: [f32; 7] = [1e-11, 1e-6, 1e-3, 1.0, 1e3, 1e6, 4.29e9];

fn all_255<const F: u32>(w: &mut Worst, wx: &mut Worst) {
    let one = 1u32 << F;
    let fracs = [0, 1, one / 2, one - 1];
    let straight = [StraightU8([255; 4]); 8];
    let assoc = [AssociatedU8([255; 4]); 8];
    let ext = [ExtinctionFx::from_straight_u8(StraightU8([255; 4])); 8];
    let sv = Volume::new(&straight, [2, 2, 2]).unwrap();
    let av = Volume::new(&assoc, [2, 2, 2]).unwrap();
    let ev = Volume::new(&ext, [2, 2, 2]).unwrap();
    let tables = ExtinctionTables::<257>::new();
    for index in [0u32, 1, 7] {
        for fx in fracs {
            for fy in fracs {
                let pos =
                    IntPos::<F>::new([index, 1, index.min(1)], [fx, fy, one - 1 - fx]).unwrap();
                let opaque = |s: IntSample| (s.c(), s.a()) == ([ONE; 3], ONE);
                assert!(
                    opaque(IntSampler::new(sv, OpacityWeighted, Trilinear::new()).sample(pos)),
                    "F={F}"
                );
                assert!(
                    opaque(IntSampler::new(sv, Separate, Trilinear::new()).sample(pos)),
                    "F={F}"
                );
                assert!(
                    opaque(IntSampler::new(av, Preweighted, Trilinear::new()).sample(pos)),
                    "F={F}"
                );
                assert!(
                    opaque(IntSampler::new(sv, OpacityWeighted, Nearest).sample(pos)),
                    "F={F}"
                );
                for r in RATIOS {
                    let mode = IntExtinction::new(&tables, r).unwrap();
                    // Widest sums: D = 2^26 at every tap, weights summing to 2^(3F).
                    for s in [
                        IntSampler::new(ev, mode, Trilinear::new()).sample(pos),
                        IntSampler::new(ev, mode, Nearest).sample(pos),
                    ] {
                        assert!(
                            s.a() <= ONE && s.c().iter().all(|&c| c <= s.a()),
                            "F={F} r={r}"
                        );
                        let (ec, ea) =
                            em::exact(&[(ext[0].tau, ext[0].c_tau)], &[1.0], f64::from(r));
                        wx.check(
                            (f64::from(s.a()) - ea).abs(),
                            itol::extinction_int_a_lsb(257),
                            || format!("F={F} r={r:e} α"),
                        );
                        for (k, (&got, want)) in s.c().iter().zip(ec).enumerate() {
                            wx.check(
                                (f64::from(got) - want).abs(),
                                itol::extinction_int_c_lsb(257),
                                || format!("F={F} r={r:e} C{k}"),
                            );
                        }
                    }
                }
            }
        }
    }
    // The whole integer pipeline at this F: opaque white through every pixel.
    let cam = Orthographic::looking_down_z([2, 2, 2]).unwrap();
    for d in [0.25f32, 1.0, 3.0] {
        let m = IntRayMarcher::<_, _, _, F>::new(
            sv,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::NEVER,
            Step::new(d).unwrap(),
        )
        .unwrap();
        let mut img = [IntSample::TRANSPARENT; 4];
        m.render_into(&cam, 2, 2, &mut img).unwrap();
        for (k, px) in img.into_iter().enumerate() {
            // A step larger than the volume may take no sample at all (then: transparent).
            let n = m
                .sample_range(&volsample::Camera::ray(&cam, k % 2, k / 2, 2, 2))
                .1;
            let want = if n > 0 { ONE } else { 0 };
            let err = f64::from(want.abs_diff(px.a())).max(f64::from(want.abs_diff(px.c()[0])));
            w.check(err, 0.0, || format!("F={F} d={d} n={n}"));
        }
    }
}

/// All-255 at every `F`: exactly opaque white in every opacity-based mode and filter and
/// through the marcher (at `d ≠ d′` too); the extinction kernel at the depth cap with the
/// widest sums and ratios `10⁻¹¹ … 4.29·10⁹` within its bound.
#[test]
fn all_255_at_every_frac_bits() {
    let mut w = Worst::new(
        "6 all-255, F=4..12, OW/Sep/Prew × Nearest/Trilinear, marcher",
        "IntSampler OW/Sep/Prew, IntRayMarcher",
        "LSB",
    );
    let mut wx = Worst::new(
        "6 all-255 extinction at the depth cap, F=4..12, r 1e-11…4.29e9",
        "IntSampler IntExtinction",
        "LSB",
    );
    all_255::<4>(&mut w, &mut wx);
    all_255::<5>(&mut w, &mut wx);
    all_255::<6>(&mut w, &mut wx);
    all_255::<7>(&mut w, &mut wx);
    all_255::<8>(&mut w, &mut wx);
    all_255::<9>(&mut w, &mut wx);
    all_255::<10>(&mut w, &mut wx);
    all_255::<11>(&mut w, &mut wx);
    all_255::<12>(&mut w, &mut wx);
    w.report();
    wx.report();
}

fn one_lsb<const F: u32>(w: &mut Worst) {
    let max = (1u32 << F) - 1;
    for a in [1u8, 254] {
        for pattern in 0..4 {
            let taps: [[u8; 4]; 8] = std::array::from_fn(|i| match pattern {
                0 => [255, 0, 128, a],
                1 => [255, 255, 255, if i % 2 == 0 { a } else { 255 - a }],
                2 => [(i * 36) as u8, 255, 0, if i == 7 { a } else { 0 }],
                _ => [128, 1, 254, if i == 0 { 255 } else { a }],
            });
            let sv: Vec<StraightU8> = taps.iter().map(|&t| StraightU8(t)).collect();
            let av: Vec<AssociatedU8> = sv.iter().map(|&v| premultiply_voxel(v)).collect();
            let svol = Volume::new(&sv, [2, 2, 2]).unwrap();
            let avol = Volume::new(&av, [2, 2, 2]).unwrap();
            for frac in [[0, 0, 0], [max, max, max], [1, max / 2, max]] {
                let pos = IntPos::<F>::new([0; 3], frac).unwrap();
                let wts = int_model::trilinear_weights(F, frac);
                let assoc: Vec<[u8; 4]> = av.iter().map(|v| v.0).collect();
                let cases = [
                    (
                        "OW",
                        IntSampler::new(svol, OpacityWeighted, Trilinear::new()).sample(pos),
                        sm::opacity_weighted(&taps, &wts),
                        itol::OPACITY_WEIGHTED_INT_LSB,
                        itol::OPACITY_WEIGHTED_INT_LSB,
                    ),
                    (
                        "Sep",
                        IntSampler::new(svol, Separate, Trilinear::new()).sample(pos),
                        sm::separate(&taps, &wts),
                        itol::SEPARATE_INT_A_LSB,
                        itol::SEPARATE_INT_LSB,
                    ),
                    (
                        "Prew",
                        IntSampler::new(avol, Preweighted, Trilinear::new()).sample(pos),
                        sm::preweighted(&assoc, &wts),
                        itol::PREWEIGHTED_INT_LSB,
                        itol::PREWEIGHTED_INT_LSB,
                    ),
                ];
                for (name, got, model, ba, bc) in cases {
                    assert_eq!(
                        (got.c(), got.a()),
                        (model.c, model.a),
                        "{name} F={F} α={a} pattern {pattern}"
                    );
                    w.check((f64::from(got.a()) - model.exact_a).abs(), ba, || {
                        format!("{name} F={F} α={a}/255 p{pattern} α")
                    });
                    for k in 0..3 {
                        w.check((f64::from(got.c()[k]) - model.exact_c[k]).abs(), bc, || {
                            format!("{name} F={F} α={a}/255 p{pattern} C{k}")
                        });
                    }
                }
            }
        }
    }
}

/// Opacity bytes one LSB from 0 and from 1 (1 and 254, mixed with 0 and 255 around them), at
/// every `F`: bit-exact against the models and within each mode's bound.
#[test]
fn one_lsb_from_zero_and_one_every_frac_bits() {
    let mut w = Worst::new(
        "6 α byte 1 and 254, F=4..12, OW/Sep/Prew vs exact",
        "IntSampler OW/Sep/Prew",
        "LSB",
    );
    one_lsb::<4>(&mut w);
    one_lsb::<6>(&mut w);
    one_lsb::<8>(&mut w);
    one_lsb::<10>(&mut w);
    one_lsb::<12>(&mut w);
    w.report();
}

/// The integer correction at U8.8 opacities one LSB from 0 and 1 (and one u8 level from
/// them), at ratios outside the exhaustive test's range: `10⁻¹¹` (ratio quantized to 0),
/// `10⁻⁶`, `10⁶` and `4.29·10⁹` (the widest `r·L` product).
#[test]
fn integer_correction_at_the_ends() {
    let mut w = Worst::new(
        "6 IntCorrection α=1, 256, ONE−256, ONE−1 LSB × r 1e-11…4.29e9",
        "IntCorrection::apply",
        "LSB",
    );
    for r in RATIOS {
        let t = IntCorrection::new(r).unwrap();
        for v in [1u16, 2, 255, 256, ONE / 2, ONE - 256, ONE - 2, ONE - 1, ONE] {
            let s = IntSample::new([v, v / 2, 0], v).unwrap();
            let out = t.apply(s);
            assert!(
                out.a() <= ONE && out.c().iter().all(|&c| c <= out.a()),
                "r={r} v={v}"
            );
            let (ec, ea) = cm::exact(s.c(), v, f64::from(r));
            let b = itol::correction_int_lsb(r);
            w.check((f64::from(out.a()) - ea).abs(), b, || {
                format!("r={r:e} v={v} α_d")
            });
            for (k, (&got, want)) in out.c().iter().zip(ec).enumerate() {
                w.check((f64::from(got) - want).abs(), b + 0.5, || {
                    format!("r={r:e} v={v} C{k}")
                });
            }
        }
    }
    w.report();
}

/// Premultiplied `u8` storage at `α_F = 1` (Wittenbrink §7) through the integer samplers, at
/// every color byte and every `F`: `Preweighted` on the stored bytes differs from
/// `OpacityWeighted` on the straight ones by at most `PREMUL_STORAGE_LSB` (½ level of
/// storage rounding plus ½ LSB), and the limit is reached (127.5 LSB at `C = 127`).
#[test]
fn premultiplied_storage_at_alpha_one() {
    let mut w = Worst::new(
        "6 premultiplied u8 at α_F=1 vs OpacityWeighted, every C",
        "IntSampler Preweighted",
        "LSB",
    );
    let mut reached = 0.0f64;
    for c in 0..=255u8 {
        let sv = [StraightU8([c, 255 - c, c / 2, 1]); 8];
        let av = sv.map(premultiply_voxel);
        let (svol, avol) = (
            Volume::new(&sv, [2, 2, 2]).unwrap(),
            Volume::new(&av, [2, 2, 2]).unwrap(),
        );
        for frac in [[0u32, 0, 0], [7, 3, 15]] {
            let pos = IntPos::<4>::new([0; 3], frac).unwrap();
            let ow = IntSampler::new(svol, OpacityWeighted, Trilinear::new()).sample(pos);
            let pw = IntSampler::new(avol, Preweighted, Trilinear::new()).sample(pos);
            assert_eq!(ow.a(), pw.a());
            for k in 0..3 {
                let exact = 256.0 * f64::from(sv[0].0[k]) / 255.0;
                let err = (f64::from(pw.c()[k]) - exact).abs();
                reached = reached.max(err);
                w.check(err, itol::PREMUL_STORAGE_LSB, || format!("C={c} ch{k}"));
                assert!((f64::from(ow.c()[k]) - exact).abs() <= itol::OPACITY_WEIGHTED_INT_LSB);
            }
        }
    }
    assert!(reached >= 127.0, "the §7 limit is reached: {reached}");
    w.report();
}
