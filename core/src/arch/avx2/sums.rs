//! Each mode's sums over the eight taps in lanes (float and exact integer), and the
//! extinction step.

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
/// fz·Y₁ ≤ 2^24·255`, while `S_c < 2^40` is formed in 64-bit lanes (`vpmuludq` of the even and
/// the odd lanes): `q + 1 = ⌊(S_c + 255·2^15 + 2^16)/2^16⌋ ≤ 2^24` and `C̃ = ⌊q/255⌋ =
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
    let (gz_odd, fz_odd) = (_mm256_srli_epi64::<32>(gz), _mm256_srli_epi64::<32>(fz));
    let (mul64, add64) = (_mm256_mul_epu32, _mm256_add_epi64);
    let bias = _mm256_set1_epi64x((255 << 15) + (1 << 16));
    let m = _mm256_set1_epi32(RECIP255 as i32);
    let top = _mm256_set1_epi32(i32::MIN);
    let color = |y0: __m256i, y1: __m256i| {
        // The true sums along the second axis (see above).
        let (y0, y1) = (_mm256_xor_si256(y0, top), _mm256_xor_si256(y1, top));
        let odd = _mm256_srli_epi64::<32>;
        let even_z = add64(add64(mul64(y0, gz), mul64(y1, fz)), bias);
        let odd_z = add64(add64(mul64(odd(y0), gz_odd), mul64(odd(y1), fz_odd)), bias);
        let e = _mm256_srli_epi64::<32>(mul64(_mm256_srli_epi64::<16>(even_z), m));
        let o = mul64(_mm256_srli_epi64::<16>(odd_z), m);
        _mm256_castsi256_ps(_mm256_blend_epi32::<0b1010_1010>(e, o))
    };
    [
        color(r0, r1),
        color(g0, g1),
        color(b0, b1),
        _mm256_castsi256_ps(alpha),
    ]
}

/// The mode's sums over the taps from the last down (`mode::dot`): `OpacityWeighted` weights
/// the colors and sums by `ω = w·α` (then `α = Σ ω`); `Separate` sums `w·C` and `w·α`, and
/// `ExtinctionWeightedU8` `w·C^τ` and `w·τ` the same way (`mode::dot_lanes8`).
/// `[Σ r, Σ g, Σ b, Σ α]`, of the channels `pair(p)` of taps `2p` and `2p + 1`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn mode_sums<const MODE: u8>(
    pair: impl Fn(usize) -> [[__m256; 4]; 2],
    w: &[__m256; 8],
) -> [__m256; 4] {
    let (add, mul) = (_mm256_add_ps, _mm256_mul_ps);
    let mut s = [_mm256_setzero_ps(); 4];
    let [w0, w1, w2, w3, w4, w5, w6, w7] = *w;
    for (p, [wl, wh]) in [[w0, w1], [w2, w3], [w4, w5], [w6, w7]]
        .into_iter()
        .enumerate()
        .rev()
    {
        let [lo, hi] = pair(p);
        for (first, wk, [r, gr, b, a]) in [(p == 3, wh, hi), (false, wl, lo)] {
            let (wc, wa) = if MODE != OPACITY_WEIGHTED {
                (wk, mul(wk, a))
            } else {
                let om = mul(wk, a);
                (om, om)
            };
            s = if first {
                [mul(wc, r), mul(wc, gr), mul(wc, b), wa]
            } else {
                [
                    add(s[0], mul(wc, r)),
                    add(s[1], mul(wc, gr)),
                    add(s[2], mul(wc, b)),
                    add(s[3], wa),
                ]
            };
        }
    }
    s
}

/// `integrate_step(C^τ, τ, d)` per lane before its clamps (which the caller applies; they
/// leave an already clamped sample as it is): `(C̃, α)` from the sums `[C^τ…, τ]`. Where every
/// lane's `x = max(τ, 0)·d` lies below 1 ([`PHI_POLY_BELOW`]), in lanes: `φ` by
/// `opacity::phi_poly`'s operations (its Estrin form, with no fused multiply-add), `α = x·φ`
/// and `C̃ = C^τ·(d·φ)` as `integrate_step`; otherwise `integrate_step` per lane
/// ([`extinction_step_per_lane`], out of line: with it inside, this function was not inlined
/// into the kernel, and inlining it took the packets from 7.1 to 6.4 ns/sample in a probe).
/// Its chain of dependent operations is short (the polynomial is five deep): with
/// `libm::expm1f`'s rational form and `φ = α/x` (seventeen deep, two divisions among them) the
/// packets took 6.2–6.3 ns/sample in a probe, with Horner's form of the polynomial (twelve
/// deep) 5.75, with Estrin's 5.4–5.5.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn extinction_step(s: [__m256; 4], d: f32) -> ([__m256; 3], __m256) {
    let (add, mul) = (_mm256_add_ps, _mm256_mul_ps);
    let [c0, c1, c2, tau] = s;
    let k = _mm256_set1_ps;
    // `tau.max(0.0)` (NaN to 0), `x = τ·d`; `x < 1` fails for NaN too.
    let x = mul(_mm256_max_ps(tau, _mm256_setzero_ps()), k(d));
    let below = _mm256_cmp_ps::<_CMP_LT_OQ>(x, k(PHI_POLY_BELOW));
    if _mm256_movemask_ps(below) != 0xff {
        return extinction_step_per_lane(s, d);
    }
    let [b0, b1, b2, b3, b4, b5, b6] = PHI_POLY;
    let c = |b: u32| k(f32::from_bits(b));
    let (p0, p1, p2, p3, p4, p5, p6) = (c(b0), c(b1), c(b2), c(b3), c(b4), c(b5), c(b6));
    let x2 = mul(x, x);
    let x4 = mul(x2, x2);
    let low = add(add(p0, mul(p1, x)), mul(add(p2, mul(p3, x)), x2));
    let high = add(add(p4, mul(p5, x)), mul(p6, x2));
    let phi = add(low, mul(high, x4));
    let g = mul(k(d), phi);
    ([mul(c0, g), mul(c1, g), mul(c2, g)], mul(x, phi))
}

/// `integrate_step` per lane: [`extinction_step`] where a lane's `τd` is not below 1 (kept
/// out of line, so that the lanes' path inlines into the kernel).
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
pub(super) fn extinction_step_per_lane(s: [__m256; 4], d: f32) -> ([__m256; 3], __m256) {
    let [c0, c1, c2, tau] = s;
    let [c0, c1, c2, tau] = [c0, c1, c2, tau].map(|v| array(v));
    let mut out = [[0.0f32; LANES]; 4];
    let [o0, o1, o2, oa] = &mut out;
    let lanes_in = c0.into_iter().zip(c1).zip(c2).zip(tau);
    let lanes_out = o0
        .iter_mut()
        .zip(o1.iter_mut())
        .zip(o2.iter_mut())
        .zip(oa.iter_mut());
    for ((((r, g), b), t), (((or, og), ob), oa)) in lanes_in.zip(lanes_out) {
        let sample = integrate_step([r, g, b], t, d);
        [*or, *og, *ob] = sample.c;
        *oa = sample.a;
    }
    let [r, g, b, a] = out.map(|l| lanes(l));
    ([r, g, b], a)
}
