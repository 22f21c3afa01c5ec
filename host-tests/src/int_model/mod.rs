//! `f64` models of the integer kernels in `volsample::fixed_point`, written from their
//! documented arithmetic: each model computes the exact (real-number) result of the method in
//! `f64`, then applies the kernel's named rounding (**round half up** `⌊x + ½⌋`) to it.
//!
//! Exactness (why an `f64` model can be bit-exact): every sum below is a dyadic rational with
//! at most 52 significant bits (weights have `3F ≤ 36` fractional bits, voxel products are
//! below `2^16`), so it is exact in `f64`; each model then divides once, by 255 or 65280, and
//! the correctly rounded quotient `q` cannot reach or cross a rounding tie `k + ½`: the
//! distance of an exact quotient `N/D` to a tie it is not on is at least `1/(2D)`, which is
//! larger than half an ulp of `q` for every divisor used (at worst `1/(510·2^28) > 2^−37`
//! against half an ulp of `2^−38` for `F = 12`).
//!
//! The unrounded value each model returns is the "exact result of the same method" against
//! which the kernels' error bounds (`tolerance::integer`) are measured.
//!
//! The extinction path and the opacity correction ([`extinction`], [`correction`]) have sums
//! and products too wide for an exact `f64` (up to 126 bits); their models keep those
//! intermediates as exact integers and say so.

pub mod composite;
pub mod correction;
pub mod downsample;
pub mod extinction;
pub mod premul;
pub mod sample;

/// Full scale of a U8.8 value (opacity 1).
pub const ONE: f64 = 65280.0;

/// **Round half up**, `⌊x + ½⌋`, computed without the rounding of `x + ½`
/// (`x − ⌊x⌋` is exact in `f64`).
pub fn round_half_up(x: f64) -> f64 {
    let f = x.floor();
    if x - f >= 0.5 {
        f + 1.0
    } else {
        f
    }
}

/// The integer weights of a filter as real numbers summing to 1 (exact in `f64`).
///
/// Trilinear at fractions `frac` (each `< 2^F`): per axis `(1 − f/2^F, f/2^F)`, product of the
/// three axes, corner `i` at `(i & 1, (i >> 1) & 1, i >> 2)`. Nearest: the single weight 1.
pub fn trilinear_weights(frac_bits: u32, frac: [u32; 3]) -> [f64; 8] {
    let s = f64::from(1u32 << frac_bits);
    let p = frac.map(|f| {
        let t = f64::from(f) / s;
        [1.0 - t, t]
    });
    std::array::from_fn(|i| p[0][i & 1] * p[1][(i >> 1) & 1] * p[2][i >> 2])
}

/// A model's result: the exact U8.8 values of the method and the kernel's rounded ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modelled {
    /// Exact associated color `C̃` (U8.8 units, unrounded).
    pub exact_c: [f64; 3],
    /// Exact opacity (U8.8 units, unrounded).
    pub exact_a: f64,
    /// The rounded values the kernel must produce.
    pub c: [u16; 3],
    /// The rounded opacity the kernel must produce.
    pub a: u16,
}

/// `x` as a `u16`, panicking if the model produced something a U8.8 channel cannot hold
/// (that would be a model bug, and the tests should say so).
pub fn to_u16(x: f64) -> u16 {
    assert!(
        (0.0..=65535.0).contains(&x) && x.fract() == 0.0,
        "model value {x} is not a u16"
    );
    x as u16
}
