//! The cameras of `render`: orthographic and perspective, as one Python class.

use pyo3::prelude::*;
use volsample::{Orthographic, Perspective, Ray};

use crate::core_err;

/// Which camera, by value (both are small `Copy` types).
#[derive(Clone, Copy, Debug)]
pub(crate) enum CameraKind {
    Ortho(Orthographic),
    Persp(Perspective),
}

/// One `Camera` type for both kinds, so each marcher's pixel loop is compiled once (not once
/// per camera type): the match costs one branch per ray.
impl volsample::Camera for CameraKind {
    #[inline]
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray {
        match self {
            CameraKind::Ortho(c) => c.ray(i, j, width, height),
            CameraKind::Persp(c) => c.ray(i, j, width, height),
        }
    }
}

/// A camera for `render`: build one with `Camera.orthographic`, `Camera.perspective` or
/// `Camera.looking_down_z`. Coordinates are voxel units, `(x, y, z)`.
#[pyclass(frozen, module = "volsample")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Camera {
    pub(crate) kind: CameraKind,
}

#[pymethods]
impl Camera {
    /// Parallel rays along `dir` from an image plane centred at `eye`; `up` is the image's
    /// vertical, `extent` the image's width in voxels.
    #[staticmethod]
    fn orthographic(eye: [f32; 3], dir: [f32; 3], up: [f32; 3], extent: f32) -> PyResult<Self> {
        let c = Orthographic::new(eye, dir, up, extent).map_err(core_err)?;
        Ok(Self {
            kind: CameraKind::Ortho(c),
        })
    }

    /// A pinhole camera at `eye` looking at `target`, `up` the image vertical, vertical field
    /// of view `fov_y` in radians.
    #[staticmethod]
    fn perspective(eye: [f32; 3], target: [f32; 3], up: [f32; 3], fov_y: f32) -> PyResult<Self> {
        let c = Perspective::new(eye, target, up, fov_y).map_err(core_err)?;
        Ok(Self {
            kind: CameraKind::Persp(c),
        })
    }

    /// The orthographic camera looking along +z at a volume of `shape` `(z, y, x[, 4])`:
    /// in an `x × y` image, pixel `(i, j)` looks down voxel column `(x, y) = (i, j)`.
    #[staticmethod]
    fn looking_down_z(shape: Vec<usize>) -> PyResult<Self> {
        if shape.len() < 3 {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "shape must be (z, y, x) or (z, y, x, 4)",
            ));
        }
        let c = Orthographic::looking_down_z([shape[2], shape[1], shape[0]]).map_err(core_err)?;
        Ok(Self {
            kind: CameraKind::Ortho(c),
        })
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.kind)
    }
}
