//! Integer opacity correction, table driven: `α_d = 1 − (1 − α)^r` with `r = d/d′`,
//! `C̃_d = C̃·α_d/α`.
//!
//! The correction is computed through the optical depth, `α_d = 1 − e^(−r·L)` with
//! `L = −ln(1 − α)`, so that no table has to follow the steep end of `1 − (1 − α)^r` near
//! `α = 1` (for `r < 1`) or near `α = 0` (for `r > 1`): every table below samples a smooth
//! function, and the error of `α_d` does not depend on `r`.
//!
//! For a U8.8 opacity `v` (`α = v/ONE`), `k = 7` fraction bits and 257-entry tables:
//!
//! 1. `v = 0`: `α_d = 0`; `v = ONE`: `α_d = ONE` (exactly; `C̃_d = C̃`).
//! 2. `v < 2^15` (`α < 0.502`): `L = α·ψ(α)` with `ψ(α) = −ln(1 − α)/α`, tabulated at
//!    `v_j = 128·j` as `G[j] = ⌊2^47·ψ(v_j/ONE)/ONE + ½⌋` and interpolated exactly,
//!    `L = v·(G[i]·(128 − f) + G[i+1]·f)/2^54` (`i = v >> 7`, `f = v mod 128`). Relative
//!    accuracy of `L` is what matters, and `ψ` is smooth and `≥ 1` here.
//! 3. `v ≥ 2^15`: with the transmittance `u = ONE − v` (`1 ≤ u < 2^15`) written with a
//!    normalised exponent, `u = 2^e·m`, `m ∈ [1, 2)`:
//!    `L = ln(ONE/2^e) − ln m`, with `K[e] = ⌊2^39·ln(ONE/2^e) + ½⌋` and the `ln m` table
//!    `Λ[j] = ⌊2^32·ln(1 + j/256) + ½⌋` interpolated exactly on the 15-bit mantissa
//!    `u·2^(15−e)` (units `2^−39`). Here `L ≥ ln(65280/32512) > 0.69`.
//! 4. `y = r·L` to 28 fractional bits, **round half up** (`u128`), **saturated** at 16;
//!    then as in the extinction kernel ([`exp_phi`](super::exp_phi), 257-entry tables):
//!    `α_d = ⌊ONE·y·φ̂(y) + ½⌋` for `y < 1`, `α_d = ⌊ONE·(1 − ê(y)) + ½⌋` for
//!    `1 ≤ y < 16`, `α_d = ONE` for `y ≥ 16` (all **round half up** of exact products).
//! 5. `C̃_d = ⌊C̃·α_d/v + ½⌋` (**round half up**; `u64`).
//!
//! Widths: `r_raw·v·PG < 2^64·2^15·2^39` and `r_raw·L_raw < 2^64·2^43` (`u128`);
//! `C̃·α_d ≤ 65280²`. `C̃_d ≤ α_d`: `C̃ ≤ v` makes `C̃·α_d/v ≤ α_d`, an integer that rounding
//! keeps.

use super::exp_phi::{
    round_half_up_shift128, round_scaled, ExtinctionTables, IntRatio, ARG_FRAC_BITS, ARG_SATURATED,
    EXP_INT_FRAC_BITS, RATIO_FRAC_BITS, TABLE_FRAC_BITS,
};
use super::{round_half_up_div, IntSample, ONE};
use crate::error::Error;

/// Entries of each correction table (`2^8 + 1`).
pub const CORRECTION_TABLE_LEN: usize = 257;
/// `U8.8` opacities below this use the `ψ` table; at or above it, the `ln m` table.
pub const PSI_LIMIT: u16 = 1 << 15;
/// Fraction bits below a table index (`2^15/2^8`).
const K: u32 = 7;
/// Fractional bits of a `G` entry (`ψ/ONE`) and of `K[e]`, `Λ` interpolated.
const G_FRAC_BITS: u32 = 47;
const LN_FRAC_BITS: u32 = 32;

/// Opacity correction for a fixed ratio `r = d/d′`, table driven through the optical depth
/// (see the module docs for the arithmetic).
///
/// Error bound (against the exact `α_d = 1 − (1 − α)^r` and `C̃·α_d/α` of the same U8.8
/// input and the given `f32` ratio), the same for every `r`: `α_d` within
/// `½ + 0.066 + 0.046 + 0.01 = 0.622` U8.8 LSB (`CORRECTION_INT_LSB` in the tolerance
/// table), and each `C̃_d` within ½ LSB more. The terms: the final rounding; `L`'s relative
/// error (at most `2.74·10^−6`: `ln m` chord `h²/8`, `h = 1/256`, over `L ≥ 0.69`; the `ψ`
/// chord is smaller) times `max y·e^(−y) = 1/e`; the `φ`/`e^(−x)` tables' chord error
/// (`h²/(8e)`); and the entry, `y` and ratio quantization and the `e^(−16)` tail. (The
/// former table on `α` reached 1023 LSB at `r = ½`.)
///
/// Size: about 4.3 KiB, all tables but the ratio independent of `r`.
#[derive(Debug, Clone, PartialEq)]
pub struct IntCorrection {
    ratio: f32,
    r: IntRatio,
    psi: [u32; CORRECTION_TABLE_LEN],
    ln_m: [u32; CORRECTION_TABLE_LEN],
    ln_top: [u64; 15],
    tables: ExtinctionTables<CORRECTION_TABLE_LEN>,
}

impl IntCorrection {
    /// Builds the tables for `ratio = d/d′` (`f64` arithmetic, one **round half up** per
    /// entry).
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `ratio` is finite, positive and below `2^32`.
    pub fn new(ratio: f32) -> Result<Self, Error> {
        let r = IntRatio::new(ratio)?;
        let one = f64::from(ONE);
        let mut psi = [0u32; CORRECTION_TABLE_LEN];
        let mut ln_m = [0u32; CORRECTION_TABLE_LEN];
        for (j, (p, l)) in (0u32..).zip(psi.iter_mut().zip(ln_m.iter_mut())) {
            let a = f64::from(j << K) / one;
            let ps = if j == 0 { 1.0 } else { -libm::log1p(-a) / a };
            // ψ ≤ 1.39 on [0, 0.502]: 2^47·ψ/ONE < 2^32.
            *p = round_scaled(ps / one, G_FRAC_BITS as i32) as u32;
            // ln(1 + j/256) ≤ ln 2 < 1.
            *l = round_scaled(
                libm::log1p(libm::ldexp(f64::from(j), -8)),
                LN_FRAC_BITS as i32,
            ) as u32;
        }
        let mut ln_top = [0u64; 15];
        for (e, t) in (0i32..).zip(ln_top.iter_mut()) {
            // ln(ONE/2^e) ≤ 11.09 < 2^4: below 2^43.
            *t = round_scaled(libm::log(libm::ldexp(one, -e)), (LN_FRAC_BITS + K) as i32);
        }
        Ok(Self {
            ratio,
            r,
            psi,
            ln_m,
            ln_top,
            tables: ExtinctionTables::new(),
        })
    }

    /// `d/d′` as given.
    pub fn ratio(&self) -> f32 {
        self.ratio
    }

    /// `d/d′` quantized.
    pub fn int_ratio(&self) -> IntRatio {
        self.r
    }

    /// `α_d` (U8.8) at each 8-bit opacity: `[alpha(256·i) for i in 0..256]` (for reference
    /// vectors; the kernel does not read it).
    pub fn table(&self) -> [u16; 256] {
        let mut t = [0u16; 256];
        for (i, e) in (0u16..).zip(t.iter_mut()) {
            *e = self.alpha(i * 256);
        }
        t
    }

    /// The `ψ` table, `G[j] = ⌊2^47·ψ(128·j/ONE)/ONE + ½⌋`.
    pub fn psi_table(&self) -> &[u32; CORRECTION_TABLE_LEN] {
        &self.psi
    }

    /// The `ln m` table, `Λ[j] = ⌊2^32·ln(1 + j/256) + ½⌋`.
    pub fn ln_table(&self) -> &[u32; CORRECTION_TABLE_LEN] {
        &self.ln_m
    }

    /// `K[e] = ⌊2^39·ln(ONE/2^e) + ½⌋` for `e = 0..15`.
    pub fn ln_top(&self) -> &[u64; 15] {
        &self.ln_top
    }

    /// The `φ` and `e^(−x)` tables of step 4.
    pub fn exp_tables(&self) -> &ExtinctionTables<CORRECTION_TABLE_LEN> {
        &self.tables
    }

    #[inline(always)]
    fn interp(table: &[u32; CORRECTION_TABLE_LEN], j: u32) -> u64 {
        let i = (j >> K) as usize;
        let f = u64::from(j & ((1 << K) - 1));
        // j < 2^15 gives i ≤ 255: both reads hit.
        let lo = u64::from(table.get(i).copied().unwrap_or(0));
        let hi = u64::from(table.get(i + 1).copied().unwrap_or(0));
        lo * ((1 << K) - f) + hi * f
    }

    /// `y = r·L` to 28 fractional bits (**round half up**, **saturated** at 16) for
    /// `0 < v < ONE`.
    #[inline(always)]
    fn depth(&self, v: u16) -> u64 {
        let r = u128::from(self.r.raw());
        let y = if v < PSI_LIMIT {
            // L = v·PG/2^(47+7); r·L in units 2^−28: shift 32 + 54 − 28.
            let pg = Self::interp(&self.psi, u32::from(v));
            round_half_up_shift128(
                r * u128::from(v) * u128::from(pg),
                RATIO_FRAC_BITS + G_FRAC_BITS + K - ARG_FRAC_BITS,
            )
        } else {
            let u = u32::from(ONE - v);
            // 1 ≤ u < 2^15: e = ⌊log2 u⌋ ∈ 0..=14, mantissa u·2^(15−e) ∈ [2^15, 2^16).
            let e = 31 - u.leading_zeros().min(31);
            let m = (u << (15 - e)) - (1 << 15);
            let top = self.ln_top.get(e as usize).copied().unwrap_or(0);
            let l = top.saturating_sub(Self::interp(&self.ln_m, m));
            round_half_up_shift128(
                r * u128::from(l),
                RATIO_FRAC_BITS + LN_FRAC_BITS + K - ARG_FRAC_BITS,
            )
        };
        if y >= u128::from(ARG_SATURATED) {
            ARG_SATURATED
        } else {
            y as u64
        }
    }

    /// The corrected opacity of a U8.8 opacity `v ≤ ONE` (steps 1–4 of the module docs).
    #[inline]
    pub fn alpha(&self, v: u16) -> u16 {
        if v == 0 {
            return 0;
        }
        if v >= ONE {
            return ONE;
        }
        let y = self.depth(v);
        let one = u128::from(ONE);
        let k = self.tables.interp_bits();
        if y < 1 << ARG_FRAC_BITS {
            let p = u128::from(self.tables.phi_interp(y));
            round_half_up_shift128(one * u128::from(y) * p, ARG_FRAC_BITS + TABLE_FRAC_BITS + k)
                as u16
        } else {
            let s = EXP_INT_FRAC_BITS + TABLE_FRAC_BITS + k;
            let q = self.tables.exp_neg_interp(y).min(1u128 << s);
            round_half_up_shift128(one * ((1u128 << s) - q), s) as u16
        }
    }

    /// Corrects one sample (see the module docs for the arithmetic).
    #[inline]
    pub fn apply(&self, s: IntSample) -> IntSample {
        let v = s.a();
        let a_d = self.alpha(v);
        let c = if v == 0 {
            [0; 3]
        } else {
            s.c()
                .map(|c| round_half_up_div(u64::from(c) * u64::from(a_d), u64::from(v)) as u16)
        };
        IntSample::from_valid(c, a_d)
    }
}
