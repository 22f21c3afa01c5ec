//! The separable symmetric 4-tap downsampling filter `(a, b, b, a)`, `a + b = ½`.

use crate::error::Error;

/// A symmetric 4-tap downsampling filter `(a, b, b, a)` with `a + b = ½` (Kraus §4.2).
///
/// Coarse sample `j` of one axis reads the fine samples `2j − 1, 2j, 2j + 1, 2j + 2` (clamped
/// to the edge) with weights `a, b, b, a`; the filter is applied along x, then y, then z.
///
/// | constructor | `a` | name |
/// |---|---|---|
/// | [`box2`](Self::box2) | 0 | 2-tap box (the common 2×2×2 average) |
/// | [`bspline`](Self::bspline) | ⅛ | B-spline mask `(1, 3, 3, 1)/8` |
/// | [`quadratic`](Self::quadratic) | ⅕ | suited to triquadratic B-spline sampling |
/// | [`box4`](Self::box4) | ¼ | 4-tap box, Kraus's compromise for trilinear sampling |
/// | [`new`](Self::new) | any `a ∈ [0, ½]` | |
///
/// ```
/// use volsample::downsample::Filter4;
/// assert_eq!(Filter4::bspline().weights(), [0.125, 0.375, 0.375, 0.125]);
/// assert!(Filter4::new(0.6).is_err()); // b would be negative
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Filter4 {
    a: f32,
}

impl Filter4 {
    /// The filter with outer weight `a` (and `b = ½ − a`).
    ///
    /// # Errors
    /// [`Error::InvalidDownsampleFilter`] unless `a` is finite and in `[0, ½]`: outside, a
    /// weight is negative and filtered opacities, extinctions and colors could leave their
    /// ranges.
    pub fn new(a: f32) -> Result<Self, Error> {
        if a.is_finite() && (0.0..=0.5).contains(&a) {
            Ok(Self { a })
        } else {
            Err(Error::InvalidDownsampleFilter)
        }
    }

    /// The 2-tap box, `a = 0`: each coarse voxel averages its 2×2×2 fine voxels.
    pub const fn box2() -> Self {
        Self { a: 0.0 }
    }

    /// The B-spline mask, `a = ⅛`: `(1, 3, 3, 1)/8`.
    pub const fn bspline() -> Self {
        Self { a: 0.125 }
    }

    /// `a = ⅕`: `(1, 1.5, 1.5, 1)/5`, the filter suited to triquadratic B-spline sampling.
    pub const fn quadratic() -> Self {
        Self { a: 0.2 }
    }

    /// The 4-tap box, `a = ¼`.
    pub const fn box4() -> Self {
        Self { a: 0.25 }
    }

    /// The outer weight `a`.
    pub const fn a(&self) -> f32 {
        self.a
    }

    /// `[a, b, b, a]` with `b = ½ − a` (rounded to `f32`; the kernel does not use `b`).
    pub fn weights(&self) -> [f32; 4] {
        let b = 0.5 - self.a;
        [self.a, b, b, self.a]
    }

    /// One 4-tap combination of fine samples `v = [v₋₁, v₀, v₁, v₂]`, per channel:
    /// `½(v₀ + v₁) + a·((v₋₁ + v₂) − (v₀ + v₁))`.
    ///
    /// That is `a·v₋₁ + b·v₀ + b·v₁ + a·v₂` in exact arithmetic, written so that a constant
    /// input is reproduced exactly (the difference is then exactly 0) whatever the rounding
    /// of `a`, and so that non-negative input gives non-negative output.
    ///
    /// Error bound: for values in `[0, M]`, within `5u·M` of the exact weighted sum of the
    /// given values, `u = 2⁻²⁴`: the two pair sums (`2uM` each, weighted by `½ − a` and `a`),
    /// the difference (`2uM`, weighted by `a ≤ ½`), the product and the final sum (`uM`
    /// each). The result lies in `[0, M(1 + 5u)]`.
    #[inline(always)]
    pub fn combine<const C: usize>(&self, v: [[f32; C]; 4]) -> [f32; C] {
        let [v0, v1, v2, v3] = v;
        let mut out = [0.0f32; C];
        for ((((o, &x0), &x1), &x2), &x3) in out
            .iter_mut()
            .zip(v0.iter())
            .zip(v1.iter())
            .zip(v2.iter())
            .zip(v3.iter())
        {
            let inner = x1 + x2;
            let outer = x0 + x3;
            *o = 0.5 * inner + self.a * (outer - inner);
        }
        out
    }
}

impl Default for Filter4 {
    /// The 4-tap box (`a = ¼`).
    fn default() -> Self {
        Self::box4()
    }
}
