//! Integer `OpacityWeighted` over straight `u8` voxels (Wittenbrink 1998, eqs. 9–12).
//!
//! With integer weights `w_i` summing to `2^s` and voxel bytes `C_i`, `α_i`:
//! `ω_i = w_i·α_i` (exact), `S_α = Σ ω_i`, `S_c = Σ ω_i·C_i` (exact), then one **round half
//! up** per output: `α = ⌊256·S_α/2^s + ½⌋`, `C̃ = ⌊256·S_c/(255·2^s) + ½⌋` (U8.8).
//!
//! Accumulator widths (`u64`), worst case all bytes 255, `s = 3F ≤ 36`:
//! `ω_i ≤ 255·2^36 < 2^44`; `S_α ≤ 255·2^36 < 2^44`; `S_c ≤ 255²·2^36 < 2^52`;
//! `256·S_c < 2^60` and the rounding numerator `2·256·S_c + 255·2^s < 2^62`: no overflow.
//!
//! `C̃ ≤ α`: `S_c ≤ 255·S_α`, so `256·S_c/(255·2^s) ≤ 256·S_α/2^s`, and round half up is
//! monotone. `α ≤ ONE`: `S_α ≤ 255·2^s`.

use super::{
    levels_to_u88, products_to_u88, sealed, IntLaneMode, IntLaneVisitor, IntMode, IntSample,
    IntWeights,
};
use crate::mode::OpacityWeighted;
use crate::voxel::StraightU8;

impl sealed::Sealed for OpacityWeighted {}

/// Error bound (against the exact result of the same method, same weights): `α` and each
/// `C̃` within ½ U8.8 LSB (`OPACITY_WEIGHTED_INT_LSB` in the tolerance table); the only
/// rounding is the final one. So the straight color `255·C̃/α` of a sample is recovered
/// within `½·255/α_raw` levels for every opacity, e.g. within `0.498` of a level at
/// `α = 1/255` (compare the premultiplied-storage limit in [`premul`](super::premul)).
impl IntMode<StraightU8> for OpacityWeighted {
    #[inline(always)]
    fn lanes8<X: IntLaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Ok(visitor.visit(self))
    }

    #[inline(always)]
    fn combine<const K: usize>(&self, taps: &[StraightU8; K], w: &IntWeights<K>) -> IntSample {
        let mut s_a = 0u64;
        let mut s_c = [0u64; 3];
        for (v, &w) in taps.iter().zip(w.weights().iter()) {
            let [r, g, b, a] = v.0;
            let omega = w * u64::from(a);
            s_a += omega;
            for (s, c) in s_c.iter_mut().zip([r, g, b]) {
                *s += omega * u64::from(c);
            }
        }
        let shift = w.shift();
        // Both ≤ ONE by the proof above, so the conversions are exact.
        let a = levels_to_u88(s_a, shift) as u16;
        let c = s_c.map(|s| products_to_u88(s, shift) as u16);
        IntSample::from_valid(c, a)
    }

    #[inline(always)]
    fn combine_trilinear<const F: u32>(&self, taps: &[StraightU8; 8], frac: [u32; 3]) -> IntSample {
        #[cfg(target_arch = "x86_64")]
        {
            let [r, g, b, a] = crate::arch::sse2::opacity_weighted_trilinear::<F>(taps, frac);
            IntSample::from_valid([r, g, b], a)
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.combine(taps, &IntWeights::trilinear_frac::<F>(frac))
    }
}

impl IntLaneMode for OpacityWeighted {
    type Voxel = StraightU8;
}
