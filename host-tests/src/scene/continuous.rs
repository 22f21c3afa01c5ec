//! The continuous definitions of the generated scenes, and the truth integrated from them.
//!
//! Every generated scene is a shape (or a scalar field) defined at every point of space; its
//! voxels are that definition sampled at the voxel centres. The report's second truth,
//! [`continuous_truth`], integrates the definition itself along each pixel's ray: exact
//! emission–absorption over fine substeps, the same rays (one per pixel, through its centre)
//! as the methods, over the same box and background. Unlike the interpolated-extinction truth
//! of [`crate::report::ground_truth`] (the trilinear `τ` field of the voxels, which
//! `ExtinctionWeighted` converges to by construction), it favours no method: every method's
//! error against it includes what voxelizing the shape lost.

use std::fmt;
use std::sync::Arc;

use volsample::shade::Light;

use super::{Classification, Scene};
use crate::reference::{self, RefIsosurface, RefTransferFunction, RefVoxel};

/// A straight color and an opacity per reference distance at a point of voxel space.
pub type RgbaField = Arc<dyn Fn([f64; 3]) -> ([f64; 3], f64) + Send + Sync>;

/// A scalar value at a point of voxel space (in the units the scene classifies).
pub type ScalarField = Arc<dyn Fn([f64; 3]) -> f64 + Send + Sync>;

/// A scene's definition before voxelization.
#[derive(Clone)]
pub enum Continuous {
    /// Straight RGBA at every point (the RGBA scenes: their voxels are this at the centres).
    Rgba(RgbaField),
    /// A scalar field at every point, classified (and shaded) point by point as the scene's
    /// [`Classification`] and light say: a transfer function is the continuous
    /// post-classified integral; Levoy's isosurface takes the gradient by central differences
    /// one voxel apart, as the classifier does on the grid.
    Scalar(ScalarField),
}

impl fmt::Debug for Continuous {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Continuous::Rgba(_) => "Continuous::Rgba(..)",
            Continuous::Scalar(_) => "Continuous::Scalar(..)",
        })
    }
}

impl Continuous {
    /// A straight RGBA field from a closure.
    pub fn rgba(f: impl Fn([f64; 3]) -> ([f64; 3], f64) + Send + Sync + 'static) -> Self {
        Continuous::Rgba(Arc::new(f))
    }

    /// A scalar field from a closure.
    pub fn scalar(f: impl Fn([f64; 3]) -> f64 + Send + Sync + 'static) -> Self {
        Continuous::Scalar(Arc::new(f))
    }
}

/// The straight RGBA of `scene`'s definition at `p`, or `None` for a scene without one.
///
/// For scalar scenes: the transfer function of the value (not quantized), or Levoy's opacity
/// of the value and its central-difference gradient with the scene's color, shaded by the
/// scene's light ([`Light::factor`]).
pub fn rgba_at(scene: &Scene, p: [f64; 3]) -> Option<RefVoxel> {
    match scene.continuous.as_ref()? {
        Continuous::Rgba(f) => {
            let (c, a) = f(p);
            Some(RefVoxel::new(c, a))
        }
        Continuous::Scalar(f) => match &scene.classification {
            Classification::None => None,
            Classification::Transfer(points) => Some(ref_tf(points).eval(f(p))),
            Classification::Isosurface {
                f_v,
                alpha_v,
                r,
                color,
            } => {
                let iso = RefIsosurface {
                    f_v: f64::from(*f_v),
                    alpha_v: f64::from(*alpha_v),
                    r: f64::from(*r),
                };
                let g: [f64; 3] = std::array::from_fn(|k| {
                    let (mut a, mut b) = (p, p);
                    a[k] += 1.0;
                    b[k] -= 1.0;
                    (f(a) - f(b)) / 2.0
                });
                let gm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
                let alpha = iso.opacity(f(p), gm);
                let shade = scene
                    .light
                    .as_ref()
                    .map_or(1.0, |l: &Light| f64::from(l.factor(g.map(|x| x as f32))));
                Some(RefVoxel::new(
                    color.map(|c| (f64::from(c) * shade).min(1.0)),
                    alpha,
                ))
            }
        },
    }
}

fn ref_tf(points: &[volsample::ControlPoint]) -> RefTransferFunction {
    RefTransferFunction::new(
        points
            .iter()
            .map(|p| {
                reference::RefControlPoint::new(f64::from(p.s), p.c.map(f64::from), f64::from(p.a))
            })
            .collect(),
    )
}

#[cfg(feature = "app")]
/// The truth of `scene` from its continuous definition: per pixel (row-major), the displayed
/// color of the exact emission–absorption integral of [`rgba_at`] along the pixel's ray over
/// the volume's box (`[−½, n − ½]` per axis, as the methods clip), substeps of at most `h`
/// voxels, over the scene's background. `None` for a scene without a definition. Rows run on
/// all cores.
pub fn continuous_truth(scene: &Scene, h: f64) -> Option<Vec<[f32; 3]>> {
    use crate::reference::{integrate_segment, RefAssoc, RefExtinction};
    scene.continuous.as_ref()?;
    let d_ref = f64::from(scene.d_ref);
    let field = |p: [f64; 3]| -> RefExtinction {
        rgba_at(scene, p).map_or_else(RefExtinction::default, |v| v.extinction(d_ref))
    };
    let cam = crate::report::ref_camera(scene);
    let [w, hgt] = scene.image;
    let bg = RefAssoc::new(
        scene.background.c.map(f64::from),
        f64::from(scene.background.a),
    );
    Some(crate::report::per_pixel(w, hgt, |i, j| {
        let ray = reference::camera_ray(&cam, w, hgt, i, j);
        let acc = match reference::clip_ray(scene.dims, &ray) {
            Some((t0, t1)) => integrate_segment(&ray, t0, t1, h, field),
            None => RefAssoc::TRANSPARENT,
        };
        reference::over_background(acc, bg).color.map(|c| c as f32)
    }))
}
