//! `composite-front-to-back`: one integer front-to-back compositing step.

use serde_json::{json, Value};
use volsample::fixed_point::{front_to_back, ONE};

use super::prng::{random_sample, SplitMix64};
use super::words::push_u88;
use super::{int_sample, raw4, sample_from, Case, Layout, Raw, VectorError};

pub(super) fn expected(acc: Raw, s: Raw) -> Result<Raw, VectorError> {
    Ok(sample_from(front_to_back(int_sample(acc)?, int_sample(s)?)))
}

pub(super) fn corner_cases() -> Vec<Case> {
    let accs: [Raw; 7] = [
        [0; 4],
        [ONE; 4],
        [ONE / 2, ONE / 4, 0, ONE / 2],
        [ONE - 1; 4],
        [1, 0, 1, 1],
        [256, 256, 0, 256],
        [100, 200, 300, 40000],
    ];
    let samples: [Raw; 7] = [
        [0; 4],
        [ONE; 4],
        [0, 0, 0, ONE],
        [256, 0, 256, 256],
        [1, 1, 1, 1],
        [ONE / 2, ONE / 4, 0, ONE / 2],
        [ONE - 1; 4],
    ];
    accs.iter()
        .flat_map(|&acc| samples.iter().map(move |&s| Case::Composite { acc, s }))
        .collect()
}

pub(super) fn random_case(rng: &mut SplitMix64) -> Case {
    let acc = random_sample(rng);
    let s = random_sample(rng);
    Case::Composite { acc, s }
}

pub(super) fn input_layout() -> Layout {
    let mut l = Layout::default();
    push_u88(&mut l, "acc_");
    push_u88(&mut l, "s_");
    l
}

pub(super) fn input_values(acc: Raw, s: Raw) -> Vec<u64> {
    acc.iter().chain(&s).map(|&x| u64::from(x)).collect()
}

pub(super) fn case_from_values(v: &[u64]) -> Option<Case> {
    Some(Case::Composite {
        acc: raw4(v.get(0..4)?)?,
        s: raw4(v.get(4..8)?)?,
    })
}

/// The rule of one step (also one step of the ray marcher).
pub(super) fn rounding_json() -> Value {
    json!({"outputs": [
        {"output": "r, g, b, a", "rule": "round half up",
         "formula": "T = 65280 − acc_a; x = acc_x + ⌊T·s_x/65280 + ½⌋ = acc_x + (T·s_x + 32640) div 65280"},
    ]})
}

pub(super) const GENERATOR_DRAWS: &str = "acc, then s, each a U8.8 sample: w=next(); k=w>>61: 0→a=0, 1→a=65280, 2→a=256·((w>>8)&255), else a=(w&0xFFFFFFFF) mod 65281; then r,g,b each next() mod (a+1)";

pub(super) const DESCRIPTION: &str =
    "one front-to-back step: volsample::fixed_point::front_to_back(acc, s), acc in front";
