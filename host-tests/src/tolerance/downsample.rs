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
