//! Integer opacity correction, table driven: `α_d = 1 − (1 − α)^(d/d′)`, `C̃_d = C̃·α_d/α`.
//!
//! The table holds `α_d` for every 8-bit opacity, `T[i] = ⌊65280·α_d(i/255) + ½⌋` (**round
//! half up** of the f64 value `−expm1(r·ln1p(−i/255))`, computed once at construction). A
//! U8.8 opacity `v = 256·i + t` reads `T[i]` and `T[i + 1]` and interpolates,
//! `α_d = ⌊(T[i]·(256 − t) + T[i+1]·t)/256 + ½⌋`, then `C̃_d = ⌊C̃·α_d/v + ½⌋` (both **round
//! half up**; `C̃_d = 0` when `v = 0`).
//!
//! Widths: `T[i]·256 < 2^24` (`u32`); `C̃·α_d ≤ 65280² < 2^32`, rounded in `u64`.
//! `C̃_d ≤ α_d`: `C̃ ≤ v` makes `C̃·α_d/v ≤ α_d`, an integer that rounding keeps.

use super::{round_half_up_div, IntSample, ONE};
use crate::error::Error;

/// Opacity correction for a fixed ratio `r = d/d′`, table driven (256 entries of `u16`).
///
/// Error bound (against the exact `α_d` and `C̃·α_d/α` of the same U8.8 input): at u8
/// opacities (`v` a multiple of 256) `α_d` within ½ U8.8 LSB (plus `1e-6` from the f64 table
/// build, `CORRECTION_INT_TABLE_LSB`). Between table points add ½ LSB of rounding and the
/// chord error of linear interpolation (`h = 1/255`): `h²/8·ONE·|r(r − 1)|·max(1, 255^(2−r))`
/// below the last interval, and `ONE·h^r·|x*^r − x*|` with `x* = r^(1/(1−r))` in the last
/// one (`correction_int_lsb(r)` in the tolerance table). For `d ≥ d′` this is a few LSB
/// (1.2 at `r = 2`, 2.3 at `r = 4` measured); for `d < d′` the steep end of
/// `1 − (1 − α)^r` near `α = 1` makes it large (about 4 levels at `r = ½`, 83 at `r = ⅛`):
/// there, feed u8 opacities or use the extinction path. `C̃_d` adds ½ LSB.
#[derive(Debug, Clone, PartialEq)]
pub struct IntCorrection {
    table: [u16; 256],
    ratio: f32,
}

impl IntCorrection {
    /// Builds the table for `ratio = d/d′`.
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `ratio` is finite and positive.
    pub fn new(ratio: f32) -> Result<Self, Error> {
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(Error::InvalidStep);
        }
        let r = f64::from(ratio);
        let mut table = [0u16; 256];
        for (i, e) in (0u32..).zip(table.iter_mut()) {
            let a = f64::from(i) / 255.0;
            // α = 1: ln1p(−1) = −∞, expm1(−∞) = −1, so α_d = 1 exactly.
            let a_d = -libm::expm1(r * libm::log1p(-a));
            let x = libm::floor(f64::from(ONE) * a_d + 0.5);
            *e = if x >= f64::from(ONE) {
                ONE
            } else if x > 0.0 {
                x as u16
            } else {
                0
            };
        }
        Ok(Self { table, ratio })
    }

    /// `d/d′`.
    pub fn ratio(&self) -> f32 {
        self.ratio
    }

    /// The table: `α_d` (U8.8) for each 8-bit opacity.
    pub fn table(&self) -> &[u16; 256] {
        &self.table
    }

    /// Corrects one sample (see the module docs for the arithmetic).
    #[inline]
    pub fn apply(&self, s: IntSample) -> IntSample {
        let v = s.a();
        let i = usize::from(v >> 8);
        let t = u32::from(v & 0xff);
        // v ≤ 65280 = 255·256, so i ≤ 255 and i = 255 only with t = 0: both reads hit.
        let lo = u32::from(self.table.get(i).copied().unwrap_or(ONE));
        let hi = u32::from(self.table.get(i + 1).copied().unwrap_or(ONE));
        let a_d = ((lo * (256 - t) + hi * t + 128) >> 8) as u16;
        let c = if v == 0 {
            [0; 3]
        } else {
            s.c()
                .map(|c| round_half_up_div(u64::from(c) * u64::from(a_d), u64::from(v)) as u16)
        };
        IntSample::from_valid(c, a_d)
    }
}
