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

/// The rule of one correction (also applied by the ray marcher when `d ≠ d′`): every
/// operation as integer arithmetic, with the tables of [`correction_tables`] by file name.
pub(super) fn rounding_json() -> Value {
    json!({
        "inputs": "v = α of the sample (s_a; U8.8, 0..=65280), c = each of its colors (s_r, s_g, s_b; each ≤ v), r = ratio_raw (U32.32); ratio_f32 is informational and not read",
        "tables": "T[j] is line j of table_T.hex (table_psi: G, table_ln_m: Λ, table_ln_top: K, table_phi: Φ, table_exp: E, table_exp_int: X); interp7(T, j) = T[j >> 7]·(128 − (j & 127)) + T[(j >> 7) + 1]·(j & 127) for 0 ≤ j < 2^15 (exact, < 2^39; j >> 7 is a truncate); interp20(T, t) = T[t >> 20]·(2^20 − (t & (2^20 − 1))) + T[(t >> 20) + 1]·(t & (2^20 − 1)) for 0 ≤ t < 2^28 (exact, ≤ 2^51)",
        "steps": [
            {"step": "1. ends", "rule": "exact",
             "formula": "v = 0: a = 0 and r, g, b = 0; v = 65280: a = 65280 (and step 6 gives c unchanged); otherwise steps 2–6"},
            {"step": "2. optical depth, v < 2^15", "rule": "round half up",
             "formula": "y = (r·v·interp7(G, v) + 2^57) >> 58, i.e. ⌊r·v·interp7(G, v)/2^58 + ½⌋ (product < 2^118): y = r·L with L = −ln(1 − α) in units of 2^−28"},
            {"step": "3. optical depth, v ≥ 2^15", "rule": "round half up; saturate (at 0)",
             "formula": "tv = 65280 − v (1..32512); e = ⌊log2 tv⌋ (0..14, the index of tv's top set bit); m = tv·2^(15−e) − 2^15 (0..2^15 − 1); L = max(K[e] − interp7(Λ, m), 0) (L < 2^43, units 2^−39); y = (r·L + 2^42) >> 43, i.e. ⌊r·L/2^43 + ½⌋ (product < 2^107)"},
            {"step": "4. saturate", "rule": "saturate",
             "formula": "y = min(y, 16·2^28) (then y < 2^33)"},
            {"step": "5. a, y < 2^28", "rule": "round half up",
             "formula": "P = interp20(Φ, y); a = (65280·y·P + 2^78) >> 79, i.e. ⌊65280·y·P/2^79 + ½⌋ (product < 2^95)"},
            {"step": "5. a, 2^28 ≤ y < 16·2^28", "rule": "truncate (yi); round half up (a)",
             "formula": "yi = y >> 28 (1..15); Q = X[yi − 1]·interp20(E, y mod 2^28) (exact, < 2^82); a = (65280·(2^83 − Q) + 2^82) >> 83, i.e. ⌊65280·(2^83 − Q)/2^83 + ½⌋"},
            {"step": "5. a, y = 16·2^28", "rule": "exact", "formula": "a = 65280"},
            {"step": "6. r, g, b", "rule": "round half up",
             "formula": "c_d = ⌊c·a/v + ½⌋ = (2·c·a + v) div (2·v) (c·a ≤ 65280², numerator < 2^33); c_d ≤ a"},
        ],
        "outputs": [
            {"output": "a", "rule": "round half up, truncate, saturate", "formula": "α_d = 1 − (1 − α)^r = 1 − e^(−r·L): steps 1–5"},
            {"output": "r, g, b", "rule": "round half up", "formula": "C̃_d = C̃·α_d/α: step 6 (0 when v = 0)"},
        ],
    })
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
