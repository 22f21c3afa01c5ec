//! `OpacityWeighted`: opacity-weighted color interpolation (Wittenbrink, Malzbender, Goss 1998).

use super::{
    channels_x4, dot_lanes8, lerp8, sealed, weighted_sums, ByOpacity, LaneMode, LaneVisitor, Mode,
    Unorm8,
};
use crate::each::Each;
use crate::lanes::{F32x4, Lanes};
use crate::num::Num;
use crate::sample::{clamped, Interp, Sample};
use crate::voxel::{StraightU8, StraightVoxel};

/// Interpolates colors weighted by opacity (eqs. 9–12): `ω_i = w_i·α_i`, `α = Σ ω`,
/// `C̃ = Σ ω C`.
///
/// Reads straight voxels (the paper's recommended storage), so no color is lost to
/// premultiplied rounding where `α` is small. As a sum of weighted products it costs the same
/// as [`Separate`](super::Separate) (36M 47A for trilinear); as a lerp tree it first
/// premultiplies the 8 colors (52M 56A).
///
/// Error bound (f32 against the f64 reference on the same stored values, at `d = d′`): `α` and
/// each `C̃` within `(1 + taps)·ε`, `ε = 2⁻²³` (`tolerance::sample_bound` in the tests).
/// Where every tap is opaque, `α = 1` exactly (the filter weights are an exact partition of
/// unity). Opacity correction adds the error of [`correct`](crate::opacity::correct).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OpacityWeighted;

impl sealed::Sealed for OpacityWeighted {}

impl<V: StraightVoxel> Mode<V> for OpacityWeighted {
    const OPACITY_BASED: bool = true;

    #[inline(always)]
    fn lanes8<X: LaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Ok(super::lanes8::visit_straight::<V, _, _>(self, visitor))
    }

    /// Eqs. 9–12 over straight channels `(C_i, α_i)` with weights `w_i` (`K`M for `ω`, then
    /// `K−1`A for `α` and `K`M `K−1`A per color): the one sum of weighted products of the
    /// modes (`mode::weighted_sums`), weighted by `ω`.
    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T> {
        weighted_sums::<T, ByOpacity, _, K>(w, taps, |v| v.straight::<T>())
    }

    #[inline(always)]
    fn weighted8_x4(&self, taps: &[[V; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        weighted_sums::<F32x4, ByOpacity, _, 8>(w, taps, |col| {
            channels_x4(*col, |v| v.straight::<f32>())
        })
    }

    #[inline(always)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, _d: f32) -> Interp<T> {
        clamped(i)
    }

    #[inline(always)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        // Lanes (C_r, C_g, C_b, 1) weighted by ω_i = w_i·α_i: the colors are `dot(ω, C)` and
        // the last lane is `Σ ω_i` in the same order (ω·1 = ω exactly), as in `weighted`.
        let mut omega = *w;
        let mut u = [[0.0f32; 4]; 8];
        for ((o, l), v) in omega.iter_mut().zip(u.iter_mut()).zip(taps.iter()) {
            let [r, g, b, a] = v.straight4();
            *o *= a;
            *l = [r, g, b, 1.0];
        }
        let [c0, c1, c2, a] = dot_lanes8(&omega, &u);
        Interp { c: [c0, c1, c2], a }
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        // Premultiply the 8 voxel colors (24M), then lerp C̃ and α (28M 56A).
        let ch = taps.each(|v| {
            let (c, a) = v.straight::<T>();
            (c.each(|c| c * a), a)
        });
        Interp {
            c: [
                lerp8(ch.each(|v| v.0[0]), f),
                lerp8(ch.each(|v| v.0[1]), f),
                lerp8(ch.each(|v| v.0[2]), f),
            ],
            a: lerp8(ch.each(|v| v.1), f),
        }
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample {
        <Self as Mode<V>>::finish_in(self, i, d).into()
    }
}

impl LaneMode for OpacityWeighted {
    type Voxel = StraightU8;
    type Taps = Unorm8;
    type W = ByOpacity;
    const LAG: u32 = 0;
    type Correction = Option<crate::opacity::Corrected>;
    #[inline(always)]
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
        <Self as Mode<StraightU8>>::finish_in(&Self, i, d)
    }
}
