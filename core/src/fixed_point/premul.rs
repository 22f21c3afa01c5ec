//! Premultiplication to `u8` storage and back, and its limit (Wittenbrink §7).
//!
//! Storing an associated color `C̃ = α·C` in 8 bits rounds it by up to ½ level; dividing
//! `α_F/255` back out multiplies that error by `255/α_F`. For byte `C` and opacity byte
//! `α_F ≥ 1`, with `C̃_F = premultiply(C, α_F)`:
//!
//! * the exactly recovered color `255·C̃_F/α_F` is within `0.5·255/α_F` of `C`, and the bound
//!   is reached within rounding: 127 at `α_F = 1` (`PREMUL_RECOVERY` in the tolerance table);
//! * [`unpremultiply`] rounds that quotient once more, so its byte is within
//!   `⌊0.5·255/α_F + ½⌋` of `C`.
//!
//! [`OpacityWeighted`](crate::OpacityWeighted) from straight storage does not have this limit:
//! the color is never stored premultiplied and its samples carry 8 more fractional bits.

use crate::voxel::{AssociatedU8, StraightU8};

/// `C̃_F = ⌊C·α_F/255 + ½⌋` (**round half up**, the paper's `Int(C̃·255 + 0.5)`).
///
/// Error bound: within ½ level of `C·α_F/255`. Never exceeds `α_F`.
#[inline(always)]
pub const fn premultiply(c: u8, a: u8) -> u8 {
    // 2·255·255 + 255 < 2^17: no overflow in u32; the quotient is ≤ a ≤ 255.
    ((2 * c as u32 * a as u32 + 255) / 510) as u8
}

/// The straight color of a premultiplied byte: `⌊255·C̃_F/α_F + ½⌋` (**round half up**),
/// **saturated** to 255 when `C̃_F > α_F` (not a valid associated byte); 0 when `α_F = 0`.
///
/// Error bound (for `C̃_F = premultiply(C, α_F)`): within `⌊0.5·255/α_F + ½⌋` of `C`, i.e. 127
/// levels at `α_F = 1` and 0 at `α_F = 255` (`PREMUL_RECOVERY` in the tolerance table).
#[inline(always)]
pub const fn unpremultiply(c: u8, a: u8) -> u8 {
    if a == 0 {
        return 0;
    }
    // 2·255·255 + 255 < 2^17: no overflow in u32.
    let q = (2 * 255 * c as u32 + a as u32) / (2 * a as u32);
    if q > 255 {
        255
    } else {
        q as u8
    }
}

/// Premultiplies each color channel of a straight voxel ([`premultiply`]); `α` is kept.
#[inline]
pub const fn premultiply_voxel(v: StraightU8) -> AssociatedU8 {
    let [r, g, b, a] = v.0;
    AssociatedU8([premultiply(r, a), premultiply(g, a), premultiply(b, a), a])
}
