//! What the eight-lane kernels (`arch::avx2`) need to know of a mode, as types: the voxel
//! format they read, how a tap becomes channels, how the sums weight it, how a sample is
//! finished. A mode that has such a kernel implements [`LaneMode`] and names itself in
//! [`Mode::lanes8`](super::Mode::lanes8); the marchers reach the kernel through a
//! [`LaneVisitor`], so that no flag and no table routes between modes: the mode's type picks
//! the kernel's instance.
//!
//! Not part of the public API: the traits are public only so that the public, sealed
//! [`Mode`](super::Mode) can name them, and their module is private.

use crate::lanes::Lanes;
use crate::num::Num;
use crate::opacity::{Corrected, Correction, Uncorrected};
use crate::sample::Interp;
use crate::voxel::{ExtinctionF32, StraightF32, StraightU8, Voxel};

/// A voxel format that an eight-lane kernel reads: [`StraightU8`] (RGBA8 words, two
/// neighbours as one 8-byte word), [`ExtinctionF32`] and [`StraightF32`] (one 16-byte vector
/// each).
pub trait LaneVoxel: Voxel {
    /// `data` as this format, where the marcher's format `V` is it (the same slice
    /// retyped); `None` otherwise, and the marcher keeps its portable paths.
    fn retype<V: Voxel>(data: &[V]) -> Option<&[Self]>;
}

impl LaneVoxel for StraightU8 {
    #[inline(always)]
    fn retype<V: Voxel>(data: &[V]) -> Option<&[Self]> {
        V::as_straight_u8(data)
    }
}

impl LaneVoxel for ExtinctionF32 {
    #[inline(always)]
    fn retype<V: Voxel>(data: &[V]) -> Option<&[Self]> {
        V::as_extinction_f32(data)
    }
}

impl LaneVoxel for StraightF32 {
    #[inline(always)]
    fn retype<V: Voxel>(data: &[V]) -> Option<&[Self]> {
        V::as_straight_f32(data)
    }
}

/// A lane kernel's correction stage ([`LaneMode::Correction`]), made from the marcher's.
pub trait LaneCorrection: Correction {
    /// The stage for a marcher whose correction is `c` (`None` where `d = d′`).
    fn of(c: Option<Corrected>) -> Self;
}

impl LaneCorrection for Option<Corrected> {
    #[inline(always)]
    fn of(c: Option<Corrected>) -> Self {
        c
    }
}

/// For the extinction modes: a marcher never corrects them (`RayMarcher::new` enables the
/// correction for opacity-based modes only), so `c` is always `None` here.
impl LaneCorrection for Uncorrected {
    #[inline(always)]
    fn of(c: Option<Corrected>) -> Self {
        debug_assert!(c.is_none(), "an extinction marcher with a correction");
        Uncorrected
    }
}

/// How a mode weights a tap in its sums (`weighted_sums`): from the tap's weight `w` and
/// its opacity-like channel `a`, the weight of its colors and its term of the `a` sum.
pub trait Weighting {
    /// `(weight of the colors, term of the a sum)`.
    fn tap<T: Num>(w: T, a: T) -> (T, T);
}

/// The linear modes' weighting: the colors by `w`, the sum of `w·a`.
#[derive(Debug)]
pub enum Linear {}

impl Weighting for Linear {
    #[inline(always)]
    fn tap<T: Num>(w: T, a: T) -> (T, T) {
        (w, w * a)
    }
}

/// `OpacityWeighted`'s: `ω = w·α`, the colors by `ω`, the sum of `ω` (eqs. 9–12).
#[derive(Debug)]
pub enum ByOpacity {}

impl Weighting for ByOpacity {
    #[inline(always)]
    fn tap<T: Num>(w: T, a: T) -> (T, T) {
        let omega = w * a;
        (omega, omega)
    }
}

/// How a lane kernel turns a tap into its four channels: one of [`Unorm8`],
/// [`TauOfAlpha8`], [`StoredF32x4`]. Its supertrait is their reads in the target's
/// instruction sets (`arch`), which implements them for each.
pub trait TapRead: crate::arch::TapReads {}

/// RGBA8 words, each byte `n` read as `n/255` correctly rounded (`OpacityWeighted`,
/// `Separate`).
#[derive(Debug)]
pub enum Unorm8 {}
impl TapRead for Unorm8 {}

/// RGBA8 words, read as `[τ·r, τ·g, τ·b, τ]` with the colors `n/255` and `τ` the mode's
/// value for the opacity byte ([`LaneMode::taus`]; `ExtinctionWeightedU8`).
#[derive(Debug)]
pub enum TauOfAlpha8 {}
impl TapRead for TauOfAlpha8 {}

/// 16-byte voxels, read as their four stored `f32`: `ExtinctionF32`'s `[C^τ, τ]`
/// (`ExtinctionWeighted`), `StraightF32`'s `[C, α]` (`OpacityWeighted`, `Separate`).
#[derive(Debug)]
pub enum StoredF32x4 {}
impl TapRead for StoredF32x4 {}

/// A float mode that the eight-lane kernels compute.
pub trait LaneMode {
    /// The voxel format the kernel reads.
    type Voxel: LaneVoxel;
    /// How the kernel reads a tap.
    type Taps: TapRead;
    /// How the sums weight a tap.
    type W: Weighting;
    /// How many steps the kernel lags the finish of a sample behind its sums (a long chain
    /// of dependent operations, extinction's `exp`, overlaps the next samples' work then).
    const LAG: u32;
    /// The correction stage the kernel applies after the finish: the marcher's
    /// `Option<Corrected>` for the opacity-based modes, [`Uncorrected`] for the extinction
    /// modes, which never correct (so their kernels carry no correction code).
    type Correction: LaneCorrection;

    /// `data` as the kernel's voxel format ([`LaneVoxel::retype`]).
    #[inline(always)]
    fn voxels<V: Voxel>(data: &[V]) -> Option<&[Self::Voxel]> {
        Self::Voxel::retype(data)
    }

    /// The `τ` of every opacity byte, read where `Taps` is [`TauOfAlpha8`] (all zero for the
    /// other modes, which never read it).
    #[inline(always)]
    fn taus(&self) -> &[f32; 256] {
        NO_TAUS
    }

    /// The mode's `Mode::finish_in` (it reads no field of the mode).
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T>;
}

/// A straight-channel mode `M` (`OpacityWeighted`, `Separate`: a lane kernel over RGBA8
/// words) over 16-byte [`StraightF32`] voxels instead, each tap read as its stored `[C, α]`:
/// the same sums and finish as `M`'s.
#[derive(Debug, Clone, Copy)]
pub struct OverF32<M>(M);

impl<M: LaneMode<Voxel = StraightU8, Taps = Unorm8>> LaneMode for OverF32<M> {
    type Voxel = StraightF32;
    type Taps = StoredF32x4;
    type W = M::W;
    const LAG: u32 = M::LAG;
    type Correction = M::Correction;

    #[inline(always)]
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
        M::finish_lanes(i, d)
    }
}

/// The lane kernel of the straight-channel mode `m` over voxels of the format `V`: `m`'s
/// own over RGBA8 words, [`OverF32`] over [`StraightF32`] (chosen by `V`'s type).
#[inline(always)]
pub(crate) fn visit_straight<V, M, X>(m: &M, visitor: X) -> X::Out
where
    V: Voxel,
    M: LaneMode<Voxel = StraightU8, Taps = Unorm8> + Copy,
    X: LaneVisitor,
{
    if V::as_straight_f32(&[]).is_some() {
        visitor.visit(&OverF32(*m))
    } else {
        visitor.visit(m)
    }
}

/// A computation over the lane kernel of a mode ([`Mode::lanes8`](super::Mode::lanes8)).
pub trait LaneVisitor {
    /// Its result.
    type Out;
    /// Runs it for the mode `mode`, of type `K`.
    fn visit<K: LaneMode>(self, mode: &K) -> Self::Out;
}

/// The `τ` table of the modes that read none.
pub(crate) const NO_TAUS: &[f32; 256] = &[0.0; 256];
