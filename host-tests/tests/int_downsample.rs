//! Integer downsampling (`volsample::downsample::integer`): bit-exact against the model
//! (`int_model::downsample`) on random and extreme volumes, every level within its stated
//! bound of the exact method, `C̃ ≤ α` and the ranges everywhere, constant volumes constant,
//! and agreement with the float chains within `tolerance::downsample::int_vs_float_*`.
//!
//! Random cases come from a fixed-seed generator; `VOLSAMPLE_SEED` and `VOLSAMPLE_ITERS`
//! override the seed and the number of cases.

use volsample::downsample::integer::{
    build_chain_int, downsample_level_int, IntExtinctionBased, IntFilter4, IntMethod,
    IntOpacityBased,
};
use volsample::downsample::{
    build_chain, chain_len, level_count, level_dims, level_offset, ExtinctionBased, Filter4,
    OpacityBased,
};
use volsample::fixed_point::extinction::MAX_DEPTH_RAW;
use volsample::fixed_point::{ExtinctionFx, IntSample, ONE};
use volsample::{AssociatedF32, AssociatedU8, Error, ExtinctionF32, Volume};
use volsample_host::int_model::downsample as model;
use volsample_host::tolerance::downsample as tol;

// ---------------------------------------------------------------------------------------------
// Cases.

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    /// A value in `0..=max`, a quarter of the time an extreme (0 or `max`).
    fn value(&mut self, max: u64) -> u64 {
        match self.below(8) {
            0 => 0,
            1 => max,
            _ => self.below(max + 1),
        }
    }
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn seed() -> u64 {
    env_u64("VOLSAMPLE_SEED", 0x1D0_5A3F)
}

fn iters() -> u64 {
    env_u64("VOLSAMPLE_ITERS", 300)
}

fn random_dims(rng: &mut Rng) -> [usize; 3] {
    [(); 3].map(|_| 1 + rng.below(9) as usize)
}

/// Named filters and random ones.
fn random_filter(rng: &mut Rng) -> IntFilter4 {
    match rng.below(6) {
        0 => IntFilter4::box2(),
        1 => IntFilter4::bspline(),
        2 => IntFilter4::quadratic(),
        3 => IntFilter4::box4(),
        4 => IntFilter4::from_raw(32768).unwrap(),
        _ => IntFilter4::from_raw(rng.below(32769) as u32).unwrap(),
    }
}

/// Associated channels `[C̃₀, C̃₁, C̃₂, α]` with `C̃ ≤ α ≤ full`.
fn random_assoc(rng: &mut Rng, full: u64) -> [u64; 4] {
    let a = rng.value(full);
    [rng.value(a), rng.value(a), rng.value(a), a]
}

fn to_u8(v: [u64; 4]) -> AssociatedU8 {
    AssociatedU8(v.map(|x| u8::try_from(x).unwrap()))
}

fn to_u88(v: [u64; 4]) -> IntSample {
    let h = |x: u64| u16::try_from(x).unwrap();
    IntSample::new([h(v[0]), h(v[1]), h(v[2])], h(v[3])).unwrap()
}

fn to_fx(v: [u64; 4]) -> ExtinctionFx {
    let h = |x: u64| u32::try_from(x).unwrap();
    ExtinctionFx {
        tau: h(v[3]),
        c_tau: [h(v[0]), h(v[1]), h(v[2])],
    }
}

fn raw_u8(v: &AssociatedU8) -> [u64; 4] {
    v.0.map(u64::from)
}

fn raw_u88(v: &IntSample) -> [u64; 4] {
    let [r, g, b] = v.c();
    [r, g, b, v.a()].map(u64::from)
}

fn raw_fx(v: &ExtinctionFx) -> [u64; 4] {
    let [r, g, b] = v.c_tau;
    [r, g, b, v.tau].map(u64::from)
}

/// What one format needs: to and from model channels, its model level, its full scale.
struct Format<V> {
    to: fn([u64; 4]) -> V,
    raw: fn(&V) -> [u64; 4],
    full: u64,
    extinction: bool,
}

fn model_level(
    f_full: u64,
    extinction: bool,
    a_q: u32,
) -> impl Fn([usize; 3], &[[u64; 4]]) -> model::Level {
    move |d, v| {
        if extinction {
            model::extinction_level(d, v, a_q)
        } else {
            model::opacity_level(d, v, a_q, f_full)
        }
    }
}

/// Statistics over many chains.
#[derive(Default, Debug)]
struct Stats {
    voxels: u64,
    mismatches: u64,
    /// Worst error of a level against the exact method on the level before (storage LSB).
    worst_exact: f64,
}

/// Builds the chain with the kernel and with the model, checks every voxel bit-exact, within
/// the per-level bound of the exact method, and in range with `C̃ ≤ α`.
fn check_chain<V: Copy + std::fmt::Debug, M: IntMethod<V>>(
    method: M,
    fmt: &Format<V>,
    filter: IntFilter4,
    dims: [usize; 3],
    base: &[[u64; 4]],
    stats: &mut Stats,
) -> Vec<V> {
    let vox: Vec<V> = base.iter().map(|&v| (fmt.to)(v)).collect();
    let mut out = vec![(fmt.to)([0; 4]); chain_len(dims)];
    let count = build_chain_int(method, filter, &vox, dims, &mut out).unwrap();
    assert_eq!(count, level_count(dims));
    let want = model::chain(
        dims,
        base,
        model_level(fmt.full, fmt.extinction, filter.a_raw()),
    );
    assert_eq!(want.len() as u32 + 1, count);
    let bound = if fmt.extinction {
        tol::INT_EXTINCTION_LEVEL_LSB
    } else {
        tol::INT_OPACITY_LEVEL_LSB
    };
    let cap = if fmt.extinction {
        u64::from(MAX_DEPTH_RAW)
    } else {
        fmt.full
    };
    for (l, (d, mv)) in (1u32..).zip(want.iter()) {
        assert_eq!(*d, level_dims(dims, l));
        let off = level_offset(dims, l);
        let got = &out[off..off + mv.len()];
        for (i, (g, m)) in got.iter().zip(mv.iter()).enumerate() {
            let g = (fmt.raw)(g);
            stats.voxels += 1;
            if g != m.raw {
                stats.mismatches += 1;
                panic!(
                    "level {l} voxel {i} of {dims:?}, a_q = {}: kernel {g:?}, model {:?}",
                    filter.a_raw(),
                    m.raw
                );
            }
            assert!(g[3] <= cap, "out of range: {g:?}");
            assert!(g[..3].iter().all(|&c| c <= g[3]), "C̃ > α: {g:?}");
            for (&r, &e) in g.iter().zip(m.exact.iter()) {
                // Saturated extinction values are not held to the rounding bound.
                if fmt.extinction && r == cap {
                    continue;
                }
                let err = (r as f64 - e).abs();
                stats.worst_exact = stats.worst_exact.max(err);
                assert!(err <= bound, "level {l} voxel {i}: {r} vs exact {e}");
            }
        }
    }
    out
}

const U8: Format<AssociatedU8> = Format {
    to: to_u8,
    raw: raw_u8,
    full: 255,
    extinction: false,
};
const U88: Format<IntSample> = Format {
    to: to_u88,
    raw: raw_u88,
    full: ONE as u64,
    extinction: false,
};
const FX: Format<ExtinctionFx> = Format {
    to: to_fx,
    raw: raw_fx,
    full: MAX_DEPTH_RAW as u64,
    extinction: true,
};

// ---------------------------------------------------------------------------------------------
// The filter.

#[test]
fn taps_are_quantised_as_documented() {
    for (f, a_q) in [
        (Filter4::box2(), 0),
        (Filter4::bspline(), 8192),
        (Filter4::quadratic(), 13107),
        (Filter4::box4(), 16384),
        (Filter4::new(0.5).unwrap(), 32768),
    ] {
        let q = IntFilter4::from_filter(f);
        assert_eq!(q.a_raw(), a_q);
        assert_eq!(q.a_raw(), model::quantise_a(f64::from(f.a())));
        assert_eq!(q.taps().iter().sum::<u32>(), 1 << 16);
        assert!((f64::from(f.a()) - f64::from(a_q) / 65536.0).abs() <= 2f64.powi(-17));
        assert_eq!(IntFilter4::from_filter(q.to_filter()), q);
    }
    assert_eq!(
        IntFilter4::quadratic(),
        IntFilter4::from_filter(Filter4::quadratic())
    );
    // Round half up at a tie: a = 1.5/65536 → 2.
    let tie = Filter4::new(1.5 / 65536.0).unwrap();
    assert_eq!(IntFilter4::from_filter(tie).a_raw(), 2);
    assert!(IntFilter4::from_raw(32768).is_ok());
    assert_eq!(
        IntFilter4::from_raw(32769),
        Err(Error::InvalidDownsampleFilter)
    );
}

// ---------------------------------------------------------------------------------------------
// Bit-exact against the model.

fn random_chains<V: Copy + std::fmt::Debug, M: IntMethod<V>>(
    method: M,
    fmt: &Format<V>,
    max: u64,
    salt: u64,
) -> Stats {
    let mut rng = Rng(seed() ^ salt);
    let mut stats = Stats::default();
    for _ in 0..iters() {
        let dims = random_dims(&mut rng);
        let filter = random_filter(&mut rng);
        let n = dims.iter().product();
        let base: Vec<[u64; 4]> = (0..n).map(|_| random_assoc(&mut rng, max)).collect();
        check_chain(method, fmt, filter, dims, &base, &mut stats);
    }
    stats
}

#[test]
fn opacity_u8_matches_model() {
    let s = random_chains(IntOpacityBased, &U8, 255, 1);
    println!("AssociatedU8: {s:?} (bound {})", tol::INT_OPACITY_LEVEL_LSB);
    assert_eq!(s.mismatches, 0);
    assert!(s.voxels > 0);
}

#[test]
fn opacity_u88_matches_model() {
    let s = random_chains(IntOpacityBased, &U88, u64::from(ONE), 2);
    println!("IntSample: {s:?} (bound {})", tol::INT_OPACITY_LEVEL_LSB);
    assert_eq!(s.mismatches, 0);
}

#[test]
fn extinction_matches_model() {
    // Full range (saturating high levels) and small depths (unsaturated chains).
    let s = random_chains(IntExtinctionBased, &FX, u64::from(MAX_DEPTH_RAW), 3);
    let t = random_chains(IntExtinctionBased, &FX, 1 << 18, 4);
    println!(
        "ExtinctionFx: {s:?}, small: {t:?} (bound {})",
        tol::INT_EXTINCTION_LEVEL_LSB
    );
    assert_eq!(s.mismatches + t.mismatches, 0);
}

/// All-0, all-full, `α = 1` with colors, odd sizes and `1 × 1 × 1`.
#[test]
fn extremes_match_model() {
    let dims_list = [
        [1, 1, 1],
        [2, 1, 1],
        [3, 1, 1],
        [1, 1, 9],
        [3, 5, 7],
        [8, 8, 8],
        [9, 2, 5],
    ];
    let filters = [
        IntFilter4::box2(),
        IntFilter4::bspline(),
        IntFilter4::quadratic(),
        IntFilter4::box4(),
        IntFilter4::from_raw(32768).unwrap(),
    ];
    let mut stats = Stats::default();
    let mut rng = Rng(seed() ^ 5);
    for dims in dims_list {
        let n: usize = dims.iter().product();
        for f in filters {
            for (full, fmt_ext) in [
                (255u64, 0),
                (u64::from(ONE), 1),
                (u64::from(MAX_DEPTH_RAW), 2),
            ] {
                let cases: Vec<Vec<[u64; 4]>> = vec![
                    vec![[0; 4]; n],
                    vec![[full; 4]; n],
                    (0..n)
                        .map(|_| [rng.value(full), rng.value(full), 0, full])
                        .collect(),
                    (0..n)
                        .map(|i| if i % 2 == 0 { [full; 4] } else { [0; 4] })
                        .collect(),
                    (0..n).map(|_| random_assoc(&mut rng, full)).collect(),
                ];
                for base in cases {
                    match fmt_ext {
                        0 => drop(check_chain(
                            IntOpacityBased,
                            &U8,
                            f,
                            dims,
                            &base,
                            &mut stats,
                        )),
                        1 => drop(check_chain(
                            IntOpacityBased,
                            &U88,
                            f,
                            dims,
                            &base,
                            &mut stats,
                        )),
                        _ => drop(check_chain(
                            IntExtinctionBased,
                            &FX,
                            f,
                            dims,
                            &base,
                            &mut stats,
                        )),
                    }
                }
            }
        }
    }
    println!("extremes: {stats:?}");
    assert_eq!(stats.mismatches, 0);
}

#[test]
fn one_voxel_and_full_scale() {
    // 1×1×1: the chain is level 0 alone, the level is the correction of the voxel.
    let v = [AssociatedU8([255, 0, 128, 255])];
    let mut none: [AssociatedU8; 0] = [];
    assert_eq!(
        build_chain_int(
            IntOpacityBased,
            IntFilter4::box4(),
            &v,
            [1, 1, 1],
            &mut none
        ),
        Ok(1)
    );
    let mut one = [AssociatedU8::default()];
    assert_eq!(
        downsample_level_int(IntOpacityBased, IntFilter4::box4(), &v, [1, 1, 1], &mut one),
        Ok([1, 1, 1])
    );
    assert_eq!(one[0], AssociatedU8([255, 0, 128, 255])); // α = 1: 1·(2 − 1) = 1
                                                          // U8.8 full scale stays full scale; extinction full scale saturates at the cap.
    let s = [IntSample::new([ONE; 3], ONE).unwrap(); 8];
    let mut o = [IntSample::TRANSPARENT];
    downsample_level_int(
        IntOpacityBased,
        IntFilter4::quadratic(),
        &s,
        [2, 2, 2],
        &mut o,
    )
    .unwrap();
    assert_eq!(o[0], s[0]);
    let e = [ExtinctionFx {
        tau: MAX_DEPTH_RAW,
        c_tau: [MAX_DEPTH_RAW, 0, 1],
    }; 8];
    let mut o = [ExtinctionFx::default()];
    downsample_level_int(
        IntExtinctionBased,
        IntFilter4::box4(),
        &e,
        [2, 2, 2],
        &mut o,
    )
    .unwrap();
    assert_eq!(
        o[0],
        ExtinctionFx {
            tau: MAX_DEPTH_RAW,
            c_tau: [MAX_DEPTH_RAW, 0, 2]
        }
    );
}

#[test]
fn invalid_voxels_are_clamped_not_trusted() {
    // C̃ > α in an unvalidated `AssociatedU8` reads as C̃ = α, so the output keeps C̃ ≤ α.
    let v = [AssociatedU8([200, 10, 0, 100]); 8];
    let mut o = [AssociatedU8::default()];
    downsample_level_int(IntOpacityBased, IntFilter4::box2(), &v, [2, 2, 2], &mut o).unwrap();
    assert_eq!(o[0].0[0], o[0].0[3]);
    let e = [ExtinctionFx {
        tau: u32::MAX,
        c_tau: [u32::MAX; 3],
    }; 8];
    let mut o = [ExtinctionFx::default()];
    downsample_level_int(
        IntExtinctionBased,
        IntFilter4::box2(),
        &e,
        [2, 2, 2],
        &mut o,
    )
    .unwrap();
    assert_eq!(
        o[0],
        ExtinctionFx {
            tau: MAX_DEPTH_RAW,
            c_tau: [MAX_DEPTH_RAW; 3]
        }
    );
}

#[test]
fn bad_dims_and_buffers_are_rejected() {
    let v = [AssociatedU8::default(); 8];
    let f = IntFilter4::box4();
    let mut o = [AssociatedU8::default(); 1];
    assert_eq!(
        downsample_level_int(IntOpacityBased, f, &v, [2, 2, 0], &mut o),
        Err(Error::ZeroDimension { axis: 2 })
    );
    assert_eq!(
        downsample_level_int(IntOpacityBased, f, &v, [2, 2, 3], &mut o),
        Err(Error::LengthMismatch {
            expected: 12,
            actual: 8
        })
    );
    assert_eq!(
        downsample_level_int(IntOpacityBased, f, &v, [1 << 25, 1, 1], &mut o),
        Err(Error::DimensionTooLarge)
    );
    let mut o2 = [AssociatedU8::default(); 2];
    assert_eq!(
        downsample_level_int(IntOpacityBased, f, &v, [2, 2, 2], &mut o2),
        Err(Error::OutputLengthMismatch {
            expected: 1,
            actual: 2
        })
    );
    let mut c = [AssociatedU8::default(); 3];
    assert_eq!(
        build_chain_int(IntOpacityBased, f, &v, [2, 2, 2], &mut c),
        Err(Error::OutputLengthMismatch {
            expected: 1,
            actual: 3
        })
    );
}

// ---------------------------------------------------------------------------------------------
// Constant volumes.

/// A constant volume is constant at every level: opacity-based, each level the rounded
/// doubled-distance correction of the one before, `⌊v(2F − v)/F + ½⌋`; extinction-based,
/// `2^ℓ·D` until the cap.
#[test]
fn constant_volume_is_constant_at_every_level() {
    let dims = [7, 4, 5];
    let n = 7 * 4 * 5;
    let filters = [
        IntFilter4::box2(),
        IntFilter4::bspline(),
        IntFilter4::quadratic(),
        IntFilter4::box4(),
    ];
    let corr = |v: u64, full: u64| (2 * v * (2 * full - v) + full) / (2 * full);
    for f in filters {
        for v in [
            [0, 0, 0, 0],
            [1, 0, 1, 1],
            [40, 20, 0, 128],
            [255, 255, 255, 255],
            [3, 200, 17, 200],
        ] {
            let base = vec![AssociatedU8(v); n];
            let mut out = vec![AssociatedU8::default(); chain_len(dims)];
            build_chain_int(IntOpacityBased, f, &base, dims, &mut out).unwrap();
            let mut want = v.map(u64::from);
            for l in 1..level_count(dims) {
                let a = want[3];
                want = [
                    corr_c(want[0], a, 255),
                    corr_c(want[1], a, 255),
                    corr_c(want[2], a, 255),
                    corr(a, 255),
                ];
                let off = level_offset(dims, l);
                let size: usize = level_dims(dims, l).iter().product();
                for g in &out[off..off + size] {
                    assert_eq!(raw_u8(g), want, "level {l} of constant {v:?}");
                }
            }
        }
        for d in [0u32, 1, 12_345, 3 << 20, MAX_DEPTH_RAW] {
            let base = vec![
                ExtinctionFx {
                    tau: d,
                    c_tau: [d, d / 3, 0]
                };
                n
            ];
            let mut out = vec![ExtinctionFx::default(); chain_len(dims)];
            build_chain_int(IntExtinctionBased, f, &base, dims, &mut out).unwrap();
            for l in 1..level_count(dims) {
                let s = |x: u32| (u64::from(x) << l).min(u64::from(MAX_DEPTH_RAW)) as u32;
                let want = ExtinctionFx {
                    tau: s(d),
                    c_tau: [s(d), s(d / 3), 0],
                };
                let off = level_offset(dims, l);
                let size: usize = level_dims(dims, l).iter().product();
                assert!(
                    out[off..off + size].iter().all(|g| *g == want),
                    "level {l}, D = {d}"
                );
            }
        }
    }
}

/// `⌊c(2F − a)/F + ½⌋`, the color correction of a constant voxel.
fn corr_c(c: u64, a: u64, full: u64) -> u64 {
    (2 * c * (2 * full - a) + full) / (2 * full)
}

// ---------------------------------------------------------------------------------------------
// Against the float chains.

/// Worst `|integer − float|` (storage LSB) per level, checked against
/// `tol::int_vs_float_*`, for the named filters both with the float filter's own `a` (tap
/// error included) and with the quantised `a` (rounding alone).
#[test]
fn integer_agrees_with_float() {
    let mut rng = Rng(seed() ^ 6);
    let named = [
        Filter4::box2(),
        Filter4::bspline(),
        Filter4::quadratic(),
        Filter4::box4(),
    ];
    let mut worst = [[0.0f64; 2]; 3]; // [u8, U8.8, Fx] × [own a, quantised a]
    let mut worst_ratio = 0.0f64; // error / bound, worst over all
    for _ in 0..iters() / 3 {
        let dims = random_dims(&mut rng);
        let n: usize = dims.iter().product();
        let ff = named[rng.below(4) as usize];
        let qf = IntFilter4::from_filter(ff);
        for (k, float_f) in [ff, qf.to_filter()].into_iter().enumerate() {
            let delta_a = (f64::from(float_f.a()) - f64::from(qf.a_raw()) / 65536.0).abs();
            // Opacity-based, u8 and U8.8.
            for (fi, full) in [255u64, u64::from(ONE)].into_iter().enumerate() {
                let base: Vec<[u64; 4]> = (0..n).map(|_| random_assoc(&mut rng, full)).collect();
                let fl: Vec<AssociatedF32> = base
                    .iter()
                    .map(|v| {
                        let s = |x: u64| (x as f64 / full as f64) as f32;
                        AssociatedF32 {
                            c: [s(v[0]), s(v[1]), s(v[2])],
                            a: s(v[3]),
                        }
                    })
                    .collect();
                let mut fout = vec![AssociatedF32::default(); chain_len(dims)];
                let fchain = build_chain(
                    OpacityBased,
                    float_f,
                    Volume::new(&fl, dims).unwrap(),
                    &mut fout,
                )
                .unwrap();
                let int_levels: Vec<Vec<[u64; 4]>> = if fi == 0 {
                    let v: Vec<_> = base.iter().map(|&x| to_u8(x)).collect();
                    let mut o = vec![AssociatedU8::default(); chain_len(dims)];
                    build_chain_int(IntOpacityBased, qf, &v, dims, &mut o).unwrap();
                    split_levels(dims, &o, raw_u8)
                } else {
                    let v: Vec<_> = base.iter().map(|&x| to_u88(x)).collect();
                    let mut o = vec![IntSample::TRANSPARENT; chain_len(dims)];
                    build_chain_int(IntOpacityBased, qf, &v, dims, &mut o).unwrap();
                    split_levels(dims, &o, raw_u88)
                };
                for (l, iv) in (1u32..).zip(int_levels.iter()) {
                    let fv = fchain.level(l).unwrap().volume().data();
                    let bound = tol::int_vs_float_opacity_lsb(full as f64, delta_a, l);
                    for (g, f) in iv.iter().zip(fv.iter()) {
                        let fr = [f.c[0], f.c[1], f.c[2], f.a].map(|x| f64::from(x) * full as f64);
                        for (&gi, &fx) in g.iter().zip(fr.iter()) {
                            let err = (gi as f64 - fx).abs();
                            worst[fi][k] = worst[fi][k].max(err);
                            worst_ratio = worst_ratio.max(err / bound);
                            assert!(
                                err <= bound,
                                "opacity full {full} level {l}: {gi} vs {fx} (bound {bound})"
                            );
                        }
                    }
                }
            }
            // Extinction-based, depths small enough that no level saturates.
            let levels = level_count(dims);
            let d0_max = (u64::from(MAX_DEPTH_RAW) >> levels).max(1);
            let base: Vec<[u64; 4]> = (0..n).map(|_| random_assoc(&mut rng, d0_max)).collect();
            let fl: Vec<ExtinctionF32> = base
                .iter()
                .map(|v| {
                    let s = |x: u64| (x as f64 / 1_048_576.0) as f32;
                    ExtinctionF32 {
                        c_tau: [s(v[0]), s(v[1]), s(v[2])],
                        tau: s(v[3]),
                    }
                })
                .collect();
            let mut fout = vec![ExtinctionF32::default(); chain_len(dims)];
            let fchain = build_chain(
                ExtinctionBased,
                float_f,
                Volume::new(&fl, dims).unwrap(),
                &mut fout,
            )
            .unwrap();
            let v: Vec<_> = base.iter().map(|&x| to_fx(x)).collect();
            let mut o = vec![ExtinctionFx::default(); chain_len(dims)];
            build_chain_int(IntExtinctionBased, qf, &v, dims, &mut o).unwrap();
            let d0 = base.iter().map(|v| v[3]).max().unwrap_or(0) as f64;
            for (l, iv) in (1u32..).zip(split_levels(dims, &o, raw_fx).iter()) {
                let fv = fchain.level(l).unwrap().volume().data();
                let bound = tol::int_vs_float_extinction_lsb(d0, delta_a, l);
                for (g, f) in iv.iter().zip(fv.iter()) {
                    let fr = [f.c_tau[0], f.c_tau[1], f.c_tau[2], f.tau]
                        .map(|x| f64::from(x) * 1_048_576.0);
                    for (&gi, &fx) in g.iter().zip(fr.iter()) {
                        let err = (gi as f64 - fx).abs();
                        worst[2][k] = worst[2][k].max(err);
                        worst_ratio = worst_ratio.max(err / bound);
                        assert!(
                            err <= bound,
                            "extinction level {l}: {gi} vs {fx} (bound {bound})"
                        );
                    }
                }
            }
        }
    }
    println!(
        "int vs float worst (storage LSB) [own a, quantised a]: u8 {:?}, U8.8 {:?}, Fx {:?}; worst error/bound {worst_ratio:.3}",
        worst[0], worst[1], worst[2]
    );
}

/// Level 1 of the float and integer chains on the named filters, one level at a time: the
/// per-level bound (`ℓ = 1`) is the tight one.
#[test]
fn one_level_within_per_level_bound() {
    let mut rng = Rng(seed() ^ 7);
    let mut worst = 0.0f64;
    for _ in 0..iters() {
        let dims = random_dims(&mut rng);
        let n: usize = dims.iter().product();
        let qf = random_filter(&mut rng);
        let base: Vec<[u64; 4]> = (0..n).map(|_| random_assoc(&mut rng, 255)).collect();
        let v: Vec<_> = base.iter().map(|&x| to_u8(x)).collect();
        let fl: Vec<AssociatedF32> = base
            .iter()
            .map(|v| AssociatedF32 {
                c: [v[0], v[1], v[2]].map(|x| (x as f64 / 255.0) as f32),
                a: (v[3] as f64 / 255.0) as f32,
            })
            .collect();
        let od = level_dims(dims, 1);
        let mut o = vec![AssociatedU8::default(); od.iter().product()];
        downsample_level_int(IntOpacityBased, qf, &v, dims, &mut o).unwrap();
        let mut fo = vec![AssociatedF32::default(); o.len()];
        volsample::downsample::downsample_level(
            OpacityBased,
            qf.to_filter(),
            &Volume::new(&fl, dims).unwrap(),
            &mut fo,
        )
        .unwrap();
        let bound = tol::int_vs_float_opacity_lsb(255.0, 0.0, 1);
        for (g, f) in o.iter().zip(fo.iter()) {
            let fr = [f.c[0], f.c[1], f.c[2], f.a].map(|x| f64::from(x) * 255.0);
            for (&gi, &fx) in g.0.iter().zip(fr.iter()) {
                let err = (f64::from(gi) - fx).abs();
                worst = worst.max(err);
                assert!(err <= bound, "{gi} vs {fx}");
            }
        }
    }
    println!(
        "one level, u8, quantised a: worst {worst:.4} LSB (bound {:.4})",
        tol::int_vs_float_opacity_lsb(255.0, 0.0, 1)
    );
}

fn split_levels<V>(dims: [usize; 3], out: &[V], raw: fn(&V) -> [u64; 4]) -> Vec<Vec<[u64; 4]>> {
    (1..level_count(dims))
        .map(|l| {
            let off = level_offset(dims, l);
            let size: usize = level_dims(dims, l).iter().product();
            out[off..off + size].iter().map(raw).collect()
        })
        .collect()
}

/// The paper's 2×2×2 example in integers: four voxels at `D = 4`, four at 0, the box filter.
/// Extinction-based keeps `D′ = 4·2^20` exactly (`α = 1 − e^(−4)` over one coarse voxel);
/// opacity-based from `α = ⌊255(1 − e^(−4)) + ½⌋ = 250`: `ᾱ = 125`,
/// `α′ = ⌊125·385/255 + ½⌋ = ⌊188.73 + ½⌋ = 189` (0.741, the paper's ≈ 0.74).
#[test]
fn paper_two_by_two_by_two_example() {
    let d = 4u32 << 20;
    let e: [ExtinctionFx; 8] = std::array::from_fn(|i| {
        let t = if i % 2 == 0 { d } else { 0 };
        ExtinctionFx {
            tau: t,
            c_tau: [t; 3],
        }
    });
    let mut o = [ExtinctionFx::default()];
    downsample_level_int(
        IntExtinctionBased,
        IntFilter4::box2(),
        &e,
        [2, 2, 2],
        &mut o,
    )
    .unwrap();
    assert_eq!(
        o[0],
        ExtinctionFx {
            tau: d,
            c_tau: [d; 3]
        }
    );
    let a = (255.0 * (1.0 - (-4.0f64).exp()) + 0.5).floor() as u8;
    assert_eq!(a, 250);
    let v: [AssociatedU8; 8] =
        std::array::from_fn(|i| AssociatedU8([if i % 2 == 0 { a } else { 0 }; 4]));
    let mut o = [AssociatedU8::default()];
    downsample_level_int(IntOpacityBased, IntFilter4::box2(), &v, [2, 2, 2], &mut o).unwrap();
    assert_eq!(o[0], AssociatedU8([189; 4]));
}
