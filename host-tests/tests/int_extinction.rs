//! Integer `ExtinctionWeighted`: tables, storage conversions and the kernel against their
//! models (bit for bit) and against the exact method and the `f64` reference (within the
//! bounds of `tolerance::integer`), on random inputs, every extreme, and every table size the
//! fuzz target uses; and the table size against the observed error.

use volsample::fixed_point::extinction::MAX_DEPTH_RAW;
use volsample::fixed_point::{
    ExtinctionFx, ExtinctionTables, IntExtinction, IntPos, IntSampler, ONE,
};
use volsample::{Error, Nearest, StraightF32, StraightU8, Trilinear, Volume};
use volsample_host::checks::{self, ExtinctionCell, EXTINCTION_TABLE_SIZES};
use volsample_host::int_model::extinction as em;
use volsample_host::tolerance::integer as tol;

/// SplitMix64 (`VOLSAMPLE_SEED` overrides the seed).
struct Rng(u64);
impl Rng {
    fn new() -> Self {
        let seed = std::env::var("VOLSAMPLE_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0xe7_1c71);
        Rng(seed)
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn iterations() -> usize {
    std::env::var("VOLSAMPLE_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000)
}

fn check_tables<const N: usize>() {
    let t = ExtinctionTables::<N>::new();
    let m = em::tables(N);
    assert_eq!(&t.phi()[..], &m.phi[..], "φ table, N = {N}");
    assert_eq!(&t.exp()[..], &m.exp[..], "exp table, N = {N}");
    assert_eq!(&t.exp_int()[..], &m.exp_int[..], "e^-n table");
    assert_eq!((t.phi()[0], t.exp()[0]), (1 << 31, 1 << 31));
    // Every entry within ½ of the scaled exact value.
    for (j, (&p, &e)) in t.phi().iter().zip(t.exp().iter()).enumerate() {
        let x = j as f64 / (N - 1) as f64;
        assert!((f64::from(p) - em::phi(x) * 2f64.powi(31)).abs() <= 0.5);
        assert!((f64::from(e) - (-x).exp() * 2f64.powi(31)).abs() <= 0.5);
    }
}

#[test]
fn tables_bit_exact_every_entry() {
    check_tables::<5>();
    check_tables::<17>();
    check_tables::<65>();
    check_tables::<257>();
    check_tables::<1025>();
    check_tables::<4097>();
    check_tables::<65537>();
}

/// Every `(C, α)` byte pair: the stored depth and color match the model, are within their
/// stated error, keep `D·C ≤ D`, and `α = 255` takes the float path's cap.
#[test]
fn conversion_every_u8_pair() {
    for a in 0..=255u8 {
        let exact_d = em::depth(f64::from(a) / 255.0);
        for c in 0..=255u8 {
            let v = ExtinctionFx::from_straight_u8(StraightU8([c, 255 - c, c / 3, a]));
            assert_eq!((v.tau, v.c_tau), em::from_u8([c, 255 - c, c / 3, a]));
            assert!((f64::from(v.tau) / em::DEPTH_UNIT - exact_d).abs() <= 0.5 / em::DEPTH_UNIT);
            let dc = f64::from(v.c_tau[0]) / em::DEPTH_UNIT;
            assert!((dc - exact_d * f64::from(c) / 255.0).abs() <= 1.0 / em::DEPTH_UNIT);
            assert!(v.c_tau.iter().all(|&x| x <= v.tau));
        }
    }
    let opaque = ExtinctionFx::from_straight_u8(StraightU8([255; 4]));
    assert_eq!(
        (opaque.tau, opaque.c_tau),
        (MAX_DEPTH_RAW, [MAX_DEPTH_RAW; 3])
    );
    assert_eq!(
        MAX_DEPTH_RAW,
        (volsample::voxel::MAX_OPTICAL_DEPTH as u32) << 20
    );
    let clear = ExtinctionFx::from_straight_u8(StraightU8([255, 255, 255, 0]));
    assert_eq!((clear.tau, clear.c_tau), (0, [0; 3]));
}

#[test]
fn conversion_from_f32() {
    let mut rng = Rng::new();
    let edge = [0.0f32, 1e-30, 1e-7, 0.5, 0.999_999, 1.0];
    for i in 0..20_000 {
        let a = if i < 36 {
            edge[i % 6]
        } else {
            rng.unit() as f32
        };
        let c = if i < 36 {
            [edge[i / 6], 1.0, 0.0]
        } else {
            [rng.unit() as f32, rng.unit() as f32, rng.unit() as f32]
        };
        let v = ExtinctionFx::from_straight_f32(StraightF32 { c, a });
        assert_eq!((v.tau, v.c_tau), em::from_f32(c, a), "c = {c:?}, α = {a}");
        assert!(v.c_tau.iter().all(|&x| x <= v.tau) && v.tau <= MAX_DEPTH_RAW);
    }
    // Out-of-range and NaN input is clamped, never overflows.
    let v = ExtinctionFx::from_straight_f32(StraightF32 {
        c: [f32::NAN, 2.0, -1.0],
        a: f32::NAN,
    });
    assert_eq!((v.tau, v.c_tau), (0, [0; 3]));
    let v = ExtinctionFx::from_straight_f32(StraightF32 {
        c: [2.0, 0.5, -1.0],
        a: 7.0,
    });
    assert_eq!(
        (v.tau, v.c_tau),
        (MAX_DEPTH_RAW, [MAX_DEPTH_RAW, MAX_DEPTH_RAW / 2, 0])
    );
}

#[test]
fn invalid_voxels_rejected_and_ratios_checked() {
    let bad = [ExtinctionFx {
        tau: MAX_DEPTH_RAW + 1,
        c_tau: [0; 3],
    }];
    assert_eq!(
        Volume::new(&bad, [1, 1, 1]).unwrap_err(),
        Error::VoxelOutOfRange { index: 0 }
    );
    let bad = [ExtinctionFx {
        tau: 5,
        c_tau: [0, 6, 0],
    }];
    assert_eq!(
        Volume::new(&bad, [1, 1, 1]).unwrap_err(),
        Error::ColorExceedsOpacity { index: 0 }
    );
    let t = ExtinctionTables::<17>::new();
    for r in [0.0, -1.0, f32::NAN, f32::INFINITY, 4_294_967_296.0] {
        assert_eq!(
            IntExtinction::new(&t, r).unwrap_err(),
            Error::InvalidStep,
            "{r}"
        );
    }
}

fn random_cell(rng: &mut Rng, i: usize) -> (ExtinctionCell, f32) {
    let mut voxels = [[0u8; 4]; 8];
    for v in &mut voxels {
        for b in v.iter_mut() {
            *b = rng.byte();
        }
        match rng.next() % 6 {
            0 => v[3] %= 4,    // faint
            1 => v[3] = 255,   // the cap
            2 => v[3] |= 0xf0, // dense
            _ => {}
        }
    }
    let raw = if i % 7 == 0 {
        [
            [
                rng.next() as u32,
                rng.next() as u32,
                rng.next() as u32,
                rng.next() as u32,
            ],
            [0; 4],
        ]
    } else {
        [[0; 4]; 2]
    };
    let ratio = match i % 5 {
        0 => 1.0,
        1 => 0.5,
        2 => (rng.unit() * 4.0) as f32 + 1e-3,
        3 => (rng.unit() * 0.25) as f32 + 1e-4,
        _ => 2.0,
    };
    (
        ExtinctionCell {
            voxels,
            raw,
            frac: [rng.next() as u32, rng.next() as u32, rng.next() as u32],
            frac_bits_sel: (i % 9) as u8,
            trilinear: i % 4 != 0,
            table_sel: (i / 9 % 4) as u8,
        },
        ratio,
    )
}

/// Random cells at every `F`, table size, filter and a spread of ratios: bit-exact, within
/// the bounds; prints table size against the worst observed error.
#[test]
fn random_inputs_bit_exact_and_within_bounds() {
    let mut rng = Rng::new();
    let mut worst = [[0.0f64; 4]; 4]; // per size: C̃, α vs exact; C̃, α vs reference
    for i in 0..iterations() {
        let (cell, ratio) = random_cell(&mut rng, i);
        let e = checks::extinction_int(&cell, ratio)
            .unwrap_or_else(|e| panic!("{e}\ncell: {cell:?}, r = {ratio}"));
        let w = &mut worst[usize::from(cell.table_sel % 4)];
        w[0] = w[0].max(e.c);
        w[1] = w[1].max(e.a);
        if let Some((c, a)) = e.reference {
            w[2] = w[2].max(c);
            w[3] = w[3].max(a);
        }
    }
    println!("table size N | bound C̃/α (LSB) | worst C̃/α vs exact | worst C̃/α vs f64 reference");
    for (n, w) in EXTINCTION_TABLE_SIZES.iter().zip(worst) {
        println!(
            "{n:>5} | {:.4} / {:.4} | {:.4} / {:.4} | {:.4} / {:.4}",
            tol::extinction_int_c_lsb(*n),
            tol::extinction_int_a_lsb(*n),
            w[0],
            w[1],
            w[2],
            w[3]
        );
    }
    // The bounds are not loose: the rounding alone reaches most of ½, and at N = 17 the
    // chord error shows.
    let w17 = worst[0];
    assert!(w17[1] > 0.5 * tol::extinction_int_a_lsb(17), "{w17:?}");
    let w1025 = worst[3];
    assert!(w1025[1] > 0.45 && w1025[0] > 0.7, "{w1025:?}");
}

#[test]
fn extremes_bit_exact_and_within_bounds() {
    let mut rng = Rng::new();
    let patterns: Vec<[[u8; 4]; 8]> = vec![
        [[0; 4]; 8],
        [[255; 4]; 8],
        [[255, 255, 255, 1]; 8],
        [[255, 0, 128, 254]; 8],
        std::array::from_fn(|i| if i % 2 == 0 { [255; 4] } else { [0; 4] }),
        std::array::from_fn(|i| {
            if i == 7 {
                [255, 0, 255, 255]
            } else {
                [0, 255, 0, 0]
            }
        }),
        std::array::from_fn(|i| if i == 0 { [255; 4] } else { [255, 0, 0, 1] }),
        std::array::from_fn(|_| [rng.byte(), rng.byte(), rng.byte(), 1]),
        std::array::from_fn(|_| [rng.byte(), rng.byte(), rng.byte(), 255]),
    ];
    let ratios = [
        1e-12f32,
        1.0 / 64.0,
        0.125,
        0.5,
        1.0,
        1.0 / 0.7,
        3.99,
        64.0,
        4e9,
    ];
    let raws = [
        [[0; 4]; 2],
        [[MAX_DEPTH_RAW; 4], [1, 1, 0, 1]],
        [[u32::MAX; 4], [MAX_DEPTH_RAW, 0, MAX_DEPTH_RAW, 7]],
    ];
    let mut count = 0;
    for sel in [0u8, 4, 8] {
        let f = 4 + u32::from(sel);
        let max = (1u32 << f) - 1;
        let fracs = [0, 1, 1 << (f - 1), max];
        for voxels in &patterns {
            for raw in raws {
                for fx in fracs {
                    for fz in [0, max] {
                        for (ri, &ratio) in ratios.iter().enumerate() {
                            let cell = ExtinctionCell {
                                voxels: *voxels,
                                raw,
                                frac: [fx, max - fx, fz],
                                frac_bits_sel: sel,
                                trilinear: ri % 3 != 0,
                                table_sel: (ri % 4) as u8,
                            };
                            checks::extinction_int(&cell, ratio)
                                .unwrap_or_else(|e| panic!("{e}\ncell: {cell:?}, r = {ratio}"));
                            count += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(count > 5000);
}

/// The widest accumulators: every voxel at the cap at `F = 12` and the largest ratio. The
/// result is exactly opaque, with the straight color kept exactly.
#[test]
fn widest_accumulators_and_closed_forms() {
    let t = ExtinctionTables::<257>::new();
    let cap = [ExtinctionFx {
        tau: MAX_DEPTH_RAW,
        c_tau: [MAX_DEPTH_RAW, 0, MAX_DEPTH_RAW / 2],
    }; 8];
    let vol = Volume::new(&cap, [2, 2, 2]).unwrap();
    for ratio in [1.0f32, 4_294_967_000.0] {
        let m = IntExtinction::new(&t, ratio).unwrap();
        for frac in [
            [0, 0, 0],
            [2048, 2048, 2048],
            [4095, 4095, 4095],
            [1, 4095, 2048],
        ] {
            let pos = IntPos::<12>::new([0, 0, 0], frac).unwrap();
            let s = IntSampler::new(vol, m, Trilinear::new()).sample(pos);
            assert_eq!((s.c(), s.a()), ([ONE, 0, ONE / 2], ONE));
        }
    }
    // Empty space: exactly transparent whatever the step.
    let zero = [ExtinctionFx::default(); 8];
    let vol = Volume::new(&zero, [2, 2, 2]).unwrap();
    let m = IntExtinction::new(&t, 1000.0).unwrap();
    let s = IntSampler::new(vol, m, Nearest).sample(IntPos::<8>::from_raw([3, 9, 200]));
    assert_eq!((s.c(), s.a()), ([0; 3], 0));
    // Kraus' example through one step of d = d′: α = 1 − e^(−4).
    let one = [ExtinctionFx {
        tau: 4 << 20,
        c_tau: [4 << 20, 0, 0],
    }];
    let vol = Volume::new(&one, [1, 1, 1]).unwrap();
    let s = IntSampler::new(vol, IntExtinction::new(&t, 1.0).unwrap(), Nearest)
        .sample(IntPos::<8>::from_raw([0; 3]));
    let want = f64::from(ONE) * -(-4.0f64).exp_m1();
    assert!((f64::from(s.a()) - want).abs() <= tol::extinction_int_a_lsb(257));
    assert_eq!(s.c(), [s.a(), 0, 0]);
}

/// The checked-in `extinction` corpus reaches the integer kernel: files decode (as the fuzz
/// target decodes them) to cells with voxels, valid ratios, both filters and every table size.
#[test]
fn corpus_exercises_integer_kernel() {
    use arbitrary::{Arbitrary, Unstructured};
    let dir =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/extinction");
    let mut sizes = std::collections::BTreeSet::new();
    let (mut used, mut trilinear, mut raw) = (0, 0, 0);
    for f in std::fs::read_dir(dir).unwrap() {
        let data = std::fs::read(f.unwrap().path()).unwrap();
        let inp = checks::ExtinctionInput::arbitrary_take_rest(Unstructured::new(&data))
            .unwrap_or_default();
        let d = f32::from_bits(inp.d_bits).abs();
        let ratio_ok = volsample::fixed_point::IntRatio::new(d).is_ok_and(|r| r.raw() > 0);
        if ratio_ok && inp.int.voxels.iter().any(|v| v[3] > 0) {
            used += 1;
            trilinear += usize::from(inp.int.trilinear);
            raw += usize::from(inp.int.raw[0][0] != 0);
            sizes.insert(inp.int.table_size());
        }
    }
    assert!(
        used >= 6 && trilinear >= 4 && raw >= 2,
        "{used} {trilinear} {raw}"
    );
    assert_eq!(sizes.len(), EXTINCTION_TABLE_SIZES.len(), "{sizes:?}");
}

/// The `fixed` views of the integer extinction formats carry exactly the kernel's bits: U12.20
/// optical depths (`D = raw/2^20`) and a U32.32 step ratio (round half up of `r·2^32`).
#[test]
fn fixed_crate_views_match_the_raw_formats() {
    use volsample::fixed_point::{ExtinctionFx, IntRatio};
    for a in [0u8, 1, 77, 128, 254, 255] {
        let v = ExtinctionFx::from_straight_u8(volsample::StraightU8([200, 100, 0, a]));
        assert_eq!(v.depth().to_bits(), v.tau);
        assert_eq!(v.depth().to_num::<f64>(), f64::from(v.tau) / 1_048_576.0);
        let want = (-(1.0 - f64::from(a) / 255.0).ln()).min(64.0);
        assert!(
            (v.depth().to_num::<f64>() - want).abs() <= 0.5 / 1_048_576.0 + 1e-12,
            "a={a}"
        );
        for (f, raw) in v.depth_color().iter().zip(v.c_tau) {
            assert_eq!(f.to_bits(), raw);
        }
    }
    for r in [0.25f32, 0.5, 1.0, 1.7, 1000.0] {
        let q = IntRatio::new(r).unwrap().to_fixed();
        assert_eq!(
            q.to_num::<f64>(),
            (f64::from(r) * 4_294_967_296.0 + 0.5).floor() / 4_294_967_296.0
        );
    }
}
