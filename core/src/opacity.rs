//! Opacity correction and the stable forms of the extinction integral.
//!
//! * [`phi`]: `φ(x) = (1 − e^(−x))/x`, with `φ(0) = 1`, so that `α/τ = d·φ(τd)` stays finite
//!   as `τ → 0`; [`phi_poly`], the same below 1 by a polynomial (the extinction kernels' `φ`).
//! * [`correct`]: opacity correction `α_d = 1 − (1 − α)^(d/d′)`, `C̃_d = C̃·α_d/α`, computed as
//!   `α_d = −expm1((d/d′)·ln1p(−α))` and `α_d/α = (d/d′)·φ(x)·ψ(α)` with
//!   `x = −(d/d′)·ln1p(−α)` and `ψ(α) = −ln1p(−α)/α`, which is finite for every `α < 1`
//!   (it tends to `d/d′` as `α → 0`) and needs no special case below `α = 1`; for `x ≥ 1`
//!   as `C̃_d = (C̃/α)·α_d`, which stays finite when `x` overflows (`d′ → 0`). Below
//!   `α = 1/2` and `x = 1` (thin samples, most of a volume's), `ψ` and `φ` come from series
//!   instead of `log1pf` and `expm1f`, so that the kernels' lanes compute it too.
//! * [`Correction`]: the stage; [`Uncorrected`] is the identity and costs nothing when
//!   `d = d′`; `Option<Corrected>` (the marchers') chooses per value, so that one march
//!   serves both.

use crate::each::Each;
use crate::lanes::Lanes;
use crate::num::Num;
use crate::sample::{clamp01, clamped, Interp, Sample};

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
    if x < PHI_SERIES_BELOW {
        1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0)))
    } else {
        -libm::expm1f(-x) / x
    }
}

/// The extinction step's `φ` ([`phi_poly`]) is a polynomial below this `x = τd` (and its
/// `α = x·φ(x)`); from here on the step uses `libm::expm1f`.
pub const PHI_POLY_BELOW: f32 = 1.0;

/// The coefficients `c₀ … c₆` of [`phi_poly`] by their bits: a relative minimax (Remez) fit of
/// `φ` on `[0, 1]` of degree 6 (its own error below `2.5·10⁻⁹`), each rounded to `f32`.
pub(crate) const PHI_POLY: [u32; 7] = [
    0x3f80_0000, // 1
    0xbeff_fff8, // −0.49999976
    0x3e2a_a9bb, // 0.16666310
    0xbd2a_948e, // −0.041645579
    0x3c07_8be1, // 0.0082730958
    0xbaaa_37ed, // −0.0012986638
    0x3906_9df0, // 0.00012838072
];

/// `φ(x) = (1 − e^(−x))/x` for `0 ≤ x < 1` ([`PHI_POLY_BELOW`]) by a polynomial of degree 6 in
/// Estrin's form: `(c₀ + c₁x) + (c₂ + c₃x)·x² + ((c₄ + c₅x) + c₆x²)·x⁴`, with no division and
/// no branch, each operation an IEEE `f32` `+` or `×` (no fused multiply-add, so every unit,
/// scalar or in lanes, rounds it alike). Its chain of dependent operations is five deep where
/// `−expm1f(−x)/x` is seventeen deep, two divisions among them: the extinction kernels use it (with
/// `α = x·φ(x)`) below `τd = 1`.
///
/// Error bound: relative error at most `2ε` (`ε = 2⁻²³`) for every `x` in `[0, 1)`
/// (`PHI_POLY_REL` in the tests' tolerance table; the host suite checks every `f32` from
/// `2⁻¹²` to 1 and a sample below). Outside `[0, 1)` it is not `φ`.
///
/// ```
/// use volsample::opacity::{phi, phi_poly};
/// let x = 0.25f32;
/// assert!((phi_poly(x) - phi(x)).abs() <= 3.0 * f32::EPSILON);
/// assert_eq!(phi_poly(0.0), 1.0);
/// ```
#[inline(always)]
pub fn phi_poly(x: f32) -> f32 {
    phi_poly_in(x)
}

/// [`phi_poly`] in any [`Num`] (the one `φ` polynomial of every kernel: `f32`, lanes).
#[inline(always)]
pub(crate) fn phi_poly_in<T: Num>(x: T) -> T {
    let [b0, b1, b2, b3, b4, b5, b6] = PHI_POLY;
    let c = |b: u32| T::from_f32(f32::from_bits(b));
    let (c0, c1, c2, c3, c4, c5, c6) = (c(b0), c(b1), c(b2), c(b3), c(b4), c(b5), c(b6));
    let x2 = x * x;
    let x4 = x2 * x2;
    let low = (c0 + c1 * x) + (c2 + c3 * x) * x2;
    let high = (c4 + c5 * x) + c6 * x2;
    low + high * x4
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

/// Below this `α` (and where `x = −(d/d′)·ln(1 − α)` is below [`PHI_POLY_BELOW`]),
/// [`correct`] takes `ψ(α)` from a series (that of `atanh`) and `φ(x)` from [`phi_poly`]: no
/// `log1pf`, no `expm1f`, no branch but the test, so that it runs in lanes.
pub const PSI_SERIES_BELOW: f32 = 0.5;

/// `1/(2k + 1)` for `k = 0 … 7`, each the nearest `f32`: the coefficients of
/// `P(t) = Σ tᵏ/(2k + 1)`, the series of `atanh(s)/s` in `t = s²`.
const ATANH_SERIES: [f32; 8] = [
    1.0,
    1.0 / 3.0,
    1.0 / 5.0,
    1.0 / 7.0,
    1.0 / 9.0,
    1.0 / 11.0,
    1.0 / 13.0,
    1.0 / 15.0,
];

/// `ψ(α) = −ln(1 − α)/α` for `0 ≤ α < 1/2` ([`PSI_SERIES_BELOW`]) in any [`Lanes`]: with
/// `q = 1/(2 − α)` and `s = α·q` (so that `1 − α = (1 − s)/(1 + s)`), `−ln(1 − α) =
/// 2·atanh(s) = 2s·P(s²)`, hence `ψ = 2·P(s²)·q`, with `P` ([`ATANH_SERIES`]) to degree 7 in
/// Estrin's form. For `α < 1/2`, `s < 1/3` and `t = s² < 1/9`: the terms left out sum to
/// less than `t⁸/(17·(1 − t)) < 1.6·10⁻⁹` relative. One division; every other operation an
/// IEEE `f32` `+` or `×` (no fused multiply-add), so every lane rounds it as the scalar does.
#[inline(always)]
fn psi_series_in<T: Lanes>(a: T) -> T {
    let [c0, c1, c2, c3, c4, c5, c6, c7] = ATANH_SERIES.each(T::from_f32);
    let q = T::ONE.div(T::from_f32(2.0) - a);
    let s = a * q;
    let t = s * s;
    let t2 = t * t;
    let t4 = t2 * t2;
    let low = (c0 + c1 * t) + (c2 + c3 * t) * t2;
    let high = (c4 + c5 * t) + (c6 + c7 * t) * t2;
    let p = low + high * t4;
    (p + p) * q
}

/// [`correct`]'s series form, in any [`Lanes`]: `ψ` by [`psi_series_in`], `x = r·(α·ψ)`,
/// `φ = phi_poly(x)`, `α_d = x·φ`, `C̃_d = C̃·((r·φ)·ψ)`, clamped; and `x`, which with `α`
/// says where the form holds (`0 ≤ α < 1/2`, `x < 1`; for `α ≤ 0` the clamp gives the
/// transparent sample).
#[inline(always)]
fn correct_series_in<T: Lanes>(i: Interp<T>, ratio: f32) -> (T, Interp<T>) {
    let r = T::from_f32(ratio);
    let psi = psi_series_in(i.a);
    let x = r * (i.a * psi);
    let phi = phi_poly_in(x);
    let gain = (r * phi) * psi;
    let [c0, c1, c2] = i.c;
    let out = Interp {
        c: [c0 * gain, c1 * gain, c2 * gain],
        a: x * phi,
    };
    (x, crate::sample::clamped(out))
}

/// Corrects an associated sample whose opacity holds for `d′` to the step `d`, where
/// `ratio = d/d′`: `α_d = 1 − (1 − α)^ratio`, `C̃_d = C̃·α_d/α`.
///
/// With `x = −ratio·ln(1 − α)`: for `α < 1/2` ([`PSI_SERIES_BELOW`]) and `x < 1`, by series
/// with no `libm` call (`ψ(α) = −ln(1 − α)/α` from the series of `atanh`, `φ` by
/// [`phi_poly`], `α_d = x·φ(x)`, `C̃_d = C̃·ratio·φ(x)·ψ(α)`), the form the kernels' lanes
/// compute; otherwise `α_d = −expm1(−x)` with `x = −ratio·ln1p(−α)`, and
/// `C̃_d = C̃·ratio·φ(x)·ψ(α)` below `x = 1`, `C̃_d = (C̃/α)·α_d` from there on.
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
    correct_one(s.into(), ratio).into()
}

/// [`correct`] of one sample's quantities.
#[inline]
fn correct_one(i: Interp<f32>, ratio: f32) -> Interp<f32> {
    let a = i.a;
    if a >= 1.0 {
        return dense(i);
    }
    if a <= 0.0 {
        return Sample::TRANSPARENT.into();
    }
    if a < PSI_SERIES_BELOW {
        let (x, series) = correct_series_in(i, ratio);
        if x < PHI_POLY_BELOW {
            return series;
        }
    }
    let x = -ratio * libm::log1pf(-a);
    let a_d = clamp01(-libm::expm1f(-x));
    if x >= 1.0 {
        // Dense: `C̃_d = (C̃/α)·α_d`, the straight color times `α_d` (as `integrate_step`
        // does for `τd ≥ 1`). The gain `ratio·φ(x)·ψ(α)` below would be `∞·0` once `x`
        // overflows (`d/d′ ≳ 10³⁷`, i.e. `d′ → 0`) and turned dense color black.
        return clamped(Interp {
            c: i.c.each(|c| (c / a) * a_d),
            a: a_d,
        });
    }
    let gain = ratio * phi(x) * psi(a);
    clamped(Interp {
        c: i.c.each(|c| c * gain),
        a: a_d,
    })
}

/// [`correct`] of an opaque sample (`α ≥ 1`): `α_d = 1`, `C̃` as it is (clamped).
#[inline(always)]
fn dense<T: Lanes>(i: Interp<T>) -> Interp<T> {
    clamped(Interp { c: i.c, a: T::ONE })
}

/// [`correct`] in any [`Lanes`], bit-identical to it lane by lane (a zero's sign aside, as
/// [`Lanes::clamp_to`] says): where every lane is either in the series form (`α < 1/2` and
/// `x < 1`; for `α ≤ 0` it gives the transparent sample) or opaque (finite `α ≥ 1`), each
/// lane's form, selected; otherwise each lane by [`correct`] (out of line).
#[inline(always)]
pub(crate) fn correct_in<T: Lanes>(i: Interp<T>, ratio: f32) -> Interp<T> {
    let (a, one) = (i.a, T::ONE);
    // Whole packets of empty (`α ≤ 0`: below the least subnormal) or opaque (`α ≥ 1`: above
    // the `f32` below 1) samples, as `correct` takes them, before any series.
    if T::all(a.lt(T::from_f32(f32::from_bits(1)))) {
        return Interp {
            c: [T::ZERO; 3],
            a: T::ZERO,
        };
    }
    if T::all(T::from_f32(f32::from_bits(1.0f32.to_bits() - 1)).lt(a)) {
        return dense(i);
    }
    let (x, series) = correct_series_in(i, ratio);
    let thin = a.lt(T::from_f32(PSI_SERIES_BELOW));
    // Below 1 in the lanes that take a form: `x` where thin, 0 where opaque and finite (`α·0`;
    // NaN for an infinite or NaN `α`), 2 in between.
    let test = T::select(thin, x, T::select(a.lt(one), one + one, a * T::ZERO));
    if T::all(test.lt(T::from_f32(PHI_POLY_BELOW))) {
        select(thin, series, dense(i))
    } else {
        correct_per_lane(i, ratio)
    }
}

/// Lane `l` of `a` where `m[l]`, else lane `l` of `b`, in every quantity.
#[inline(always)]
fn select<T: Lanes>(m: T::Mask, a: Interp<T>, b: Interp<T>) -> Interp<T> {
    let [a0, a1, a2] = a.c;
    let [b0, b1, b2] = b.c;
    Interp {
        c: [
            T::select(m, a0, b0),
            T::select(m, a1, b1),
            T::select(m, a2, b2),
        ],
        a: T::select(m, a.a, b.a),
    }
}

/// [`correct`] of each lane ([`correct_in`] where some lane is outside the series form).
#[cold]
#[inline(never)]
fn correct_per_lane<T: Lanes>(i: Interp<T>, ratio: f32) -> Interp<T> {
    crate::sample::per_lane(i, |l| correct_one(l, ratio))
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Uncorrected {}
    impl Sealed for super::Corrected {}
    impl Sealed for Option<super::Corrected> {}
}

/// The opacity-correction stage of a pipeline, chosen by type.
pub trait Correction: sealed::Sealed + Copy + core::fmt::Debug {
    /// Applies the correction to one sample.
    fn apply(&self, s: Sample) -> Sample;

    /// [`apply`](Self::apply) in any [`Lanes`] (`c` associated color, `a` opacity), lane by
    /// lane (bit-identical).
    #[inline(always)]
    #[doc(hidden)]
    fn apply_in<T: Lanes>(&self, s: Interp<T>) -> Interp<T> {
        crate::sample::per_lane(s, |x| self.apply(x.into()).into())
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
    fn apply_in<T: Lanes>(&self, s: Interp<T>) -> Interp<T> {
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

    #[inline(always)]
    fn apply_in<T: Lanes>(&self, s: Interp<T>) -> Interp<T> {
        correct_in(s, self.ratio)
    }
}

/// The correction a marcher chose at construction: [`Corrected`], or none (`d = d′`). One
/// march serves both, branching per sample (or lane packet) on a value that does not change
/// along the ray, instead of one march per stage: a firmware image that never corrects still
/// links a single march.
impl Correction for Option<Corrected> {
    #[inline(always)]
    fn apply(&self, s: Sample) -> Sample {
        match self {
            Some(c) => c.apply(s),
            None => s,
        }
    }

    #[inline(always)]
    fn apply_in<T: Lanes>(&self, s: Interp<T>) -> Interp<T> {
        match self {
            Some(c) => c.apply_in(s),
            None => s,
        }
    }
}
