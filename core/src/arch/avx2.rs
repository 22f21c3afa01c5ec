//! The AVX2 + FMA instance: the [`Avx2`] token and its entry ([`Avx2::run`], which compiles
//! the portable kernels inlined into it for AVX2), and eight rays in the eight `f32` lanes of
//! AVX2 vectors: the packet kernel of
//! [`RayMarcher::cast_rays`](crate::RayMarcher::cast_rays) for `OpacityWeighted`, `Separate`
//! and `ExtinctionWeightedU8` trilinear (`WeightedSum`) sampling of straight RGBA8 voxels,
//! and `ExtinctionWeighted` of [`ExtinctionF32`] voxels ([`EXTINCTION_F32`]), front to back,
//! without opacity correction or empty-space skipping; and, in `i32` lanes, that of
//! [`IntRayMarcher::cast_rays`](crate::fixed_point::IntRayMarcher::cast_rays) for the integer
//! `OpacityWeighted` trilinear pipeline at `F = 8` ([`march8_int`], [`int_sums`]).
//!
//! Compiled into every x86-64 build; entered only with an [`Avx2`] token, which only
//! [`Avx2::detect`] makes (CPUID: AVX2, FMA, and the OS saving the 256-bit registers; every
//! AVX2 CPU of Intel and AMD has FMA). Elsewhere `cast_rays` keeps its portable four-ray
//! packets (the integer one casts one ray at a time). Inside the
//! `#[target_feature(enable = "avx2,fma")]` functions the value intrinsics of `core::arch`
//! are safe functions; the entries ([`Avx2::run`], [`march8`], [`march8_int`]) call them in an
//! `unsafe` block whose proof is the token. Five more `unsafe` blocks, each with its
//! proof: the bit casts between an integer vector and `[i32; 8]` (`to_i32s`, `from_i32s`),
//! the unchecked voxel loads of [`Taps::load`], taken only after one vector test per read
//! has shown all 64 tap indices inside the data (eight scalar loads per tap; a gather
//! instruction was slower on the machine measured), those of [`Taps::load_f32x4`] (16-byte
//! `ExtinctionF32` voxels, after the same test), and the unchecked 8-byte loads of
//! [`Taps::load_pair`].
//!
//! **Pair reads**: where no lane's x taps are clamped together (at the grid's x edges), each
//! lane's taps `k` and `k + 1` are neighbours in memory, and for [`StraightU8`] voxels one
//! 8-byte load reads both (four such loads and two shuffles make two taps' vectors, for
//! sixteen 4-byte loads and inserts); the test is a dozen vector operations per read. Faces
//! across y or z are two such pairs; faces across x (x-major parallel rays) none. In a probe
//! this took perspective packets from 8.4–11.0 to 7.4–7.6 ns/sample.
//!
//! **Bit-identical to [`RayMarcher::cast`](crate::RayMarcher::cast)** per ray: each lane
//! performs the one-ray kernel's `f32` operations in the same order — `t = t₀ + j·d`,
//! `p = o + dir·t`, `⌊p⌋` and the fraction `p − ⌊p⌋`, the taps' coordinates clamped into
//! the grid, the trilinear weights of `filter::trilinear_weights`, the mode's sums from the
//! last tap to the first (`ω = w·α`, `Σ ω·C`, `Σ ω` for `OpacityWeighted`; `Σ w·C`, `Σ w·α`
//! and `C̃ = α·C` for `Separate`; `Σ w·C^τ`, `Σ w·τ` with `τ` from the `TauTable` and
//! `integrate_step` for `ExtinctionWeightedU8` (and the same sums and step of the stored
//! `[C^τ, τ]` for `ExtinctionWeighted` over `ExtinctionF32`), its polynomial `φ` in lanes
//! where every lane's `τd` is below 1, else per lane), the clamps, and the front-to-back
//! step — with no fused multiply-add (IEEE `+`, `−`, `×`, `÷` round the same in any unit).
//! A byte `n` becomes the correctly rounded `n/255` of the table the one-ray kernel reads as
//! `n·h + (n·l)` with `1/255 = h + l` split into two `f32` (one product, one fused
//! multiply-add), which is the rounded quotient for every byte (a unit test here checks all
//! 256).
//! `tests/fast_paths.rs` compares `cast_rays` in every instruction set the CPU has with the
//! baseline `cast`, bit for bit.
//!
//! **The integer pipeline** ([`march8_int`], `INTEGER_OW`) is bit-identical to
//! [`IntRayMarcher::cast`](crate::fixed_point::IntRayMarcher::cast) the same way: the
//! positions are the float marcher's, each clamped into `[0, n − 1]` and quantized with
//! round half up to 8 fractional bits (exactly, in `f32`, for volumes up to `2^14` voxels
//! per axis: [`quantize8`]); the taps' bytes stay integers, two neighbours' packed into
//! 16-bit halves as `α·C − 2^15` and `α` ([`int_pair`], kept so by the reuse); [`int_sums`]
//! forms `OpacityWeighted`'s exact sums axis by axis, the first by `vpmaddwd`, the second in
//! `u32` lanes and the last axis's color sums in 64-bit lanes (the widths are in its doc), and
//! rounds them as the portable kernel does;
//! compositing is `fixed_point::front_to_back` (`T·x + ONE/2` in a `u32` lane, the quotient by
//! `ONE` with [`div65280`]), and a lane stops once `A ≥ A_stop`. Unit tests here check
//! `int_sums` against `IntMode::combine`, `div65280` for every `u32` and `quantize8` for every
//! `f32` it takes; `tests/fast_paths.rs` compares `cast_rays` with `cast`. In a probe (the
//! bench's 256³ volume and coherent rays) the first version took 5.1–5.2 ns/sample, against
//! 18.5 for the integer `cast` and 4.5 for the float packets; computing each lerp as
//! `(256 − f)·a + f·b` (two products, one sum, where `256·a + f·(b − a)` took four
//! operations), the quantization by a truncation, and the last axis's color sums in 64-bit
//! lanes (16 operations per color where a split into two 32-bit lerps took 19) brought it to
//! 4.64–4.67; the whole sample's arithmetic costs about 1.5 ns/sample of it (a probe that
//! skipped it ran at 3.2). The quantization by one fused multiply-add took it to 4.62, the
//! first axis by `vpmaddwd` to 4.40 (0.96 of the float packets).
//!
//! **Reuse and prefetch for parallel rays** (the same values, so the same results): where
//! the eight rays have one direction (an orthographic view), their lanes move from cell to
//! cell together, and the taps' channels are kept between steps. When every lane is still in
//! the cell of the last step (at step 0.5 a ray stays in a cell for about two samples) nothing
//! is read or converted; when every lane has moved on by one cell along the packet's major
//! axis (that of the direction's largest component), the four taps of the cell's far face
//! become the near face and only the new far face is read. Each step also prefetches, for
//! lanes 0 and 7, the tap rows of the sample [`PREFETCH_STEPS`] steps ahead (along y or z
//! the two on the near side of the major axis, whose far rows are near rows a cell further
//! on; along x all four): without it, the reads that remain (behind the reuse's branches)
//! wait on memory; a prefetch never faults, so its address needs no bounds check. On the
//! 256³ bench this took the packets from 7.4 to about 5.15 ns/sample (with all four rows,
//! four steps ahead; two rows six steps ahead took a probe from 4.87–4.89 to 4.51–4.52).
//! Rays of different directions (a perspective view) leave their cells at different steps;
//! there the reuse cost a quarter more time in a probe (10.4 against 8.3 ns/sample), so such
//! packets read and convert every tap at every step.

use core::arch::x86_64::*;

use crate::composite::front_to_back;
use crate::mode::integrate_step;
use crate::opacity::{PHI_POLY, PHI_POLY_BELOW};
use crate::ray::Ray;
use crate::sample::Sample;
use crate::volume::Volume;
use crate::voxel::{ExtinctionF32, StraightU8, Voxel};

/// Proof that this CPU runs AVX2 and FMA instructions: made only by [`detect`](Self::detect).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Avx2(());

impl Avx2 {
    /// The token, where CPUID says the CPU has AVX2 and FMA and the operating system saves
    /// the AVX registers (XCR0 bits 1 and 2, read with XGETBV where CPUID says the OS enabled
    /// it, OSXSAVE).
    pub(crate) fn detect() -> Option<Self> {
        // Leaf 1, ECX: bit 12 FMA, bit 27 OSXSAVE, bit 28 AVX; leaf 7 sub-leaf 0, EBX: bit 5
        // AVX2 (Intel SDM vol. 2A, CPUID; AMD APM vol. 3, appendix E).
        if __cpuid(0).eax < 7 {
            return None;
        }
        let ecx = __cpuid(1).ecx;
        let bit = |r: u32, b: u32| r & (1 << b) != 0;
        if !(bit(ecx, 12) && bit(ecx, 27) && bit(ecx, 28)) {
            return None;
        }
        // SAFETY: XGETBV needs the OS to have set CR4.OSXSAVE, which CPUID.1:ECX.OSXSAVE
        // (bit 27, tested above) reports.
        let xcr0 = unsafe { xcr0() };
        let ebx = __cpuid_count(7, 0).ebx;
        (xcr0 & 0b110 == 0b110 && bit(ebx, 5)).then_some(Avx2(()))
    }

    /// Runs `f` inside a function compiled for AVX2 and FMA, into which `f` and the
    /// `#[inline(always)]` code it calls are inlined.
    #[inline(always)]
    pub(crate) fn run<R>(self, f: impl FnOnce() -> R) -> R {
        // SAFETY: `self` exists only where `detect` found AVX2 and FMA on this CPU.
        unsafe { run_avx2(f) }
    }
}

/// XCR0, the register of the state components the OS saves.
///
/// # Safety
/// The OS must have enabled XGETBV (CPUID.1:ECX.OSXSAVE).
#[target_feature(enable = "xsave")]
unsafe fn xcr0() -> u64 {
    // SAFETY: the caller's contract: XGETBV is enabled; 0 is the index of XCR0.
    unsafe { _xgetbv(0) }
}

/// `f()`, compiled for AVX2 and FMA ([`Avx2::run`]).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn run_avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// How many steps ahead each step prefetches the voxels (of lanes 0 and 7: in a packet of a
/// row of pixels the others lie between them).
const PREFETCH_STEPS: f32 = 6.0;

/// Rays per packet.
pub(crate) const LANES: usize = 8;

/// How many steps the extinction modes' compositing lags behind their sums (see the
/// pipelining in [`march8_avx2`]). A lag of 1 took `ExtinctionWeightedU8` from 7.8 to 7.1
/// ns/sample in a probe; 2 gained nothing (6.3–7.9 against 6.3–6.5, both modes).
const LAG: u32 = 1;

/// The modes the kernel computes (its `MODE` parameter): `OpacityWeighted`, `Separate`, and
/// `ExtinctionWeightedU8` (its `τ` looked up per tap, `ExtinctionWeighted`'s sums and step).
pub(crate) const OPACITY_WEIGHTED: u8 = 0;
/// See [`OPACITY_WEIGHTED`].
pub(crate) const SEPARATE: u8 = 1;
/// See [`OPACITY_WEIGHTED`].
pub(crate) const EXTINCTION_U8: u8 = 2;
/// The integer `OpacityWeighted` kernel at `F = 8` (`fixed_point`, [`march8_int`]): its
/// channels, sums and compositing in `i32` lanes (carried in the kernel's `__m256` values
/// as bit patterns).
pub(crate) const INTEGER_OW: u8 = 3;
/// `ExtinctionWeighted` over [`ExtinctionF32`] voxels: each tap's `[C^τ, τ]` read as one
/// 16-byte vector per lane, then `EXTINCTION_U8`'s sums and step.
pub(crate) const EXTINCTION_F32: u8 = 4;

/// Whether `MODE` is one of the extinction modes ([`EXTINCTION_U8`], [`EXTINCTION_F32`]),
/// whose samples are integrated over the step (`integrate_step`).
const fn extinction(mode: u8) -> bool {
    mode == EXTINCTION_U8 || mode == EXTINCTION_F32
}

/// Eight `f32` lanes from an array.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn lanes(a: [f32; LANES]) -> __m256 {
    let [a0, a1, a2, a3, a4, a5, a6, a7] = a;
    _mm256_setr_ps(a0, a1, a2, a3, a4, a5, a6, a7)
}

/// The lanes as an array.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn array(v: __m256) -> [f32; LANES] {
    map8(to_i32s(_mm256_castps_si256(v)), |x| {
        f32::from_bits(x as u32)
    })
}

/// The lanes of an integer vector as an array (through memory: the eight lanes of a tap's
/// indices are read as scalars, where eight lane extractions cost about 6 % of the kernel's
/// time).
#[inline(always)]
fn to_i32s(v: __m256i) -> [i32; LANES] {
    // SAFETY: a bit cast between two 32-byte plain-data types, every bit pattern valid in both.
    unsafe { core::mem::transmute::<__m256i, [i32; LANES]>(v) }
}

/// An integer vector of an array's lanes ([`to_i32s`] inverted).
#[inline(always)]
fn from_i32s(a: [i32; LANES]) -> __m256i {
    // SAFETY: as in `to_i32s`.
    unsafe { core::mem::transmute::<[i32; LANES], __m256i>(a) }
}

/// `a.map(f)` without `core::array::map`: that generic is compiled for the baseline (it does
/// not inherit a caller's target features), so a closure with AVX2 instructions passed to it
/// cannot be inlined into it and stays a call; these are inlined into their AVX2 callers
/// first, and the closure then into the caller. (With `map`, the AVX2 packets took 1.11 of
/// their time in the build for an AVX2 CPU, which compiles `map` with AVX2.)
#[inline(always)]
fn map8<T, U>(a: [T; 8], mut f: impl FnMut(T) -> U) -> [U; 8] {
    let [a0, a1, a2, a3, a4, a5, a6, a7] = a;
    [f(a0), f(a1), f(a2), f(a3), f(a4), f(a5), f(a6), f(a7)]
}

/// [`map8`] for four elements.
#[inline(always)]
fn map4<T, U>(a: [T; 4], mut f: impl FnMut(T) -> U) -> [U; 4] {
    let [a0, a1, a2, a3] = a;
    [f(a0), f(a1), f(a2), f(a3)]
}

/// [`map8`] for three elements.
#[inline(always)]
fn map3<T, U>(a: [T; 3], mut f: impl FnMut(T) -> U) -> [U; 3] {
    let [a0, a1, a2] = a;
    [f(a0), f(a1), f(a2)]
}

/// `1/255` as the sum of two `f32`: `UNORM_HI` rounded, `UNORM_LO` the rest rounded.
const UNORM_HI: f32 = 1.0 / 255.0;
const UNORM_LO: f32 = (1.0f64 / 255.0 - UNORM_HI as f64) as f32;

/// `n/255` per lane for bytes `n` (0..=255), correctly rounded, as `n·HI + (n·LO)` in one
/// multiplication and one fused multiply-add (`1/255 = HI + LO` split into two `f32`). Not
/// correctly rounded for every real `n`, but for each of the 256 bytes: a test here checks
/// them all against the table of `voxel::unorm8`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn unorm8(n: __m256i) -> __m256 {
    let n = _mm256_cvtepi32_ps(n);
    _mm256_fmadd_ps(
        n,
        _mm256_set1_ps(UNORM_HI),
        _mm256_mul_ps(n, _mm256_set1_ps(UNORM_LO)),
    )
}

/// The eight taps' voxel indices of a step, eight lanes each, as scalars (read through memory:
/// eight lane extractions per tap cost about 6 % of the kernel's time).
///
/// The clamped indices always lie in the data; [`Taps::new`] proves it for all 64 by one
/// vector test (their unsigned maximum below `data.len()`), and then [`Taps::load`] reads
/// without a bounds check per voxel (which cost about 13 % of the kernel's time). Were an
/// index ever outside, every load would be checked and such a voxel read as transparent:
/// never out of bounds either way.
struct Taps<'d, V> {
    data: &'d [V],
    at: [__m256i; 8],
    /// Set only by `new`, and only when every index of `at` is below `data.len()`.
    inside: bool,
    /// `data` as `StraightU8` (`Voxel::as_straight_u8`, of the same length), whose pairs
    /// of voxels [`load_pair`](Self::load_pair) reads as 8-byte words; `None` for other
    /// formats.
    bytes: Option<&'d [StraightU8]>,
    /// Set only by `new`, and only where `inside`, `bytes` is there and, in every lane, the
    /// index of each odd tap `k + 1` is that of tap `k` plus one: the x neighbours lie side by
    /// side in memory.
    pairs: bool,
    /// `data` as `ExtinctionF32` (`Voxel::as_extinction_f32`, of the same length), read by
    /// [`load_f32x4`](Self::load_f32x4); `None` for other formats.
    f32x4: Option<&'d [ExtinctionF32]>,
}

impl<'d, V: Voxel> Taps<'d, V> {
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn new(data: &'d [V], at: [__m256i; 8]) -> Self {
        let [a0, a1, a2, a3, a4, a5, a6, a7] = at;
        let max = |a, b| _mm256_max_epu32(a, b);
        let max = max(max(max(a0, a1), max(a2, a3)), max(max(a4, a5), max(a6, a7)));
        // `last` is the last index as an `i32` where the length is `1..=i32::MAX` (`fits`
        // holds for every volume the kernel is given; the test below repeats it).
        let len = data.len();
        let last = _mm256_set1_epi32((len as i32).wrapping_sub(1));
        let below = _mm256_cmpeq_epi32(_mm256_max_epu32(max, last), last);
        let inside = (1..=i32::MAX as usize).contains(&len) && _mm256_movemask_epi8(below) == -1;
        let [a0, a1, a2, a3, a4, a5, a6, a7] = at;
        let one = _mm256_set1_epi32(1);
        let next = |a: __m256i, b: __m256i| _mm256_cmpeq_epi32(_mm256_add_epi32(a, one), b);
        let side_by_side = _mm256_and_si256(
            _mm256_and_si256(next(a0, a1), next(a2, a3)),
            _mm256_and_si256(next(a4, a5), next(a6, a7)),
        );
        let bytes = V::as_straight_u8(data).filter(|b| b.len() == len);
        let pairs = inside && bytes.is_some() && _mm256_movemask_epi8(side_by_side) == -1;
        let f32x4 = V::as_extinction_f32(data).filter(|e| e.len() == len);
        Self {
            data,
            at,
            inside,
            bytes,
            pairs,
            f32x4,
        }
    }

    /// The `[C^τ r, g, b, τ]` of tap `k`'s eight [`ExtinctionF32`] voxels, one 16-byte read
    /// per lane and a 4 × 4 transposition per half; without bounds checks where `INSIDE` and
    /// `inside` (as [`load`](Self::load)). All zero (transparent) for other formats, which the
    /// kernel never reads this way.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn load_f32x4<const INSIDE: bool>(&self, k: usize) -> [__m256; 4] {
        let (Some(&at), Some(ext)) = (self.at.get(k), self.f32x4) else {
            return [_mm256_setzero_ps(); 4];
        };
        let vector = |v: ExtinctionF32| {
            let [r, g, b] = v.c_tau;
            _mm_setr_ps(r, g, b, v.tau)
        };
        let at = to_i32s(at);
        let m = if INSIDE && self.inside {
            map8(at, |i| {
                // SAFETY: `inside`: `0 ≤ i < data.len()` = `ext.len()` as unsigned numbers,
                // tested by `new` for every lane of every tap.
                vector(unsafe { *ext.get_unchecked(i as u32 as usize) })
            })
        } else {
            map8(at, |i| {
                vector(
                    ext.get(i as u32 as usize)
                        .copied()
                        .unwrap_or(ExtinctionF32::TRANSPARENT),
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

    /// The channels of tap `k` as the kernel computes with them ([`channels`] of its words,
    /// or for `EXTINCTION_F32` its vectors); `INSIDE` as [`load`](Self::load).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn channels<const MODE: u8, const INSIDE: bool>(
        &self,
        k: usize,
        taus: &[f32; 256],
    ) -> [__m256; 4] {
        if MODE == EXTINCTION_F32 {
            self.load_f32x4::<INSIDE>(k)
        } else {
            channels::<MODE>(self.load::<INSIDE>(k), taus)
        }
    }

    /// The voxels of tap `k` as little-endian RGBA words; without bounds checks where
    /// `INSIDE` and `inside` (a caller that has tested `inside` passes `INSIDE`, so that the
    /// test here folds away).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn load<const INSIDE: bool>(&self, k: usize) -> __m256i {
        let word = |v: V| i32::from_le_bytes(v.rgba8());
        // (`k < 8` in every call; another `k` reads transparent voxels.)
        let Some(&at) = self.at.get(k) else {
            return _mm256_setzero_si256();
        };
        let at = to_i32s(at);
        if INSIDE && self.inside {
            from_i32s(map8(at, |i| {
                // SAFETY: `inside`: `0 ≤ i < data.len()` as unsigned numbers, tested by `new`
                // for every lane of every tap (`max_epu32(max, last) = last` in all lanes).
                word(unsafe { *self.data.get_unchecked(i as u32 as usize) })
            }))
        } else {
            from_i32s(map8(at, |i| {
                word(
                    self.data
                        .get(i as u32 as usize)
                        .copied()
                        .unwrap_or(V::TRANSPARENT),
                )
            }))
        }
    }

    /// The voxels of taps `k` and `k + 1` (`k` even: x neighbours), as [`load`](Self::load)
    /// of each, in one 8-byte read per lane (the two words side by side) without bounds checks
    /// where `pairs` (a caller that has tested `pairs` calls it only then; elsewhere it falls
    /// back to the checked loads).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn load_pair(&self, k: usize) -> [__m256i; 2] {
        let (at, bytes) = match (self.at.get(k), self.bytes) {
            (Some(&at), Some(bytes)) if self.pairs && k % 2 == 0 => (to_i32s(at), bytes),
            _ => return self.load_two(k),
        };
        let [i0, i1, i2, i3, i4, i5, i6, i7] = at;
        let pair = |i: i32| {
            let i = i as u32 as usize;
            // SAFETY: `pairs`: tap `k + 1`'s index is `i + 1` (`k` even) and, by `inside`,
            // below `data.len()` = `bytes.len()`, as is `i`; the two `StraightU8`
            // (`repr(transparent)` over `[u8; 4]`) are eight initialised bytes side by side,
            // read unaligned.
            unsafe {
                let two = bytes.get_unchecked(i..i + 2);
                two.as_ptr().cast::<i64>().read_unaligned()
            }
        };
        // Lanes 0, 1, 4, 5 and 2, 3, 6, 7, so that taking the even and the odd words of the
        // two (per 128-bit half) leaves the lanes in order.
        let half = |a: i32, b: i32| _mm_insert_epi64::<1>(_mm_cvtsi64_si128(pair(a)), pair(b));
        let four = |lo: __m128i, hi: __m128i| {
            _mm256_castsi256_ps(_mm256_inserti128_si256::<1>(_mm256_castsi128_si256(lo), hi))
        };
        let a = four(half(i0, i1), half(i4, i5));
        let b = four(half(i2, i3), half(i6, i7));
        [
            _mm256_castps_si256(_mm256_shuffle_ps::<0b10_00_10_00>(a, b)),
            _mm256_castps_si256(_mm256_shuffle_ps::<0b11_01_11_01>(a, b)),
        ]
    }

    /// Taps `k` and `k + 1` by the checked [`load`](Self::load): [`load_pair`](Self::load_pair)
    /// where it is called without `pairs` (which its callers do not do).
    #[cold]
    #[inline(never)]
    #[target_feature(enable = "avx2,fma")]
    fn load_two(&self, k: usize) -> [__m256i; 2] {
        [self.load::<false>(k), self.load::<false>(k + 1)]
    }
}

/// The taps of the cell's two faces across axis `A` (0 = x, 1 = y, 2 = z): tap `k` (bit 0 of
/// `k` the x side, bit 1 the y side, bit 2 the z side, as in `filter::trilinear_weights`)
/// lies on face `(k >> A) & 1`, at place [`place::<A>(k)`](place) within it.
#[inline(always)]
fn face<const A: usize>(side: usize) -> [usize; 4] {
    // Tap `k` of place `p`: `p` with the bit `side` inserted at bit `A`.
    let tap = |p: usize| (p & ((1 << A) - 1)) | ((side & 1) << A) | ((p >> A) << (A + 1));
    [tap(0), tap(1), tap(2), tap(3)]
}

/// The place of tap `k` within its face across axis `A` (see [`face`]).
#[inline(always)]
fn place<const A: usize>(k: usize) -> usize {
    let low = k & ((1 << A) - 1);
    let high = k >> (A + 1);
    low | (high << A)
}

/// The channels of a cell's eight taps as `f32` (`[r, g, b, α]`, each `n/255` correctly
/// rounded), kept between steps as two faces across axis `A`: `faces[near ^ s]` holds the
/// taps of side `s` (see [`face`]), so that a step of one cell along `A` turns the far face
/// into the near one by flipping `near`. For `INTEGER_OW` a face holds its two pairs of taps
/// packed ([`int_pair`]) at places 0 and 2 (and again at 1 and 3).
struct Cell<const A: usize> {
    faces: [[[__m256; 4]; 4]; 2],
    near: usize,
    /// The indices of taps `0`, `7` and `far₀` (the far face's tap `0`) of the cell held, per
    /// lane; −1 (no index) before the first read.
    at: [__m256i; 3],
}

impl<const A: usize> Cell<A> {
    /// Of a cell's eight tap indices, that of the far face's tap `0` (tap `1 << A`).
    #[inline(always)]
    fn far0(at: &[__m256i; 8]) -> __m256i {
        match A {
            0 => at[1],
            1 => at[2],
            _ => at[4],
        }
    }

    /// Of a cell's eight tap indices, that of the near face's tap `7` (tap `7 ^ (1 << A)`).
    #[inline(always)]
    fn near7(at: &[__m256i; 8]) -> __m256i {
        match A {
            0 => at[6],
            1 => at[5],
            _ => at[3],
        }
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn new() -> Self {
        Self {
            faces: [[[_mm256_setzero_ps(); 4]; 4]; 2],
            near: 0,
            at: [_mm256_set1_epi32(-1); 3],
        }
    }

    /// Reads and converts the taps of side `SIDE` (see [`face`]). The branch on `inside` is
    /// taken once per face, outside the taps' loop.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn read<V: Voxel, const MODE: u8, const SIDE: usize>(
        &mut self,
        taps: &Taps<'_, V>,
        taus: &[f32; 256],
    ) {
        let [f0, f1] = &mut self.faces;
        let out = if (self.near ^ SIDE) & 1 == 0 { f0 } else { f1 };
        let [k0, k1, k2, k3] = face::<A>(SIDE);
        if MODE == INTEGER_OW {
            // The face's words, then its two pairs (places 0 and 1, 2 and 3: neighbours
            // along x, or along y for a face across x) packed for `int_sums`, held at places
            // 0 and 2, and again at 1 and 3 ([`int_pair`]).
            let [w0, w1, w2, w3] = if A != 0 && taps.pairs {
                let [w0, w1] = taps.load_pair(k0);
                let [w2, w3] = taps.load_pair(k2);
                [w0, w1, w2, w3]
            } else if taps.inside {
                map4([k0, k1, k2, k3], |k| taps.load::<true>(k))
            } else {
                map4([k0, k1, k2, k3], |k| taps.load::<false>(k))
            };
            let [p0, p1] = [int_pair(w0, w1), int_pair(w2, w3)];
            *out = [p0, p0, p1, p1];
            return;
        }
        // Across y or z, a face's taps are two x pairs (`face`); across x, none.
        if A != 0 && taps.pairs {
            let [t0, t1] = taps.load_pair(k0);
            let [t2, t3] = taps.load_pair(k2);
            *out = [
                channels::<MODE>(t0, taus),
                channels::<MODE>(t1, taus),
                channels::<MODE>(t2, taus),
                channels::<MODE>(t3, taus),
            ];
        } else if taps.inside {
            unpack::<V, MODE, true>(taps, face::<A>(SIDE), out, taus);
        } else {
            unpack::<V, MODE, false>(taps, face::<A>(SIDE), out, taus);
        }
    }

    /// The channels of tap `k`.
    #[inline(always)]
    fn tap(&self, k: usize) -> [__m256; 4] {
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

/// Reads and converts the taps `ks` into `out`; `INSIDE` as [`Taps::load`].
#[inline]
#[target_feature(enable = "avx2,fma")]
fn unpack<V: Voxel, const MODE: u8, const INSIDE: bool>(
    taps: &Taps<'_, V>,
    ks: [usize; 4],
    out: &mut [[__m256; 4]; 4],
    taus: &[f32; 256],
) {
    for (c, k) in out.iter_mut().zip(ks) {
        *c = taps.channels::<MODE, INSIDE>(k, taus);
    }
}

/// The channels of eight little-endian RGBA words as `f32`: `[r, g, b, α]`, each `n/255`
/// correctly rounded; for `EXTINCTION_U8` `[τ·r, τ·g, τ·b, τ]` with `τ = taus[α byte]`, as
/// `TauTable::extinction` (`INTEGER_OW` reads words, [`int_pair`]).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn channels<const MODE: u8>(g: __m256i, taus: &[f32; 256]) -> [__m256; 4] {
    let byte = _mm256_set1_epi32(0xff);
    let a = _mm256_srli_epi32::<24>(g);
    let bytes = [
        _mm256_and_si256(g, byte),
        _mm256_and_si256(_mm256_srli_epi32::<8>(g), byte),
        _mm256_and_si256(_mm256_srli_epi32::<16>(g), byte),
    ];
    let [r, g, b] = map3(bytes, |n| unorm8(n));
    if MODE == EXTINCTION_U8 {
        // (Every lane is a byte, so the lookup cannot miss.)
        let t = |n: i32| taus.get(usize::from(n as u8)).copied().unwrap_or(0.0);
        let [n0, n1, n2, n3, n4, n5, n6, n7] = to_i32s(a);
        let tau = _mm256_setr_ps(t(n0), t(n1), t(n2), t(n3), t(n4), t(n5), t(n6), t(n7));
        let mul = _mm256_mul_ps;
        [mul(tau, r), mul(tau, g), mul(tau, b), tau]
    } else {
        [r, g, b, unorm8(a)]
    }
}

/// `⌊n/65280⌋` (`65280 = 255·256 = fixed_point::ONE`) per lane for every `u32` `n`:
/// `⌊n·0x8080_8081/2^47⌋` (`0x8080_8081 = ⌈2^47/65280⌉`; the excess `n·0.498…/2^47` stays
/// below `1/65280` for `n < 2^32`), the 64-bit products of the even and the odd lanes by two
/// `vpmuludq`. A unit test checks every `n`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn div65280(n: __m256i) -> __m256i {
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
fn quantize8(p: __m256) -> __m256i {
    let up = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(p, _mm256_set1_ps(1.0 / 512.0)));
    let y = _mm256_fmadd_ps(p, _mm256_set1_ps(256.0), _mm256_set1_ps(0.5));
    _mm256_and_si256(_mm256_cvttps_epi32(y), up)
}

/// `(2^32 − 1)/255`: `⌊q/255⌋ = ⌊(q + 1)·RECIP255/2^32⌋` for `q < 2^24` (see [`int_sums`]; a
/// unit test checks every such `q`).
const RECIP255: u32 = 0x0101_0101;

/// `fixed_point::ONE` (opacity 1 in U8.8) in an `i32` lane.
const INT_ONE: i32 = crate::fixed_point::ONE as i32;

/// [`int_pair`] of two words.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn int_pair_of([w0, w1]: [__m256i; 2]) -> [__m256; 4] {
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
fn int_pair(w0: __m256i, w1: __m256i) -> [__m256; 4] {
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
fn int_sums(pair: impl Fn(usize) -> [__m256; 4], f: [__m256i; 3]) -> [__m256; 4] {
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
fn mode_sums<const MODE: u8>(
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
fn extinction_step(s: [__m256; 4], d: f32) -> ([__m256; 3], __m256) {
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
fn extinction_step_per_lane(s: [__m256; 4], d: f32) -> ([__m256; 3], __m256) {
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

/// Marches the leading multiple of eight rays of `rays` by `march` (eight rays to their eight
/// results) into `out`, and returns the rays and outputs left (fewer than eight; all of them
/// if `out` is not as long as `rays`).
#[inline]
pub(crate) fn in_packets<'r, 'o, P>(
    rays: &'r [Ray],
    out: &'o mut [P],
    mut march: impl FnMut(&[Ray; LANES]) -> [P; LANES],
) -> (&'r [Ray], &'o mut [P]) {
    if out.len() != rays.len() {
        return (rays, out);
    }
    let whole = rays.len() / LANES * LANES;
    let (r8, rest) = rays.split_at(whole);
    let (o8, out_rest) = out.split_at_mut(whole);
    for (r, o) in r8.chunks_exact(LANES).zip(o8.chunks_exact_mut(LANES)) {
        if let (Ok(r), Ok(o)) = (<&[Ray; LANES]>::try_from(r), <&mut [P; LANES]>::try_from(o)) {
            *o = march(r);
        }
    }
    (rest, out_rest)
}

/// Whether the kernel can index `vol` with `i32` lanes.
#[inline(always)]
pub(crate) fn fits<V: Voxel>(vol: &Volume<'_, V>) -> bool {
    vol.data().len() <= i32::MAX as usize
}

/// Marches eight rays front to back, lane `l` over the samples `t₀ + j·d`, `j < n`, with
/// `(t₀, n) = ranges[l]`, stopping a lane once its `A ≥ a_stop`: the accumulated samples
/// before the background, bit-identical to the one-ray march of the mode `MODE`
/// ([`OPACITY_WEIGHTED`], [`SEPARATE`], or [`EXTINCTION_U8`] with the `τ` of every opacity
/// byte in `taus`; the other modes ignore it), or [`EXTINCTION_F32`]. `V` must be
/// [`Voxel::STRAIGHT_RGBA8`] (for `EXTINCTION_F32`, [`ExtinctionF32`]: others read as
/// transparent) and `vol` must [`fits`].
pub(crate) fn march8<V: Voxel, const MODE: u8>(
    _cpu: Avx2,
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    ranges: &[(f32, u32); LANES],
    d: f32,
    a_stop: f32,
    taus: &[f32; 256],
) -> [Sample; LANES] {
    // SAFETY: `march8_any` needs a CPU with AVX2 and FMA; `_cpu` exists only where
    // `Avx2::detect` found them on this CPU.
    let acc = unsafe { march8_any::<V, MODE>(vol, rays, ranges, d, a_stop, taus) };
    let [r, g, b, a] = acc.map(|v| v.map(|x| f32::from_bits(x as u32)));
    let mut out = [Sample::TRANSPARENT; LANES];
    for ((((o, r), g), b), a) in out.iter_mut().zip(r).zip(g).zip(b).zip(a) {
        *o = Sample { c: [r, g, b], a };
    }
    out
}

/// One ray front to back over its samples `t₀ + j·d`, `j < n`, with `(t₀, n) = range`, eight
/// consecutive samples at a time in the lanes, composited in order until `A ≥ a_stop`: the
/// accumulated sample before the background and the number of samples composited,
/// bit-identical to the one-ray march (`RayMarcher::cast_counted`) of the mode `MODE`, as
/// [`march8`] (whose requirements on `V` and `vol` hold here too).
pub(crate) fn march_one<V: Voxel, const MODE: u8>(
    _cpu: Avx2,
    vol: &Volume<'_, V>,
    ray: &Ray,
    range: (f32, u32),
    d: f32,
    a_stop: f32,
    taus: &[f32; 256],
) -> (Sample, u32) {
    let (rays, ranges) = ([*ray; LANES], [range; LANES]);
    // SAFETY: as in `march8`.
    let out =
        unsafe { march8_avx2::<V, MODE, 2, false, true>(vol, &rays, &ranges, d, a_stop, taus) };
    let [[r, n, ..], [g, ..], [b, ..], [a, ..]] = out;
    let f = |x: i32| f32::from_bits(x as u32);
    (
        Sample {
            c: [f(r), f(g), f(b)],
            a: f(a),
        },
        n as u32,
    )
}

/// The integer `OpacityWeighted` trilinear march at `F = 8` of eight rays
/// (`IntRayMarcher::cast_rays`): as [`march8`], with the samples `t₀ + j·d` of
/// `ranges` (`IntRayMarcher::sample_range`) at the positions `Ray::at` computes, each
/// clamped into `[0, n − 1]` per axis and quantized (**round half up** to 8 fractional bits,
/// `IntPos::quantize`), sampled by [`int_sums`] (`IntMode::combine`, bit for bit) and
/// composited by `fixed_point::front_to_back` until `A ≥ a_stop` before a sample: the
/// accumulated samples before the background, bit-identical to `IntRayMarcher::cast`'s march.
/// `V` must be [`Voxel::STRAIGHT_RGBA8`] and `vol` must [`fits_int`].
pub(crate) fn march8_int<V: Voxel>(
    _cpu: Avx2,
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    ranges: &[(f32, u32); LANES],
    d: f32,
    a_stop: u16,
) -> [crate::fixed_point::IntSample; LANES] {
    let stop = f32::from(a_stop);
    // SAFETY: as in `march8`.
    let acc = unsafe { march8_any::<V, INTEGER_OW>(vol, rays, ranges, d, stop, &[0.0; 256]) };
    let [r, g, b, a] = acc;
    let mut out = [crate::fixed_point::IntSample::TRANSPARENT; LANES];
    for ((((o, r), g), b), a) in out.iter_mut().zip(r).zip(g).zip(b).zip(a) {
        // Every lane holds `C ≤ A ≤ ONE`: `front_to_back`'s invariants, whose integer
        // arithmetic the kernel performs.
        let narrow = |x: i32| u16::try_from(x).unwrap_or(u16::MAX);
        *o =
            crate::fixed_point::IntSample::from_valid([narrow(r), narrow(g), narrow(b)], narrow(a));
    }
    out
}

/// Whether the integer kernel can march `vol`: it [`fits`], and every coordinate times 256
/// stays below `2^22` (its `f32` quantization is exact there, and in an `i32` lane).
#[inline(always)]
pub(crate) fn fits_int<V: Voxel>(vol: &Volume<'_, V>) -> bool {
    fits(vol) && vol.dims().iter().all(|&n| n <= 1 << 14)
}

/// [`march8_avx2`] of the packet's kind (parallel rays with the reuse across their major
/// axis, others without): the accumulated `[r, g, b, α]` lanes as bit patterns.
#[target_feature(enable = "avx2,fma")]
fn march8_any<V: Voxel, const MODE: u8>(
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    ranges: &[(f32, u32); LANES],
    d: f32,
    a_stop: f32,
    taus: &[f32; 256],
) -> [[i32; LANES]; 4] {
    let [r0, ..] = rays;
    if rays.iter().any(|r| r.dir() != r0.dir()) {
        march8_avx2::<V, MODE, 2, false, false>(vol, rays, ranges, d, a_stop, taus)
    } else {
        match major_axis(r0.dir()) {
            0 => march8_avx2::<V, MODE, 0, true, false>(vol, rays, ranges, d, a_stop, taus),
            1 => march8_avx2::<V, MODE, 1, true, false>(vol, rays, ranges, d, a_stop, taus),
            _ => march8_avx2::<V, MODE, 2, true, false>(vol, rays, ranges, d, a_stop, taus),
        }
    }
}

/// The axis of `dir`'s largest component (by magnitude; the last of equals).
fn major_axis(dir: [f32; 3]) -> usize {
    let [x, y, z] = dir.map(f32::abs);
    if x > y && x > z {
        0
    } else if y > z {
        1
    } else {
        2
    }
}

/// [`march8`] (or [`march8_int`]) in AVX2; where `REUSE` (parallel rays), the taps' channels
/// kept as faces across axis `A` ([`Cell`]) and the voxels ahead prefetched. Returns the
/// accumulated `[r, g, b, α]` lanes as bit patterns.
///
/// Where `ONE` ([`march_one`]), the eight lanes are eight consecutive samples of one ray
/// instead (`rays[0]`, `ranges[0]`; lane `l` of step `j` is sample `8j + l`, at
/// `t₀ + (8j + l)·d` as the one-ray march computes it), composited in order, one lane after
/// the other, by `composite::front_to_back` until `A ≥ a_stop` after a sample: then lane 0 of
/// the four arrays holds the accumulated sample and lane 1 of the first the number of samples
/// composited. (Not inlined: its four instances
/// inlined into `march8` slowed the reuse by about a tenth in a probe, 5.7 against 5.15
/// ns/sample. Not returning the vectors themselves: returned through memory, they kept the
/// accumulator there across the loop, which took the `ExtinctionWeightedU8` packets from 7.1
/// to 8.6 ns/sample.)
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
fn march8_avx2<V: Voxel, const MODE: u8, const A: usize, const REUSE: bool, const ONE: bool>(
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    ranges: &[(f32, u32); LANES],
    d: f32,
    a_stop: f32,
    taus: &[f32; 256],
) -> [[i32; LANES]; 4] {
    let data = vol.data();
    let [nx, ny, nz] = vol.dims().map(|n| n as i32);
    // Per axis: (origin, direction, last voxel index, `n` as `f32`).
    let (org, dir) = (
        rays.each_ref().map(Ray::origin),
        rays.each_ref().map(Ray::dir),
    );
    let lead = PREFETCH_STEPS * d;
    let axis = |o: [f32; LANES], d: [f32; LANES], n: i32| {
        (
            lanes(o),
            lanes(d),
            _mm256_set1_epi32(n - 1),
            _mm256_set1_ps(n as f32),
            _mm256_mul_ps(lanes(d), _mm256_set1_ps(lead)),
        )
    };
    let axes = [
        axis(org.map(|o| o[0]), dir.map(|d| d[0]), nx),
        axis(org.map(|o| o[1]), dir.map(|d| d[1]), ny),
        axis(org.map(|o| o[2]), dir.map(|d| d[2]), nz),
    ];
    let t0 = lanes(ranges.map(|r| r.0));
    let count = ranges.map(|r| r.1);
    // (With `ONE`, every range is the one ray's.)
    let [(_, samples), ..] = *ranges;
    let steps = if ONE {
        samples.div_ceil(LANES as u32)
    } else {
        count.iter().copied().max().unwrap_or(0)
    };
    let [c0, c1, c2, c3, c4, c5, c6, c7] = count.map(|c| c as i32);
    let count = _mm256_setr_epi32(c0, c1, c2, c3, c4, c5, c6, c7);

    let dv = _mm256_set1_ps(d);
    let stop = _mm256_set1_ps(a_stop);
    let one = _mm256_set1_ps(1.0);
    let zf = _mm256_setzero_ps();
    let zero = _mm256_setzero_si256();
    // `⌊p⌋` is limited to `[−1, n]` before the conversion (the clamp below maps both ends to
    // the edge), so no coordinate overflows an `i32` lane.
    let lo_f = _mm256_set1_ps(-1.0);
    let ione = _mm256_set1_epi32(1);
    let (sx, sy) = (_mm256_set1_epi32(nx), _mm256_set1_epi32(nx * ny));

    let (add, sub, mul) = (_mm256_add_ps, _mm256_sub_ps, _mm256_mul_ps);
    // The sample of the sums `s`, `Sample::clamped`: `α` into [0, 1] (NaN to 0), each color
    // into [0, α]; `Separate` first weights the colors by the clamped `α` (its `finish`),
    // the extinction modes integrate the step (`integrate_step`).
    let finish = |s: [__m256; 4]| {
        if MODE == INTEGER_OW {
            // (The sample itself.)
            return s;
        }
        let (a, c) = if extinction(MODE) {
            let (c, a) = extinction_step(s, d);
            (_mm256_min_ps(_mm256_max_ps(a, zf), one), c)
        } else {
            let a = _mm256_min_ps(_mm256_max_ps(s[3], zf), one);
            if MODE == SEPARATE {
                (a, [mul(s[0], a), mul(s[1], a), mul(s[2], a)])
            } else {
                (a, [s[0], s[1], s[2]])
            }
        };
        let clamp = |c| _mm256_min_ps(_mm256_max_ps(c, zf), a);
        [clamp(c[0]), clamp(c[1]), clamp(c[2]), a]
    };
    // `front_to_back` of sample `[cr, cg, cb, a]` onto `acc`, kept in the live lanes only.
    let over = |acc: [__m256; 4], [cr, cg, cb, a]: [__m256; 4], live: __m256| {
        let [ar, ag, ab, aa] = acc;
        if MODE == INTEGER_OW {
            // `fixed_point::front_to_back`: `T = ONE − A`, each channel plus
            // `⌊(T·x + ONE/2)/ONE⌋` (`T·x + ONE/2 < 2^32`: the wrapping `i32` product is the
            // `u32` one). A lane that is not live takes `T = 0`, whose increments are
            // `⌊(ONE/2)/ONE⌋ = 0`.
            let int = _mm256_castps_si256;
            let t = _mm256_sub_epi32(_mm256_set1_epi32(INT_ONE), int(aa));
            let t = _mm256_and_si256(t, int(live));
            let half = _mm256_set1_epi32(INT_ONE / 2);
            let step = |acc: __m256, x: __m256| {
                let n = _mm256_add_epi32(_mm256_mullo_epi32(t, int(x)), half);
                _mm256_castsi256_ps(_mm256_add_epi32(int(acc), div65280(n)))
            };
            return [step(ar, cr), step(ag, cg), step(ab, cb), step(aa, a)];
        }
        let tr = sub(one, aa);
        [
            _mm256_blendv_ps(ar, add(ar, mul(tr, cr)), live),
            _mm256_blendv_ps(ag, add(ag, mul(tr, cg)), live),
            _mm256_blendv_ps(ab, add(ab, mul(tr, cb)), live),
            _mm256_blendv_ps(aa, add(aa, mul(tr, a)), live),
        ]
    };

    // The lanes still live after sample `i` has been composited onto `acc`: a lane stops
    // after its last sample, or once `A ≥ A_stop` (`Termination::done`).
    let still = |acc: &[__m256; 4], live: __m256, i: u32| {
        let more = _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, _mm256_set1_epi32(i as i32 + 1)));
        let done = if MODE == INTEGER_OW {
            // `A ≥ a_stop` as `A > a_stop − 1` (`1 ≤ a_stop ≤ ONE`).
            let below = _mm256_set1_epi32(a_stop as i32 - 1);
            _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_castps_si256(acc[3]), below))
        } else {
            _mm256_cmp_ps::<_CMP_GE_OQ>(acc[3], stop)
        };
        _mm256_andnot_ps(done, _mm256_and_ps(live, more))
    };

    // With `ONE`: the eight samples of step `i` (sample `8i + l` in lane `l`) composited in
    // order onto `acc` by `composite::front_to_back`; `Some` of the number of samples
    // composited once the ray ends or `A ≥ a_stop` (`Termination::done`).
    let serial = |acc: &mut Sample, [r, g, b, a]: [__m256; 4], i: u32| {
        let [r, g, b, a] = map4([r, g, b, a], |v| array(v));
        let lanes = r.into_iter().zip(g).zip(b).zip(a);
        for (k, (((r, g), b), a)) in (i * LANES as u32..).zip(lanes) {
            if k >= samples {
                return Some(samples);
            }
            *acc = front_to_back(*acc, Sample { c: [r, g, b], a });
            if acc.a >= a_stop {
                return Some(k + 1);
            }
        }
        None
    };
    let one_result = |s: Sample, n: u32| {
        let bits = |x: f32| x.to_bits() as i32;
        let mut out = [[0i32; LANES]; 4];
        let [or, og, ob, oa] = &mut out;
        [or[0], or[1], og[0], ob[0], oa[0]] = [
            bits(s.c[0]),
            n as i32,
            bits(s.c[1]),
            bits(s.c[2]),
            bits(s.a),
        ];
        out
    };
    let mut one_acc = Sample::TRANSPARENT;

    let mut acc = [zf; 4];
    // Lanes still compositing: before their last sample and not yet stopped (with `ONE`,
    // all of them while the ray has samples; `serial` stops it).
    let mut live = if ONE {
        _mm256_castsi256_ps(_mm256_set1_epi32(if samples > 0 { -1 } else { 0 }))
    } else {
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, zero))
    };
    let mut cell = Cell::<A>::new();
    // The extinction modes only: the sums of the [`LAG`] steps before, finished and
    // composited after this step's sums, oldest first (software pipelining: the step's long
    // chain of dependent operations, two divisions among them, then overlaps the next
    // samples' work; same operations, same order of compositing, so the same results).
    let lag = if extinction(MODE) { LAG } else { 0 };
    let mut pending = [[zf; 4]; LAG as usize];
    let mut j = 0u32;
    while j < steps && _mm256_movemask_ps(live) != 0 {
        // The sample position, as `Ray::at(t_first + j·d)` (with `ONE`, of sample `8j + l` in
        // lane `l`: every index below `2^24`, `MAX_SAMPLES_PER_RAY`, so exact as an `f32`).
        let t = if ONE {
            let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
            let jv = _mm256_add_epi32(_mm256_set1_epi32((j * LANES as u32) as i32), lane);
            _mm256_add_ps(t0, _mm256_mul_ps(_mm256_cvtepi32_ps(jv), dv))
        } else {
            _mm256_add_ps(t0, _mm256_mul_ps(_mm256_set1_ps(j as f32), dv))
        };
        // Per axis: the fraction `p − ⌊p⌋`, the two tap coordinates clamped into the grid, and
        // the coordinate `PREFETCH_STEPS` steps ahead (truncated: only a prefetch address).
        let split = |(o, d, last, n, ahead): (__m256, __m256, __m256i, __m256, __m256)| {
            let p = _mm256_add_ps(o, _mm256_mul_ps(d, t));
            let next = _mm256_cvttps_epi32(_mm256_add_ps(p, ahead));
            if MODE == INTEGER_OW {
                // `IntRayMarcher::quantize`: `p` clamped into `[0, n − 1]` (NaN to 0: `max`
                // returns its second operand then), `raw = ⌊256·p + ½⌋` (`quantize8`), then
                // the index `raw >> 8` and the fraction `raw & 255` (an `i32` bit pattern);
                // the index is at most `n − 1`, the second tap clamped to it.
                let p = _mm256_min_ps(_mm256_max_ps(p, zf), _mm256_sub_ps(n, one));
                let raw = quantize8(p);
                let i = _mm256_srli_epi32::<8>(raw);
                let f = _mm256_and_si256(raw, _mm256_set1_epi32(0xff));
                return (
                    _mm256_castsi256_ps(f),
                    i,
                    _mm256_min_epi32(_mm256_add_epi32(i, ione), last),
                    next,
                );
            }
            let fl = _mm256_floor_ps(p);
            let i = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(fl, lo_f), n));
            let c = |i| _mm256_min_epi32(_mm256_max_epi32(i, zero), last);
            (
                _mm256_sub_ps(p, fl),
                c(i),
                c(_mm256_add_epi32(i, ione)),
                next,
            )
        };
        let [(fx, x0, x1, qx), (fy, y0, y1, qy), (fz, z0, z1, qz)] = map3(axes, split);
        let row = |y, z| _mm256_add_epi32(_mm256_mullo_epi32(y, sx), _mm256_mullo_epi32(z, sy));
        // The prefetch (with the reuse, whose branches would otherwise leave the remaining
        // reads waiting on memory): lanes 0 and 7 of the four tap rows ahead. Its addresses
        // may lie outside the data (`wrapping_offset`, never dereferenced).
        if REUSE {
            let q = _mm256_add_epi32(qx, row(qy, qz));
            // Along y or z, the two rows on the near side of the major axis (a far row ahead
            // is a near row of a sample a cell further on, prefetched by a later step); along
            // x, all four.
            let rows = match A {
                2 => [zero, sx, sy, sy],
                1 => [zero, sy, sx, sx],
                _ => [zero, sx, sy, _mm256_add_epi32(sx, sy)],
            };
            for r in rows.into_iter().take(if A == 0 { 4 } else { 2 }) {
                let [a0, .., a7] = to_i32s(_mm256_add_epi32(q, r));
                for l in [a0, a7] {
                    let p = data.as_ptr().wrapping_offset(l as isize);
                    _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>());
                }
            }
        }
        let (r00, r10, r01, r11) = (row(y0, z0), row(y1, z0), row(y0, z1), row(y1, z1));
        let at = [
            _mm256_add_epi32(x0, r00),
            _mm256_add_epi32(x1, r00),
            _mm256_add_epi32(x0, r10),
            _mm256_add_epi32(x1, r10),
            _mm256_add_epi32(x0, r01),
            _mm256_add_epi32(x1, r01),
            _mm256_add_epi32(x0, r11),
            _mm256_add_epi32(x1, r11),
        ];

        // `filter::trilinear_weights`, operation for operation.
        let xy = mul(fx, fy);
        let xz = mul(fx, fz);
        let yz = mul(fy, fz);
        let xyz = mul(xy, fz);
        let w110 = sub(xy, xyz);
        let w101 = sub(xz, xyz);
        let w011 = sub(yz, xyz);
        let w100 = add(sub(sub(fx, xy), xz), xyz);
        let w010 = add(sub(sub(fy, xy), yz), xyz);
        let w001 = add(sub(sub(fz, xz), yz), xyz);
        let rest = add(
            add(add(add(add(add(xyz, w011), w101), w001), w110), w010),
            w100,
        );
        let w000 = sub(one, rest);
        let w = [w000, w100, w010, w110, w001, w101, w011, xyz];

        // The taps' channels, then the sums from the last tap down (`mode::dot`). With the
        // reuse, the channels are read only where the packet has moved on (here rather than in
        // a `Cell` method: a `target_feature` function was not inlined into its caller, and
        // the call cost about 5 % of the kernel's time). The branch on `inside` is taken once
        // per step or face, outside the taps' loop.
        let s = if REUSE {
            let same = |a: __m256i, b: __m256i, c: __m256i, d: __m256i| {
                let eq = _mm256_and_si256(_mm256_cmpeq_epi32(a, b), _mm256_cmpeq_epi32(c, d));
                _mm256_movemask_epi8(eq) == -1
            };
            let [c0, c7, far0] = cell.at;
            if !same(at[0], c0, at[7], c7) {
                let taps = Taps::new(data, at);
                if same(at[0], far0, Cell::<A>::near7(&at), c7) {
                    cell.near ^= 1;
                } else {
                    cell.read::<V, MODE, 0>(&taps, taus);
                }
                cell.read::<V, MODE, 1>(&taps, taus);
                cell.at = [at[0], at[7], Cell::<A>::far0(&at)];
            }
            if MODE == INTEGER_OW {
                // The packed pairs along x, or along y for faces across x (`Cell::read`),
                // held at the place of their first tap; the fractions in that order.
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
            } else {
                mode_sums::<MODE>(|p| [cell.tap(2 * p), cell.tap(2 * p + 1)], &w)
            }
        } else {
            let taps = Taps::new(data, at);
            let pair =
                |[lo, hi]: [__m256i; 2]| [channels::<MODE>(lo, taus), channels::<MODE>(hi, taus)];
            if MODE == INTEGER_OW {
                // Pairs along x: taps `2j` and `2j + 1`.
                let f = map3([fx, fy, fz], |v| _mm256_castps_si256(v));
                if taps.pairs {
                    int_sums(|j| int_pair_of(taps.load_pair(2 * j)), f)
                } else if taps.inside {
                    let load = |k| taps.load::<true>(k);
                    int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
                } else {
                    let load = |k| taps.load::<false>(k);
                    int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
                }
            } else if taps.pairs {
                mode_sums::<MODE>(|p| pair(taps.load_pair(2 * p)), &w)
            } else if taps.inside {
                let two = |k| {
                    [
                        taps.channels::<MODE, true>(k, taus),
                        taps.channels::<MODE, true>(k + 1, taus),
                    ]
                };
                mode_sums::<MODE>(|p| two(2 * p), &w)
            } else {
                let two = |k| {
                    [
                        taps.channels::<MODE, false>(k, taus),
                        taps.channels::<MODE, false>(k + 1, taus),
                    ]
                };
                mode_sums::<MODE>(|p| two(2 * p), &w)
            }
        };
        // The sums to composite now, of sample `j − lag`: this step's, or (pipelined) the
        // oldest pending.
        let s = if lag > 0 {
            let oldest = pending[0];
            pending.rotate_left(1);
            if let Some(newest) = pending.last_mut() {
                *newest = s;
            }
            if j < lag {
                j += 1;
                continue;
            }
            oldest
        } else {
            s
        };
        if ONE {
            if let Some(n) = serial(&mut one_acc, finish(s), j - lag) {
                return one_result(one_acc, n);
            }
        } else {
            acc = over(acc, finish(s), live);
            live = still(&acc, live, j - lag);
        }
        j += 1;
    }
    // The pipelined samples left (`j − lag` to `j − 1`, of those that exist), where a lane is
    // still live.
    if lag > 0 {
        let first = j.saturating_sub(lag);
        let left = pending.iter().skip((LAG - (j - first)) as usize);
        for (i, s) in (first..j).zip(left) {
            if ONE {
                if let Some(n) = serial(&mut one_acc, finish(*s), i) {
                    return one_result(one_acc, n);
                }
            } else if _mm256_movemask_ps(live) != 0 {
                acc = over(acc, finish(*s), live);
                live = still(&acc, live, i);
            }
        }
    }
    if ONE {
        return one_result(one_acc, samples);
    }
    let [r, g, b, a] = acc;
    let bits = |v: __m256| to_i32s(_mm256_castps_si256(v));
    [bits(r), bits(g), bits(b), bits(a)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::voxel::StraightU8;

    fn indices(a: [i32; LANES]) -> __m256i {
        from_i32s(a)
    }

    /// xorshift64: deterministic test data from `seed` (not 0).
    fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        }
    }

    /// `Taps::new` proves the indices inside exactly when all 64 are below the length (as
    /// unsigned numbers), and both loads read the voxels' words; an index outside reads the
    /// transparent voxel.
    #[test]
    fn taps_are_loaded_unchecked_only_when_all_indices_are_inside() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { taps_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn taps_check() {
        let data: [StraightU8; 10] = core::array::from_fn(|i| StraightU8([i as u8, 1, 2, 200]));
        let word = |i: usize| data.get(i).map_or(0, |v| i32::from_le_bytes(v.0));
        let ok = [0, 1, 2, 3, 4, 5, 8, 9];
        for bad in [None, Some(10), Some(-1), Some(i32::MAX)] {
            let mut at = [indices(ok); 8];
            if let Some(b) = bad {
                let mut lanes = ok;
                lanes[5] = b;
                at[3] = indices(lanes);
            }
            let taps = Taps::new(&data, at);
            assert_eq!(taps.inside, bad.is_none(), "{bad:?}");
            for k in 0..8 {
                for got in [
                    to_i32s(taps.load::<true>(k)),
                    to_i32s(taps.load::<false>(k)),
                ] {
                    let want = ok.map(|i| word(i as usize));
                    if k == 3 && bad.is_some() {
                        assert_eq!(got[5], 0, "{bad:?}");
                        assert_eq!(got[..5], want[..5]);
                        assert_eq!(got[6..], want[6..]);
                    } else {
                        assert_eq!(got, want, "{bad:?} tap {k}");
                    }
                }
            }
        }
        assert!(!Taps::<StraightU8>::new(&[], [indices([0; LANES]); 8]).inside);
    }

    /// `Taps::new` sets `pairs` exactly where every odd tap lies just after its even one, all
    /// inside, in `StraightU8` data; `load_pair` reads what `load` reads, with `pairs` or
    /// without (its fallback), for even and odd `k`.
    #[test]
    fn pairs_are_read_only_side_by_side() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { pairs_check() }
    }

    /// A format like `StraightU8` but not it: never read in pairs.
    #[derive(Clone, Copy)]
    struct Other([u8; 4]);

    impl Voxel for Other {
        const TRANSPARENT: Self = Self([0; 4]);
        const STRAIGHT_RGBA8: bool = true;
        fn check(&self) -> Result<(), crate::voxel::VoxelFault> {
            Ok(())
        }
        fn rgba8(self) -> [u8; 4] {
            self.0
        }
    }

    #[target_feature(enable = "avx2,fma")]
    fn pairs_check() {
        let bytes = |i: usize| [i as u8, 3 * i as u8, 7, 255 - i as u8];
        let data: [StraightU8; 20] = core::array::from_fn(|i| StraightU8(bytes(i)));
        let other: [Other; 20] = core::array::from_fn(|i| Other(bytes(i)));
        let even = [0, 3, 7, 2, 10, 18, 5, 11];
        let odd = even.map(|i| i + 1);
        let side_by_side = [even, odd, even, odd, even, odd, even, odd].map(indices);
        let mut apart = side_by_side;
        apart[5] = indices([1, 4, 8, 3, 12, 19, 6, 12]);
        let mut outside = side_by_side;
        outside[0] = indices([0, 3, 7, 2, 10, 19, 5, 11]);
        outside[1] = indices([1, 4, 8, 3, 11, 20, 6, 12]);
        for (at, pairs) in [(side_by_side, true), (apart, false), (outside, false)] {
            let taps = Taps::new(&data, at);
            assert_eq!(taps.pairs, pairs);
            let others = Taps::new(&other, at);
            assert!(!others.pairs);
            for k in 0..7 {
                let want = [taps.load::<false>(k), taps.load::<false>(k + 1)].map(to_i32s);
                assert_eq!(taps.load_pair(k).map(to_i32s), want, "tap {k}, {pairs}");
                assert_eq!(others.load_pair(k).map(to_i32s), want, "tap {k}, {pairs}");
            }
        }
    }

    /// `extinction_step`, clamped as the kernel clamps it, is `integrate_step` in every lane:
    /// packets of sums all below `τd = 1` (the lanes' path: `phi_poly`), among them whole
    /// packets of tiny `τd` (`2⁻³⁰..2⁻¹⁰`) and packets just below 1, and packets with a lane
    /// at or above 1, NaN, infinite or negative `τ` (the per-lane path); colors `C^τ ≤ τ`
    /// mostly, so that `φ` shows (the clamp of `C̃` into `[0, α]` would hide it).
    #[test]
    fn extinction_step_is_integrate_step_per_lane() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { extinction_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn extinction_check() {
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
        let mut unit = || (next() >> 40) as f32 / (1u64 << 24) as f32;
        let clamp =
            |v: __m256, hi: __m256| _mm256_min_ps(_mm256_max_ps(v, _mm256_setzero_ps()), hi);
        for case in 0..20_000 {
            let d = match case % 4 {
                0 => 0.5,
                1 => 1.0,
                2 => 0.3,
                _ => 2.0,
            };
            let wild = case % 3 == 0;
            // `τ` per lane: some whole packets of tiny `τd`, some of `τd` in `[0.9, 1)`, else
            // mostly `[0, 0.9)`, with single lanes of edge values (1 and just below it among
            // them).
            let tiny = case % 7 == 0;
            let near_one = case % 11 == 0;
            let tau: [f32; LANES] = core::array::from_fn(|l| {
                let u = unit();
                if tiny {
                    libm::exp2f(-10.0 - 20.0 * u) / d
                } else if near_one {
                    (0.9 + 0.1 * u).min(f32::from_bits(1.0f32.to_bits() - 1)) / d
                } else if l == case % 8 && u < 0.1 {
                    match l % 4 {
                        0 => 0.0,
                        1 => 1e-9,
                        2 => 3e-5,
                        _ => 2e-4,
                    }
                } else if wild && l == 3 {
                    match case % 6 {
                        0 => f32::NAN,
                        1 => f32::INFINITY,
                        2 => 40.0,
                        3 => 1.0 / d,
                        4 => 1.02 / d,
                        _ => -1.0,
                    }
                } else {
                    u * 0.9 / d
                }
            });
            // `C^τ = τ·C` (so that the clamps of `C̃` into `[0, α]` rarely hide `φ`), and
            // sometimes above `τ`.
            let s: [[f32; LANES]; 4] = core::array::from_fn(|k| {
                if k == 3 {
                    return tau;
                }
                core::array::from_fn(|l| {
                    let t = tau.get(l).copied().unwrap_or(0.0);
                    let u = unit();
                    if case % 5 == 0 {
                        u * 0.3
                    } else {
                        t * u
                    }
                })
            });
            let (c, a) = extinction_step(s.map(|v| lanes(v)), d);
            let a = clamp(a, _mm256_set1_ps(1.0));
            let c = c.map(|c| array(clamp(c, a)));
            let a = array(a);
            for l in 0..LANES {
                let [r, g, b, t] = s.map(|v| v.get(l).copied().unwrap_or(0.0));
                let want = integrate_step([r, g, b], t, d);
                let got = c.map(|c| c.get(l).copied().unwrap_or(-1.0));
                let got_a = a.get(l).copied().unwrap_or(-1.0);
                assert_eq!(
                    got_a.to_bits(),
                    want.a.to_bits(),
                    "α, case {case}, lane {l}"
                );
                for (g, w) in got.into_iter().zip(want.c) {
                    assert_eq!(g.to_bits(), w.to_bits(), "C̃, case {case}, lane {l}");
                }
            }
        }
    }

    /// `div65280` is `⌊n/65280⌋` for every `u32` `n`, in every lane.
    #[test]
    fn div65280_is_the_floor_of_the_quotient_for_every_u32() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { div65280_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn div65280_check() {
        for n0 in (0..=u32::MAX).step_by(LANES) {
            // Lane `l` holds one of `n0..n0 + 8`, rotated by `n0`, so every `n` meets every
            // lane.
            let lanes: [i32; LANES] =
                core::array::from_fn(|l| (n0 + ((l as u32 + n0 / 8) & 7)) as i32);
            let got = to_i32s(div65280(indices(lanes)));
            let want = lanes.map(|n| (n as u32 / 65280) as i32);
            assert_eq!(got, want, "{lanes:?}");
        }
    }

    /// `⌊(q + 1)·RECIP255/2^32⌋ = ⌊q/255⌋` for every `q < 2^24` (the quotient `int_sums`
    /// forms; `black_box` keeps the compiler from folding the comparison).
    #[test]
    fn quotient_by_255_is_exact_below_2_24() {
        let m = u64::from(core::hint::black_box(RECIP255));
        for q in 0u64..1 << 24 {
            assert_eq!(((q + 1) * m) >> 32, q / 255, "q = {q}");
        }
    }

    /// `quantize8` is `⌊256·p + ½⌋` for every `f32` `p` in `[0, 2^14)` (`IntPos::quantize`'s
    /// `⌊x·2^8 + ½⌋`, which it computes in `f64`), in every lane.
    #[test]
    fn quantization_rounds_half_up_for_every_f32_below_2_14() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { quantize8_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn quantize8_check() {
        let end = 16_384f32.to_bits();
        for b0 in (0..end).step_by(LANES) {
            let lanes: [f32; LANES] = core::array::from_fn(|l| {
                f32::from_bits((b0 + ((l as u32 + b0 / 8) & 7)).min(end - 1))
            });
            let got = to_i32s(quantize8(super::lanes(lanes)));
            let want = lanes.map(|p| libm::floor(f64::from(p) * 256.0 + 0.5) as i32);
            assert_eq!(got, want, "{lanes:?}");
        }
    }

    /// `int_sums` is `IntMode::combine` of `OpacityWeighted` at `F = 8`, bit for bit: the
    /// widest sums (all bytes 255, and opaque taps of mixed colors), the extreme fractions
    /// (0, 1, 127, 128, 254, 255 on each axis), and random taps and fractions; with the taps
    /// packed into pairs along x and along y ([`int_pair`]).
    #[test]
    fn integer_sums_are_the_portable_kernel() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { int_sums_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn int_sums_check() {
        use crate::fixed_point::{IntMode, IntWeights};
        let mut next = xorshift(0x2545_F491_4F6C_DD1D);
        let edges = [0u32, 1, 127, 128, 254, 255];
        for case in 0..6000 {
            // Eight lanes of taps (tap `k` of lane `l`) and fractions.
            let taps: [[StraightU8; 8]; LANES] = core::array::from_fn(|_| {
                core::array::from_fn(|_| {
                    let r = next().to_le_bytes();
                    match case % 3 {
                        0 => StraightU8([255; 4]),
                        1 => StraightU8([r[0], r[1], r[2], 255]),
                        _ => StraightU8([r[0], r[1], r[2], r[3]]),
                    }
                })
            });
            let frac: [[u32; 3]; LANES] = core::array::from_fn(|l| {
                core::array::from_fn(|k| {
                    if case < 216 * 8 {
                        let e = case / 8 + l;
                        let pick = [e % 6, (e / 6) % 6, (e / 36) % 6];
                        edges
                            .get(pick.get(k).copied().unwrap_or(0))
                            .copied()
                            .unwrap_or(0)
                    } else {
                        (next() & 0xff) as u32
                    }
                })
            });
            let word = |k: usize| {
                indices(core::array::from_fn(|l| {
                    let t = taps.get(l).and_then(|t| t.get(k)).copied();
                    i32::from_le_bytes(t.unwrap_or(StraightU8([0; 4])).0)
                }))
            };
            let f = |k: usize| {
                indices(core::array::from_fn(|l| {
                    frac.get(l).and_then(|f| f.get(k)).copied().unwrap_or(0) as i32
                }))
            };
            // Pairs along x (taps `2j`, `2j + 1`), and along y (taps `b`, `b + 2`, with the
            // fractions of y and x swapped), as the kernel forms them.
            let along_x = int_sums(
                |j| int_pair(word(2 * j), word(2 * j + 1)),
                [f(0), f(1), f(2)],
            );
            let base = |j: usize| (j & 1) | ((j >> 1) << 2);
            let along_y = int_sums(
                |j| int_pair(word(base(j)), word(base(j) + 2)),
                [f(1), f(0), f(2)],
            );
            for (first, got) in [("x", along_x), ("y", along_y)] {
                let got = got.map(|v| to_i32s(_mm256_castps_si256(v)));
                for l in 0..LANES {
                    let (Some(t), Some(&fr)) = (taps.get(l), frac.get(l)) else {
                        continue;
                    };
                    let want =
                        crate::OpacityWeighted.combine(t, &IntWeights::trilinear_frac::<8>(fr));
                    let [r, g, b, a] = got.map(|c| c.get(l).copied().unwrap_or(-1));
                    assert_eq!(
                        ([r, g, b], a),
                        (want.c().map(i32::from), i32::from(want.a())),
                        "pairs along {first}, case {case}, lane {l}: {t:?} {fr:?}"
                    );
                }
            }
        }
    }

    /// `unorm8` of every byte, in each lane, is the table's correctly rounded `n/255`.
    #[test]
    fn byte_conversion_is_the_correctly_rounded_quotient() {
        let Some(_cpu) = Avx2::detect() else {
            return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
        };
        // SAFETY: `detect` found AVX2 and FMA on this CPU.
        unsafe { unorm8_check() }
    }

    #[target_feature(enable = "avx2,fma")]
    fn unorm8_check() {
        for n in 0..=255 {
            let lanes: [i32; LANES] = core::array::from_fn(|l| (n + 37 * l as i32) & 0xff);
            let got = array(unorm8(indices(lanes)));
            for (g, b) in got.into_iter().zip(lanes) {
                let want = crate::voxel::unorm8(b as u8);
                assert_eq!(g.to_bits(), want.to_bits(), "byte {b}: {g} against {want}");
            }
        }
    }
}
