//! Piecewise-linear transfer function from scalars to straight RGBA.

use super::volume::RefVoxel;

/// One control point of a transfer function.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefControlPoint {
    /// Scalar value at which this point applies.
    pub s: f64,
    /// Straight color at `s`.
    pub color: [f64; 3],
    /// Opacity at `s` (for the volume's `d_ref`).
    pub alpha: f64,
}

impl RefControlPoint {
    /// Builds a control point.
    pub fn new(s: f64, color: [f64; 3], alpha: f64) -> Self {
        Self { s, color, alpha }
    }
}

/// Transfer function: control points sorted by `s`, linear in between, clamped to the first
/// and last point outside their range.
///
/// Where several points share one `s` (a step), a scalar exactly at that `s` takes the last of
/// them (the function is right-continuous). An empty function maps everything to transparent
/// black.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RefTransferFunction {
    /// Control points in non-decreasing order of `s`.
    pub points: Vec<RefControlPoint>,
}

impl RefTransferFunction {
    /// Builds a transfer function.
    ///
    /// # Panics
    /// If the points are not sorted by non-decreasing `s` or an `s` is NaN.
    pub fn new(points: Vec<RefControlPoint>) -> Self {
        assert!(
            points.windows(2).all(|p| p[0].s <= p[1].s),
            "transfer function points must be sorted by s"
        );
        Self { points }
    }

    /// Linear ramp from transparent black at `s0` to `(color, alpha)` at `s1` (`s0 < s1`).
    pub fn ramp(s0: f64, s1: f64, color: [f64; 3], alpha: f64) -> Self {
        Self::new(vec![
            RefControlPoint::new(s0, [0.0; 3], 0.0),
            RefControlPoint::new(s1, color, alpha),
        ])
    }

    /// Evaluates the function at scalar `s`.
    pub fn eval(&self, s: f64) -> RefVoxel {
        let (first, last) = match (self.points.first(), self.points.last()) {
            (Some(f), Some(l)) => (f, l),
            _ => return RefVoxel::default(),
        };
        if s < first.s {
            return RefVoxel::new(first.color, first.alpha);
        }
        if s >= last.s {
            return RefVoxel::new(last.color, last.alpha);
        }
        // first.s <= s < last.s: the window with p0.s <= s < p1.s (so p1.s > p0.s) exists.
        for pair in self.points.windows(2) {
            let (p0, p1) = (pair[0], pair[1]);
            if p0.s <= s && s < p1.s {
                let t = (s - p0.s) / (p1.s - p0.s);
                let lerp = |a: f64, b: f64| a + t * (b - a);
                return RefVoxel::new(
                    [
                        lerp(p0.color[0], p1.color[0]),
                        lerp(p0.color[1], p1.color[1]),
                        lerp(p0.color[2], p1.color[2]),
                    ],
                    lerp(p0.alpha, p1.alpha),
                );
            }
        }
        // Unreachable for sorted points without NaN; NaN input lands here.
        RefVoxel::new(last.color, last.alpha)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tf() -> RefTransferFunction {
        RefTransferFunction::new(vec![
            RefControlPoint::new(0.0, [0.0, 0.0, 1.0], 0.0),
            RefControlPoint::new(1.0, [1.0, 0.0, 0.0], 0.5),
            RefControlPoint::new(3.0, [1.0, 1.0, 0.0], 1.0),
        ])
    }

    #[test]
    fn control_points_and_midpoints() {
        let f = tf();
        assert_eq!(f.eval(0.0), RefVoxel::new([0.0, 0.0, 1.0], 0.0));
        assert_eq!(f.eval(1.0), RefVoxel::new([1.0, 0.0, 0.0], 0.5));
        assert_eq!(f.eval(3.0), RefVoxel::new([1.0, 1.0, 0.0], 1.0));
        assert_eq!(f.eval(0.5), RefVoxel::new([0.5, 0.0, 0.5], 0.25));
        assert_eq!(f.eval(2.0), RefVoxel::new([1.0, 0.5, 0.0], 0.75));
    }

    #[test]
    fn clamps_outside() {
        let f = tf();
        assert_eq!(f.eval(-5.0), f.eval(0.0));
        assert_eq!(f.eval(1e9), f.eval(3.0));
    }

    #[test]
    fn step_is_right_continuous() {
        let f = RefTransferFunction::new(vec![
            RefControlPoint::new(0.0, [0.0; 3], 0.0),
            RefControlPoint::new(1.0, [0.0; 3], 0.0),
            RefControlPoint::new(1.0, [1.0; 3], 1.0),
            RefControlPoint::new(2.0, [1.0; 3], 1.0),
        ]);
        assert_eq!(f.eval(0.999).alpha, 0.0);
        assert_eq!(f.eval(1.0).alpha, 1.0);
        let g = RefTransferFunction::new(vec![
            RefControlPoint::new(0.0, [0.0; 3], 0.0),
            RefControlPoint::new(0.0, [1.0; 3], 1.0),
        ]);
        assert_eq!(g.eval(-1.0).alpha, 0.0);
        assert_eq!(g.eval(0.0).alpha, 1.0);
        assert_eq!(g.eval(1.0).alpha, 1.0);
    }

    #[test]
    fn empty_is_transparent() {
        assert_eq!(
            RefTransferFunction::default().eval(0.3),
            RefVoxel::default()
        );
    }

    #[test]
    #[should_panic(expected = "sorted")]
    fn unsorted_rejected() {
        let _ = RefTransferFunction::new(vec![
            RefControlPoint::new(1.0, [0.0; 3], 0.0),
            RefControlPoint::new(0.0, [0.0; 3], 0.0),
        ]);
    }
}
