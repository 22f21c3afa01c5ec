//! `extinction-weighted-{nearest,trilinear}`: one integer `ExtinctionWeighted` sample of a
//! 2×2×2 tap set of `ExtinctionFx` voxels, with `φ`/`e^(−x)` tables of `table_size` entries.

use serde_json::{json, Value};
use volsample::fixed_point::extinction::{DEPTH_FRAC_BITS, MAX_DEPTH_RAW};
use volsample::fixed_point::{
    ExtinctionFx, ExtinctionTables, IntExtinction, IntFilter, IntPos, IntSampler,
};
use volsample::{Nearest, StraightU8, Trilinear, Volume};

use super::correction::{push_ratio, ratio_from_value, ratio_values};
use super::prng::{ratio_of_draw, voxel_of_draw, SplitMix64};
use super::sampling::{
    corner_fractions, fractions_from_values, push_fractions, random_fractions, weights_json,
};
use super::{
    mismatch, sample_from, with_frac_bits, Case, Kernel, Layout, Raw, SampleFilter, Spec,
    TableFile, VectorError,
};

/// Width of a U7.20 field (`tau ≤ 2^26` needs 27 bits).
const DEPTH_BITS: u32 = 27;

/// Runs `$body` with the const `$N` set to the runtime table size `$n` (one of
/// [`TABLE_SIZES`](super::TABLE_SIZES)), else `Err(VectorError::TableSize)`.
macro_rules! with_table_size {
    ($n:expr, $N:ident => $body:expr) => {
        match $n {
            5 => {
                const $N: usize = 5;
                $body
            }
            17 => {
                const $N: usize = 17;
                $body
            }
            65 => {
                const $N: usize = 65;
                $body
            }
            257 => {
                const $N: usize = 257;
                $body
            }
            1025 => {
                const $N: usize = 1025;
                $body
            }
            4097 => {
                const $N: usize = 4097;
                $body
            }
            n => Err(VectorError::TableSize(n)),
        }
    };
}

/// Not inlined: the dispatch below instantiates it for every fraction width and filter (and
/// table size), and inlining them all into one function optimized each body twice (the
/// `vectors` module's LLVM function passes took 11.9 s instead of 14.6 in a time trace).
#[inline(never)]
fn run_sampler<Fl: IntFilter, const F: u32, const N: usize>(
    tables: &ExtinctionTables<N>,
    filter: Fl,
    voxels: &[ExtinctionFx; 8],
    frac: [u32; 3],
    ratio: f32,
) -> Result<Raw, VectorError> {
    let vol = Volume::new(voxels, [2, 2, 2])?;
    let mode = IntExtinction::new(tables, ratio)?;
    let pos = IntPos::<F>::new([0; 3], frac)?;
    Ok(sample_from(IntSampler::new(vol, mode, filter).sample(pos)))
}

fn sample_with<const N: usize>(
    tables: &ExtinctionTables<N>,
    spec: &Spec,
    case: &Case,
) -> Result<Raw, VectorError> {
    let (
        Kernel::Extinction(filter),
        Case::Extinction {
            voxels,
            frac,
            ratio,
        },
    ) = (spec.kernel, case)
    else {
        return Err(mismatch(spec.kernel, case));
    };
    let (frac, ratio) = (*frac, *ratio);
    with_frac_bits!(spec.frac_bits, F => match filter {
        SampleFilter::Nearest => run_sampler::<_, F, N>(tables, Nearest, voxels, frac, ratio),
        SampleFilter::Trilinear => {
            run_sampler::<_, F, N>(tables, Trilinear::new(), voxels, frac, ratio)
        }
    })
}

/// The core's sample of one case (builds the tables).
pub(super) fn expected(spec: &Spec, case: &Case) -> Result<Raw, VectorError> {
    with_table_size!(spec.table_size, N => {
        sample_with(&ExtinctionTables::<N>::new(), spec, case)
    })
}

/// The core's samples of many cases (builds the tables once).
pub(super) fn expected_all(
    spec: &Spec,
    cases: &[Case],
) -> Result<Vec<(Raw, Option<u32>)>, VectorError> {
    with_table_size!(spec.table_size, N => {
        let tables = ExtinctionTables::<N>::new();
        cases
            .iter()
            .map(|c| sample_with(&tables, spec, c).map(|s| (s, None)))
            .collect()
    })
}

fn from_u8(v: [u8; 4]) -> ExtinctionFx {
    ExtinctionFx::from_straight_u8(StraightU8(v))
}

fn raw(tau: u32, c_tau: [u32; 3]) -> ExtinctionFx {
    ExtinctionFx { tau, c_tau }
}

/// The corner voxel sets, in order.
fn corner_voxel_sets() -> [[ExtinctionFx; 8]; 12] {
    let equal = |v: ExtinctionFx| [v; 8];
    let one = 1u32 << DEPTH_FRAC_BITS;
    let m = MAX_DEPTH_RAW;
    [
        equal(from_u8([200, 100, 50, 0])),  // α = 0 everywhere: D = 0
        equal(from_u8([255; 4])),           // α = 255: D capped at 64, white
        equal(from_u8([255, 128, 0, 1])),   // α_F = 1
        equal(from_u8([37, 201, 99, 137])), // all eight equal, mid opacity
        equal(raw(m, [m, 0, m / 2])),       // saturating raw depth
        equal(raw(1, [1, 0, 1])),           // the smallest non-zero depth
        equal(raw(one, [one, one / 2, 0])), // D = 1: x = r, the φ/e^(−x) split
        equal(raw(one - 1, [one - 1, 0, one / 3])), // just below the split at r = 1
        equal(raw(16 * one, [16 * one, 0, 8 * one])), // D = 16: x saturates at r = 1
        // Wittenbrink fig. 4 along x: opaque white next to transparent red.
        std::array::from_fn(|i| {
            if i & 1 == 0 {
                from_u8([255; 4])
            } else {
                from_u8([255, 0, 0, 0])
            }
        }),
        // One opaque voxel on the far corner.
        std::array::from_fn(|i| {
            if i == 7 {
                from_u8([255, 64, 0, 255])
            } else {
                ExtinctionFx::default()
            }
        }),
        // Distinct raw depths from 0 to the cap.
        std::array::from_fn(|i| {
            let t = (i as u32) * (m / 7);
            raw(t, [t, t / 2, t / (i as u32 + 1)])
        }),
    ]
}

/// The corner ratios tried at one mixed fraction (the corner fractions use ratio 1).
const CORNER_RATIOS: [f32; 6] = [1.0 / 1_073_741_824.0, 1.0 / 4096.0, 0.25, 4.0, 16.0, 1024.0];

/// The corner cases: each corner voxel set at every corner fraction with ratio 1, then at the
/// mixed fraction `(½ − 2^−F, ½, 1 − 2^−F)` with every corner ratio.
pub(super) fn corner_cases(f: u32) -> Vec<Case> {
    let (m, h) = ((1u32 << f) - 1, 1u32 << (f - 1));
    let mut out = Vec::new();
    for voxels in corner_voxel_sets() {
        for frac in corner_fractions(f) {
            out.push(Case::Extinction {
                voxels,
                frac,
                ratio: 1.0,
            });
        }
        for ratio in CORNER_RATIOS {
            out.push(Case::Extinction {
                voxels,
                frac: [h - 1, h, m],
                ratio,
            });
        }
    }
    out
}

/// One random extinction voxel (see the module docs).
fn random_voxel(rng: &mut SplitMix64) -> ExtinctionFx {
    let w = rng.next_u64();
    let tau = match w >> 62 {
        0 | 1 => return from_u8(voxel_of_draw(w, false)),
        2 => ((w & 0xFFF_FFFF) % (u64::from(MAX_DEPTH_RAW) + 1)) as u32,
        _ => (w & 0xF_FFFF) as u32,
    };
    let mut c_tau = [0u32; 3];
    for c in c_tau.iter_mut() {
        *c = (rng.next_u64() % (u64::from(tau) + 1)) as u32;
    }
    raw(tau, c_tau)
}

pub(super) fn random_case(f: u32, rng: &mut SplitMix64) -> Case {
    let mut voxels = [ExtinctionFx::default(); 8];
    for v in voxels.iter_mut() {
        *v = random_voxel(rng);
    }
    let frac = random_fractions(f, rng);
    let ratio = ratio_of_draw(rng.next_u64());
    Case::Extinction {
        voxels,
        frac,
        ratio,
    }
}

pub(super) fn input_layout(f: u32) -> Layout {
    let mut l = Layout::default();
    for i in 0..8 {
        for ch in ["r", "g", "b"] {
            l.push(
                format!("v{i}_ctau_{ch}"),
                DEPTH_BITS,
                DEPTH_FRAC_BITS,
                "U7.20 D·C = C^τ·d′ (≤ tau)",
            );
        }
        l.push(
            format!("v{i}_tau"),
            DEPTH_BITS,
            DEPTH_FRAC_BITS,
            "U7.20 optical depth per reference distance D = τ·d′ (≤ 2^26, i.e. 64)",
        );
    }
    push_fractions(&mut l, f);
    push_ratio(&mut l);
    l
}

pub(super) fn input_values(case: &Case) -> Result<Vec<u64>, VectorError> {
    let Case::Extinction {
        voxels,
        frac,
        ratio,
    } = case
    else {
        return Err(VectorError::InvalidCase(format!(
            "{case:?} is not an extinction case"
        )));
    };
    let mut v = Vec::with_capacity(8 * 4 + 5);
    for x in voxels {
        v.extend(x.c_tau.map(u64::from));
        v.push(u64::from(x.tau));
    }
    v.extend(frac.map(u64::from));
    v.extend(ratio_values(*ratio)?);
    Ok(v)
}

pub(super) fn case_from_values(v: &[u64]) -> Option<Case> {
    let mut voxels = [ExtinctionFx::default(); 8];
    for (i, x) in voxels.iter_mut().enumerate() {
        let u = |k: usize| u32::try_from(*v.get(4 * i + k)?).ok();
        *x = raw(u(3)?, [u(0)?, u(1)?, u(2)?]);
    }
    Some(Case::Extinction {
        voxels,
        frac: fractions_from_values(v, 32)?,
        ratio: ratio_from_value(*v.get(36)?)?,
    })
}

pub(super) fn rounding_json(filter: SampleFilter, f: u32, n: usize) -> Value {
    let b = (n - 1).trailing_zeros();
    let k = 28 - b;
    json!({
        "weights": weights_json(filter, f),
        "tables": format!("N = {n} = 2^B + 1 entries, B = {b}, k = 28 − B = {k}; interp(T, t) for t < 2^28: i = t >> k (truncate), f = t mod 2^k, interp = T[i]·(2^k − f) + T[i+1]·f (exact)"),
        "outputs": [
            {"output": "(sums, internal)", "rule": "exact",
             "formula": "S_τ = Σ w_i·min(tau_i, 2^26); S_c = Σ w_i·min(ctau_i, min(tau_i, 2^26)) per channel (≤ 2^62)"},
            {"output": "(step depth, internal)", "rule": "round half up, saturate",
             "formula": "x = min(⌊S_τ·ratio_raw/2^(s+24) + ½⌋, 16·2^28), x_c = min(⌊S_c·ratio_raw/2^(s+24) + ½⌋, 16·2^28): the step's optical depth, 28 fractional bits"},
            {"output": "a, r, g, b (x < 2^28)", "rule": "round half up",
             "formula": format!("P = interp(table_phi, x); a = ⌊65280·x·P/2^(59+k) + ½⌋; c = ⌊65280·x_c·P/2^(59+k) + ½⌋ (59 + k = {})", 59 + k)},
            {"output": "a, r, g, b (2^28 ≤ x < 16·2^28)", "rule": "round half up",
             "formula": format!("n = x >> 28; Q = table_exp_int[n − 1]·interp(table_exp, x mod 2^28) (exact); a = ⌊65280·(2^(63+k) − Q)/2^(63+k) + ½⌋ (63 + k = {}); c = ⌊a·S_c/S_τ + ½⌋", 63 + k)},
            {"output": "a, r, g, b (x = 16·2^28, saturated)", "rule": "round half up",
             "formula": "a = 65280; c = ⌊65280·S_c/S_τ + ½⌋"},
        ],
    })
}

pub(super) const GENERATOR_DRAWS: &str = "per voxel i=0..8: w=next(); k=w>>62: k≤1 → the straight voxel r,g,b,a = bytes 0..3 of w; k'=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; converted with ExtinctionFx::from_straight_u8 (tau = ⌊2^20·min(−ln(1 − a/255), 64) + ½⌋, ctau = ⌊(2·tau·c + 255)/510⌋); k=2 → tau = (w & 0xFFFFFFF) mod (2^26 + 1), k=3 → tau = w & 0xFFFFF; for k ≥ 2 then ctau_r, ctau_g, ctau_b each next() mod (tau + 1). Then w=next(); m=2^F−1; fx=w&m, fy=(w>>16)&m, fz=(w>>32)&m; k=(w>>48)&7: 0→all 0, 1→all m, 2→all 2^(F−1). Then w=next(); k=w>>61: 0→ratio=1, 1→ratio=(1 + w mod 4096)/2^20, else ratio=(1 + w mod 65536)/4096 (each exact in f32)";

pub(super) const DESCRIPTION: &str = "one sample of a 2×2×2 tap set of ExtinctionFx voxels: IntSampler::new(Volume::new(v0..v7, [2,2,2]), IntExtinction::new(&ExtinctionTables::<N>::new(), ratio_f32), filter).sample(IntPos::<F>::new([0,0,0], [fx,fy,fz])), voxel i at (i&1, (i>>1)&1, i>>2), N = table_size; tables in table_*.hex";

/// The `φ`/`e^(−x)` tables of `n` entries, as the core builds them
/// (`ExtinctionTables::<n>::new()`).
///
/// # Errors
/// [`VectorError::TableSize`] unless `n` is one of [`TABLE_SIZES`](super::TABLE_SIZES).
pub fn extinction_tables(n: usize) -> Result<Vec<TableFile>, VectorError> {
    with_table_size!(n, N => {
        let t = ExtinctionTables::<N>::new();
        Ok(vec![
            TableFile {
                file: "table_phi.hex",
                bits: 32,
                values: t.phi().iter().map(|&x| u64::from(x)).collect(),
                meaning: "table_phi[j] = ⌊2^31·φ(j/2^B) + ½⌋, φ(x) = (1 − e^(−x))/x, φ(0) = 1, j = 0..N−1, N = table_size = 2^B + 1",
            },
            TableFile {
                file: "table_exp.hex",
                bits: 32,
                values: t.exp().iter().map(|&x| u64::from(x)).collect(),
                meaning: "table_exp[j] = ⌊2^31·e^(−j/2^B) + ½⌋, j = 0..N−1, N = table_size = 2^B + 1",
            },
            TableFile {
                file: "table_exp_int.hex",
                bits: 32,
                values: t.exp_int().iter().map(|&x| u64::from(x)).collect(),
                meaning: "table_exp_int[n − 1] = ⌊2^32·e^(−n) + ½⌋, n = 1..15",
            },
        ])
    })
}
