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
//! Already covered elsewhere: front-to-back = back-to-front for 64 random samples
//! (`float_vs_reference`); the integer compositor's random and extreme sequences
//! (`int_composite`).

use volsample::composite::{back_to_front, front_to_back};
use volsample::fixed_point::{front_to_back as int_ftb, IntSample, ONE};
use volsample::mode::integrate_step;
use volsample::{
    AssociatedF32, BackToFront, ControlPoint, ExtinctionF32, ExtinctionWeighted, FrontToBack,
    OpacityWeighted, PostClassified, Preweighted, Ray, RayMarcher, Sample, Separate, Step,
    StraightF32, TransferFunction, Trilinear, Volume,
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
    let mut wa = Worst::new("3 10⁶ faint steps, A vs 1−e^(−Στd)", "abs");
    let mut wc = Worst::new("3 10⁶ faint steps, C̃ vs C·(1−e^(−Στd))", "abs");
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
    for a in [1e-6f32, 1e-3, 0.5, next_down(1.0), 1.0] {
        let s = Sample::clamped([0.7 * a, a, 0.0], a);
        let mut ftb = Sample::TRANSPARENT;
        let mut btf = Sample::TRANSPARENT;
        for k in 0..N {
            ftb = front_to_back(ftb, s);
            btf = back_to_front(btf, s);
            assert!(
                ftb.is_valid() && btf.is_valid(),
                "α={a:e} step {k}: {ftb:?} {btf:?}"
            );
        }
        assert!(ftb.a <= 1.0 && btf.a <= 1.0);
    }
}

/// A ray of `10⁶` samples through the whole pipeline in every mode (opacity-based modes with
/// correction to `d = 2·10⁻⁶·d′`), both orders: the pixel against `1 − (1 − α)^(n·d/d′)`,
/// the exact composite of the `n` segments.
#[test]
fn million_sample_ray_every_mode() {
    let mut wa = Worst::new("3 10⁶-sample ray, every mode, both orders", "abs");
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
/// never passes `ONE`, `C̃ ≤ A` throughout, and the result is within the compositor's stated
/// `n/2` (`A`) and `n` (`C̃`) LSB. The increments `⌊T·α_s/ONE + ½⌋` stop once
/// `T·α_s < ONE/2`, so a faint integer ray saturates at `A = ONE − ⌈ONE/(2α_s)⌉` or so:
/// the error against the exact `ONE·(1 − (1 − α_s/ONE)^n)` is about `ONE/(2α_s)` LSB —
/// half of full scale at `α_s` = 1 LSB. Within the stated bound, but a real limit of U8.8
/// front-to-back compositing of faint samples (reported in the closing table).
#[test]
fn integer_compositor_million_faint_samples() {
    let mut w = Worst::new(
        "3 int compositor 10⁶ faint samples (stall ≈ ONE/(2α_s))",
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
        let exact = one * (1.0 - (1.0 - f64::from(k) / one).powf(N as f64));
        let err = (f64::from(acc.a()) - exact).abs();
        let stall = one / (2.0 * f64::from(k)) + 1.0;
        assert!(
            err <= stall,
            "α_s={k}: error {err} beyond the stall level {stall}"
        );
        w.check(err, N as f64 * itol::COMPOSITE_INT_A_LSB_PER_STEP, || {
            format!("α_s={k} LSB, A={}", acc.a())
        });
    }
    w.report();
}
