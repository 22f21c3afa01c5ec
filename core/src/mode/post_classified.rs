//! `PostClassified`: interpolate the scalar, then classify.

use super::{lerp8, sealed, weighted_sums, Linear, Mode};
use crate::each::Each;
use crate::num::Num;
use crate::sample::{Interp, Sample};
use crate::transfer::TransferFunction;
use crate::voxel::ScalarVoxel;

/// Interpolates the scalar, then applies the transfer function:
/// `(C, α) = TF(Σ w s)`, `C̃ = α·C` (Wittenbrink table 2, method 1).
///
/// Error bound (f32 against the f64 reference, at `d = d′`): `α` and each `C̃` within
/// `3ε + L·taps·ε·s_max`, `ε = 2⁻²³`, where `L` is the transfer function's steepest slope and
/// `s_max` the largest scalar magnitude (`tolerance::sample_bound` in the tests).
#[derive(Debug, Clone, Copy)]
pub struct PostClassified<'t, const N: usize> {
    tf: &'t TransferFunction<N>,
}

impl<'t, const N: usize> PostClassified<'t, N> {
    /// Post-classification through `tf`.
    pub fn new(tf: &'t TransferFunction<N>) -> Self {
        Self { tf }
    }

    /// The transfer function.
    pub fn transfer_function(&self) -> &'t TransferFunction<N> {
        self.tf
    }
}

impl<const N: usize> sealed::Sealed for PostClassified<'_, N> {}

impl<V: ScalarVoxel, const N: usize> Mode<V> for PostClassified<'_, N> {
    const OPACITY_BASED: bool = true;

    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T> {
        // The scalar in `a` (the colors, zeros, are dropped by the compiler).
        weighted_sums::<T, Linear, _, K>(w, taps, |v| ([T::ZERO; 3], v.scalar::<T>()))
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        Interp {
            c: [T::ZERO; 3],
            a: lerp8(taps.each(|v| v.scalar::<T>()), f),
        }
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, _d: f32) -> Sample {
        let (c, a) = self.tf.eval(i.a);
        Sample::clamped(c.each(|c| c * a), a)
    }
}
