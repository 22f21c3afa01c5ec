//! The AVX2 + FMA instance: the [`Avx2`] token and its entry ([`Avx2::run`], which compiles
//! the portable kernels inlined into it for AVX2), and eight rays in the eight `f32` lanes of
//! AVX2 vectors: the packet kernel of
//! [`RayMarcher::cast_rays`](crate::RayMarcher::cast_rays) for `OpacityWeighted`, `Separate`
//! and `ExtinctionWeightedU8` trilinear (`WeightedSum`) sampling of straight RGBA8 voxels
//! (the first two also of 16-byte [`StraightF32`] voxels), and `ExtinctionWeighted` of
//! [`ExtinctionF32`] voxels, front to back, with the marcher's
//! opacity correction ([`Kind::Corr`]) and each lane over its ray's occupied samples where
//! it skips empty space; and, in `i32` lanes, that of
//! [`IntRayMarcher::cast_rays`](crate::render::IntRayMarcher::cast_rays) for the integer
//! `OpacityWeighted` trilinear pipeline at `F = 8` ([`IntOw`], [`int_sums`]).
//!
//! Compiled into every x86-64 build; entered only with an [`Avx2`] token, which only
//! [`Avx2::detect`] makes (CPUID: AVX2, FMA, and the OS saving the 256-bit registers; every
//! AVX2 CPU of Intel and AMD has FMA). Elsewhere `cast_rays` keeps its portable four-ray
//! packets (the integer one casts one ray at a time). Inside the
//! `#[target_feature(enable = "avx2,fma")]` functions the value intrinsics of `core::arch`
//! are safe functions; the entries ([`Avx2::run`], [`march8`], [`march_one`]) call them in an
//! `unsafe` block whose proof is the token, and the kernel calls the methods of [`Kind`]
//! (`unsafe fn`s compiled for AVX2 and FMA, as the kernel is) in blocks whose proof is the
//! same. Five more kinds of `unsafe` block, each with its proof: the bit casts between an integer vector and `[i32; 8]` (`to_i32s`, `from_i32s`),
//! the unchecked voxel loads of [`Taps::load`], taken only after one vector test per read
//! has shown all 64 tap indices inside the data (eight scalar loads per tap; a gather
//! instruction was slower on the machine measured), those of [`Taps::load_f32x4`] (16-byte
//! `ExtinctionF32` voxels, after the same test), and the unchecked 8-byte loads of
//! [`Taps::load_pair`].
//!
//! **Pair reads**: each lane's taps `k` and `k + 1` are neighbours in memory, or one voxel
//! where the lane's x is clamped at an edge of the grid; for [`StraightU8`] voxels one
//! 8-byte load reads both (four such loads and two shuffles make two taps' vectors, for
//! sixteen 4-byte loads and inserts, and a blend puts tap `k`'s word in the lanes where the
//! two are one voxel); the test is a dozen vector operations per read. Faces across y or z
//! are two such pairs; faces across x (x-major parallel rays) none. In a probe this took
//! perspective packets from 8.4–11.0 to 7.4–7.6 ns/sample. Taking the clamped lanes too (a
//! packet with a lane at an x edge had read each tap's voxels alone: a fifth of the steps of
//! the bench's perspective view of 32³) saved 1.6 % of that view's kernel instructions.
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
//! `tests/fast_paths_avx2.rs` compares `cast_rays` in every instruction set the CPU has with the
//! baseline `cast`, bit for bit.
//!
//! **The integer pipeline** ([`IntOw`]) is bit-identical to
//! [`IntRayMarcher::cast`](crate::render::IntRayMarcher::cast) the same way: the
//! positions are the float marcher's, each clamped into `[0, n − 1]` and quantized with
//! round half up to 8 fractional bits (exactly, in `f32`, for volumes up to `2^14` voxels
//! per axis: [`quantize8`]); the taps' bytes stay integers, two neighbours' packed into
//! 16-bit halves as `α·C − 2^15` and `α` ([`int_pair`], kept so by the reuse); [`int_sums`]
//! forms `OpacityWeighted`'s exact sums axis by axis, the first by `vpmaddwd`, the second in
//! `u32` lanes and the last in 16-bit halves by `vpmaddwd` again (the widths are in its doc),
//! and rounds them as the portable kernel does;
//! compositing is `fixed_point::front_to_back` on an accumulator of two channels a lane in
//! 16-bit halves ([`over_u16`]: `⌊(T·x + ONE/2)/ONE⌋` by `u16` products), and a lane stops
//! once `A ≥ A_stop`. Unit tests here check `int_sums` against `IntMode::combine`,
//! `over_u16` for every pair of U8.8 values and `quantize8` for every `f32` it takes;
//! `tests/fast_paths.rs` compares `cast_rays` with `cast`. In a probe (the
//! bench's 256³ volume and coherent rays) the first version took 5.1–5.2 ns/sample, against
//! 18.5 for the integer `cast` and 4.5 for the float packets; computing each lerp as
//! `(256 − f)·a + f·b` (two products, one sum, where `256·a + f·(b − a)` took four
//! operations), the quantization by a truncation, and the last axis's color sums in 64-bit
//! lanes (16 operations per color where a split into two 32-bit lerps took 19) brought it to
//! 4.64–4.67; the whole sample's arithmetic costs about 1.5 ns/sample of it (a probe that
//! skipped it ran at 3.2). The quantization by one fused multiply-add took it to 4.62, the
//! first axis by `vpmaddwd` to 4.40 (0.96 of the float packets). The last axis by
//! `vpmaddwd` and the compositing in 16-bit halves took the step loop from 296 instructions
//! to 267 (callgrind), and the packets from 1.00 to 0.93–0.94 of the float packets' time (a
//! probe running the old and the new kernel and the float one in turn in one process).
//!
//! **Reuse and prefetch for parallel rays** (the same values, so the same results): where
//! the eight rays have one direction (an orthographic view), their lanes move from cell to
//! cell together, and the taps' channels are kept between steps. When every lane is still in
//! the cell of the last step (at step 0.5 a ray stays in a cell for about two samples) nothing
//! is read or converted; when every lane has moved on by one cell along the packet's major
//! axis (that of the direction's largest component), the four taps of the cell's far face
//! become the near face and only the new far face is read. Each step also prefetches the tap
//! rows of the sample [`PREFETCH_STEPS`] steps ahead (along y or z the two on the near side
//! of the major axis, whose far rows are near rows a cell further on; along x all four),
//! every cache line from lane 0's first tap to lane 7's second: without it, the reads that
//! remain (behind the reuse's branches) wait on memory; a prefetch never faults, so its
//! address needs no bounds check. On the 256³ bench this took the packets from 7.4 to about
//! 5.15 ns/sample (with all four rows, four steps ahead; two rows six steps ahead took a probe
//! from 4.87–4.89 to 4.51–4.52). Lanes 0 and 7 alone (one or two lines of RGBA8 voxels)
//! leave the middle lines of a row of 16-byte voxels (three or four lines) unfetched: on an
//! Intel Xeon the 16-byte extinction packets then took 1.66–1.88 times the RGBA8
//! `OpacityWeighted` packets' time, 1.05–1.25 with every line.
//! Rays of different directions (a perspective view) leave their cells at different steps;
//! there the reuse cost a quarter more time in a probe (10.4 against 8.3 ns/sample), so such
//! packets read and convert every tap at every step.

use core::arch::x86_64::*;
use core::ops::Range;

use crate::composite::{front_to_back, front_to_back_in};
use crate::each::Each;
use crate::filter::trilinear_weights;
use crate::fixed_point::{front_to_back as int_front_to_back, IntSample};
use crate::mode::{weighted_sums, Weighting};
use crate::ray::Ray;
use crate::sample::Sample;
use crate::volume::Volume;
use crate::voxel::{ExtinctionF32, StraightF32, StraightU8, Voxel};

mod kernel;
mod kind;
mod lanes;
mod reads;
mod sums;
mod taps;
#[cfg(test)]
mod tests;

use kernel::*;
pub(crate) use kind::{IntOw, Kind};
use lanes::*;
pub use reads::ReadTaps;
pub(crate) use reads::Taus;
use sums::*;
use taps::*;

/// Proof that this CPU runs AVX2 and FMA instructions: made only by [`detect`](Self::detect).
/// It also says whether the CPU's gather instructions are fast ([`gathers`](Self::gathers)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Avx2 {
    gathers: bool,
}

impl Avx2 {
    /// The token, where CPUID says the CPU has AVX2 and FMA and the operating system saves
    /// the AVX registers (XCR0 bits 1 and 2, read with XGETBV where CPUID says the OS enabled
    /// it, OSXSAVE).
    pub(crate) fn detect() -> Option<Self> {
        // Miri cannot run CPUID (inline assembly) or XGETBV: there the answer is the target
        // features the crate is compiled with, as `std::is_x86_feature_detected!` answers
        // under Miri (so "no AVX2" unless the run enables `avx2` and `fma`).
        if cfg!(miri) {
            return (cfg!(target_feature = "avx2") && cfg!(target_feature = "fma"))
                .then_some(Avx2 { gathers: false });
        }
        // Leaf 1, ECX: bit 12 FMA, bit 27 OSXSAVE, bit 28 AVX; leaf 7 sub-leaf 0, EBX: bit 5
        // AVX2 (Intel SDM vol. 2A, CPUID; AMD APM vol. 3, appendix E).
        let leaf0 = __cpuid(0);
        if leaf0.eax < 7 {
            return None;
        }
        let leaf1 = __cpuid(1);
        let ecx = leaf1.ecx;
        let bit = |r: u32, b: u32| r & (1 << b) != 0;
        if !(bit(ecx, 12) && bit(ecx, 27) && bit(ecx, 28)) {
            return None;
        }
        // SAFETY: XGETBV needs the OS to have set CR4.OSXSAVE, which CPUID.1:ECX.OSXSAVE
        // (bit 27, tested above) reports.
        let xcr0 = unsafe { xcr0() };
        let ebx = __cpuid_count(7, 0).ebx;
        (xcr0 & 0b110 == 0b110 && bit(ebx, 5)).then_some(Avx2 {
            gathers: fast_gathers(leaf0, leaf1),
        })
    }

    /// Whether the kernels look up eight table entries by one gather instruction rather than
    /// by eight scalar loads ([`fast_gathers`]). Only speed depends on it, never a result
    /// (`Taus` in `kind`).
    #[inline(always)]
    pub(crate) fn gathers(self) -> bool {
        self.gathers
    }

    /// Runs `f` inside a function compiled for AVX2 and FMA, into which `f` and the
    /// `#[inline(always)]` code it calls are inlined.
    #[inline(always)]
    pub(crate) fn run<R>(self, f: impl FnOnce() -> R) -> R {
        // SAFETY: `self` exists only where `detect` found AVX2 and FMA on this CPU.
        unsafe { run_avx2(f) }
    }
}

/// Whether this CPU's gathers are fast (a few micro-operations), from CPUID leaves 0 (the
/// vendor string in EBX, EDX, ECX) and 1 (EAX: family and model): an Intel CPU that is not
/// one of the models affected by Gather Data Sampling.
///
/// Measured on this project's machines: on an Intel Xeon (family 6, model 207) the gather
/// was the faster way, on an AMD EPYC (Zen 3) the scalar loads (an AMD Zen 3 gather is 39
/// micro-operations by uops.info's measurements). Inferred, not measured here: the models
/// that Linux lists as affected by Gather Data Sampling (`cpu_vuln_blacklist`, `GDS`:
/// Skylake, Kaby Lake, Coffee Lake, Ice Lake, Comet Lake, Tiger Lake, Rocket Lake) run gathers
/// far slower under the microcode that mitigates it, so they take the scalar loads; so does
/// every other vendor's CPU, the way that no CPU runs badly.
fn fast_gathers(leaf0: CpuidResult, leaf1: CpuidResult) -> bool {
    let intel = [leaf0.ebx, leaf0.edx, leaf0.ecx] == [0x756e_6547, 0x4965_6e69, 0x6c65_746e];
    // Family 6: the model is EAX bits 4–7 with the extended model (bits 16–19) above them.
    let family = (leaf1.eax >> 8) & 0xf;
    let model = ((leaf1.eax >> 4) & 0xf) | (((leaf1.eax >> 16) & 0xf) << 4);
    /// Skylake (0x4E, 0x55, 0x5E), Kaby and Coffee Lake (0x8E, 0x9E), Ice Lake (0x6A, 0x6C,
    /// 0x7E), Comet Lake (0xA5, 0xA6), Tiger Lake (0x8C, 0x8D), Rocket Lake (0xA7).
    const GDS: [u32; 13] = [
        0x4E, 0x55, 0x5E, 0x8E, 0x9E, 0x6A, 0x6C, 0x7E, 0xA5, 0xA6, 0x8C, 0x8D, 0xA7,
    ];
    intel && family == 6 && !GDS.contains(&model)
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

/// How many steps ahead each step prefetches the voxels (from lane 0 to lane 7: in a packet of a
/// row of pixels the others lie between them).
const PREFETCH_STEPS: f32 = 6.0;

/// Rays per packet.
pub(crate) const LANES: usize = 8;

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

/// The samples the kernel marches ([`march8`], [`march_one`]): lane `l` over
/// `t₀ + j·d` for `first ≤ j < end`, with `(t₀, end) = ranges[l]` (with `ONE`, every lane the
/// one ray's). `total` is the ray's number of samples, which `march_one` reports where the
/// ray does not stop early.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Samples {
    pub(crate) ranges: [(f32, u32); LANES],
    pub(crate) first: u32,
    pub(crate) total: u32,
}

impl Samples {
    /// One ray's samples `window` of its `(t₀, n)` range.
    #[inline(always)]
    pub(crate) fn window((t0, n): (f32, u32), window: Range<u32>) -> Self {
        Self {
            ranges: [(t0, window.end.min(n)); LANES],
            first: window.start,
            total: n,
        }
    }

    /// Eight rays' samples, each ray's `(t₀, n)` by `range` and the part of it holding every
    /// sample that is not empty by `occupied` (`0..n` without skipping): every lane from
    /// the first such sample of any lane on, to its own last.
    #[inline(always)]
    pub(crate) fn packet(
        rays: &[Ray; LANES],
        range: impl Fn(&Ray) -> (f32, u32),
        occupied: impl Fn(&Ray, (f32, u32)) -> Range<u32>,
    ) -> Self {
        let mut first = u32::MAX;
        let ranges = rays.each_ref().each(|r| {
            let (t0, n) = range(r);
            let w = occupied(r, (t0, n));
            if w.start < w.end {
                first = first.min(w.start);
                (t0, w.end.min(n))
            } else {
                (t0, 0)
            }
        });
        Self {
            ranges,
            first: if first == u32::MAX { 0 } else { first },
            total: 0,
        }
    }
}

/// What the kernel does with each sample after its sums: the step `d` it finishes it for,
/// the opacity correction `corr` ([`Kind::Corr`]), the stop level `a_stop` (`A ≥ a_stop` ends
/// a lane) and the `τ` of every opacity byte (`ExtinctionWeightedU8`; the others ignore it).
#[derive(Clone, Copy)]
pub(crate) struct Stage<'t, C> {
    pub(crate) d: f32,
    pub(crate) a_stop: f32,
    pub(crate) taus: &'t [f32; 256],
    pub(crate) corr: C,
}

/// Marches eight rays front to back, lane `l` over its `samples` ([`Samples`]), stopping a
/// lane once its `A ≥ a_stop`: the accumulated samples before the background,
/// bit-identical to the one-ray march of the kind `K` ([`Kind`]) where every sample left
/// out is transparent: the float modes `OpacityWeighted`, `Separate`,
/// `ExtinctionWeightedU8` (with the `τ` of every opacity byte in `taus`, which the others
/// ignore) and `ExtinctionWeighted`, where `V` must be the mode's `LaneMode::Voxel`
/// ([`StraightU8`], or [`StraightF32`] for their `OverF32` kinds; for `ExtinctionWeighted`,
/// [`ExtinctionF32`]: others read as transparent)
/// and `vol` must [`fits`]; or [`IntOw`], the integer `OpacityWeighted` trilinear march at
/// `F = 8` of `IntRayMarcher::cast`, where `V` must be [`StraightU8`], `vol` must
/// [`fits_int`] and `a_stop` is the U8.8 stop level: the positions `Ray::at` computes, each
/// clamped into `[0, n − 1]` per axis and quantized (**round half up** to 8 fractional bits,
/// `IntPos::quantize`), sampled by [`int_sums`] (`IntMode::combine`, bit for bit) and
/// composited by `fixed_point::front_to_back` until `A ≥ a_stop` before a sample.
pub(crate) fn march8<V: Voxel, K: Kind>(
    cpu: Avx2,
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    samples: &Samples,
    stage: Stage<'_, K::Corr>,
) -> [K::Out; LANES] {
    // SAFETY: `march8_any` needs a CPU with AVX2 and FMA; `cpu` exists only where
    // `Avx2::detect` found them on this CPU.
    let [r, g, b, a] = unsafe { march8_any::<V, K>(cpu, vol, rays, samples, stage) };
    let mut out = [K::out([0; 4]); LANES];
    for ((((o, r), g), b), a) in out.iter_mut().zip(r).zip(g).zip(b).zip(a) {
        *o = K::out([r, g, b, a]);
    }
    out
}

/// One ray front to back over its `samples` ([`Samples::window`]), eight consecutive samples
/// at a time in the lanes, composited in order until `A ≥ a_stop` (as the kind's one-ray
/// march stops): the accumulated sample before the background and the number of samples
/// composited (the ray's `total` where it does not stop early), bit-identical to the
/// one-ray march (`cast_counted`) of the kind `K` where the samples left out are
/// transparent, as [`march8`] (whose requirements on `V`, `vol` and `a_stop` hold here too).
pub(crate) fn march_one<V: Voxel, K: Kind>(
    cpu: Avx2,
    vol: &Volume<'_, V>,
    ray: &Ray,
    samples: &Samples,
    stage: Stage<'_, K::Corr>,
) -> (K::Out, u32) {
    let rays = [*ray; LANES];
    // SAFETY: as in `march8`.
    let out = unsafe { march8_avx2::<V, K, 2, false, true>(cpu, vol, &rays, samples, stage) };
    let [[r, n, ..], [g, ..], [b, ..], [a, ..]] = out;
    (K::out([r, g, b, a]), n as u32)
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
fn march8_any<V: Voxel, K: Kind>(
    cpu: Avx2,
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    samples: &Samples,
    stage: Stage<'_, K::Corr>,
) -> [[i32; LANES]; 4] {
    let [r0, ..] = rays;
    if rays.iter().any(|r| r.dir() != r0.dir()) {
        march8_avx2::<V, K, 2, false, false>(cpu, vol, rays, samples, stage)
    } else {
        match major_axis(r0.dir()) {
            0 => march8_avx2::<V, K, 0, true, false>(cpu, vol, rays, samples, stage),
            1 => march8_avx2::<V, K, 1, true, false>(cpu, vol, rays, samples, stage),
            _ => march8_avx2::<V, K, 2, true, false>(cpu, vol, rays, samples, stage),
        }
    }
}

/// The axis of `dir`'s largest component (by magnitude; the last of equals).
fn major_axis(dir: [f32; 3]) -> usize {
    let [x, y, z] = dir.each(f32::abs);
    if x > y && x > z {
        0
    } else if y > z {
        1
    } else {
        2
    }
}
