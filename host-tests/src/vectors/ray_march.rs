//! `ray-march-opacity-weighted-{nearest,trilinear}`: one ray of the integer ray marcher at
//! integer sample positions through its own 4×4×4 straight `u8` volume
//! (`IntRayMarcher::march_positions`).

use serde_json::{json, Value};
use volsample::fixed_point::{IntFilter, IntPos, IntStop, ONE};
use volsample::render::IntRayMarcher;
use volsample::{Nearest, OpacityWeighted, Step, StraightU8, Trilinear, Volume};

use super::correction::{push_ratio, ratio_from_value, ratio_values};
use super::prng::{random_sample, random_voxel, ratio_of_draw, SplitMix64};
use super::words::push_u88;
use super::{
    int_sample, raw4, sample_from, with_frac_bits, Case, Layout, Raw, SampleFilter, SampleMode,
    VectorError, ONE_U64,
};

/// The volume of a ray-march vector: 4×4×4 voxels, voxel `i` at `(i & 3, (i >> 2) & 3, i >> 4)`.
pub const RAY_DIMS: [usize; 3] = [4, 4, 4];
/// The most sample positions of one ray-march vector (the `n` field is 5 bits).
pub const RAY_MAX_SAMPLES: u32 = 31;
/// Width of the `n` and `samples` fields.
const SAMPLES_BITS: u32 = 5;

/// The sample positions `p_k = start + k·step` (`k = 0..samples`, per axis, `F` fractional
/// bits) of a ray-march vector.
///
/// # Errors
/// [`VectorError::InvalidCase`] if `samples` exceeds [`RAY_MAX_SAMPLES`] or a position falls
/// outside `u32`.
pub fn ray_positions(
    start: [u32; 3],
    step: [i32; 3],
    samples: u32,
) -> Result<Vec<[u32; 3]>, VectorError> {
    if samples > RAY_MAX_SAMPLES {
        return Err(VectorError::InvalidCase(format!(
            "{samples} ray samples, at most {RAY_MAX_SAMPLES}"
        )));
    }
    (0..i64::from(samples))
        .map(|k| {
            let mut p = [0u32; 3];
            for ((p, &s), &d) in p.iter_mut().zip(&start).zip(&step) {
                let v = i64::from(s) + k * i64::from(d);
                *p = u32::try_from(v).map_err(|_| {
                    VectorError::InvalidCase(format!(
                        "ray position {k} = {v} (start {start:?}, step {step:?}) is outside u32"
                    ))
                })?;
            }
            Ok(p)
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn march<Fl: IntFilter, const F: u32>(
    filter: Fl,
    voxels: &[[u8; 4]; 64],
    positions: &[[u32; 3]],
    ratio: f32,
    a_stop: u16,
    background: Raw,
) -> Result<(Raw, u32), VectorError> {
    let voxels = voxels.map(StraightU8);
    let vol = Volume::new(&voxels, RAY_DIMS)?;
    let marcher = IntRayMarcher::<_, _, _, F>::new(
        vol,
        OpacityWeighted,
        filter,
        IntStop::new(a_stop)?,
        Step::new(ratio)?,
    )?
    .with_background(int_sample(background)?);
    let (s, n) = marcher.march_positions(positions.iter().map(|&p| IntPos::<F>::from_raw(p)));
    Ok((sample_from(s), n))
}

/// The core's composite of one ray and the number of samples it composited.
pub(super) fn expected(
    filter: SampleFilter,
    frac_bits: u32,
    case: &Case,
) -> Result<(Raw, u32), VectorError> {
    let Case::RayMarch {
        voxels,
        start,
        step,
        samples,
        ratio,
        a_stop,
        background,
    } = case
    else {
        return Err(VectorError::InvalidCase(format!(
            "{case:?} is not a ray-march case"
        )));
    };
    let pos = ray_positions(*start, *step, *samples)?;
    let (r, a, bg) = (*ratio, *a_stop, *background);
    with_frac_bits!(frac_bits, F => match filter {
        SampleFilter::Nearest => march::<_, F>(Nearest, voxels, &pos, r, a, bg),
        SampleFilter::Trilinear => march::<_, F>(Trilinear::new(), voxels, &pos, r, a, bg),
    })
}

/// The corner volumes, in order.
fn corner_volumes() -> [[[u8; 4]; 64]; 6] {
    let at = |i: usize| (i & 3, (i >> 2) & 3, i >> 4);
    [
        [[200, 100, 50, 0]; 64],  // α = 0 everywhere
        [[255; 4]; 64],           // α = 255 everywhere (every byte saturated)
        [[37, 201, 99, 137]; 64], // all voxels equal, mid opacity
        [[255, 128, 0, 1]; 64],   // α_F = 1 everywhere
        // An opaque white 2×2×2 core in transparent black air.
        std::array::from_fn(|i| {
            let (x, y, z) = at(i);
            if (1..3).contains(&x) && (1..3).contains(&y) && (1..3).contains(&z) {
                [255; 4]
            } else {
                [0; 4]
            }
        }),
        // A color and opacity gradient.
        std::array::from_fn(|i| {
            let (x, y, z) = at(i);
            [
                (85 * x) as u8,
                (85 * y) as u8,
                (85 * z) as u8,
                (20 * (1 + x + y + z)) as u8,
            ]
        }),
    ]
}

/// The corner rays `(start, step, n)` at `F = f`, in order.
fn corner_rays(f: u32) -> [([u32; 3], [i32; 3], u32); 7] {
    let u = 1u32 << f;
    let (h, l) = (u / 2, 3 * u);
    let s = |x: u32| x as i32;
    [
        ([h, h, h], [0; 3], 0),                 // no sample: background only
        ([0, 3 * h, 3 * h], [s(h), 0, 0], 7),   // along x through the middle
        ([0; 3], [s(h); 3], 7),                 // the main diagonal
        ([l; 3], [0; 3], 1),                    // one sample on the far corner
        ([u, 2 * u, l], [0, 0, -s(u / 4)], 13), // backwards along z
        ([3 * h; 3], [0; 3], RAY_MAX_SAMPLES),  // the most samples, all at the centre
        (
            [1, l, h + 1],
            [s(7 * u / 16), -s(5 * u / 16), s(3 * u / 16)],
            7,
        ), // oblique, off-grid
    ]
}

/// The corner parameters `(ratio, a_stop, background)`, in order.
const CORNER_PARAMS: [(f32, u16, Raw); 5] = [
    (1.0, ONE, [0; 4]),                         // no correction, no stop, transparent
    (1.0, 1, [ONE / 2, ONE / 2, ONE / 2, ONE]), // stop after the first non-zero sample
    (0.5, ONE / 2, [0, 0, ONE, ONE]),           // corrected, stop at half, opaque blue
    (2.0, ONE - 1, [100, 200, 300, 40000]),     // corrected, stop just below 1
    (1.0 / 4096.0, ONE, [ONE; 4]),              // a tiny ratio, opaque white
];

/// The corner cases: every corner volume × ray × parameter set.
pub(super) fn corner_cases(f: u32) -> Vec<Case> {
    let mut out = Vec::new();
    for voxels in corner_volumes() {
        for (start, step, samples) in corner_rays(f) {
            for (ratio, a_stop, background) in CORNER_PARAMS {
                out.push(Case::RayMarch {
                    voxels,
                    start,
                    step,
                    samples,
                    ratio,
                    a_stop,
                    background,
                });
            }
        }
    }
    out
}

/// Three coordinates in `[0, limit]` from one draw.
fn position_of_draw(w: u64, limit: u32) -> [u32; 3] {
    std::array::from_fn(|c| ((w >> (20 * c)) & 0xF_FFFF) as u32 % (limit + 1))
}

pub(super) fn random_case(f: u32, rng: &mut SplitMix64) -> Case {
    let mut voxels = [[0u8; 4]; 64];
    match rng.next_u64() & 3 {
        0 => voxels
            .iter_mut()
            .for_each(|v| *v = random_voxel(rng, false)),
        1 => voxels.iter_mut().for_each(|v| {
            let w = rng.next_u64();
            *v = [
                w as u8,
                (w >> 8) as u8,
                (w >> 16) as u8,
                (w >> 24) as u8 >> 3,
            ];
        }),
        2 => voxels = [random_voxel(rng, false); 64],
        _ => voxels.iter_mut().for_each(|v| {
            let w = rng.next_u64();
            let a = if (w >> 32) & 7 == 0 {
                (w >> 24) as u8
            } else {
                0
            };
            *v = [w as u8, (w >> 8) as u8, (w >> 16) as u8, a];
        }),
    }
    let samples = (rng.next_u64() & 31) as u32;
    let limit = 3 << f;
    let start = position_of_draw(rng.next_u64(), limit);
    let last = position_of_draw(rng.next_u64(), limit);
    let step = std::array::from_fn(|c| {
        let span = i64::from(last[c]) - i64::from(start[c]);
        // Truncation toward zero keeps every p_k between start and last.
        (if samples >= 2 {
            span / i64::from(samples - 1)
        } else {
            span
        }) as i32
    });
    let ratio = ratio_of_draw(rng.next_u64());
    let w = rng.next_u64();
    let a_stop = if w >> 62 < 2 {
        ONE
    } else {
        (1 + (w & 0xFFFF_FFFF) % ONE_U64) as u16
    };
    let background = random_sample(rng);
    Case::RayMarch {
        voxels,
        start,
        step,
        samples,
        ratio,
        a_stop,
        background,
    }
}

pub(super) fn input_layout(f: u32) -> Layout {
    let mut l = Layout::default();
    for i in 0..64 {
        for ch in ["r", "g", "b"] {
            l.push(format!("v{i}_{ch}"), 8, 0, "u8 straight color C");
        }
        l.push(format!("v{i}_a"), 8, 0, "u8 opacity α (255 is opaque)");
    }
    for ax in ["px", "py", "pz"] {
        l.push(
            ax.into(),
            f + 2,
            f,
            "first sample position p, raw/2^F voxel (0 ≤ p ≤ 3·2^F)",
        );
    }
    for ax in ["dx", "dy", "dz"] {
        l.push_signed(
            ax.into(),
            f + 3,
            f,
            "step Δ between sample positions, two's complement, raw/2^F voxel",
        );
    }
    l.push(
        "n".into(),
        SAMPLES_BITS,
        0,
        "number of sample positions p_k = p + k·Δ, k = 0..n−1 (0..=31)",
    );
    push_ratio(&mut l);
    l.push(
        "a_stop".into(),
        16,
        8,
        "U8.8 early-termination threshold A_stop (1..=65280): stop before a sample once A ≥ a_stop",
    );
    push_u88(&mut l, "bg_");
    l
}

pub(super) fn output_layout() -> Layout {
    let mut l = Layout::default();
    push_u88(&mut l, "");
    l.push(
        "samples".into(),
        SAMPLES_BITS,
        0,
        "number of samples composited (n, or fewer when the stop was reached; the background is not counted)",
    );
    l
}

pub(super) fn input_values(case: &Case) -> Result<Vec<u64>, VectorError> {
    let Case::RayMarch {
        voxels,
        start,
        step,
        samples,
        ratio,
        a_stop,
        background,
    } = case
    else {
        return Err(VectorError::InvalidCase(format!(
            "{case:?} is not a ray-march case"
        )));
    };
    let mut v: Vec<u64> = voxels.iter().flatten().map(|&b| u64::from(b)).collect();
    v.extend(start.map(u64::from));
    // Two's complement: the layout keeps the low F + 3 bits.
    v.extend(step.map(|d| i64::from(d) as u64));
    v.push(u64::from(*samples));
    v.extend(ratio_values(*ratio)?);
    v.push(u64::from(*a_stop));
    v.extend(background.map(u64::from));
    Ok(v)
}

/// The value of a `width`-bit two's complement field.
fn sign_extend(v: u64, width: u32) -> i64 {
    let s = 64 - width;
    ((v << s) as i64) >> s
}

pub(super) fn case_from_values(f: u32, v: &[u64]) -> Option<Case> {
    let mut voxels = [[0u8; 4]; 64];
    for (i, b) in voxels.iter_mut().flatten().enumerate() {
        *b = u8::try_from(*v.get(i)?).ok()?;
    }
    let u32_at = |k: usize| u32::try_from(*v.get(k)?).ok();
    let i32_at = |k: usize| i32::try_from(sign_extend(*v.get(k)?, f + 3)).ok();
    Some(Case::RayMarch {
        voxels,
        start: [u32_at(256)?, u32_at(257)?, u32_at(258)?],
        step: [i32_at(259)?, i32_at(260)?, i32_at(261)?],
        samples: u32_at(262)?,
        ratio: ratio_from_value(*v.get(264)?)?,
        a_stop: u16::try_from(*v.get(265)?).ok()?,
        background: raw4(v.get(266..270)?)?,
    })
}

pub(super) fn rounding_json(filter: SampleFilter, f: u32) -> Value {
    json!({
        "positions": "p_k = p + k·Δ per axis, k = 0..n−1, exact (the generator keeps 0 ≤ p_k ≤ 3·2^F); voxel index of p_k: trilinear p_k >> F (truncate), taps at index and index + 1 clamped to 3 (clamp to edge, reached only with weight 0), fraction p_k mod 2^F; nearest ⌊p_k/2^F + ½⌋ (round half up)",
        "sample": super::sampling::rounding_json(SampleMode::OpacityWeighted, filter, f),
        "correction": {
            "when": "ratio_raw ≠ 2^32 (d ≠ d′), applied to every sample",
            "rule": super::correction::rounding_json(),
        },
        "compositing": super::composite::rounding_json(),
        "loop": "acc = 0 (U8.8); samples = 0; for k = 0..n−1: if acc_a ≥ a_stop then stop; s = sample(p_k), corrected when enabled; acc = front_to_back(acc, s); samples += 1. Output: front_to_back(acc, bg) (the same rounding) and samples",
    })
}

pub(super) const GENERATOR_DRAWS: &str = "u=2^F, L=3u. w=next(); style=w&3: 0 → per voxel i=0..64 w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; 1 (haze) → per voxel w=next(); r,g,b = bytes 0..2, a = byte 3 >> 3; 2 (uniform) → one voxel drawn as for style 0, copied to all 64; 3 (sparse) → per voxel w=next(); r,g,b,a = bytes 0..3, a=0 unless (w>>32)&7 = 0. Then w=next(); n = w&31. w=next(); p_c = ((w>>20c)&0xFFFFF) mod (L+1) for c=0,1,2 (x,y,z); w=next(); q_c likewise (the last position); Δ_c = (q_c − p_c)/(n − 1) truncated toward zero if n ≥ 2, else q_c − p_c. Then w=next(); k=w>>61: 0→ratio=1, 1→ratio=(1 + w mod 4096)/2^20, else ratio=(1 + w mod 65536)/4096 (each exact in f32). Then w=next(); a_stop = 65280 if w>>62 < 2, else 1 + (w&0xFFFFFFFF) mod 65280. Then the background as a U8.8 sample: w=next(); k=w>>61: 0→a=0, 1→a=65280, 2→a=256·((w>>8)&255), else a=(w&0xFFFFFFFF) mod 65281; then r,g,b each next() mod (a+1)";

pub(super) const DESCRIPTION: &str = "one ray of IntRayMarcher::<StraightU8, OpacityWeighted, filter, F>::new(Volume::new(v0..v63, [4,4,4]) (voxel i at (i&3, (i>>2)&3, i>>4), d′ = 1), OpacityWeighted, filter, IntStop::new(a_stop), Step::new(ratio_f32)).with_background(bg).march_positions(p_0..p_(n−1)), p_k = p + k·Δ: samples each position, corrects the opacity for d/d′ when the ratio is not 1, composites front to back, stops before a sample once A ≥ a_stop, composites the result over bg; outputs that sample and the number of samples composited. Correction tables in table_*.hex";
