//! Group 2, extinction: `τ = 0` and `−0`, subnormal `τ`, `τd` at the kernel's `τd = 1` branch
//! (`PHI_POLY_BELOW`: `phi_poly` below, `expm1f` from there on), huge (`MAX_TAU`) and capped
//! (`α = 1`) `τ`; `d/d′ = 10^±6` in every mode; `d′ → 0`.
//!
//! Already covered elsewhere: `φ` one ulp at a time across the switch-over and `integrate_step`
//! for `τ ∈ [10⁻⁴⁰, 10⁴]`, `d ∈ [10⁻⁴, 100]` against the absolute bound (`scalar_functions`);
//! extinction sampling at `d ∈ [10⁻³, 8]` (`float_vs_reference`); the integer extinction
//! kernel's extremes (`int_extinction::extremes_bit_exact_and_within_bounds`).

use volsample::mode::integrate_step;
use volsample::opacity::PHI_POLY_BELOW;
use volsample::voxel::MAX_TAU;
use volsample::{
    AssociatedF32, Error, ExtinctionF32, ExtinctionWeighted, FrontToBack, Nearest, OpacityWeighted,
    Preweighted, Ray, RayMarcher, Separate, Step, StraightF32, Trilinear, TriquadraticBSpline,
    Volume,
};
use volsample_host::edge_cases::{self as edge, alpha_edges, next_down, next_up};
use volsample_host::float_checks::{FilterKind, FloatCase, ModeKind};
use volsample_host::int_model::correction::exact_alpha;
use volsample_host::reference::{self, RefAssoc, RefExtinction};
use volsample_host::tolerance::{self as tol, hard_cases as hc};

use crate::common::{abs_err, assert_valid, rel_excess, Worst};

fn ref_step(c_tau: [f32; 3], tau: f32, d: f32) -> RefAssoc {
    reference::extinction_sample(
        RefExtinction {
            tau: f64::from(tau.max(0.0)),
            color_tau: c_tau.map(f64::from),
        },
        f64::from(d),
    )
}

fn step_case(wa: &mut Worst, wr: &mut Worst, tau: f32, d: f32, straight: f32) {
    let c_tau = [tau * straight, tau.max(0.0) * 0.5, 0.0].map(|c| c.max(0.0));
    let got = integrate_step(c_tau, tau, d);
    assert_valid(got, || format!("τ={tau:e} d={d:e}"));
    let want = ref_step(c_tau, tau, d);
    wa.check(abs_err(got, want), tol::INTEGRATE_STEP_ABS, || {
        format!("τ={tau:e} d={d:e}")
    });
    let e = rel_excess(got, want, hc::INTEGRATE_STEP_REL, 4.0 * hc::SUBNORMAL_FLOOR);
    wr.check(e, 1.0, || format!("τ={tau:e} d={d:e} C={straight}"));
}

/// `integrate_step` at `τ ∈ {0, −0, subnormal, …, MAX_TAU}` × `d ∈ {10⁻³⁰ … 10³⁰}`: absolute
/// error within `INTEGRATE_STEP_ABS`, and relative accuracy kept for faint steps
/// (`C̃ → C^τ·d`, `α → τd`).
#[test]
fn integrate_step_at_the_edges() {
    let mut wa = Worst::new(
        "2 integrate_step τ∈{0,−0,subnormal…MAX_TAU}×d∈{1e-30…1e30}",
        "mode::integrate_step",
        "abs",
    );
    let mut wr = Worst::new(
        "2 integrate_step same, relative (faint steps)",
        "mode::integrate_step",
        "×budget",
    );
    let taus = [
        0.0,
        -0.0,
        edge::MIN_SUBNORMAL,
        edge::MAX_SUBNORMAL,
        f32::MIN_POSITIVE,
        1e-30,
        1e-10,
        1e-4,
        0.5,
        1.0,
        64.0,
        1e6,
        1e18,
        MAX_TAU,
    ];
    let ds = [1e-30f32, 1e-18, 1e-6, 1e-3, 0.5, 1.0, 3.0, 1e6, 1e18, 1e30];
    for tau in taus {
        for d in ds {
            for c in [1.0, 0.3] {
                step_case(&mut wa, &mut wr, tau, d, c);
            }
        }
    }
    // `τd` one ulp at a time across the `τd = 1` branch.
    for centre in [PHI_POLY_BELOW] {
        for d in [1.0f32, 0.5, 1e-6, 1e6] {
            let mut x = centre;
            for _ in 0..64 {
                x = next_down(x);
            }
            let mut prev = None;
            for _ in 0..128 {
                let tau = x / d;
                step_case(&mut wa, &mut wr, tau, d, 1.0);
                // Monotone across the switch: α and C̃ = C^τ·α/τ grow with τ (C fixed).
                let s = integrate_step([tau; 3], tau, d);
                if let Some((pt, p)) = prev {
                    let p: volsample::Sample = p;
                    // Monotone up to the rounding of each side (the `τd = 1` branch switch
                    // may step back by one ulp).
                    let slack = |v: f32| f64::from(v) * (1.0 - 2.0 * hc::INTEGRATE_STEP_REL);
                    if tau >= pt {
                        assert!(
                            f64::from(s.a) >= slack(p.a) && f64::from(s.c[0]) >= slack(p.c[0]),
                            "not monotone at τd={x:e}, d={d}: {p:?} → {s:?}"
                        );
                    }
                }
                prev = Some((tau, s));
                x = next_up(x);
            }
        }
    }
    wa.report();
    wr.report();
}

/// One sample of `M` through a `1×1×1` volume at `d`.
fn one<V: volsample::voxel::Voxel, M: volsample::Mode<V>>(
    v: V,
    mode: M,
    d_ref: f32,
    d: f32,
) -> Result<volsample::Sample, Error> {
    let data = [v];
    let vol = Volume::new(&data, [1, 1, 1])?.with_reference_distance(d_ref)?;
    let m = RayMarcher::new(
        vol,
        mode,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(d)?,
    )?;
    Ok(m.sample([0.0; 3]))
}

/// Huge `τ` through the whole pipeline: `τ = MAX_TAU` renders opaque with the voxel's color at
/// every step down to `10⁻³` (1 700 samples), never NaN, in every filter.
#[test]
fn huge_tau_renders_opaque() {
    let mut w = Worst::new(
        "2 τ=MAX_TAU ray, every filter, d 1e-3…10",
        "RayMarcher::cast ExtinctionWeighted",
        "abs",
    );
    let e = ExtinctionF32 {
        c_tau: [MAX_TAU, MAX_TAU * 0.5, 0.0],
        tau: MAX_TAU,
    };
    let data = [e; 8];
    let vol = Volume::new(&data, [2, 2, 2]).unwrap();
    let ray = Ray::new([0.3, 0.6, -2.0], [0.1, -0.05, 1.0]).unwrap();
    for d in [1e-3f32, 0.1, 1.0, 10.0] {
        let step = Step::new(d).unwrap();
        let got = [
            RayMarcher::new(vol, ExtinctionWeighted, Nearest, FrontToBack::new(), step)
                .unwrap()
                .cast(&ray),
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                step,
            )
            .unwrap()
            .cast(&ray),
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::tree(),
                FrontToBack::new(),
                step,
            )
            .unwrap()
            .cast(&ray),
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                TriquadraticBSpline,
                FrontToBack::new(),
                step,
            )
            .unwrap()
            .cast(&ray),
        ];
        let n = RayMarcher::new(vol, ExtinctionWeighted, Nearest, FrontToBack::new(), step)
            .unwrap()
            .sample_range(&ray)
            .1;
        for g in got {
            assert_valid(g, || format!("d={d}"));
            let want = if n == 0 {
                RefAssoc::TRANSPARENT
            } else {
                RefAssoc::new([1.0, 0.5, 0.0], 1.0)
            };
            w.check(abs_err(g, want), tol::INTEGRATE_STEP_ABS, || {
                format!("d={d} n={n}")
            });
        }
    }
    w.report();
}

/// The derivative of the corrected opacity, `|∂α_d/∂α| = r·(1 − α)^(r−1)`: how much an error
/// of the interpolated `α` is magnified by correction (the conditioning, not the kernel).
fn correction_slope(a: f64, r: f64) -> f64 {
    if a >= 1.0 {
        return 0.0;
    }
    r * ((r - 1.0) * (-a).ln_1p()).exp()
}

/// Every mode × filter on uniform volumes of every edge opacity at `d/d′ = 10^±6` (and
/// 10^±3): within the sample bound carried through the correction's conditioning
/// (`|∂α_d/∂α|`), plus the correction's own relative error. For constant data the
/// interpolation is exact up to rounding, so the result is accurate wherever the problem is.
#[test]
fn extreme_ratios_every_mode_uniform_volumes() {
    let mut w = Worst::new(
        "2 d/d′=1e±6,1e±3, uniform α edges, every mode×filter",
        "sample, 5 modes × 4 filters + correct",
        "abs",
    );
    for a in alpha_edges() {
        for r in [1e-6f32, 1e-3, 1e3, 1e6] {
            let c = [1.0f32, 0.5, 0.25];
            let case = FloatCase {
                dims: [2, 2, 2],
                voxels: vec![StraightF32 { c, a }; 8],
                scalars: vec![100.0; 8],
                tf: vec![volsample::ControlPoint { s: 0.0, c, a }],
                d_ref: 1.0,
            };
            for pos in [[0.5f32, 0.5, 0.5], [0.0, 1.0, 0.25]] {
                for mode in ModeKind::ALL {
                    for filter in FilterKind::ALL {
                        let got = case.core_sample(mode, filter, pos, r);
                        assert_valid(got, || format!("{mode:?} {filter:?} α={a:e} r={r:e}"));
                        let want = case.reference_sample(mode, filter, pos, r);
                        let base = tol::sample_bound(mode, filter, &case, 1.0);
                        let bound = if mode == ModeKind::ExtinctionWeighted {
                            tol::sample_bound(mode, filter, &case, r) + tol::INTEGRATE_STEP_ABS
                        } else {
                            // α's error magnified by the slope, C̃'s by the gain α_d/α ≤ max(1, r)·ψ.
                            let af = f64::from(a);
                            let gain = if af > 0.0 {
                                exact_alpha(af, f64::from(r)) / af
                            } else {
                                f64::from(r)
                            };
                            base * correction_slope(af, f64::from(r)).max(gain).max(1.0)
                                + hc::CORRECTION_REL
                        };
                        w.check(abs_err(got, want), bound, || {
                            format!("{mode:?} {filter:?} α={a:e} r={r:e}")
                        });
                    }
                }
            }
        }
    }
    w.report();
}

/// `d′ → 0` at `d = 1`: the ratio `d/d′` grows to `10³⁸`; past `f32::MAX` the pipeline
/// reports [`Error::InvalidStep`]. Below that, every opacity-based mode gives the exact
/// limit (`α_d → 1`, `C̃_d → C`) and the extinction mode the capped `τ`'s (`α = 1`, `C̃ = C`).
/// Before the fix in `opacity::correct`, dense voxels (`α ≳ 0.97` at `d′ = 10⁻³⁸`) came out
/// opaque *black*: `r·(−ln(1 − α))` overflowed to `∞` and the gain `r·φ(∞)·ψ` was 0.
#[test]
fn reference_distance_to_zero() {
    let mut w = Worst::new(
        "2 d′→0 (1e-6…MIN_POSITIVE), every mode, α edges",
        "RayMarcher::sample, 5 modes + correct",
        "abs",
    );
    let d_refs = [
        1e-6f32,
        1e-20,
        1e-30,
        1e-37,
        f32::MIN_POSITIVE,
        edge::MAX_SUBNORMAL,
        edge::MIN_SUBNORMAL,
    ];
    for d_ref in d_refs {
        let r = 1.0 / d_ref;
        for a in alpha_edges().into_iter().filter(|&a| a > 0.0) {
            let c = [1.0f32, 0.5, 0.0];
            let sv = StraightF32 { c, a };
            let results = [
                one(sv, OpacityWeighted, d_ref, 1.0),
                one(sv, Separate, d_ref, 1.0),
                one(AssociatedF32::from_straight(sv), Preweighted, d_ref, 1.0),
            ];
            let a_d = exact_alpha(f64::from(a), f64::from(r));
            for got in results {
                if !r.is_finite() {
                    assert_eq!(got.unwrap_err(), Error::InvalidStep, "d′={d_ref:e}");
                    continue;
                }
                let got = got.unwrap();
                assert_valid(got, || format!("α={a:e} d′={d_ref:e}"));
                let want = RefAssoc::new(c.map(|c| f64::from(c) * a_d), a_d);
                let bound = hc::CORRECTION_REL + 4.0 * tol::EPS32;
                w.check(abs_err(got, want), bound, || {
                    format!("α={a:e} d′={d_ref:e} got {got:?}")
                });
            }
            let e = ExtinctionF32::from_straight(sv, d_ref);
            let got = one(e, ExtinctionWeighted, d_ref, 1.0).unwrap();
            let want = ref_step(e.c_tau, e.tau, 1.0);
            w.check(abs_err(got, want), tol::INTEGRATE_STEP_ABS, || {
                format!("ext α={a:e} d′={d_ref:e}")
            });
        }
    }
    w.report();
}
