//! Scenes: what to render and which stages it calls for.
//!
//! A [`Scene`] names its volume (generated or loaded), classification, shading, step,
//! reference distance, compositing order, termination, background and camera; the methods
//! (mode × precision × filter) are chosen per render. [`Scene::prepare`] runs exactly the
//! pre-passes the scene needs — classification only for scalar data, shading only with a
//! light — and the pipeline ([`crate::pipeline`]) picks the per-sample stages by type.

pub mod continuous;
#[cfg(feature = "app")]
pub mod generate;
pub mod load;
pub mod phantom;

use volsample::classify::{classify_isosurface, classify_transfer, Isosurface};
use volsample::shade::{shade_in_place, Light};
use volsample::{ControlPoint, Sample, StraightF32, Volume};

use crate::float_checks::CameraSpec;

/// The volume data of a scene.
#[derive(Debug, Clone)]
pub enum VolumeData {
    /// Straight RGBA voxels: no classification stage.
    Rgba(Vec<StraightF32>),
    /// Scalars (any range; 8-bit data holds `0..=255`), classified by the scene.
    Scalar(Vec<f32>),
}

/// How scalar data becomes RGBA.
#[derive(Debug, Clone)]
pub enum Classification {
    /// RGBA data: nothing to classify.
    None,
    /// Levoy's isosurface classifier with one straight color.
    Isosurface {
        /// Isovalue `f_v`.
        f_v: f32,
        /// Opacity at the isovalue.
        alpha_v: f32,
        /// Thickness in voxels.
        r: f32,
        /// Straight color of the material.
        color: [f32; 3],
    },
    /// A piecewise-linear transfer function (also usable per sample by `PostClassified`).
    Transfer(Vec<ControlPoint>),
}

/// A complete scene description.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Short name (used in file names).
    pub name: String,
    /// One line describing what the scene shows.
    pub description: String,
    /// Volume dimensions.
    pub dims: [usize; 3],
    /// The voxels.
    pub data: VolumeData,
    /// Classification of scalar data.
    pub classification: Classification,
    /// Pre-shading light, if any.
    pub light: Option<Light>,
    /// Step `d` (voxels).
    pub step: f32,
    /// Ray phase in `[0, 1)`.
    pub phase: f32,
    /// Reference distance `d′` (voxels).
    pub d_ref: f32,
    /// Early-termination threshold (`1.0`: none).
    pub a_stop: f32,
    /// Associated background.
    pub background: Sample,
    /// The camera.
    pub camera: CameraSpec,
    /// Image width and height.
    pub image: [usize; 2],
    /// The scene's definition before voxelization, where it has one (the generated scenes):
    /// the report integrates its truth from it ([`continuous::continuous_truth`]).
    pub continuous: Option<continuous::Continuous>,
}

/// The effects (stages) a scene calls for, as the pipeline will build them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Effects {
    /// Pre-classification of scalar data.
    pub classification: bool,
    /// Pre-shading with a light.
    pub shading: bool,
    /// Opacity correction (`d ≠ d′`, opacity-based modes).
    pub correction: bool,
    /// Early termination (`A_stop < 1`).
    pub termination: bool,
    /// A non-transparent background.
    pub background: bool,
}

impl std::fmt::Display for Effects {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut v = Vec::new();
        if self.classification {
            v.push("classify");
        }
        if self.shading {
            v.push("shade");
        }
        if self.correction {
            v.push("opacity-correct");
        }
        if self.termination {
            v.push("early-stop");
        }
        if self.background {
            v.push("background");
        }
        if v.is_empty() {
            f.write_str("(bare kernel)")
        } else {
            f.write_str(&v.join(", "))
        }
    }
}

/// A scene after its pre-passes: RGBA voxels ready for any mode, plus the scalars and
/// transfer function where `PostClassified` can run.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Straight RGBA voxels.
    pub rgba: Vec<StraightF32>,
    /// Scalars and control points, for `PostClassified` (transfer-function scenes only).
    pub post: Option<(Vec<f32>, Vec<ControlPoint>)>,
}

impl Scene {
    /// The stages this scene calls for (correction as for opacity-based modes).
    pub fn effects(&self) -> Effects {
        Effects {
            classification: matches!(self.data, VolumeData::Scalar(_)),
            shading: self.light.is_some(),
            correction: self.step != self.d_ref,
            termination: self.a_stop < 1.0,
            background: self.background != Sample::TRANSPARENT,
        }
    }

    /// Runs the pre-passes the scene calls for, and only those.
    ///
    /// # Errors
    /// Invalid data or classifier parameters, as the core reports them.
    pub fn prepare(&self) -> Result<Prepared, volsample::Error> {
        match (&self.data, &self.classification) {
            (VolumeData::Rgba(v), _) => {
                Volume::new(v, self.dims)?;
                Ok(Prepared {
                    rgba: v.clone(),
                    post: None,
                })
            }
            (VolumeData::Scalar(s), cls) => {
                let vol = Volume::new(s, self.dims)?;
                let mut rgba = vec![StraightF32::default(); s.len()];
                let mut post = None;
                match cls {
                    Classification::None => {
                        return Err(volsample::Error::InvalidClassifier);
                    }
                    Classification::Isosurface {
                        f_v,
                        alpha_v,
                        r,
                        color,
                    } => {
                        let iso = Isosurface::new(*f_v, *alpha_v, *r)?;
                        classify_isosurface(&vol, &iso, *color, &mut rgba)?;
                    }
                    Classification::Transfer(points) => {
                        let tf = volsample::TransferFunction::<64>::new(points)?;
                        classify_transfer(&vol, &tf, &mut rgba)?;
                        post = Some((s.clone(), points.clone()));
                    }
                }
                if let Some(light) = &self.light {
                    shade_in_place(&vol, light, &mut rgba)?;
                }
                Ok(Prepared { rgba, post })
            }
        }
    }
}
