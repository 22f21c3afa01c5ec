//! Reconstruction filters: tap indices and weights, clamp to edge.

use super::volume::linear_index;

/// Reconstruction filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RefFilter {
    /// Nearest voxel: `i = ⌊x + ½⌋`, one tap of weight 1.
    Nearest,
    /// Trilinear: `i0 = ⌊x⌋`, `f = x − i0`, taps `i0, i0 + 1` with weights `1 − f, f`.
    Trilinear,
    /// Triquadratic B-spline: `i = ⌊x + ½⌋`, `t = x − i`, taps `i − 1, i, i + 1` with weights
    /// `(½ − t)²/2, ¾ − t², (½ + t)²/2`.
    TriquadraticBSpline,
}

impl RefFilter {
    /// Every filter.
    pub const ALL: [RefFilter; 3] = [
        RefFilter::Nearest,
        RefFilter::Trilinear,
        RefFilter::TriquadraticBSpline,
    ];

    /// Taps per axis: 1, 2 or 3.
    pub fn taps_per_axis(self) -> usize {
        match self {
            RefFilter::Nearest => 1,
            RefFilter::Trilinear => 2,
            RefFilter::TriquadraticBSpline => 3,
        }
    }
}

/// Clamps an integral-valued tap position into `[0, n − 1]` (NaN goes to `0`).
fn clamp_index(i: f64, n: usize) -> usize {
    let hi = (n - 1) as f64;
    if i >= hi {
        n - 1
    } else if i > 0.0 {
        i as usize
    } else {
        0
    }
}

/// Taps of one axis of length `n` at coordinate `x`: `(index, weight)` pairs, lowest tap first,
/// indices clamped into `[0, n − 1]` (so clamped taps may repeat an index). Weights sum to 1.
///
/// # Panics
/// If `n == 0`.
pub fn axis_taps(n: usize, filter: RefFilter, x: f64) -> Vec<(usize, f64)> {
    assert!(n > 0, "empty axis");
    match filter {
        RefFilter::Nearest => vec![(clamp_index((x + 0.5).floor(), n), 1.0)],
        RefFilter::Trilinear => {
            let i0 = x.floor();
            let f = x - i0;
            vec![(clamp_index(i0, n), 1.0 - f), (clamp_index(i0 + 1.0, n), f)]
        }
        RefFilter::TriquadraticBSpline => {
            let i = (x + 0.5).floor();
            let t = x - i;
            vec![
                (clamp_index(i - 1.0, n), (0.5 - t) * (0.5 - t) / 2.0),
                (clamp_index(i, n), 0.75 - t * t),
                (clamp_index(i + 1.0, n), (0.5 + t) * (0.5 + t) / 2.0),
            ]
        }
    }
}

/// All taps of `filter` at position `pos` in a volume of dimensions `dims`:
/// `(linear index, weight)` with weight `w_x·w_y·w_z`, ordered z outermost, x innermost
/// (1, 8 or 27 entries; clamped taps are not merged).
///
/// # Panics
/// If a dimension is zero.
pub fn taps(dims: [usize; 3], filter: RefFilter, pos: [f64; 3]) -> Vec<(usize, f64)> {
    let ax = axis_taps(dims[0], filter, pos[0]);
    let ay = axis_taps(dims[1], filter, pos[1]);
    let az = axis_taps(dims[2], filter, pos[2]);
    let mut out = Vec::with_capacity(ax.len() * ay.len() * az.len());
    for &(z, wz) in &az {
        for &(y, wy) in &ay {
            for &(x, wx) in &ax {
                out.push((linear_index(dims, [x, y, z]), wx * wy * wz));
            }
        }
    }
    out
}

/// Filtered value `Σ w_i·values[i]` of a scalar field stored in storage order.
///
/// # Panics
/// If a dimension is zero or `values` is shorter than the volume.
pub fn interpolate(dims: [usize; 3], filter: RefFilter, pos: [f64; 3], values: &[f64]) -> f64 {
    taps(dims, filter, pos)
        .iter()
        .map(|&(i, w)| w * values[i])
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in `[0, 1)` (64-bit LCG, top 53 bits).
    fn lcg(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn weights_sum_to_one_and_counts() {
        let dims = [5, 4, 3];
        let mut s = 1;
        for filter in RefFilter::ALL {
            for _ in 0..500 {
                let pos = [
                    lcg(&mut s) * 9.0 - 2.0,
                    lcg(&mut s) * 8.0 - 2.0,
                    lcg(&mut s) * 7.0 - 2.0,
                ];
                let t = taps(dims, filter, pos);
                assert_eq!(t.len(), filter.taps_per_axis().pow(3));
                let sum: f64 = t.iter().map(|&(_, w)| w).sum();
                assert!((sum - 1.0).abs() < 1e-14, "{filter:?} {pos:?} {sum}");
                assert!(t.iter().all(|&(i, w)| i < 60 && w >= 0.0));
            }
        }
    }

    #[test]
    fn nearest_rounds_half_up() {
        assert_eq!(axis_taps(5, RefFilter::Nearest, 1.49), vec![(1, 1.0)]);
        assert_eq!(axis_taps(5, RefFilter::Nearest, 1.5), vec![(2, 1.0)]);
        assert_eq!(axis_taps(5, RefFilter::Nearest, -0.5), vec![(0, 1.0)]);
        assert_eq!(axis_taps(5, RefFilter::Nearest, -7.0), vec![(0, 1.0)]);
        assert_eq!(axis_taps(5, RefFilter::Nearest, 4.6), vec![(4, 1.0)]);
    }

    #[test]
    fn trilinear_axis() {
        assert_eq!(
            axis_taps(5, RefFilter::Trilinear, 1.25),
            vec![(1, 0.75), (2, 0.25)]
        );
        // Exactly on the last voxel: i0 = n − 1, f = 0, the second tap clamps.
        assert_eq!(
            axis_taps(5, RefFilter::Trilinear, 4.0),
            vec![(4, 1.0), (4, 0.0)]
        );
        assert_eq!(
            axis_taps(5, RefFilter::Trilinear, -0.25),
            vec![(0, 0.25), (0, 0.75)]
        );
        assert_eq!(
            axis_taps(1, RefFilter::Trilinear, 0.5),
            vec![(0, 0.5), (0, 0.5)]
        );
    }

    #[test]
    fn bspline_axis_closed_forms() {
        assert_eq!(
            axis_taps(5, RefFilter::TriquadraticBSpline, 2.0),
            vec![(1, 0.125), (2, 0.75), (3, 0.125)]
        );
        // t = −½: weights (½, ½, 0) on i − 1, i.
        assert_eq!(
            axis_taps(5, RefFilter::TriquadraticBSpline, 1.5),
            vec![(1, 0.5), (2, 0.5), (3, 0.0)]
        );
        // t = ¼: (1/32, 11/16, 9/32).
        assert_eq!(
            axis_taps(5, RefFilter::TriquadraticBSpline, 2.25),
            vec![(1, 0.03125), (2, 0.6875), (3, 0.28125)]
        );
        // Clamped at the low edge.
        assert_eq!(
            axis_taps(5, RefFilter::TriquadraticBSpline, 0.0),
            vec![(0, 0.125), (0, 0.75), (1, 0.125)]
        );
    }

    #[test]
    fn reproduces_linear_functions_inside() {
        let dims = [6, 5, 4];
        let f = |p: [f64; 3]| 0.5 + 2.0 * p[0] - 3.0 * p[1] + 0.25 * p[2];
        let mut values = vec![0.0; 120];
        for z in 0..4 {
            for y in 0..5 {
                for x in 0..6 {
                    values[linear_index(dims, [x, y, z])] = f([x as f64, y as f64, z as f64]);
                }
            }
        }
        let mut s = 7;
        for _ in 0..500 {
            let u = [lcg(&mut s), lcg(&mut s), lcg(&mut s)];
            // Trilinear: exact on [0, n − 1]; B-spline: exact on [1, n − 2].
            let p = [u[0] * 5.0, u[1] * 4.0, u[2] * 3.0];
            let got = interpolate(dims, RefFilter::Trilinear, p, &values);
            assert!((got - f(p)).abs() < 1e-12, "trilinear {p:?}");
            let q = [1.0 + u[0] * 3.0, 1.0 + u[1] * 2.0, 1.0 + u[2]];
            let got = interpolate(dims, RefFilter::TriquadraticBSpline, q, &values);
            assert!((got - f(q)).abs() < 1e-12, "bspline {q:?}");
        }
        // Nearest reproduces the voxel value at voxel centres.
        assert_eq!(
            interpolate(dims, RefFilter::Nearest, [2.2, 3.9, 0.4], &values),
            f([2.0, 4.0, 0.0])
        );
    }

    #[test]
    fn outside_clamps_to_edge_value() {
        let dims = [3, 3, 3];
        let values: Vec<f64> = (0..27).map(|i| i as f64).collect();
        for filter in RefFilter::ALL {
            let v = interpolate(dims, filter, [-10.0, -10.0, -10.0], &values);
            assert_eq!(v, 0.0, "{filter:?}");
            let v = interpolate(dims, filter, [10.0, 10.0, 10.0], &values);
            assert_eq!(v, 26.0, "{filter:?}");
        }
    }

    #[test]
    fn product_order() {
        let t = taps([2, 2, 2], RefFilter::Trilinear, [0.25, 0.5, 0.0]);
        let idx: Vec<usize> = t.iter().map(|&(i, _)| i).collect();
        assert_eq!(idx, vec![0, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(t[0].1, 0.75 * 0.5);
        assert_eq!(t[1].1, 0.25 * 0.5);
        assert_eq!(t[4].1, 0.0);
    }
}
