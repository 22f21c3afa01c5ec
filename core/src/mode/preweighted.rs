//! `Preweighted`: interpolation of stored associated colors (Drebin 1988).

use super::{
    channels_x4, linear_tree, linear_weighted, linear_weighted8_f32, sealed, weighted_sums, Linear,
    Mode,
};
use crate::each::Each;
use crate::lanes::{F32x4, Lanes};
use crate::num::Num;
use crate::sample::{clamped, Interp, Sample};
use crate::voxel::AssociatedVoxel;

/// Interpolates stored associated colors: `α = Σ wα`, `C̃ = Σ wC̃`.
///
/// Equal to [`OpacityWeighted`](super::OpacityWeighted) in exact arithmetic; worse when `C̃`
/// is stored in few bits ([`AssociatedU8`](crate::AssociatedU8)), because the color of a
/// voxel with small `α` is rounded to a few levels before it is ever interpolated.
///
/// Error bound (f32 against the f64 reference on the same stored values, at `d = d′`): `α` and
/// each `C̃` within `(1 + taps)·ε`, `ε = 2⁻²³` (`tolerance::sample_bound` in the tests).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Preweighted;

impl sealed::Sealed for Preweighted {}

impl<V: AssociatedVoxel> Mode<V> for Preweighted {
    const OPACITY_BASED: bool = true;

    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T> {
        linear_weighted(&taps.each(|v| v.associated::<T>()), w)
    }

    #[inline(always)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        let u = taps.each(|v| {
            let ([r, g, b], a) = v.associated::<f32>();
            [r, g, b, a]
        });
        linear_weighted8_f32(&u, w)
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        linear_tree(&taps.each(|v| v.associated::<T>()), f)
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample {
        <Self as Mode<V>>::finish_in(self, i, d).into()
    }

    #[inline(always)]
    fn weighted8_x4(&self, taps: &[[V; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        weighted_sums::<F32x4, Linear, _, 8>(w, taps, |col| {
            channels_x4(*col, |v| v.associated::<f32>())
        })
    }

    #[inline(always)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, _d: f32) -> Interp<T> {
        clamped(i)
    }
}
