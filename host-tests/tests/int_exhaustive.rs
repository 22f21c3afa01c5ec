//! Exhaustive tests over the small integer domains: every `(C, α)` byte pair for
//! premultiply/unpremultiply and the Wittenbrink §7 limit, every 8-bit and every U8.8 opacity
//! for the opacity-correction tables.

use volsample::fixed_point::{
    premultiply, unpremultiply, IntCorrection, IntPos, IntSample, IntSampler, ONE,
};
use volsample::{Nearest, OpacityWeighted, StraightU8, Volume};
use volsample_host::int_model::{correction as cm, premul as pm};
use volsample_host::tolerance::integer as tol;

#[test]
fn premultiply_every_pair() {
    for a in 0..=255u8 {
        for c in 0..=255u8 {
            let p = premultiply(c, a);
            assert_eq!(p, pm::premultiply(c, a), "premultiply({c}, {a})");
            assert!(p <= a);
            let exact = f64::from(c) * f64::from(a) / 255.0;
            assert!((f64::from(p) - exact).abs() <= tol::PREMULTIPLY_LEVELS);
            for q in [p, c] {
                assert_eq!(
                    unpremultiply(q, a),
                    pm::unpremultiply(q, a),
                    "unpremultiply({q}, {a})"
                );
            }
        }
    }
}

/// Wittenbrink §7: the color recovered from u8 premultiplied storage is within
/// `0.5·255/α_F` of the stored color for every pair, the bound is reached (127 at `α_F = 1`),
/// and it is within one level of tight for every `α_F`.
#[test]
fn premultiplied_storage_limit_every_pair() {
    let mut worst_at_1 = 0.0f64;
    for a in 1..=255u8 {
        let bound = tol::PREMUL_RECOVERY_HALF * 255.0 / f64::from(a);
        let mut worst = 0.0f64;
        let mut worst_u8 = 0i32;
        for c in 0..=255u8 {
            let e = pm::recovery_error(c, a);
            assert!(e <= bound + 1e-12, "C = {c}, α = {a}: error {e} > {bound}");
            worst = worst.max(e);
            let u = unpremultiply(premultiply(c, a), a);
            worst_u8 = worst_u8.max((i32::from(u) - i32::from(c)).abs());
        }
        // Reached: within one level (the stored color is an integer) of the bound.
        assert!(
            worst >= bound - 1.0,
            "α = {a}: worst {worst} far below bound {bound}"
        );
        assert!(
            f64::from(worst_u8) <= (bound + 0.5).floor(),
            "α = {a}: unpremultiply off by {worst_u8}"
        );
        if a == 1 {
            worst_at_1 = worst;
        }
    }
    assert_eq!(worst_at_1, tol::PREMUL_RECOVERY_REACHED_AT_ALPHA_1);
}

/// `OpacityWeighted` from straight u8 storage keeps the color of every voxel: its U8.8 sample
/// gives back the exact byte for every `(C, α)` with `α ≥ 1`, where premultiplied storage
/// loses up to 127 levels.
#[test]
fn opacity_weighted_from_straight_keeps_every_color() {
    let mut worst = 0.0f64;
    for a in 1..=255u8 {
        let voxels: Vec<StraightU8> = (0..=255u8)
            .map(|c| StraightU8([c, 255 - c, c / 2, a]))
            .collect();
        let vol = Volume::new(&voxels, [256, 1, 1]).unwrap();
        let s = IntSampler::new(vol, OpacityWeighted, Nearest);
        for c in 0..=255u8 {
            let smp = s.sample(IntPos::<8>::new([u32::from(c), 0, 0], [0, 0, 0]).unwrap());
            assert_eq!(smp.a(), u16::from(a) * 256);
            let rec = 255.0 * f64::from(smp.c()[0]) / f64::from(smp.a());
            let e = (rec - f64::from(c)).abs();
            let bound = tol::recovered_color_bound(tol::OPACITY_WEIGHTED_INT_LSB, smp.a())
                - 0.5 * 255.0 / f64::from(smp.a());
            assert!(e <= bound + 1e-12, "C = {c}, α = {a}: {e} > {bound}");
            assert_eq!(rec.round() as u8, c);
            worst = worst.max(e);
        }
    }
    println!("OpacityWeighted from straight u8: worst recovered color error {worst:.4} levels");
    assert!(worst < 0.5);
}

const RATIOS: [f32; 11] = [
    0.001, 0.125, 0.37, 0.5, 0.9, 1.0, 1.5, 2.0, 4.0, 16.0, 1000.0,
];

/// Every table entry of the correction against the model's (bit for bit), and the reported
/// u8-opacity table against the exact corrected opacity.
#[test]
fn correction_tables_every_entry() {
    for r in RATIOS {
        let t = IntCorrection::new(r).unwrap();
        let m = cm::tables(r);
        assert_eq!(t.int_ratio().raw(), m.r, "r = {r}");
        assert_eq!(&t.psi_table()[..], &m.psi[..], "ψ table, r = {r}");
        assert_eq!(&t.ln_table()[..], &m.ln_m[..], "ln table, r = {r}");
        assert_eq!(&t.ln_top()[..], &m.ln_top[..], "ln top, r = {r}");
        assert_eq!(&t.exp_tables().phi()[..], &m.exp.phi[..]);
        assert_eq!(&t.exp_tables().exp()[..], &m.exp.exp[..]);
        assert_eq!(&t.exp_tables().exp_int()[..], &m.exp.exp_int[..]);
        let table = t.table();
        for (i, &e) in table.iter().enumerate() {
            let exact = f64::from(ONE) * cm::exact_alpha(i as f64 / 255.0, f64::from(r));
            assert!(
                (f64::from(e) - exact).abs() <= tol::CORRECTION_INT_LSB,
                "r = {r}, α = {i}: {e} vs {exact}"
            );
        }
        assert_eq!((table[0], table[255]), (0, ONE));
    }
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY, 4_294_967_296.0] {
        assert!(IntCorrection::new(bad).is_err(), "{bad}");
    }
}

/// Applying the correction at every U8.8 opacity, for ratios from 0.001 to 1000: bit-exact
/// against the model, `C̃ ≤ α` kept, `α_d` within `CORRECTION_INT_LSB` of the exact value and
/// each `C̃_d` within ½ LSB more, the same bound for every ratio.
#[test]
fn correction_apply_every_u88_alpha() {
    let mut overall = 0.0f64;
    for r in RATIOS {
        let t = IntCorrection::new(r).unwrap();
        let m = cm::tables(r);
        let mut worst_a = 0.0f64;
        let mut worst_c = 0.0f64;
        for v in 0..=ONE {
            let s = IntSample::new([v, v / 2, v / 3], v).unwrap();
            let out = t.apply(s);
            assert_eq!((out.c(), out.a()), m.apply(s.c(), v), "r = {r}, v = {v}");
            assert!(out.c().iter().all(|&c| c <= out.a()) && out.a() <= ONE);
            let (ec, ea) = cm::exact(s.c(), v, f64::from(r));
            worst_a = worst_a.max((f64::from(out.a()) - ea).abs());
            for (c, want) in out.c().iter().zip(ec) {
                worst_c = worst_c.max((f64::from(*c) - want).abs());
            }
        }
        let bound = tol::correction_int_lsb(r);
        println!(
            "r = {r}: worst α_d error {worst_a:.4} LSB, C̃_d {worst_c:.4} LSB (bounds {bound:.4}, {:.4})",
            bound + 0.5
        );
        assert!(worst_a <= bound, "r = {r}: α_d {worst_a} > {bound}");
        assert!(
            worst_c <= bound + 0.5,
            "r = {r}: C̃_d {worst_c} > {}",
            bound + 0.5
        );
        overall = overall.max(worst_a);
    }
    // The bound is nearly reached (the final rounding alone is ½).
    assert!(overall > 0.49, "worst α_d error {overall}");
}
