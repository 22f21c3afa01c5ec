//! Integer front-to-back compositing of U8.8 associated samples.
//!
//! `T = ONE − A`, then per channel `A ← A + ⌊T·α_s/ONE + ½⌋` and
//! `C ← C + ⌊T·C̃_s/ONE + ½⌋` (**round half up**, computed as `(T·x + ONE/2)/ONE`).
//!
//! Accumulator width: the accumulator is an [`IntSample`] (U8.8, `u16` per channel); the
//! products `T·x ≤ 65280² = 4 261 478 400` plus `32 640` stay below `2^32`, so `u32` suffices.
//!
//! Invariants by construction: each increment is at most `T` (as `x ≤ ONE`), so `A ≤ ONE`;
//! `A` never decreases; `C̃_s ≤ α_s` makes each color increment at most the opacity
//! increment (monotone rounding), so `C ≤ A` by induction.

use super::{IntSample, ONE};
use crate::error::Error;

/// `⌊T·x/ONE + ½⌋` in `u32` (see the module docs for the width).
#[inline(always)]
const fn blend(t: u32, x: u16) -> u16 {
    ((t * x as u32 + ONE as u32 / 2) / ONE as u32) as u16
}

/// One front-to-back step: `acc` is in front of `s`.
///
/// Error bound: over `n` steps from [`IntSample::TRANSPARENT`], the accumulated `A` is within
/// `n/2` U8.8 LSB and each `C` within `n` U8.8 LSB of the exact composite of the same samples
/// (`COMPOSITE_INT_A_LSB_PER_STEP`, `COMPOSITE_INT_C_LSB_PER_STEP`). Proof: with the
/// transmittance error `e_k` and rounding errors `|r_k| ≤ ½`, `e_(k+1) = e_k(1 − α_k) − r_k`
/// gives `|e_n| ≤ n/2`, and `Σ|e_k|·α_k ≤ Σ(|e_k| − |e_(k+1)| + ½) ≤ n/2` bounds what the
/// color inherits, plus `n/2` of its own rounding.
#[inline(always)]
pub const fn front_to_back(acc: IntSample, s: IntSample) -> IntSample {
    let t = (ONE - acc.a()) as u32;
    let [r, g, b] = acc.c();
    let [sr, sg, sb] = s.c();
    IntSample::from_valid(
        [r + blend(t, sr), g + blend(t, sg), b + blend(t, sb)],
        acc.a() + blend(t, s.a()),
    )
}

/// Early termination of an integer ray: stop once `A ≥ a_stop` (U8.8).
///
/// With `a_stop = ONE` ([`IntStop::NEVER`]) a ray stops only when fully opaque, where further
/// samples could not change it: the same result as never stopping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntStop {
    a_stop: u16,
}

impl IntStop {
    /// Never stop early.
    pub const NEVER: Self = Self { a_stop: ONE };

    /// Stop once `A ≥ a_stop`; the color then misses at most `ONE − a_stop` (times the largest
    /// straight color behind) of the full composite.
    ///
    /// # Errors
    /// [`Error::InvalidThreshold`] unless `0 < a_stop ≤ ONE`.
    pub const fn new(a_stop: u16) -> Result<Self, Error> {
        if a_stop > 0 && a_stop <= ONE {
            Ok(Self { a_stop })
        } else {
            Err(Error::InvalidThreshold)
        }
    }

    /// `A_stop` (U8.8).
    pub const fn a_stop(&self) -> u16 {
        self.a_stop
    }
}

/// Composites `samples` front to back from transparent, stopping once `A ≥ a_stop`.
/// Returns the composite and the number of samples used.
///
/// Error bound: as [`front_to_back`], per sample used; with early termination the color
/// additionally misses at most `ONE − a_stop` of what the remaining samples would add.
pub fn composite_front_to_back<I: IntoIterator<Item = IntSample>>(
    samples: I,
    stop: IntStop,
) -> (IntSample, usize) {
    let mut acc = IntSample::TRANSPARENT;
    let mut used = 0usize;
    for s in samples {
        if acc.a() >= stop.a_stop {
            break;
        }
        acc = front_to_back(acc, s);
        used += 1;
    }
    (acc, used)
}
