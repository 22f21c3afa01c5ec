//! Kraus & Bürger 2008 experiments (`volsample_host::kraus`) and the filter-design evaluator
//! (`volsample_host::filters`), checked against closed forms derived by hand below.

use volsample_host::filters::{bspline, cascade, evaluate, minimise, Criterion, Recon};
use volsample_host::kraus::{
    self, artifact_rms, fig4_core, fig4_exact, fig4_model, Method, Scene36, ARTIFACT_RMS, TAU_MAX,
};

// ---------------------------------------------------------------------------------------------
// Figs. 1 and 4.

/// Extinction-based sampling is exact whenever `d = 1/m`, for every phase and `τ_max` (proof in
/// the `kraus` module docs: the Riemann sum of the hat is then constant in the phase). The f64
/// model must reproduce `1 − e^(−τ_max)` to rounding.
#[test]
fn extinction_is_exact_for_d_one_over_m() {
    for &t in &TAU_MAX {
        for m in 1..=12 {
            let d = 1.0 / f64::from(m);
            for j in 0..50 {
                let r = f64::from(j) / 50.0 + 0.0037;
                let got = fig4_model(Method::ExtinctionBased, t, d, r.fract());
                assert!(
                    (got - fig4_exact(t)).abs() < 1e-12,
                    "τ {t}, d 1/{m}, r {r}: {got}"
                );
            }
        }
    }
    // … and not for other d: d = 0.7, τ_max = 1 misses by more than 1 %.
    let worst = (0..100)
        .map(|j| {
            (fig4_model(Method::ExtinctionBased, 1.0, 0.7, f64::from(j) / 100.0) - fig4_exact(1.0))
                .abs()
        })
        .fold(0.0, f64::max);
    assert!(worst > 0.01, "{worst}");
}

/// The opacity-based method (`d′ = d`) is not exact even at `d = 1/m`: with `d = ½`,
/// `τ_max = 4`, `r = 0` the samples hit the column and its half-way points:
/// `α_v = 1 − e^(−2)`, `α = 1 − (1 − α_v)·(1 − α_v/2)² ≈ 0.9564` (derived by hand), below
/// `1 − e^(−4)`.
#[test]
fn opacity_based_closed_form_at_half() {
    let a_v = 1.0 - (-2.0f64).exp();
    let want = 1.0 - (1.0 - a_v) * (1.0 - a_v / 2.0).powi(2);
    let got = fig4_model(Method::OpacityBased, 4.0, 0.5, 0.0);
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    assert!(fig4_exact(4.0) - got > 0.02); // 0.9564 against 0.9817
}

/// Over `0.5 < d < 1` extinction-based sampling is closer to the exact opacity than
/// opacity-based sampling for every `τ_max` (Kraus fig. 4).
#[test]
fn extinction_beats_opacity_over_typical_steps() {
    let rows = kraus::fig4_sweep(100, 50);
    for (t, o, e) in kraus::fig4_max_errors(&rows, 0.5, 1.0) {
        assert!(e < o, "τ_max {t}: extinction {e} vs opacity {o}");
    }
}

/// The f64 model against the same ray through the core's `RayMarcher` (f32, bilinear via
/// `Trilinear` on a `9 × 2 × 1` volume): within `2e-5` (position and `exp` rounding in f32
/// over at most 3 nonzero samples, times `|∂α/∂x| ≤ τ_max·d`).
#[test]
fn model_matches_core() {
    for &t in &[1.0f32, 2.0, 8.0] {
        for &d in &[0.3f32, 0.5, 0.77, 1.0, 1.6, 2.0] {
            for &r in &[0.0f32, 0.25, 0.6, 0.99] {
                for m in Method::ALL {
                    let core = fig4_core(m, t, d, r).unwrap();
                    let model = fig4_model(m, f64::from(t), f64::from(d), f64::from(r));
                    assert!(
                        (f64::from(core) - model).abs() < 2e-5,
                        "{m:?} τ {t} d {d} r {r}: core {core} model {model}"
                    );
                }
            }
        }
    }
}

/// CSV and PNG outputs are well formed.
#[test]
fn csv_and_png_outputs() {
    let rows = kraus::fig4_sweep(20, 10);
    let csv = kraus::fig4_csv(&rows);
    assert_eq!(csv.lines().count(), 1 + 4 * 20 * 10);
    assert!(csv.starts_with("tau_max,d,r,alpha_opacity,alpha_extinction,alpha_exact\n"));
    let (w, h, rgb) = kraus::fig4_image(&rows, 20, 10, 2);
    assert_eq!(rgb.len(), (w * h * 3) as usize);
    let png = kraus::encode_png(w, h, &rgb).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(png));
    let reader = decoder.read_info().unwrap();
    assert_eq!((reader.info().width, reader.info().height), (w, h));
}

// ---------------------------------------------------------------------------------------------
// §3.6.

/// The wall at `d = d′`: at `d = 0.25` neither method shows artifacts; opacity-based sampling
/// fails the criterion (RMS against the converged rendering above one 8-bit step) by `d = 0.6`
/// (the paper: first artifacts at about 0.6), extinction-based sampling passes up to `d = 2`
/// (the paper: about 1.6). `volsample kraus` prints the exact thresholds of the sweep.
#[test]
fn wall_thresholds() {
    let rms = |m: Method, d: f32| {
        let img = kraus::scene36(Scene36::Wall, m, d, d).unwrap();
        let lim = kraus::scene36(Scene36::Wall, m, d / kraus::REFINE, d).unwrap();
        artifact_rms(&img, &lim)
    };
    for m in Method::ALL {
        assert!(rms(m, 0.25) < ARTIFACT_RMS, "{m:?} at 0.25");
    }
    assert!(rms(Method::OpacityBased, 0.6) > ARTIFACT_RMS);
    for d in [0.6, 1.0, 1.6, 2.0] {
        assert!(
            rms(Method::ExtinctionBased, d) < ARTIFACT_RMS,
            "extinction at {d}"
        );
    }
    let sweep = [(0.1, 0.0), (0.2, 0.01), (0.3, 0.0)];
    assert_eq!(kraus::first_failure(&sweep), Some(0.2));
}

// ---------------------------------------------------------------------------------------------
// The filter-design evaluator.

/// The cubic B-spline (autocorrelation of the hat) at `s`, by hand:
/// `2/3 − s² + |s|³/2` for `|s| ≤ 1`, `(2 − |s|)³/6` for `1 ≤ |s| ≤ 2`.
fn hat_autocorrelation(s: f64) -> f64 {
    let s = s.abs();
    if s <= 1.0 {
        2.0 / 3.0 - s * s + s * s * s / 2.0
    } else if s <= 2.0 {
        (2.0 - s).powi(3) / 6.0
    } else {
        0.0
    }
}

#[test]
fn bsplines() {
    assert!((bspline(1, 0.25) - 0.75).abs() < 1e-15);
    assert!((bspline(2, 0.0) - 0.75).abs() < 1e-15);
    assert!((bspline(2, 1.0) - 0.125).abs() < 1e-15);
    assert!((bspline(5, 0.0) - 11.0 / 20.0).abs() < 1e-14);
    for &x in &[0.0, 0.3, 0.5, 1.25, 1.9, 2.5] {
        assert!(
            (bspline(3, x) - hat_autocorrelation(x)).abs() < 1e-14,
            "{x}"
        );
    }
    for m in 1..=5 {
        let s: f64 = (-4..=4).map(|k| bspline(m, 0.37 - f64::from(k))).sum();
        assert!((s - 1.0).abs() < 1e-13, "partition of unity, degree {m}");
    }
}

/// One level (`n = 1`), linear reconstruction, any `a` (`b = ½ − a`), derived by hand.
///
/// The two fine voxels of the level-1 cell have phases `¼`, `¾`, i.e. positions `u = ∓¼`.
/// Impulse at fine 0 reaches coarse 0 with weight `b` and coarse −1 with `a`; normalised to
/// unit mass (×2): `K_0(u) = 2b·h(u − ¼) + 2a·h(u + ¾)`; the other is its mirror image
/// `K_1(u) = 2b·h(u + ¼) + 2a·h(u − ¾)`. With `c = h ⋆ h` (`c(0) = 2/3`, `c(½) = 23/48`,
/// `c(1) = 1/6`, `c(3/2) = 1/48`):
///
/// * `A = ∫K_0² = ∫K_1² = 4·((a² + b²)·c(0) + 2ab·c(1))`,
/// * `X = ∫K_0·K_1 = 4·((b² + 2ab)·c(½) + a²·c(3/2))`,
/// * `B = ∫K̄² = ¼(2A + 2X) = ½(A + X)`, so `ε² = A − B = ½(A − X)`;
/// * `K_0(0) = K_1(0) = 2b·¾ + 2a·¼` (mirror images), so `ε_c = 0`;
/// * separable 2D: `ε₂² = A² − B²`, `ε_{c,2} = 0`.
///
/// For `a = 0`: `ε² = ½(2/3 − 23/48) = 3/32`; for `a = ¼`: `ε² = ½(5/12 − 35/96) = 5/192`.
#[test]
fn one_level_closed_form() {
    for &a in &[0.0, 0.1, 0.125, 0.2, 0.25, 0.4, -0.1] {
        let b = 0.5 - a;
        let big_a = 4.0 * ((a * a + b * b) * (2.0 / 3.0) + 2.0 * a * b / 6.0);
        let x = 4.0 * ((b * b + 2.0 * a * b) * (23.0 / 48.0) + a * a / 48.0);
        let eps2 = 0.5 * (big_a - x);
        let big_b = 0.5 * (big_a + x);
        let q = evaluate(a, Recon::Linear, 1);
        assert!(
            (q.eps() - eps2.sqrt()).abs() < 1e-13,
            "a = {a}: {} vs {}",
            q.eps(),
            eps2.sqrt()
        );
        assert!(q.eps_c() < 1e-7, "a = {a}: ε_c = {}", q.eps_c());
        assert!((q.eps_nd(2) - (big_a * big_a - big_b * big_b).sqrt()).abs() < 1e-13);
        assert!(q.eps_c_nd(2) < 1e-7);
    }
    assert!((evaluate(0.0, Recon::Linear, 1).eps() - (3.0f64 / 32.0).sqrt()).abs() < 1e-14);
    assert!((evaluate(0.25, Recon::Linear, 1).eps() - (5.0f64 / 192.0).sqrt()).abs() < 1e-14);
}

/// Two levels of the 2-tap box, linear: every fine voxel of the level-2 cell lands on coarse
/// voxel 0 with weight 1 (normalised), so `K_k(u) = h(u + u_k)` with `u_k = −⅜, −⅛, ⅛, ⅜`.
/// `K_k(0) = h(u_k) = ⅝, ⅞, ⅞, ⅝`: mean `¾`, `ε_c = ⅛`. `A = c(0) = 2/3`;
/// `B = (1/16)·Σ_{k,k′} c(u_k − u_k′) = (4c(0) + 6c(¼) + 4c(½) + 2c(¾))/16` with
/// `c(¼) = 235/384`, `c(½) = 184/384`, `c(¾) = 121/384`: `B = 3412/6144`, so
/// `ε² = 684/6144 = 57/512`.
///
/// As `n → ∞` the phases become uniform on `[−½, ½]`: `ε_c² = Var(1 − |s|) = 1/12 − 1/16 =
/// 1/48` and `ε² = 2/3 − ∫∫c(s − s′) = 2/3 − 2∫₀¹(1 − s)c(s)ds = 2/3 − 0.55 = 7/60`
/// (Kraus: "ε = 0.34 and ε_c = 0.14" for the 2-tap box).
#[test]
fn box_filter_closed_forms() {
    let q = evaluate(0.0, Recon::Linear, 2);
    assert!((q.eps_c() - 0.125).abs() < 1e-14, "{}", q.eps_c());
    assert!(
        (q.eps() - (57.0f64 / 512.0).sqrt()).abs() < 1e-14,
        "{}",
        q.eps()
    );
    let q = evaluate(0.0, Recon::Linear, 10);
    assert!(
        (q.eps() - (7.0f64 / 60.0).sqrt()).abs() < 1e-6,
        "{}",
        q.eps()
    );
    assert!(
        (q.eps_c() - (1.0f64 / 48.0).sqrt()).abs() < 1e-6,
        "{}",
        q.eps_c()
    );
}

/// The exact autocorrelation formulas against brute-force quadrature of the definition:
/// `K_k` sampled with 3-point Gauss–Legendre on every cell of the `1/(2N)` grid (exact for
/// the squared piecewise quadratics), `K̄` as the pointwise mean.
#[test]
fn evaluator_matches_quadrature() {
    for recon in Recon::ALL {
        for &a in &[0.0, 0.2, 0.3] {
            let n = 3u32;
            let nn = 1i64 << n;
            let nf = nn as f64;
            let gl = [
                (-(0.6f64).sqrt() / 2.0 + 0.5, 5.0 / 18.0),
                (0.5, 8.0 / 18.0),
                ((0.6f64).sqrt() / 2.0 + 0.5, 5.0 / 18.0),
            ];
            let cell = 1.0 / (2.0 * nf);
            let cells = (12.0 / cell) as i64;
            let mut sum_k = vec![0.0; (cells * 3) as usize];
            let mut sum_k2 = 0.0;
            for k in 0..nn {
                let (lo, g) = cascade(a, n, k);
                let uk = (k as f64 + 0.5) / nf - 0.5;
                for c in 0..cells {
                    for (qi, (x, w)) in gl.iter().enumerate() {
                        let u = -6.0 + (c as f64 + x) * cell;
                        let v: f64 = g
                            .iter()
                            .enumerate()
                            .map(|(i, gi)| gi * recon.eval(u + uk - (lo + i as i64) as f64))
                            .sum();
                        sum_k[(c * 3) as usize + qi] += v;
                        sum_k2 += w * cell * v * v;
                    }
                }
            }
            let a_mean = sum_k2 / nf;
            let mut b = 0.0;
            for c in 0..cells {
                for (qi, (_, w)) in gl.iter().enumerate() {
                    let m = sum_k[(c * 3) as usize + qi] / nf;
                    b += w * cell * m * m;
                }
            }
            let q = evaluate(a, recon, n);
            assert!((q.a_mean - a_mean).abs() < 1e-12, "{recon:?} a {a}: A");
            assert!((q.b_mean - b).abs() < 1e-12, "{recon:?} a {a}: B");
        }
    }
}

/// Kraus's figures: for linear reconstruction the 4-tap box gives `ε ≈ 0.057`,
/// `ε_c ≈ 0.0093`; the `ε_c`-optimal filter for quadratic B-spline sampling is close to
/// `a = ⅕` and for linear close to `a = ¼`.
#[test]
fn paper_figures_and_minimisers() {
    let q = evaluate(0.25, Recon::Linear, 10);
    assert!((q.eps() - 0.057).abs() < 0.001, "{}", q.eps());
    assert!((q.eps_c() - 0.0093).abs() < 0.0002, "{}", q.eps_c());
    let (a, _) = minimise(
        Recon::QuadraticBSpline,
        Criterion::EpsC,
        -0.25,
        0.5,
        75,
        6,
        8,
    );
    assert!((a - 0.2).abs() < 0.005, "{a}");
    let (a, _) = minimise(Recon::Linear, Criterion::EpsC, -0.25, 0.5, 75, 6, 8);
    assert!((a - 0.25).abs() < 0.01, "{a}");
}

// ---------------------------------------------------------------------------------------------
// §3.5: a fixed d′ > d.

/// The limit of the opacity-based fig. 1 ray with opacities for a fixed `d′` as `d → 0`,
/// derived by hand (see `docs/scenes.md`): the corrected transmittance is
/// `exp((d/d′)·Σ_k ln(1 − α_v·h(x_k))) → exp(−(1/d′)·∫ −ln(1 − α_v·h))`, and
/// `∫_(−1)^(1) −ln(1 − a·h(x)) dx = 2·(1 + (1 − a)·ln(1 − a)/a)`; with
/// `ln(1 − α_v) = −τ·d′` the optical depth is `D∞ = (2/d′)·(1 − τd′/(e^(τd′) − 1))`.
fn fixed_dref_limit(tau: f64, d_ref: f64) -> f64 {
    let x = tau * d_ref;
    let depth = 2.0 / d_ref * (1.0 - x / x.exp_m1());
    -(-depth).exp_m1()
}

/// Riemann-sum bound for [`fixed_dref_limit`]: `g(x) = −ln(1 − α_v·h(x))` is Lipschitz with
/// `L = α_v/(1 − α_v) = e^(τd′) − 1`, so `|d·Σ g(x_k) − ∫g| ≤ L·d²/2` per sample over the
/// `2/d + 2` samples that can touch the support: `L·d·(1 + d)`; the optical depth divides
/// this by `d′`, and `|∂α/∂D| ≤ 1`.
fn fixed_dref_riemann_bound(tau: f64, d: f64, d_ref: f64) -> f64 {
    (tau * d_ref).exp_m1() * d * (1.0 + d) / d_ref
}

/// Kraus §3.5: with opacities for a fixed `d′ > d`, opacity-based sampling (corrected to the
/// step) converges, as `d → 0`, to the closed-form limit `1 − e^(−D∞)` — not to the exact
/// `1 − e^(−τ)`: it underestimates, and the error does not shrink with `d`.
#[test]
fn fixed_dref_underestimates_and_does_not_converge() {
    // The gap the limit leaves must be far above the Riemann-sum error of the small steps.
    for &(tau, d_ref) in &[(1.0, 2.0), (2.0, 1.0), (4.0, 1.0), (1.0, 4.0)] {
        let exact = fig4_exact(tau);
        let limit = fixed_dref_limit(tau, d_ref);
        let gap = exact - limit;
        // D∞ < τ for every τd′ > 0 (convexity): the limit is below the exact opacity.
        assert!(gap > 0.01, "τ {tau}, d′ {d_ref}: gap {gap}");
        for m in [64u32, 256, 1024, 4096] {
            let d = d_ref / f64::from(m);
            let bound = fixed_dref_riemann_bound(tau, d, d_ref);
            for j in 0..7 {
                let r = f64::from(j) / 7.0;
                let got = kraus::fig4_model_fixed_dref(tau, d, d_ref, r);
                assert!(
                    (got - limit).abs() <= bound,
                    "τ {tau} d′ {d_ref} d {d} r {r}: {got} vs limit {limit} (bound {bound})"
                );
                // Underestimates by at least the gap less the Riemann error, at every d.
                assert!(
                    exact - got >= gap - bound,
                    "τ {tau} d′ {d_ref} d {d}: {got} vs exact {exact}"
                );
            }
        }
        // Does not converge: at d = d′/4096 the error is still at least 90 % of the gap.
        let tiny = kraus::fig4_model_fixed_dref(tau, d_ref / 4096.0, d_ref, 0.3);
        assert!(exact - tiny > 0.9 * gap, "τ {tau} d′ {d_ref}: {tiny}");
    }
    // "Considerably stronger deviations" than d′ = d: at d = ½, τ = 4, d′ = 2 against d′ = d
    // (the same phases), the largest error is larger.
    let worst = |d_ref: f64| {
        (0..50)
            .map(|j| {
                let r = f64::from(j) / 50.0;
                (kraus::fig4_model_fixed_dref(4.0, 0.5, d_ref, r) - fig4_exact(4.0)).abs()
            })
            .fold(0.0, f64::max)
    };
    assert!(worst(2.0) > worst(0.5), "{} vs {}", worst(2.0), worst(0.5));
}

/// [`kraus::fig4_model_fixed_dref`] with `d′ = d` is the opacity-based fig. 4 model.
#[test]
fn fixed_dref_model_reduces_to_fig4() {
    for &d in &[0.3, 0.5, 0.77, 1.6] {
        for &r in &[0.0, 0.4, 0.9] {
            let a = kraus::fig4_model_fixed_dref(4.0, d, d, r);
            let b = fig4_model(Method::OpacityBased, 4.0, d, r);
            assert!((a - b).abs() < 1e-12, "d {d} r {r}: {a} vs {b}");
        }
    }
}

/// The fixed-`d′` ray through the core's `RayMarcher` (which corrects the opacity, as
/// `d ≠ d′`) against the f64 model. Per nonzero sample: the correction's own
/// `CORRECTION_ABS·max(1, r)` and a compositing step `COMPOSITE_STEP`, plus the error of the
/// interpolated `α` (two nonzero taps, `2·INTERP_PER_TAP`) and of the sample position (`t`
/// and `x` below 16: two roundings of at most `2^−20`, so `16ε`, times the hat's slope
/// `α_v`), both through the correction's slope `K = r·(1 − α_v)^(r − 1)` (its largest value
/// on `[0, α_v]` for `r < 1`); over the `2/d + 1` samples on the hat's support (each
/// sample's error passes through the transmittance product with a factor at most 1).
#[test]
fn fixed_dref_core_matches_model() {
    use volsample_host::tolerance::{COMPOSITE_STEP, CORRECTION_ABS, EPS32, INTERP_PER_TAP};
    for &(tau, d_ref) in &[(1.0f32, 2.0f32), (4.0, 1.0)] {
        let a_v = -(-f64::from(tau) * f64::from(d_ref)).exp_m1();
        for &d in &[d_ref / 8.0, d_ref / 32.0, 0.3] {
            let r = f64::from(d / d_ref);
            let slope = if r < 1.0 {
                r * (1.0 - a_v).powf(r - 1.0)
            } else {
                r
            };
            let per_sample = CORRECTION_ABS * r.max(1.0)
                + COMPOSITE_STEP
                + slope * (2.0 * INTERP_PER_TAP + 16.0 * EPS32 * a_v);
            let bound = per_sample * (2.0 / f64::from(d) + 1.0);
            for &phase in &[0.0f32, 0.37, 0.8] {
                let core = kraus::fig4_core_fixed_dref(tau, d, d_ref, phase).unwrap();
                let model = kraus::fig4_model_fixed_dref(
                    f64::from(tau),
                    f64::from(d),
                    f64::from(d_ref),
                    f64::from(phase),
                );
                assert!(
                    (f64::from(core) - model).abs() <= bound,
                    "τ {tau} d′ {d_ref} d {d} r {phase}: core {core} model {model} (bound {bound})"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Fig. 7: the scattered voxels, as the paper set it up.

/// The exact line integral of the trilinear field against closed forms derived by hand, for
/// one voxel of value 1 at `(10, 10, 10)` (the field is the product of three hats):
/// along `x` through its centre `∫h = 1`; along `x` at `(y, z) = (10.5, 10.25)`
/// `h(½)·h(¼)·∫h = 0.375`; along `(1, 1, 0)/√2` through it `√2·∫h² = √2·⅔`; a line that
/// misses the support gives 0; and a voxel on the grid's face `x = 0` is extended to
/// `x = −½` by the clamp to the edge: along `x` through it, `½ + ∫_0^1 h = 1`.
#[test]
fn line_integral_closed_forms() {
    let mut f = vec![0.0f64; 24 * 24 * 24];
    f[10 + 24 * (10 + 24 * 10)] = 1.0;
    let li = kraus::line_integral_trilinear;
    let s2 = std::f64::consts::SQRT_2;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(li(&f, [-5.0, 10.0, 10.0], [1.0, 0.0, 0.0]), 1.0));
    assert!(close(li(&f, [-5.0, 10.5, 10.25], [1.0, 0.0, 0.0]), 0.375));
    let got = li(&f, [5.0, 5.0, 10.0], [1.0 / s2, 1.0 / s2, 0.0]);
    assert!(close(got, s2 * 2.0 / 3.0), "{got}");
    assert_eq!(li(&f, [-5.0, 12.0, 10.0], [1.0, 0.0, 0.0]), 0.0);
    let mut g = vec![0.0f64; 24 * 24 * 24];
    g[24 * (10 + 24 * 10)] = 1.0;
    assert!(close(li(&g, [-5.0, 10.0, 10.0], [1.0, 0.0, 0.0]), 1.0));
}

/// The sample phases of the fig. 7 measures (viewing parameters: where the samples fall).
const FIG7_PHASES: usize = 4;
/// The optical depths per voxel of the paper's experiments (fig. 4's `τ_max`): `τ = 4` is the
/// paper's "almost opaque" voxel (`α = 0.98` over one voxel).
const FIG7_TAUS: [f32; 4] = [1.0, 2.0, 4.0, 8.0];

/// RMS and mean of `image − exact` over the pixels.
fn rms_and_mean(image: &[f32], exact: &[f64]) -> (f64, f64) {
    let n = exact.len() as f64;
    let (mut s, mut s2) = (0.0, 0.0);
    for (a, e) in image.iter().zip(exact) {
        let v = f64::from(*a) - e;
        s += v;
        s2 += v * v;
    }
    ((s2 / n).sqrt(), s / n)
}

/// Kraus fig. 7 as the paper ran its experiments (§3.5): the scattered voxels hold a fixed
/// extinction `τ` (the opacity-based data are `α_v = 1 − e^(−τd)` for `d′ = d`), and the
/// criterion is the distance from the exact emission–absorption integral of the voxels'
/// interpolated extinction field (`kraus::scene36_exact`, integrated exactly, independent of
/// the core), over [`FIG7_PHASES`] sample phases. Extinction-based sampling is closer at
/// every step `d ∈ {0.2, 0.4, …, 1.6}` and every `τ` of [`FIG7_TAUS`], and fails the
/// artifact criterion (RMS above one 8-bit step, `ARTIFACT_RMS`) at a larger `d`: the paper's
/// ranking.
#[test]
fn fig7_paper_setup_extinction_is_closer_to_exact() {
    for tau in FIG7_TAUS {
        let exact = kraus::scene36_exact(Scene36::Scattered, f64::from(tau)).unwrap();
        let mut first = [None, None];
        for i in 1..=8 {
            let d = 0.2 * i as f32;
            let e = Method::ALL.map(|m| {
                kraus::fig7_measures(Scene36::Scattered, m, tau, d, FIG7_PHASES, &exact)
                    .unwrap()
                    .0
            });
            assert!(
                e[1] < e[0],
                "τ {tau}, d {d}: extinction {} vs opacity {}",
                e[1],
                e[0]
            );
            for k in 0..2 {
                if first[k].is_none() && e[k] > ARTIFACT_RMS {
                    first[k] = Some(d);
                }
            }
        }
        let [op, ex] = first.map(|f| f.unwrap_or(f32::INFINITY));
        assert!(
            ex > op,
            "τ {tau}: first failing d, extinction {ex} vs opacity {op}"
        );
    }
}

/// What the opacity-based error is: a systematic underestimate (the non-linear mapping of
/// §3.4), not noise. With `d′ = d`, at `d = 0.4` and `0.8` and `τ ∈ {2, 4, 8}`, the mean of
/// `α − exact` is negative and at least half the RMS error in magnitude; the extinction-based
/// mean error is below a quarter of its RMS (its error is sampling noise).
#[test]
fn fig7_opacity_based_error_is_an_underestimate() {
    for tau in [2.0f32, 4.0, 8.0] {
        let exact = kraus::scene36_exact(Scene36::Scattered, f64::from(tau)).unwrap();
        for d in [0.4f32, 0.8] {
            let op =
                kraus::scene36_tau(Scene36::Scattered, Method::OpacityBased, tau, d, 0.0).unwrap();
            let (rms, mean) = rms_and_mean(&op, &exact);
            assert!(
                mean < -0.5 * rms,
                "opacity τ {tau} d {d}: mean {mean}, RMS {rms}"
            );
            let ex = kraus::scene36_tau(Scene36::Scattered, Method::ExtinctionBased, tau, d, 0.0)
                .unwrap();
            let (rms, mean) = rms_and_mean(&ex, &exact);
            assert!(
                mean.abs() < 0.25 * rms,
                "extinction τ {tau} d {d}: mean {mean}, RMS {rms}"
            );
        }
    }
}

/// The scattered voxels with a fixed `τ`, opacities for `d_ref`, rendered at step `d`
/// (phase 0) through the core: as `kraus::scene36_tau`, but with `d′` free, so that the
/// report's criterion (the same data at step `d/REFINE`) can be applied to the paper's data.
fn scattered_fixed_tau(method: Method, tau: f32, d: f32, d_ref: f32) -> Vec<f32> {
    use volsample::{
        ExtinctionF32, ExtinctionWeighted, FrontToBack, OpacityWeighted, RayMarcher, Sample, Step,
        StraightF32, Trilinear, Volume,
    };
    let occ = kraus::scene36_occupancy(Scene36::Scattered);
    let cam = kraus::scene36_camera().unwrap();
    let step = Step::new(d).unwrap();
    let mut img = vec![Sample::TRANSPARENT; kraus::IMAGE * kraus::IMAGE];
    let n = kraus::IMAGE;
    match method {
        Method::OpacityBased => {
            let a_v = -(-tau * d_ref).exp_m1();
            let vox: Vec<StraightF32> = occ
                .iter()
                .map(|&o| StraightF32 {
                    c: [1.0; 3],
                    a: if o > 0.0 { a_v } else { 0.0 },
                })
                .collect();
            let vol = Volume::new(&vox, [24; 3])
                .unwrap()
                .with_reference_distance(d_ref)
                .unwrap();
            let m = RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                step,
            );
            m.unwrap().render_into(&cam, n, n, &mut img).unwrap();
        }
        Method::ExtinctionBased => {
            let vox: Vec<ExtinctionF32> = occ
                .iter()
                .map(|&o| {
                    let t = if o > 0.0 { tau } else { 0.0 };
                    ExtinctionF32 {
                        c_tau: [t; 3],
                        tau: t,
                    }
                })
                .collect();
            let vol = Volume::new(&vox, [24; 3]).unwrap();
            let m = RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                step,
            );
            m.unwrap().render_into(&cam, n, n, &mut img).unwrap();
        }
    }
    img.iter().map(|s| s.a).collect()
}

/// Why `volsample kraus` ranks the methods the other way on the scattered voxels (first
/// failing `d` 0.20 for extinction-based against 0.40 for opacity-based), shown in three
/// computations:
///
/// 1. the report's setup — opaque voxels `α = 1`, so the extinction data are the capped
///    `τ = 64/d′` (`MAX_OPTICAL_DEPTH`), growing without bound as `d = d′` shrinks — and its
///    criterion (RMS against the same data at step `d/REFINE`): extinction-based fails
///    first;
/// 2. the same criterion on the paper's data (a fixed `τ` of [`FIG7_TAUS`] beyond 1, `d′ = d`):
///    no reversal, extinction-based fails no earlier;
/// 3. the report's capped data against the exact integral of their own extinction field
///    (`τ = 64/d`): extinction-based is closer at every `d` — the criterion of 1 measures how
///    fast each method converges to *its own* limit, and the opacity-based limit is far from
///    the exact image (an underestimate, as §3.5 predicts).
#[test]
fn fig7_report_reversal_comes_from_the_capped_data() {
    use kraus::{first_failure, sweep36, REFINE};
    // 1.
    let op = first_failure(&sweep36(Scene36::Scattered, Method::OpacityBased, 0.6).unwrap());
    let ex = first_failure(&sweep36(Scene36::Scattered, Method::ExtinctionBased, 0.6).unwrap());
    let (op, ex) = (op.unwrap_or(f32::INFINITY), ex.unwrap_or(f32::INFINITY));
    assert!(ex < op, "report setup: extinction {ex} vs opacity {op}");
    // 2.
    for tau in [2.0f32, 4.0, 8.0] {
        let first = Method::ALL.map(|m| {
            let sweep: Vec<(f32, f64)> = (1..=12)
                .map(|i| {
                    let d = 0.05 * i as f32;
                    let img = scattered_fixed_tau(m, tau, d, d);
                    let lim = scattered_fixed_tau(m, tau, d / REFINE, d);
                    (d, artifact_rms(&img, &lim))
                })
                .collect();
            first_failure(&sweep).unwrap_or(f32::INFINITY)
        });
        assert!(
            first[1] >= first[0],
            "paper data τ {tau}: extinction {} vs opacity {}",
            first[1],
            first[0]
        );
    }
    // 3.
    for d in [0.2f32, 0.4, 0.8] {
        let exact = kraus::scene36_exact(Scene36::Scattered, 64.0 / f64::from(d)).unwrap();
        let e = Method::ALL.map(|m| {
            let img = kraus::scene36(Scene36::Scattered, m, d, d).unwrap();
            rms_and_mean(&img, &exact).0
        });
        assert!(
            e[1] < e[0],
            "capped, d {d}: extinction {} vs opacity {}",
            e[1],
            e[0]
        );
    }
}
