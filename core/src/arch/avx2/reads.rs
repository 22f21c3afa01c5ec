//! How the float kinds read a tap's channels ([`ReadTaps`], one implementation per
//! [`TapRead`](crate::mode::TapRead) format), and the `τ` table of
//! `ExtinctionWeightedU8` with the way this CPU looks it up ([`Taus`]).

use core::arch::x86_64::*;

use super::*;
use crate::each::Each;
use crate::mode::{StoredF32x4, TauOfAlpha8, Unorm8};

/// The `τ` of every opacity byte (`ExtinctionWeightedU8`'s `TauTable`; the other kinds ignore
/// it), and how this CPU looks eight of them up at once.
///
/// By one gather instruction where the CPU's gathers are fast (Intel's, but for the models
/// that mitigate Gather Data Sampling), by eight scalar loads on all others ([`Avx2::gathers`]):
/// an eight-lane gather is 5 micro-operations, one every 5 cycles, on Intel's Skylake, and 39,
/// one every 8 cycles, on AMD's Zen 3 (uops.info's measurements), and the two ways measured
/// the opposite way round on this project's Intel Xeon and AMD EPYC (the performance log,
/// 2026-12-05 (late night) and 2026-12-07 (day)). Both give the same values; the choice is
/// one predictable branch per tap read. Where the taps are read in pairs, the scalar loads
/// take each lane's opacity bytes beside its pair's 8-byte read ([`Taps::load_pair_tau`]),
/// not from the lanes of the words: those lane extractions were most of the instructions
/// this mode's one-ray march executed beyond `OpacityWeighted`'s (the performance log,
/// 2026-12-07 (midday) and (afternoon)).
#[derive(Debug, Clone, Copy)]
pub struct Taus<'t> {
    pub(crate) table: &'t [f32; 256],
    pub(crate) gather: bool,
}

/// How the kernel reads a tap's channels, for each [`TapRead`] of the float modes.
/// # Safety of the methods: the CPU must have AVX2 and FMA.
pub trait ReadTaps {
    /// The channels of eight little-endian RGBA words: `[r, g, b, α]`, each `n/255`
    /// correctly rounded ([`channels`]); `taus` is the `τ` of every opacity byte (read by
    /// [`TauOfAlpha8`] only, [`Taus`]).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn channels(word: __m256i, taus: Taus<'_>) -> [__m256; 4] {
        let _ = taus;
        channels(word)
    }

    /// The channels of tap `k` (its words' [`channels`](Self::channels)); `INSIDE` as
    /// [`Taps::load`]. Safety, besides AVX2 and FMA: `INSIDE` only where `taps.inside()` (a
    /// read may then skip its bounds checks, as [`Taps::load_f32x4`] does).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn tap<V: Voxel, const INSIDE: bool>(
        taps: &Taps<'_, V>,
        k: usize,
        taus: Taus<'_>,
    ) -> [__m256; 4] {
        // SAFETY: the caller's contract (AVX2 and FMA), which this function has too.
        unsafe { Self::channels(taps.load::<INSIDE>(k), taus) }
    }

    /// What a read of two taps side by side ([`read_pair`](Self::read_pair)) holds of each
    /// until the sums take its channels ([`channels_of`](Self::channels_of)).
    type Raw: Copy;

    /// Taps `k` and `k + 1` (`k` even) read as a pair ([`Taps::load_pair`]), where
    /// `taps.pairs()` (elsewhere by the checked loads).
    unsafe fn read_pair<V: Voxel>(taps: &Taps<'_, V>, k: usize, taus: Taus<'_>) -> [Self::Raw; 2];

    /// The channels of a tap read by [`read_pair`](Self::read_pair), as
    /// [`channels`](Self::channels) of its word.
    unsafe fn channels_of(raw: Self::Raw, taus: Taus<'_>) -> [__m256; 4];
}

/// The tap reads of RGBA8 words whose channels follow from the word alone.
macro_rules! word_pairs {
    () => {
        type Raw = __m256i;

        #[inline(always)]
        unsafe fn read_pair<V: Voxel>(taps: &Taps<'_, V>, k: usize, _: Taus<'_>) -> [__m256i; 2] {
            // SAFETY: the caller's contract (AVX2 and FMA).
            unsafe { taps.load_pair(k) }
        }

        #[inline(always)]
        unsafe fn channels_of(word: __m256i, taus: Taus<'_>) -> [__m256; 4] {
            // SAFETY: the caller's contract (AVX2 and FMA).
            unsafe { Self::channels(word, taus) }
        }
    };
}

impl ReadTaps for Unorm8 {
    word_pairs!();
}

impl ReadTaps for TauOfAlpha8 {
    /// `[τ·r, τ·g, τ·b, τ]` with `τ = taus[α byte]`, as `TauTable::extinction`: the eight
    /// `τ` by one gather where the CPU's gathers are fast ([`Taus`]), else by eight scalar
    /// loads (the same values either way).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn channels(word: __m256i, taus: Taus<'_>) -> [__m256; 4] {
        let tau = if taus.gather {
            let alpha = _mm256_srli_epi32::<24>(word);
            // SAFETY: every index is the top byte of a lane (`0..=255`), inside the table's
            // 256 `f32`s; AVX2, which the gather needs, is this function's contract.
            unsafe { _mm256_i32gather_ps::<4>(taus.table.as_ptr(), alpha) }
        } else {
            taus_of(word, taus.table)
        };
        times_tau(word, tau)
    }

    /// A word and its `τ`: without gathers, the `τ` read beside the pair
    /// ([`Taps::load_pair_tau`]); with them, looked up by [`channels_of`](Self::channels_of)
    /// as [`channels`](Self::channels) does.
    type Raw = (__m256i, __m256);

    #[inline(always)]
    unsafe fn read_pair<V: Voxel>(
        taps: &Taps<'_, V>,
        k: usize,
        taus: Taus<'_>,
    ) -> [(__m256i, __m256); 2] {
        if taus.gather {
            // SAFETY: the caller's contract (AVX2 and FMA).
            unsafe { taps.load_pair(k).each(|w| (w, _mm256_setzero_ps())) }
        } else {
            // SAFETY: as above.
            unsafe { taps.load_pair_tau(k, taus.table) }
        }
    }

    #[inline(always)]
    unsafe fn channels_of((word, tau): (__m256i, __m256), taus: Taus<'_>) -> [__m256; 4] {
        if taus.gather {
            // SAFETY: the caller's contract (AVX2 and FMA).
            unsafe { Self::channels(word, taus) }
        } else {
            // SAFETY: as above.
            unsafe { times_tau(word, tau) }
        }
    }
}

/// `[τ·r, τ·g, τ·b, τ]` of a word's colors ([`channels`]) and its `τ`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn times_tau(word: __m256i, tau: __m256) -> [__m256; 4] {
    let [r, g, b, _] = channels(word);
    let mul = _mm256_mul_ps;
    [mul(tau, r), mul(tau, g), mul(tau, b), tau]
}

impl ReadTaps for StoredF32x4 {
    /// Each tap's stored `[C^τ, τ]` ([`Taps::load_f32x4`]).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn tap<V: Voxel, const INSIDE: bool>(
        taps: &Taps<'_, V>,
        k: usize,
        _taus: Taus<'_>,
    ) -> [__m256; 4] {
        // SAFETY: the caller's contract: AVX2 and FMA, and `taps.inside()` where `INSIDE`.
        unsafe { taps.load_f32x4::<INSIDE>(k) }
    }

    // (16-byte voxels are never read in pairs: `Taps::pairs` is never set for them.)
    word_pairs!();
}

/// The channels of all eight taps ([`ReadTaps::tap`] of each, called here directly: through a
/// closure per tap, the one-ray march of 16-byte extinction voxels took 1.18–1.19 of its
/// former time in quick passes, the reads apparently not inlined). Safety: AVX2 and FMA, and
/// `INSIDE` only where `taps.inside()`.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn all_taps<R: ReadTaps, V: Voxel, const INSIDE: bool>(
    taps: &Taps<'_, V>,
    taus: Taus<'_>,
) -> [[__m256; 4]; 8] {
    // SAFETY: the caller's contract (AVX2 and FMA, and `taps.inside()` where `INSIDE`), which
    // `ReadTaps::tap` asks for.
    unsafe {
        [
            R::tap::<V, INSIDE>(taps, 0, taus),
            R::tap::<V, INSIDE>(taps, 1, taus),
            R::tap::<V, INSIDE>(taps, 2, taus),
            R::tap::<V, INSIDE>(taps, 3, taus),
            R::tap::<V, INSIDE>(taps, 4, taus),
            R::tap::<V, INSIDE>(taps, 5, taus),
            R::tap::<V, INSIDE>(taps, 6, taus),
            R::tap::<V, INSIDE>(taps, 7, taus),
        ]
    }
}
