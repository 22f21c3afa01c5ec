//! Group 8, integer downsampling (`downsample::integer`): `IntOpacityBased` on `AssociatedU8`
//! and U8.8 `IntSample`, `IntExtinctionBased` on `ExtinctionFx`, one level and whole chains,
//! through the edges: `α = 0` and full scale everywhere, one LSB from each end, all-full
//! inputs, depths at and above the cap, odd sizes and `1×1×1`, `1×N×1`, `2×2×2`; filters
//! `a = 0`, `a = ¼`, `a = ½`, one LSB inside them, and arbitrary (quantised) `a`. Each level
//! is held
//!
//! * bit-exact to the exact-integer model (`int_model::downsample`) and within the per-level
//!   bound of the exact method on the same stored input (`INT_OPACITY_LEVEL_LSB`,
//!   `INT_EXTINCTION_LEVEL_LSB`; saturated depths are exact at the cap);
//! * within `int_vs_float_opacity_lsb` / `int_vs_float_extinction_lsb` of the float chain
//!   (`volsample::downsample`) with the *unquantised* `a` (extinction: while no level
//!   saturates);
//! * `C̃ ≤ α ≤ full` (`(D·C) ≤ D ≤ cap`) everywhere.
//!
//! **Accumulators.** The exact sums `S = Σ w_i w_j w_k·v` carry `SUM_FRAC_BITS = 48`
//! fractional bits: at most `2^48·2^26 = 2^74` for depths at the cap `MAX_DEPTH_RAW = 2^26`
//! (every tap at the cap, any filter — reached by the all-cap volumes and by inputs above the
//! cap, clamped on read). The opacity path rounds `ᾱ` to `GUARD_BITS = 8` guard bits,
//! `ᾱ_g ≤ 2^8·FULL`, and forms `ᾱ_g·(2^9·FULL − ᾱ_g) ≤ (2^8·FULL)² < 2^48`, largest at
//! `ᾱ = FULL`: reached by every constant U8.8 volume up to `ONE` (exhaustive, below). The
//! constants are checked against the closed forms `⌊v(2·FULL − v)/FULL + ½⌋` and
//! `min(2D, cap)` bit for bit.
//!
//! Already covered elsewhere: random chains bit-exact against the model and the float chains
//! at 300 seeded cases (`int_downsample`), the paper's 2×2×2 example, invalid inputs.

use proptest::prelude::*;
use volsample::downsample::integer::{
    build_chain_int, downsample_level_int, IntExtinctionBased, IntFilter4, IntMethod,
    IntOpacityBased, GUARD_BITS, SUM_FRAC_BITS, TAP_FRAC_BITS,
};
use volsample::downsample::{
    build_chain, chain_len, level_count, level_dims, level_offset, ExtinctionBased, Filter4,
    OpacityBased,
};
use volsample::fixed_point::extinction::MAX_DEPTH_RAW;
use volsample::fixed_point::{ExtinctionFx, IntSample, ONE};
use volsample::{AssociatedF32, AssociatedU8, ExtinctionF32, Volume};
use volsample_host::edge_cases::{next_down, MIN_SUBNORMAL};
use volsample_host::int_model::downsample as model;
use volsample_host::tolerance::downsample as dtol;

use crate::common::Worst;

/// `2^20`: one U7.20 depth unit.
const DEPTH_UNIT: f64 = 1_048_576.0;

/// The three storage formats.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fmt {
    U8,
    U88,
    Fx,
}

impl Fmt {
    /// Full scale: the largest valid `α` (or `D`).
    fn full(self) -> u64 {
        match self {
            Fmt::U8 => 255,
            Fmt::U88 => u64::from(ONE),
            Fmt::Fx => u64::from(MAX_DEPTH_RAW),
        }
    }
}

/// Runs the kernel's chain over `base` (`[c₀, c₁, c₂, α or D]` raw) and returns every level
/// `ℓ ≥ 1` in raw channels.
fn kernel_chain<V: Copy, M: IntMethod<V>>(
    method: M,
    filter: IntFilter4,
    dims: [usize; 3],
    base: &[[u64; 4]],
    to: impl Fn([u64; 4]) -> V,
    raw: impl Fn(&V) -> [u64; 4],
) -> Vec<Vec<[u64; 4]>> {
    let vox: Vec<V> = base.iter().map(|&v| to(v)).collect();
    let mut out = vec![to([0; 4]); chain_len(dims)];
    let count = build_chain_int(method, filter, &vox, dims, &mut out).unwrap();
    assert_eq!(count, level_count(dims));
    (1..count)
        .map(|l| {
            let off = level_offset(dims, l);
            let n: usize = level_dims(dims, l).iter().product();
            out[off..off + n].iter().map(&raw).collect()
        })
        .collect()
}

fn int_chain(
    fmt: Fmt,
    filter: IntFilter4,
    dims: [usize; 3],
    base: &[[u64; 4]],
) -> Vec<Vec<[u64; 4]>> {
    match fmt {
        Fmt::U8 => kernel_chain(
            IntOpacityBased,
            filter,
            dims,
            base,
            |v| AssociatedU8(v.map(|x| u8::try_from(x).unwrap())),
            |v| v.0.map(u64::from),
        ),
        Fmt::U88 => kernel_chain(
            IntOpacityBased,
            filter,
            dims,
            base,
            |v| {
                let h = |x: u64| u16::try_from(x).unwrap();
                IntSample::new([h(v[0]), h(v[1]), h(v[2])], h(v[3])).unwrap()
            },
            |v| {
                let [r, g, b] = v.c();
                [r, g, b, v.a()].map(u64::from)
            },
        ),
        Fmt::Fx => kernel_chain(
            IntExtinctionBased,
            filter,
            dims,
            base,
            |v| {
                let h = |x: u64| u32::try_from(x).unwrap();
                ExtinctionFx {
                    tau: h(v[3]),
                    c_tau: [h(v[0]), h(v[1]), h(v[2])],
                }
            },
            |v| {
                let [r, g, b] = v.c_tau;
                [r, g, b, v.tau].map(u64::from)
            },
        ),
    }
}

/// The float chain of the same method on the same input (converted to `f32`) with the
/// unquantised `a`, every level `ℓ ≥ 1` in raw units.
fn float_chain(fmt: Fmt, a: f32, dims: [usize; 3], base: &[[u64; 4]]) -> Vec<Vec<[f64; 4]>> {
    let f = Filter4::new(a).unwrap();
    let levels = level_count(dims);
    match fmt {
        Fmt::U8 | Fmt::U88 => {
            let full = fmt.full() as f64;
            let s = |x: u64| (x as f64 / full) as f32;
            let fl: Vec<AssociatedF32> = base
                .iter()
                .map(|v| AssociatedF32 {
                    c: [s(v[0]), s(v[1]), s(v[2])],
                    a: s(v[3]),
                })
                .collect();
            let mut out = vec![AssociatedF32::default(); chain_len(dims)];
            let chain =
                build_chain(OpacityBased, f, Volume::new(&fl, dims).unwrap(), &mut out).unwrap();
            (1..levels)
                .map(|l| {
                    let lv = chain.level(l).unwrap();
                    let d = lv.volume().data();
                    d.iter()
                        .map(|v| [v.c[0], v.c[1], v.c[2], v.a].map(|x| f64::from(x) * full))
                        .collect()
                })
                .collect()
        }
        Fmt::Fx => {
            let s = |x: u64| (x as f64 / DEPTH_UNIT) as f32;
            let fl: Vec<ExtinctionF32> = base
                .iter()
                .map(|v| ExtinctionF32 {
                    c_tau: [s(v[0]), s(v[1]), s(v[2])],
                    tau: s(v[3]),
                })
                .collect();
            let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
            let chain = build_chain(
                ExtinctionBased,
                f,
                Volume::new(&fl, dims).unwrap(),
                &mut out,
            )
            .unwrap();
            (1..levels)
                .map(|l| {
                    let lv = chain.level(l).unwrap();
                    let d = lv.volume().data();
                    d.iter()
                        .map(|v| {
                            [v.c_tau[0], v.c_tau[1], v.c_tau[2], v.tau]
                                .map(|x| f64::from(x) * DEPTH_UNIT)
                        })
                        .collect()
                })
                .collect()
        }
    }
}

/// An integer filter and the float `a` it stands for (its own `a` when given as a float).
#[derive(Debug, Clone, Copy)]
struct Tap {
    int: IntFilter4,
    a: f32,
}

impl Tap {
    fn raw(a_raw: u32) -> Self {
        Self {
            int: IntFilter4::from_raw(a_raw).unwrap(),
            a: (f64::from(a_raw) / 65536.0) as f32,
        }
    }
    fn float(a: f32) -> Self {
        Self {
            int: IntFilter4::from_filter(Filter4::new(a).unwrap()),
            a,
        }
    }
    /// `|a − a_q/2^16|`.
    fn delta(&self) -> f64 {
        (f64::from(self.a) - f64::from(self.int.a_raw()) / 65536.0).abs()
    }
}

/// `a = 0`, `¼`, `½`, one LSB inside each, the B-spline mask, `⅕` quantised, and float `a`
/// that do not quantise exactly (the smallest subnormal, `⅓`, one ulp below `½`).
fn taps() -> Vec<Tap> {
    let mut t: Vec<Tap> = [0u32, 1, 8192, 13107, 16383, 16384, 16385, 32767, 32768]
        .into_iter()
        .map(Tap::raw)
        .collect();
    t.extend([MIN_SUBNORMAL, 0.2, 1.0 / 3.0, next_down(0.5)].map(Tap::float));
    t
}

/// The worst errors of one group of chains.
struct Rows {
    exact_op: Worst,
    float_op: Worst,
    exact_fx: Worst,
    float_fx: Worst,
}

impl Rows {
    fn new(suffix: &'static [&'static str; 4]) -> Self {
        Self {
            exact_op: Worst::new(
                suffix[0],
                "build_chain_int IntOpacityBased (u8, U8.8)",
                "LSB",
            ),
            float_op: Worst::new(
                suffix[1],
                "build_chain_int IntOpacityBased vs build_chain OpacityBased",
                "LSB",
            ),
            exact_fx: Worst::new(suffix[2], "build_chain_int IntExtinctionBased", "LSB"),
            float_fx: Worst::new(
                suffix[3],
                "build_chain_int IntExtinctionBased vs build_chain ExtinctionBased",
                "LSB",
            ),
        }
    }
    fn report(self) {
        self.exact_op.report();
        self.float_op.report();
        self.exact_fx.report();
        self.float_fx.report();
    }
}

/// One chain of one format: bit-exact against the model, within the per-level bound of the
/// exact method, in range, and against the float chain where that bound applies.
fn check_chain(rows: &mut Rows, fmt: Fmt, tap: Tap, dims: [usize; 3], base: &[[u64; 4]]) {
    let got = int_chain(fmt, tap.int, dims, base);
    let a_q = tap.int.a_raw();
    let full = fmt.full();
    let want = model::chain(dims, base, |d, v| match fmt {
        Fmt::Fx => model::extinction_level(d, v, a_q),
        _ => model::opacity_level(d, v, a_q, full),
    });
    assert_eq!(got.len(), want.len(), "{dims:?}");
    let (exact_row, float_row, bound) = match fmt {
        Fmt::Fx => (
            &mut rows.exact_fx,
            &mut rows.float_fx,
            dtol::INT_EXTINCTION_LEVEL_LSB,
        ),
        _ => (
            &mut rows.exact_op,
            &mut rows.float_op,
            dtol::INT_OPACITY_LEVEL_LSB,
        ),
    };
    for (l, (gv, (wd, wv))) in (1u32..).zip(got.iter().zip(&want)) {
        assert_eq!(*wd, level_dims(dims, l));
        for (i, (g, m)) in gv.iter().zip(wv).enumerate() {
            let at = || format!("{fmt:?} {dims:?} a_q={a_q} level {l} voxel {i}: {g:?}");
            assert_eq!(*g, m.raw, "model {:?} at {}", m.raw, at());
            assert!(
                g[3] <= full && g[..3].iter().all(|&c| c <= g[3]),
                "{}",
                at()
            );
            for (&r, &e) in g.iter().zip(&m.exact) {
                if fmt == Fmt::Fx && r == full {
                    // Saturated: exactly the cap, and the exact value is at or above it.
                    assert!(e >= full as f64 - bound, "{}", at());
                    continue;
                }
                exact_row.check((r as f64 - e).abs(), bound, at);
            }
        }
    }
    // The float chain: opacity always; extinction while no level can reach the cap (each
    // level at most doubles the largest depth, plus ½ of rounding) and no input is above it.
    let d0 = base.iter().map(|v| v[3]).max().unwrap_or(0);
    let levels = got.len() as i32;
    let unsaturated =
        d0 <= full && (d0 as f64) * 2f64.powi(levels) + f64::from(levels) < full as f64;
    if fmt == Fmt::Fx && !unsaturated {
        return;
    }
    let fl = float_chain(fmt, tap.a, dims, base);
    for (l, (gv, fv)) in (1u32..).zip(got.iter().zip(&fl)) {
        let b = match fmt {
            Fmt::Fx => dtol::int_vs_float_extinction_lsb(d0 as f64, tap.delta(), l),
            _ => dtol::int_vs_float_opacity_lsb(full as f64, tap.delta(), l),
        };
        for (i, (g, f)) in gv.iter().zip(fv).enumerate() {
            for (&r, &x) in g.iter().zip(f) {
                float_row.check((r as f64 - x).abs(), b, || {
                    format!(
                        "{fmt:?} {dims:?} a={:e} level {l} voxel {i}: {g:?} vs {f:?}",
                        tap.a
                    )
                });
            }
        }
    }
}

const DIMS: [[usize; 3]; 7] = [
    [1, 1, 1],
    [1, 7, 1],
    [2, 2, 2],
    [3, 3, 3],
    [5, 3, 2],
    [1, 1, 9],
    [4, 4, 4],
];

/// Edge volumes of `n` voxels in a format of full scale `full`.
fn patterns(n: usize, full: u64) -> Vec<Vec<[u64; 4]>> {
    let edges = [0, 1, full - 1, full];
    let half = full / 2;
    vec![
        vec![[0; 4]; n],
        vec![[full; 4]; n],
        vec![[1, 0, 1, 1]; n],
        vec![[full - 1, 0, (full - 1) / 2, full - 1]; n],
        (0..n)
            .map(|i| if i % 2 == 0 { [full; 4] } else { [0; 4] })
            .collect(),
        (0..n)
            .map(|i| {
                let a = edges[(i * 3 + 1) % 4];
                [a, a / 2, 0, a]
            })
            .collect(),
        (0..n)
            .map(|i| {
                if i == n / 2 {
                    [full, half, 0, full]
                } else {
                    [0; 4]
                }
            })
            .collect(),
        (0..n)
            .map(|i| {
                if i % 3 == 0 {
                    [1; 4]
                } else {
                    [full - 1, 0, full - 1, full]
                }
            })
            .collect(),
    ]
}

/// Every edge volume, size and filter, in every format.
#[test]
fn int_chains_at_the_edges() {
    let mut rows = Rows::new(&[
        "8 int opacity chains (u8, U8.8) vs exact method, edges",
        "8 int opacity chains vs float chain, edges",
        "8 int extinction chains vs exact method, edges, D ≥ cap",
        "8 int extinction chains vs float chain, edges (unsaturated)",
    ]);
    for dims in DIMS {
        let n: usize = dims.iter().product();
        for fmt in [Fmt::U8, Fmt::U88, Fmt::Fx] {
            let mut cases = patterns(n, fmt.full());
            if fmt == Fmt::Fx {
                // Above the cap (clamped on read), and small depths that never saturate.
                cases.push(vec![[u64::from(u32::MAX); 4]; n]);
                cases.push(vec![[fmt.full() + 1, 0, 5, fmt.full() + 1]; n]);
                cases.extend(patterns(n, 1 << 12));
            }
            for base in &cases {
                for tap in taps() {
                    check_chain(&mut rows, fmt, tap, dims, base);
                }
            }
        }
    }
    rows.report();
}

/// Constant volumes: every `u8` opacity with its colors, every U8.8 opacity, and depths from 0
/// to above the cap, through one level of every filter; the closed forms bit for bit, within
/// ½ LSB of the exact value, and within the one-level bound of the float kernel. The
/// U8.8 constants up to `ONE` reach the correction's widest product `(2^8·ONE)²`.
#[test]
fn constant_volumes_and_widest_accumulators() {
    let mut w = Worst::new(
        "8 constants: every u8 α, every U8.8 α, D 0…u32::MAX (S ≤ 2^74)",
        "downsample_level_int IntOpacityBased/IntExtinctionBased",
        "LSB",
    );
    let mut wf = Worst::new(
        "8 constants vs float level (u8, U8.8)",
        "downsample_level_int vs downsample_level OpacityBased",
        "LSB",
    );
    // The documented widths: 48 fractional bits of three Q0.16 passes, a 2^74 sum in u128,
    // the guarded correction's product below 2^48 (exact in `round_half_up_div`).
    const {
        assert!(SUM_FRAC_BITS == 3 * TAP_FRAC_BITS);
        assert!(SUM_FRAC_BITS + 26 < 128);
        assert!(((ONE as u64) << GUARD_BITS).pow(2) < 1 << 48);
    }
    let filters = [0u32, 16384, 32768, 13107].map(|a| IntFilter4::from_raw(a).unwrap());
    for f in filters {
        for v in 0..=255u8 {
            let g = 510 - u32::from(v);
            let closed = |c: u8| ((u32::from(c) * g + 127) / 255) as u8; // ⌊c·g/255 + ½⌋
            let cs = [v, v / 2, 0];
            let src = [AssociatedU8([cs[0], cs[1], cs[2], v]); 8];
            let mut o = [AssociatedU8::default()];
            downsample_level_int(IntOpacityBased, f, &src, [2, 2, 2], &mut o).unwrap();
            assert_eq!(
                o[0],
                AssociatedU8([closed(cs[0]), closed(cs[1]), closed(cs[2]), closed(v)]),
                "v={v} a_q={}",
                f.a_raw()
            );
            for (k, c) in [cs[0], cs[1], cs[2], v].into_iter().enumerate() {
                let exact = f64::from(c) * f64::from(g) / 255.0;
                w.check(
                    (f64::from(o[0].0[k]) - exact).abs(),
                    dtol::INT_OPACITY_LEVEL_LSB,
                    || format!("u8 v={v} ch{k}"),
                );
            }
            // The float kernel on the same constant, level 1.
            let s = |x: u8| (f64::from(x) / 255.0) as f32;
            let fl = [AssociatedF32 {
                c: cs.map(s),
                a: s(v),
            }; 8];
            let mut fo = [AssociatedF32::default()];
            volsample::downsample::downsample_level(
                OpacityBased,
                f.to_filter(),
                &Volume::new(&fl, [2, 2, 2]).unwrap(),
                &mut fo,
            )
            .unwrap();
            let fr = [fo[0].c[0], fo[0].c[1], fo[0].c[2], fo[0].a].map(|x| f64::from(x) * 255.0);
            for (k, (&gi, &fx)) in o[0].0.iter().zip(&fr).enumerate() {
                wf.check(
                    (f64::from(gi) - fx).abs(),
                    dtol::int_vs_float_opacity_lsb(255.0, 0.0, 1),
                    || format!("u8 v={v} ch{k}"),
                );
            }
        }
    }
    // Every U8.8 opacity (box filter: the sums are exact for constants whatever the filter).
    let one = u64::from(ONE);
    for v in 0..=ONE {
        let src = [IntSample::new([v, v / 3, 0], v).unwrap(); 8];
        let mut o = [IntSample::TRANSPARENT];
        downsample_level_int(IntOpacityBased, IntFilter4::box2(), &src, [2, 2, 2], &mut o).unwrap();
        let g = 2 * one - u64::from(v);
        let closed = |c: u16| ((u64::from(c) * g + one / 2) / one) as u16;
        assert_eq!(o[0].a(), closed(v), "U8.8 v={v}");
        assert_eq!(o[0].c(), [closed(v), closed(v / 3), 0], "U8.8 v={v}");
        let exact = f64::from(v) * g as f64 / one as f64;
        w.check(
            (f64::from(o[0].a()) - exact).abs(),
            dtol::INT_OPACITY_LEVEL_LSB,
            || format!("U8.8 v={v}"),
        );
    }
    // Depths: 2D below the cap, the cap from there on; inputs above the cap read as the cap.
    let cap = MAX_DEPTH_RAW;
    let mut depths: Vec<u32> = (0..32)
        .flat_map(|k| {
            let p = 1u32 << k;
            [p - 1, p, p + 1]
        })
        .collect();
    depths.extend([
        cap / 2 - 1,
        cap / 2,
        cap / 2 + 1,
        cap - 1,
        cap,
        cap + 1,
        u32::MAX,
    ]);
    for f in filters {
        for &d in &depths {
            let src = [ExtinctionFx {
                tau: d,
                c_tau: [d, d / 2, 0],
            }; 8];
            let mut o = [ExtinctionFx::default()];
            downsample_level_int(IntExtinctionBased, f, &src, [2, 2, 2], &mut o).unwrap();
            // min(2·min(x, cap), cap): each channel clamped on read (colors to the clamped
            // depth), doubled, saturated.
            let dd = |x: u32| (u64::from(x.min(cap)) * 2).min(u64::from(cap)) as u32;
            let want = ExtinctionFx {
                tau: dd(d),
                c_tau: [dd(d), dd(d / 2), 0],
            };
            assert_eq!(o[0], want, "D={d} a_q={}", f.a_raw());
            let exact = 2.0 * f64::from(d.min(cap));
            let got = f64::from(o[0].tau);
            if got < f64::from(cap) {
                w.check((got - exact).abs(), dtol::INT_EXTINCTION_LEVEL_LSB, || {
                    format!("D={d}")
                });
            }
        }
    }
    w.report();
    wf.report();
}

// ---------------------------------------------------------------------------------------------
// Fuzzed.

/// A raw value in `0..=max`, drawn at the ends half of the time.
fn raw_value(max: u64) -> impl Strategy<Value = u64> {
    prop_oneof![
        1 => Just(0u64),
        1 => Just(1u64.min(max)),
        1 => Just(max - 1),
        1 => Just(max),
        4 => 0..=max,
    ]
}

/// A voxel `[c₀, c₁, c₂, α]` with `c ≤ α ≤ max`.
fn voxel(max: u64) -> impl Strategy<Value = [u64; 4]> {
    (
        raw_value(max),
        [raw_value(max), raw_value(max), raw_value(max)],
    )
        .prop_map(|(a, c)| [c[0].min(a), c[1].min(a), c[2].min(a), a])
}

fn tap() -> impl Strategy<Value = Tap> {
    prop_oneof![
        2 => prop::sample::select(vec![0u32, 1, 16384, 32767, 32768]).prop_map(Tap::raw),
        1 => (0u32..=32768).prop_map(Tap::raw),
        2 => (0.0f32..=0.5).prop_map(Tap::float),
    ]
}

prop_compose! {
    fn chain_case()(dims in [1usize..=5, 1usize..=5, 1usize..=5], fmt in prop::sample::select(vec![Fmt::U8, Fmt::U88, Fmt::Fx]), small in any::<bool>())
        (base in {
            // Extinction: the whole range (saturating) or depths small enough never to.
            let max = if fmt == Fmt::Fx && small { 1 << 14 } else { fmt.full() };
            prop::collection::vec(voxel(max), dims[0] * dims[1] * dims[2])
        }, dims in Just(dims), fmt in Just(fmt), tap in tap())
        -> (Fmt, [usize; 3], Vec<[u64; 4]>, Tap) {
        (fmt, dims, base, tap)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Chains of fuzzed edge volumes, sizes, formats and filters.
    #[test]
    fn int_chains_fuzzed((fmt, dims, base, tap) in chain_case()) {
        let mut rows = Rows::new(&[
            "8 int opacity chains vs exact method (fuzzed)",
            "8 int opacity chains vs float chain (fuzzed)",
            "8 int extinction chains vs exact method (fuzzed)",
            "8 int extinction chains vs float chain (fuzzed)",
        ]);
        check_chain(&mut rows, fmt, tap, dims, &base);
        // One run reaches the rows of its format only (and 1×1×1 none).
        rows.exact_op.report_if_checked();
        rows.float_op.report_if_checked();
        rows.exact_fx.report_if_checked();
        rows.float_fx.report_if_checked();
    }
}
