//! The arithmetic the generic interpolation kernels are written against.
//!
//! The float kernels run with `f32`; the host reference and the operation-counting tests run
//! the *same* generic code with `f64` and with a counting type. Only `+`, `−` and `×` are used
//! by the interpolation kernels, so [`Num`] asks for nothing else.

use core::ops::{Add, Mul, Sub};

/// A number the generic interpolation kernels can run on.
///
/// Implemented for `f32` and `f64`; a test can implement it for a type that counts
/// operations (that is how the operation counts of Wittenbrink's Table 1 are reproduced).
pub trait Num: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
    /// Additive identity.
    const ZERO: Self;
    /// Multiplicative identity.
    const ONE: Self;
    /// Conversion from `f32` (voxel values, fractions); not counted as an operation.
    fn from_f32(x: f32) -> Self;
}

impl Num for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        x
    }
}

impl Num for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        f64::from(x)
    }
}
