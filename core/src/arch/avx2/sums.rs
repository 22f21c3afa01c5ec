//! Each mode's sums over the eight taps in lanes: the float ones `mode::weighted_sums` in
//! [`F32x8`] lanes, the exact integer ones of `OpacityWeighted` reordered for `vpmaddwd`.

use core::arch::x86_64::*;

use super::*;

/// [`int_pair`] of two words.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn int_pair_of([w0, w1]: [__m256i; 2]) -> [__m256; 4] {
    int_pair(w0, w1)
}

/// Two taps' little-endian RGBA words (`w0`, `w1`, neighbours along the first axis of
/// [`int_sums`]) packed for its `vpmaddwd`: four vectors whose 32-bit lanes hold the first
/// tap's value in the low 16 bits and the second's in the high 16 — `α·C − 2^15` for each
/// color (`α·C ≤ 255² < 2^16`, so the difference fits an `i16`: the top bit of the `u16`
/// flipped) and `α` itself, as bit patterns. 14 operations per pair, where the channels of
/// two taps took 12.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn int_pair(w0: __m256i, w1: __m256i) -> [__m256; 4] {
    // `[r₀ g₀ | r₁ g₁]` and `[b₀ α₀ | b₁ α₁]` per lane (bytes, low 16 bits first).
    let rg = _mm256_blend_epi16::<0b1010_1010>(w0, _mm256_slli_epi32::<16>(w1));
    let ba = _mm256_blend_epi16::<0b1010_1010>(_mm256_srli_epi32::<16>(w0), w1);
    let byte = _mm256_set1_epi16(0xff);
    let (r, g) = (_mm256_and_si256(rg, byte), _mm256_srli_epi16::<8>(rg));
    let (b, a) = (_mm256_and_si256(ba, byte), _mm256_srli_epi16::<8>(ba));
    let flip = _mm256_set1_epi16(i16::MIN);
    let weighted = |c: __m256i| _mm256_xor_si256(_mm256_mullo_epi16(c, a), flip);
    map4([weighted(r), weighted(g), weighted(b), a], |v| {
        _mm256_castsi256_ps(v)
    })
}

/// The integer `OpacityWeighted` trilinear sample at `F = 8` from the taps' pairs along a
/// first axis (`pair(j)`, [`int_pair`]: for the first axis x, taps `2j` and `2j + 1`; for
/// y, taps `b` and `b + 2`, `b` = 0, 1, 4, 5) and the fractions `f` (`0..=255`) of the first
/// axis, the second (x or y, the other one) and z: `[C̃_r, C̃_g, C̃_b, α]` in U8.8, bit for bit
/// `IntMode::combine` of `OpacityWeighted` (`ω_i = w_i·α_i`, `S_α = Σ ω_i`, `S_c = Σ ω_i·C_i`
/// with the exact weights `w_i = wx·wy·wz`, `s = 24`; `α = ⌊(S_α + 2^15)/2^16⌋`,
/// `C̃ = ⌊(S_c + 255·2^15)/(255·2^16)⌋`).
///
/// The sums are the same integers formed axis by axis (in any order of the axes, since every
/// step is exact), with `g = 256 − f` per axis, in wrapping `u32` lanes where each product and
/// each sum is a true value below `2^32` (so exact modulo `2^32`, hence exact): along the
/// first axis one `vpmaddwd` per channel and pair, `X = g·(α₀C₀ − 2^15) + f·(α₁C₁ − 2^15) =
/// g·α₀C₀ + f·α₁C₁ − 2^23` (as `g + f = 256`; `|X| < 2^24`) and `X_α = g·α₀ + f·α₁` (`g ≤ 256`,
/// `f ≤ 255` and the packed values fit its signed 16-bit operands); along the second,
/// `Y = g·X₀ + f·X₁`, which for a color is the true sum `≤ 2^16·255² < 2^32` minus `2^31`
/// modulo `2^32` (so the true sum is `Y` with its top bit flipped); along z, `S_α = gz·Y₀ +
/// fz·Y₁ ≤ 2^24·255`, while `S_c < 2^40` is formed in two halves: with each true `Y =
/// 2^16·Y_h + Y_l`, `S_c = 2^16·H + L` for `H = gz·Y_h₀ + fz·Y_h₁` and `L = gz·Y_l₀ + fz·Y_l₁`
/// (each below `2^24`), one `vpmaddwd` each: `Y_h − 2^15` is the high half of `Y` as it is
/// held (top bit flipped) read as an `i16`, and `Y_l − 2^15` its low half with the top bit
/// flipped, so the products sum to `H − 2^23` and `L − 2^23`. Then `q + 1 =
/// H + ⌊(L + 255·2^15)/2^16⌋ + 1 ≤ 2^24` and `C̃ = ⌊q/255⌋ =
/// ⌊(q + 1)·0x0101_0101/2^32⌋` (`0x0101_0101 = (2^32 − 1)/255`: with `q = 255k + r`,
/// `(q + 1)/255 − (q + 1)/(255·2^32)` lies in `(k, k + 1)`; [`RECIP255`]). The first axis by
/// `vpmaddwd` (one instruction per channel and pair, where three products and a sum were)
/// took a probe from 4.62–4.63 to 4.40 ns/sample, 0.96 of the `OpacityWeighted` packets.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn int_sums(pair: impl Fn(usize) -> [__m256; 4], f: [__m256i; 3]) -> [__m256; 4] {
    let [fp, fq, fz] = f;
    let (add, sub, mul) = (_mm256_add_epi32, _mm256_sub_epi32, _mm256_mullo_epi32);
    let k256 = _mm256_set1_epi32(256);
    let (gp, gq, gz) = (sub(k256, fp), sub(k256, fq), sub(k256, fz));
    // `g` in the low 16 bits, `f` in the high 16, for `vpmaddwd`.
    let wp = _mm256_or_si256(gp, _mm256_slli_epi32::<16>(fp));
    let (fq, fz) = ((gq, fq), (gz, fz));
    let lerp = |a: __m256i, b: __m256i, (g, f): (__m256i, __m256i)| add(mul(a, g), mul(b, f));
    let along_p = |j: usize| map4(pair(j), |v| _mm256_madd_epi16(_mm256_castps_si256(v), wp));
    let along_q = |[r0, g0, b0, a0]: [__m256i; 4], [r1, g1, b1, a1]: [__m256i; 4]| {
        [
            lerp(r0, r1, fq),
            lerp(g0, g1, fq),
            lerp(b0, b1, fq),
            lerp(a0, a1, fq),
        ]
    };
    let [r0, g0, b0, a0] = along_q(along_p(0), along_p(1));
    let [r1, g1, b1, a1] = along_q(along_p(2), along_p(3));
    let alpha = _mm256_srli_epi32::<16>(add(lerp(a0, a1, fz), _mm256_set1_epi32(1 << 15)));
    let (gz, fz) = fz;
    let wz = _mm256_or_si256(gz, _mm256_slli_epi32::<16>(fz));
    let flip = _mm256_set1_epi16(i16::MIN);
    let (k_lo, k_hi) = (
        _mm256_set1_epi32((1 << 23) + (255 << 15)),
        _mm256_set1_epi32((1 << 23) + 1),
    );
    let m = _mm256_set1_epi32(RECIP255 as i32);
    let color = |y0: __m256i, y1: __m256i| {
        // The high halves of the true sums less `2^15` (the flipped top bit), and the low
        // halves so, paired for `vpmaddwd`: `H − 2^23` and `L − 2^23` (see above).
        let hi = _mm256_blend_epi16::<0b1010_1010>(_mm256_srli_epi32::<16>(y0), y1);
        let lo = _mm256_blend_epi16::<0b1010_1010>(y0, _mm256_slli_epi32::<16>(y1));
        let (h, l) = (
            _mm256_madd_epi16(hi, wz),
            _mm256_madd_epi16(_mm256_xor_si256(lo, flip), wz),
        );
        let q1 = add(add(h, _mm256_srli_epi32::<16>(add(l, k_lo))), k_hi);
        let e = _mm256_srli_epi64::<32>(_mm256_mul_epu32(q1, m));
        let o = _mm256_mul_epu32(_mm256_srli_epi64::<32>(q1), m);
        _mm256_castsi256_ps(_mm256_blend_epi32::<0b1010_1010>(e, o))
    };
    [
        color(r0, r1),
        color(g0, g1),
        color(b0, b1),
        _mm256_castsi256_ps(alpha),
    ]
}

/// The mode's sums over the taps from the last down: `mode::weighted_sums` in [`F32x8`]
/// lanes, weighted by `W` (`ω = w·α` for `OpacityWeighted`, [`ByOpacity`]; `w` for `Separate`
/// and the extinction modes, [`Linear`]), of the channels `tap(k)` of each tap `k`:
/// `[Σ r, Σ g, Σ b, Σ α]`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn mode_sums<W: Weighting>(
    tap: impl Fn(usize) -> [__m256; 4],
    w: &[F32x8; 8],
) -> [__m256; 4] {
    let channels = |&k: &usize| {
        let [r, g, b, a] = tap(k);
        ([F32x8(r), F32x8(g), F32x8(b)], F32x8(a))
    };
    const TAPS: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    vectors(weighted_sums::<F32x8, W, _, 8>(w, &TAPS, channels))
}
