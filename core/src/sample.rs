//! The values that flow between the stages of a kernel.

use crate::each::Each;
use crate::lanes::{clamp_to, Lanes};

/// An associated (opacity-weighted) color and its opacity: one sample along a ray, or a
/// composited pixel.
///
/// Invariant kept by every kernel: `0 ≤ c[k] ≤ a ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample {
    /// Associated color `C̃`.
    pub c: [f32; 3],
    /// Opacity `α`.
    pub a: f32,
}

impl Sample {
    /// Fully transparent black.
    pub const TRANSPARENT: Self = Self {
        c: [0.0; 3],
        a: 0.0,
    };

    /// Builds a sample from an associated color and opacity, clamping `α` into `[0, 1]` and
    /// each channel into `[0, α]` (NaN becomes 0).
    ///
    /// The kernels use this to absorb rounding at the ulp level (a convex combination of
    /// values ≤ 1 can round to `1 + ε`); it never hides more than that for valid input.
    #[inline(always)]
    pub fn clamped(c: [f32; 3], a: f32) -> Self {
        Self::from(clamped(Interp { c, a }))
    }

    /// The straight (displayed) color `C/α`, or black when `α = 0`.
    pub fn straight_color(&self) -> [f32; 3] {
        if self.a > 0.0 {
            self.c.each(|c| (c / self.a).min(1.0))
        } else {
            [0.0; 3]
        }
    }

    /// `true` when every field is finite and `0 ≤ c[k] ≤ a ≤ 1`.
    pub fn is_valid(&self) -> bool {
        self.a.is_finite()
            && (0.0..=1.0).contains(&self.a)
            && self
                .c
                .iter()
                .all(|&c| c.is_finite() && c >= 0.0 && c <= self.a)
    }
}

/// [`Sample::clamped`] in any [`Lanes`] (the one clamp of every kernel's sample): `α` into
/// `[0, 1]`, each `C̃` into `[0, α]`, NaN to 0.
#[inline(always)]
pub(crate) fn clamped<T: Lanes>(i: Interp<T>) -> Interp<T> {
    let a = i.a.clamp_to(T::ONE);
    // A loop rather than the three written out: the same operations, and fewer bytes in the
    // Cortex-M4F `min_float` image.
    let mut c = i.c;
    for x in &mut c {
        *x = x.clamp_to(a);
    }
    Interp { c, a }
}

impl From<Interp<f32>> for Sample {
    /// The quantities as they are, read as an associated color and its opacity.
    #[inline(always)]
    fn from(i: Interp<f32>) -> Self {
        Self { c: i.c, a: i.a }
    }
}

impl From<Sample> for Interp<f32> {
    /// The sample's color and opacity as quantities.
    #[inline(always)]
    fn from(s: Sample) -> Self {
        Self { c: s.c, a: s.a }
    }
}

/// Clamps into `[0, 1]`; NaN becomes 0.
#[inline(always)]
pub(crate) fn clamp01(x: f32) -> f32 {
    clamp_to(x, 1.0)
}

/// `f` of each lane's quantities ([`Lanes::per_lane`] of the four vectors `c₀, c₁, c₂, a`).
#[inline(always)]
pub(crate) fn per_lane<T: Lanes>(
    i: Interp<T>,
    f: impl Fn(Interp<f32>) -> Interp<f32>,
) -> Interp<T> {
    let [c0, c1, c2] = i.c;
    let [c0, c1, c2, a] = T::per_lane([c0, c1, c2, i.a], |[c0, c1, c2, a]| {
        let o = f(Interp { c: [c0, c1, c2], a });
        let [c0, c1, c2] = o.c;
        [c0, c1, c2, o.a]
    });
    Interp { c: [c0, c1, c2], a }
}

/// The quantities a sampling mode interpolates, before it turns them into a [`Sample`].
///
/// What `c` and `a` mean depends on the mode: straight `C` and `α` (`Separate`), associated
/// `C̃` and `α` (`OpacityWeighted`, `Preweighted`), `C^τ` and `τ` (`ExtinctionWeighted`), or
/// the scalar in `a` (`PostClassified`, `c` unused).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Interp<T> {
    /// The three interpolated color-like channels.
    pub c: [T; 3],
    /// The interpolated opacity-like channel.
    pub a: T,
}
