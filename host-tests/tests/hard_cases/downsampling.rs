//! Group 7, downsampling: the same edges through one level and whole chains — faint
//! (subnormal) and opaque opacities, `τ` at 0, subnormal and near `MAX_TAU`, volumes of
//! `1×1×1`, `1×N×1` and `2×2×2`, filters at the ends of `a ∈ [0, ½]` (and one subnormal or
//! ulp inside them) — and mip-level sampling at `d′ → 0`.
//!
//! Already covered elsewhere: random chains against the reference for `a ∈ [0, ½]`, the
//! paper's example, constant volumes, `MAX_TAU` saturation (`downsample`).

use volsample::downsample::{build_chain, chain_len, ExtinctionBased, Filter4, OpacityBased};
use volsample::voxel::MAX_TAU;
use volsample::{
    AssociatedF32, ExtinctionF32, OpacityWeighted, Preweighted, Step, Trilinear, Volume,
};
use volsample_host::edge_cases::{alpha_edges, next_down, MIN_SUBNORMAL};
use volsample_host::reference::downsample as rd;
use volsample_host::reference::{RefAssoc, RefExtinction};
use volsample_host::tolerance::downsample as dtol;
use volsample_host::tolerance::hard_cases as hc;

use crate::common::Worst;

const DIMS: [[usize; 3]; 4] = [[1, 1, 1], [1, 7, 1], [2, 2, 2], [5, 3, 2]];

fn filters() -> Vec<(Filter4, f64)> {
    [0.0f32, MIN_SUBNORMAL, 0.125, 0.2, 0.25, next_down(0.5), 0.5]
        .into_iter()
        .map(|a| (Filter4::new(a).unwrap(), f64::from(a)))
        .collect()
}

/// Opacity-based chains over faint-to-opaque edge opacities, every size and filter: each
/// level within `opacity_chain(ℓ)` of the f64 chain, in range, `1×1×1` needing an empty
/// buffer.
#[test]
fn opacity_chains_at_the_edges() {
    let mut w = Worst::new(
        "7 opacity chains, α edges, 1×1×1…5×3×2, a∈{0,2⁻¹⁴⁹…½}",
        "build_chain OpacityBased",
        "abs",
    );
    let alphas = alpha_edges();
    for dims in DIMS {
        let n = dims[0] * dims[1] * dims[2];
        let fine: Vec<AssociatedF32> = (0..n)
            .map(|i| {
                let a = alphas[(i * 5 + 1) % alphas.len()];
                AssociatedF32 {
                    c: [a, a * 0.5, 0.0],
                    a,
                }
            })
            .collect();
        let reffine: Vec<RefAssoc> = fine
            .iter()
            .map(|v| RefAssoc::new(v.c.map(f64::from), f64::from(v.a)))
            .collect();
        for (f, a) in filters() {
            let mut out = vec![AssociatedF32::default(); chain_len(dims)];
            let chain =
                build_chain(OpacityBased, f, Volume::new(&fine, dims).unwrap(), &mut out).unwrap();
            let want = rd::chain(dims, &reffine, a, rd::downsample_opacity);
            assert_eq!(chain.len(), want.len(), "{dims:?}");
            for (l, (wd, wv)) in want.iter().enumerate().skip(1) {
                let level = chain.level(l as u32).unwrap().volume();
                assert_eq!(level.dims(), *wd);
                for (got, r) in level.data().iter().zip(wv) {
                    assert!(got.c.iter().all(|&c| (0.0..=got.a).contains(&c)) && got.a <= 1.0);
                    let err = (0..3)
                        .map(|k| (f64::from(got.c[k]) - r.color[k]).abs())
                        .fold((f64::from(got.a) - r.alpha).abs(), f64::max);
                    w.check(err, dtol::opacity_chain(l as u32), || {
                        format!("{dims:?} a={a:e} level {l}")
                    });
                }
            }
        }
    }
    w.report();
}

/// Uniform faint volumes keep relative accuracy through a level: the filter reproduces a
/// constant exactly, and `α′ = ᾱ(2 − ᾱ)` rounds twice (`DOWNSAMPLE_UNIFORM_REL`).
#[test]
fn uniform_faint_level_is_relatively_exact() {
    let mut w = Worst::new(
        "7 uniform level, α→0 … 1, relative",
        "build_chain OpacityBased",
        "×budget",
    );
    for a in alpha_edges() {
        let fine = [AssociatedF32 {
            c: [a, 0.5 * a, 0.0],
            a,
        }; 8];
        for (f, _) in filters() {
            let mut out = vec![AssociatedF32::default(); 1];
            let chain = build_chain(
                OpacityBased,
                f,
                Volume::new(&fine, [2, 2, 2]).unwrap(),
                &mut out,
            )
            .unwrap();
            let got = chain.level(1).unwrap().volume().data()[0];
            let af = f64::from(a);
            let want = af * (2.0 - af);
            let budget = |x: f64| hc::DOWNSAMPLE_UNIFORM_REL * x + 2.0 * hc::SUBNORMAL_FLOOR;
            w.check((f64::from(got.a) - want).abs() / budget(want), 1.0, || {
                format!("α={a:e} a={}", f.a())
            });
            let wc = f64::from(fine[0].c[1]) * (2.0 - af);
            w.check((f64::from(got.c[1]) - wc).abs() / budget(wc), 1.0, || {
                format!("C̃ α={a:e} a={}", f.a())
            });
        }
    }
    w.report();
}

/// Extinction-based chains with `τ ∈ {0, subnormal, 1, MAX_TAU/4}`: each level within
/// `extinction_chain(ℓ, τ_max)` of the f64 chain (below saturation), `C^τ ≤ τ ≤ MAX_TAU`.
#[test]
fn extinction_chains_at_the_edges() {
    let mut w = Worst::new(
        "7 extinction chains, τ∈{0,2⁻¹⁴⁹,1,MAX_TAU/4}",
        "build_chain ExtinctionBased",
        "rel τ_max",
    );
    let taus = [0.0f32, MIN_SUBNORMAL, 1.0, MAX_TAU / 4.0];
    for dims in DIMS {
        let n = dims[0] * dims[1] * dims[2];
        let fine: Vec<ExtinctionF32> = (0..n)
            .map(|i| {
                let t = taus[(i * 3 + 1) % taus.len()];
                ExtinctionF32 {
                    c_tau: [t, t * 0.5, 0.0],
                    tau: t,
                }
            })
            .collect();
        let tau_max = fine.iter().fold(0.0f64, |m, v| m.max(f64::from(v.tau)));
        let reffine: Vec<RefExtinction> = fine
            .iter()
            .map(|v| RefExtinction {
                tau: f64::from(v.tau),
                color_tau: v.c_tau.map(f64::from),
            })
            .collect();
        for (f, a) in filters() {
            let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
            let chain = build_chain(
                ExtinctionBased,
                f,
                Volume::new(&fine, dims).unwrap(),
                &mut out,
            )
            .unwrap();
            let want = rd::chain(dims, &reffine, a, rd::downsample_extinction);
            for (l, (_, wv)) in want.iter().enumerate().skip(1) {
                for (got, r) in chain
                    .level(l as u32)
                    .unwrap()
                    .volume()
                    .data()
                    .iter()
                    .zip(wv)
                {
                    assert!(got.tau <= MAX_TAU && got.c_tau.iter().all(|&c| c <= got.tau));
                    let sat = |x: f64| x.min(f64::from(MAX_TAU));
                    let err = (0..3)
                        .map(|k| (f64::from(got.c_tau[k]) - sat(r.color_tau[k])).abs())
                        .fold((f64::from(got.tau) - sat(r.tau)).abs(), f64::max);
                    let bound = dtol::extinction_chain(l as u32, tau_max) + hc::SUBNORMAL_FLOOR;
                    w.check(
                        err / tau_max.max(f64::MIN_POSITIVE),
                        bound / tau_max.max(f64::MIN_POSITIVE),
                        || format!("{dims:?} a={a:e} level {l}"),
                    );
                }
            }
        }
    }
    w.report();
}

/// Mip-level sampling at `d′ → 0` (`d/d′` up to `8.5·10³⁷`): dense opacity-based levels keep
/// their color (the `opacity::correct` fix), every sample valid.
#[test]
fn mip_level_sampling_with_tiny_reference_distance() {
    let mut w = Worst::new(
        "7 mip level sampling at d′→0 (d/d′ ≤ 8.5e37)",
        "MipLevel::sample Preweighted",
        "abs",
    );
    let fine = [AssociatedF32 {
        c: [0.99, 0.495, 0.0],
        a: 0.99,
    }; 8];
    for d_ref in [1e-6f32, 1e-30, f32::MIN_POSITIVE] {
        let vol = Volume::new(&fine, [2, 2, 2])
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let mut out = vec![AssociatedF32::default(); 1];
        let chain = build_chain(OpacityBased, Filter4::box4(), vol, &mut out).unwrap();
        for l in 0..2 {
            let level = chain.level(l).unwrap();
            let s = level.sample(
                &Preweighted,
                Trilinear::new(),
                [0.5; 3],
                Step::new(1.0).unwrap(),
            );
            assert!(s.is_valid(), "{s:?}");
            assert_eq!(s.a, 1.0, "d′={d_ref:e} level {l}");
            let err = (f64::from(s.c[0]) - 1.0)
                .abs()
                .max((f64::from(s.c[1]) - 0.5).abs());
            w.check(err, 1e-6, || format!("d′={d_ref:e} level {l}: {s:?}"));
        }
    }
    let _ = OpacityWeighted;
    w.report();
}
