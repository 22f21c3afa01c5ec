//! Bounds of the hard-case catalog (`tests/hard_cases`): where a kernel's general bound is
//! absolute on `[0, 1]` and says nothing at the edges (faint samples, subnormals, extreme
//! ratios, very long rays), these state what the kernels keep there.
//!
//! `ε = 2⁻²³` ([`EPS32`]); `u = ε/2` is the unit roundoff.

use super::EPS32;

/// Half the smallest subnormal `f32`, `2⁻¹⁵⁰`: the absolute rounding of one operation whose
/// result is subnormal. Relative bounds below carry this as a floor per operation.
pub const SUBNORMAL_FLOOR: f64 = 7.006_492_321_624_085e-46; // 2^-150

/// [`volsample::opacity::correct`], relative error of `α_d` and of each `C̃_d` against the
/// exact `1 − (1 − α)^r` and `C̃·α_d/α` of the same `f32` input, for every `α ∈ [0, 1]` and
/// every ratio `r` the stage accepts (`10⁻⁶ … 10³⁸` tested): `log1p`, the product `r·L`,
/// `expm1` (each ≤ 1 ulp, `x·e^(−x)/(1 − e^(−x)) ≤ 1` keeps the product's error relative),
/// and for `C̃_d` the gain `r·φ(x)·ψ(α)` or `α_d·(C̃/α)`, 4 more roundings: `12ε`, plus
/// [`SUBNORMAL_FLOOR`] per operation where a result is subnormal.
pub const CORRECTION_REL: f64 = 12.0 * EPS32;

/// [`volsample::mode::integrate_step`], relative error of `α` and each `C̃` against the
/// exact step of the same `f32` input (the absolute bound is `INTEGRATE_STEP_ABS`): `τ·d`
/// (½ ulp, passed on with a factor `x·e^(−x)/(1 − e^(−x)) ≤ 1`), `expm1` (1 ulp), and for
/// `C̃` either `d·φ(x)` (`φ` within `PHI_REL = 4ε`) and the product, or `C^τ/τ` and the
/// product with `α`: `8ε`, plus [`SUBNORMAL_FLOOR`] per operation with a subnormal result.
pub const INTEGRATE_STEP_REL: f64 = 8.0 * EPS32;

/// Unit roundoff of `f32`, `u = 2⁻²⁴`.
const U32: f64 = EPS32 / 2.0;

/// Front-to-back or back-to-front compositing of `n` samples of opacity at most `α_max`:
/// the accumulated `A` is within `n·LONG_RAY_A_PER_SAMPLE·(1 + 3α_max)` of the exact
/// composite (see `tests/hard_cases/long_rays.rs` for the derivation): linear in `n`.
pub const LONG_RAY_A_PER_SAMPLE: f64 = U32;

/// …and each accumulated `C̃` within `n·LONG_RAY_C_PER_SAMPLE·(1 + 3α_max)`: its own
/// roundings plus what it inherits from `A`'s.
pub const LONG_RAY_C_PER_SAMPLE: f64 = 2.0 * U32;

/// One opacity-based downsampling level of a *uniform* volume, relative error of `α′` and
/// `C̃′`: the filter reproduces a constant exactly, then `ᾱ·(2 − ᾱ)` and `C̄·(2 − ᾱ)` round
/// twice (`2u`), plus [`SUBNORMAL_FLOOR`] per operation with a subnormal result.
pub const DOWNSAMPLE_UNIFORM_REL: f64 = EPS32;
