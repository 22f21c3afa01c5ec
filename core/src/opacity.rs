//! Opacity correction and the stable forms of the extinction integral.
//!
//! * [`phi`]: `φ(x) = (1 − e^(−x))/x`, with `φ(0) = 1`, so that `α/τ = d·φ(τd)` stays finite
//!   as `τ → 0`.
//! * [`correct`]: opacity correction `α_d = 1 − (1 − α)^(d/d′)`, `C̃_d = C̃·α_d/α`, computed as
//!   `α_d = −expm1((d/d′)·ln1p(−α))` and `α_d/α = (d/d′)·φ(x)·ψ(α)` with
//!   `x = −(d/d′)·ln1p(−α)` and `ψ(α) = −ln1p(−α)/α`, which is finite for every `α < 1`
//!   (it tends to `d/d′` as `α → 0`) and needs no special case below `α = 1`; for `x ≥ 1`
//!   as `C̃_d = (C̃/α)·α_d`, which stays finite when `x` overflows (`d′ → 0`).
//! * [`Correction`]: the stage chosen by type; [`Uncorrected`] is the identity and costs
//!   nothing when `d = d′`.

use crate::lanes::F32x4;
use crate::mode::{pack_interp, unpack_interp};
use crate::sample::{clamp01, Interp, Sample};

/// Below this `x`, [`phi`] uses its Taylor polynomial `1 − x/2 + x²/6 − x³/24`.
///
/// Chosen where the truncation error (`x⁴/120 ≈ 8e-19`) and the cancellation error of
/// `expm1(−x)/x` are both far below half an ulp of `f32`.
pub const PHI_SERIES_BELOW: f32 = 1.0e-4;

/// `φ(x) = (1 − e^(−x))/x` for `x ≥ 0`, `φ(0) = 1`, `φ(∞) = 0`.
///
/// Error bound: relative error at most `4ε` (`ε = 2⁻²³`) for every finite `x ≥ 0`
/// (`PHI_REL` in the tests' tolerance table).
/// Negative `x` (not produced by the kernels) is evaluated by the same formula; NaN gives NaN.
#[inline]
pub fn phi(x: f32) -> f32 {
    phi_with(x, || -libm::expm1f(-x))
}

/// The arguments `x` for which `libm::expm1f` takes its primary-range path (no argument
/// reduction, `k = 0`): `2⁻²⁵ ≤ |x| ≤ ½ ln 2` by the bits of `|x|` (NaN excluded).
#[inline(always)]
fn expm1f_primary(x: f32) -> bool {
    (0x3300_0000..=0x3eb1_7218).contains(&(x.to_bits() & 0x7fff_ffff))
}

/// `libm::expm1f` of four lanes, bit-identical lane by lane: where every lane lies in the
/// library's primary range (`2⁻²⁵ ≤ |x| ≤ ½ ln 2`, the common case of the extinction kernels,
/// whose `τd` is mostly below 0.35) its rational approximation without branches, so that the
/// four lanes vectorise; otherwise `libm::expm1f` per lane. (The host suite checks the
/// primary range exhaustively.)
#[inline(always)]
pub(crate) fn expm1f_x4(x: [f32; 4]) -> [f32; 4] {
    if !x.iter().all(|&x| expm1f_primary(x)) {
        return x.map(libm::expm1f);
    }
    // FreeBSD's `s_expm1f.c` (as `libm` 0.2) for `k = 0`, its constants by their bits.
    let q1 = f32::from_bits(0xbd08_8868); // −0x888868p−28
    let q2 = f32::from_bits(0x3acf_3010); // 0xcf3010p−33
    x.map(|x| {
        let hfx = 0.5 * x;
        let hxs = x * hfx;
        let r1 = 1.0 + hxs * (q1 + hxs * q2);
        let t = 3.0 - r1 * hfx;
        let e = hxs * ((r1 - t) / (6.0 - x * t));
        x - (x * e - hxs)
    })
}

/// [`expm1f_x4`], exposed for the host suite's exhaustive check (not part of the API).
#[doc(hidden)]
pub fn expm1f_lanes(x: [f32; 4]) -> [f32; 4] {
    expm1f_x4(x)
}

/// [`phi`] with `1 − e^(−x)` supplied by the caller (who has computed it already): the
/// extinction step needs both, and one `expm1f` per sample instead of two. Bit-identical to
/// `phi(x)` when `one_minus_exp` returns `-libm::expm1f(-x)`.
#[inline(always)]
pub(crate) fn phi_with(x: f32, one_minus_exp: impl FnOnce() -> f32) -> f32 {
    if x < PHI_SERIES_BELOW {
        1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0)))
    } else {
        one_minus_exp() / x
    }
}

/// `ψ(α) = −ln(1 − α)/α` for `α ∈ (0, 1)`, `ψ(0) = 1` (the limit).
#[inline]
fn psi(a: f32) -> f32 {
    if a > 0.0 {
        -libm::log1pf(-a) / a
    } else {
        1.0
    }
}

/// Corrects an associated sample whose opacity holds for `d′` to the step `d`, where
/// `ratio = d/d′`: `α_d = 1 − (1 − α)^ratio`, `C̃_d = C̃·α_d/α`.
///
/// Stable for every `α ∈ [0, 1]` and every finite `ratio > 0`: `α = 0` gives 0, `α = 1`
/// gives `α_d = 1` and `C̃_d = C̃`, subnormal `α` gives `C̃·ratio`, and no intermediate is
/// NaN. `ratio = 1` returns the sample unchanged up to rounding; the pipeline skips the stage
/// altogether in that case (see [`Uncorrected`]).
///
/// Error bound: `α_d` and each `C̃_d` within 8 ulp (relative to 1, for `C̃_d`, times
/// `max(1, ratio)`) of the exact value for the given `f32` input (`CORRECTION_ABS` in
/// the tests).
#[inline]
pub fn correct(s: Sample, ratio: f32) -> Sample {
    let a = s.a;
    if a >= 1.0 {
        return Sample::clamped(s.c, 1.0);
    }
    if a <= 0.0 {
        return Sample::TRANSPARENT;
    }
    let x = -ratio * libm::log1pf(-a);
    let a_d = clamp01(-libm::expm1f(-x));
    if x >= 1.0 {
        // Dense: `C̃_d = (C̃/α)·α_d`, the straight color times `α_d` (as `integrate_step`
        // does for `τd ≥ 1`). The gain `ratio·φ(x)·ψ(α)` below would be `∞·0` once `x`
        // overflows (`d/d′ ≳ 10³⁷`, i.e. `d′ → 0`) and turned dense color black.
        return Sample::clamped(s.c.map(|c| (c / a) * a_d), a_d);
    }
    let gain = ratio * phi(x) * psi(a);
    Sample::clamped(s.c.map(|c| c * gain), a_d)
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Uncorrected {}
    impl Sealed for super::Corrected {}
}

/// The opacity-correction stage of a pipeline, chosen by type.
pub trait Correction: sealed::Sealed + Copy + core::fmt::Debug {
    /// Applies the correction to one sample.
    fn apply(&self, s: Sample) -> Sample;

    /// [`apply`](Self::apply) to four samples in lanes (`c` associated color, `a` opacity),
    /// lane by lane (bit-identical).
    #[inline(always)]
    fn apply_x4(&self, s: Interp<F32x4>) -> Interp<F32x4> {
        pack_interp(unpack_interp(s).map(|x| {
            let y = self.apply(Sample { c: x.c, a: x.a });
            Interp { c: y.c, a: y.a }
        }))
    }
}

/// No correction: the step equals the reference distance (`d = d′`), where correction is
/// the identity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Uncorrected;

impl Correction for Uncorrected {
    #[inline(always)]
    fn apply(&self, s: Sample) -> Sample {
        s
    }

    #[inline(always)]
    fn apply_x4(&self, s: Interp<F32x4>) -> Interp<F32x4> {
        s
    }
}

/// Opacity correction to a step `d ≠ d′` ([`correct`] with `ratio = d/d′`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Corrected {
    ratio: f32,
}

impl Corrected {
    /// Correction for the ratio `d/d′`; `None` unless it is finite and positive.
    pub fn new(ratio: f32) -> Option<Self> {
        (ratio.is_finite() && ratio > 0.0).then_some(Self { ratio })
    }

    /// `d/d′`.
    pub fn ratio(&self) -> f32 {
        self.ratio
    }
}

impl Correction for Corrected {
    #[inline(always)]
    fn apply(&self, s: Sample) -> Sample {
        correct(s, self.ratio)
    }
}
