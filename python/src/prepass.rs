//! The classification and shading pre-passes (before any interpolation): scalar volumes
//! `(z, y, x)` to straight `float32` RGBA (`classify::classify_transfer`,
//! `classify::classify_isosurface` with Levoy's `Isosurface`), the scalar gradient per voxel
//! (`classify::gradient`) and shading of straight RGBA with a directional `Light`
//! (`shade::shade_in_place`, on a copy).

use numpy::ndarray::Array4;
use numpy::{IntoPyArray, PyArray4};
use pyo3::prelude::*;
use volsample::classify::{self, Isosurface};
use volsample::shade::{shade_in_place, Light as CoreLight};
use volsample::voxel::ScalarVoxel;
use volsample::{Error, StraightF32, Volume};

use crate::post::{read_scalars_for, Scalars, TransferFunction};
use crate::{core_err, read_volume, straight_of, to_array4, value_err};

/// Runs `$body` with `$d` bound to the scalar voxels at hand (one instance per scalar type).
macro_rules! with_scalars {
    ($scalars:expr, $d:ident => $body:expr) => {
        match $scalars {
            Scalars::U8($d) => $body,
            Scalars::U16($d) => $body,
            Scalars::F32($d) => $body,
        }
    };
}

/// Straight `(n, 4)` voxels as `[r, g, b, a]` rows.
fn rows(v: Vec<StraightF32>) -> Vec<[f32; 4]> {
    v.into_iter()
        .map(|s| [s.c[0], s.c[1], s.c[2], s.a])
        .collect()
}

/// A directional light with ambient and diffuse (two-sided Lambert) terms (the core's
/// `shade::Light`): a shaded color is `C·min(1, k_a + k_d·|n·L|)`, `n` the normalised scalar
/// gradient, `|n·L|` taken as 1 where the gradient vanishes.
#[pyclass(frozen, module = "volsample")]
#[derive(Clone, Debug)]
pub(crate) struct Light {
    light: CoreLight,
    dir: [f32; 3],
    ambient: f32,
    diffuse: f32,
}

#[pymethods]
impl Light {
    /// A light shining along `direction` (`(x, y, z)`, any finite non-zero length; normalised
    /// by the core), ambient `k_a ≥ 0`, diffuse `k_d ≥ 0`.
    #[new]
    #[pyo3(signature = (direction, ambient = 0.25, diffuse = 0.75))]
    fn new(direction: [f32; 3], ambient: f32, diffuse: f32) -> PyResult<Self> {
        let light = CoreLight::new(direction, ambient, diffuse).map_err(core_err)?;
        Ok(Self {
            light,
            dir: direction,
            ambient,
            diffuse,
        })
    }

    /// The identity light (`k_a = 1`, `k_d = 0`): shading with it changes no color.
    #[staticmethod]
    fn unlit() -> Self {
        Self {
            light: CoreLight::UNLIT,
            dir: [0.0, 0.0, 1.0],
            ambient: 1.0,
            diffuse: 0.0,
        }
    }

    /// The direction as given, `(x, y, z)`.
    #[getter]
    fn direction(&self) -> [f32; 3] {
        self.dir
    }

    #[getter]
    fn ambient(&self) -> f32 {
        self.ambient
    }

    #[getter]
    fn diffuse(&self) -> f32 {
        self.diffuse
    }

    fn __repr__(&self) -> String {
        let [x, y, z] = self.dir;
        format!(
            "Light(direction=({x}, {y}, {z}), ambient={}, diffuse={})",
            self.ambient, self.diffuse
        )
    }
}

/// Classifies every voxel of a scalar volume `(z, y, x)` (`uint8`, `uint16` or `float32`)
/// through a transfer function: straight `float32` RGBA `(z, y, x, 4)`
/// (`classify::classify_transfer`).
#[pyfunction]
pub(crate) fn classify_transfer<'py>(
    py: Python<'py>,
    scalars: &Bound<'py, PyAny>,
    tf: PyRef<'py, TransferFunction>,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let (s, dims) = read_scalars_for(scalars, "classify_transfer")?;
    let tf = &tf.tf;
    let out = py.allow_threads(|| {
        with_scalars!(&s, d => {
            let vol = Volume::new(d, dims)?;
            let mut out = vec![StraightF32::default(); d.len()];
            classify::classify_transfer(&vol, tf, &mut out)?;
            Ok::<_, Error>(rows(out))
        })
    });
    Ok(to_array4(out.map_err(core_err)?, dims)?.into_pyarray(py))
}

/// Classifies every voxel of a scalar volume with Levoy's isosurface opacity and one straight
/// `color`: straight `float32` RGBA `(z, y, x, 4)` (`classify::classify_isosurface`).
#[pyfunction]
#[pyo3(signature = (scalars, isovalue, opacity = 1.0, thickness = 1.0, color = [1.0, 1.0, 1.0]))]
pub(crate) fn classify_isosurface<'py>(
    py: Python<'py>,
    scalars: &Bound<'py, PyAny>,
    isovalue: f32,
    opacity: f32,
    thickness: f32,
    color: [f32; 3],
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let iso = Isosurface::new(isovalue, opacity, thickness).map_err(core_err)?;
    // The core reports a bad color as voxel 0 out of range; name it here instead.
    if !color.iter().all(|c| (0.0..=1.0).contains(c)) {
        return Err(value_err(
            "color must be three values in [0, 1] (straight r, g, b)",
        ));
    }
    let (s, dims) = read_scalars_for(scalars, "classify_isosurface")?;
    let out = py.allow_threads(|| {
        with_scalars!(&s, d => {
            let vol = Volume::new(d, dims)?;
            let mut out = vec![StraightF32::default(); d.len()];
            classify::classify_isosurface(&vol, &iso, color, &mut out)?;
            Ok::<_, Error>(rows(out))
        })
    });
    Ok(to_array4(out.map_err(core_err)?, dims)?.into_pyarray(py))
}

/// The gradient of every voxel of `vol`, `(gx, gy, gz)` per voxel, in voxel order.
fn gradients<V: ScalarVoxel>(vol: &Volume<'_, V>) -> Vec<[f32; 3]> {
    let [nx, ny, nz] = vol.dims();
    let mut out = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                out.push(classify::gradient(vol, x, y, z));
            }
        }
    }
    out
}

/// The gradient of a scalar volume `(z, y, x)` at every voxel, `(z, y, x, 3)` `float32`
/// `(∂f/∂x, ∂f/∂y, ∂f/∂z)` per voxel (`classify::gradient`: central differences inside,
/// one-sided at the faces, 0 along an axis of length 1): the normals `classify_isosurface`
/// and `shade` use.
#[pyfunction]
pub(crate) fn gradient<'py>(
    py: Python<'py>,
    scalars: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let (s, dims) = read_scalars_for(scalars, "gradient")?;
    let out = py.allow_threads(|| {
        with_scalars!(&s, d => {
            let vol = Volume::new(d, dims)?;
            Ok::<_, Error>(gradients(&vol))
        })
    });
    let flat: Vec<f32> = out.map_err(core_err)?.into_iter().flatten().collect();
    Array4::from_shape_vec((dims[2], dims[1], dims[0], 3), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| value_err(format!("internal shape error: {e}")))
}

/// Shades a straight RGBA volume `(z, y, x, 4)` (`uint8`, `n/255`, or `float32`) with
/// `light`, the normals taken from the scalar volume `scalars` of the same `(z, y, x)`:
/// a new straight `float32` volume, opacities unchanged (`shade::shade_in_place` on a copy;
/// the input is not modified).
#[pyfunction]
pub(crate) fn shade<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    scalars: &Bound<'py, PyAny>,
    light: PyRef<'py, Light>,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let vol = read_volume(volume)?;
    let (s, dims) = read_scalars_for(scalars, "shade")?;
    if dims != vol.dims {
        let [x, y, z] = dims;
        let [vx, vy, vz] = vol.dims;
        return Err(value_err(format!(
            "scalars have shape ({z}, {y}, {x}) but the volume has (z, y, x) = ({vz}, {vy}, {vx}): they must match"
        )));
    }
    let light = light.light;
    let out = py.allow_threads(|| {
        let mut rgba = straight_of(&vol.channels);
        Volume::new(&rgba, dims)?;
        with_scalars!(&s, d => {
            let sv = Volume::new(d, dims)?;
            shade_in_place(&sv, &light, &mut rgba)?;
        });
        Ok::<_, Error>(rows(rgba))
    });
    Ok(to_array4(out.map_err(core_err)?, dims)?.into_pyarray(py))
}
