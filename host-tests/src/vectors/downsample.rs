//! `downsample-opacity-based`: one coarse voxel of integer opacity-based downsampling of `u8`
//! associated voxels (a 64-voxel tap set).

use serde_json::{json, Value};
use volsample::downsample::integer::{downsample_level_int, IntFilter4, IntOpacityBased};
use volsample::fixed_point::premultiply;
use volsample::AssociatedU8;

use super::prng::{random_voxel, SplitMix64};
use super::{Case, Layout, Raw, VectorError};

/// The downsampled coarse voxel of a 64-voxel tap set (see the module docs).
pub(super) fn expected(taps: &[[u8; 4]; 64], a_raw: u32) -> Result<Raw, VectorError> {
    let filter = IntFilter4::from_raw(a_raw)?;
    let mut src = [AssociatedU8([0; 4]); 216];
    for (t, v) in taps.iter().enumerate() {
        let (i, j, k) = (t % 4, (t / 4) % 4, t / 16);
        if let Some(d) = src.get_mut((1 + i) + 6 * ((1 + j) + 6 * (1 + k))) {
            *d = AssociatedU8(*v);
        }
    }
    let mut dst = [AssociatedU8([0; 4]); 27];
    downsample_level_int(IntOpacityBased, filter, &src, [6, 6, 6], &mut dst)?;
    Ok(dst[1 + 3 * (1 + 3)].0.map(u16::from))
}

pub(super) fn corner_cases() -> Vec<Case> {
    let filters = [0u32, 8192, 13107, 16384, 32768];
    let straight: [[[u8; 4]; 64]; 7] = [
        [[200, 100, 50, 0]; 64],  // α = 0 everywhere
        [[255; 4]; 64],           // every byte saturated
        [[255, 128, 0, 1]; 64],   // α_F = 1
        [[37, 201, 99, 137]; 64], // all equal, mid opacity
        std::array::from_fn(|t| if t % 2 == 0 { [255; 4] } else { [255, 0, 0, 0] }),
        // One opaque voxel on an inner tap, one on an outer (corner) tap.
        std::array::from_fn(|t| {
            if t == 21 || t == 63 {
                [255, 64, 0, 255]
            } else {
                [0; 4]
            }
        }),
        std::array::from_fn(|t| {
            [
                (t * 4) as u8,
                255 - (t * 3) as u8,
                (t * 7) as u8,
                (t * 4 + 3) as u8,
            ]
        }),
    ];
    let mut out = Vec::new();
    for set in straight {
        let taps =
            set.map(|[r, g, b, a]| [premultiply(r, a), premultiply(g, a), premultiply(b, a), a]);
        for a_raw in filters {
            out.push(Case::Downsample { taps, a_raw });
        }
    }
    out
}

pub(super) fn random_case(rng: &mut SplitMix64) -> Case {
    let mut taps = [[0u8; 4]; 64];
    for v in taps.iter_mut() {
        *v = random_voxel(rng, true);
    }
    let w = rng.next_u64();
    let a_raw = match w >> 61 {
        0 => 0,
        1 => 8192,
        2 => 13107,
        3 => 16384,
        4 => 32768,
        _ => ((w & 0xFFFF) % 32769) as u32,
    };
    Case::Downsample { taps, a_raw }
}

pub(super) fn input_layout() -> Layout {
    let mut l = Layout::default();
    for t in 0..64 {
        for ch in ["r", "g", "b"] {
            l.push(format!("t{t}_{ch}"), 8, 0, "u8 premultiplied color C̃ (≤ α)");
        }
        l.push(format!("t{t}_a"), 8, 0, "u8 opacity α (255 is opaque)");
    }
    l.push(
        "a_raw".into(),
        16,
        16,
        "outer filter tap a (Q0.16, ≤ 2^15); taps (a, 2^15 − a, 2^15 − a, a)",
    );
    l
}

pub(super) fn output_layout() -> Layout {
    let mut l = Layout::default();
    for ch in ["r", "g", "b"] {
        l.push(ch.to_string(), 8, 0, "u8 premultiplied color C̃′ (≤ α′)");
    }
    l.push("a".into(), 8, 0, "u8 opacity α′ (255 is opaque)");
    l
}

pub(super) fn input_values(taps: &[[u8; 4]; 64], a_raw: u32) -> Vec<u64> {
    taps.iter()
        .flatten()
        .map(|&b| u64::from(b))
        .chain([u64::from(a_raw)])
        .collect()
}

pub(super) fn case_from_values(v: &[u64]) -> Option<Case> {
    let mut taps = [[0u8; 4]; 64];
    for (i, b) in taps.iter_mut().flatten().enumerate() {
        *b = u8::try_from(*v.get(i)?).ok()?;
    }
    Some(Case::Downsample {
        taps,
        a_raw: u32::try_from(*v.get(256)?).ok()?,
    })
}

pub(super) fn rounding_json() -> Value {
    json!({"outputs": [
        {"output": "(filter sums, internal)", "rule": "exact",
         "formula": "S_x = Σ w_i·w_j·w_k·x_t over the 64 taps (x = min(C̃, α) per color, α), w = (a, 2^15 − a, 2^15 − a, a), Σ = 2^48 per unit"},
        {"output": "(guarded means, internal)", "rule": "round half up",
         "formula": "ᾱ_g = ⌊S_α/2^40 + ½⌋, C̄_g = min(⌊S_c/2^40 + ½⌋, ᾱ_g) (8 guard bits)"},
        {"output": "a", "rule": "round half up",
         "formula": "G = 2·256·255 − ᾱ_g; α′ = ⌊ᾱ_g·G/(2^16·255) + ½⌋ (α′ = 1 − (1 − ᾱ)²)"},
        {"output": "r, g, b", "rule": "round half up", "formula": "C̃′ = ⌊C̄_g·G/(2^16·255) + ½⌋"},
    ]})
}

pub(super) const GENERATOR_DRAWS: &str = "per tap t=0..64 as a preweighted sampling voxel: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; each color byte c→⌊(2·c·a+255)/510⌋. Then w=next(); k=w>>61: a_raw = 0, 8192, 13107, 16384, 32768 for k=0..4, else (w&0xFFFF) mod 32769";

pub(super) const DESCRIPTION: &str = "one coarse voxel of volsample::downsample::integer::downsample_level_int(IntOpacityBased, IntFilter4::from_raw(a_raw), …) over AssociatedU8: taps t = i + 4j + 16k are fine voxels (2X−1+i, 2Y−1+j, 2Z−1+k); computed as coarse voxel (1,1,1) of a 6×6×6 volume (no edge clamping)";
