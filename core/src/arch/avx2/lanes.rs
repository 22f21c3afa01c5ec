//! Lane conversions and the kernel's exact integer helpers: arrays to and from vectors,
//! `n/255` of bytes, the compositing's `⌊(t·x + ONE/2)/ONE⌋`, the round-half-up quantization.

use core::arch::x86_64::*;

use super::*;
use crate::each::Each;

/// Eight `f32` lanes from an array.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn lanes(a: [f32; LANES]) -> __m256 {
    let [a0, a1, a2, a3, a4, a5, a6, a7] = a;
    _mm256_setr_ps(a0, a1, a2, a3, a4, a5, a6, a7)
}

/// The lanes as an array.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn array(v: __m256) -> [f32; LANES] {
    map8(to_i32s(_mm256_castps_si256(v)), |x| {
        f32::from_bits(x as u32)
    })
}

/// The lanes of an integer vector as an array (through memory: the eight lanes of a tap's
/// indices are read as scalars, where eight lane extractions cost about 6 % of the kernel's
/// time).
#[inline(always)]
pub(super) fn to_i32s(v: __m256i) -> [i32; LANES] {
    // SAFETY: a bit cast between two 32-byte plain-data types, every bit pattern valid in both.
    unsafe { core::mem::transmute::<__m256i, [i32; LANES]>(v) }
}

/// An integer vector of an array's lanes ([`to_i32s`] inverted).
#[inline(always)]
pub(super) fn from_i32s(a: [i32; LANES]) -> __m256i {
    // SAFETY: as in `to_i32s`.
    unsafe { core::mem::transmute::<[i32; LANES], __m256i>(a) }
}

/// `a.map(f)` without `core::array::map`: that generic is compiled for the baseline (it does
/// not inherit a caller's target features), so a closure with AVX2 instructions passed to it
/// cannot be inlined into it and stays a call; these are inlined into their AVX2 callers
/// first, and the closure then into the caller. (With `map`, the AVX2 packets took 1.11 of
/// their time in the build for an AVX2 CPU, which compiles `map` with AVX2.)
#[inline(always)]
pub(super) fn map8<T, U>(a: [T; 8], mut f: impl FnMut(T) -> U) -> [U; 8] {
    let [a0, a1, a2, a3, a4, a5, a6, a7] = a;
    [f(a0), f(a1), f(a2), f(a3), f(a4), f(a5), f(a6), f(a7)]
}

/// [`map8`] for four elements.
#[inline(always)]
pub(super) fn map4<T, U>(a: [T; 4], mut f: impl FnMut(T) -> U) -> [U; 4] {
    let [a0, a1, a2, a3] = a;
    [f(a0), f(a1), f(a2), f(a3)]
}

/// [`map8`] for three elements.
#[inline(always)]
pub(super) fn map3<T, U>(a: [T; 3], mut f: impl FnMut(T) -> U) -> [U; 3] {
    let [a0, a1, a2] = a;
    [f(a0), f(a1), f(a2)]
}

/// `1/255` as the sum of two `f32`: `UNORM_HI` rounded, `UNORM_LO` the rest rounded.
pub(super) const UNORM_HI: f32 = 1.0 / 255.0;
pub(super) const UNORM_LO: f32 = (1.0f64 / 255.0 - UNORM_HI as f64) as f32;

/// `n/255` per lane for bytes `n` (0..=255), correctly rounded, as `n·HI + (n·LO)` in one
/// multiplication and one fused multiply-add (`1/255 = HI + LO` split into two `f32`). Not
/// correctly rounded for every real `n`, but for each of the 256 bytes: a test here checks
/// them all against the table of `voxel::unorm8`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn unorm8(n: __m256i) -> __m256 {
    let n = _mm256_cvtepi32_ps(n);
    _mm256_fmadd_ps(
        n,
        _mm256_set1_ps(UNORM_HI),
        _mm256_mul_ps(n, _mm256_set1_ps(UNORM_LO)),
    )
}

/// `fixed_point::front_to_back`'s increment `⌊(t·x + ONE/2)/ONE⌋` (**round half up**) in
/// each of the sixteen 16-bit lanes, for `t, x ≤ ONE = 65280 = 255·256`, in `u16` operations
/// only: with the product `t·x = 2^16·h + l` (`vpmulhuw`, `vpmullw`; `h ≤ 65025`), the
/// quotient is `⌊⌊N/256⌋/255⌋` for `N = t·x + ONE/2`, where `⌊N/256⌋ = 256·h + m` and
/// `m = ⌊(l + 32640)/256⌋ ≤ 383`; so it is `h + ⌊(h + m)/255⌋`, and for `y = h + m ≤ 65408`,
/// `⌊y/255⌋ = ⌊(y + 1)·257/2^16⌋` (with `y = 255k + r`, `(y + 1)·257 = 65535k + 257(r + 1)`
/// lies in `[2^16·k, 2^16·(k + 1))` as `k ≤ 256`). `m + 1 = ⌊(l + 32896)/256⌋ =
/// ⌊(⌊l/128⌋ + 257)/2⌋`: the rounding average (`vpavgw`, `⌊(a + b + 1)/2⌋`) of `l >> 7` and
/// 256. (The average of `l` and `32895` shifted by 7, the same value, LLVM widened to `u32`
/// lanes: eight operations for the two.) Eight operations for two channels of eight lanes,
/// where a channel in `u32` lanes took nine (`t·x + ONE/2`, then `⌊n/65280⌋` by two 64-bit
/// `vpmuludq` of its even and odd lanes). A unit test checks every pair `t, x`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn over_u16(t: __m256i, x: __m256i) -> __m256i {
    let (h, l) = (_mm256_mulhi_epu16(t, x), _mm256_mullo_epi16(t, x));
    let m1 = _mm256_avg_epu16(_mm256_srli_epi16::<7>(l), _mm256_set1_epi16(256));
    let q = _mm256_mulhi_epu16(_mm256_add_epi16(h, m1), _mm256_set1_epi16(257));
    _mm256_add_epi16(h, q)
}

/// `⌊256·p + ½⌋` (**round half up**) per lane for `0 ≤ p < 2^14` (`256·p` exact): for
/// `256·p ≥ ½`, i.e. `p ≥ 2⁻⁹`, the rounded `256·p + ½` (one fused multiply-add, the same
/// rounding as the exact product's sum), truncated (a unit test checks every such `f32`);
/// below, 0 (there the rounded sum is 1 for `256·p = ½ − 2⁻²⁵`). The comparison runs beside
/// the multiply-add, not after a product: the integer packets went from 1.03–1.04 to
/// 1.01–1.015 of the `OpacityWeighted` packets' time in a probe (4.70–4.77 → 4.62–4.63
/// ns/sample).
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn quantize8(p: __m256) -> __m256i {
    let up = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(p, _mm256_set1_ps(1.0 / 512.0)));
    let y = _mm256_fmadd_ps(p, _mm256_set1_ps(256.0), _mm256_set1_ps(0.5));
    _mm256_and_si256(_mm256_cvttps_epi32(y), up)
}

/// `(2^32 − 1)/255`: `⌊q/255⌋ = ⌊(q + 1)·RECIP255/2^32⌋` for `q < 2^24` (see [`int_sums`]; a
/// unit test checks every such `q`).
pub(super) const RECIP255: u32 = 0x0101_0101;

/// `fixed_point::ONE` (opacity 1 in U8.8) in an `i32` lane.
pub(super) const INT_ONE: i32 = crate::fixed_point::ONE as i32;

/// Eight `f32` lanes in an AVX2 vector: the [`Lanes`] instance of the eight-lane kernels, so
/// that the portable generic code (`filter::trilinear_weights`, the modes' sums and finishes,
/// the extinction step, the front-to-back step) runs in them unchanged, each lane doing the
/// `f32` operations of the scalar kernel in the same order (no fused multiply-add).
///
/// Private to `arch::avx2`: its values are made and used only by this module's kernels, all
/// of which run inside `#[target_feature(enable = "avx2,fma")]` functions entered through an
/// [`Avx2`] token, which exists only where the CPU has AVX2 and FMA. That is the proof of
/// every `unsafe` block of its operations (each an AVX intrinsic, which the operation, an
/// `#[inline(always)]` function, hands to that caller).
#[derive(Clone, Copy)]
pub(super) struct F32x8(pub(super) __m256);

/// One flag per lane of an [`F32x8`]: all ones or all zeros.
#[derive(Clone, Copy)]
pub(super) struct Mask8(pub(super) __m256);

impl F32x8 {
    /// The lanes as an array (a bit cast, no instruction set needed).
    #[inline(always)]
    pub(super) fn to_array(self) -> [f32; LANES] {
        // SAFETY: a bit cast between two 32-byte plain-data types, every bit pattern valid in
        // both.
        unsafe { core::mem::transmute::<__m256, [f32; LANES]>(self.0) }
    }

    /// Lanes from an array (a bit cast).
    #[inline(always)]
    pub(super) fn from_array(a: [f32; LANES]) -> Self {
        // SAFETY: as in `to_array`.
        Self(unsafe { core::mem::transmute::<[f32; LANES], __m256>(a) })
    }
}

impl core::ops::Add for F32x8 {
    type Output = Self;
    #[inline(always)]
    fn add(self, rhs: Self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_add_ps(self.0, rhs.0) })
    }
}

impl core::ops::Sub for F32x8 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_sub_ps(self.0, rhs.0) })
    }
}

impl core::ops::Mul for F32x8 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, rhs: Self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_mul_ps(self.0, rhs.0) })
    }
}

impl crate::num::Num for F32x8 {
    const ZERO: Self = Self(
        // SAFETY: as in `F32x8::to_array`.
        unsafe { core::mem::transmute::<[f32; LANES], __m256>([0.0; LANES]) },
    );
    const ONE: Self = Self(
        // SAFETY: as in `F32x8::to_array`.
        unsafe { core::mem::transmute::<[f32; LANES], __m256>([1.0; LANES]) },
    );
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_set1_ps(x) })
    }
}

impl crate::lanes::Lanes for F32x8 {
    type Mask = Mask8;

    #[inline(always)]
    fn clamp_to(self, hi: Self) -> Self {
        // `max` returns its second operand where either is NaN: NaN to 0, as the scalar
        // `x.max(0.0).min(hi)`.
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_min_ps(_mm256_max_ps(self.0, _mm256_setzero_ps()), hi.0) })
    }

    #[inline(always)]
    fn max0(self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_max_ps(self.0, _mm256_setzero_ps()) })
    }

    #[inline(always)]
    fn lt(self, other: Self) -> Mask8 {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Mask8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, other.0) })
    }

    #[inline(always)]
    fn div(self, other: Self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_div_ps(self.0, other.0) })
    }

    #[inline(always)]
    fn all(m: Mask8) -> bool {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        unsafe { _mm256_movemask_ps(m.0) == 0xff }
    }

    #[inline(always)]
    fn select(m: Mask8, a: Self, b: Self) -> Self {
        // SAFETY: the CPU has AVX2 (see `F32x8`).
        Self(unsafe { _mm256_blendv_ps(b.0, a.0, m.0) })
    }

    #[inline(always)]
    fn per_lane(x: [Self; 4], f: impl Fn([f32; 4]) -> [f32; 4]) -> [Self; 4] {
        let x = x.each(F32x8::to_array);
        let mut out = [[0.0f32; LANES]; 4];
        for l in 0..LANES {
            let lane = x.each(|v| v.get(l).copied().unwrap_or(0.0));
            for (o, y) in out.iter_mut().zip(f(lane)) {
                if let Some(slot) = o.get_mut(l) {
                    *slot = y;
                }
            }
        }
        out.each(F32x8::from_array)
    }
}

/// Four vectors `[c₀, c₁, c₂, a]` as the quantities of a sample in [`F32x8`] lanes.
#[inline(always)]
pub(super) fn interp([r, g, b, a]: [__m256; 4]) -> crate::sample::Interp<F32x8> {
    crate::sample::Interp {
        c: [F32x8(r), F32x8(g), F32x8(b)],
        a: F32x8(a),
    }
}

/// The inverse of [`interp`].
#[inline(always)]
pub(super) fn vectors(i: crate::sample::Interp<F32x8>) -> [__m256; 4] {
    let [r, g, b] = i.c;
    [r.0, g.0, b.0, i.a.0]
}
