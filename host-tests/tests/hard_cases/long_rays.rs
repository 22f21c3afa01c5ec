//! Group 3, long rays: `10⁶` samples of tiny opacity, against the exact `1 − e^(−Στd)`, and
//! no drift of `A` past 1 (or of `C̃` past `A`) over `10⁶` compositing steps.
//!
//! **The bound** (`tolerance::hard_cases::LONG_RAY_A_PER_SAMPLE`, `…_C_PER_SAMPLE`). One
//! front-to-back step `A ← A + fl(fl(1 − A)·α)` adds a rounding error of at most
//! `u·(1 + 3α)` (`u = 2⁻²⁴`: `1 − A` rounds only for `A < ½`, and then by `u·(1 − A)`,
//! multiplied by `α`; the product by `2u·α`; the sum by `u·A ≤ u`), and an error `e_k` of `A`
//! is carried on as `e_k·(1 − α_k)`, so after `n` steps `|e_n| ≤ n·u·(1 + 3α_max)`: linear in
//! `n`, not the `n·3ε` of the general compositor bound (`COMPOSITE_STEP`), 6 times
//! tighter. The color inherits `Σ|e_k|·α_k ≤ Σ r_k` (telescoping `|e_k|α_k ≤ |e_k| − |e_(k+1)|
//! + r_k`) and adds its own, so it is within twice that. Each sample's own relative error
//! (`≤ 12ε` after correction or integration) adds `12ε·Σα_k·(1 − A) ≤ 12ε·A`, negligible.
//!
//! **The integer bound** (`tolerance::hard_cases::int_compositor_a_lsb`,
//! `int_long_ray_a_lsb`). The integer compositor's documented `n/2` LSB is vacuous at
//! `n = 10⁶` (it exceeds `ONE`); its own recursion `e_(k+1) = e_k(1 − q_k) − r_k`,
//! `|r_k| ≤ ½`, gives `|e_n| ≤ ½·(1 − (1 − q_min)^n)/q_min ≤ min(n/2, ONE/(2x_min))`, which is
//! what is held here, and reached: faint integer rays stall at `T ≈ ONE/(2x)`. Against the
//! exact `1 − e^(−Στd)` of the stored data the samples' own rounding (`δ` LSB each) adds
//! `n·δ·(1 − s)^(n−1)`, `s` the smallest per-sample opacity.
//!
//! Already covered elsewhere: front-to-back = back-to-front for 64 random samples
//! (`float_vs_reference`); the integer compositor's random and extreme sequences
//! (`int_composite`).

use volsample::composite::{back_to_front, front_to_back};
use volsample::fixed_point::{front_to_back as int_ftb, IntSample, IntStop, ONE};
use volsample::mode::integrate_step;
use volsample::render::IntRayMarcher;
use volsample::{
    AssociatedF32, BackToFront, ControlPoint, ExtinctionF32, ExtinctionWeighted, FrontToBack,
    OpacityWeighted, PostClassified, Preweighted, Ray, RayMarcher, Sample, Separate, Step,
    StraightF32, StraightU8, TransferFunction, Trilinear, Volume,
};
use volsample_host::edge_cases::next_down;
use volsample_host::tolerance::hard_cases as hc;
use volsample_host::tolerance::integer as itol;

use crate::common::{assert_valid, Worst};

const N: usize = 1_000_000;

/// `10⁶` steps of `integrate_step` with `τd = 10⁻⁶` (and `10⁻⁷`, `10⁻⁵`), composited front to
/// back and back to front, against `1 − e^(−Στd)` in `f64`.
#[test]
fn million_faint_samples_against_the_exact_integral() {
    let mut wa = Worst::new(
        "3 10⁶ faint steps, A vs 1−e^(−Στd)",
        "composite front_to_back/back_to_front",
        "abs",
    );
    let mut wc = Worst::new(
        "3 10⁶ faint steps, C̃ vs C·(1−e^(−Στd))",
        "composite front_to_back/back_to_front",
        "abs",
    );
    for (tau, d) in [(1.0f32, 1e-6f32), (0.1, 1e-6), (1.0, 1e-5), (3.0, 2e-6)] {
        let straight = [1.0f32, 0.6, 0.1];
        let c_tau = straight.map(|c| c * tau);
        let s = integrate_step(c_tau, tau, d);
        let mut ftb = Sample::TRANSPARENT;
        let mut btf = Sample::TRANSPARENT;
        for _ in 0..N {
            ftb = front_to_back(ftb, s);
            btf = back_to_front(btf, s);
        }
        let sum = N as f64 * f64::from(tau) * f64::from(d);
        let a = -(-sum).exp_m1();
        let bound_a = N as f64 * hc::LONG_RAY_A_PER_SAMPLE * (1.0 + 3.0 * f64::from(s.a));
        let bound_c = N as f64 * hc::LONG_RAY_C_PER_SAMPLE * (1.0 + 3.0 * f64::from(s.a));
        for (name, acc) in [("front-to-back", ftb), ("back-to-front", btf)] {
            assert_valid(acc, || name.to_string());
            wa.check((f64::from(acc.a) - a).abs(), bound_a, || {
                format!("{name} τd={:e} Στd={sum}", tau * d)
            });
            for (k, (&got, &sc)) in acc.c.iter().zip(straight.iter()).enumerate() {
                let want = f64::from(sc) * a;
                wc.check((f64::from(got) - want).abs(), bound_c, || {
                    format!("{name} τd={:e} ch{k}", tau * d)
                });
            }
        }
    }
    wa.report();
    wc.report();
}

/// `10⁶` compositing steps of opacities from faint to opaque never take `A` past 1 or `C̃`
/// past `A`, in either order, checked after every step.
#[test]
fn no_drift_past_one() {
    let mut w = Worst::new(
        "3 10⁶ steps α∈{1e-6…1}: drift past A=1 or C̃ past A",
        "composite front_to_back/back_to_front",
        "abs",
    );
    for a in [1e-6f32, 1e-3, 0.5, next_down(1.0), 1.0] {
        let s = Sample::clamped([0.7 * a, a, 0.0], a);
        let mut ftb = Sample::TRANSPARENT;
        let mut btf = Sample::TRANSPARENT;
        // The largest overshoot of `A` past 1 or of a `C̃` past `A`, over every step.
        let mut drift = 0.0f32;
        for k in 0..N {
            ftb = front_to_back(ftb, s);
            btf = back_to_front(btf, s);
            for acc in [ftb, btf] {
                let over = acc.c.iter().fold(acc.a - 1.0, |m, &c| m.max(c - acc.a));
                drift = drift.max(over);
            }
            assert!(
                ftb.is_valid() && btf.is_valid(),
                "α={a:e} step {k}: {ftb:?} {btf:?}"
            );
        }
        w.check(f64::from(drift), 0.0, || format!("α={a:e}"));
    }
    w.report();
}

/// A ray of `10⁶` samples through the whole pipeline in every mode (opacity-based modes with
/// correction to `d = 2·10⁻⁶·d′`), both orders: the pixel against `1 − (1 − α)^(n·d/d′)`,
/// the exact composite of the `n` segments.
#[test]
fn million_sample_ray_every_mode() {
    let mut wa = Worst::new(
        "3 10⁶-sample ray, every mode, both orders",
        "RayMarcher::cast, 5 modes, both orders",
        "abs",
    );
    let a0 = 0.3f32;
    let c = [1.0f32, 0.5, 0.25];
    let sv = [StraightF32 { c, a: a0 }; 8];
    let assoc = sv.map(AssociatedF32::from_straight);
    let ext = sv.map(|v| ExtinctionF32::from_straight(v, 1.0));
    let scal = [50.0f32; 8];
    let tf = TransferFunction::<2>::new(&[ControlPoint { s: 0.0, c, a: a0 }]).unwrap();
    let step = Step::new(2e-6).unwrap();
    let ray = Ray::new([0.5, 0.5, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let dims = [2, 2, 2];
    macro_rules! run {
        ($data:expr, $mode:expr) => {{
            let vol = Volume::new(&$data, dims).unwrap();
            let f =
                RayMarcher::new(vol, $mode, Trilinear::new(), FrontToBack::new(), step).unwrap();
            let b = RayMarcher::new(vol, $mode, Trilinear::new(), BackToFront, step).unwrap();
            let n = f.sample_range(&ray).1;
            (n, f.cast(&ray), b.cast(&ray))
        }};
    }
    let results = [
        ("Separate", run!(sv, Separate)),
        ("OpacityWeighted", run!(sv, OpacityWeighted)),
        ("Preweighted", run!(assoc, Preweighted)),
        ("ExtinctionWeighted", run!(ext, ExtinctionWeighted)),
        ("PostClassified", run!(scal, PostClassified::new(&tf))),
    ];
    for (name, (n, f, b)) in results {
        assert!(
            (999_999..=1_000_001).contains(&(n as usize)),
            "{name}: {n} samples"
        );
        let length = f64::from(n) * f64::from(step.d());
        let a = -(length * (-f64::from(a0)).ln_1p()).exp_m1();
        let alpha_s = -(f64::from(step.d()) * (-f64::from(a0)).ln_1p()).exp_m1();
        let bound = f64::from(n) * hc::LONG_RAY_C_PER_SAMPLE * (1.0 + 3.0 * alpha_s);
        for (order, px) in [("ftb", f), ("btf", b)] {
            assert_valid(px, || format!("{name} {order}"));
            wa.check((f64::from(px.a) - a).abs(), bound / 2.0, || {
                format!("{name} {order} A")
            });
            for (k, (&got, &ck)) in px.c.iter().zip(c.iter()).enumerate() {
                wa.check((f64::from(got) - f64::from(ck) * a).abs(), bound, || {
                    format!("{name} {order} C{k}")
                });
            }
        }
    }
    wa.report();
}

/// The integer compositor over `10⁶` faint samples (`α_s` = 1, 2, 16, 256 U8.8 LSB): `A`
/// never passes `ONE`, `C̃ ≤ A` throughout, and the result is within
/// `int_compositor_a_lsb(n, α_s)` of the exact `ONE·(1 − (1 − α_s/ONE)^n)`: the documented
/// `n/2` LSB taken through the compositor's own error recursion, which also caps it at
/// `ONE/(2α_s)`. The increments `⌊T·α_s/ONE + ½⌋` stop once `T·α_s < ONE/2`, so a faint
/// integer ray **stalls** at `A ≈ ONE − ONE/(2α_s)`: half of full scale at `α_s` = 1 LSB. The
/// bound is reached (ratio ≈ 1 in the closing table): a real limit of U8.8 front-to-back
/// compositing of faint samples, stated, not hidden.
#[test]
fn integer_compositor_million_faint_samples() {
    let mut w = Worst::new(
        "3 int compositor 10⁶ faint samples α_s=1…256 LSB (stall ≤ ONE/(2α_s))",
        "fixed_point::front_to_back",
        "LSB",
    );
    for k in [1u16, 2, 16, 256] {
        let s = IntSample::new([k, k / 2, 0], k).unwrap();
        let mut acc = IntSample::TRANSPARENT;
        for step in 0..N {
            let next = int_ftb(acc, s);
            assert!(
                next.a() >= acc.a() && next.a() <= ONE && next.c().iter().all(|&c| c <= next.a()),
                "α_s={k} step {step}"
            );
            acc = next;
        }
        let one = f64::from(ONE);
        let q = f64::from(k) / one;
        let exact = one * -((N as f64) * (-q).ln_1p()).exp_m1();
        let err = (f64::from(acc.a()) - exact).abs();
        w.check(err, hc::int_compositor_a_lsb(N as u64, k), || {
            format!("α_s={k} LSB, A={}", acc.a())
        });
    }
    w.report();
}

/// One uniform `1×1×N` column of straight bytes `[255, 128, 0, a]` marched along `z` with
/// step `d` (`d′ = 1`): `n ≈ N/d` samples, every one the same integer sample.
fn int_column_ray<const F: u32>(w: &mut Worst, a: u8, d: f32) {
    let len = (N as f64 * f64::from(d)).ceil() as usize;
    let vox = vec![StraightU8([255, 128, 0, a]); len];
    let vol = Volume::new(&vox, [1, 1, len]).unwrap();
    let m = IntRayMarcher::<_, _, _, F>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        Step::new(d).unwrap(),
    )
    .unwrap();
    let ray = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let n = m.sample_range(&ray).1;
    assert!((999_000..=1_001_000).contains(&n), "{n} samples");
    // Uniform: every sample, wherever it falls, is the same.
    let s = m.sample([0.0, 0.0, 0.0]);
    for z in [0.37f32, len as f32 / 2.0 + 0.5, len as f32 - 1.0] {
        assert_eq!(m.sample([0.0, 0.0, z]), s, "F={F} z={z}");
    }
    // The sample against the exact corrected opacity: the sampler's ½ LSB, and the
    // correction's bound when d ≠ d′ (its slope r·(1 − α)^(r−1) ≤ 1 here: r ≤ 1).
    let r = f64::from(d);
    let p = -(r * (-f64::from(a) / 255.0).ln_1p()).exp_m1();
    let one = f64::from(ONE);
    let delta = itol::OPACITY_WEIGHTED_INT_LSB
        + if d == 1.0 {
            0.0
        } else {
            itol::CORRECTION_INT_LSB
        };
    assert!(
        (f64::from(s.a()) - one * p).abs() <= delta,
        "F={F} a={a} d={d}: sample {} vs {}",
        s.a(),
        one * p
    );
    let px = m.cast(&ray);
    assert!(
        px.a() <= ONE && px.c().iter().all(|&c| c <= px.a()),
        "{px:?}"
    );
    // C̃ = α per sample (white channel): the same increments as A; black stays 0.
    assert_eq!((px.c()[0], px.c()[2]), (px.a(), 0), "F={F} a={a} d={d}");
    let exact = one * -(f64::from(n) * r * (-f64::from(a) / 255.0).ln_1p()).exp_m1();
    let bound = hc::int_long_ray_a_lsb(u64::from(n), s.a(), p, delta);
    w.check((f64::from(px.a()) - exact).abs(), bound, || {
        format!(
            "F={F} α=byte {a} d={d} n={n}: A={} (sample {} LSB)",
            px.a(),
            s.a()
        )
    });
}

/// A `1×1×10⁶` column of bytes cycling through `α` = 1, 2, 3 (of 255), sampled on the voxel
/// centres at `d = d′`: `10⁶` different faint samples, exact positions at every `F` (up to
/// `(10⁶ − 1)·2^12 < 2^32`), against `ONE·(1 − Π(1 − α_k))`.
fn int_varying_column<const F: u32>(w: &mut Worst, vox: &[StraightU8]) {
    let vol = Volume::new(vox, [1, 1, vox.len()]).unwrap();
    let m = IntRayMarcher::<_, _, _, F>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        Step::new(1.0).unwrap(),
    )
    .unwrap();
    let ray = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let (t0, n) = m.sample_range(&ray);
    assert_eq!((t0, n as usize), (1.0, vox.len()), "centres z = 0 … N − 1");
    let px = m.cast(&ray);
    assert!(
        px.a() <= ONE && px.c().iter().all(|&c| c <= px.a()),
        "{px:?}"
    );
    let log_t: f64 = vox
        .iter()
        .map(|v| (-f64::from(v.0[3]) / 255.0).ln_1p())
        .sum();
    let exact = f64::from(ONE) * -log_t.exp_m1();
    let a_min = vox.iter().map(|v| v.0[3]).min().unwrap();
    let bound = hc::int_long_ray_a_lsb(
        u64::from(n),
        256 * u16::from(a_min),
        f64::from(a_min) / 255.0,
        itol::OPACITY_WEIGHTED_INT_LSB,
    );
    w.check((f64::from(px.a()) - exact).abs(), bound, || {
        format!("F={F} varying column: A={}", px.a())
    });
}

/// The integer ray marcher over `10⁶` faint samples at `F` = 4, 8, 12: uniform columns whose
/// corrected samples are 1, 2, 16 and 128 U8.8 LSB (`d/d′ = 1/256 … 1/2`) and 256 LSB at
/// `d = d′`, and a column of varying faint bytes. `A` never passes `ONE`, and against the
/// exact `1 − e^(−Στd)` of the stored bytes it stays within `int_long_ray_a_lsb`: the
/// compositor's stall `≤ ONE/(2·α_min)` plus the samples' rounding carried through the
/// transmittance (a fraction of an LSB at `10⁶` samples). The stall is reached at 1 LSB.
#[test]
fn int_ray_marcher_million_faint_samples() {
    let mut w = Worst::new(
        "3 IntRayMarcher 10⁶ faint samples, F=4/8/12, α_s 1…256 LSB",
        "IntRayMarcher::cast OW trilinear + IntCorrection + front_to_back",
        "LSB",
    );
    let mut wv = Worst::new(
        "3 IntRayMarcher 10⁶ varying faint voxels on centres, F=4/8/12",
        "IntRayMarcher::cast OW trilinear + front_to_back",
        "LSB",
    );
    let cycle: Vec<StraightU8> = (0..N)
        .map(|i| StraightU8([255, 0, 128, 1 + (i % 3) as u8]))
        .collect();
    macro_rules! at_f {
        ($f:literal) => {
            for (a, d) in [
                (1u8, 1.0 / 256.0),
                (1, 1.0 / 128.0),
                (1, 1.0 / 16.0),
                (1, 0.5),
                (1, 1.0),
            ] {
                int_column_ray::<$f>(&mut w, a, d);
            }
            int_varying_column::<$f>(&mut wv, &cycle);
        };
    }
    at_f!(4);
    at_f!(8);
    at_f!(12);
    w.report();
    wv.report();
}
