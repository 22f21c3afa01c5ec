//! The one tolerance table: every error bound a doc comment states, as a named constant the
//! tests hold the kernels to.
//!
//! Float bounds are absolute errors on values in `[0, 1]` (opacity, associated color) unless
//! the name says ulp. Integer bounds (in [`integer`]) are in output LSBs.
//!
//! A bound here is a promise made in the kernel's doc comment; a test that measures a larger
//! error fails, and the closing notes quote the worst error observed next to the bound.

/// `f32` machine epsilon as `f64`, the unit the float bounds are built from.
pub const EPS32: f64 = f32::EPSILON as f64;
