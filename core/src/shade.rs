//! Pre-shading: lighting straight voxel colors with a directional light before interpolation
//! (the papers' "classified and shaded before interpolation").
//!
//! A scene without a light skips this stage; with [`Light::UNLIT`] it would be the identity.

use crate::classify::scaled_gradient;
use crate::each::Each;
use crate::error::Error;
use crate::volume::Volume;
use crate::voxel::{ScalarVoxel, StraightF32};

/// A directional light with ambient and diffuse (two-sided Lambert) terms.
///
/// The shaded color is `C·min(1, k_a + k_d·|n·L|)`, with `n` the normalised scalar gradient;
/// where the gradient vanishes (inside homogeneous material) `|n·L|` is taken as 1.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Light {
    dir: [f32; 3],
    ambient: f32,
    diffuse: f32,
}

impl Light {
    /// The identity light: `k_a = 1`, `k_d = 0`.
    pub const UNLIT: Self = Self {
        dir: [0.0, 0.0, 1.0],
        ambient: 1.0,
        diffuse: 0.0,
    };

    /// A light shining along `dir` (normalised here), ambient `k_a ≥ 0`, diffuse `k_d ≥ 0`.
    ///
    /// Every finite non-zero direction is accepted, subnormal to `f32::MAX` components: it is
    /// scaled by a power of two before its length is taken. (Unscaled, the squared length of
    /// `[1e20, 0, 0]` overflowed and that of `[1e-30, 0, 0]` underflowed, and both were
    /// rejected.)
    ///
    /// # Errors
    /// [`Error::InvalidLight`] for non-finite input, a zero direction or negative
    /// coefficients.
    pub fn new(dir: [f32; 3], ambient: f32, diffuse: f32) -> Result<Self, Error> {
        let ok = dir.iter().all(|d| d.is_finite())
            && ambient.is_finite()
            && diffuse.is_finite()
            && ambient >= 0.0
            && diffuse >= 0.0;
        let scaled = if ok { unit_scaled(dir) } else { None };
        let Some(s) = scaled else {
            return Err(Error::InvalidLight);
        };
        // |s| ∈ [½, √3]: the length neither overflows nor underflows.
        let n = norm(s);
        Ok(Self {
            dir: s.each(|d| d / n),
            ambient,
            diffuse,
        })
    }

    /// The light factor for a gradient `g`: `min(1, k_a + k_d·|n·L|)`.
    ///
    /// `|n·L|` is taken from `g` scaled by a power of two, so it is accurate for every finite
    /// non-zero gradient, subnormal to `f32::MAX` (unscaled, `|g|²` overflowed above about
    /// `1.8·10¹⁹` and underflowed below `10⁻¹⁹`, both read as a vanishing gradient); a zero
    /// or non-finite `g` counts as vanishing (`|n·L| = 1`).
    ///
    /// Error bound: within `6ε` (`ε = 2⁻²³`) of the exact value for the given `f32` input
    /// (`LIGHT_FACTOR_ABS` in the tests).
    #[inline]
    pub fn factor(&self, g: [f32; 3]) -> f32 {
        let scaled = if g.iter().all(|x| x.is_finite()) {
            unit_scaled(g)
        } else {
            None
        };
        self.factor_scaled(scaled)
    }

    /// The factor for a gradient already scaled to `[½, √3]` in length (`None`: vanishing).
    #[inline(always)]
    fn factor_scaled(&self, g: Option<[f32; 3]>) -> f32 {
        let cos = match g {
            Some(g) => {
                let dot: f32 = g.iter().zip(self.dir.iter()).map(|(a, b)| a * b).sum();
                (dot / norm(g)).abs()
            }
            None => 1.0,
        };
        (self.ambient + self.diffuse * cos.min(1.0)).min(1.0)
    }
}

/// `|v|` by the textbook formula (for vectors whose length is in a safe range).
#[inline(always)]
fn norm(v: [f32; 3]) -> f32 {
    libm::sqrtf(v.iter().map(|x| x * x).sum())
}

/// `v·2^−e` with its largest component in `[½, 1)` (exact but for components more than `2^125`
/// times smaller, which may be flushed), or `None` for the zero vector. `v` must be finite.
#[inline(always)]
fn unit_scaled(v: [f32; 3]) -> Option<[f32; 3]> {
    let m = v.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    if m > 0.0 {
        let e = libm::frexpf(m).1;
        Some(v.each(|x| libm::scalbnf(x, -e)))
    } else {
        None
    }
}

/// Shades straight voxels `rgba` in place with `light`, taking normals from the scalar
/// volume `scalars` (same dimensions); opacity is unchanged.
///
/// Error bound: each shaded channel within `k_d·7ε + 2u·min(1, k_a + k_d) + u` of
/// `C·min(1, k_a + k_d·|n·L|)` with the exact normal of the same `f32` scalars (`ε = 2⁻²³`,
/// `u = ε/2`; `shade_abs` in the tests), for every finite scalar field.
///
/// # Errors
/// [`Error::LengthMismatch`] if `rgba` does not hold one voxel per scalar voxel.
pub fn shade_in_place<V: ScalarVoxel>(
    scalars: &Volume<'_, V>,
    light: &Light,
    rgba: &mut [StraightF32],
) -> Result<(), Error> {
    if rgba.len() != scalars.data().len() {
        return Err(Error::LengthMismatch {
            expected: scalars.data().len(),
            actual: rgba.len(),
        });
    }
    let [nx, ny, _] = scalars.dims();
    for (i, v) in rgba.iter_mut().enumerate() {
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        // The gradient comes scaled (largest component in [½, 1)), so no value of the
        // scalars — near ±f32::MAX or subnormal — loses its direction on the way.
        let (g, _) = scaled_gradient(scalars, x, y, z);
        let k = light.factor_scaled(g.iter().any(|&c| c != 0.0).then_some(g));
        v.c = v.c.each(|c| (c * k).clamp(0.0, 1.0));
    }
    Ok(())
}
