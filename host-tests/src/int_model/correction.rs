//! Model of the table-driven integer opacity correction.

use super::{round_half_up, ONE};

/// The exact corrected opacity `1 − (1 − α)^r` for `α ∈ [0, 1]`, in `f64`.
pub fn exact_alpha(a: f64, r: f64) -> f64 {
    if a >= 1.0 {
        1.0
    } else {
        -(r * (-a).ln_1p()).exp_m1()
    }
}

/// The model of one table entry: `⌊ONE·α_d(i/255) + ½⌋` (**round half up**).
pub fn table_entry(i: u8, r: f64) -> f64 {
    round_half_up(ONE * exact_alpha(f64::from(i) / 255.0, r))
}

/// The kernel's arithmetic on a given table: `α_d = ⌊(T[i]·(256 − t) + T[i+1]·t)/256 + ½⌋`,
/// `C̃_d = ⌊C̃·α_d/v + ½⌋` (**round half up**), for U8.8 input `(c, v)`.
pub fn apply(table: &[u16; 256], c: [u16; 3], v: u16) -> ([u16; 3], u16) {
    let i = usize::from(v >> 8);
    let t = f64::from(v & 0xff);
    let lo = f64::from(table[i]);
    let hi = f64::from(table[(i + 1).min(255)]);
    let a_d = round_half_up((lo * (256.0 - t) + hi * t) / 256.0);
    let c_d = if v == 0 {
        [0.0; 3]
    } else {
        c.map(|c| round_half_up(f64::from(c) * a_d / f64::from(v)))
    };
    (c_d.map(|x| x as u16), a_d as u16)
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
