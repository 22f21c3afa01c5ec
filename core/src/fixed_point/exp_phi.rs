//! Table-driven `e^(−x)` and `φ(x) = (1 − e^(−x))/x` for the integer extinction path, and
//! the fixed-point step ratio `r = d/d′`.
//!
//! # Formats
//!
//! | quantity | format | meaning |
//! |---|---|---|
//! | argument `x` (optical depth of one step) | `u64`, [`ARG_FRAC_BITS`] `= 28` fractional bits | `raw/2^28`, **saturated** at `16·2^28` |
//! | table entry `φ(x_j)`, `e^(−x_j)` | `u32`, [`TABLE_FRAC_BITS`] `= 31` fractional bits | `raw/2^31` (1 is `2^31`) |
//! | `e^(−n)`, `n = 1..=15` | `u32`, [`EXP_INT_FRAC_BITS`] `= 32` fractional bits | `raw/2^32` |
//! | step ratio [`IntRatio`] | `u64`, [`RATIO_FRAC_BITS`] `= 32` fractional bits | `raw/2^32`, `r < 2^32` |
//!
//! # The tables
//!
//! [`ExtinctionTables<N>`] holds `φ` and `e^(−x)` at the `N = 2^B + 1` nodes `x_j = j/2^B` of
//! `[0, 1]` (`B` = [`ExtinctionTables::INTERVAL_BITS`], `2 ≤ B ≤ 16`, checked at compile time),
//! each entry `⌊2^31·f(x_j) + ½⌋` (**round half up** of the `f64` value, computed once by
//! [`ExtinctionTables::new`]), plus `e^(−n)` for the integer parts `n = 1..=15`, each
//! `⌊2^32·e^(−n) + ½⌋`.
//!
//! With `k = 28 − B`, an argument `x < 1` reads node `i = raw >> k` and the fraction
//! `f = raw mod 2^k`, and the interpolated value is the exact integer
//! `P = T[i]·(2^k − f) + T[i+1]·f` (in units of `2^−(31+k)`; `P ≤ 2^(31+k) ≤ 2^58`, `u64`).
//! For `x ≥ 1`, `e^(−x) = e^(−n)·e^(−t)` with `n = ⌊x⌋` and `t = x − n` read from the
//! `e^(−t)` table the same way; `x ≥ 16` reads `e^(−x)` as 0 (it is below `1.2·10^−7`, under
//! 0.008 U8.8 LSB). No rounding happens here: the callers round once, at the end.
//!
//! Linear interpolation error (chord) with `h = 2^−B`: at most `h²/8·max|f''|`, i.e. `h²/24`
//! for `φ` on `[0, 1]` and `h²/8·e^(−n)` for `e^(−n−t)`. The table size `N` is the knob that
//! trades memory for accuracy: `N = 257` (2 KiB) keeps each term under 0.05 U8.8 LSB.

use crate::error::Error;

/// Fractional bits of a step's optical depth `x` (the argument of the tables).
pub const ARG_FRAC_BITS: u32 = 28;
/// Fractional bits of a `φ` or `e^(−t)` table entry.
pub const TABLE_FRAC_BITS: u32 = 31;
/// Fractional bits of an `e^(−n)` entry.
pub const EXP_INT_FRAC_BITS: u32 = 32;
/// Arguments `x ≥ ARG_LIMIT` read `e^(−x)` as 0 (and are **saturated** to this value).
pub const ARG_LIMIT: u32 = 16;
/// The saturated argument, `ARG_LIMIT·2^ARG_FRAC_BITS`.
pub const ARG_SATURATED: u64 = (ARG_LIMIT as u64) << ARG_FRAC_BITS;
/// Fractional bits of an [`IntRatio`].
pub const RATIO_FRAC_BITS: u32 = 32;

/// **Round half up** of `n/2^s` in `u128`: `(n + 2^(s−1)) >> s` (`n` for `s = 0`).
///
/// Exact for `n < 2^127` and `1 ≤ s < 128`; the addition saturates outside that domain and
/// `s ≥ 128` gives 0 (never reached: every caller proves `n < 2^127`, `s < 128`).
#[inline(always)]
pub(crate) const fn round_half_up_shift128(n: u128, s: u32) -> u128 {
    if s == 0 {
        n
    } else if s >= 128 {
        0
    } else {
        n.saturating_add(1 << (s - 1)) >> s
    }
}

/// **Round half up** of `n/d` in `u128`: `⌊(2n + d)/(2d)⌋`; exact for `n, d < 2^126`,
/// saturating outside, and 0 for `d = 0` (never reached).
#[inline(always)]
pub(crate) const fn round_half_up_div128(n: u128, d: u128) -> u128 {
    let num = n.saturating_mul(2).saturating_add(d);
    match num.checked_div(d.saturating_mul(2)) {
        Some(q) => q,
        None => 0,
    }
}

/// `⌊v·2^s + ½⌋` for a finite `v ≥ 0` with `v·2^s < 2^52` (**round half up**; `v·2^s` and the
/// added `½` are exact in `f64`). Used to build tables.
#[inline]
pub(crate) fn round_scaled(v: f64, s: i32) -> u64 {
    let x = libm::floor(libm::ldexp(v, s) + 0.5);
    if x > 0.0 {
        x as u64
    } else {
        0
    }
}

/// The step ratio `r = d/d′` in fixed point: `raw = ⌊r·2^32 + ½⌋` (**round half up**), so
/// `|r − raw/2^32| ≤ 2^−33`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IntRatio {
    raw: u64,
}

impl IntRatio {
    /// The quantized ratio as a `fixed` U32.32 number (the same bits as the kernel uses).
    /// With the feature `fixed` (on by default).
    #[cfg(feature = "fixed")]
    pub fn to_fixed(&self) -> fixed::types::U32F32 {
        fixed::types::U32F32::from_bits(self.raw)
    }

    /// Quantizes `ratio = d/d′`. A ratio below `2^−33` quantizes to 0 (every integer step then
    /// has zero optical depth, within 0.001 LSB of the exact result).
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `ratio` is finite, positive and below `2^32`.
    pub fn new(ratio: f32) -> Result<Self, Error> {
        if !(ratio.is_finite() && ratio > 0.0 && ratio < 4_294_967_296.0) {
            return Err(Error::InvalidStep);
        }
        // r·2^32 < 2^64 is exact in f64; when it is ≥ 2^52 it is already an integer (an f32
        // has 24 significant bits), so adding ½ and flooring returns it unchanged.
        let x = libm::floor(libm::ldexp(f64::from(ratio), RATIO_FRAC_BITS as i32) + 0.5);
        Ok(Self {
            raw: if x >= 18_446_744_073_709_551_615.0 {
                u64::MAX
            } else {
                x as u64
            },
        })
    }

    /// The raw value (`RATIO_FRAC_BITS` fractional bits).
    #[inline(always)]
    pub const fn raw(&self) -> u64 {
        self.raw
    }
}

/// The `φ` and `e^(−x)` tables with `N = 2^B + 1` nodes on `[0, 1]` (see the module docs).
///
/// `N` must be `2^B + 1` with `2 ≤ B ≤ 16` (5, 9, 17, …, 65537); anything else is a
/// compile-time error:
///
/// ```compile_fail
/// let _ = volsample::fixed_point::ExtinctionTables::<256>::new();
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExtinctionTables<const N: usize> {
    phi: [u32; N],
    exp: [u32; N],
    exp_int: [u32; 15],
}

impl<const N: usize> ExtinctionTables<N> {
    /// `B = log2(N − 1)`: the table has `2^B` intervals.
    pub const INTERVAL_BITS: u32 = {
        assert!(
            N >= 5 && (N - 1).is_power_of_two() && N - 1 <= 1 << 16,
            "N must be 2^B + 1 with 2 <= B <= 16"
        );
        (N - 1).trailing_zeros()
    };

    /// `k = 28 − B`: the argument bits below a table index.
    const FRAC_BITS: u32 = ARG_FRAC_BITS - Self::INTERVAL_BITS;

    /// Builds the tables (`f64` arithmetic, one **round half up** per entry; see the module
    /// docs).
    pub fn new() -> Self {
        let b = Self::INTERVAL_BITS as i32;
        let mut phi = [0u32; N];
        let mut exp = [0u32; N];
        for (j, (p, e)) in (0u32..).zip(phi.iter_mut().zip(exp.iter_mut())) {
            let x = libm::ldexp(f64::from(j), -b);
            let ph = if j == 0 { 1.0 } else { -libm::expm1(-x) / x };
            // Both values lie in (0, 1], so each entry is at most 2^31.
            *p = round_scaled(ph, TABLE_FRAC_BITS as i32) as u32;
            *e = round_scaled(libm::exp(-x), TABLE_FRAC_BITS as i32) as u32;
        }
        let mut exp_int = [0u32; 15];
        for (n, e) in (1u32..).zip(exp_int.iter_mut()) {
            // e^(−n) ≤ e^(−1) < 2^−1, so each entry is below 2^31.
            *e = round_scaled(libm::exp(-f64::from(n)), EXP_INT_FRAC_BITS as i32) as u32;
        }
        Self { phi, exp, exp_int }
    }

    /// The `φ` table, `⌊2^31·φ(j/2^B) + ½⌋`.
    pub fn phi(&self) -> &[u32; N] {
        &self.phi
    }

    /// The `e^(−t)` table, `⌊2^31·e^(−j/2^B) + ½⌋`.
    pub fn exp(&self) -> &[u32; N] {
        &self.exp
    }

    /// `⌊2^32·e^(−n) + ½⌋` for `n = 1..=15` (index `n − 1`).
    pub fn exp_int(&self) -> &[u32; 15] {
        &self.exp_int
    }

    /// `k = 28 − B`: interpolated values are in units of `2^−(31+k)`.
    #[inline(always)]
    pub const fn interp_bits(&self) -> u32 {
        Self::FRAC_BITS
    }

    /// Linear interpolation of `table` at `t < 2^28` (units `2^−28`): the exact integer
    /// `T[i]·(2^k − f) + T[i+1]·f`, `≤ 2^(31+k)`.
    #[inline(always)]
    fn interp(table: &[u32; N], t: u64) -> u64 {
        let k = Self::FRAC_BITS;
        let i = (t >> k) as usize;
        let f = t & ((1 << k) - 1);
        // t < 2^28 gives i ≤ 2^B − 1 = N − 2, so both reads hit.
        let lo = u64::from(table.get(i).copied().unwrap_or(0));
        let hi = u64::from(table.get(i + 1).copied().unwrap_or(0));
        lo * ((1 << k) - f) + hi * f
    }

    /// `φ(x)` for `x = x_raw/2^28 < 1`, interpolated: `P/2^(31+k)` with `P` returned.
    #[inline(always)]
    pub fn phi_interp(&self, x_raw: u64) -> u64 {
        Self::interp(&self.phi, x_raw & ((1 << ARG_FRAC_BITS) - 1))
    }

    /// `e^(−x)` for `1 ≤ x = x_raw/2^28`, as the exact product `e^(−n)·e^(−t)` of the two
    /// tables: `Q/2^(63+k)` with `Q < 2^(63+k)` returned; `Q = 0` for `x ≥ 16` (and for
    /// `x < 1`, where the callers use [`phi_interp`](Self::phi_interp) instead).
    #[inline(always)]
    pub fn exp_neg_interp(&self, x_raw: u64) -> u128 {
        let n = x_raw >> ARG_FRAC_BITS;
        if n == 0 || n >= u64::from(ARG_LIMIT) {
            return 0;
        }
        let e_n = self.exp_int.get((n - 1) as usize).copied().unwrap_or(0);
        let p = Self::interp(&self.exp, x_raw & ((1 << ARG_FRAC_BITS) - 1));
        // e_n < 2^31 (n ≥ 1) and p ≤ 2^(31+k): the product is below 2^(62+k).
        u128::from(e_n) * u128::from(p)
    }
}

impl<const N: usize> Default for ExtinctionTables<N> {
    fn default() -> Self {
        Self::new()
    }
}
