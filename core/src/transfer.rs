//! Transfer functions: scalar value → straight color and opacity.

use crate::error::Error;

/// One control point of a [`TransferFunction`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ControlPoint {
    /// Scalar value, in the scalar voxel's units.
    pub s: f32,
    /// Straight color at `s`, each channel in `[0, 1]`.
    pub c: [f32; 3],
    /// Opacity at `s` (for the reference distance `d′`), in `[0, 1]`.
    pub a: f32,
}

/// A piecewise-linear transfer function with at most `N` control points, stored inline.
///
/// Between control points color and opacity are interpolated linearly; outside them the end
/// values hold.
///
/// ```
/// use volsample::{ControlPoint, TransferFunction};
/// let tf = TransferFunction::<4>::new(&[
///     ControlPoint { s: 0.0, c: [0.0; 3], a: 0.0 },
///     ControlPoint { s: 100.0, c: [1.0; 3], a: 1.0 },
/// ])?;
/// assert_eq!(tf.eval(50.0), ([0.5; 3], 0.5));
/// assert_eq!(tf.eval(1e9), ([1.0; 3], 1.0));
/// # Ok::<(), volsample::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct TransferFunction<const N: usize> {
    points: heapless::Vec<ControlPoint, N>,
}

impl<const N: usize> TransferFunction<N> {
    /// Builds a transfer function from control points sorted by strictly increasing `s`.
    ///
    /// `N = 0` is rejected at compile time.
    ///
    /// # Errors
    /// [`Error::TransferFunctionEmpty`], [`Error::TransferFunctionFull`] (more than `N`
    /// points), [`Error::TransferFunctionValue`] (NaN/∞ anywhere, color or opacity outside
    /// `[0, 1]`), [`Error::TransferFunctionUnsorted`].
    pub fn new(points: &[ControlPoint]) -> Result<Self, Error> {
        const { assert!(N > 0, "a transfer function needs capacity for one point") };
        if points.is_empty() {
            return Err(Error::TransferFunctionEmpty);
        }
        let mut v = heapless::Vec::new();
        let mut prev: Option<f32> = None;
        for p in points {
            let unit_ok =
                p.c.iter()
                    .chain(core::iter::once(&p.a))
                    .all(|x| x.is_finite() && (0.0..=1.0).contains(x));
            if !p.s.is_finite() || !unit_ok {
                return Err(Error::TransferFunctionValue);
            }
            if prev.is_some_and(|s| p.s <= s) {
                return Err(Error::TransferFunctionUnsorted);
            }
            prev = Some(p.s);
            v.push(*p).map_err(|_| Error::TransferFunctionFull)?;
        }
        Ok(Self { points: v })
    }

    /// The control points.
    pub fn points(&self) -> &[ControlPoint] {
        &self.points
    }

    /// Straight color and opacity at `s`.
    ///
    /// Error bound: each output within `3ε + 2ε·L·m` of the exact piecewise-linear value,
    /// `ε = 2⁻²³`, `L` the segment's slope and `m` the largest magnitude among `s` and the
    /// segment's end points (the rounding of `s − s_lo`; `TF_EVAL_BASE`, `TF_EVAL_PER_SLOPE` in
    /// the tests), for every finite `s` and control points anywhere in `f32` (segments wider
    /// than `f32::MAX` included). NaN `s` gives the first point's values.
    #[inline]
    pub fn eval(&self, s: f32) -> ([f32; 3], f32) {
        let i = self.points.partition_point(|p| p.s <= s);
        let first = self.points.first().copied().unwrap_or_default();
        let (lo, hi) = match (
            i.checked_sub(1).and_then(|j| self.points.get(j)),
            self.points.get(i),
        ) {
            (Some(lo), Some(hi)) => (*lo, *hi),
            (Some(lo), None) => return (lo.c, lo.a),
            _ => return (first.c, first.a),
        };
        // A segment wider than f32::MAX (ends near ±f32::MAX) is measured in halves, exact
        // at that scale; unhalved, `∞/∞` gave a NaN color and `x/∞` a 0 where `t` was ½.
        let width = hi.s - lo.s;
        let t = if width.is_finite() {
            (s - lo.s) / width
        } else {
            (s * 0.5 - lo.s * 0.5) / (hi.s * 0.5 - lo.s * 0.5)
        };
        let lerp = |a: f32, b: f32| (a + t * (b - a)).clamp(0.0, 1.0);
        (
            [
                lerp(lo.c[0], hi.c[0]),
                lerp(lo.c[1], hi.c[1]),
                lerp(lo.c[2], hi.c[2]),
            ],
            lerp(lo.a, hi.a),
        )
    }
}
