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

/// `e`, for the bounds below.
const E: f64 = std::f64::consts::E;

/// Chord error of one `φ`/`e^(−x)` table with `n = 2^B + 1` nodes on `[0, 1]`
/// (`h = 1/(n − 1)`), in U8.8 LSB: `ONE·h²/(8e)`, the larger of the `e^(−n−t)` term
/// (`h²/8·e^(−1)`, `x ≥ 1`) and the `x·φ` term (`h²/24`, `x < 1`).
pub fn table_chord_lsb(n: usize) -> f64 {
    let h = 1.0 / (n - 1) as f64;
    65280.0 * h * h / (8.0 * E)
}

/// What the table-driven paths add beyond rounding and chord error, in U8.8 LSB: table
/// entries (`2^−32`), the step's optical depth to 28 bits (`2^−29`), the ratio to 32 bits
/// (`64·2^−33` at most) and the `e^(−16)` tail (0.0074).
pub const TABLE_QUANT_LSB: f64 = 0.01;

/// Integer `ExtinctionWeighted` with `n`-node tables, against the exact method on the same
/// stored voxels: `α` (U8.8 LSB), `½ + table_chord_lsb(n) + TABLE_QUANT_LSB`.
pub fn extinction_int_a_lsb(n: usize) -> f64 {
    0.5 + table_chord_lsb(n) + TABLE_QUANT_LSB
}

/// Integer `ExtinctionWeighted`, each `C̃`: ½ more than `α` (at `x ≥ 1` the color reuses the
/// rounded `α`).
pub fn extinction_int_c_lsb(n: usize) -> f64 {
    1.0 + table_chord_lsb(n) + TABLE_QUANT_LSB
}

/// Storage of `(τ, C^τ)` in U7.20 (`D` within `2^−21`, `D·C` within `2^−20`), seen through a
/// step of ratio `r`, in U8.8 LSB: `(α, C̃)` terms `ONE·r·2^−21` and `1.25·ONE·r·2^−20`
/// (`|∂α/∂D̄| ≤ r`, `|∂C̃/∂C̄| ≤ r`, `|∂C̃/∂D̄| ≤ r·max x|φ'(x)| < 0.3·r`). Added to the
/// kernel bounds when comparing with the `f64` reference on the straight voxels.
pub fn extinction_int_storage_lsb(r: f64) -> (f64, f64) {
    let lsb = 65280.0 * r / 1_048_576.0;
    (0.5 * lsb, 1.25 * lsb)
}

/// Relative error of the correction's optical depth `L = −ln(1 − α)`: the `ln m` chord
/// `2^−16/8` plus entries, over `L ≥ ln(65280/32512) > 0.697` (the `ψ` branch's
/// `(128/65280)²/8·3.1 = 1.5·10^−6` is smaller).
pub const CORRECTION_L_REL: f64 = (1.0 / 65536.0 / 8.0 + 2e-10) / 0.697;

/// Table-driven integer opacity correction, any U8.8 opacity and any ratio: `α_d` (U8.8
/// LSB). ½ of final rounding, `L`'s relative error times `max y·e^(−y) = 1/e`, the 257-node
/// `φ`/`e^(−x)` chord, and [`TABLE_QUANT_LSB`]: 0.62 LSB. `C̃_d` adds ½ LSB to this.
pub const CORRECTION_INT_LSB: f64 =
    0.5 + 65280.0 * CORRECTION_L_REL / E + 65280.0 / (65536.0 * 8.0 * E) + TABLE_QUANT_LSB;

/// The correction bound for ratio `r` (the same for every `r`: [`CORRECTION_INT_LSB`]).
pub fn correction_int_lsb(r: f32) -> f64 {
    let _ = r;
    CORRECTION_INT_LSB
}
