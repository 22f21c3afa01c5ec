//! Integer filter weights: nearest-neighbour index and exact trilinear weights.

/// The nearest voxel index of a raw coordinate with `F` fractional bits:
/// `⌊raw/2^F + ½⌋` (**round half up**, as the float [`Nearest`](crate::Nearest) filter's
/// `⌊x + ½⌋`). Exact for every `u32` (computed in `u64`).
#[inline(always)]
pub const fn nearest_index<const F: u32>(raw: u32) -> u32 {
    super::check_frac_bits!(F);
    // raw + 2^(F−1) < 2^33: no overflow in u64, and the quotient is below 2^(33−F) ≤ 2^29.
    ((raw as u64 + (1 << (F - 1))) >> F) as u32
}

/// The 8 trilinear weights of fractions `f = [fx, fy, fz]` (each `< 2^F`), indexed like the
/// float kernels' taps (`w[i]` for corner `(i & 1, (i >> 1) & 1, i >> 2)`).
///
/// Each weight is the exact product `px·py·pz` with `p = 2^F − f` for the low corner and
/// `p = f` for the high one; no rounding. Each factor is at most `2^F`, so each weight is at
/// most `2^(3F) ≤ 2^36`, and they sum to exactly `2^(3F)` (the product of the three per-axis
/// sums `(2^F − f) + f`). Fractions `≥ 2^F` (impossible from [`IntPos`](super::IntPos)) are
/// reduced modulo `2^F`.
///
/// Error bound: exact.
#[inline(always)]
pub const fn trilinear_weights<const F: u32>(f: [u32; 3]) -> [u64; 8] {
    super::check_frac_bits!(F);
    let one = 1u64 << F;
    let m = one - 1;
    let [fx, fy, fz] = f;
    let (x1, y1, z1) = (fx as u64 & m, fy as u64 & m, fz as u64 & m);
    let (x0, y0, z0) = (one - x1, one - y1, one - z1);
    // Each pair product ≤ 2^(2F) ≤ 2^24, each triple ≤ 2^36: no overflow in u64.
    let (xy00, xy10, xy01, xy11) = (x0 * y0, x1 * y0, x0 * y1, x1 * y1);
    [
        xy00 * z0,
        xy10 * z0,
        xy01 * z0,
        xy11 * z0,
        xy00 * z1,
        xy10 * z1,
        xy01 * z1,
        xy11 * z1,
    ]
}

/// Integer filter weights that sum to exactly `2^shift` (`shift ≤ 36`), the precondition of
/// every [`IntMode`](super::IntMode) kernel, guaranteed by construction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntWeights<const K: usize> {
    w: [u64; K],
    shift: u32,
}

impl IntWeights<1> {
    /// The single weight of nearest-neighbour sampling: `w = [1]`, `shift = 0`.
    pub const NEAREST: Self = Self { w: [1], shift: 0 };
}

impl IntWeights<8> {
    /// The trilinear weights of `pos` ([`trilinear_weights`] of its fractions, `shift = 3F`).
    #[inline(always)]
    pub const fn trilinear<const F: u32>(pos: super::IntPos<F>) -> Self {
        Self::trilinear_frac::<F>(pos.frac())
    }

    /// The trilinear weights of the fractions `frac` ([`trilinear_weights`], `shift = 3F`).
    #[inline(always)]
    pub const fn trilinear_frac<const F: u32>(frac: [u32; 3]) -> Self {
        Self {
            w: trilinear_weights::<F>(frac),
            shift: 3 * F,
        }
    }
}

impl<const K: usize> IntWeights<K> {
    /// The weights.
    #[inline(always)]
    pub const fn weights(&self) -> &[u64; K] {
        &self.w
    }

    /// `log2` of their sum.
    #[inline(always)]
    pub const fn shift(&self) -> u32 {
        self.shift
    }
}
