//! Voxel storage formats and what each one means.
//!
//! | type | holds | valid when |
//! |---|---|---|
//! | [`StraightF32`] | straight color `C` and opacity `α` | all finite, in `[0, 1]` |
//! | [`StraightU8`] | straight RGBA bytes, read as `n/255` | always |
//! | [`AssociatedF32`] | associated color `C̃ = α·C` and `α` | finite, `0 ≤ C̃ ≤ α ≤ 1` |
//! | [`AssociatedU8`] | associated RGBA bytes, read as `n/255` | `C̃ ≤ α` per channel |
//! | [`ExtinctionF32`] | extinction `τ` (per unit length) and `C^τ = τ·C` | finite, `0 ≤ C^τ ≤ τ ≤` [`MAX_TAU`] |
//! | `u8`, `u16`, `f32` | a scalar for a transfer function | `f32`: finite |
//!
//! Opacities are defined for the volume's reference distance `d′`
//! ([`Volume::reference_distance`](crate::Volume::reference_distance)).

// The voxel decodes keep `[T; N]::map` (`core/clippy.toml` asks for `crate::each`): with
// `each`, or written out per channel, the baseline instance's `OpacityWeighted` `cast` took 7 %
// longer (23.8 against 22.3 ns/sample in a probe of the `ray_march` bench's rays), through
// inlining decisions elsewhere in the march that were not pinned down.
#![allow(clippy::disallowed_methods)]

use crate::num::Num;

/// Largest extinction coefficient an [`ExtinctionF32`] voxel may hold (per unit length).
///
/// With this cap no interpolated `τ` nor any `τ·C` can overflow `f32`.
pub const MAX_TAU: f32 = 1.0e18;

/// Optical depth `τ·d′` given to a fully opaque voxel (`α = 1`, for which `−ln(1 − α) = ∞`)
/// when it is converted to extinction form.
///
/// `1 − e^(−64)` rounds to `1` in `f32` and `f64`, so the cap is invisible at distances
/// `d ≥ d′`; at a step `d < d′` a capped voxel has opacity `1 − e^(−64·d/d′)` instead of 1.
pub const MAX_OPTICAL_DEPTH: f32 = 64.0;

/// A validation failure of one voxel (turned into an [`Error`](crate::Error) by the volume).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum VoxelFault {
    /// NaN or ±∞.
    NonFinite,
    /// Outside the format's range.
    OutOfRange,
    /// An associated color channel exceeds the opacity (or extinction).
    ColorExceedsOpacity,
}

/// Every voxel format.
pub trait Voxel: Copy {
    /// The fully transparent voxel.
    const TRANSPARENT: Self;
    /// Checks that the voxel is valid for its format.
    fn check(&self) -> Result<(), VoxelFault>;

    /// `true` for the formats that hold their four channels as `f32` already
    /// ([`StraightF32`], [`AssociatedF32`]): a tap is then a four-lane vector as it is, and
    /// the ray marcher keeps computing the opacity-based trilinear samples one at a time (in
    /// `volsample report` four in lanes ran 1.06–1.13× slower for them). `false` by default.
    #[doc(hidden)]
    const F32_CHANNELS: bool = false;

    /// `data` itself where `Self` is [`StraightU8`], `None` for every other format: lets the
    /// eight-ray lane kernel (the AVX2 instance) read two neighbouring voxels as one 8-byte word
    /// (a `StraightU8` is its four bytes in memory). Not meant to be overridden.
    #[doc(hidden)]
    #[inline(always)]
    fn as_straight_u8(data: &[Self]) -> Option<&[StraightU8]> {
        let _ = data;
        None
    }

    /// `data` itself where `Self` is [`ExtinctionF32`], `None` for every other format: lets
    /// the eight-ray lane kernel (the AVX2 instance) read such a voxel as one 16-byte vector (an
    /// `ExtinctionF32` is `repr(C)`: its four `f32` in order), and `Trilinear` read the taps
    /// of `ExtinctionWeighted` in place. Not meant to be overridden.
    #[doc(hidden)]
    #[inline(always)]
    fn as_extinction_f32(data: &[Self]) -> Option<&[ExtinctionF32]> {
        let _ = data;
        None
    }

    /// `data` itself where `Self` is [`StraightF32`], `None` for every other format: lets the
    /// eight-ray lane kernel (the AVX2 instance) read such a voxel as one 16-byte vector (a
    /// `StraightF32` is `repr(C)`: its four `f32` in order). Not meant to be overridden.
    #[doc(hidden)]
    #[inline(always)]
    fn as_straight_f32(data: &[Self]) -> Option<&[StraightF32]> {
        let _ = data;
        None
    }
}

/// A voxel holding straight (unweighted) color and opacity.
pub trait StraightVoxel: Voxel {
    /// Straight color `C` and opacity `α`, each in `[0, 1]`.
    fn straight<T: Num>(self) -> ([T; 3], T);

    /// [`straight`](Self::straight) in `f32` as `[C_r, C_g, C_b, α]`: the same values, in
    /// the four-lane form of [`Mode::weighted8_f32`](crate::Mode::weighted8_f32).
    #[inline(always)]
    fn straight4(self) -> [f32; 4] {
        let ([r, g, b], a) = self.straight::<f32>();
        [r, g, b, a]
    }
}

/// A voxel holding associated (opacity-weighted, premultiplied) color and opacity.
pub trait AssociatedVoxel: Voxel {
    /// Associated color `C̃` and opacity `α`, `C̃ ≤ α`.
    fn associated<T: Num>(self) -> ([T; 3], T);
}

/// A voxel holding extinction `τ` and extinction-weighted color `C^τ`.
pub trait ExtinctionVoxel: Voxel {
    /// Extinction-weighted color `C^τ` and extinction `τ` (per unit length).
    fn extinction<T: Num>(self) -> ([T; 3], T);
}

/// A scalar voxel, classified by a transfer function.
pub trait ScalarVoxel: Voxel {
    /// The scalar value in its own units (`u8`: `0..=255`, `u16`: `0..=65535`).
    fn scalar<T: Num>(self) -> T;
}

// Evaluated at compile time only: an out-of-range index would be a build error, never a
// run-time panic.
#[allow(clippy::indexing_slicing)]
const fn unorm8_table() -> [f32; 256] {
    let mut t = [0.0f32; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = i as f32 / 255.0;
        i += 1;
    }
    t
}

/// `n/255` for every byte, correctly rounded (so `255 ↦ 1.0` exactly).
static UNORM8: [f32; 256] = unorm8_table();

/// A byte read as a unit-range value, `n/255`, correctly rounded to `f32`.
#[inline(always)]
pub fn unorm8(n: u8) -> f32 {
    // The table has 256 entries, so the lookup cannot miss; `get` keeps the crate panic-free.
    UNORM8.get(usize::from(n)).copied().unwrap_or(0.0)
}

fn check_unit(x: f32) -> Result<(), VoxelFault> {
    if !x.is_finite() {
        Err(VoxelFault::NonFinite)
    } else if !(0.0..=1.0).contains(&x) {
        Err(VoxelFault::OutOfRange)
    } else {
        Ok(())
    }
}

/// Straight color and opacity in `f32`.
///
/// `repr(C)`: four `f32` in memory, red, green, blue, then `α` (16 bytes, the layout a C
/// caller can rely on, and the eight-lane kernel reads as one vector).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(C)]
pub struct StraightF32 {
    /// Straight color `C`, each channel in `[0, 1]`.
    pub c: [f32; 3],
    /// Opacity `α` in `[0, 1]` for the reference distance `d′`.
    pub a: f32,
}

impl Voxel for StraightF32 {
    const F32_CHANNELS: bool = true;
    #[inline(always)]
    fn as_straight_f32(data: &[Self]) -> Option<&[StraightF32]> {
        Some(data)
    }
    const TRANSPARENT: Self = Self {
        c: [0.0; 3],
        a: 0.0,
    };
    fn check(&self) -> Result<(), VoxelFault> {
        for x in self.c.iter().chain(core::iter::once(&self.a)) {
            check_unit(*x)?;
        }
        Ok(())
    }
}

impl StraightVoxel for StraightF32 {
    #[inline(always)]
    fn straight<T: Num>(self) -> ([T; 3], T) {
        (self.c.map(T::from_f32), T::from_f32(self.a))
    }
}

/// Straight RGBA bytes, each read as `n/255` (the storage Wittenbrink recommends).
///
/// `#[repr(transparent)]` over `[u8; 4]`: a C array of `uint8_t[4]` has the same layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(transparent)]
pub struct StraightU8(pub [u8; 4]);

impl Voxel for StraightU8 {
    const TRANSPARENT: Self = Self([0; 4]);
    fn check(&self) -> Result<(), VoxelFault> {
        Ok(())
    }
    #[inline(always)]
    fn as_straight_u8(data: &[Self]) -> Option<&[StraightU8]> {
        Some(data)
    }
}

impl StraightVoxel for StraightU8 {
    #[inline(always)]
    fn straight<T: Num>(self) -> ([T; 3], T) {
        let [r, g, b, a] = self.0;
        (
            [r, g, b].map(|n| T::from_f32(unorm8(n))),
            T::from_f32(unorm8(a)),
        )
    }

    #[inline(always)]
    fn straight4(self) -> [f32; 4] {
        self.0.map(unorm8)
    }
}

/// Associated color `C̃ = α·C` and opacity in `f32`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AssociatedF32 {
    /// Associated color, each channel in `[0, α]`.
    pub c: [f32; 3],
    /// Opacity `α` in `[0, 1]`.
    pub a: f32,
}

impl AssociatedF32 {
    /// The associated form of a straight voxel: `C̃ = α·C`, rounded to `f32`.
    pub fn from_straight(v: StraightF32) -> Self {
        Self {
            c: v.c.map(|c| c * v.a),
            a: v.a,
        }
    }
}

impl Voxel for AssociatedF32 {
    const F32_CHANNELS: bool = true;
    const TRANSPARENT: Self = Self {
        c: [0.0; 3],
        a: 0.0,
    };
    fn check(&self) -> Result<(), VoxelFault> {
        check_unit(self.a)?;
        for c in self.c {
            check_unit(c)?;
            if c > self.a {
                return Err(VoxelFault::ColorExceedsOpacity);
            }
        }
        Ok(())
    }
}

impl AssociatedVoxel for AssociatedF32 {
    #[inline(always)]
    fn associated<T: Num>(self) -> ([T; 3], T) {
        (self.c.map(T::from_f32), T::from_f32(self.a))
    }
}

/// Associated RGBA bytes (Drebin-style premultiplied storage), each read as `n/255`.
///
/// Storing `C̃` in 8 bits loses color where `α` is small: see the integer module for the
/// bound on the recovered color. `#[repr(transparent)]` over `[u8; 4]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(transparent)]
pub struct AssociatedU8(pub [u8; 4]);

impl Voxel for AssociatedU8 {
    const TRANSPARENT: Self = Self([0; 4]);
    fn check(&self) -> Result<(), VoxelFault> {
        let [r, g, b, a] = self.0;
        if r > a || g > a || b > a {
            Err(VoxelFault::ColorExceedsOpacity)
        } else {
            Ok(())
        }
    }
}

impl AssociatedVoxel for AssociatedU8 {
    #[inline(always)]
    fn associated<T: Num>(self) -> ([T; 3], T) {
        let [r, g, b, a] = self.0;
        (
            [r, g, b].map(|n| T::from_f32(unorm8(n))),
            T::from_f32(unorm8(a)),
        )
    }
}

/// Extinction `τ` (per unit length) and extinction-weighted color `C^τ = τ·C` (Kraus 2008).
///
/// `repr(C)`: four `f32` in memory, `C^τ` red, green, blue, then `τ` (16 bytes, the layout a
/// C caller or a DMA engine can rely on).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(C)]
pub struct ExtinctionF32 {
    /// Extinction-weighted color, each channel in `[0, τ]`.
    pub c_tau: [f32; 3],
    /// Extinction coefficient, in `[0, MAX_TAU]`.
    pub tau: f32,
}

impl ExtinctionF32 {
    /// Converts a straight voxel whose opacity holds for distance `d_ref`:
    /// `τ = −ln(1 − α)/d′` with the optical depth capped at [`MAX_OPTICAL_DEPTH`]
    /// (so `α = 1` gives a finite `τ`), and `C^τ = τ·C`.
    ///
    /// Error bound: `τ` within relative `2ε` (`ε = 2⁻²³`) of `−ln(1 − α)/d′` for the given
    /// `f32` `α`, below the cap (`FROM_STRAIGHT_TAU_REL` in the tests).
    /// A non-finite or non-positive `d_ref` gives `τ = 0` (the volume constructor rejects such
    /// a distance before it could reach here).
    pub fn from_straight(v: StraightF32, d_ref: f32) -> Self {
        let depth = (-libm::log1pf(-v.a)).min(MAX_OPTICAL_DEPTH);
        let tau = if d_ref > 0.0 && d_ref.is_finite() {
            (depth / d_ref).min(MAX_TAU)
        } else {
            0.0
        };
        let tau = if tau.is_nan() { 0.0 } else { tau.max(0.0) };
        Self {
            c_tau: v.c.map(|c| (tau * c).min(tau)),
            tau,
        }
    }
}

impl Voxel for ExtinctionF32 {
    const TRANSPARENT: Self = Self {
        c_tau: [0.0; 3],
        tau: 0.0,
    };
    #[inline(always)]
    fn as_extinction_f32(data: &[Self]) -> Option<&[ExtinctionF32]> {
        Some(data)
    }
    fn check(&self) -> Result<(), VoxelFault> {
        for x in self.c_tau.iter().chain(core::iter::once(&self.tau)) {
            if !x.is_finite() {
                return Err(VoxelFault::NonFinite);
            }
            if !(0.0..=MAX_TAU).contains(x) {
                return Err(VoxelFault::OutOfRange);
            }
        }
        if self.c_tau.iter().any(|&c| c > self.tau) {
            return Err(VoxelFault::ColorExceedsOpacity);
        }
        Ok(())
    }
}

impl ExtinctionF32 {
    /// `[C^τ r, g, b, τ]`, read in place (the four lanes of the extinction kernels).
    #[inline(always)]
    pub(crate) fn lanes(&self) -> [f32; 4] {
        let [r, g, b] = self.c_tau;
        [r, g, b, self.tau]
    }
}

impl ExtinctionVoxel for ExtinctionF32 {
    #[inline(always)]
    fn extinction<T: Num>(self) -> ([T; 3], T) {
        (self.c_tau.map(T::from_f32), T::from_f32(self.tau))
    }
}

impl Voxel for u8 {
    const TRANSPARENT: Self = 0;
    fn check(&self) -> Result<(), VoxelFault> {
        Ok(())
    }
}

impl ScalarVoxel for u8 {
    #[inline(always)]
    fn scalar<T: Num>(self) -> T {
        T::from_f32(f32::from(self))
    }
}

impl Voxel for u16 {
    const TRANSPARENT: Self = 0;
    fn check(&self) -> Result<(), VoxelFault> {
        Ok(())
    }
}

impl ScalarVoxel for u16 {
    #[inline(always)]
    fn scalar<T: Num>(self) -> T {
        T::from_f32(f32::from(self))
    }
}

impl Voxel for f32 {
    const TRANSPARENT: Self = 0.0;
    fn check(&self) -> Result<(), VoxelFault> {
        if self.is_finite() {
            Ok(())
        } else {
            Err(VoxelFault::NonFinite)
        }
    }
}

impl ScalarVoxel for f32 {
    #[inline(always)]
    fn scalar<T: Num>(self) -> T {
        T::from_f32(self)
    }
}
