//! Pre-classification: scalar voxels → straight RGBA voxels, before any interpolation.
//!
//! A scene with RGBA data skips this stage entirely; a scene with scalars either
//! pre-classifies here (then samples the RGBA result with any mode) or post-classifies
//! per sample ([`PostClassified`](crate::PostClassified)).

use crate::error::Error;
use crate::transfer::TransferFunction;
use crate::volume::Volume;
use crate::voxel::{ScalarVoxel, StraightF32};

/// Levoy's isosurface classifier (Levoy 1988): opacity `α_v` on the isosurface `f = f_v`,
/// falling linearly to 0 over a thickness of `r` voxels measured along the gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Isosurface {
    f_v: f32,
    alpha_v: f32,
    r: f32,
}

impl Isosurface {
    /// Isovalue `f_v` (scalar units), opacity `α_v ∈ [0, 1]`, thickness `r > 0` (voxels).
    ///
    /// # Errors
    /// [`Error::InvalidClassifier`] for non-finite values, `α_v` outside `[0, 1]`, or `r ≤ 0`.
    pub fn new(f_v: f32, alpha_v: f32, r: f32) -> Result<Self, Error> {
        if f_v.is_finite() && (0.0..=1.0).contains(&alpha_v) && r.is_finite() && r > 0.0 {
            Ok(Self { f_v, alpha_v, r })
        } else {
            Err(Error::InvalidClassifier)
        }
    }

    /// The opacity for value `f` and gradient magnitude `g ≥ 0`:
    /// `α_v·(1 − |f_v − f|/(r·g))` when `g > 0` and `|f_v − f| ≤ r·g`; `α_v` when `f = f_v`;
    /// otherwise 0.
    ///
    /// Error bound: within `4ε` (`ε = 2⁻²³`) of the exact value for the given `f32` input
    /// (`ISOSURFACE_ABS` in the tests).
    #[inline]
    pub fn opacity(&self, f: f32, g: f32) -> f32 {
        let diff = (self.f_v - f).abs();
        if diff == 0.0 {
            self.alpha_v
        } else if g > 0.0 && diff <= self.r * g {
            (self.alpha_v * (1.0 - diff / (self.r * g))).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// The gradient of a scalar volume at voxel `(x, y, z)`, per voxel: central differences
/// `(f[i+1] − f[i−1])/2` inside, one-sided differences at the faces, 0 along an axis of
/// length 1. Coordinates outside the grid are clamped.
///
/// Error bound: each component within `ε·m` of the exact difference of the `f32` values,
/// `ε = 2⁻²³`, `m` the largest magnitude of the differenced values (`GRADIENT_REL` in the tests).
pub fn gradient<V: ScalarVoxel>(vol: &Volume<'_, V>, x: usize, y: usize, z: usize) -> [f32; 3] {
    let [nx, ny, nz] = vol.dims();
    let at = |p: [usize; 3]| -> f32 {
        let [cx, cy, cz] = p;
        vol.get(cx, cy, cz).map_or(0.0, |v| v.scalar::<f32>())
    };
    let axis = |n: usize, c: usize, f: &dyn Fn(usize) -> f32| -> f32 {
        if n < 2 {
            0.0
        } else if c == 0 {
            f(1) - f(0)
        } else if c >= n - 1 {
            f(n - 1) - f(n - 2)
        } else {
            (f(c + 1) - f(c - 1)) * 0.5
        }
    };
    let (x, y, z) = (x.min(nx - 1), y.min(ny - 1), z.min(nz - 1));
    [
        axis(nx, x, &|k| at([k, y, z])),
        axis(ny, y, &|k| at([x, k, z])),
        axis(nz, z, &|k| at([x, y, k])),
    ]
}

fn check_out_len(expected: usize, out: usize) -> Result<(), Error> {
    if expected == out {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            expected,
            actual: out,
        })
    }
}

/// Classifies every voxel with Levoy's isosurface opacity and one straight `color`, writing
/// straight voxels into `out` (same layout).
///
/// # Errors
/// [`Error::LengthMismatch`] if `out` does not hold one voxel per input voxel,
/// [`Error::VoxelOutOfRange`] (index 0) if `color` is not in `[0, 1]`.
pub fn classify_isosurface<V: ScalarVoxel>(
    vol: &Volume<'_, V>,
    iso: &Isosurface,
    color: [f32; 3],
    out: &mut [StraightF32],
) -> Result<(), Error> {
    check_out_len(vol.data().len(), out.len())?;
    if !color.iter().all(|c| (0.0..=1.0).contains(c)) {
        return Err(Error::VoxelOutOfRange { index: 0 });
    }
    let [nx, ny, _] = vol.dims();
    for (i, (o, v)) in out.iter_mut().zip(vol.data()).enumerate() {
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        let [gx, gy, gz] = gradient(vol, x, y, z);
        let g = libm::sqrtf(gx * gx + gy * gy + gz * gz);
        *o = StraightF32 {
            c: color,
            a: iso.opacity(v.scalar::<f32>(), g),
        };
    }
    Ok(())
}

/// Classifies every voxel through a transfer function, writing straight voxels into `out`.
///
/// # Errors
/// [`Error::LengthMismatch`] if `out` does not hold one voxel per input voxel.
pub fn classify_transfer<V: ScalarVoxel, const N: usize>(
    vol: &Volume<'_, V>,
    tf: &TransferFunction<N>,
    out: &mut [StraightF32],
) -> Result<(), Error> {
    check_out_len(vol.data().len(), out.len())?;
    for (o, v) in out.iter_mut().zip(vol.data()) {
        let (c, a) = tf.eval(v.scalar::<f32>());
        *o = StraightF32 { c, a };
    }
    Ok(())
}
