//! Error bounds of the integer kernels (`volsample::fixed_point`), in output LSBs.
//!
//! One U8.8 LSB is `1/256` of a u8 level, `1/65280` of full scale. Each bound is measured
//! against the exact (real-number) result of the same method at the same quantized position,
//! as the kernel's doc comment states it; the tests and the fuzz checks hold the kernels to
//! these constants, and the closing notes quote the worst error observed next to each.

/// `OpacityWeighted` (straight `u8`), any filter: `α` and each `C̃` (U8.8 LSB).
pub const OPACITY_WEIGHTED_INT_LSB: f64 = 0.5;

/// `Preweighted` (premultiplied `u8`, against the same stored bytes): `α` and each `C̃`.
pub const PREWEIGHTED_INT_LSB: f64 = 0.5;

/// `Separate` (straight `u8`): `α`.
pub const SEPARATE_INT_A_LSB: f64 = 0.5;

/// `Separate` (straight `u8`): each `C̃` (½ from `α`, ½ from `C`, ½ from the product).
pub const SEPARATE_INT_LSB: f64 = 1.5;

/// Extra allowance when an integer kernel is compared with the `f32` float kernel of the same
/// method instead of the exact value (the float kernel's own error, `≤ 1e-6` of full scale,
/// is below 0.07 LSB).
pub const FLOAT_KERNEL_SLACK_LSB: f64 = 0.1;

/// `Preweighted` sample from `u8` premultiplied storage of straight voxels, against the exact
/// `OpacityWeighted` sample of those straight voxels: ½ level of storage rounding (128 LSB)
/// plus ½ LSB of output rounding (each `C̃`, U8.8 LSB).
pub const PREMUL_STORAGE_LSB: f64 = 128.5;

/// Wittenbrink §7: the color recovered from `u8` premultiplied storage is within
/// `PREMUL_RECOVERY_HALF·255/α_F` levels of the stored straight color.
pub const PREMUL_RECOVERY_HALF: f64 = 0.5;

/// …and the bound is reached: the worst recovery error at `α_F = 1` (levels).
pub const PREMUL_RECOVERY_REACHED_AT_ALPHA_1: f64 = 127.0;

/// Every 8-bit `premultiply`: within ½ level of `C·α/255`.
pub const PREMULTIPLY_LEVELS: f64 = 0.5;

/// Straight color recovered from a U8.8 sample, `255·C̃/α` (levels), against the exact
/// straight color of the method: within `(e_c + ½)·255/α_raw` where `e_c` is the sample's
/// `C̃` bound in LSB. For `OpacityWeighted` from straight storage this is at most
/// `255/α_raw` (under one level for every `α ≥ 1/255`, raw 256).
pub fn recovered_color_bound(c_bound_lsb: f64, a_raw: u16) -> f64 {
    (c_bound_lsb + 0.5) * 255.0 / f64::from(a_raw)
}

/// Integer front-to-back compositor, per sample composited: accumulated `A` (U8.8 LSB).
pub const COMPOSITE_INT_A_LSB_PER_STEP: f64 = 0.5;

/// Integer front-to-back compositor, per sample composited: each `C` (U8.8 LSB).
pub const COMPOSITE_INT_C_LSB_PER_STEP: f64 = 1.0;

/// Table-driven integer opacity correction at a u8 opacity (a table point): `α_d` (U8.8
/// LSB), ½ of rounding plus the f64 table build.
pub const CORRECTION_INT_TABLE_LSB: f64 = 0.5 + 1e-6;

/// Table-driven integer opacity correction at any U8.8 opacity, ratio `r = d/d′`: `α_d`
/// (U8.8 LSB). The table bound, ½ LSB for rounding the interpolated value, and the chord
/// error of linear interpolation between table points (`h = 1/255`, `f(α) = 1 − (1 − α)^r`):
/// in the intervals below the last, `h²/8·ONE·|r(r − 1)|·max(1, 255^(2−r))` (`|f''|` at their
/// largest); in the last one, where `f` behaves like `1 − T^r` near `T = 1 − α = 0`,
/// `ONE·h^r·|x*^r − x*|` with `x* = r^(1/(1−r))`. For `r < 1` the last term is large
/// (1022 LSB ≈ 4 levels at `r = ½`). `C̃_d` adds ½ LSB to this.
pub fn correction_int_lsb(r: f32) -> f64 {
    let r = f64::from(r);
    let one = 65280.0;
    let h = 1.0 / 255.0;
    if (r - 1.0).abs() < 1e-12 {
        return CORRECTION_INT_TABLE_LSB + 0.5;
    }
    let interior = h * h / 8.0 * one * (r * (r - 1.0)).abs() * 255.0f64.powf(2.0 - r).max(1.0);
    let xs = r.powf(1.0 / (1.0 - r));
    let last = one * h.powf(r) * (xs.powf(r) - xs).abs();
    CORRECTION_INT_TABLE_LSB + 0.5 + interior.max(last)
}
