//! The small numeric functions of the core against f64, each held to the bound its doc
//! comment states (one named constant per function in the tolerance table). Each test prints
//! its worst error as a fraction of the bound.

use proptest::prelude::*;
use volsample::classify::{gradient, Isosurface};
use volsample::filter::trilinear_weights;
use volsample::mode::integrate_step;
use volsample::opacity::{
    correct, phi, phi_poly, PHI_POLY_BELOW, PHI_SERIES_BELOW, PSI_SERIES_BELOW,
};
use volsample::shade::Light;
use volsample::{ControlPoint, ExtinctionF32, Sample, StraightF32, TransferFunction, Volume};
use volsample_host::reference::{self, RefExtinction};
use volsample_host::tolerance as tol;

#[test]
fn phi_relative_error() {
    let mut worst = 0.0f64;
    let mut xs: Vec<f32> = (0..4000)
        .map(|k| 10f32.powf(-30.0 + k as f32 * 0.00875))
        .collect();
    // Around the series switch-over, one ulp at a time.
    let mut x = PHI_SERIES_BELOW;
    for _ in 0..200 {
        x = f32::from_bits(x.to_bits() - 1);
    }
    for _ in 0..400 {
        xs.push(x);
        x = f32::from_bits(x.to_bits() + 1);
    }
    xs.extend([0.0, f32::MIN_POSITIVE, 1e-45, 88.0, 1e30, f32::MAX]);
    for x in xs {
        let got = f64::from(phi(x));
        let want = reference::phi(f64::from(x));
        let rel = if want == 0.0 {
            got.abs()
        } else {
            ((got - want) / want).abs()
        };
        worst = worst.max(rel);
    }
    assert_eq!(phi(f32::INFINITY), 0.0);
    assert!(phi(f32::NAN).is_nan());
    println!(
        "phi: worst relative error {:.3} of the bound",
        worst / tol::PHI_REL
    );
    assert!(worst <= tol::PHI_REL, "{worst:e}");
}

proptest! {
    #[test]
    fn integrate_step_matches_reference(
        log_tau in -40.0f64..4.0, zero in any::<bool>(), c in [0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0],
        log_d in -4.0f64..2.0,
    ) {
        let tau = if zero { 0.0 } else { 10f64.powf(log_tau) as f32 };
        let d = 10f64.powf(log_d) as f32;
        let c_tau = c.map(|c| tau * c);
        let got = integrate_step(c_tau, tau, d);
        let want = reference::extinction_sample(
            RefExtinction { tau: f64::from(tau), color_tau: c_tau.map(f64::from) },
            f64::from(d),
        );
        let err = (0..3).map(|k| (f64::from(got.c[k]) - want.color[k]).abs())
            .fold((f64::from(got.a) - want.alpha).abs(), f64::max);
        prop_assert!(err <= tol::INTEGRATE_STEP_ABS, "tau={tau} d={d}: {err:e}");
        prop_assert!(got.is_valid());
    }

    #[test]
    fn extinction_from_straight_matches_f64(a in 0.0f32..1.0, c in 0.0f32..=1.0, d_ref in 0.01f32..100.0) {
        let e = ExtinctionF32::from_straight(StraightF32 { c: [c; 3], a }, d_ref);
        let depth = (-(-f64::from(a)).ln_1p()).min(64.0);
        let want = depth / f64::from(d_ref);
        let rel = if want == 0.0 { f64::from(e.tau) } else { (f64::from(e.tau) - want).abs() / want };
        prop_assert!(rel <= tol::FROM_STRAIGHT_TAU_REL, "a={a}: {rel:e}");
        prop_assert!(e.c_tau.iter().all(|&x| x <= e.tau));
    }

    #[test]
    fn transfer_function_eval_matches_f64(
        pts in prop::collection::vec((0.0f32..300.0, 0.0f32..=1.0, 0.0f32..=1.0), 2..6),
        s in -10.0f32..310.0,
    ) {
        let mut pts = pts;
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts.dedup_by(|a, b| a.0 <= b.0 + 1e-3);
        prop_assume!(pts.len() >= 2);
        let cps: Vec<ControlPoint> = pts.iter().map(|&(s, c, a)| ControlPoint { s, c: [c; 3], a }).collect();
        let tf = TransferFunction::<8>::new(&cps).unwrap();
        let (c, a) = tf.eval(s);
        // f64 piecewise linear.
        let s64 = f64::from(s);
        let i = cps.partition_point(|p| f64::from(p.s) <= s64);
        let (want_c, want_a, slope) = if i == 0 {
            (f64::from(cps[0].c[0]), f64::from(cps[0].a), 0.0)
        } else if i == cps.len() {
            (f64::from(cps[i - 1].c[0]), f64::from(cps[i - 1].a), 0.0)
        } else {
            let (lo, hi) = (cps[i - 1], cps[i]);
            let w = f64::from(hi.s) - f64::from(lo.s);
            let t = (s64 - f64::from(lo.s)) / w;
            let l = (f64::from(hi.c[0] - lo.c[0]).abs()).max(f64::from(hi.a - lo.a).abs()) / w;
            (f64::from(lo.c[0]) + t * f64::from(hi.c[0] - lo.c[0]), f64::from(lo.a) + t * f64::from(hi.a - lo.a), l)
        };
        let m = cps.iter().fold(s.abs(), |m, p| m.max(p.s.abs()));
        let bound = tol::TF_EVAL_BASE + slope * tol::TF_EVAL_PER_SLOPE * f64::from(m);
        let err = (f64::from(c[0]) - want_c).abs().max((f64::from(a) - want_a).abs());
        prop_assert!(err <= bound, "s={s}: {err:e} > {bound:e}");
    }

    #[test]
    fn trilinear_weights_match_products(f in [0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0]) {
        let w = trilinear_weights(f);
        let [x, y, z] = f.map(f64::from);
        for (i, wi) in w.iter().enumerate() {
            let ax = if i & 1 == 1 { x } else { 1.0 - x };
            let ay = if i & 2 == 2 { y } else { 1.0 - y };
            let az = if i & 4 == 4 { z } else { 1.0 - z };
            let err = (f64::from(*wi) - ax * ay * az).abs();
            prop_assert!(err <= tol::TRILINEAR_WEIGHT_ABS, "w[{i}]: {err:e}");
        }
    }

    #[test]
    fn isosurface_opacity_matches_reference(
        f_v in 0.0f32..255.0, alpha_v in 0.0f32..=1.0, r in 0.1f32..4.0, f in 0.0f32..255.0, g in 0.0f32..100.0,
    ) {
        let iso = Isosurface::new(f_v, alpha_v, r).unwrap();
        let want = reference::RefIsosurface { f_v: f64::from(f_v), alpha_v: f64::from(alpha_v), r: f64::from(r) }
            .opacity(f64::from(f), f64::from(g));
        let got = f64::from(iso.opacity(f, g));
        // At the edge |f_v − f| = r·g the f32 comparison may fall on either side; both sides are
        // within the bound of 0 there.
        prop_assert!((got - want).abs() <= tol::ISOSURFACE_ABS, "{got} vs {want}");
    }

    #[test]
    fn gradient_matches_reference(vals in prop::collection::vec(0.0f32..255.0, 27), p in [0usize..3, 0usize..3, 0usize..3]) {
        let vol = Volume::new(&vals, [3, 3, 3]).unwrap();
        let got = gradient(&vol, p[0], p[1], p[2]);
        let want = reference::central_gradient([3, 3, 3], &vals.iter().map(|&v| f64::from(v)).collect::<Vec<_>>(), p);
        let m = vals.iter().fold(0.0f32, |a, &b| a.max(b.abs()));
        for k in 0..3 {
            prop_assert!((f64::from(got[k]) - want[k]).abs() <= tol::GRADIENT_REL * f64::from(m));
        }
    }

    #[test]
    fn light_factor_matches_f64(
        dir in [-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0], g in [-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0],
        ka in 0.0f32..1.0, kd in 0.0f32..1.0,
    ) {
        prop_assume!(dir.iter().map(|x| x * x).sum::<f32>() > 1e-3);
        let light = Light::new(dir, ka, kd).unwrap();
        let got = f64::from(light.factor(g));
        let dn = dir.map(f64::from);
        let dl = dn.iter().map(|x| x * x).sum::<f64>().sqrt();
        let gn = g.map(f64::from);
        let gl = gn.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cos = if gl > 0.0 { (gn.iter().zip(&dn).map(|(a, b)| a * b).sum::<f64>() / (gl * dl)).abs() } else { 1.0 };
        let want = (f64::from(ka) + f64::from(kd) * cos.min(1.0)).min(1.0);
        prop_assert!((got - want).abs() <= tol::LIGHT_FACTOR_ABS, "{got} vs {want}");
    }
}

/// `phi_poly` against the f64 `φ`: every `f32` from `2⁻¹²` up to `PHI_POLY_BELOW` (where the
/// polynomial's own error and its rounding matter) and every 61st below, down to 0, within
/// `PHI_POLY_REL`; two threads.
#[test]
fn phi_poly_relative_error() {
    let worst_in = |bits: std::ops::Range<u32>, stride: usize| {
        let mut worst = (0.0f64, 0.0f32);
        for b in bits.step_by(stride) {
            let x = f32::from_bits(b);
            let want = reference::phi(f64::from(x));
            let rel = ((f64::from(phi_poly(x)) - want) / want).abs();
            if rel > worst.0 {
                worst = (rel, x);
            }
        }
        worst
    };
    let (lo, hi) = ((2.0f32).powi(-12).to_bits(), PHI_POLY_BELOW.to_bits());
    let mid = lo + (hi - lo) / 2;
    let worst = std::thread::scope(|s| {
        let upper = s.spawn(|| worst_in(mid..hi, 1));
        let parts = [worst_in(lo..mid, 1), worst_in(0..lo, 61)];
        parts
            .into_iter()
            .chain(upper.join().ok())
            .fold((0.0f64, 0.0f32), |a, b| if b.0 > a.0 { b } else { a })
    });
    assert_eq!(phi_poly(0.0), 1.0);
    println!(
        "phi_poly: worst relative error {:.3} of the bound, at x = {:e}",
        worst.0 / tol::PHI_POLY_REL,
        worst.1
    );
    assert!(
        worst.0 <= tol::PHI_POLY_REL,
        "{:e} at x = {:e}",
        worst.0,
        worst.1
    );
}

/// Below `τd = 1`, `integrate_step` is `α = x·φ` and `C̃ = C^τ·(d·φ)` with `φ = phi_poly(x)`
/// bit for bit (so that the kernels in lanes, which evaluate the same expressions, match it),
/// from tiny `τd` up to the branch at 1.
#[test]
fn integrate_step_below_one_uses_phi_poly_bit_for_bit() {
    let mut x = PHI_SERIES_BELOW / 64.0;
    let mut checked = 0;
    while x < PHI_POLY_BELOW {
        for d in [0.25f32, 0.5, 1.0, 1.7] {
            let tau = x / d;
            let xd = tau * d;
            if xd >= PHI_POLY_BELOW {
                continue;
            }
            let c_tau = [0.3 * tau, 0.6 * tau, 0.9 * tau];
            let s = integrate_step(c_tau, tau, d);
            let phi = phi_poly(xd);
            let a = xd * phi;
            let g = d * phi;
            let want = c_tau.map(|c| (c * g).max(0.0).min(a));
            assert_eq!(s.a.to_bits(), a.to_bits(), "α: τ = {tau}, d = {d}");
            assert_eq!(
                s.c.map(f32::to_bits),
                want.map(f32::to_bits),
                "C̃: τ = {tau}, d = {d}"
            );
            checked += 1;
        }
        x *= 1.0 + 1.0 / 64.0;
    }
    assert!(checked > 1000, "{checked} cases");
}

/// `correct` against the f64 correction (`α_d = −expm1(r·ln1p(−α))`, `C̃_d = C̃·α_d/α`) over
/// the series form's whole domain (every 41st `f32` from `2⁻²⁴` up to `PSI_SERIES_BELOW`, and
/// the ulps around it) and the ratios where it holds and where `x = r·(−ln(1 − α))` crosses 1,
/// within `CORRECTION_ABS·max(1, r)`; two threads.
#[test]
fn correct_series_form_within_bound() {
    let ratios = [1e-3f32, 0.125, 0.37, 0.5, 0.9, 1.0, 1.4, 1.5, 2.5];
    let worst_of = |bits: &mut dyn Iterator<Item = u32>| {
        let mut worst = (0.0f64, 0.0f32, 0.0f32);
        for b in bits {
            let a = f32::from_bits(b);
            let s = Sample {
                c: [a, a * 0.5, a * 0.125],
                a,
            };
            for &r in &ratios {
                let got = correct(s, r);
                let ad = -(f64::from(r) * (-f64::from(a)).ln_1p()).exp_m1();
                let k = ad / f64::from(a);
                let want = [0, 1, 2].map(|i| f64::from(s.c[i]) * k);
                let err = want
                    .iter()
                    .zip(got.c)
                    .map(|(w, g)| (w - f64::from(g)).abs())
                    .fold((f64::from(got.a) - ad).abs(), f64::max);
                let frac = err / (tol::CORRECTION_ABS * f64::from(r.max(1.0)));
                if frac > worst.0 {
                    worst = (frac, a, r);
                }
            }
        }
        worst
    };
    let (lo, hi) = ((2.0f32).powi(-24).to_bits(), PSI_SERIES_BELOW.to_bits());
    let mid = lo + (hi - lo) / 2;
    let worst = std::thread::scope(|s| {
        let upper = s.spawn(|| worst_of(&mut (mid..hi + 64).step_by(41)));
        let near = (hi - 64..hi + 64).chain(lo..mid);
        let parts = [worst_of(&mut near.step_by(41))];
        parts
            .into_iter()
            .chain(upper.join().ok())
            .fold((0.0, 0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
    });
    println!(
        "correct: worst error {:.3} of the bound, at α = {:e}, r = {}",
        worst.0, worst.1, worst.2
    );
    assert!(worst.0 <= 1.0, "{worst:?}");
}
