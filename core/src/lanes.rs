//! The lane types of the kernels: the [`Lanes`] trait over which every kernel concept that
//! runs in lanes is written once (the mode's sums and finish, the extinction step with its
//! `φ`, the clamps of a sample, the front-to-back step with a lane mask, the trilinear
//! weights), and its instances: `f32` (one lane), [`F32x4`] (four consecutive samples of one
//! ray in [`RayMarcher::cast`](crate::RayMarcher::cast) on SIMD targets, or four rays in
//! [`RayMarcher::cast4`](crate::RayMarcher::cast4)) and, on x86-64, the eight AVX2 lanes of
//! `arch::avx2` (eight rays, or eight samples of one ray).
//!
//! Each lane does exactly the `f32` operations of the scalar kernel in the same order. IEEE
//! 754 `+`, `−`, `×` are correctly rounded whatever unit computes them, so **every lane is
//! bit-identical to the scalar kernel** on every target; `tests/fast_paths.rs` in the host
//! tests checks that for every mode and filter.
//!
//! [`F32x4`] is a plain `[f32; 4]` in portable Rust, with no `unsafe` and no target-specific
//! code; the compiler may vectorise the lane loops. (An SSE2 `__m128` representation behind a
//! feature was measured against it and gave no speed-up on x86-64, so it is not offered.)
//!
//! ```
//! use volsample::lanes::F32x4;
//! let x = F32x4::from_array([1.0, 2.0, 3.0, 4.0]);
//! let y = x * x - F32x4::splat(1.0);
//! assert_eq!(y.to_array(), [0.0, 3.0, 8.0, 15.0]);
//! // Clamping as the scalar `Sample::clamped` does: NaN → 0, then into [0, hi].
//! let c = F32x4::from_array([f32::NAN, -1.0, 0.5, 2.0]).clamp_to(F32x4::splat(1.0));
//! assert_eq!(c.to_array(), [0.0, 0.0, 0.5, 1.0]);
//! ```

use core::ops::{Add, Mul, Sub};

use crate::num::Num;

/// Clamps into `[0, hi]`; NaN becomes 0.
#[inline(always)]
pub(crate) fn clamp_to(x: f32, hi: f32) -> f32 {
    // `max` returns the non-NaN operand, so NaN maps to 0.
    x.max(0.0).min(hi)
}

/// The number type of the lane kernels: `f32` itself (one lane), [`F32x4`], and on x86-64
/// the eight AVX2 lanes of `arch::avx2`. Every kernel concept that runs in lanes (the
/// extinction step, the front-to-back step, the clamps of a sample, the sums of every mode,
/// the trilinear weights) is written once over it; each operation is the `f32` operation
/// lane by lane, so every instance is bit-identical to the scalar one (up to the sign of a
/// zero where [`clamp_to`](Self::clamp_to) says so).
pub trait Lanes: Num {
    /// One flag per lane.
    type Mask: Copy;

    /// Each lane clamped into `[0, hi]` with NaN mapped to 0, as `x.max(0.0).min(hi)`, for
    /// `hi ≥ 0` and not NaN. Where `x` or `hi` is a zero, the result may be the other zero
    /// than the scalar one: the kernels only add such a value to an accumulator that starts
    /// at `+0`, or multiply it, so no result of theirs can tell.
    fn clamp_to(self, hi: Self) -> Self;

    /// `x.max(0.0)` per lane (NaN to 0; the sign of a zero as in
    /// [`clamp_to`](Self::clamp_to)).
    fn max0(self) -> Self;

    /// `self < other` per lane (false where either is NaN).
    fn lt(self, other: Self) -> Self::Mask;

    /// `self / other` per lane (IEEE division, correctly rounded in every instance).
    fn div(self, other: Self) -> Self;

    /// Whether every lane of `m` is set.
    fn all(m: Self::Mask) -> bool;

    /// Lane `l` of `a` where `m[l]`, else lane `l` of `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;

    /// `f` of each lane's four values `[x₀, x₁, x₂, x₃]` (one per vector of `x`): the rare
    /// paths a kernel takes lane by lane.
    fn per_lane(x: [Self; 4], f: impl Fn([f32; 4]) -> [f32; 4]) -> [Self; 4];
}

impl Lanes for f32 {
    type Mask = bool;

    #[inline(always)]
    fn clamp_to(self, hi: Self) -> Self {
        clamp_to(self, hi)
    }

    #[inline(always)]
    fn max0(self) -> Self {
        self.max(0.0)
    }

    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }

    #[inline(always)]
    fn div(self, other: Self) -> Self {
        self / other
    }

    #[inline(always)]
    fn all(m: bool) -> bool {
        m
    }

    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m {
            a
        } else {
            b
        }
    }

    #[inline(always)]
    fn per_lane(x: [Self; 4], f: impl Fn([f32; 4]) -> [f32; 4]) -> [Self; 4] {
        f(x)
    }
}

mod repr {
    //! One `f32` per lane.

    /// The lanes.
    pub type Repr = [f32; 4];

    #[inline(always)]
    fn zip(a: Repr, b: Repr, f: impl Fn(f32, f32) -> f32) -> Repr {
        let [a0, a1, a2, a3] = a;
        let [b0, b1, b2, b3] = b;
        [f(a0, b0), f(a1, b1), f(a2, b2), f(a3, b3)]
    }

    #[inline(always)]
    pub const fn from_array(a: [f32; 4]) -> Repr {
        a
    }

    #[inline(always)]
    pub fn to_array(v: Repr) -> [f32; 4] {
        v
    }

    #[inline(always)]
    pub fn splat(x: f32) -> Repr {
        [x; 4]
    }

    #[inline(always)]
    pub fn from_lanes(a: f32, b: f32, c: f32, d: f32) -> Repr {
        [a, b, c, d]
    }

    #[inline(always)]
    pub fn add(a: Repr, b: Repr) -> Repr {
        zip(a, b, |x, y| x + y)
    }

    #[inline(always)]
    pub fn sub(a: Repr, b: Repr) -> Repr {
        zip(a, b, |x, y| x - y)
    }

    #[inline(always)]
    pub fn mul(a: Repr, b: Repr) -> Repr {
        zip(a, b, |x, y| x * y)
    }

    #[inline(always)]
    pub fn div(a: Repr, b: Repr) -> Repr {
        zip(a, b, |x, y| x / y)
    }

    #[inline(always)]
    pub fn clamp_to(x: Repr, hi: Repr) -> Repr {
        zip(x, hi, super::clamp_to)
    }

    #[inline(always)]
    pub fn select(m: [bool; 4], a: Repr, b: Repr) -> Repr {
        let [m0, m1, m2, m3] = m;
        let pick = |m: bool, x: f32, y: f32| if m { x } else { y };
        [
            pick(m0, a[0], b[0]),
            pick(m1, a[1], b[1]),
            pick(m2, a[2], b[2]),
            pick(m3, a[3], b[3]),
        ]
    }
}

/// Four `f32` lanes; every operation is the `f32` operation lane by lane.
#[derive(Clone, Copy)]
pub struct F32x4(repr::Repr);

impl F32x4 {
    /// All lanes `x`.
    #[inline(always)]
    pub fn splat(x: f32) -> Self {
        Self(repr::splat(x))
    }

    /// Lanes from an array, lane 0 first.
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> Self {
        let [a0, a1, a2, a3] = a;
        Self(repr::from_lanes(a0, a1, a2, a3))
    }

    /// The lanes as an array, lane 0 first.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 4] {
        repr::to_array(self.0)
    }

    /// `f(lane)` for each of four values, packed into lanes.
    #[inline(always)]
    pub fn gather<X: Copy>(xs: [X; 4], f: impl Fn(X) -> f32) -> Self {
        let [a, b, c, d] = xs;
        Self(repr::from_lanes(f(a), f(b), f(c), f(d)))
    }

    /// Clamps each lane into `[0, hi]` with NaN mapped to 0, as the scalar kernels clamp
    /// (`x.max(0.0).min(hi)`), for `hi ≥ 0` and not NaN. Where `x` or `hi` is a zero, the
    /// result may be the other zero than the scalar one: the kernels only add such a value to
    /// an accumulator that starts at `+0`, so no result of theirs can tell.
    #[inline(always)]
    pub fn clamp_to(self, hi: Self) -> Self {
        Self(repr::clamp_to(self.0, hi.0))
    }

    /// Lane `l` of `self` where `mask[l]`, else lane `l` of `other`.
    #[inline(always)]
    pub fn select(mask: [bool; 4], a: Self, b: Self) -> Self {
        Self(repr::select(mask, a.0, b.0))
    }
}

impl core::fmt::Debug for F32x4 {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_tuple("F32x4").field(&self.to_array()).finish()
    }
}

impl PartialEq for F32x4 {
    /// Lane-wise `==` on every lane (so NaN ≠ NaN, `+0 == −0`).
    fn eq(&self, other: &Self) -> bool {
        self.to_array() == other.to_array()
    }
}

impl Add for F32x4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, rhs: Self) -> Self {
        Self(repr::add(self.0, rhs.0))
    }
}

impl Sub for F32x4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        Self(repr::sub(self.0, rhs.0))
    }
}

impl Mul for F32x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, rhs: Self) -> Self {
        Self(repr::mul(self.0, rhs.0))
    }
}

impl Num for F32x4 {
    const ZERO: Self = Self(repr::from_array([0.0; 4]));
    const ONE: Self = Self(repr::from_array([1.0; 4]));
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        Self::splat(x)
    }
}

impl Lanes for F32x4 {
    type Mask = [bool; 4];

    #[inline(always)]
    fn clamp_to(self, hi: Self) -> Self {
        Self(repr::clamp_to(self.0, hi.0))
    }

    #[inline(always)]
    fn max0(self) -> Self {
        let [a, b, c, d] = self.to_array();
        Self::from_array([a.max(0.0), b.max(0.0), c.max(0.0), d.max(0.0)])
    }

    #[inline(always)]
    fn lt(self, other: Self) -> [bool; 4] {
        let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (self.to_array(), other.to_array());
        [a0 < b0, a1 < b1, a2 < b2, a3 < b3]
    }

    #[inline(always)]
    fn div(self, other: Self) -> Self {
        Self(repr::div(self.0, other.0))
    }

    #[inline(always)]
    fn all(m: [bool; 4]) -> bool {
        let [m0, m1, m2, m3] = m;
        m0 & m1 & m2 & m3
    }

    #[inline(always)]
    fn select(m: [bool; 4], a: Self, b: Self) -> Self {
        Self(repr::select(m, a.0, b.0))
    }

    #[inline(always)]
    fn per_lane(x: [Self; 4], f: impl Fn([f32; 4]) -> [f32; 4]) -> [Self; 4] {
        let [l0, l1, l2, l3] = unpack(x);
        pack([f(l0), f(l1), f(l2), f(l3)])
    }
}

/// Transposes four lanes of `N` values into `N` lane vectors: `out[k]` lane `l` is
/// `rows[l][k]`.
#[inline(always)]
pub(crate) fn pack<const N: usize>(rows: [[f32; N]; 4]) -> [F32x4; N] {
    let [r0, r1, r2, r3] = rows;
    let mut out = [F32x4::ZERO; N];
    for ((((o, a), b), c), d) in out.iter_mut().zip(r0).zip(r1).zip(r2).zip(r3) {
        *o = F32x4(repr::from_lanes(a, b, c, d));
    }
    out
}

/// The inverse of [`pack`]: lane `l` of every vector, per lane.
#[inline(always)]
pub(crate) fn unpack<const N: usize>(v: [F32x4; N]) -> [[f32; N]; 4] {
    let mut out = [[0.0f32; N]; 4];
    for (k, x) in v.iter().enumerate() {
        let [a, b, c, d] = x.to_array();
        for (row, y) in out.iter_mut().zip([a, b, c, d]) {
            if let Some(slot) = row.get_mut(k) {
                *slot = y;
            }
        }
    }
    out
}
