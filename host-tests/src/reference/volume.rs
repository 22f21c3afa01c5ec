//! Voxels and volumes (straight, associated, scalar) and the per-voxel conversions.

use super::tf::RefTransferFunction;
use super::MAX_OPTICAL_DEPTH;

/// Linear index of voxel `(x, y, z)` in a volume of dimensions `dims`: `x + nx·(y + ny·z)`.
///
/// No bounds check: the caller keeps `x < nx`, `y < ny`, `z < nz`.
pub fn linear_index(dims: [usize; 3], voxel: [usize; 3]) -> usize {
    voxel[0] + dims[0] * (voxel[1] + dims[1] * voxel[2])
}

/// Number of voxels `nx·ny·nz`.
fn voxel_count(dims: [usize; 3]) -> usize {
    dims[0] * dims[1] * dims[2]
}

/// Calls `f` for every voxel coordinate in storage order (x fastest, then y, then z).
fn collect_grid<T>(dims: [usize; 3], mut f: impl FnMut([usize; 3]) -> T) -> Vec<T> {
    let mut out = Vec::with_capacity(voxel_count(dims));
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                out.push(f([x, y, z]));
            }
        }
    }
    out
}

/// Optical depth `−ln(1 − α)` of opacity `alpha`, capped at [`MAX_OPTICAL_DEPTH`].
///
/// `alpha = 1` gives exactly `MAX_OPTICAL_DEPTH`; `alpha = 0` gives `0`.
pub fn optical_depth(alpha: f64) -> f64 {
    let depth = -(-alpha).ln_1p();
    depth.min(MAX_OPTICAL_DEPTH)
}

/// A straight (unweighted) RGBA voxel: color in `[0, 1]³`, opacity in `[0, 1]` for `d_ref`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefVoxel {
    /// Straight color `C`.
    pub color: [f64; 3],
    /// Opacity `α` over the reference distance.
    pub alpha: f64,
}

impl RefVoxel {
    /// Builds a voxel from its straight color and opacity.
    pub fn new(color: [f64; 3], alpha: f64) -> Self {
        Self { color, alpha }
    }

    /// Associated (premultiplied) form `(α·C, α)`.
    pub fn associated(self) -> RefAssoc {
        RefAssoc {
            color: [
                self.alpha * self.color[0],
                self.alpha * self.color[1],
                self.alpha * self.color[2],
            ],
            alpha: self.alpha,
        }
    }

    /// Extinction form: `τ = optical_depth(α)/d_ref` (capped, see [`MAX_OPTICAL_DEPTH`]) and
    /// `C^τ = τ·C`.
    pub fn extinction(self, d_ref: f64) -> RefExtinction {
        let tau = optical_depth(self.alpha) / d_ref;
        RefExtinction {
            tau,
            color_tau: [
                tau * self.color[0],
                tau * self.color[1],
                tau * self.color[2],
            ],
        }
    }
}

/// An associated (opacity-weighted, premultiplied) RGBA value: a voxel, a sample, or an
/// accumulated pixel. Each color channel is at most `alpha` for valid data.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefAssoc {
    /// Associated color `C̃ = α·C`.
    pub color: [f64; 3],
    /// Opacity `α`.
    pub alpha: f64,
}

impl RefAssoc {
    /// Fully transparent black `(0, 0, 0, 0)`.
    pub const TRANSPARENT: Self = Self {
        color: [0.0; 3],
        alpha: 0.0,
    };

    /// Builds an associated value from its associated color and opacity.
    pub fn new(color: [f64; 3], alpha: f64) -> Self {
        Self { color, alpha }
    }

    /// Largest absolute difference over the four channels.
    pub fn max_abs_diff(self, other: RefAssoc) -> f64 {
        (0..3)
            .map(|k| (self.color[k] - other.color[k]).abs())
            .fold((self.alpha - other.alpha).abs(), f64::max)
    }

    /// True when every channel is finite, `α ∈ [0, 1]` and each color channel is in
    /// `[0, α]`, each bound widened by `tol`.
    pub fn is_valid(self, tol: f64) -> bool {
        self.alpha.is_finite()
            && self.alpha >= -tol
            && self.alpha <= 1.0 + tol
            && self
                .color
                .iter()
                .all(|c| c.is_finite() && *c >= -tol && *c <= self.alpha + tol)
    }

    /// Straight form `(C̃/α, α)`; the color is `0` when `α = 0`.
    pub fn straight(self) -> RefVoxel {
        if self.alpha == 0.0 {
            return RefVoxel::new([0.0; 3], 0.0);
        }
        RefVoxel {
            color: [
                self.color[0] / self.alpha,
                self.color[1] / self.alpha,
                self.color[2] / self.alpha,
            ],
            alpha: self.alpha,
        }
    }
}

/// Extinction coefficient and extinction-weighted color of a voxel or a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefExtinction {
    /// Extinction coefficient `τ` (per voxel unit of distance).
    pub tau: f64,
    /// Extinction-weighted color `C^τ = τ·C`.
    pub color_tau: [f64; 3],
}

/// A volume of straight RGBA voxels.
#[derive(Clone, Debug, PartialEq)]
pub struct RefVolume {
    /// Dimensions `[nx, ny, nz]`.
    pub dims: [usize; 3],
    /// Voxels in storage order (see [`linear_index`]).
    pub voxels: Vec<RefVoxel>,
    /// Reference distance `d′` of the opacities.
    pub d_ref: f64,
}

impl RefVolume {
    /// Builds a volume from its voxels in storage order.
    ///
    /// # Panics
    /// If `voxels.len() != nx·ny·nz`.
    pub fn new(dims: [usize; 3], voxels: Vec<RefVoxel>, d_ref: f64) -> Self {
        assert_eq!(voxels.len(), voxel_count(dims), "voxel count != nx*ny*nz");
        Self {
            dims,
            voxels,
            d_ref,
        }
    }

    /// Builds a volume by calling `f([x, y, z])` for every voxel.
    pub fn from_fn(dims: [usize; 3], d_ref: f64, f: impl FnMut([usize; 3]) -> RefVoxel) -> Self {
        Self::new(dims, collect_grid(dims, f), d_ref)
    }

    /// Builds a volume whose voxels are all `voxel`.
    pub fn uniform(dims: [usize; 3], voxel: RefVoxel, d_ref: f64) -> Self {
        Self::new(dims, vec![voxel; voxel_count(dims)], d_ref)
    }

    /// The voxel at `(x, y, z)`.
    ///
    /// # Panics
    /// If the coordinate is outside the volume.
    pub fn get(&self, voxel: [usize; 3]) -> RefVoxel {
        assert!(
            (0..3).all(|k| voxel[k] < self.dims[k]),
            "voxel outside volume"
        );
        self.voxels[linear_index(self.dims, voxel)]
    }

    /// The same volume with every voxel in associated form (exact `f64` products).
    pub fn to_associated(&self) -> RefAssocVolume {
        RefAssocVolume {
            dims: self.dims,
            voxels: self.voxels.iter().map(|v| v.associated()).collect(),
            d_ref: self.d_ref,
        }
    }
}

/// A volume of stored associated voxels `(α·C, α)` (for `Preweighted`; the values may be
/// quantized by the caller).
#[derive(Clone, Debug, PartialEq)]
pub struct RefAssocVolume {
    /// Dimensions `[nx, ny, nz]`.
    pub dims: [usize; 3],
    /// Associated voxels in storage order (see [`linear_index`]).
    pub voxels: Vec<RefAssoc>,
    /// Reference distance `d′` of the opacities.
    pub d_ref: f64,
}

impl RefAssocVolume {
    /// Builds a volume from its associated voxels in storage order.
    ///
    /// # Panics
    /// If `voxels.len() != nx·ny·nz`.
    pub fn new(dims: [usize; 3], voxels: Vec<RefAssoc>, d_ref: f64) -> Self {
        assert_eq!(voxels.len(), voxel_count(dims), "voxel count != nx*ny*nz");
        Self {
            dims,
            voxels,
            d_ref,
        }
    }

    /// Builds a volume by calling `f([x, y, z])` for every voxel.
    pub fn from_fn(dims: [usize; 3], d_ref: f64, f: impl FnMut([usize; 3]) -> RefAssoc) -> Self {
        Self::new(dims, collect_grid(dims, f), d_ref)
    }

    /// The same volume in straight form (`C̃/α`, color `0` where `α = 0`).
    pub fn to_straight(&self) -> RefVolume {
        RefVolume {
            dims: self.dims,
            voxels: self.voxels.iter().map(|v| v.straight()).collect(),
            d_ref: self.d_ref,
        }
    }
}

/// A volume of scalars, classified by a transfer function (or Levoy's classifier).
#[derive(Clone, Debug, PartialEq)]
pub struct RefScalarVolume {
    /// Dimensions `[nx, ny, nz]`.
    pub dims: [usize; 3],
    /// Scalars in storage order (see [`linear_index`]).
    pub scalars: Vec<f64>,
    /// Reference distance `d′` of the opacities the transfer function produces.
    pub d_ref: f64,
}

impl RefScalarVolume {
    /// Builds a volume from its scalars in storage order.
    ///
    /// # Panics
    /// If `scalars.len() != nx·ny·nz`.
    pub fn new(dims: [usize; 3], scalars: Vec<f64>, d_ref: f64) -> Self {
        assert_eq!(scalars.len(), voxel_count(dims), "scalar count != nx*ny*nz");
        Self {
            dims,
            scalars,
            d_ref,
        }
    }

    /// Builds a volume by calling `f([x, y, z])` for every voxel.
    pub fn from_fn(dims: [usize; 3], d_ref: f64, f: impl FnMut([usize; 3]) -> f64) -> Self {
        Self::new(dims, collect_grid(dims, f), d_ref)
    }

    /// Pre-classification: every voxel mapped through `tf` (same dims and `d_ref`).
    pub fn classify(&self, tf: &RefTransferFunction) -> RefVolume {
        RefVolume {
            dims: self.dims,
            voxels: self.scalars.iter().map(|&s| tf.eval(s)).collect(),
            d_ref: self.d_ref,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_index_is_x_fastest() {
        let dims = [4, 3, 2];
        assert_eq!(linear_index(dims, [0, 0, 0]), 0);
        assert_eq!(linear_index(dims, [1, 0, 0]), 1);
        assert_eq!(linear_index(dims, [0, 1, 0]), 4);
        assert_eq!(linear_index(dims, [0, 0, 1]), 12);
        assert_eq!(linear_index(dims, [3, 2, 1]), 23);
        let vol = RefScalarVolume::from_fn(dims, 1.0, |[x, y, z]| (x + 10 * y + 100 * z) as f64);
        assert_eq!(vol.scalars[linear_index(dims, [3, 2, 1])], 123.0);
    }

    #[test]
    fn optical_depth_limits() {
        assert_eq!(optical_depth(0.0), 0.0);
        assert_eq!(optical_depth(1.0), MAX_OPTICAL_DEPTH);
        let a = 1.0 - (-2.0f64).exp();
        assert!((optical_depth(a) - 2.0).abs() < 1e-14);
        // Just below the cap and just above it.
        assert!(optical_depth(1.0 - 1e-15) < MAX_OPTICAL_DEPTH);
        assert_eq!(
            optical_depth(1.0 - 1e-300),
            MAX_OPTICAL_DEPTH.min(-(1e-300f64).ln())
        );
    }

    #[test]
    fn extinction_of_voxel() {
        let a = 1.0 - (-3.0f64).exp();
        let e = RefVoxel::new([0.5, 1.0, 0.0], a).extinction(2.0);
        assert!((e.tau - 1.5).abs() < 1e-14);
        assert!((e.color_tau[0] - 0.75).abs() < 1e-14);
        assert!((e.color_tau[1] - 1.5).abs() < 1e-14);
        assert_eq!(e.color_tau[2], 0.0);
        let opaque = RefVoxel::new([1.0; 3], 1.0).extinction(0.5);
        assert_eq!(opaque.tau, 128.0);
        assert!(opaque.tau.is_finite());
    }

    #[test]
    fn associated_round_trip() {
        let v = RefVoxel::new([0.25, 0.5, 1.0], 0.5);
        let a = v.associated();
        assert_eq!(a, RefAssoc::new([0.125, 0.25, 0.5], 0.5));
        assert_eq!(a.straight(), v);
        assert_eq!(RefAssoc::TRANSPARENT.straight(), RefVoxel::default());
        let vol = RefVolume::uniform([2, 2, 2], v, 1.0);
        assert_eq!(vol.to_associated().to_straight(), vol);
    }

    #[test]
    fn assoc_helpers() {
        let a = RefAssoc::new([0.1, 0.2, 0.3], 0.5);
        let b = RefAssoc::new([0.1, 0.25, 0.3], 0.4);
        assert!((a.max_abs_diff(b) - 0.1).abs() < 1e-16);
        assert!(a.is_valid(0.0));
        assert!(!RefAssoc::new([0.6, 0.0, 0.0], 0.5).is_valid(0.0));
        assert!(RefAssoc::new([0.6, 0.0, 0.0], 0.5).is_valid(0.2));
        assert!(!RefAssoc::new([f64::NAN, 0.0, 0.0], 0.5).is_valid(1.0));
    }

    #[test]
    #[should_panic(expected = "voxel count")]
    fn new_rejects_wrong_length() {
        let _ = RefVolume::new([2, 2, 2], vec![RefVoxel::default(); 7], 1.0);
    }
}
