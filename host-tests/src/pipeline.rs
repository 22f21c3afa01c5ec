//! Scene-driven pipelines: a [`Method`] (mode × precision × filter) applied to a prepared
//! [`Scene`], with every stage chosen by type once per render (never per sample).
//!
//! Opacity correction is on exactly when `d ≠ d′` (and the mode is opacity-based), early
//! termination exactly when `A_stop < 1`, and the background is composited once per ray; the
//! core picks the first two by type ([`volsample::RayMarcher`]), so an absent stage has no
//! code in the inner loop.

use std::time::Instant;

use volsample::fixed_point::{self, IntCorrection, IntPos, IntSample, IntSampler, IntStop, ONE};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Camera, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack, Mode, Nearest,
    OpacityWeighted, Orthographic, Perspective, PostClassified, Preweighted, RayMarcher, Sample,
    Separate, Step, StraightF32, StraightU8, TransferFunction, Trilinear, TriquadraticBSpline,
    Volume,
};

use crate::float_checks::{CameraSpec, FilterKind};
use crate::scene::{Prepared, Scene};

/// What is interpolated, including the storage it reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModeChoice {
    /// `Separate` on straight voxels.
    Separate,
    /// `OpacityWeighted` on straight voxels.
    OpacityWeighted,
    /// `Preweighted` on associated voxels stored in `f32`.
    Preweighted,
    /// `Preweighted` on associated voxels stored in 8 bits (Drebin; Wittenbrink §7).
    PreweightedU8,
    /// `ExtinctionWeighted` on `(τ, C^τ)` voxels.
    ExtinctionWeighted,
    /// `PostClassified` on the scalars (transfer-function scenes only).
    PostClassified,
}

impl ModeChoice {
    /// Every mode.
    pub const ALL: [ModeChoice; 6] = [
        ModeChoice::Separate,
        ModeChoice::OpacityWeighted,
        ModeChoice::Preweighted,
        ModeChoice::PreweightedU8,
        ModeChoice::ExtinctionWeighted,
        ModeChoice::PostClassified,
    ];

    /// A short label.
    pub fn label(self) -> &'static str {
        match self {
            ModeChoice::Separate => "separate",
            ModeChoice::OpacityWeighted => "opacity-weighted",
            ModeChoice::Preweighted => "preweighted",
            ModeChoice::PreweightedU8 => "preweighted-u8",
            ModeChoice::ExtinctionWeighted => "extinction",
            ModeChoice::PostClassified => "post-classified",
        }
    }

    /// Parses a [`label`](Self::label).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.label() == s)
    }
}

/// Arithmetic of the kernels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Precision {
    /// `f32` kernels.
    F32,
    /// Integer kernels, `u8` storage, 8 fractional position bits, U8.8 samples.
    Int8,
}

impl Precision {
    /// A short label.
    pub fn label(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::Int8 => "int-F8",
        }
    }
}

/// One sampling choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Method {
    /// Mode.
    pub mode: ModeChoice,
    /// Precision.
    pub precision: Precision,
    /// Filter.
    pub filter: FilterKind,
}

impl Method {
    /// `mode/precision/filter`.
    pub fn label(&self) -> String {
        let f = match self.filter {
            FilterKind::Nearest => "nearest",
            FilterKind::TrilinearTree => "trilinear-tree",
            FilterKind::TrilinearSum => "trilinear",
            FilterKind::BSpline => "bspline",
        };
        format!("{}/{}/{}", self.mode.label(), self.precision.label(), f)
    }

    /// Whether the method exists for this scene (post-classification needs a transfer
    /// function; the integer kernels cover nearest and trilinear for the opacity-based
    /// RGBA modes).
    pub fn available(&self, scene_has_tf: bool) -> bool {
        let mode_ok = self.mode != ModeChoice::PostClassified || scene_has_tf;
        let int_ok = match self.precision {
            Precision::F32 => true,
            Precision::Int8 => {
                matches!(
                    self.mode,
                    ModeChoice::Separate | ModeChoice::OpacityWeighted | ModeChoice::PreweightedU8
                ) && matches!(self.filter, FilterKind::Nearest | FilterKind::TrilinearSum)
            }
        };
        mode_ok && int_ok
    }

    /// The methods a report runs: every mode × precision × filter available for the scene
    /// (the tree trilinear order only in `full`, as it computes the same values).
    pub fn all(scene_has_tf: bool, full: bool) -> Vec<Method> {
        let mut v = Vec::new();
        for precision in [Precision::F32, Precision::Int8] {
            for mode in ModeChoice::ALL {
                for filter in FilterKind::ALL {
                    if filter == FilterKind::TrilinearTree && !full {
                        continue;
                    }
                    let m = Method {
                        mode,
                        precision,
                        filter,
                    };
                    if m.available(scene_has_tf) {
                        v.push(m);
                    }
                }
            }
        }
        v
    }
}

/// A rendered image with its cost.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// Associated pixels (over the scene's background), row-major.
    pub pixels: Vec<Sample>,
    /// Samples taken (early termination included).
    pub samples: u64,
    /// Wall time of the render, seconds.
    pub seconds: f64,
}

/// Quantises a unit value to a byte with **round half up**, `⌊255·x + ½⌋` (the paper's
/// `Int(C·(N−1) + 0.5)`).
pub fn to_u8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8
}

/// The scene's straight voxels stored as bytes (round half up).
pub fn straight_u8(rgba: &[StraightF32]) -> Vec<StraightU8> {
    rgba.iter()
        .map(|v| StraightU8([to_u8(v.c[0]), to_u8(v.c[1]), to_u8(v.c[2]), to_u8(v.a)]))
        .collect()
}

/// Drebin-style 8-bit associated storage: `⌊255·αC + ½⌋` and `⌊255·α + ½⌋`, each color
/// byte capped at the alpha byte.
pub fn associated_u8(rgba: &[StraightF32]) -> Vec<AssociatedU8> {
    rgba.iter()
        .map(|v| {
            let a = to_u8(v.a);
            let c = v.c.map(|c| to_u8(c * v.a).min(a));
            AssociatedU8([c[0], c[1], c[2], a])
        })
        .collect()
}

enum Cam {
    Ortho(Orthographic),
    Persp(Perspective),
}

impl Cam {
    fn new(spec: &CameraSpec) -> Result<Self, volsample::Error> {
        Ok(match *spec {
            CameraSpec::Orthographic(e, d, u, x) => Cam::Ortho(Orthographic::new(e, d, u, x)?),
            CameraSpec::Perspective(e, t, u, f) => Cam::Persp(Perspective::new(e, t, u, f)?),
        })
    }

    fn ray(&self, i: usize, j: usize, w: usize, h: usize) -> volsample::Ray {
        match self {
            Cam::Ortho(c) => c.ray(i, j, w, h),
            Cam::Persp(c) => c.ray(i, j, w, h),
        }
    }
}

fn float_render<V: Voxel, M: Mode<V> + Copy, F: Filter>(
    scene: &Scene,
    data: &[V],
    mode: M,
    filter: F,
) -> Result<Rendered, volsample::Error> {
    let vol = Volume::new(data, scene.dims)?.with_reference_distance(scene.d_ref)?;
    let step = Step::new(scene.step)?.with_phase(scene.phase)?;
    if scene.a_stop < 1.0 {
        let order = FrontToBack::with_threshold(scene.a_stop)?;
        let m =
            RayMarcher::new(vol, mode, filter, order, step)?.with_background(scene.background)?;
        trace(scene, |ray| m.cast_counted(ray))
    } else {
        let m = RayMarcher::new(vol, mode, filter, FrontToBack::new(), step)?
            .with_background(scene.background)?;
        trace(scene, |ray| m.cast_counted(ray))
    }
}

fn trace(
    scene: &Scene,
    cast: impl Fn(&volsample::Ray) -> (Sample, u32),
) -> Result<Rendered, volsample::Error> {
    let cam = Cam::new(&scene.camera)?;
    let [w, h] = scene.image;
    let mut pixels = vec![Sample::TRANSPARENT; w * h];
    let mut samples = 0u64;
    let start = Instant::now();
    for (k, px) in pixels.iter_mut().enumerate() {
        let (s, n) = cast(&cam.ray(k % w, k / w, w, h));
        *px = s;
        samples += u64::from(n);
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok(Rendered {
        pixels,
        samples,
        seconds,
    })
}

fn int_render<V: Voxel, M: fixed_point::IntMode<V> + Copy, Fl: fixed_point::IntFilter>(
    scene: &Scene,
    data: &[V],
    mode: M,
    filter: Fl,
) -> Result<Rendered, volsample::Error> {
    // The integer path: positions from the same f32 rays, quantised (round half up) to
    // F = 8 bits after clamping into the grid (exact under clamp-to-edge), integer samples,
    // table-driven correction when d ≠ d′, integer front-to-back with early stop.
    let vol = Volume::new(data, scene.dims)?;
    let sampler = IntSampler::new(vol, mode, filter);
    let ratio = scene.step / scene.d_ref;
    let correction = if ratio != 1.0 {
        Some(IntCorrection::new(ratio)?)
    } else {
        None
    };
    let stop = if scene.a_stop < 1.0 {
        IntStop::new((scene.a_stop * f32::from(ONE)) as u16)?
    } else {
        IntStop::NEVER
    };
    let dims = scene.dims;
    let hi = dims.map(|n| n as f32 - 1.0);
    let (d, phase) = (scene.step, scene.phase);
    let bg = scene.background;
    let cast = |ray: &volsample::Ray| -> (Sample, u32) {
        let Some((t0, t1)) = ray.clip(dims) else {
            return (bg, 0);
        };
        let k0 = (t0 / d - phase).ceil();
        let n = ((t1 / d - phase).ceil() - k0).max(0.0) as u32;
        let t_first = (k0 + phase) * d;
        let mut acc = IntSample::TRANSPARENT;
        let mut used = 0u32;
        for j in 0..n {
            if acc.a() >= stop.a_stop() {
                break;
            }
            let p = ray.at(t_first + j as f32 * d);
            let p = [0, 1, 2].map(|k| p[k].clamp(0.0, hi[k]));
            let Ok(pos) = IntPos::<8>::quantize(p) else {
                continue;
            };
            let mut s = sampler.sample(pos);
            if let Some(c) = &correction {
                s = c.apply(s);
            }
            acc = fixed_point::front_to_back(acc, s);
            used += 1;
        }
        (volsample::composite::over(acc.to_f32(), bg), used)
    };
    trace(scene, cast)
}

/// Renders `scene` (already [`prepare`](Scene::prepare)d) with `method`.
///
/// # Errors
/// As the core reports them for the scene's parameters; [`volsample::Error::InvalidClassifier`]
/// for `PostClassified` on a scene without a transfer function.
pub fn render(
    scene: &Scene,
    prepared: &Prepared,
    method: Method,
) -> Result<Rendered, volsample::Error> {
    macro_rules! with_filter {
        ($f:ident, $data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => $f(scene, $data, $mode, Nearest),
                FilterKind::TrilinearTree => $f(scene, $data, $mode, Trilinear::tree()),
                FilterKind::TrilinearSum => $f(scene, $data, $mode, Trilinear::new()),
                FilterKind::BSpline => $f(scene, $data, $mode, TriquadraticBSpline),
            }
        };
    }
    macro_rules! with_int_filter {
        ($data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => int_render(scene, $data, $mode, Nearest),
                FilterKind::TrilinearSum => int_render(scene, $data, $mode, Trilinear::new()),
                _ => Err(volsample::Error::InvalidClassifier),
            }
        };
    }
    match (method.precision, method.mode) {
        (Precision::F32, ModeChoice::Separate) => {
            with_filter!(float_render, &prepared.rgba, Separate)
        }
        (Precision::F32, ModeChoice::OpacityWeighted) => {
            with_filter!(float_render, &prepared.rgba, OpacityWeighted)
        }
        (Precision::F32, ModeChoice::Preweighted) => {
            let a: Vec<_> = prepared
                .rgba
                .iter()
                .map(|&v| volsample::AssociatedF32::from_straight(v))
                .collect();
            with_filter!(float_render, &a, Preweighted)
        }
        (Precision::F32, ModeChoice::PreweightedU8) => {
            with_filter!(float_render, &associated_u8(&prepared.rgba), Preweighted)
        }
        (Precision::F32, ModeChoice::ExtinctionWeighted) => {
            let e: Vec<_> = prepared
                .rgba
                .iter()
                .map(|&v| ExtinctionF32::from_straight(v, scene.d_ref))
                .collect();
            with_filter!(float_render, &e, ExtinctionWeighted)
        }
        (Precision::F32, ModeChoice::PostClassified) => {
            let (s, points) = prepared
                .post
                .as_ref()
                .ok_or(volsample::Error::InvalidClassifier)?;
            let tf = TransferFunction::<64>::new(points)?;
            with_filter!(float_render, s, PostClassified::new(&tf))
        }
        (Precision::Int8, ModeChoice::Separate) => {
            with_int_filter!(&straight_u8(&prepared.rgba), Separate)
        }
        (Precision::Int8, ModeChoice::OpacityWeighted) => {
            with_int_filter!(&straight_u8(&prepared.rgba), OpacityWeighted)
        }
        (Precision::Int8, ModeChoice::PreweightedU8) => {
            with_int_filter!(&associated_u8(&prepared.rgba), Preweighted)
        }
        (Precision::Int8, _) => Err(volsample::Error::InvalidClassifier),
    }
}
