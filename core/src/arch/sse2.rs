//! The integer `OpacityWeighted` trilinear kernel in SSE2 (every x86-64 build): the same
//! exact sums as the portable [`combine`](crate::fixed_point::IntMode::combine), in another order, so the
//! same U8.8 sample bit for bit.
//!
//! The portable kernel forms `S_α = Σ w_i·α_i` and `S_c = Σ w_i·α_i·C_i` with the 64-bit
//! trilinear weights `w_i = wx·wy·wz` (44 multiplications per sample, one at a time on the
//! scalar multiplier). Here the weights are applied axis by axis, all four channels
//! `(α·C_r, α·C_g, α·C_b, α)` of a tap in the lanes of one vector:
//!
//! 1. `P = α·(C_r, C_g, C_b, 1)` per tap, in 16-bit lanes (`≤ 255² < 2^16`, exact);
//! 2. along x, per pair of taps: `X = (2^F − f_x)·P₀ + f_x·P₁ ≤ 2^F·255² < 2^28` with one
//!    `pmaddwd`, whose operands are signed 16-bit: it reads `P − 2^15` (which fits) and the
//!    weights (`≤ 2^F ≤ 2^12`, which fit), and `2^15·Σ wx = 2^(15+F)` is added back (the
//!    signed sums stay within `±2^27`);
//! 3. along y and z at once: `S = Σ_j wyz_j·X_j` with `wyz_j ≤ 2^(2F) ≤ 2^24`, in 64-bit lanes
//!    (`pmuludq` of two 32-bit operands; `S ≤ 2^(3F)·255² < 2^52`);
//! 4. the rounding of [`levels_to_u88`](crate::fixed_point::levels_to_u88) and
//!    [`products_to_u88`](crate::fixed_point::products_to_u88) (**round half up**):
//!    `α = ⌊(256·S_α + 2^(s−1))/2^s⌋`, `C̃ = ⌊(512·S_c + 255·2^s)/(510·2^s)⌋` with `s = 3F`
//!    (numerators below `2^62`), the latter as `⌊q/255⌋` of
//!    `q = ⌊(512·S_c + 255·2^s)/2^(s+1)⌋ < 2^25` (the floor of a floor of a quotient is the
//!    floor of the whole quotient), and `⌊q/255⌋ = (q·0x8080_8081) >> 39` (`0x8080_8081 =
//!    (2^39 + 127)/255`; a unit test checks every `q < 2^25` and a sample up to `2^32`).
//!
//! Every intermediate is an exact integer within its lane, so the result is `combine`'s, for
//! every `F` in `4..=12`.
//! One `unsafe` call enters the kernel, a `#[target_feature(enable = "sse2")]` function (SSE2
//! is part of x86-64), inside which the value intrinsics are safe functions.

use core::arch::x86_64::*;

use crate::each::Each;
use crate::voxel::StraightU8;

/// `(q·DIV255_MAGIC) >> DIV255_SHIFT = ⌊q/255⌋` for every `q < 2^32`.
pub(crate) const DIV255_MAGIC: u64 = 0x8080_8081;
/// See [`DIV255_MAGIC`].
pub(crate) const DIV255_SHIFT: u32 = 39;

/// `combine` of the 8 taps of a trilinear cell with the weights of `frac`: the sample's
/// `[C̃_r, C̃_g, C̃_b, α]` in U8.8, with `C̃ ≤ α ≤ ONE` (`IntSample::from_valid` takes them as
/// they are; returned as numbers so that this module does not depend on `fixed_point`).
#[inline(always)]
pub(crate) fn opacity_weighted_trilinear<const F: u32>(
    taps: &[StraightU8; 8],
    frac: [u32; 3],
) -> [u16; 4] {
    // SAFETY: the kernel needs SSE2 only, which every x86-64 CPU has (it is part of the
    // architecture's baseline, and this module is compiled for x86-64 only).
    unsafe { kernel::<F>(taps, frac) }
}

/// The kernel, compiled with SSE2 enabled (where its value intrinsics are safe functions).
#[inline]
#[target_feature(enable = "sse2")]
fn kernel<const F: u32>(taps: &[StraightU8; 8], frac: [u32; 3]) -> [u16; 4] {
    let one = 1i32 << F;
    let [fx, fy, fz] = frac.each(|f| (f as i32) & (one - 1));
    let word = |v: StraightU8| i32::from_le_bytes(v.0);
    let [t0, t1, t2, t3, t4, t5, t6, t7] = *taps;
    let lo = _mm_setr_epi32(word(t0), word(t1), word(t2), word(t3));
    let hi = _mm_setr_epi32(word(t4), word(t5), word(t6), word(t7));
    let zero = _mm_setzero_si128();
    // The pair weights (2^F − fx, fx) as i16, repeated; each ≤ 2^F ≤ 2^12.
    let wx = _mm_set1_epi32((fx << 16) | (one - fx));
    let x = [
        along_x::<F>(_mm_unpacklo_epi8(lo, zero), wx),
        along_x::<F>(_mm_unpackhi_epi8(lo, zero), wx),
        along_x::<F>(_mm_unpacklo_epi8(hi, zero), wx),
        along_x::<F>(_mm_unpackhi_epi8(hi, zero), wx),
    ];
    let (y0, z0) = (one - fy, one - fz);
    let wyz = [y0 * z0, fy * z0, y0 * fz, fy * fz];
    // Lanes 0 and 2 of each X (C_r, C_b) and lanes 1 and 3 (C_g, α), times wyz_j, summed.
    let mut even = zero;
    let mut odd = zero;
    for (xj, w) in x.iter().zip(wyz) {
        let w = _mm_set1_epi32(w);
        even = _mm_add_epi64(even, _mm_mul_epu32(*xj, w));
        odd = _mm_add_epi64(odd, _mm_mul_epu32(_mm_srli_epi64::<32>(*xj), w));
    }
    let s = 3 * F;
    let shift = |n: u32| _mm_cvtsi32_si128(n as i32);
    // C̃ = ⌊q/255⌋, q = (512·S + 255·2^s) >> (s + 1), for both vectors.
    let products = |v: __m128i| {
        let n = _mm_add_epi64(_mm_slli_epi64::<9>(v), _mm_set1_epi64x((255i64) << s));
        let q = _mm_srl_epi64(n, shift(s + 1));
        let m = _mm_set1_epi64x(DIV255_MAGIC as i64);
        _mm_srl_epi64(_mm_mul_epu32(q, m), shift(DIV255_SHIFT))
    };
    let c_even = products(even);
    let c_odd = products(odd);
    // α = (256·S_α + 2^(s−1)) >> s.
    let alpha = _mm_srl_epi64(
        _mm_add_epi64(_mm_slli_epi64::<8>(odd), _mm_set1_epi64x(1i64 << (s - 1))),
        shift(s),
    );
    // Each result is at most ONE < 2^16: the low 16 bits of its 64-bit lane.
    let first = |v: __m128i| _mm_extract_epi16::<0>(v) as u16;
    let second = |v: __m128i| _mm_extract_epi16::<4>(v) as u16;
    [first(c_even), first(c_odd), second(c_even), second(alpha)]
}

/// Step 2 for one pair of taps, `p` = the pair's bytes widened to 16-bit lanes
/// `(r₀, g₀, b₀, α₀, r₁, g₁, b₁, α₁)`: `X = (X_r, X_g, X_b, X_α)` in 32-bit lanes.
#[inline]
#[target_feature(enable = "sse2")]
fn along_x<const F: u32>(p: __m128i, wx: __m128i) -> __m128i {
    // (r₀, r₁, g₀, g₁, b₀, b₁, α₀, α₁): each channel's two taps side by side.
    let pair = _mm_unpacklo_epi16(p, _mm_shuffle_epi32::<0xEE>(p));
    // (α₀, α₁) in every 32-bit lane; the channels with 1 in place of α.
    let alpha = _mm_shuffle_epi32::<0xFF>(pair);
    let ones = _mm_setr_epi32(0, 0, 0, 0x0001_0001);
    let rgb = _mm_setr_epi32(-1, -1, -1, 0);
    let c = _mm_or_si128(_mm_and_si128(pair, rgb), ones);
    // P = α·C ≤ 255² (exact in 16 bits), read as i16 P − 2^15.
    let p = _mm_xor_si128(_mm_mullo_epi16(alpha, c), _mm_set1_epi16(i16::MIN));
    // Σ wx·(P − 2^15) + 2^15·2^F.
    _mm_add_epi32(_mm_madd_epi16(p, wx), _mm_set1_epi32(1 << (15 + F)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg_attr(
        miri,
        ignore = "exhaustive (2^25 quotients): too slow for Miri; runs natively and under ASan"
    )]
    fn div255_magic_is_exact_for_every_quotient_the_kernel_forms() {
        // q = (512·S + 255·2^24) >> 25 < 2^25 for S < 2^40 (F = 8; smaller F, smaller q).
        // The constants pass through `black_box`, so the compiler cannot turn `q / 255` into
        // the same multiplication and fold the comparison away; the check is the definition
        // of the floor: `0 ≤ q − 255·d < 255`.
        let (magic, shift) = core::hint::black_box((DIV255_MAGIC, DIV255_SHIFT));
        for q in 0u64..1 << 25 {
            let d = (q * magic) >> shift;
            let r = q.wrapping_sub(255 * d);
            assert!(r < 255, "q = {q}: {d}");
        }
        // Beyond the kernel's range it holds up to 2^32 too (sampled).
        for q in (1u64 << 25..1 << 32).step_by(65_521) {
            let d = (q * magic) >> shift;
            assert!(q.wrapping_sub(255 * d) < 255, "q = {q}: {d}");
        }
    }
}
