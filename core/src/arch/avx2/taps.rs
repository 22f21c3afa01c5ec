//! The taps of a step: indices, the bounds test before the unchecked loads, the loads
//! (words, pairs, 16-byte voxels), the channels, and the faces a packet of parallel rays
//! keeps between steps ([`Cell`]).

use core::arch::x86_64::*;

use super::*;

/// The eight taps' voxel indices of a step, eight lanes each, as scalars (read through memory:
/// eight lane extractions per tap cost about 6 % of the kernel's time).
///
/// The clamped indices always lie in the data; [`Taps::new`] proves it for all 64 by one
/// vector test (their unsigned maximum below `data.len()`), and then [`Taps::load`] reads
/// without a bounds check per voxel (which cost about 13 % of the kernel's time). Were an
/// index ever outside, every load would be checked and such a voxel read as transparent:
/// never out of bounds either way.
#[derive(Debug)]
pub struct Taps<'d, V> {
    at: [__m256i; 8],
    /// Set only by `new`, and only when every index of `at` is below `data.len()`.
    inside: bool,
    /// `data` as `StraightU8` (`Voxel::as_straight_u8`, of the same length), whose pairs
    /// of voxels [`load_pair`](Self::load_pair) reads as 8-byte words; `None` for other
    /// formats.
    bytes: Option<&'d [StraightU8]>,
    /// Set only by `new`, and only where `inside`, `bytes` is there and, in every lane, the
    /// index `i` of each even tap `k` has `i + 1 < data.len()` and the odd tap `k + 1` is at
    /// `i + 1` or (an x coordinate clamped at an edge of the grid) at `i`: the x neighbours
    /// lie side by side in memory, or are one voxel.
    pairs: bool,
    /// The voxels, read by [`load_f32x4`](Self::load_f32x4) as `ExtinctionF32` or
    /// `StraightF32` (`Voxel::as_extinction_f32`, `as_straight_f32`: the same slice retyped,
    /// chosen by `V` at compile time, so each instance keeps one of the two reads).
    data: &'d [V],
}

impl<'d, V: Voxel> Taps<'d, V> {
    /// Whether every tap index lies in the data (the fields stay private to this module, so
    /// that only [`new`](Self::new), which tests it, sets it).
    #[inline(always)]
    pub(super) fn inside(&self) -> bool {
        self.inside
    }

    /// Whether the x neighbours lie side by side in memory (set only by `new`).
    #[inline(always)]
    pub(super) fn pairs(&self) -> bool {
        self.pairs
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn new(data: &'d [V], at: [__m256i; 8]) -> Self {
        let [a0, a1, a2, a3, a4, a5, a6, a7] = at;
        let max = |a, b| _mm256_max_epu32(a, b);
        let even = max(max(a0, a2), max(a4, a6));
        let all = max(even, max(max(a1, a3), max(a5, a7)));
        // `last` is the last index as an `i32` where the length is `1..=i32::MAX` (`fits`
        // holds for every volume the kernel is given; the test below repeats it).
        let len = data.len();
        let last = _mm256_set1_epi32((len as i32).wrapping_sub(1));
        let at_most = |m: __m256i, bound: __m256i| {
            _mm256_movemask_epi8(_mm256_cmpeq_epi32(_mm256_max_epu32(m, bound), bound)) == -1
        };
        let inside = (1..=i32::MAX as usize).contains(&len) && at_most(all, last);
        // Every even tap's pair in the data (`i ≤ len − 2`, unsigned; `len ≥ 2` is tested
        // apart, since below it `len − 2` wraps to a bound every index meets), and every odd
        // tap at its even tap's index plus 0 or 1 (unsigned difference ≤ 1).
        let one = _mm256_set1_epi32(1);
        let pair_end = _mm256_set1_epi32((len as i32).wrapping_sub(2));
        let step = |a: __m256i, b: __m256i| _mm256_sub_epi32(b, a);
        let steps = max(
            max(step(a0, a1), step(a2, a3)),
            max(step(a4, a5), step(a6, a7)),
        );
        let bytes = V::as_straight_u8(data).filter(|b| b.len() == len);
        let pairs =
            inside && len >= 2 && bytes.is_some() && at_most(even, pair_end) && at_most(steps, one);
        Self {
            at,
            inside,
            bytes,
            pairs,
            data,
        }
    }

    /// The four stored `f32` of tap `k`'s eight 16-byte voxels: `[C^τ r, g, b, τ]` of
    /// [`ExtinctionF32`], `[r, g, b, α]` of [`StraightF32`]; one 16-byte read per lane and a
    /// 4 × 4 transposition per half; without bounds checks where `INSIDE` (which, unlike
    /// [`load`](Self::load)'s, is the caller's promise, below). All zero (transparent) for
    /// other formats, which the kernel never reads this way.
    ///
    /// # Safety
    /// Where `INSIDE`, every tap index must lie in the data ([`inside`](Self::inside), which
    /// the callers test before they pass `INSIDE`): the reads are then unchecked, with no test
    /// here, so that the read is small enough to be inlined into the kernel (with the test and
    /// the checked reads beside the unchecked ones it stayed a call, and the 16-byte
    /// `ExtinctionWeighted` packets took about 1.4 times `OpacityWeighted`'s time).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn load_f32x4<const INSIDE: bool>(&self, k: usize) -> [__m256; 4] {
        let Some(&at) = self.at.get(k) else {
            return [_mm256_setzero_ps(); 4];
        };
        let len = self.data.len();
        if let Some(ext) = V::as_extinction_f32(self.data).filter(|e| e.len() == len) {
            let vector = |v: ExtinctionF32| {
                let [r, g, b] = v.c_tau;
                _mm_setr_ps(r, g, b, v.tau)
            };
            // SAFETY: the caller's contract (`inside` where `INSIDE`); `ext` is `self.data`
            // retyped, of its length.
            unsafe { transposed::<_, INSIDE>(ext, at, vector) }
        } else if let Some(straight) = V::as_straight_f32(self.data).filter(|e| e.len() == len) {
            let vector = |v: StraightF32| {
                let [r, g, b] = v.c;
                _mm_setr_ps(r, g, b, v.a)
            };
            // SAFETY: as above.
            unsafe { transposed::<_, INSIDE>(straight, at, vector) }
        } else {
            [_mm256_setzero_ps(); 4]
        }
    }

    /// The [`StraightU8`] voxels of tap `k` as little-endian RGBA words; without bounds
    /// checks where `INSIDE` and `inside` (a caller that has tested `inside` passes `INSIDE`,
    /// so that the test here folds away). All zero (transparent) for other formats, which
    /// the kernel never reads this way.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn load<const INSIDE: bool>(&self, k: usize) -> __m256i {
        let word = |v: StraightU8| i32::from_le_bytes(v.0);
        // (`k < 8` in every call; another `k` reads transparent voxels.)
        let (Some(&at), Some(bytes)) = (self.at.get(k), self.bytes) else {
            return _mm256_setzero_si256();
        };
        let at = to_i32s(at);
        if INSIDE && self.inside {
            from_i32s(map8(at, |i| {
                // SAFETY: `inside`: `0 ≤ i < data.len()` = `bytes.len()` as unsigned numbers,
                // tested by `new` for every lane of every tap (`max_epu32(max, last) = last`
                // in all lanes).
                word(unsafe { *bytes.get_unchecked(i as u32 as usize) })
            }))
        } else {
            from_i32s(map8(at, |i| {
                word(
                    bytes
                        .get(i as u32 as usize)
                        .copied()
                        .unwrap_or(StraightU8::TRANSPARENT),
                )
            }))
        }
    }

    /// The voxels of taps `k` and `k + 1` (`k` even: x neighbours), as [`load`](Self::load)
    /// of each, in one 8-byte read per lane (the voxel of tap `k` and the one after it, which
    /// is tap `k + 1`'s unless the two taps are one voxel: then tap `k`'s word in both) without
    /// bounds checks where `pairs` (a caller that has tested `pairs` calls it only then;
    /// elsewhere it falls back to the checked loads).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn load_pair(&self, k: usize) -> [__m256i; 2] {
        // SAFETY: this function's AVX2 and FMA.
        match unsafe { self.pair_reads(k, |_| ()) } {
            Some((words, _, _)) => words,
            None => self.load_two(k),
        }
    }

    /// [`load_pair`](Self::load_pair), and the `τ` of the two taps' opacity bytes by `table`:
    /// each lane's two bytes read as scalars beside its pair (at the indices the pair read
    /// has taken out of the vector already), so that no lane of the words is taken out again
    /// for the lookups. Where `pairs` is not set, the checked loads and the `τ` of their
    /// opacity bytes.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA. (`#[inline(always)]`, which `#[target_feature]` does
    /// not allow: with the hint alone LLVM kept it a call, and the one-ray march of
    /// `ExtinctionWeightedU8` executed about a third more instructions.)
    #[inline(always)]
    pub(super) unsafe fn load_pair_tau(
        &self,
        k: usize,
        table: &[f32; 256],
    ) -> [(__m256i, __m256); 2] {
        let tau = |v: StraightU8| table.get(usize::from(v.0[3])).copied().unwrap_or(0.0);
        // SAFETY: the caller's contract (AVX2 and FMA), which the reads and the vector
        // operations below need.
        unsafe {
            let Some(([even, odd], same, t)) = self.pair_reads(k, |two| two.each(tau)) else {
                return self.load_two(k).each(|w| (w, taus_of(w, table)));
            };
            let [t0, t1] = [0, 1].each(|j| lanes(t.each(|two| two.get(j).copied().unwrap_or(0.0))));
            // Tap `k + 1`'s `τ` is tap `k`'s where the two are one voxel, as its word is.
            [
                (even, t0),
                (odd, _mm256_blendv_ps(t1, t0, _mm256_castsi256_ps(same))),
            ]
        }
    }

    /// The pair read of [`load_pair`](Self::load_pair) where `pairs` (else `None`): the two
    /// taps' words, the lanes where the two taps are one voxel (all ones), and `also` of each
    /// lane's two voxels side by side (the first tap's voxel and the one after it).
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA (`#[inline(always)]`, as
    /// [`load_pair_tau`](Self::load_pair_tau)).
    #[inline(always)]
    unsafe fn pair_reads<T: Copy>(
        &self,
        k: usize,
        also: impl Fn([StraightU8; 2]) -> T,
    ) -> Option<([__m256i; 2], __m256i, [T; 8])> {
        let (at, odd, bytes) = match (self.at.get(k), self.at.get(k + 1), self.bytes) {
            (Some(&at), Some(&odd), Some(bytes)) if self.pairs && k % 2 == 0 => (at, odd, bytes),
            _ => return None,
        };
        // SAFETY: the caller's contract (AVX2 and FMA) for the vector operations; for the
        // reads, `pairs`: `i + 1 < data.len()` = `bytes.len()` for the index `i` of every even
        // tap `k`, and the two `StraightU8` (`repr(transparent)` over `[u8; 4]`) are eight
        // initialised bytes side by side, read unaligned.
        unsafe {
            let read = |i: i32| {
                let i = i as u32 as usize;
                let two = bytes.get_unchecked(i..i + 2);
                let pair = two.as_ptr().cast::<i64>().read_unaligned();
                (pair, also([*two.get_unchecked(0), *two.get_unchecked(1)]))
            };
            let [p0, p1, p2, p3, p4, p5, p6, p7] = map8(to_i32s(at), read);
            // Lanes 0, 1, 4, 5 and 2, 3, 6, 7, so that taking the even and the odd words of
            // the two (per 128-bit half) leaves the lanes in order.
            let half = |a: i64, b: i64| _mm_insert_epi64::<1>(_mm_cvtsi64_si128(a), b);
            let four = |lo: __m128i, hi: __m128i| {
                _mm256_castsi256_ps(_mm256_inserti128_si256::<1>(_mm256_castsi128_si256(lo), hi))
            };
            let a = four(half(p0.0, p1.0), half(p4.0, p5.0));
            let b = four(half(p2.0, p3.0), half(p6.0, p7.0));
            let even = _mm256_castps_si256(_mm256_shuffle_ps::<0b10_00_10_00>(a, b));
            let next = _mm256_castps_si256(_mm256_shuffle_ps::<0b11_01_11_01>(a, b));
            // Tap `k + 1` is tap `k`'s voxel where its index is the same (`pairs`: else the
            // next).
            let same = _mm256_cmpeq_epi32(at, odd);
            let also = [p0.1, p1.1, p2.1, p3.1, p4.1, p5.1, p6.1, p7.1];
            Some(([even, _mm256_blendv_epi8(next, even, same)], same, also))
        }
    }

    /// Taps `k` and `k + 1` by the checked [`load`](Self::load): [`load_pair`](Self::load_pair)
    /// where it is called without `pairs` (which its callers do not do).
    #[cold]
    #[inline(never)]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn load_two(&self, k: usize) -> [__m256i; 2] {
        [self.load::<false>(k), self.load::<false>(k + 1)]
    }
}

/// The taps of the cell's two faces across axis `A` (0 = x, 1 = y, 2 = z): tap `k` (bit 0 of
/// `k` the x side, bit 1 the y side, bit 2 the z side, as in `filter::trilinear_weights`)
/// lies on face `(k >> A) & 1`, at place [`place::<A>(k)`](place) within it.
#[inline(always)]
pub(super) fn face<const A: usize>(side: usize) -> [usize; 4] {
    // Tap `k` of place `p`: `p` with the bit `side` inserted at bit `A`.
    let tap = |p: usize| (p & ((1 << A) - 1)) | ((side & 1) << A) | ((p >> A) << (A + 1));
    [tap(0), tap(1), tap(2), tap(3)]
}

/// The place of tap `k` within its face across axis `A` (see [`face`]).
#[inline(always)]
pub(super) fn place<const A: usize>(k: usize) -> usize {
    let low = k & ((1 << A) - 1);
    let high = k >> (A + 1);
    low | (high << A)
}

/// The channels of a cell's eight taps as `f32` (`[r, g, b, α]`, each `n/255` correctly
/// rounded), kept between steps as two faces across axis `A`: `faces[near ^ s]` holds the
/// taps of side `s` (see [`face`]), so that a step of one cell along `A` turns the far face
/// into the near one by flipping `near`. For [`IntOw`] a face holds its two pairs of taps
/// packed ([`int_pair`]) at places 0 and 2 (and again at 1 and 3).
pub(crate) struct Cell<const A: usize> {
    faces: [[[__m256; 4]; 4]; 2],
    pub(super) near: usize,
    /// The indices of taps `0`, `7` and `far₀` (the far face's tap `0`) of the cell held, per
    /// lane; −1 (no index) before the first read.
    pub(super) at: [__m256i; 3],
}

impl<const A: usize> Cell<A> {
    /// Of a cell's eight tap indices, that of the far face's tap `0` (tap `1 << A`).
    #[inline(always)]
    pub(super) fn far0(at: &[__m256i; 8]) -> __m256i {
        match A {
            0 => at[1],
            1 => at[2],
            _ => at[4],
        }
    }

    /// Of a cell's eight tap indices, that of the near face's tap `7` (tap `7 ^ (1 << A)`).
    #[inline(always)]
    pub(super) fn near7(at: &[__m256i; 8]) -> __m256i {
        match A {
            0 => at[6],
            1 => at[5],
            _ => at[3],
        }
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn new() -> Self {
        Self {
            faces: [[[_mm256_setzero_ps(); 4]; 4]; 2],
            near: 0,
            at: [_mm256_set1_epi32(-1); 3],
        }
    }

    /// Reads and converts the taps of side `SIDE` (see [`face`]) as the kind `K` does
    /// ([`Kind::read_face`]).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn read<V: Voxel, K: Kind, const SIDE: usize>(
        &mut self,
        taps: &Taps<'_, V>,
        taus: Taus<'_>,
    ) {
        let [f0, f1] = &mut self.faces;
        let out = if (self.near ^ SIDE) & 1 == 0 { f0 } else { f1 };
        // SAFETY: `Kind::read_face` needs AVX2 and FMA, which this function has.
        unsafe { K::read_face::<V, A>(out, taps, face::<A>(SIDE), taus) }
    }

    /// The channels of tap `k`.
    #[inline(always)]
    pub(super) fn tap(&self, k: usize) -> [__m256; 4] {
        let [f0, f1] = &self.faces;
        let f = if (self.near ^ (k >> A)) & 1 == 0 {
            f0
        } else {
            f1
        };
        match place::<A>(k) {
            0 => f[0],
            1 => f[1],
            2 => f[2],
            _ => f[3],
        }
    }
}

/// The channels of eight little-endian RGBA words as `f32`: `[r, g, b, α]`, each `n/255`
/// correctly rounded.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn channels(g: __m256i) -> [__m256; 4] {
    let byte = _mm256_set1_epi32(0xff);
    let bytes = [
        _mm256_and_si256(g, byte),
        _mm256_and_si256(_mm256_srli_epi32::<8>(g), byte),
        _mm256_and_si256(_mm256_srli_epi32::<16>(g), byte),
        _mm256_srli_epi32::<24>(g),
    ];
    map4(bytes, |n| unorm8(n))
}

/// The `τ` of the opacity bytes of eight little-endian RGBA words by `table`: eight scalar
/// lookups.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) fn taus_of(word: __m256i, table: &[f32; 256]) -> __m256 {
    let alpha = _mm256_srli_epi32::<24>(word);
    // (Each index is below 256: `get` never misses, and its test folds away.)
    let tau = |n: i32| table.get(n as u32 as usize).copied().unwrap_or(0.0);
    lanes(map8(to_i32s(alpha), tau))
}

/// [`Taps::load_f32x4`] of the voxels `data` at the indices `at`, each voxel a vector by
/// `vector`: one 16-byte read per lane and a 4 × 4 transposition per half.
///
/// # Safety
/// Where `INSIDE`, every index of `at` must lie in `data` (as unsigned numbers).
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn transposed<W: Voxel, const INSIDE: bool>(
    data: &[W],
    at: __m256i,
    vector: impl Fn(W) -> __m128,
) -> [__m256; 4] {
    let at = to_i32s(at);
    let m = if INSIDE {
        map8(at, |i| {
            // SAFETY: the caller's contract: `0 ≤ i < data.len()` as unsigned numbers.
            vector(unsafe { *data.get_unchecked(i as u32 as usize) })
        })
    } else {
        map8(at, |i| {
            vector(
                data.get(i as u32 as usize)
                    .copied()
                    .unwrap_or(W::TRANSPARENT),
            )
        })
    };
    let [m0, m1, m2, m3, m4, m5, m6, m7] = m;
    // Lanes `l` and `l + 4` in the two halves, then per half the transposition of four
    // `[r, g, b, τ]` rows into four columns.
    let (v04, v15) = (_mm256_set_m128(m4, m0), _mm256_set_m128(m5, m1));
    let (v26, v37) = (_mm256_set_m128(m6, m2), _mm256_set_m128(m7, m3));
    let rg01 = _mm256_unpacklo_ps(v04, v15);
    let bt01 = _mm256_unpackhi_ps(v04, v15);
    let rg23 = _mm256_unpacklo_ps(v26, v37);
    let bt23 = _mm256_unpackhi_ps(v26, v37);
    [
        _mm256_shuffle_ps::<0b01_00_01_00>(rg01, rg23),
        _mm256_shuffle_ps::<0b11_10_11_10>(rg01, rg23),
        _mm256_shuffle_ps::<0b01_00_01_00>(bt01, bt23),
        _mm256_shuffle_ps::<0b11_10_11_10>(bt01, bt23),
    ]
}
