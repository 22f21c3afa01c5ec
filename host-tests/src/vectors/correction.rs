//! `opacity-correction`: the table-driven `IntCorrection` of one sample, and its tables (also
//! read by the ray marcher).

use serde_json::{json, Value};
use volsample::fixed_point::correction::PSI_LIMIT;
use volsample::fixed_point::{IntCorrection, IntRatio, ONE};

use super::prng::{random_sample, SplitMix64};
use super::words::push_u88;
use super::{int_sample, raw4, sample_from, Case, Layout, Raw, TableFile, VectorError};

pub(super) fn expected(ratio: f32, s: Raw) -> Result<Raw, VectorError> {
    let corr = IntCorrection::new(ratio)?;
    Ok(sample_from(corr.apply(int_sample(s)?)))
}

pub(super) fn corner_cases() -> Vec<Case> {
    let ratios = [1.0f32, 0.5, 2.0, 0.25, 4.0, 1.0 / 4096.0, 16.0, 65536.0];
    let samples: [Raw; 9] = [
        [0; 4],
        [ONE; 4],
        [256; 4],
        [0, 0, 0, 256],
        [1, 1, 1, 1],
        [ONE - 1; 4],
        [PSI_LIMIT - 1, 0, 1000, PSI_LIMIT - 1],
        [PSI_LIMIT, 0, 1000, PSI_LIMIT],
        [ONE / 2, ONE / 4, 0, ONE / 2],
    ];
    ratios
        .iter()
        .flat_map(|&ratio| samples.iter().map(move |&s| Case::Correction { ratio, s }))
        .collect()
}

pub(super) fn random_case(rng: &mut SplitMix64) -> Case {
    let k = 1 + rng.next_u64() % 65536;
    let ratio = k as f32 / 4096.0;
    let s = random_sample(rng);
    Case::Correction { ratio, s }
}

/// Appends `ratio_raw` (the core's `IntRatio`) and `ratio_f32`.
pub(super) fn push_ratio(l: &mut Layout) {
    l.push(
        "ratio_raw".into(),
        64,
        32,
        "IntRatio: ⌊(d/d′)·2^32 + ½⌋ (round half up)",
    );
    l.push(
        "ratio_f32".into(),
        32,
        0,
        "the ratio d/d′ as IEEE-754 f32 bits (informational; ratio_raw is derived from it)",
    );
}

/// The values of the [`push_ratio`] fields.
pub(super) fn ratio_values(ratio: f32) -> Result<[u64; 2], VectorError> {
    Ok([IntRatio::new(ratio)?.raw(), u64::from(ratio.to_bits())])
}

/// The ratio of the `ratio_f32` field value.
pub(super) fn ratio_from_value(v: u64) -> Option<f32> {
    Some(f32::from_bits(u32::try_from(v).ok()?))
}

pub(super) fn input_layout() -> Layout {
    let mut l = Layout::default();
    push_u88(&mut l, "s_");
    push_ratio(&mut l);
    l
}

pub(super) fn input_values(ratio: f32, s: Raw) -> Result<Vec<u64>, VectorError> {
    let mut v: Vec<u64> = s.iter().map(|&x| u64::from(x)).collect();
    v.extend(ratio_values(ratio)?);
    Ok(v)
}

pub(super) fn case_from_values(v: &[u64]) -> Option<Case> {
    Some(Case::Correction {
        s: raw4(v.get(0..4)?)?,
        ratio: ratio_from_value(*v.get(5)?)?,
    })
}

/// The rule of one correction (also applied by the ray marcher when `d ≠ d′`).
pub(super) fn rounding_json() -> Value {
    json!({"outputs": [
        {"output": "a", "rule": "round half up, truncate, saturate",
         "formula": "α_d = 1 − e^(−r·L), L = −ln(1 − α) from the ψ (α < 2^15) or ln m tables; y = r·L to 28 fractional bits (round half up, saturate at 16); α_d = ⌊65280·y·φ(y) + ½⌋ (y < 1) or ⌊65280·(1 − e^(−y)) + ½⌋ (1 ≤ y < 16) or 65280; α = 0 → 0, α = 65280 → 65280. Exact arithmetic: volsample::fixed_point::correction module docs"},
        {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊C̃·α_d/α + ½⌋ (0 when α = 0)"},
    ]})
}

pub(super) const GENERATOR_DRAWS: &str = "w=next(); ratio=(1 + w mod 65536)/4096 (exact f32); then s as a U8.8 sample: w=next(); k=w>>61: 0→a=0, 1→a=65280, 2→a=256·((w>>8)&255), else a=(w&0xFFFFFFFF) mod 65281; then r,g,b each next() mod (a+1)";

pub(super) const DESCRIPTION: &str = "IntCorrection::new(ratio_f32).apply(s): α_d = 1 − (1 − α)^r, C̃_d = C̃·α_d/α, table driven; tables in table_*.hex";

/// The correction tables (independent of the ratio).
pub fn correction_tables() -> Vec<TableFile> {
    // Any valid ratio: the tables do not depend on it.
    let Ok(c) = IntCorrection::new(1.0) else {
        return Vec::new();
    };
    let t = c.exp_tables();
    vec![
        TableFile {
            file: "table_psi.hex",
            bits: 32,
            values: c.psi_table().iter().map(|&x| u64::from(x)).collect(),
            meaning: "G[j] = ⌊2^47·ψ(128·j/65280)/65280 + ½⌋, ψ(α) = −ln(1 − α)/α, j = 0..256",
        },
        TableFile {
            file: "table_ln_m.hex",
            bits: 32,
            values: c.ln_table().iter().map(|&x| u64::from(x)).collect(),
            meaning: "Λ[j] = ⌊2^32·ln(1 + j/256) + ½⌋, j = 0..256",
        },
        TableFile {
            file: "table_ln_top.hex",
            bits: 44,
            values: c.ln_top().to_vec(),
            meaning: "K[e] = ⌊2^39·ln(65280/2^e) + ½⌋, e = 0..14",
        },
        TableFile {
            file: "table_phi.hex",
            bits: 32,
            values: t.phi().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^31·φ(j/256) + ½⌋, φ(x) = (1 − e^(−x))/x, j = 0..256",
        },
        TableFile {
            file: "table_exp.hex",
            bits: 32,
            values: t.exp().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^31·e^(−j/256) + ½⌋, j = 0..256",
        },
        TableFile {
            file: "table_exp_int.hex",
            bits: 32,
            values: t.exp_int().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^32·e^(−n) + ½⌋, n = 1..15 (index n − 1)",
        },
    ]
}
