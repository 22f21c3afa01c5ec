//! Integer (fixed-point) sampling and compositing: the bit-exact golden model for FPU-less
//! firmware and hardware datapaths.
//!
//! # Formats
//!
//! | quantity | format | meaning |
//! |---|---|---|
//! | voxel | [`StraightU8`](crate::StraightU8) / [`AssociatedU8`](crate::AssociatedU8) | byte `n` is `n/255` |
//! | sample position | [`IntPos<F>`]: `u32` per axis, `F` fractional bits | `raw/2^F` voxel units |
//! | trilinear weight | `u64`, exact product `(2^F − f)·…·f`, `3F` bits | weights sum to `2^(3F)` exactly |
//! | sample, accumulator | [`IntSample`]: `u16` per channel, U8.8 | `raw/256` u8 levels; opacity 1 is [`ONE`] `= 255·256` |
//! | extinction voxel | [`ExtinctionFx`]: `u32` U7.20 per field | optical depth per `d′`, `D = τ·d′ ≤ 64`, and `D·C` |
//! | step ratio `d/d′` | [`IntRatio`]: `u64`, 32 fractional bits | `raw/2^32` |
//! | `φ`, `e^(−x)` tables | [`ExtinctionTables<N>`]: `u32`, 31 fractional bits | see [`exp_phi`] |
//!
//! A U8.8 value is a u8 level with 8 more fractional bits, so a voxel byte `n` is the
//! sample value `256·n` exactly, the output byte is `⌊raw/256 + ½⌋`, and the extra bits keep
//! opacity-weighted colors of faint samples that an 8-bit associated store would lose
//! (Wittenbrink §7, see [`premul`]).
//!
//! # Rounding (named, and the same in the kernels, the f64 models and the docs)
//!
//! * **round half up** — `⌊x + ½⌋`, the paper's `Int(C·(N−1) + 0.5)`: [`round_half_up_div`],
//!   [`round_half_up_shift`]. Every kernel output is produced by exactly one such rounding of an
//!   exact integer quotient, unless its doc says otherwise.
//! * **truncate** — `⌊x⌋`: [`truncate_shift`] (table indices of the extinction path).
//! * **saturate** — clamp to the largest value of the format: [`saturate_u16`]
//!   (only where an input outside the documented domain could otherwise overflow).
//!
//! # Error bounds
//!
//! Each kernel states its error against the exact (real-number) result of the same method at
//! the same quantized position, in output LSBs (one LSB is `1/256` of a u8 level, i.e.
//! `1/65280` of full scale). `host-tests` holds these bounds as named constants
//! (`tolerance::integer`) and checks them against an f64 model that mirrors every rounding.
//!
//! # Example
//!
//! ```
//! use volsample::fixed_point::{IntPos, IntSampler, ONE};
//! use volsample::{OpacityWeighted, Separate, StraightU8, Trilinear, Volume};
//! // Wittenbrink fig. 4: an opaque white voxel next to a transparent red one.
//! let voxels = [StraightU8([255, 255, 255, 255]), StraightU8([255, 0, 0, 0])];
//! let vol = Volume::new(&voxels, [2, 1, 1])?;
//! let mid = IntPos::<8>::from_raw([128, 0, 0]); // x = 0.5
//! let ow = IntSampler::new(vol, OpacityWeighted, Trilinear::new()).sample(mid);
//! assert_eq!((ow.c(), ow.a()), ([ONE / 2; 3], ONE / 2)); // white, half opaque
//! let sep = IntSampler::new(vol, Separate, Trilinear::new()).sample(mid);
//! assert_eq!(sep.c(), [ONE / 2, ONE / 4, ONE / 4]); // red bleeds in
//! # Ok::<(), volsample::Error>(())
//! ```
// The integer kernels keep `[T; N]::map` (`core/clippy.toml` asks for `crate::each`): at the
// firmware's `opt-level = "s"` a map here compiles to one loop body, `each` to two (its first
// element apart), which took the Cortex-M4F `min_int` image from 3 128 to 3 208 bytes; and
// their instances are few (one per `F` and mode), so the host's build gains little from it.
#![allow(clippy::disallowed_methods)]

pub mod composite;
pub mod correction;
pub mod exp_phi;
pub mod extinction;
mod lanes8;
pub mod opacity_weighted;
pub mod premul;
pub mod preweighted;
pub mod separate;
pub mod weights;

pub use composite::{composite_front_to_back, front_to_back, IntStop};
pub use correction::IntCorrection;
pub use exp_phi::{ExtinctionTables, IntRatio};
pub use extinction::{ExtinctionFx, IntExtinction};
pub use premul::{premultiply, premultiply_voxel, unpremultiply};
pub use weights::{nearest_index, trilinear_weights, IntWeights};

pub(crate) use lanes8::{IntLaneMode, IntLaneVisitor};

use crate::error::Error;
use crate::filter::{Nearest, Trilinear, WeightedSum};
use crate::sample::Sample;
use crate::volume::Volume;
use crate::voxel::Voxel;

/// Full scale of a U8.8 value: opacity 1 (`255·256 = 65280`).
pub const ONE: u16 = 255 * 256;

/// Smallest supported number of fractional position bits.
pub const MIN_FRAC_BITS: u32 = 4;
/// Largest supported number of fractional position bits (keeps every accumulator below
/// `2^62`, see the module docs of each kernel).
pub const MAX_FRAC_BITS: u32 = 12;
/// The default number of fractional position bits.
pub const DEFAULT_FRAC_BITS: u32 = 8;

/// `⌊sum·256/2^shift + ½⌋`: a weighted sum of u8 levels (weights summing to `2^shift`) as a
/// U8.8 value, **round half up**. Exact for `sum < 2^54`, `shift ≤ 63`.
#[inline(always)]
pub(crate) const fn levels_to_u88(sum: u64, shift: u32) -> u64 {
    round_half_up_shift(sum << 8, shift)
}

/// `⌊sum·256/(255·2^shift) + ½⌋`: a weighted sum of products of two u8 levels as a U8.8
/// value, **round half up**. Exact for `sum < 2^53`, `shift ≤ 36`.
#[inline(always)]
pub(crate) const fn products_to_u88(sum: u64, shift: u32) -> u64 {
    round_half_up_div(sum << 8, 255 << shift)
}

/// Rejects `F` outside [`MIN_FRAC_BITS`]`..=`[`MAX_FRAC_BITS`] at compile time.
macro_rules! check_frac_bits {
    ($f:expr) => {
        const {
            assert!(
                $f >= $crate::fixed_point::MIN_FRAC_BITS
                    && $f <= $crate::fixed_point::MAX_FRAC_BITS,
                "F (fractional position bits) must lie in 4..=12"
            )
        }
    };
}
pub(crate) use check_frac_bits;

/// **Round half up** of an exact quotient: `⌊n/d + ½⌋`, computed as `⌊(2n + d)/(2d)⌋`.
///
/// Exact for `n ≤ 2^62` and `1 ≤ d ≤ 2^62` (every kernel stays within this; see their
/// accumulator proofs). Outside that domain the intermediate **saturates** instead of
/// wrapping, and `d = 0` gives 0: the function never panics.
#[inline(always)]
pub const fn round_half_up_div(n: u64, d: u64) -> u64 {
    let num = n.saturating_mul(2).saturating_add(d);
    match num.checked_div(d.saturating_mul(2)) {
        Some(q) => q,
        None => 0,
    }
}

/// **Round half up** of `n/2^s`: `⌊n/2^s + ½⌋ = (n + 2^(s−1)) >> s` (`n` itself for `s = 0`).
///
/// Exact for `n < 2^63` and `s < 64`; the addition saturates outside that domain
/// and `s ≥ 64` gives 0 (never reached by the kernels).
#[inline(always)]
pub const fn round_half_up_shift(n: u64, s: u32) -> u64 {
    if s == 0 {
        n
    } else if s >= 64 {
        0
    } else {
        n.saturating_add(1 << (s - 1)) >> s
    }
}

/// **Truncate** `n/2^s`: `⌊n/2^s⌋` (0 for `s ≥ 64`).
#[inline(always)]
pub const fn truncate_shift(n: u64, s: u32) -> u64 {
    if s >= 64 {
        0
    } else {
        n >> s
    }
}

/// **Saturate** to `u16`: `min(n, 65535)`.
#[inline(always)]
pub const fn saturate_u16(n: u64) -> u16 {
    if n > u16::MAX as u64 {
        u16::MAX
    } else {
        n as u16
    }
}

/// A sample position in fixed point: per axis a `u32` with `F` fractional bits, so the voxel
/// index is `raw >> F` and the fraction `raw & (2^F − 1)` (in units of `2^−F` voxel).
///
/// Positions are non-negative; reconstruction clamps to the edge like the float kernels.
/// `F` must lie in `4..=12`; any other value is a compile-time error:
///
/// ```compile_fail
/// let _ = volsample::fixed_point::IntPos::<13>::from_raw([0; 3]);
/// ```
/// ```compile_fail
/// let _ = volsample::fixed_point::IntPos::<3>::from_raw([0; 3]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntPos<const F: u32 = DEFAULT_FRAC_BITS> {
    raw: [u32; 3],
}

impl<const F: u32> IntPos<F> {
    /// The position whose coordinates are `raw[k]/2^F` voxel units. Every `u32` is valid.
    #[inline(always)]
    pub const fn from_raw(raw: [u32; 3]) -> Self {
        check_frac_bits!(F);
        Self { raw }
    }

    /// The position at voxel `index` plus `frac/2^F` per axis.
    ///
    /// # Errors
    /// [`Error::InvalidPosition`] if a fraction is `≥ 2^F` or `index·2^F + frac` exceeds `u32`.
    pub fn new(index: [u32; 3], frac: [u32; 3]) -> Result<Self, Error> {
        check_frac_bits!(F);
        let mut raw = [0u32; 3];
        for ((r, &i), &f) in raw.iter_mut().zip(index.iter()).zip(frac.iter()) {
            if f >= 1 << F {
                return Err(Error::InvalidPosition);
            }
            *r = i
                .checked_mul(1 << F)
                .and_then(|v| v.checked_add(f))
                .ok_or(Error::InvalidPosition)?;
        }
        Ok(Self { raw })
    }

    /// Quantizes a float position (voxel units) with **round half up** to `F` fractional
    /// bits: `raw = ⌊x·2^F + ½⌋`.
    ///
    /// Error bound: each coordinate within `2^−(F+1)` voxel of `x`.
    ///
    /// # Errors
    /// [`Error::InvalidPosition`] for NaN, negative coordinates or `x·2^F + ½ ≥ 2^32`.
    pub fn quantize(pos: [f32; 3]) -> Result<Self, Error> {
        check_frac_bits!(F);
        let mut raw = [0u32; 3];
        for (r, &x) in raw.iter_mut().zip(pos.iter()) {
            // f64 holds x·2^F + ½ exactly for every f32 x below 2^32.
            let v = f64::from(x) * f64::from(1u32 << F) + 0.5;
            // `⌊v⌋` lies in `[0, 2^32)` exactly when `v` does (NaN fails), and there the
            // truncating cast is `⌊v⌋`: no call to `floor` on the hot path.
            if !(0.0..4_294_967_296.0).contains(&v) {
                return Err(Error::InvalidPosition);
            }
            *r = v as u32;
        }
        Ok(Self { raw })
    }

    /// The raw coordinates (`F` fractional bits).
    #[inline(always)]
    pub const fn raw(&self) -> [u32; 3] {
        self.raw
    }

    /// The voxel index `raw >> F` per axis.
    #[inline(always)]
    pub const fn index(&self) -> [u32; 3] {
        let [x, y, z] = self.raw;
        [x >> F, y >> F, z >> F]
    }

    /// The fraction `raw mod 2^F` per axis (units of `2^−F` voxel).
    #[inline(always)]
    pub const fn frac(&self) -> [u32; 3] {
        let m = (1u32 << F) - 1;
        let [x, y, z] = self.raw;
        [x & m, y & m, z & m]
    }

    /// The position as `f32` voxel coordinates (exact below `2^(24−F)` voxels).
    pub fn to_f32(&self) -> [f32; 3] {
        let s = 1.0 / (1u32 << F) as f32;
        self.raw.map(|r| r as f32 * s)
    }
}

/// An associated sample (or a composited pixel) in U8.8: each channel a `u16` holding
/// `raw/256` u8 levels, opacity 1 being [`ONE`].
///
/// Invariant, kept by construction: `c[k] ≤ a ≤ ONE`. The kernels build it from their exact
/// sums with the same rounding for `α` and `C̃`, so the invariant follows from monotonicity,
/// never from a final clamp.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntSample {
    c: [u16; 3],
    a: u16,
}

impl IntSample {
    /// Fully transparent black.
    pub const TRANSPARENT: Self = Self { c: [0; 3], a: 0 };

    /// Builds a sample from raw U8.8 values.
    ///
    /// # Errors
    /// [`Error::InvalidIntSample`] unless `c[k] ≤ a ≤ ONE`.
    pub const fn new(c: [u16; 3], a: u16) -> Result<Self, Error> {
        let [r, g, b] = c;
        if a <= ONE && r <= a && g <= a && b <= a {
            Ok(Self { c, a })
        } else {
            Err(Error::InvalidIntSample)
        }
    }

    /// Builds a sample from values the caller has proven valid (`c[k] ≤ a ≤ ONE`).
    #[inline(always)]
    pub(crate) const fn from_valid(c: [u16; 3], a: u16) -> Self {
        Self { c, a }
    }

    /// The sample a u8 associated voxel stands for: each byte `n` becomes `256·n` (exact).
    #[inline(always)]
    pub fn from_associated_u8(v: crate::voxel::AssociatedU8) -> Self {
        let [r, g, b, a] = v.0;
        // `AssociatedU8` is not validated by type; keep the invariant by clamping each
        // channel to α (a no-op for voxels a `Volume` accepted).
        let a16 = u16::from(a) * 256;
        let cl = |x: u8| u16::from(x.min(a)) * 256;
        Self {
            c: [cl(r), cl(g), cl(b)],
            a: a16,
        }
    }

    /// Raw associated color `C̃` (U8.8).
    #[inline(always)]
    pub const fn c(&self) -> [u16; 3] {
        self.c
    }

    /// Raw opacity `α` (U8.8, [`ONE`] = opaque).
    #[inline(always)]
    pub const fn a(&self) -> u16 {
        self.a
    }

    /// The bytes of this sample, each `⌊raw/256 + ½⌋` (**round half up**); `C̃ ≤ α` is kept
    /// because the rounding is monotone. Error bound: ½ u8 level per channel.
    #[inline]
    pub const fn to_u8(&self) -> [u8; 4] {
        let [r, g, b] = self.c;
        [round_u8(r), round_u8(g), round_u8(b), round_u8(self.a)]
    }

    /// The float sample `raw/ONE` per channel (each within ½ ulp of `f32`).
    pub fn to_f32(&self) -> Sample {
        let s = |x: u16| (f64::from(x) / f64::from(ONE)) as f32;
        Sample {
            c: self.c.map(s),
            a: s(self.a),
        }
    }
}

/// `⌊raw/256 + ½⌋` (round half up) of a U8.8 value.
#[inline(always)]
const fn round_u8(x: u16) -> u8 {
    ((x as u32 + 128) >> 8) as u8
}

pub(crate) mod sealed {
    pub trait Sealed {}
}

/// A sampling mode the integer kernels implement over voxels of format `V`.
///
/// Implemented for [`OpacityWeighted`](crate::OpacityWeighted) and
/// [`Separate`](crate::Separate) over [`StraightU8`](crate::StraightU8), and for
/// [`Preweighted`](crate::Preweighted) over [`AssociatedU8`](crate::AssociatedU8): the same
/// zero-sized mode types the float kernels use; and for [`IntExtinction`] over
/// [`ExtinctionFx`]. Sealed.
pub trait IntMode<V: Voxel>: sealed::Sealed + Copy + core::fmt::Debug {
    /// `true` for the modes whose samples hold for the reference distance `d′` and need
    /// [`IntCorrection`] when the step differs; `false` for [`IntExtinction`], which
    /// integrates over the step itself.
    const OPACITY_BASED: bool = true;

    /// Runs `visitor` for the mode's eight-lane kernel, where it has one
    /// ([`OpacityWeighted`](crate::OpacityWeighted) over [`StraightU8`](crate::StraightU8),
    /// the AVX2 packets of [`IntRayMarcher::cast_rays`]): the mode's type picks the kernel.
    /// `Err(visitor)` for the modes without one.
    #[doc(hidden)]
    #[inline(always)]
    fn lanes8<X: IntLaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Err(visitor)
    }

    /// The mode configured for the step ratio `d/d′` (the identity for the opacity-based
    /// modes; [`IntExtinction`] takes the ratio).
    ///
    /// # Errors
    /// [`Error::InvalidStep`] where the mode cannot use the ratio.
    fn for_step_ratio(self, ratio: f32) -> Result<Self, Error> {
        let _ = ratio;
        Ok(self)
    }

    /// Combines `K` taps with integer weights (summing to exactly `2^shift`, `shift ≤ 36`,
    /// guaranteed by [`IntWeights`]) into an associated U8.8 sample.
    fn combine<const K: usize>(&self, taps: &[V; K], w: &IntWeights<K>) -> IntSample;

    /// [`combine`](Self::combine) of the 8 taps of a trilinear cell (tap `i` the corner
    /// `(i & 1, (i >> 1) & 1, i >> 2)`) with the weights of the fractions `frac` (each
    /// `< 2^F`, [`IntWeights::trilinear`]): the same result, bit for bit. A mode may compute
    /// it in another exact order (the default is `combine` itself).
    #[doc(hidden)]
    #[inline(always)]
    fn combine_trilinear<const F: u32>(&self, taps: &[V; 8], frac: [u32; 3]) -> IntSample {
        self.combine(taps, &IntWeights::trilinear_frac::<F>(frac))
    }
}

/// A reconstruction filter the integer kernels implement: [`Nearest`] and
/// [`Trilinear`] (evaluated as a sum of weighted products). Sealed.
pub trait IntFilter: sealed::Sealed + Copy + core::fmt::Debug {
    /// Number of voxels read per sample.
    const TAPS: usize;

    /// Runs `visitor` for the eight-lane kernel (the AVX2 instance of
    /// [`IntRayMarcher`](crate::render::IntRayMarcher)) of `mode` with this filter, where
    /// there is one: [`Trilinear`] passes it on to the mode ([`IntMode::lanes8`]).
    /// `Err(visitor)` for [`Nearest`].
    #[doc(hidden)]
    #[inline(always)]
    fn lanes8<V: Voxel, M: IntMode<V>, X: IntLaneVisitor>(
        mode: &M,
        visitor: X,
    ) -> Result<X::Out, X> {
        let _ = mode;
        Err(visitor)
    }

    /// Reconstructs an associated sample at `pos`.
    #[inline(always)]
    fn sample<V: Voxel, M: IntMode<V>, const F: u32>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: IntPos<F>,
    ) -> IntSample {
        Self::combine(mode, Self::fetch(vol, pos), pos)
    }

    /// The voxels one sample reads.
    #[doc(hidden)]
    type Taps<V: Voxel>: Copy;

    /// The first half of [`sample`](Self::sample): reads the voxels at `pos` (clamped to the
    /// edge), so that a marcher can read the next sample's voxels before it combines these.
    #[doc(hidden)]
    fn fetch<V: Voxel, const F: u32>(vol: &Volume<'_, V>, pos: IntPos<F>) -> Self::Taps<V>;

    /// The second half of [`sample`](Self::sample): the sample of the voxels `fetch` read.
    #[doc(hidden)]
    fn combine<V: Voxel, M: IntMode<V>, const F: u32>(
        mode: &M,
        taps: Self::Taps<V>,
        pos: IntPos<F>,
    ) -> IntSample;
}

impl sealed::Sealed for Nearest {}
impl sealed::Sealed for Trilinear<WeightedSum> {}

#[inline(always)]
fn to_isize(i: u32) -> isize {
    isize::try_from(i).unwrap_or(isize::MAX)
}

impl IntFilter for Nearest {
    const TAPS: usize = 1;
    type Taps<V: Voxel> = [V; 1];

    #[inline(always)]
    fn fetch<V: Voxel, const F: u32>(vol: &Volume<'_, V>, pos: IntPos<F>) -> [V; 1] {
        let [x, y, z] = pos.raw().map(|r| to_isize(nearest_index::<F>(r)));
        [vol.fetch_clamped(x, y, z)]
    }

    #[inline(always)]
    fn combine<V: Voxel, M: IntMode<V>, const F: u32>(
        mode: &M,
        taps: [V; 1],
        _pos: IntPos<F>,
    ) -> IntSample {
        mode.combine(&taps, &IntWeights::NEAREST)
    }
}

impl IntFilter for Trilinear<WeightedSum> {
    const TAPS: usize = 8;
    type Taps<V: Voxel> = [V; 8];

    #[inline(always)]
    fn lanes8<V: Voxel, M: IntMode<V>, X: IntLaneVisitor>(
        mode: &M,
        visitor: X,
    ) -> Result<X::Out, X> {
        mode.lanes8(visitor)
    }

    #[inline(always)]
    fn fetch<V: Voxel, const F: u32>(vol: &Volume<'_, V>, pos: IntPos<F>) -> [V; 8] {
        // Interior fast path: the whole cell inside the grid, no clamps (same taps).
        let [xi, yi, zi] = pos
            .index()
            .map(|i| usize::try_from(i).unwrap_or(usize::MAX));
        if let Some(taps) = vol.cell(xi, yi, zi) {
            return taps;
        }
        let [x, y, z] = pos.index().map(to_isize);
        vol.cell_clamped(x, y, z)
    }

    #[inline(always)]
    fn combine<V: Voxel, M: IntMode<V>, const F: u32>(
        mode: &M,
        taps: [V; 8],
        pos: IntPos<F>,
    ) -> IntSample {
        mode.combine_trilinear::<F>(&taps, pos.frac())
    }
}

/// An integer sampler: a volume, a mode and a filter, all chosen by type, at `F` fractional
/// position bits.
///
/// Error bound: that of the mode's kernel ([`opacity_weighted`], [`separate`],
/// [`preweighted`], [`extinction`]) for the filter's weights at the quantized position.
#[derive(Debug, Clone, Copy)]
pub struct IntSampler<'a, V, M, Fl> {
    vol: Volume<'a, V>,
    mode: M,
    filter: Fl,
}

impl<'a, V: Voxel, M: IntMode<V>, Fl: IntFilter> IntSampler<'a, V, M, Fl> {
    /// A sampler over a validated volume. (The volume's reference distance is not used:
    /// apply [`IntCorrection`] when the step differs from it.)
    pub const fn new(vol: Volume<'a, V>, mode: M, filter: Fl) -> Self {
        Self { vol, mode, filter }
    }

    /// The filter.
    pub const fn filter(&self) -> Fl {
        self.filter
    }

    /// The volume.
    pub const fn volume(&self) -> &Volume<'a, V> {
        &self.vol
    }

    /// The mode.
    pub const fn mode(&self) -> &M {
        &self.mode
    }

    /// Reconstructs the associated sample at `pos` (clamped to the edge).
    #[inline]
    pub fn sample<const F: u32>(&self, pos: IntPos<F>) -> IntSample {
        check_frac_bits!(F);
        Fl::sample(&self.mode, &self.vol, pos)
    }

    /// [`sample`](Self::sample) in two halves (see [`IntFilter::fetch`]).
    #[inline(always)]
    pub(crate) fn fetch<const F: u32>(&self, pos: IntPos<F>) -> Fl::Taps<V> {
        Fl::fetch(&self.vol, pos)
    }

    /// The second half.
    #[inline(always)]
    pub(crate) fn combine<const F: u32>(&self, taps: Fl::Taps<V>, pos: IntPos<F>) -> IntSample {
        Fl::combine(&self.mode, taps, pos)
    }
}
