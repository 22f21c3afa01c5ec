//! Lane conversions and the kernel's exact integer helpers: arrays to and from vectors,
//! `n/255` of bytes, `⌊n/65280⌋`, the round-half-up quantization.

use core::arch::x86_64::*;

use super::*;

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

/// `⌊n/65280⌋` (`65280 = 255·256 = fixed_point::ONE`) per lane for every `u32` `n`:
/// `⌊n·0x8080_8081/2^47⌋` (`0x8080_8081 = ⌈2^47/65280⌉`; the excess `n·0.498…/2^47` stays
/// below `1/65280` for `n < 2^32`), the 64-bit products of the even and the odd lanes by two
/// `vpmuludq`. A unit test checks every `n`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn div65280(n: __m256i) -> __m256i {
    let m = _mm256_set1_epi32(0x8080_8081_u32 as i32);
    let even = _mm256_srli_epi64::<47>(_mm256_mul_epu32(n, m));
    // The odd lanes' quotients land in the high half of each 64-bit lane.
    let odd = _mm256_srli_epi64::<15>(_mm256_mul_epu32(_mm256_srli_epi64::<32>(n), m));
    _mm256_blend_epi32::<0b1010_1010>(even, odd)
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
