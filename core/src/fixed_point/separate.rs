//! Integer `Separate` over straight `u8` voxels (Levoy 1988/1990, the flawed baseline).
//!
//! With integer weights `w_i` summing to `2^s`: `S_α = Σ w_i·α_i`, `S_C = Σ w_i·C_i` (exact);
//! opacity and straight color each to U8.8 with **round half up**,
//! `α = ⌊256·S_α/2^s + ½⌋`, `C = ⌊256·S_C/2^s + ½⌋`; then the associated color as a
//! 16 × 16-bit product, `C̃ = ⌊α·C/ONE + ½⌋` (**round half up**) — the datapath a hardware
//! implementation of the method has.
//!
//! Accumulator widths: `S_α, S_C ≤ 255·2^36 < 2^44` (`u64`, shifted by 8: `< 2^52`);
//! `α·C + ONE/2 ≤ 65280² + 32640 < 2^32` (`u32`).
//!
//! `C̃ ≤ α`: `C ≤ ONE`, so `α·C/ONE ≤ α`, an integer that rounding keeps.

use super::{levels_to_u88, sealed, IntMode, IntSample, IntWeights, ONE};
use crate::mode::Separate;
use crate::voxel::StraightU8;

impl sealed::Sealed for Separate {}

/// Error bound (against the exact result of the same method, same weights): `α` within ½
/// U8.8 LSB, each `C̃` within 1.5 U8.8 LSB (`SEPARATE_INT_LSB`): ½ from `α` (times a
/// straight color `≤ 1`), ½ from `C` (times `α ≤ 1`), ½ from the product's rounding.
impl IntMode<StraightU8> for Separate {
    #[inline(always)]
    fn combine<const K: usize>(&self, taps: &[StraightU8; K], w: &IntWeights<K>) -> IntSample {
        let mut s_a = 0u64;
        let mut s_c = [0u64; 3];
        for (v, &w) in taps.iter().zip(w.weights().iter()) {
            let [r, g, b, a] = v.0;
            s_a += w * u64::from(a);
            for (s, c) in s_c.iter_mut().zip([r, g, b]) {
                *s += w * u64::from(c);
            }
        }
        let shift = w.shift();
        // Both ≤ ONE (weights sum to 2^s, bytes ≤ 255), so the u32 arithmetic below is exact.
        let a = levels_to_u88(s_a, shift) as u32;
        let c = s_c.map(|s| {
            let c = levels_to_u88(s, shift) as u32;
            ((a * c + u32::from(ONE) / 2) / u32::from(ONE)) as u16
        });
        IntSample::from_valid(c, a as u16)
    }
}
