//! Integer (fixed-point) downsampling: one pyramid level and a whole mipmap chain for `u8`
//! associated, U8.8 and fixed-point extinction voxels, bit-exact and without floats in the
//! kernel.
//!
//! Geometry is that of the float path ([module docs](super)): each axis halves, `n ↦ ⌈n/2⌉`,
//! coarse voxel `j` reads fine voxels `2j − 1 … 2j + 2` clamped to the edge, separably along
//! x, y, z; levels are laid out in a chain buffer by [`level_offset`]
//! and [`level_dims`].
//!
//! # The integer filter: [`IntFilter4`]
//!
//! The taps are Q0.16 integers `(a_q, b_q, b_q, a_q)`: `a_q = ⌊2^16·a + ½⌋` (**round half up**,
//! computed once, when the filter is made), `b_q = 2^15 − a_q` **exactly**, so the four taps
//! sum to `2^16` and the 64 products of a level to `2^48`. `a = 0, ⅛, ¼` are exact
//! (`a_q = 0, 8192, 16384`); `a = ⅕` becomes `13107/65536` (`a − a_q = 0.2/65536`).
//!
//! # Arithmetic (every rounding named)
//!
//! 1. **Exact sums.** Per channel `S = Σ w_i w_j w_k·v` over the 64 clamped taps, evaluated
//!    separably in `u128` without rounding, in units of `2^−48` raw input units. Bound: a
//!    channel is at most `2^26` (U7.20 at [`MAX_DEPTH_RAW`]), so `S ≤ 2^48·2^26 = 2^74`.
//! 2. **[`IntOpacityBased`]** (storage full scale `FULL = 255` for [`AssociatedU8`], [`ONE`]
//!    `= 65280` for U8.8 [`IntSample`]):
//!    * filtered values with 8 guard bits: `ᾱ_g = ⌊S_α/2^40 + ½⌋`, `C̄_g = ⌊S_c/2^40 + ½⌋`
//!      (**round half up**; `≤ 256·FULL < 2^24`);
//!    * the doubled-distance correction `α′ = ᾱ(2 − ᾱ)`, `C̃′ = C̄(2 − ᾱ)` with
//!      `G = 2·256·FULL − ᾱ_g`: `α′ = ⌊ᾱ_g·G/(2^16·FULL) + ½⌋`,
//!      `C̃′ = ⌊C̄_g·G/(2^16·FULL) + ½⌋` (**round half up** of exact quotients; numerators
//!      `< 2^49`, `u64`).
//!
//!    `C̃′ ≤ α′` by construction: each input channel is clamped to its `α` on read (a no-op
//!    for valid voxels), so `S_c ≤ S_α`, `C̄_g ≤ ᾱ_g`, and the roundings are monotone.
//!    `α′ ≤ FULL` because `ᾱ(2 − ᾱ) ≤ 1`. A constant volume `v` gives the constant
//!    `⌊v(2·FULL − v)/FULL + ½⌋` (the sums are exact, so `ᾱ_g = 256·v`).
//! 3. **[`IntExtinctionBased`]** ([`ExtinctionFx`], U7.20 `D = τ·d′` and `D·C`): the coarse
//!    voxel's doubled length folds into the shift: `D′ = min(⌊S_τ/2^47 + ½⌋, MAX_DEPTH_RAW)`
//!    and `(D·C)′ = min(⌊S_c/2^47 + ½⌋, MAX_DEPTH_RAW)` (**round half up**, then
//!    **saturate** at [`MAX_DEPTH_RAW`] `= 64·2^20`, the format's cap). `(D·C)′ ≤ D′` by
//!    construction (`S_c ≤ S_τ`, monotone rounding and the same cap). Each level is in its own
//!    voxel units with the same `d′` (in level voxels), exactly like the float
//!    [`ExtinctionBased`](super::ExtinctionBased): sample a level with
//!    [`IntExtinction`](crate::fixed_point::IntExtinction) at `r = d_level/d′`.
//!
//! # Error bounds
//!
//! Against the exact (real-number) result of the same method with the same quantised taps on
//! the same stored input, per level, in storage LSBs:
//! * opacity-based: `α′` and each `C̃′` within `½ + 2^−8`: the final rounding, plus the guard
//!   rounding (`2^−9` LSB) through the correction, whose slope in `ᾱ` and `C̄` is at most 2
//!   (`|∂α′| ≤ 2|∂ᾱ|`, `|∂C̃′| ≤ (2 − ᾱ)|∂C̄| + C̄|∂ᾱ| ≤ 2·max` as `C̄ ≤ ᾱ`);
//! * extinction-based: `D′` and each `(D·C)′` within ½ (one rounding), until saturation.
//!
//! Against the float method with the unquantised `a` add the tap error: a 1D pass changes by
//! `|a − a_q|·|(v₋₁ + v₂) − (v₀ + v₁)| ≤ 2|a − a_q|·V` (`V` the channel's largest input), three
//! passes `6|a − a_q|·V`, doubled by the opacity correction or the extinction doubling:
//! `12|a − a_q|·V` (0 for `a = 0, ⅛, ¼`; below `2.4` U8.8 LSB for `a = ⅕`). Over a chain the
//! level errors compound with the slope 2: level `ℓ` within `(2^ℓ − 1)` times the per-level
//! bound (with `V` taken at the largest level). `host-tests` holds these bounds
//! (`tolerance::downsample`) and an `f64`/exact-integer model of every rounding
//! (`int_model::downsample`).
//!
//! # Example
//!
//! ```
//! use volsample::downsample::integer::{build_chain_int, IntFilter4, IntOpacityBased};
//! use volsample::downsample::{chain_len, level_offset};
//! use volsample::AssociatedU8;
//! // A constant 4×4×4 volume: every level is the doubled-distance correction of the one before.
//! let base = [AssociatedU8([40, 20, 0, 128]); 64];
//! let mut out = [AssociatedU8::default(); chain_len([4, 4, 4])];
//! let levels = build_chain_int(IntOpacityBased, IntFilter4::quadratic(), &base, [4, 4, 4], &mut out)?;
//! assert_eq!(levels, 3);
//! // α: 128·(510 − 128)/255 = 191.75 → 192 (1 − (1 − α)² = 0.752); C̃: 40·382/255 = 59.92 → 60.
//! assert!(out[..8].iter().all(|v| *v == AssociatedU8([60, 30, 0, 192])));
//! assert_eq!(out[level_offset([4, 4, 4], 2)], AssociatedU8([75, 37, 0, 239]));
//! # Ok::<(), volsample::Error>(())
//! ```

use super::{chain_len, level_count, level_dims, level_offset, sealed, voxel_count, Filter4};
use crate::each::Each;
use crate::error::Error;
use crate::fixed_point::extinction::{ExtinctionFx, MAX_DEPTH_RAW};
use crate::fixed_point::{round_half_up_div, IntSample, ONE};
use crate::volume::MAX_DIM;
use crate::voxel::AssociatedU8;

/// Fractional bits of a tap of [`IntFilter4`] (Q0.16).
pub const TAP_FRAC_BITS: u32 = 16;
/// `½` in Q0.16: `a_q + b_q`.
const HALF: u32 = 1 << (TAP_FRAC_BITS - 1);
/// Fractional bits of the exact 3D sums: three passes of Q0.16 taps.
pub const SUM_FRAC_BITS: u32 = 3 * TAP_FRAC_BITS;
/// Guard bits the opacity-based path keeps on the filtered `ᾱ`, `C̄` before the correction.
pub const GUARD_BITS: u32 = 8;

/// **Round half up** of `n/2^s` in `u128`, `s ≥ 1`: `⌊(⌊n/2^(s−1)⌋ + 1)/2⌋`, which equals
/// `⌊n/2^s + ½⌋` for every `n` and cannot overflow. (`s = 0` gives `n`; `s ≥ 128` gives 0.)
#[inline(always)]
const fn round_half_up_shift_u128(n: u128, s: u32) -> u128 {
    if s == 0 {
        n
    } else if s >= 128 {
        0
    } else {
        ((n >> (s - 1)) + 1) >> 1
    }
}

/// The integer 4-tap filter `(a_q, b_q, b_q, a_q)` in Q0.16, `a_q + b_q = 2^15` exactly (see
/// the [module docs](self)).
///
/// ```
/// use volsample::downsample::{integer::IntFilter4, Filter4};
/// assert_eq!(IntFilter4::from_filter(Filter4::quadratic()).taps(), [13107, 19661, 19661, 13107]);
/// assert_eq!(IntFilter4::from_filter(Filter4::bspline()), IntFilter4::bspline());
/// assert!(IntFilter4::from_raw(32769).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntFilter4 {
    a: u32,
}

impl IntFilter4 {
    /// The filter with outer tap `a_raw/2^16`.
    ///
    /// # Errors
    /// [`Error::InvalidDownsampleFilter`] unless `a_raw ≤ 2^15` (else `b_q` would be negative).
    pub const fn from_raw(a_raw: u32) -> Result<Self, Error> {
        if a_raw <= HALF {
            Ok(Self { a: a_raw })
        } else {
            Err(Error::InvalidDownsampleFilter)
        }
    }

    /// Quantises a float filter: `a_q = ⌊2^16·a + ½⌋` (**round half up**; exact in `f64`).
    ///
    /// Error bound: `|a − a_q/2^16| ≤ 2^−17`.
    pub fn from_filter(filter: Filter4) -> Self {
        // a ∈ [0, ½] (checked by Filter4): 2^16·a ≤ 2^15 and the sum with ½ are exact in f64.
        let q = libm::floor(f64::from(filter.a()) * f64::from(1u32 << TAP_FRAC_BITS) + 0.5);
        // `as` saturates; q ∈ [0, 2^15] anyway.
        Self {
            a: (q as u32).min(HALF),
        }
    }

    /// The 2-tap box, `a = 0` (exact).
    pub const fn box2() -> Self {
        Self { a: 0 }
    }

    /// The B-spline mask, `a = ⅛` (exact).
    pub const fn bspline() -> Self {
        Self { a: HALF / 4 }
    }

    /// `a = ⅕` quantised: `13107/2^16`.
    pub const fn quadratic() -> Self {
        Self { a: 13107 }
    }

    /// The 4-tap box, `a = ¼` (exact).
    pub const fn box4() -> Self {
        Self { a: HALF / 2 }
    }

    /// `a_q` (Q0.16).
    pub const fn a_raw(&self) -> u32 {
        self.a
    }

    /// `[a_q, b_q, b_q, a_q]` (Q0.16), summing to `2^16`.
    pub const fn taps(&self) -> [u32; 4] {
        let b = HALF - self.a;
        [self.a, b, b, self.a]
    }

    /// The float filter with the same (dyadic, so exactly representable) `a`.
    pub fn to_filter(&self) -> Filter4 {
        let a = self.a as f32 / (1u32 << TAP_FRAC_BITS) as f32;
        // a_q ≤ 2^15, so `a ∈ [0, ½]` and `new` succeeds; the default is never taken.
        Filter4::new(a).unwrap_or_default()
    }

    /// One exact 1D pass: `a_q·(v₋₁ + v₂) + b_q·(v₀ + v₁)` per channel (no rounding).
    /// Inputs below `2^(128−17)` cannot overflow; the kernels stay below `2^74`.
    #[inline(always)]
    fn combine(&self, v: [[u128; 4]; 4]) -> [u128; 4] {
        let a = u128::from(self.a);
        let b = u128::from(HALF - self.a);
        let [v0, v1, v2, v3] = v;
        let mut out = [0u128; 4];
        for ((((o, &x0), &x1), &x2), &x3) in out
            .iter_mut()
            .zip(v0.iter())
            .zip(v1.iter())
            .zip(v2.iter())
            .zip(v3.iter())
        {
            *o = a * (x0 + x3) + b * (x1 + x2);
        }
        out
    }
}

impl Default for IntFilter4 {
    /// The 4-tap box (`a = ¼`), as [`Filter4::default`].
    fn default() -> Self {
        Self::box4()
    }
}

/// What an integer downsampling filter is applied to, and how the exact sums become a coarse
/// voxel of format `V`: [`IntOpacityBased`] (for [`AssociatedU8`] and [`IntSample`]) or
/// [`IntExtinctionBased`] (for [`ExtinctionFx`]). Sealed.
pub trait IntMethod<V: Copy>: sealed::Sealed + Copy + Default + core::fmt::Debug {
    /// The four channels `[c₀, c₁, c₂, α or D]` of a voxel in raw units, each color clamped to
    /// the last channel and that to the format's cap (no-ops for valid voxels).
    fn channels(v: V) -> [u128; 4];

    /// The coarse voxel from the exact sums (units `2^−48` raw, each at most `2^74`).
    fn finish(sums: [u128; 4]) -> V;
}

/// Integer opacity-based downsampling: filter `α` and `C̃`, then correct for the doubled
/// distance, `α′ = ᾱ(2 − ᾱ)`, `C̃′ = C̄(2 − ᾱ)` (see the [module docs](self) for the
/// roundings). Levels keep the input format: [`AssociatedU8`] or U8.8 [`IntSample`].
///
/// Error bound: per level `½ + 2^−8` storage LSB against the exact method with the quantised
/// taps (module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntOpacityBased;

impl sealed::Sealed for IntOpacityBased {}

/// The opacity-based finish for storage full scale `full` (255 or 65280): returns `(C̃′, α′)`.
#[inline(always)]
fn opacity_finish(sums: [u128; 4], full: u64) -> ([u64; 3], u64) {
    let [r, g, b, a] = sums;
    let shift = SUM_FRAC_BITS - GUARD_BITS;
    let full_g = full << GUARD_BITS;
    // S_α ≤ 2^48·full, so ᾱ_g ≤ 2^8·full < 2^24; the `min` only guards the type conversion.
    let to_g = |s: u128| round_half_up_shift_u128(s, shift).min(u128::from(full_g)) as u64;
    let a_g = to_g(a);
    let gain = 2 * full_g - a_g; // in [full_g, 2·full_g]
    let den = full << (2 * GUARD_BITS);
    // ᾱ_g·gain ≤ full_g² < 2^48: exact in `round_half_up_div`.
    let a2 = round_half_up_div(a_g * gain, den);
    let c2 = [r, g, b].each(|c| round_half_up_div(to_g(c).min(a_g) * gain, den));
    (c2, a2)
}

impl IntMethod<AssociatedU8> for IntOpacityBased {
    #[inline(always)]
    fn channels(v: AssociatedU8) -> [u128; 4] {
        let [r, g, b, a] = v.0;
        let c = |x: u8| u128::from(x.min(a));
        [c(r), c(g), c(b), u128::from(a)]
    }

    #[inline(always)]
    fn finish(sums: [u128; 4]) -> AssociatedU8 {
        let (c, a) = opacity_finish(sums, 255);
        // Every value is at most 255 (module docs); `min` keeps the cast lossless.
        let b = |x: u64| x.min(255) as u8;
        AssociatedU8([b(c[0]), b(c[1]), b(c[2]), b(a)])
    }
}

impl IntMethod<IntSample> for IntOpacityBased {
    #[inline(always)]
    fn channels(v: IntSample) -> [u128; 4] {
        // `IntSample` keeps `c ≤ a ≤ ONE` by construction.
        let [r, g, b] = v.c();
        let a = v.a();
        let c = |x: u16| u128::from(x.min(a));
        [c(r), c(g), c(b), u128::from(a.min(ONE))]
    }

    #[inline(always)]
    fn finish(sums: [u128; 4]) -> IntSample {
        let (c, a) = opacity_finish(sums, u64::from(ONE));
        // C̃′ ≤ α′ ≤ ONE by construction (module docs); `min` keeps the casts lossless.
        let h = |x: u64| x.min(u64::from(ONE)) as u16;
        IntSample::from_valid(c.each(h), h(a))
    }
}

/// Integer extinction-based downsampling: filter `D = τ·d′` and `D·C`, double for the coarse
/// voxel's length, **saturate** at [`MAX_DEPTH_RAW`] (see the [module docs](self)).
///
/// Error bound: per level ½ U7.20 LSB (`2^−21` optical depth) against the exact method with
/// the quantised taps, until saturation (module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntExtinctionBased;

impl sealed::Sealed for IntExtinctionBased {}

impl IntMethod<ExtinctionFx> for IntExtinctionBased {
    #[inline(always)]
    fn channels(v: ExtinctionFx) -> [u128; 4] {
        let t = v.tau.min(MAX_DEPTH_RAW);
        let [r, g, b] = v.c_tau.each(|c| u128::from(c.min(t)));
        [r, g, b, u128::from(t)]
    }

    #[inline(always)]
    fn finish(sums: [u128; 4]) -> ExtinctionFx {
        let cap = u128::from(MAX_DEPTH_RAW);
        // Doubling: one bit less of shift.
        let d = |s: u128| round_half_up_shift_u128(s, SUM_FRAC_BITS - 1).min(cap) as u32;
        let [r, g, b, t] = sums;
        ExtinctionFx {
            tau: d(t),
            c_tau: [d(r), d(g), d(b)],
        }
    }
}

/// Validates `dims` against `len` as [`Volume::new`](crate::Volume::new) does.
fn check_dims(len: usize, dims: [usize; 3]) -> Result<(), Error> {
    for (axis, &n) in (0u8..).zip(dims.iter()) {
        if n == 0 {
            return Err(Error::ZeroDimension { axis });
        }
        if n > MAX_DIM {
            return Err(Error::DimensionTooLarge);
        }
    }
    let [nx, ny, nz] = dims;
    let expected = nx
        .checked_mul(ny)
        .and_then(|p| p.checked_mul(nz))
        .ok_or(Error::DimensionTooLarge)?;
    if len != expected {
        return Err(Error::LengthMismatch {
            expected,
            actual: len,
        });
    }
    Ok(())
}

/// The four clamped fine indices `2j − 1 … 2j + 2` of coarse index `j` on an axis of `n`
/// (the float kernel's convention).
#[inline(always)]
fn axis_taps(j: usize, n: usize) -> [usize; 4] {
    let last = n.saturating_sub(1);
    let c = j.saturating_mul(2);
    [
        c.saturating_sub(1).min(last),
        c.min(last),
        c.saturating_add(1).min(last),
        c.saturating_add(2).min(last),
    ]
}

/// Downsamples the `dims` volume `src` by one level with `filter` and `method` into `dst`,
/// and returns the coarse dimensions [`level_dims`]`(dims, 1)`.
///
/// Coarse voxel `(X, Y, Z)` is the method's finish of the exact sums
/// `Σ w_i w_j w_k·v(2X − 1 + i, 2Y − 1 + j, 2Z − 1 + k)`, `w` the Q0.16 taps, reads clamped
/// to the edge. No scratch buffer, no allocation. For [`Voxel`](crate::voxel::Voxel) formats
/// ([`AssociatedU8`], [`ExtinctionFx`]) wrap `dst` in a [`Volume`](crate::Volume) to sample it
/// with the integer samplers.
///
/// Error bound: the method's (module docs): `½ + 2^−8` storage LSB (opacity-based), ½ LSB
/// (extinction-based), plus `12|a − a_q|·V` against the unquantised float filter.
///
/// # Errors
/// [`Error::ZeroDimension`], [`Error::DimensionTooLarge`] or [`Error::LengthMismatch`] for
/// `dims` that do not describe `src` (as [`Volume::new`](crate::Volume::new));
/// [`Error::OutputLengthMismatch`] unless `dst.len()` is the coarse voxel count.
pub fn downsample_level_int<V: Copy, M: IntMethod<V>>(
    method: M,
    filter: IntFilter4,
    src: &[V],
    dims: [usize; 3],
    dst: &mut [V],
) -> Result<[usize; 3], Error> {
    let _ = method;
    check_dims(src.len(), dims)?;
    filter_level::<V, M>(filter, src, dims, dst)
}

/// The kernel: `src` already validated against `dims`.
fn filter_level<V: Copy, M: IntMethod<V>>(
    filter: IntFilter4,
    src: &[V],
    dims: [usize; 3],
    dst: &mut [V],
) -> Result<[usize; 3], Error> {
    let out_dims = level_dims(dims, 1);
    let expected = voxel_count(out_dims);
    if dst.len() != expected {
        return Err(Error::OutputLengthMismatch {
            expected,
            actual: dst.len(),
        });
    }
    let [nx, ny, nz] = dims;
    let [ox, oy, _] = out_dims;
    let fetch = |x: usize, y: usize, z: usize| -> [u128; 4] {
        // In range by the clamps in `axis_taps` and the validated length, so `get` hits.
        src.get(x + nx * (y + ny * z))
            .map_or([0; 4], |&v| M::channels(v))
    };
    for (row, out_row) in dst.chunks_exact_mut(ox.max(1)).enumerate() {
        let ys = axis_taps(row % oy.max(1), ny);
        let zs = axis_taps(row / oy.max(1), nz);
        for (x, out) in out_row.iter_mut().enumerate() {
            let xs = axis_taps(x, nx);
            let planes = zs
                .each(|z| filter.combine(ys.each(|y| filter.combine(xs.each(|x| fetch(x, y, z))))));
            *out = M::finish(filter.combine(planes));
        }
    }
    Ok(out_dims)
}

/// Builds the whole chain below the `dims` volume `base` into `out`: level `ℓ ≥ 1` at
/// [`level_offset`]`(dims, ℓ)` with
/// [`level_dims`]`(dims, ℓ)`, each [`downsample_level_int`] of the level
/// before (bit-identical), down to `1 × 1 × 1`. Returns the number of levels,
/// [`level_count`]`(dims)`, level 0 included.
///
/// Error bound: per level as [`downsample_level_int`]; level `ℓ` against the exact chain
/// within `(2^ℓ − 1)` times the per-level bound (module docs).
///
/// # Errors
/// As [`downsample_level_int`] for `base`; [`Error::OutputLengthMismatch`] unless
/// `out.len() == `[`chain_len`]`(dims)`.
pub fn build_chain_int<V: Copy, M: IntMethod<V>>(
    method: M,
    filter: IntFilter4,
    base: &[V],
    dims: [usize; 3],
    out: &mut [V],
) -> Result<u32, Error> {
    let _ = method;
    check_dims(base.len(), dims)?;
    let expected = chain_len(dims);
    let mismatch = Error::OutputLengthMismatch {
        expected,
        actual: out.len(),
    };
    if out.len() != expected {
        return Err(mismatch);
    }
    let count = level_count(dims);
    // Level ℓ ≥ 2 reads level ℓ − 1 from the part of `out` already written.
    for level in 1..count {
        let off = level_offset(dims, level);
        let n = voxel_count(level_dims(dims, level));
        let (done, todo) = out.split_at_mut_checked(off).ok_or(mismatch)?;
        let dst = todo.get_mut(..n).ok_or(mismatch)?;
        if level == 1 {
            filter_level::<V, M>(filter, base, dims, dst)?;
        } else {
            let prev = done.get(level_offset(dims, level - 1)..).ok_or(mismatch)?;
            filter_level::<V, M>(filter, prev, level_dims(dims, level - 1), dst)?;
        }
    }
    Ok(count)
}
