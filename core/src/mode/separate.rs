//! `Separate`: color and opacity interpolated independently (Levoy 1988/1990).

use super::{
    channels_x4, linear_tree, linear_weighted, linear_weighted8_f32, sealed, weighted_sums,
    LaneMode, LaneVisitor, Linear, Mode, Unorm8,
};
use crate::each::Each;
use crate::lanes::{F32x4, Lanes};
use crate::num::Num;
use crate::sample::{clamped, Interp, Sample};
use crate::voxel::{StraightU8, StraightVoxel};

/// Interpolates straight color and opacity separately, then associates:
/// `α = Σ wα`, `C̃ = α·Σ wC`.
///
/// This is the common method Wittenbrink shows to be wrong: a transparent voxel's color leaks
/// into the sample (red air bleeds, black air darkens). Kept as the baseline.
///
/// Error bound (f32 against the f64 reference on the same stored values, at `d = d′`): `α` and
/// each `C̃` within `(1 + taps)·ε`, `ε = 2⁻²³` (`tolerance::sample_bound` in the tests).
/// Opacity correction adds the error of [`correct`](crate::opacity::correct).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Separate;

impl sealed::Sealed for Separate {}

impl<V: StraightVoxel> Mode<V> for Separate {
    const OPACITY_BASED: bool = true;

    #[inline(always)]
    fn lanes8<X: LaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Ok(super::lanes8::visit_straight::<V, _, _>(self, visitor))
    }

    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T> {
        linear_weighted(&taps.each(|v| v.straight::<T>()), w)
    }

    #[inline(always)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        linear_weighted8_f32(&taps.each(|v| v.straight4()), w)
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        linear_tree(&taps.each(|v| v.straight::<T>()), f)
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample {
        <Self as Mode<V>>::finish_in(self, i, d).into()
    }

    #[inline(always)]
    fn weighted8_x4(&self, taps: &[[V; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        weighted_sums::<F32x4, Linear, _, 8>(w, taps, |col| {
            channels_x4(*col, |v| v.straight::<f32>())
        })
    }

    /// `α` clamped, `C̃ = C·α`, then [`Sample::clamped`] (which clamps `α` again).
    #[inline(always)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, _d: f32) -> Interp<T> {
        let a = i.a.clamp_to(T::ONE);
        let [r, g, b] = i.c;
        clamped(Interp {
            c: [r * a, g * a, b * a],
            a,
        })
    }
}

impl LaneMode for Separate {
    type Voxel = StraightU8;
    type Taps = Unorm8;
    type W = Linear;
    const LAG: u32 = 0;
    type Correction = Option<crate::opacity::Corrected>;
    #[inline(always)]
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
        <Self as Mode<StraightU8>>::finish_in(&Self, i, d)
    }
}
