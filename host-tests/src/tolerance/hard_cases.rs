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
/// (½ ulp, passed on with a factor `x·e^(−x)/(1 − e^(−x)) ≤ 1`); below `τd = 1`
/// `φ = phi_poly(x)` (within `PHI_POLY_REL = 2ε`), `α = x·φ` and `C̃ = C^τ·(d·φ)` (two
/// roundings each); from 1 on `expm1` (1 ulp) and `C̃ = (C^τ/τ)·α` (two roundings): `8ε`,
/// plus [`SUBNORMAL_FLOOR`] per operation with a subnormal result.
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

// ---------------------------------------------------------------------------------------------
// Integer long rays (`fixed_point::front_to_back`, `IntRayMarcher`), in U8.8 LSB.

/// The integer front-to-back compositor over `n` samples whose opacities are at least
/// `x_min` U8.8 LSB: the accumulated `A` against the exact composite of the same samples.
///
/// The compositor's proof (`fixed_point::composite`): the transmittance error follows
/// `e_(k+1) = e_k·(1 − q_k) − r_k` with `q_k = x_k/ONE` and `|r_k| ≤ ½` (round half up), so
/// `|e_n| ≤ ½·Σ_(j<n) (1 − q_min)^j = ½·(1 − (1 − q_min)^n)/q_min`: at most the documented
/// `n/2` ([`COMPOSITE_INT_A_LSB_PER_STEP`](super::integer::COMPOSITE_INT_A_LSB_PER_STEP)), and
/// at most `ONE/(2·x_min)` however long the ray. The second is reached: once
/// `T·x < ONE/2` every increment rounds to 0 and a faint ray **stalls** at
/// `T ≈ ONE/(2x)` — half of full scale at `x = 1` LSB.
pub fn int_compositor_a_lsb(n: u64, x_min: u16) -> f64 {
    let half_n = 0.5 * n as f64;
    if x_min == 0 {
        return half_n;
    }
    let q = f64::from(x_min) / 65280.0;
    // 1 − (1 − q)^n = −expm1(n·ln1p(−q)), stable for tiny q.
    let reached = -((n as f64) * (-q).ln_1p()).exp_m1();
    (0.5 * reached / q).min(half_n)
}

/// An integer ray of `n` samples against the exact `ONE·(1 − e^(−Στd))` of its data, the
/// per-sample opacities exact `p_k` (at least `p_min`) and as the integer pipeline samples
/// them `x_k = ONE·q_k` (at least `x_min`), `|x_k − ONE·p_k| ≤ delta` LSB (the sampler's and
/// the correction's rounding): the compositor's [`int_compositor_a_lsb`] plus what the
/// samples' rounding does to the transmittance, `|Π(1 − q_k) − Π(1 − p_k)| ≤
/// Σ_k |q_k − p_k|·Π_(i≠k)(1 − min(p_i, q_i))`, that is `n·delta·(1 − s)^(n−1)` LSB with
/// `s = min(p_min, q_min)`.
pub fn int_long_ray_a_lsb(n: u64, x_min: u16, p_min: f64, delta: f64) -> f64 {
    let s = p_min.min(f64::from(x_min) / 65280.0);
    let carried = n as f64 * delta * ((n as f64 - 1.0) * (-s).ln_1p()).exp();
    int_compositor_a_lsb(n, x_min) + carried
}

// ---------------------------------------------------------------------------------------------
// Pre-passes (`classify`, `shade`): the whole pass against the f64 reference of the same
// `f32` scalars, gradient included.

/// [`volsample::classify::classify_isosurface`] against `reference::levoy_opacities` on the
/// same scalars, absolute error of `α`, for every finite scalar (subnormal to `±f32::MAX`)
/// and every valid classifier. The pass works on scaled mantissas, so no step overflows or
/// underflows: each gradient component is one rounded difference (`u = ε/2`), the
/// magnitude of the scaled components adds `2.5u` (squares, sum, `√`), `|f_v − f|`, the
/// product `r·|∇f|` and the quotient `q` one `u` each — `q` within `6.5u` relative — and
/// `α = α_v·(1 − q)` two more roundings: `α_v·(6.5u·q + u·(1 − q)) + u ≤ 7.5u < 4ε`.
/// Where `q` is near 1 the comparison `q ≤ 1` may fall either way; `α ≤ 6.5u·α_v` there.
pub const CLASSIFY_ISOSURFACE_ABS: f64 = 4.0 * EPS32;

/// [`volsample::classify::gradient`], each component against the exact central or one-sided
/// difference of the same `f32` scalars: one rounding (`u` relative), plus
/// [`SUBNORMAL_FLOOR`] where the result is subnormal (a halved subnormal difference).
/// A one-sided difference beyond `f32::MAX` is `±∞` (it has no `f32` value).
pub const GRADIENT_EDGE_REL: f64 = U32;

/// `|n·L|` of the shading pass (unit light direction `L`, `n` the normalised gradient of the
/// same `f32` scalars), absolute: the direction normalised in `f32` (`√` of the scaled
/// squares and 3 quotients, within `4u` per component), the gradient components (`u`), the
/// dot product of the scaled vectors (3 products, 2 sums: `4u·|g|`), the length (`3.5u`) and
/// the quotient (`u`): `13.5u < 7ε`.
pub const SHADE_COS_ABS: f64 = 7.0 * EPS32;

/// [`volsample::shade::shade_in_place`], each shaded channel `C·min(1, k_a + k_d·|n·L|)`
/// against the exact value: `k_d·`[`SHADE_COS_ABS`] through the factor (`min(1, ·)` is
/// 1-Lipschitz), plus the product with `k_d`, the sum with `k_a` (relative `u` each, at most
/// `u·(k_a + k_d)` before the `min`) and the product with `C` (`u`).
pub fn shade_abs(ka: f64, kd: f64) -> f64 {
    kd * SHADE_COS_ABS + U32 * (2.0 * (ka + kd)).min(2.0) + U32
}
