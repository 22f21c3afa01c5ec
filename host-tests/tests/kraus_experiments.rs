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
