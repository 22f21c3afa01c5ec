//! The opacity-based sampling kernels: `opacity-weighted-*`, `separate-*`, `preweighted-*`
//! (one sample of a 2×2×2 tap set), and the fraction and weight parts the extinction kernels
//! share.

use serde_json::{json, Value};
use volsample::fixed_point::{premultiply, IntFilter, IntMode, IntPos, IntSampler};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Nearest, OpacityWeighted, Preweighted, Separate, StraightU8, Trilinear, Volume,
};

use super::prng::{random_voxel, SplitMix64};
use super::VectorError;
use super::{sample_from, with_frac_bits, Case, Layout, Raw, SampleFilter, SampleMode};

/// Not inlined: the dispatch below instantiates it for every fraction width, mode and filter,
/// and inlining them all into one function optimized each body twice (the
/// `vectors` module's LLVM function passes took 11.9 s instead of 14.6 in a time trace).
#[inline(never)]
fn run_sampler<V: Voxel, M: IntMode<V>, Fl: IntFilter, const F: u32>(
    voxels: &[V; 8],
    mode: M,
    filter: Fl,
    frac: [u32; 3],
) -> Result<Raw, VectorError> {
    let vol = Volume::new(voxels, [2, 2, 2])?;
    let pos = IntPos::<F>::new([0; 3], frac)?;
    Ok(sample_from(IntSampler::new(vol, mode, filter).sample(pos)))
}

fn sample_kernel<const F: u32>(
    mode: SampleMode,
    filter: SampleFilter,
    voxels: &[[u8; 4]; 8],
    frac: [u32; 3],
) -> Result<Raw, VectorError> {
    let straight = voxels.map(StraightU8);
    let assoc = voxels.map(AssociatedU8);
    match (mode, filter) {
        (SampleMode::OpacityWeighted, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&straight, OpacityWeighted, Nearest, frac)
        }
        (SampleMode::OpacityWeighted, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&straight, OpacityWeighted, Trilinear::new(), frac)
        }
        (SampleMode::Separate, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&straight, Separate, Nearest, frac)
        }
        (SampleMode::Separate, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&straight, Separate, Trilinear::new(), frac)
        }
        (SampleMode::Preweighted, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&assoc, Preweighted, Nearest, frac)
        }
        (SampleMode::Preweighted, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&assoc, Preweighted, Trilinear::new(), frac)
        }
    }
}

/// The core's sample of a tap set at `F = frac_bits`.
pub(super) fn expected(
    mode: SampleMode,
    filter: SampleFilter,
    frac_bits: u32,
    voxels: &[[u8; 4]; 8],
    frac: [u32; 3],
) -> Result<Raw, VectorError> {
    with_frac_bits!(frac_bits, F => sample_kernel::<F>(mode, filter, voxels, frac))
}

/// The corner fractions, in order: all 0, all `m`, all `½`, all just below `½`, and two mixed.
pub(super) fn corner_fractions(f: u32) -> [[u32; 3]; 6] {
    let m = (1u32 << f) - 1;
    let h = 1u32 << (f - 1);
    [
        [0, 0, 0],
        [m, m, m],
        [h, h, h],
        [h - 1, h - 1, h - 1],
        [0, m, h],
        [m, h, 0],
    ]
}

/// The corner voxel sets (straight), in order.
pub(super) fn corner_voxel_sets() -> [[[u8; 4]; 8]; 9] {
    let equal = |v: [u8; 4]| [v; 8];
    let distinct: [[u8; 4]; 8] =
        std::array::from_fn(|i| [(i * 31) as u8, 255 - (i * 29) as u8, (i * 17) as u8, 0]);
    let with_a = |a: fn(usize) -> u8| {
        let mut v = distinct;
        for (i, x) in v.iter_mut().enumerate() {
            x[3] = a(i);
        }
        v
    };
    [
        equal([200, 100, 50, 0]),    // α = 0 everywhere
        equal([255, 255, 255, 255]), // every byte saturated
        equal([255, 128, 0, 1]),     // α_F = 1
        equal([37, 201, 99, 137]),   // all eight equal, mid opacity
        equal([0, 0, 0, 0]),         // all zero
        // Wittenbrink fig. 4 along x: opaque white next to transparent red.
        std::array::from_fn(|i| {
            if i & 1 == 0 {
                [255, 255, 255, 255]
            } else {
                [255, 0, 0, 0]
            }
        }),
        with_a(|i| if i % 2 == 0 { 0 } else { 255 }),
        with_a(|_| 1),
        with_a(|i| if i == 7 { 255 } else { 0 }),
    ]
}

/// The corner cases: every corner voxel set at every corner fraction.
pub(super) fn corner_cases(mode: SampleMode, f: u32) -> Vec<Case> {
    let mut out = Vec::new();
    for set in corner_voxel_sets() {
        let set = if mode == SampleMode::Preweighted {
            set.map(|[r, g, b, a]| [premultiply(r, a), premultiply(g, a), premultiply(b, a), a])
        } else {
            set
        };
        for frac in corner_fractions(f) {
            out.push(Case::Sample { voxels: set, frac });
        }
    }
    out
}

/// The random fractions: one draw (see the module docs).
pub(super) fn random_fractions(f: u32, rng: &mut SplitMix64) -> [u32; 3] {
    let m = (1u64 << f) - 1;
    let w = rng.next_u64();
    let mut frac = [w & m, (w >> 16) & m, (w >> 32) & m].map(|x| x as u32);
    match (w >> 48) & 7 {
        0 => frac = [0; 3],
        1 => frac = [m as u32; 3],
        2 => frac = [1 << (f - 1); 3],
        _ => {}
    }
    frac
}

pub(super) fn random_case(mode: SampleMode, f: u32, rng: &mut SplitMix64) -> Case {
    let mut voxels = [[0u8; 4]; 8];
    for v in voxels.iter_mut() {
        *v = random_voxel(rng, mode == SampleMode::Preweighted);
    }
    let frac = random_fractions(f, rng);
    Case::Sample { voxels, frac }
}

/// Appends `fx, fy, fz` (`F` bits each).
pub(super) fn push_fractions(l: &mut Layout, f: u32) {
    for ax in ["fx", "fy", "fz"] {
        l.push(
            ax.to_string(),
            f,
            f,
            "fraction of the position within the tap set, raw/2^F voxel",
        );
    }
}

pub(super) fn input_layout(mode: SampleMode, f: u32) -> Layout {
    let mut l = Layout::default();
    let color = if mode == SampleMode::Preweighted {
        "u8 premultiplied color C̃ (≤ α)"
    } else {
        "u8 straight color C"
    };
    for i in 0..8 {
        for ch in ["r", "g", "b"] {
            l.push(format!("v{i}_{ch}"), 8, 0, color);
        }
        l.push(format!("v{i}_a"), 8, 0, "u8 opacity α (255 is opaque)");
    }
    push_fractions(&mut l, f);
    l
}

pub(super) fn input_values(voxels: &[[u8; 4]; 8], frac: [u32; 3]) -> Vec<u64> {
    voxels
        .iter()
        .flatten()
        .map(|&b| u64::from(b))
        .chain(frac.iter().map(|&f| u64::from(f)))
        .collect()
}

/// The fractions at field values `v[at..at + 3]`.
pub(super) fn fractions_from_values(v: &[u64], at: usize) -> Option<[u32; 3]> {
    Some([
        u32::try_from(*v.get(at)?).ok()?,
        u32::try_from(*v.get(at + 1)?).ok()?,
        u32::try_from(*v.get(at + 2)?).ok()?,
    ])
}

pub(super) fn case_from_values(v: &[u64]) -> Option<Case> {
    let mut voxels = [[0u8; 4]; 8];
    for (i, b) in voxels.iter_mut().flatten().enumerate() {
        *b = u8::try_from(*v.get(i)?).ok()?;
    }
    let frac = fractions_from_values(v, 32)?;
    Some(Case::Sample { voxels, frac })
}

/// The weight rule of a filter at `F = f`.
pub(super) fn weights_json(filter: SampleFilter, f: u32) -> Value {
    let s = 3 * f;
    match filter {
        SampleFilter::Nearest => json!({
            "rule": "round half up",
            "formula": "nearest voxel per axis: ⌊(index·2^F + f)/2^F + ½⌋, i.e. corner bit = (f ≥ 2^(F−1)); weight 1, shift s = 0",
        }),
        SampleFilter::Trilinear => json!({
            "rule": "exact",
            "formula": format!("w_i = wx·wy·wz, per axis the factor of the low corner 2^F − f and of the high corner f (wx from fx, wy from fy, wz from fz; corner i at (i&1, (i>>1)&1, i>>2), so w_0 = (2^F − fx)·(2^F − fy)·(2^F − fz)); exact, each ≤ 2^s; Σ w_i = 2^s, s = 3F = {s}"),
        }),
    }
}

/// The output rules of a mode.
pub(super) fn outputs_json(mode: SampleMode) -> Value {
    match mode {
        SampleMode::OpacityWeighted => json!([
            {"output": "a", "rule": "round half up", "formula": "S_α = Σ w_i·α_i; a = ⌊256·S_α/2^s + ½⌋"},
            {"output": "r, g, b", "rule": "round half up", "formula": "S_c = Σ (w_i·α_i)·C_i; c = ⌊256·S_c/(255·2^s) + ½⌋"},
        ]),
        SampleMode::Separate => json!([
            {"output": "a", "rule": "round half up", "formula": "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"},
            {"output": "(straight C, internal)", "rule": "round half up", "formula": "C = ⌊256·Σ w_i·C_i/2^s + ½⌋"},
            {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊a·C/65280 + ½⌋ = (a·C + 32640) div 65280"},
        ]),
        SampleMode::Preweighted => json!([
            {"output": "a", "rule": "round half up", "formula": "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"},
            {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊256·Σ w_i·min(C̃_i, α_i)/2^s + ½⌋"},
        ]),
    }
}

pub(super) fn rounding_json(mode: SampleMode, filter: SampleFilter, f: u32) -> Value {
    json!({"weights": weights_json(filter, f), "outputs": outputs_json(mode)})
}

/// The random draws of a sampling vector.
pub(super) fn generator_draws(mode: SampleMode) -> &'static str {
    match mode {
        SampleMode::Preweighted => "per voxel i=0..8: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; then each color byte c→⌊(2·c·a+255)/510⌋ (premultiply, round half up). Then w=next(); m=2^F−1; fx=w&m, fy=(w>>16)&m, fz=(w>>32)&m; k=(w>>48)&7: 0→all 0, 1→all m, 2→all 2^(F−1)",
        _ => "per voxel i=0..8: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255. Then w=next(); m=2^F−1; fx=w&m, fy=(w>>16)&m, fz=(w>>32)&m; k=(w>>48)&7: 0→all 0, 1→all m, 2→all 2^(F−1)",
    }
}

/// What a sampling vector is.
pub(super) const DESCRIPTION: &str = "one sample of a 2×2×2 tap set: the voxels v0..v7 of a 2×2×2 volume (voxel i at (i&1, (i>>1)&1, i>>2)) sampled at IntPos::<F>::new([0,0,0], [fx,fy,fz])";
