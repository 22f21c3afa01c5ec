//! Pre-shading: lighting straight voxel colors with a directional light before interpolation
//! (the papers' "classified and shaded before interpolation").
//!
//! A scene without a light skips this stage; with [`Light::UNLIT`] it would be the identity.

use crate::classify::gradient;
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
    /// # Errors
    /// [`Error::InvalidLight`] for non-finite input, a zero direction or negative
    /// coefficients.
    pub fn new(dir: [f32; 3], ambient: f32, diffuse: f32) -> Result<Self, Error> {
        let n = libm::sqrtf(dir.iter().map(|d| d * d).sum());
        let ok = dir.iter().all(|d| d.is_finite())
            && n.is_finite()
            && n > 0.0
            && ambient.is_finite()
            && diffuse.is_finite()
            && ambient >= 0.0
            && diffuse >= 0.0;
        if !ok {
            return Err(Error::InvalidLight);
        }
        Ok(Self {
            dir: dir.map(|d| d / n),
            ambient,
            diffuse,
        })
    }

    /// The light factor for a gradient `g`: `min(1, k_a + k_d·|n·L|)`.
    ///
    /// Error bound: within `6ε` (`ε = 2⁻²³`) of the exact value for the given `f32` input
    /// (`LIGHT_FACTOR_ABS` in the tests).
    #[inline]
    pub fn factor(&self, g: [f32; 3]) -> f32 {
        let len = libm::sqrtf(g.iter().map(|x| x * x).sum());
        let cos = if len > 0.0 && len.is_finite() {
            (g.iter()
                .zip(self.dir.iter())
                .map(|(a, b)| a * b)
                .sum::<f32>()
                / len)
                .abs()
        } else {
            1.0
        };
        (self.ambient + self.diffuse * cos.min(1.0)).min(1.0)
    }
}

/// Shades straight voxels `rgba` in place with `light`, taking normals from the scalar
/// volume `scalars` (same dimensions); opacity is unchanged.
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
        let k = light.factor(gradient(scalars, x, y, z));
        v.c = v.c.map(|c| (c * k).clamp(0.0, 1.0));
    }
    Ok(())
}
