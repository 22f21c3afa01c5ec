//! Models of `u8` premultiplication and its inverse.

use super::round_half_up;

/// `⌊C·α/255 + ½⌋` (**round half up**).
pub fn premultiply(c: u8, a: u8) -> u8 {
    round_half_up(f64::from(c) * f64::from(a) / 255.0) as u8
}

/// `min(255, ⌊255·C̃/α + ½⌋)` (**round half up**, **saturate**); 0 when `α = 0`.
pub fn unpremultiply(c: u8, a: u8) -> u8 {
    if a == 0 {
        return 0;
    }
    round_half_up(255.0 * f64::from(c) / f64::from(a)).min(255.0) as u8
}

/// The color recovered from premultiplied storage without further rounding,
/// `255·premultiply(C, α)/α` (levels), and its error against `C`.
pub fn recovery_error(c: u8, a: u8) -> f64 {
    (255.0 * f64::from(premultiply(c, a)) / f64::from(a) - f64::from(c)).abs()
}

/// The §7 bound on [`recovery_error`]: `0.5·255/α`.
pub fn recovery_bound(a: u8) -> f64 {
    0.5 * 255.0 / f64::from(a)
}
