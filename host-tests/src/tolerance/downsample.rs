//! Downsampling bounds (`volsample::downsample`), absolute errors against the f64 reference
//! of the same input; `ε = 2⁻²³` ([`EPS32`]).

use super::EPS32;

/// The filtered channels of one level (three [`Filter4::combine`] passes, `5u` each with
/// `u = ε/2`), relative to the largest input value.
///
/// [`Filter4::combine`]: volsample::downsample::Filter4::combine
pub const FILTERED_PER_LEVEL: f64 = 7.5 * EPS32;

/// One opacity-based level: `α′` and `C̃′` (the correction's slope is at most 2, plus two
/// roundings), absolute.
pub const OPACITY_PER_LEVEL: f64 = 17.0 * EPS32;

/// Level `ℓ` of an opacity-based chain against the f64 chain: `17ε·(2^ℓ − 1)`.
pub fn opacity_chain(level: u32) -> f64 {
    OPACITY_PER_LEVEL * (2f64.powi(level as i32) - 1.0)
}

/// Level `ℓ` of an extinction-based chain against the f64 chain, `τ′` and `C^τ′`:
/// `7.5ε·ℓ·2^ℓ·τ_max`, `τ_max` the largest level-0 `τ`.
pub fn extinction_chain(level: u32, tau_max: f64) -> f64 {
    FILTERED_PER_LEVEL * f64::from(level) * 2f64.powi(level as i32) * tau_max
}

/// Sampling a mip level with `MipLevel::sample` against the reference sample at the same
/// (f32-converted) level position: the sample bounds of the modes, `(1 + taps·(1 + d·τ_max))ε`
/// for extinction and `(1 + taps)ε` plus the correction's `8ε·max(1, d/d′)` for opacity-based
/// levels; this is the common ceiling used for 27 taps, `d·τ_max ≤ 8`.
pub const MIP_SAMPLE: f64 = (1.0 + 27.0 * 9.0 + 8.0 * 4.0) * EPS32;

// ---------------------------------------------------------------------------------------------
// Integer downsampling (`volsample::downsample::integer`), in storage LSBs: `1/255` of full
// scale for `AssociatedU8`, `1/65280` for U8.8 `IntSample`, `2^−20` optical depth for
// `ExtinctionFx`.

/// One opacity-based integer level, `α′` and each `C̃′`, against the exact method with the same
/// quantised taps on the same stored input: the final **round half up** (½) plus the 8-guard-bit
/// rounding of `ᾱ`, `C̄` (`2^−9`) through the correction's slope 2.
pub const INT_OPACITY_LEVEL_LSB: f64 = 0.5 + 1.0 / 256.0;

/// One extinction-based integer level, `D′` and each `(D·C)′`, against the exact method with
/// the same quantised taps on the same stored input (below saturation): one **round half up**.
pub const INT_EXTINCTION_LEVEL_LSB: f64 = 0.5;

/// Gain of the tap quantisation error `|a − a_q|` on one level, times the channel's largest
/// input: three 1D passes of `2|a − a_q|·V` each, doubled by the correction or the doubling.
pub const INT_TAP_GAIN: f64 = 12.0;

/// Level `level ≥ 1` of an integer opacity-based chain (full scale `full`, tap error
/// `delta_a = |a − a_q|`) against the float (`f32`) chain of the same method with the
/// unquantised `a`, on the same input bytes converted to `f32`: per level
/// `B = INT_OPACITY_LEVEL_LSB + 12·delta_a·full + (17 + 1)ε·full` (integer rounding, taps,
/// the float kernel's [`OPACITY_PER_LEVEL`] and the input's conversion to `f32` through the
/// correction), compounded by the correction's slope 2: `B·(2^ℓ − 1)`.
pub fn int_vs_float_opacity_lsb(full: f64, delta_a: f64, level: u32) -> f64 {
    let per =
        INT_OPACITY_LEVEL_LSB + INT_TAP_GAIN * delta_a * full + (OPACITY_PER_LEVEL + EPS32) * full;
    per * (2f64.powi(level as i32) - 1.0)
}

/// Level `level ≥ 1` of an integer extinction-based chain against the float chain (`τ = D/2^20`,
/// `d′ = 1`), U7.20 LSB, for level-0 depths at most `d0_max_raw` and no saturation at any
/// level: `e_0 = ε/2·D₀` (input conversion), `e_j = 2e_{j−1} + ½ + (12·delta_a + 15ε)·2^(j−1)·D₀`
/// (integer rounding, taps, the float kernel's doubled [`FILTERED_PER_LEVEL`]).
pub fn int_vs_float_extinction_lsb(d0_max_raw: f64, delta_a: f64, level: u32) -> f64 {
    let mut e = 0.5 * EPS32 * d0_max_raw;
    for j in 1..=level {
        let v = 2f64.powi(j as i32 - 1) * d0_max_raw;
        e = 2.0 * e
            + INT_EXTINCTION_LEVEL_LSB
            + (INT_TAP_GAIN * delta_a + 2.0 * FILTERED_PER_LEVEL) * v;
    }
    e
}
