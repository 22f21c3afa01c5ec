//! The one tolerance table: every error bound a doc comment states, as a named constant the
//! tests hold the kernels to.
//!
//! Float bounds are absolute errors on values in `[0, 1]` (opacity, associated color) unless
//! the name says ulp. Integer bounds are in output LSBs.
//!
//! A bound here is a promise made in the kernel's doc comment; a test that measures a larger
//! error fails, and the closing notes quote the worst error observed next to the bound.

pub mod downsample;
pub mod hard_cases;
/// Integer-kernel bounds (`volsample::fixed_point`), in output LSBs.
pub mod integer;

/// `f32` machine epsilon as `f64`, the unit the float bounds are built from.
pub const EPS32: f64 = f32::EPSILON as f64;

use crate::float_checks::{CameraSpec, FilterKind, FloatCase, ModeKind, RenderSpec};

/// Interpolation: absolute error per tap of a sum of `f32` products of values in `[0, 1]`
/// with weights summing to 1 (weight rounding, product and sum rounding), in either trilinear
/// order. For values up to `v_max` it scales with `v_max`.
pub const INTERP_PER_TAP: f64 = EPS32;

/// Final rounding and clamping of a sample.
pub const FLOAT_SAMPLE_BASE: f64 = EPS32;

/// [`volsample::opacity::correct`] against the textbook formula on the same input: absolute
/// error, times `max(1, d/d′)`.
pub const CORRECTION_ABS: f64 = 8.0 * EPS32;

/// One compositing step (front to back or back to front): absolute error; `n` steps at most
/// `n` times this.
pub const COMPOSITE_STEP: f64 = 3.0 * EPS32;

/// `Preweighted` on `f32` associated voxels against `OpacityWeighted` on the straight ones
/// (the stored `α·C` is rounded once more).
pub const PREWEIGHTED_VS_OPACITY_WEIGHTED: f64 = 2.0 * (FLOAT_SAMPLE_BASE + 27.0 * INTERP_PER_TAP);

/// The error bound of one float sample of `mode` with `filter` on `case` at step `d`, as the
/// modes' doc comments state it (opacity-based modes: at `d = d′`, before correction):
///
/// * `Separate`, `OpacityWeighted`, `Preweighted`: `(1 + taps)·ε`;
/// * `ExtinctionWeighted`: `(1 + taps·(1 + d·τ_max))·ε`, `τ_max` the largest stored `τ`
///   (the interpolated `τ` has absolute error `taps·ε·τ_max`, and `|∂α/∂τ| ≤ d`);
/// * `PostClassified`: `3ε + L·taps·ε·s_max`, `L` the transfer function's steepest slope and
///   `s_max` the largest scalar magnitude;
///
/// with `ε = 2⁻²³`.
pub fn sample_bound(mode: ModeKind, filter: FilterKind, case: &FloatCase, d: f32) -> f64 {
    let taps = filter.taps() as f64;
    match mode {
        ModeKind::Separate | ModeKind::OpacityWeighted | ModeKind::Preweighted => {
            FLOAT_SAMPLE_BASE + INTERP_PER_TAP * taps
        }
        ModeKind::ExtinctionWeighted => {
            let tau_max = case.extinction().iter().fold(0.0f32, |m, e| m.max(e.tau));
            FLOAT_SAMPLE_BASE + INTERP_PER_TAP * taps * (1.0 + f64::from(d * tau_max))
        }
        ModeKind::PostClassified => {
            let s_max = case.scalars.iter().fold(1.0f32, |m, &s| m.max(s.abs()));
            let slope = case
                .tf
                .windows(2)
                .map(|w| {
                    let ds = f64::from(w[1].s - w[0].s);
                    let dv = w[1]
                        .c
                        .iter()
                        .zip(w[0].c.iter())
                        .map(|(a, b)| (a - b).abs())
                        .fold((w[1].a - w[0].a).abs(), f32::max);
                    f64::from(dv) / ds
                })
                .fold(0.0, f64::max);
            3.0 * FLOAT_SAMPLE_BASE + slope * f64::from(s_max) * INTERP_PER_TAP * taps
        }
    }
}

/// The error bound of one rendered pixel of `mode` with `filter` on `case` for `spec`, against
/// the reference renderer: `n` samples (the volume's diagonal over the step, plus two), each
/// within [`sample_bound`] (doubled for the correction's conditioning, plus the correction's
/// own error [`CORRECTION_ABS`] times `max(1, d/d′)`), plus the error of the `f32` sample
/// position (`16ε` times the camera's reach plus the diagonal) times the largest gradient of a
/// sample, composited with at most `2n` times that, plus `n` compositing roundings
/// ([`COMPOSITE_STEP`]); early termination may stop one sample apart, which costs at most
/// `1 − A_stop`.
///
/// The bound holds where opacity correction is well conditioned (`α ≤ 0.9` when `d ≠ d′`).
pub fn render_pixel_bound(
    case: &FloatCase,
    mode: ModeKind,
    filter: FilterKind,
    spec: &RenderSpec,
) -> f64 {
    let diag = case
        .dims
        .iter()
        .map(|&n| (n * n) as f64)
        .sum::<f64>()
        .sqrt();
    let n = diag / f64::from(spec.step) + 2.0;
    let ratio = f64::from(spec.step / case.d_ref);
    let reach = match spec.camera {
        CameraSpec::Orthographic(eye, _, _, extent) => {
            eye.iter().map(|x| x.abs()).sum::<f32>() + extent
        }
        CameraSpec::Perspective(eye, ..) => eye.iter().map(|x| x.abs()).sum::<f32>(),
    };
    let pos_err = 16.0 * EPS32 * (f64::from(reach) + diag);
    let tau_max = case.extinction().iter().fold(0.0f32, |m, e| m.max(e.tau));
    let gradient = match mode {
        ModeKind::ExtinctionWeighted => 1.0 + f64::from(spec.step * tau_max),
        ModeKind::PostClassified => 1.0 + sample_bound(mode, filter, case, spec.step) / EPS32,
        _ => 2.0,
    };
    let per_sample = 2.0 * sample_bound(mode, filter, case, spec.step)
        + CORRECTION_ABS * ratio.max(1.0)
        + 4.0 * EPS32
        + pos_err * gradient * 2.0;
    2.0 * n * per_sample + n * COMPOSITE_STEP + f64::from(1.0 - spec.a_stop)
}

/// Extinction-weighted ray integration (midpoint samples) against the ground-truth integral
/// of the same trilinear extinction field, on smooth data: error at most this times the step
/// `d` (voxel units).
pub const EXTINCTION_TRUTH_PER_STEP: f64 = 0.05;

/// [`volsample::opacity::phi`]: relative error against the f64 `φ`.
pub const PHI_REL: f64 = 4.0 * EPS32;

/// [`volsample::opacity::phi_poly`] on `[0, 1)`: relative error against the f64 `φ`.
pub const PHI_POLY_REL: f64 = 2.0 * EPS32;

/// [`volsample::mode::integrate_step`]: absolute error of `α` and each `C̃`.
pub const INTEGRATE_STEP_ABS: f64 = 6.0 * EPS32;

/// [`volsample::ExtinctionF32::from_straight`]: relative error of `τ` (below the cap).
pub const FROM_STRAIGHT_TAU_REL: f64 = 2.0 * EPS32;

/// [`volsample::TransferFunction::eval`]: absolute error is at most
/// `TF_EVAL_BASE + L·TF_EVAL_PER_SLOPE·|s|`, `L` the segment's slope.
pub const TF_EVAL_BASE: f64 = 3.0 * EPS32;
/// See [`TF_EVAL_BASE`].
pub const TF_EVAL_PER_SLOPE: f64 = 2.0 * EPS32;

/// [`volsample::filter::trilinear_weights`]: absolute error of each weight.
pub const TRILINEAR_WEIGHT_ABS: f64 = 4.0 * EPS32;

/// [`volsample::classify::Isosurface::opacity`]: absolute error.
pub const ISOSURFACE_ABS: f64 = 4.0 * EPS32;

/// [`volsample::classify::gradient`]: absolute error per component, times the largest
/// scalar magnitude among the differenced values.
pub const GRADIENT_REL: f64 = EPS32;

/// [`volsample::shade::Light::factor`]: absolute error.
pub const LIGHT_FACTOR_ABS: f64 = 6.0 * EPS32;
