//! Edge-case generator for `f32` inputs (after libm-test's): signed zeros, subnormals, the
//! normal range ends, ±∞, NaN, the ends of the unit range and one ulp inside and outside each
//! of them, as plain lists (for exhaustive loops) and as proptest strategies (edge values
//! mixed with values drawn near them), so every hard case is both enumerated and fuzzed.

use proptest::prelude::*;

/// The next `f32` towards `+∞` (`x` itself for NaN and `+∞`; `-0.0 ↦` the smallest
/// subnormal).
pub fn next_up(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f32::from_bits(1);
    }
    let b = x.to_bits();
    f32::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

/// The next `f32` towards `−∞` (`x` itself for NaN and `−∞`; `+0.0 ↦` the negative smallest
/// subnormal).
pub fn next_down(x: f32) -> f32 {
    -next_up(-x)
}

/// The smallest positive subnormal, `2⁻¹⁴⁹`.
pub const MIN_SUBNORMAL: f32 = f32::from_bits(1);
/// The largest subnormal, `2⁻¹²⁶ − 2⁻¹⁴⁹`.
pub const MAX_SUBNORMAL: f32 = f32::from_bits(0x007f_ffff);

/// Every special and range-end `f32`, valid or not for any particular parameter:
/// `±0`, the smallest and largest subnormal (both signs), `±MIN_POSITIVE`, one ulp around
/// 0, ½ and 1, `±1`, `±MAX`, `±∞` and NaN.
pub fn specials() -> Vec<f32> {
    let mut v = vec![
        0.0,
        -0.0,
        MIN_SUBNORMAL,
        -MIN_SUBNORMAL,
        MAX_SUBNORMAL,
        -MAX_SUBNORMAL,
        f32::MIN_POSITIVE,
        -f32::MIN_POSITIVE,
        0.5,
        next_down(0.5),
        next_up(0.5),
        1.0,
        -1.0,
        next_down(1.0),
        next_up(1.0),
        2.0,
        f32::MAX,
        -f32::MAX,
        next_down(f32::MAX),
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
        f32::from_bits(0x7fc0_0001), // a NaN with a payload
    ];
    v.extend([1e-30f32, 1e-10, 1e-6, 1e30, -1e-30]);
    v
}

/// The values valid in the unit range `[0, 1]` that stress it most: `±0`, subnormals,
/// `MIN_POSITIVE`, tiny normals, one ulp from 0.5, one ulp below 1, and 1.
pub fn unit_edges() -> Vec<f32> {
    specials()
        .into_iter()
        .filter(|x| x.is_finite() && (0.0..=1.0).contains(x))
        .collect()
}

/// Opacities from transparent to opaque that stress the stable forms: `0`, subnormal,
/// tiny normal, mid, and the last few `f32` below 1 (where `−ln(1 − α)` is largest).
pub fn alpha_edges() -> Vec<f32> {
    let mut v = unit_edges();
    let mut x = next_down(1.0);
    for _ in 0..3 {
        x = next_down(x);
        v.push(x);
    }
    v.extend([
        1e-38f32, 1e-20, 1e-7, 1e-4, 0.01, 0.25, 0.9, 0.99, 0.999_999,
    ]);
    v.sort_by(f32::total_cmp);
    v.dedup();
    v
}

/// A strategy around an edge value: the value itself, a few ulps either side (kept within
/// `[lo, hi]`), or a value drawn from the whole `[lo, hi]`.
fn around(edges: Vec<f32>, lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    let picks = edges.clone();
    prop_oneof![
        3 => prop::sample::select(edges),
        3 => (prop::sample::select(picks), -4i32..=4).prop_map(move |(x, k)| {
            let mut y = x;
            for _ in 0..k.unsigned_abs() {
                y = if k > 0 { next_up(y) } else { next_down(y) };
            }
            if y.is_nan() || y < lo || y > hi { x } else { y }
        }),
        2 => lo..=hi,
    ]
}

/// Any `f32`: a special value, a few ulps from one, or an arbitrary bit pattern.
pub fn any_edge() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => around(specials(), -f32::MAX, f32::MAX),
        1 => any::<u32>().prop_map(f32::from_bits),
    ]
}

/// A valid opacity (or unit-range color) concentrated on the edges of [`alpha_edges`].
pub fn unit_edge() -> impl Strategy<Value = f32> {
    around(alpha_edges(), 0.0, 1.0)
}

/// A tiny positive scale `10^k`, `k ∈ [−44, −5]`, or a subnormal: the `α → 0`, `τ → 0` regime.
pub fn tiny() -> impl Strategy<Value = f32> {
    prop_oneof![
        2 => (-44.0f32..-5.0).prop_map(|k| 10f32.powf(k).max(MIN_SUBNORMAL)),
        1 => (1u32..0x0080_0000).prop_map(f32::from_bits),
    ]
}

/// A step ratio `d/d′` spanning `10⁻⁶ … 10⁶` log-uniformly, with the ends and 1 drawn often.
pub fn ratio_edge() -> impl Strategy<Value = f32> {
    prop_oneof![
        1 => Just(1e-6f32),
        1 => Just(1e6f32),
        1 => Just(1.0f32),
        4 => (-6.0f32..6.0).prop_map(|k| 10f32.powf(k)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours() {
        assert_eq!(next_up(0.0), MIN_SUBNORMAL);
        assert_eq!(next_up(-0.0), MIN_SUBNORMAL);
        assert_eq!(next_down(0.0), -MIN_SUBNORMAL);
        assert_eq!(next_up(1.0), 1.0 + f32::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - f32::EPSILON / 2.0);
        assert_eq!(next_up(MAX_SUBNORMAL), f32::MIN_POSITIVE);
        assert_eq!(next_up(f32::MAX), f32::INFINITY);
        assert!(next_up(f32::NAN).is_nan());
        assert_eq!(next_down(f32::NEG_INFINITY), f32::NEG_INFINITY);
        assert!(unit_edges().iter().all(|x| (0.0..=1.0).contains(x)));
        assert!(unit_edges().contains(&MIN_SUBNORMAL));
        assert!(alpha_edges().contains(&next_down(1.0)));
    }
}
