//! What the kernel computes at each step, by type: [`Kind`], implemented by every float mode
//! with a lane kernel (`mode::LaneMode`: `OpacityWeighted`, `Separate`, `ExtinctionWeightedU8`
//! over RGBA8 words, `ExtinctionWeighted` over 16-byte `ExtinctionF32` voxels; their taps read
//! as their [`ReadTaps`] says) and by the integer
//! `OpacityWeighted` pipeline at `F = 8` ([`IntOw`]). The eight-lane kernel ([`march8_avx2`]) is
//! written once over it, as the AVX2 instance of the one march loop (`crate::march`).
//!
//! Every method is an `unsafe fn` compiled for AVX2 and FMA, inlined into the kernel, which is
//! compiled so too: its one requirement is a CPU with AVX2 and FMA, which the kernel's callers
//! prove with an [`Avx2`] token. Most carry `#[target_feature]` and an `#[inline]` hint; the
//! reads of a face of both kinds and the tap sums of both are `#[inline(always)]` instead
//! (which `#[target_feature]` does not allow), compiled in the kernel's instruction set once
//! inlined: with the hint alone LLVM kept them as calls in the step loop, whose arguments and
//! results then went through memory (the performance log, 2026-12-06 and 2026-12-07, has the
//! effect). Of the float kinds' tap sums only the pair reads are inlined; the reads of each
//! tap's voxels alone (16-byte voxels, taps not side by side) stay one call per step
//! (`tap_sums_apart`): inlined too, they made the packets of rays in every direction slower.

use core::arch::x86_64::*;

use super::reads::all_taps;
use super::*;
use crate::mode::LaneMode;
use crate::opacity::Correction;

/// The per-step operations of one kind of kernel (see the module doc). # Safety of every
/// method: the CPU must have AVX2 and FMA.
pub(crate) trait Kind {
    /// How many steps the compositing lags behind the sums (the pipelining of
    /// march, `crate::march`: 1 for the extinction modes, 0 for the others).
    const LAG: u32;

    /// A lane's result: a float [`Sample`] or an [`IntSample`].
    type Out: Copy;

    /// The opacity correction the kernel applies to each finished sample: for the float
    /// kinds an `Option<Corrected>` (`None` when `d = d′` or the mode is extinction-based),
    /// for [`IntOw`] `()` (its callers take the kernel only without correction).
    type Corr: Copy;

    /// The result of a lane from its accumulated `[r, g, b, α]` (bit patterns).
    fn out(bits: [i32; 4]) -> Self::Out;

    /// Along one axis, the fraction and the two tap coordinates of the positions `p`, for an
    /// axis of `n` voxels (`n` as `f32`, `last = n − 1`).
    unsafe fn split(p: __m256, last: __m256i, n: __m256) -> (__m256, __m256i, __m256i);

    /// Reads and converts the taps `ks` (a face of a [`Cell`]) into `out`.
    unsafe fn read_face<V: Voxel, const A: usize>(
        out: &mut [[__m256; 4]; 4],
        taps: &Taps<'_, V>,
        ks: [usize; 4],
        taus: Taus<'_>,
    );

    /// The sums of the taps a [`Cell`] holds, at the fractions `f` (`[fx, fy, fz]`, from
    /// [`split`](Self::split)).
    unsafe fn cell_sums<const A: usize>(cell: &Cell<A>, f: [__m256; 3]) -> [__m256; 4];

    /// The sums of the taps read now.
    unsafe fn tap_sums<V: Voxel>(taps: &Taps<'_, V>, f: [__m256; 3], taus: Taus<'_>)
        -> [__m256; 4];

    /// The sample of the sums `s` for a step of length `d`, corrected by `corr`.
    unsafe fn finish(s: [__m256; 4], d: f32, corr: Self::Corr) -> [__m256; 4];

    /// The front-to-back step of sample `s` onto `acc`, kept in the `live` lanes only.
    unsafe fn over(acc: [__m256; 4], s: [__m256; 4], live: __m256) -> [__m256; 4];

    /// The lanes whose `acc` has reached `A ≥ a_stop` (`Termination::done`).
    unsafe fn done(acc: &[__m256; 4], a_stop: f32) -> __m256;

    /// With `ONE` ([`march_one`]): the eight samples `s` of a step (sample `k0 + l` in lane
    /// `l`) composited in order onto the one ray's `acc` (`[r, g, b, α]` as bit patterns) as
    /// the one-ray march does; `Some` of the number of samples composited once it stops at
    /// `a_stop`, or once the samples marched end at `end` ([`ran_out`](Self::ran_out) of
    /// the ray's `total`).
    unsafe fn serial(
        acc: &mut [i32; 4],
        s: [__m256; 4],
        k0: u32,
        ends: (u32, u32),
        a_stop: f32,
    ) -> Option<u32>;

    /// The count the one-ray march reports where the samples marched end at `end` of the
    /// ray's `total` (the samples after `end` transparent) with `acc` composited: `total`,
    /// unless the march stops before a sample (as the integer one does) and `acc` has
    /// reached `a_stop` with samples left, which the march would have stopped at.
    fn ran_out(acc: &[i32; 4], (end, total): (u32, u32), a_stop: f32) -> u32 {
        let _ = (acc, end, a_stop);
        total
    }
}

impl<M: LaneMode> Kind for M {
    const LAG: u32 = M::LAG;
    type Out = Sample;
    type Corr = M::Correction;

    #[inline(always)]
    fn out([r, g, b, a]: [i32; 4]) -> Sample {
        let f = |x: i32| f32::from_bits(x as u32);
        Sample {
            c: [f(r), f(g), f(b)],
            a: f(a),
        }
    }

    /// `p − ⌊p⌋`, and `⌊p⌋`, `⌊p⌋ + 1` clamped into `[0, n − 1]` (`⌊p⌋` is limited to
    /// `[−1, n]` before the conversion, which the clamp maps to the edges, so no coordinate
    /// overflows an `i32` lane).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn split(p: __m256, last: __m256i, n: __m256) -> (__m256, __m256i, __m256i) {
        let fl = _mm256_floor_ps(p);
        let i = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(fl, _mm256_set1_ps(-1.0)), n));
        let c = |i| _mm256_min_epi32(_mm256_max_epi32(i, _mm256_setzero_si256()), last);
        (
            _mm256_sub_ps(p, fl),
            c(i),
            c(_mm256_add_epi32(i, _mm256_set1_epi32(1))),
        )
    }

    /// Across y or z, a face's taps are two x pairs (`face`), read as such where the taps
    /// allow; across x, none. The branch on `inside` is taken once per face, outside the
    /// taps' loop.
    #[inline(always)]
    unsafe fn read_face<V: Voxel, const A: usize>(
        out: &mut [[__m256; 4]; 4],
        taps: &Taps<'_, V>,
        ks: [usize; 4],
        taus: Taus<'_>,
    ) {
        let [k0, _, k2, _] = ks;
        if A != 0 && taps.pairs() {
            // SAFETY: the caller's contract (AVX2 and FMA), on which this function runs; so
            // below.
            let [t0, t1] = unsafe { <M::Taps as ReadTaps>::read_pair(taps, k0, taus) };
            // SAFETY: as above.
            let [t2, t3] = unsafe { <M::Taps as ReadTaps>::read_pair(taps, k2, taus) };
            *out = map4(
                [t0, t1, t2, t3],
                #[inline(always)]
                |t| {
                    // SAFETY: as above.
                    unsafe { <M::Taps as ReadTaps>::channels_of(t, taus) }
                },
            );
        } else if taps.inside() {
            for (c, k) in out.iter_mut().zip(ks) {
                // SAFETY: as above, and `taps.inside()` for `INSIDE`.
                *c = unsafe { <M::Taps as ReadTaps>::tap::<V, true>(taps, k, taus) };
            }
        } else {
            for (c, k) in out.iter_mut().zip(ks) {
                // SAFETY: as above.
                *c = unsafe { <M::Taps as ReadTaps>::tap::<V, false>(taps, k, taus) };
            }
        }
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn cell_sums<const A: usize>(cell: &Cell<A>, f: [__m256; 3]) -> [__m256; 4] {
        mode_sums::<M::W>(|k| cell.tap(k), &weights(f))
    }

    #[inline(always)]
    unsafe fn tap_sums<V: Voxel>(
        taps: &Taps<'_, V>,
        f: [__m256; 3],
        taus: Taus<'_>,
    ) -> [__m256; 4] {
        if taps.pairs() {
            let w = weights(f);
            // The four pairs' words first (eight registers; and their `τ`, [`TauOfAlpha8`]),
            // then each tap's channels when the sums come to it.
            // SAFETY: the caller's contract (AVX2 and FMA): this function is inlined into the
            // kernel, compiled for them; so below.
            // (The closures `#[inline(always)]`: with `TauOfAlpha8`'s reads LLVM kept them
            // calls.)
            let [[w0, w1], [w2, w3], [w4, w5], [w6, w7]] = map4(
                [0, 2, 4, 6],
                #[inline(always)]
                |k| unsafe { <M::Taps as ReadTaps>::read_pair(taps, k, taus) },
            );
            let raws = [w0, w1, w2, w3, w4, w5, w6, w7];
            mode_sums::<M::W>(
                #[inline(always)]
                |k| {
                    let raw = raws.get(k).copied().unwrap_or(w0);
                    // SAFETY: as above.
                    unsafe { <M::Taps as ReadTaps>::channels_of(raw, taus) }
                },
                &w,
            )
        } else {
            // SAFETY: as above.
            unsafe { tap_sums_apart::<M, V>(taps, f, taus) }
        }
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn finish(s: [__m256; 4], d: f32, corr: M::Correction) -> [__m256; 4] {
        vectors(corr.apply_in(M::finish_lanes(interp(s), d)))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn over(acc: [__m256; 4], s: [__m256; 4], live: __m256) -> [__m256; 4] {
        vectors(front_to_back_in(interp(acc), interp(s), Mask8(live)))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn done(acc: &[__m256; 4], a_stop: f32) -> __m256 {
        _mm256_cmp_ps::<_CMP_GE_OQ>(acc[3], _mm256_set1_ps(a_stop))
    }

    /// `composite::front_to_back`, stopping once `A ≥ a_stop` after a sample.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn serial(
        acc: &mut [i32; 4],
        [r, g, b, a]: [__m256; 4],
        k0: u32,
        (end, total): (u32, u32),
        a_stop: f32,
    ) -> Option<u32> {
        let f = |x: i32| f32::from_bits(x as u32);
        let bits = |x: f32| x.to_bits() as i32;
        let [ar, ag, ab, aa] = *acc;
        let mut s = Sample {
            c: [f(ar), f(ag), f(ab)],
            a: f(aa),
        };
        let [r, g, b, a] = map4([r, g, b, a], |v| array(v));
        let lanes = r.into_iter().zip(g).zip(b).zip(a);
        let mut stop = None;
        for (k, (((r, g), b), a)) in (k0..).zip(lanes) {
            if k >= end {
                stop = Some(total);
                break;
            }
            s = front_to_back(s, Sample { c: [r, g, b], a });
            if s.a >= a_stop {
                stop = Some(k + 1);
                break;
            }
        }
        *acc = [bits(s.c[0]), bits(s.c[1]), bits(s.c[2]), bits(s.a)];
        stop
    }
}

/// `filter::trilinear_weights` in [`F32x8`] lanes.
#[inline(always)]
fn weights([fx, fy, fz]: [__m256; 3]) -> [F32x8; 8] {
    trilinear_weights([F32x8(fx), F32x8(fy), F32x8(fz)])
}

/// The integer `OpacityWeighted` trilinear pipeline at `F = 8` (see [`march8`]): its
/// channels, sums and compositing in `i32` lanes (carried in the kernel's `__m256` values as
/// bit patterns).
pub(crate) struct IntOw;

impl Kind for IntOw {
    const LAG: u32 = 0;
    type Out = IntSample;
    type Corr = ();

    /// The accumulator's lanes hold `[r | g << 16, b | A << 16, 0, 0]` ([`packed`]), each
    /// with `C ≤ A ≤ ONE`: `front_to_back`'s invariants, whose integer arithmetic the kernel
    /// performs.
    #[inline(always)]
    fn out(bits: [i32; 4]) -> IntSample {
        let [r, g, b, a] = unpacked(bits);
        IntSample::from_valid([r, g, b], a)
    }

    /// `IntRayMarcher::quantize`: `p` clamped into `[0, n − 1]` (NaN to 0: `max` returns its
    /// second operand then), `raw = ⌊256·p + ½⌋` (`quantize8`), then the index `raw >> 8` and
    /// the fraction `raw & 255` (an `i32` bit pattern); the index is at most `n − 1`, the
    /// second tap clamped to it.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn split(p: __m256, last: __m256i, n: __m256) -> (__m256, __m256i, __m256i) {
        let p = _mm256_min_ps(
            _mm256_max_ps(p, _mm256_setzero_ps()),
            _mm256_sub_ps(n, _mm256_set1_ps(1.0)),
        );
        let raw = quantize8(p);
        let i = _mm256_srli_epi32::<8>(raw);
        let f = _mm256_and_si256(raw, _mm256_set1_epi32(0xff));
        (
            _mm256_castsi256_ps(f),
            i,
            _mm256_min_epi32(_mm256_add_epi32(i, _mm256_set1_epi32(1)), last),
        )
    }

    /// The face's words, then its two pairs (places 0 and 1, 2 and 3: neighbours along x, or
    /// along y for a face across x) packed for [`int_sums`], held at places 0 and 2, and again
    /// at 1 and 3 ([`int_pair`]).
    #[inline(always)]
    unsafe fn read_face<V: Voxel, const A: usize>(
        out: &mut [[__m256; 4]; 4],
        taps: &Taps<'_, V>,
        ks: [usize; 4],
        _taus: Taus<'_>,
    ) {
        let [k0, _, k2, _] = ks;
        let [w0, w1, w2, w3] = if A != 0 && taps.pairs() {
            let [w0, w1] = taps.load_pair(k0);
            let [w2, w3] = taps.load_pair(k2);
            [w0, w1, w2, w3]
        } else if taps.inside() {
            map4(ks, |k| taps.load::<true>(k))
        } else {
            map4(ks, |k| taps.load::<false>(k))
        };
        let [p0, p1] = [int_pair(w0, w1), int_pair(w2, w3)];
        *out = [p0, p0, p1, p1];
    }

    /// The packed pairs along x, or along y for faces across x ([`read_face`](Self::read_face)),
    /// held at the place of their first tap; the fractions in that order.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn cell_sums<const A: usize>(cell: &Cell<A>, [fx, fy, fz]: [__m256; 3]) -> [__m256; 4] {
        let ([b0, b1, b2, b3], f) = if A == 0 {
            ([0, 1, 4, 5], [fy, fx, fz])
        } else {
            ([0, 2, 4, 6], [fx, fy, fz])
        };
        let first = |j: usize| match j {
            0 => b0,
            1 => b1,
            2 => b2,
            _ => b3,
        };
        int_sums(|j| cell.tap(first(j)), map3(f, |v| _mm256_castps_si256(v)))
    }

    /// Pairs along x: taps `2j` and `2j + 1`.
    #[inline(always)]
    unsafe fn tap_sums<V: Voxel>(
        taps: &Taps<'_, V>,
        f: [__m256; 3],
        _taus: Taus<'_>,
    ) -> [__m256; 4] {
        let f = map3(f, |v| _mm256_castps_si256(v));
        if taps.pairs() {
            int_sums(|j| int_pair_of(taps.load_pair(2 * j)), f)
        } else if taps.inside() {
            let load = |k| taps.load::<true>(k);
            int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
        } else {
            let load = |k| taps.load::<false>(k);
            int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
        }
    }

    /// (The sums are the sample itself.)
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn finish(s: [__m256; 4], _d: f32, _corr: ()) -> [__m256; 4] {
        s
    }

    /// `fixed_point::front_to_back` onto the accumulator of two channels a lane in 16-bit
    /// halves (`[r | g << 16, b | A << 16]`, the last two vectors zero): `T = ONE − A` in both
    /// halves, and each channel plus `⌊(T·x + ONE/2)/ONE⌋` ([`over_u16`]) of the sample `s`
    /// (`[r, g, b, α]` lanes, packed so). A lane that is not live takes `T = 0`, whose
    /// increments are `⌊(ONE/2)/ONE⌋ = 0`. Per step 23 operations, where the four channels in
    /// `u32` lanes took 38.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn over(acc: [__m256; 4], s: [__m256; 4], live: __m256) -> [__m256; 4] {
        let int = |v: __m256| _mm256_castps_si256(v);
        let [rg, ba, ..] = map4(acc, int);
        let [r, g, b, a] = map4(s, int);
        let pack = |lo: __m256i, hi: __m256i| {
            _mm256_blend_epi16::<0b1010_1010>(lo, _mm256_slli_epi32::<16>(hi))
        };
        // `A` in both halves of each lane: bytes 2 and 3 of every 32-bit lane, twice (the
        // indices of `vpshufb` count within each 128-bit half).
        let (low, high) = (0x0706_0706_0302_0302, 0x0f0e_0f0e_0b0a_0b0a);
        let dup_a = _mm256_set_epi64x(high, low, high, low);
        let a2 = _mm256_shuffle_epi8(ba, dup_a);
        let t = _mm256_and_si256(
            _mm256_sub_epi16(_mm256_set1_epi16(INT_ONE as i16), a2),
            int(live),
        );
        let step = |acc: __m256i, x: __m256i| _mm256_add_epi16(acc, over_u16(t, x));
        let zero = _mm256_setzero_ps();
        [
            _mm256_castsi256_ps(step(rg, pack(r, g))),
            _mm256_castsi256_ps(step(ba, pack(b, a))),
            zero,
            zero,
        ]
    }

    /// `A ≥ a_stop` as `A > a_stop − 1` (`1 ≤ a_stop ≤ ONE`), with `A` the high half of the
    /// accumulator's second vector.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn done(acc: &[__m256; 4], a_stop: f32) -> __m256 {
        let below = _mm256_set1_epi32(a_stop as i32 - 1);
        let a = _mm256_srli_epi32::<16>(_mm256_castps_si256(acc[1]));
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, below))
    }

    /// `fixed_point::front_to_back` of each sample, stopping before a sample once
    /// `A ≥ a_stop` (as `IntRayMarcher::cast` does); `acc` packed as the lanes' accumulator.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn serial(
        acc: &mut [i32; 4],
        [r, g, b, a]: [__m256; 4],
        k0: u32,
        ends: (u32, u32),
        a_stop: f32,
    ) -> Option<u32> {
        // Every lane holds `C ≤ A ≤ ONE` (`IntMode::combine`'s invariant, whose integer
        // arithmetic the kernel performs; the accumulator `front_to_back`'s).
        let narrow = |x: i32| u16::try_from(x).unwrap_or(u16::MAX);
        let [ar, ag, ab, aa] = unpacked(*acc);
        let mut s = IntSample::from_valid([ar, ag, ab], aa);
        let [r, g, b, a] = map4([r, g, b, a], |v| to_i32s(_mm256_castps_si256(v)));
        let lanes = r.into_iter().zip(g).zip(b).zip(a);
        let mut stop = None;
        for (k, (((r, g), b), a)) in (k0..).zip(lanes) {
            if k >= ends.0 {
                break;
            }
            if f32::from(s.a()) >= a_stop {
                stop = Some(k);
                break;
            }
            let x = IntSample::from_valid([narrow(r), narrow(g), narrow(b)], narrow(a));
            s = int_front_to_back(s, x);
        }
        let [r, g, b] = s.c();
        *acc = packed([r, g, b, s.a()]);
        if stop.is_none() && k0 + LANES as u32 > ends.0 {
            stop = Some(Self::ran_out(acc, ends, a_stop));
        }
        stop
    }

    /// The march stops before a sample once `A ≥ a_stop`: at `end` if samples are left.
    fn ran_out(acc: &[i32; 4], (end, total): (u32, u32), a_stop: f32) -> u32 {
        let [.., a] = unpacked(*acc);
        if end < total && f32::from(a) >= a_stop {
            end
        } else {
            total
        }
    }
}

/// [`IntOw`]'s accumulator of one lane as bit patterns: `[r | g << 16, b | A << 16, 0, 0]`.
#[inline(always)]
fn packed([r, g, b, a]: [u16; 4]) -> [i32; 4] {
    let pair = |lo: u16, hi: u16| (u32::from(lo) | u32::from(hi) << 16) as i32;
    [pair(r, g), pair(b, a), 0, 0]
}

/// [`packed`] inverted: `[r, g, b, A]`.
#[inline(always)]
fn unpacked([rg, ba, ..]: [i32; 4]) -> [u16; 4] {
    let (lo, hi) = (|x: i32| x as u16, |x: i32| (x as u32 >> 16) as u16);
    [lo(rg), hi(rg), lo(ba), hi(ba)]
}

/// [`Kind::tap_sums`] of taps not side by side: each tap's eight voxels read alone (out of
/// line).
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
unsafe fn tap_sums_apart<M: LaneMode, V: Voxel>(
    taps: &Taps<'_, V>,
    f: [__m256; 3],
    taus: Taus<'_>,
) -> [__m256; 4] {
    let w = weights(f);
    if taps.inside() {
        // SAFETY: the caller's contract (AVX2 and FMA), and `taps.inside()` for `INSIDE`.
        let c = unsafe { all_taps::<M::Taps, V, true>(taps, taus) };
        mode_sums::<M::W>(
            |k| c.get(k).copied().unwrap_or([_mm256_setzero_ps(); 4]),
            &w,
        )
    } else {
        // SAFETY: as above.
        let c = unsafe { all_taps::<M::Taps, V, false>(taps, taus) };
        mode_sums::<M::W>(
            |k| c.get(k).copied().unwrap_or([_mm256_setzero_ps(); 4]),
            &w,
        )
    }
}
