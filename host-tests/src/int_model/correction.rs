//! Model of the table-driven integer opacity correction (`fixed_point::correction`), through
//! the optical depth: `α_d = 1 − e^(−r·L)`, `L = −ln(1 − α)`.
//!
//! Tables in `f64` with `std` (`ln_1p`, `ln`), every exact intermediate as an integer
//! (`u128`) and each documented quotient rounded half up by remainder ([`rhu`]).

use super::extinction::{rhu, tables as exp_tables, Tables};
use super::{round_half_up, ONE};

/// The exact corrected opacity `1 − (1 − α)^r` for `α ∈ [0, 1]`, in `f64`.
pub fn exact_alpha(a: f64, r: f64) -> f64 {
    if a >= 1.0 {
        1.0
    } else {
        -(r * (-a).ln_1p()).exp_m1()
    }
}

/// The model's correction tables for a ratio.
#[derive(Debug, Clone, PartialEq)]
pub struct CorrTables {
    /// `⌊r·2^32 + ½⌋`.
    pub r: u64,
    /// `G[j] = ⌊2^47·ψ(128·j/ONE)/ONE + ½⌋`, `ψ(α) = −ln(1 − α)/α`.
    pub psi: Vec<u32>,
    /// `Λ[j] = ⌊2^32·ln(1 + j/256) + ½⌋`.
    pub ln_m: Vec<u32>,
    /// `K[e] = ⌊2^39·ln(ONE/2^e) + ½⌋`.
    pub ln_top: Vec<u64>,
    /// The 257-node `φ`/`e^(−x)` tables.
    pub exp: Tables,
}

/// Builds the tables for ratio `r`.
pub fn tables(r: f32) -> CorrTables {
    let psi = (0..=256u32)
        .map(|j| {
            let a = f64::from(128 * j) / ONE;
            let p = if j == 0 { 1.0 } else { -(-a).ln_1p() / a };
            round_half_up(p / ONE * 2f64.powi(47)) as u32
        })
        .collect();
    let ln_m = (0..=256u32)
        .map(|j| round_half_up((f64::from(j) / 256.0).ln_1p() * 2f64.powi(32)) as u32)
        .collect();
    let ln_top = (0..15)
        .map(|e| round_half_up((ONE / 2f64.powi(e)).ln() * 2f64.powi(39)) as u64)
        .collect();
    CorrTables {
        r: super::extinction::ratio_raw(r),
        psi,
        ln_m,
        ln_top,
        exp: exp_tables(257),
    }
}

impl CorrTables {
    fn interp(t: &[u32], j: u32) -> u128 {
        let (i, f) = ((j / 128) as usize, u128::from(j % 128));
        u128::from(t[i]) * (128 - f) + u128::from(t[i + 1]) * f
    }

    /// The model's `y = r·L` (28 fractional bits, saturated at 16) for `0 < v < ONE`.
    pub fn depth(&self, v: u16) -> u64 {
        let r = u128::from(self.r);
        let y = if v < 1 << 15 {
            rhu(
                r * u128::from(v) * Self::interp(&self.psi, u32::from(v)),
                1 << 58,
            )
        } else {
            let u = ONE as u32 - u32::from(v);
            let e = 31 - u.leading_zeros();
            let m = u * (1 << (15 - e)) - (1 << 15);
            let l = u128::from(self.ln_top[e as usize]) - Self::interp(&self.ln_m, m);
            rhu(r * l, 1 << 43)
        };
        y.min(16 << 28) as u64
    }

    /// The model's corrected opacity.
    pub fn alpha(&self, v: u16) -> u16 {
        if v == 0 {
            return 0;
        }
        if f64::from(v) >= ONE {
            return ONE as u16;
        }
        let y = self.depth(v);
        self.exp.integrate(y, [0; 3], 1, [0; 3]).1
    }

    /// The model's corrected sample: `α_d`, then `C̃_d = ⌊C̃·α_d/v + ½⌋`.
    pub fn apply(&self, c: [u16; 3], v: u16) -> ([u16; 3], u16) {
        let a = self.alpha(v);
        let c = if v == 0 {
            [0; 3]
        } else {
            c.map(|c| rhu(u128::from(c) * u128::from(a), u128::from(v)) as u16)
        };
        (c, a)
    }
}

/// The exact corrected sample (U8.8 units, unrounded): `ONE·α_d(v/ONE)` and `C̃·α_d/α`.
pub fn exact(c: [u16; 3], v: u16, r: f64) -> ([f64; 3], f64) {
    let a = f64::from(v) / ONE;
    let a_d = exact_alpha(a, r);
    let c_d = if v == 0 {
        [0.0; 3]
    } else {
        c.map(|c| f64::from(c) * a_d / a)
    };
    (c_d, ONE * a_d)
}
