//! Integer `Preweighted` over `u8` premultiplied voxels (Drebin 1988).
//!
//! With integer weights `w_i` summing to `2^s`: `S_α = Σ w_i·α_i`, `S_c = Σ w_i·C̃_i`
//! (exact), then `α = ⌊256·S_α/2^s + ½⌋` and `C̃ = ⌊256·S_c/2^s + ½⌋` (**round half up**,
//! U8.8). The kernel is exact up to that rounding; what it cannot undo is the rounding of
//! `C̃_i` to 8 bits in storage, which [`premul`](super::premul) bounds.
//!
//! Accumulator widths (`u64`): `S_α, S_c ≤ 255·2^36 < 2^44`, shifted by 8: `< 2^52`.
//!
//! `C̃ ≤ α`: each stored `C̃_i ≤ α_i` (checked by the volume, and clamped to `α_i` when read),
//! so `S_c ≤ S_α` and the same monotone rounding keeps the order.

use super::{levels_to_u88, sealed, IntMode, IntSample, IntWeights};
use crate::mode::Preweighted;
use crate::voxel::AssociatedU8;

impl sealed::Sealed for Preweighted {}

/// Error bound (against the exact result of the same method on the same stored bytes, same
/// weights): `α` and each `C̃` within ½ U8.8 LSB (`PREWEIGHTED_INT_LSB`). Against the exact
/// associated color of the straight voxels the stored bytes came from, add ½ u8 level
/// (128 U8.8 LSB) of storage rounding: the §7 limit.
impl IntMode<AssociatedU8> for Preweighted {
    #[inline(always)]
    fn combine<const K: usize>(&self, taps: &[AssociatedU8; K], w: &IntWeights<K>) -> IntSample {
        let mut s_a = 0u64;
        let mut s_c = [0u64; 3];
        for (v, &w) in taps.iter().zip(w.weights().iter()) {
            let [r, g, b, a] = v.0;
            s_a += w * u64::from(a);
            for (s, c) in s_c.iter_mut().zip([r, g, b]) {
                // `min` keeps C̃_i ≤ α_i for a voxel that bypassed validation (no-op otherwise).
                *s += w * u64::from(c.min(a));
            }
        }
        let shift = w.shift();
        let a = levels_to_u88(s_a, shift) as u16;
        let c = s_c.map(|s| levels_to_u88(s, shift) as u16);
        IntSample::from_valid(c, a)
    }
}
