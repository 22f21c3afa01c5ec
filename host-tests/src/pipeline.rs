//! Scene-driven pipelines: a [`Method`] (mode × precision × filter) applied to a prepared
//! [`Scene`], with every stage chosen by type once per render (never per sample).
//!
//! Opacity correction is on exactly when `d ≠ d′` (and the mode is opacity-based), early
//! termination exactly when `A_stop < 1`, and the background is composited once per ray; the
//! core picks the first two by type ([`volsample::RayMarcher`]), so an absent stage has no
//! code in the inner loop (the integer pipeline is the core's
//! [`IntRayMarcher`]).
//!
//! [`with_pipeline`] builds a pipeline once (storage conversion and validation, `O(voxels)`)
//! and renders any number of frames with it (`O(samples)`); [`render`] times one frame.

use std::time::Instant;

use volsample::fixed_point::{
    self, ExtinctionFx, ExtinctionTables, IntExtinction, IntSample, IntStop, ONE,
};
use volsample::render::IntRayMarcher;
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Camera, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack, Mode, Nearest,
    OpacityWeighted, Orthographic, Perspective, PostClassified, Preweighted, RayMarcher, Sample,
    Separate, Step, StraightF32, StraightU8, Threshold, TransferFunction, Trilinear,
    TriquadraticBSpline, Volume,
};

use crate::float_checks::{CameraSpec, FilterKind};
use crate::scene::{Prepared, Scene};
use crate::texture_unit::{Bytes, Shader, Texels};

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
    /// Integer kernels, `u8` storage, 8 fractional position bits, U8.8 samples (and
    /// [`INT_EXTINCTION_TABLE`]-node tables for the extinction mode).
    Int8,
    /// The integer `OpacityWeighted` trilinear kernel at another number of fractional
    /// position bits `F` (one of [`INT_BITS_SWEEP`]): error against bits.
    IntBits(u32),
    /// The integer `ExtinctionWeighted` trilinear kernel (F = 8) with tables of another size
    /// `N` (one of [`INT_TABLE_SWEEP`]): error against table size.
    IntTable(usize),
    /// A GPU texture unit's filtering ([`crate::texture_unit`]): trilinear weights with 8
    /// fractional bits on RGBA8 texels, compositing in `f32`; on straight RGBA8
    /// (`Separate`) and premultiplied RGBA8 (`PreweightedU8`). Not timed: its time on a CPU
    /// says nothing of a GPU's.
    Texture8,
}

/// The fractional position bits of the [`Precision::IntBits`] rows (8 is [`Precision::Int8`]).
pub const INT_BITS_SWEEP: [u32; 4] = [4, 6, 10, 12];

/// The table sizes of the [`Precision::IntTable`] rows ([`INT_EXTINCTION_TABLE`] is
/// [`Precision::Int8`]).
pub const INT_TABLE_SWEEP: [usize; 4] = [17, 65, 1025, 4097];

impl Precision {
    /// A short label.
    pub fn label(self) -> String {
        match self {
            Precision::F32 => "f32".into(),
            Precision::Int8 => "int-F8".into(),
            Precision::IntBits(f) => format!("int-F{f}"),
            Precision::IntTable(n) => format!("int-F8-N{n}"),
            Precision::Texture8 => "gpu-tex8".into(),
        }
    }

    /// The precisions a report runs: `f32`, the integer kernels at F = 8, the sweeps over
    /// bits and table sizes, and the GPU texture unit.
    pub fn all() -> Vec<Precision> {
        let mut v = vec![Precision::F32, Precision::Int8];
        v.extend(INT_BITS_SWEEP.map(Precision::IntBits));
        v.extend(INT_TABLE_SWEEP.map(Precision::IntTable));
        v.push(Precision::Texture8);
        v
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
    /// function; the integer kernels cover nearest and trilinear for the RGBA modes with
    /// 8-bit storage: `Separate`, `OpacityWeighted`, `PreweightedU8`, and `ExtinctionWeighted`
    /// on `(τ, C^τ)` fixed point converted from the 8-bit straight voxels; the sweeps over
    /// bits and table sizes cover `OpacityWeighted` and `ExtinctionWeighted` trilinear; the
    /// GPU texture unit `Separate` and `PreweightedU8` trilinear).
    pub fn available(&self, scene_has_tf: bool) -> bool {
        let mode_ok = self.mode != ModeChoice::PostClassified || scene_has_tf;
        let int_ok = match self.precision {
            Precision::F32 => true,
            Precision::Int8 => {
                matches!(
                    self.mode,
                    ModeChoice::Separate
                        | ModeChoice::OpacityWeighted
                        | ModeChoice::PreweightedU8
                        | ModeChoice::ExtinctionWeighted
                ) && matches!(self.filter, FilterKind::Nearest | FilterKind::TrilinearSum)
            }
            Precision::IntBits(_) => {
                self.mode == ModeChoice::OpacityWeighted && self.filter == FilterKind::TrilinearSum
            }
            Precision::IntTable(_) => {
                self.mode == ModeChoice::ExtinctionWeighted
                    && self.filter == FilterKind::TrilinearSum
            }
            Precision::Texture8 => {
                matches!(self.mode, ModeChoice::Separate | ModeChoice::PreweightedU8)
                    && self.filter == FilterKind::TrilinearSum
            }
        };
        mode_ok && int_ok
    }

    /// Whether the report times the method (not the emulated GPU texture unit).
    pub fn timed(&self) -> bool {
        self.precision != Precision::Texture8
    }

    /// The methods a report runs: every mode × precision × filter available for the scene
    /// (the tree trilinear order only in `full`, as it computes the same values), the
    /// precision sweeps and the GPU texture unit included ([`Precision::all`]).
    pub fn all(scene_has_tf: bool, full: bool) -> Vec<Method> {
        let mut v = Vec::new();
        for precision in Precision::all() {
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
}

impl Camera for Cam {
    #[inline]
    fn ray(&self, i: usize, j: usize, w: usize, h: usize) -> volsample::Ray {
        match self {
            Cam::Ortho(c) => c.ray(i, j, w, h),
            Cam::Persp(c) => c.ray(i, j, w, h),
        }
    }
}

/// A built pipeline: the voxels converted to the method's storage and validated, the kernels
/// and stages chosen, the camera set up. What is left per frame is the ray marching.
pub trait Frames {
    /// Image width and height.
    fn image(&self) -> [usize; 2];

    /// Renders one frame into `pixels` (row-major, row 0 at the top) through the marcher's
    /// `render_into`: its fastest path (the eight-ray packets where they apply), every pixel
    /// bit-identical to `cast` of its ray.
    ///
    /// # Errors
    /// [`volsample::Error::ImageSizeMismatch`] unless `pixels` holds `width·height` pixels.
    fn frame(&self, pixels: &mut [Sample]) -> Result<(), volsample::Error>;

    /// The number of samples a frame takes, early termination included (not part of a
    /// frame's time): each ray cast once more, one at a time, to count them (the float
    /// marchers always stop at their threshold, `A = 1` where the scene sets none); an
    /// integer pipeline without early termination takes each ray's sample count
    /// (`sample_range`, which `cast_counted` returns for a ray that does not stop).
    fn samples(&self) -> u64;
}

/// Front to back without early termination, as the report's float pipelines, `kraus` and
/// `demo` build it: stopping at `A ≥ 1`, after which every step would add `(1 − 1)·x = 0` to each
/// channel of the accumulated sample (the samples are clamped, so finite). The image is
/// bit-identical to [`FrontToBack::new`]'s, and the marchers of a (storage, mode, filter)
/// share one type, whether they stop early or not: half the marcher instances to compile.
///
/// # Errors
/// None (`1` is a valid threshold).
pub(crate) fn front_to_back() -> Result<FrontToBack<Threshold>, volsample::Error> {
    FrontToBack::with_threshold(1.0)
}

/// The rays of a `w × h` image of `cam`, with `cast`'s sample count summed.
fn count(cam: &Cam, [w, h]: [usize; 2], cast: impl Fn(&volsample::Ray) -> u32) -> u64 {
    let mut samples = 0u64;
    for j in 0..h {
        for i in 0..w {
            samples += u64::from(cast(&cam.ray(i, j, w, h)));
        }
    }
    samples
}

struct FloatFrames<'v, V, M, F, O> {
    marcher: RayMarcher<'v, V, M, F, O>,
    cam: Cam,
    image: [usize; 2],
}

impl<V: Voxel, M: Mode<V>, F: Filter, O: volsample::composite::Order> Frames
    for FloatFrames<'_, V, M, F, O>
{
    fn image(&self) -> [usize; 2] {
        self.image
    }

    fn frame(&self, pixels: &mut [Sample]) -> Result<(), volsample::Error> {
        let [w, h] = self.image;
        self.marcher.render_into(&self.cam, w, h, pixels)
    }

    fn samples(&self) -> u64 {
        count(&self.cam, self.image, |ray| {
            self.marcher.cast_counted(ray).1
        })
    }
}

struct IntFrames<'v, V, M, Fl, const B: u32> {
    marcher: IntRayMarcher<'v, V, M, Fl, B>,
    cam: Cam,
    image: [usize; 2],
    /// Early termination is on.
    stops: bool,
}

impl<V: Voxel, M: fixed_point::IntMode<V>, Fl: fixed_point::IntFilter, const B: u32> Frames
    for IntFrames<'_, V, M, Fl, B>
{
    fn image(&self) -> [usize; 2] {
        self.image
    }

    fn frame(&self, pixels: &mut [Sample]) -> Result<(), volsample::Error> {
        let [w, h] = self.image;
        let mut ints = vec![IntSample::TRANSPARENT; pixels.len()];
        self.marcher.render_into(&self.cam, w, h, &mut ints)?;
        for (p, s) in pixels.iter_mut().zip(ints) {
            *p = s.to_f32();
        }
        Ok(())
    }

    fn samples(&self) -> u64 {
        count(&self.cam, self.image, |ray| {
            if self.stops {
                self.marcher.cast_counted(ray).1
            } else {
                self.marcher.sample_range(ray).1
            }
        })
    }
}

/// Fractional position bits of the report's integer pipeline.
pub const INT_FRAC_BITS: u32 = 8;

/// Table size of the report's integer extinction mode (`0.56`/`1.06` LSB table bound).
pub const INT_EXTINCTION_TABLE: usize = 257;

/// A U8.8 value of a unit float, **round half up**: `⌊ONE·x + ½⌋` (clamped to `[0, 1]`).
fn to_u88(x: f32) -> u16 {
    (f64::from(x.clamp(0.0, 1.0)) * f64::from(ONE) + 0.5).floor() as u16
}

/// The scene's associated background in U8.8 (each channel round half up, capped at `A`).
///
/// # Errors
/// None in practice: the capped value is always a valid [`IntSample`].
pub fn int_background(bg: Sample) -> Result<IntSample, volsample::Error> {
    let a = to_u88(bg.a);
    IntSample::new(bg.c.map(|c| to_u88(c).min(a)), a)
}

fn float_build<V: Voxel, M: Mode<V> + Copy, F: Filter, T>(
    scene: &Scene,
    data: &[V],
    mode: M,
    filter: F,
    body: impl FnOnce(&dyn Frames) -> T,
) -> Result<T, volsample::Error> {
    let vol = Volume::new(data, scene.dims)?.with_reference_distance(scene.d_ref)?;
    let step = Step::new(scene.step)?.with_phase(scene.phase)?;
    let cam = Cam::new(&scene.camera)?;
    let image = scene.image;
    // One marcher type per (storage, mode, filter): see `front_to_back`.
    let order = FrontToBack::with_threshold(scene.a_stop.min(1.0))?;
    let marcher = RayMarcher::new(vol, mode, filter, order, step)?
        .with_background(scene.background)?
        .with_isa(crate::isa::chosen());
    Ok(body(&FloatFrames {
        marcher,
        cam,
        image,
    }))
}

fn int_build<V: Voxel, M: fixed_point::IntMode<V>, Fl: fixed_point::IntFilter, T, const B: u32>(
    scene: &Scene,
    data: &[V],
    mode: M,
    filter: Fl,
    body: impl FnOnce(&dyn Frames) -> T,
) -> Result<T, volsample::Error> {
    // The core's integer pipeline: positions from the same f32 rays, clamped into the grid
    // and quantised (round half up) to F = B bits (8 but in the sweep), integer samples, table-driven correction
    // when d ≠ d′ (opacity-based modes), integer front-to-back with early stop, and the
    // background composited in U8.8.
    let vol = Volume::new(data, scene.dims)?.with_reference_distance(scene.d_ref)?;
    let step = Step::new(scene.step)?.with_phase(scene.phase)?;
    let stop = if scene.a_stop < 1.0 {
        IntStop::new(to_u88(scene.a_stop))?
    } else {
        IntStop::NEVER
    };
    let marcher = IntRayMarcher::<_, _, _, B>::new(vol, mode, filter, stop, step)?
        .with_background(int_background(scene.background)?)
        .with_isa(crate::isa::chosen());
    Ok(body(&IntFrames {
        marcher,
        cam: Cam::new(&scene.camera)?,
        image: scene.image,
        stops: scene.a_stop < 1.0,
    }))
}

/// Builds the pipeline of `method` for `scene` (already [`prepare`](Scene::prepare)d) —
/// storage conversion, validation, stage choice — and hands it to `body`, which renders as
/// many frames as it likes. Building is `O(voxels)`; a frame is `O(samples)`.
///
/// # Errors
/// As the core reports them for the scene's parameters; [`volsample::Error::InvalidClassifier`]
/// for a method the scene does not offer ([`Method::available`]).
pub fn with_pipeline<T>(
    scene: &Scene,
    prepared: &Prepared,
    method: Method,
    body: impl FnOnce(&dyn Frames) -> T,
) -> Result<T, volsample::Error> {
    macro_rules! with_filter {
        ($data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => float_build(scene, $data, $mode, Nearest, body),
                FilterKind::TrilinearTree => {
                    float_build(scene, $data, $mode, Trilinear::tree(), body)
                }
                FilterKind::TrilinearSum => {
                    float_build(scene, $data, $mode, Trilinear::new(), body)
                }
                FilterKind::BSpline => float_build(scene, $data, $mode, TriquadraticBSpline, body),
            }
        };
    }
    macro_rules! with_int_filter {
        ($data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => {
                    int_build::<_, _, _, _, INT_FRAC_BITS>(scene, $data, $mode, Nearest, body)
                }
                FilterKind::TrilinearSum => int_build::<_, _, _, _, INT_FRAC_BITS>(
                    scene,
                    $data,
                    $mode,
                    Trilinear::new(),
                    body,
                ),
                _ => Err(volsample::Error::InvalidClassifier),
            }
        };
    }
    match (method.precision, method.mode) {
        (Precision::F32, ModeChoice::Separate) => with_filter!(&prepared.rgba, Separate),
        (Precision::F32, ModeChoice::OpacityWeighted) => {
            with_filter!(&prepared.rgba, OpacityWeighted)
        }
        (Precision::F32, ModeChoice::Preweighted) => {
            let a: Vec<_> = prepared
                .rgba
                .iter()
                .map(|&v| volsample::AssociatedF32::from_straight(v))
                .collect();
            with_filter!(&a, Preweighted)
        }
        (Precision::F32, ModeChoice::PreweightedU8) => {
            with_filter!(&associated_u8(&prepared.rgba), Preweighted)
        }
        (Precision::F32, ModeChoice::ExtinctionWeighted) => {
            let e: Vec<_> = prepared
                .rgba
                .iter()
                .map(|&v| ExtinctionF32::from_straight(v, scene.d_ref))
                .collect();
            with_filter!(&e, ExtinctionWeighted)
        }
        (Precision::F32, ModeChoice::PostClassified) => {
            let (s, points) = prepared
                .post
                .as_ref()
                .ok_or(volsample::Error::InvalidClassifier)?;
            let tf = TransferFunction::<64>::new(points)?;
            with_filter!(s, PostClassified::new(&tf))
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
        (Precision::Int8, ModeChoice::ExtinctionWeighted) => {
            // The integer extinction mode reads the same 8-bit straight storage as the other
            // integer modes, converted once to (τ, C^τ) fixed point.
            let e: Vec<_> = straight_u8(&prepared.rgba)
                .into_iter()
                .map(ExtinctionFx::from_straight_u8)
                .collect();
            let tables = ExtinctionTables::<INT_EXTINCTION_TABLE>::new();
            let mode = IntExtinction::new(&tables, 1.0)?;
            with_int_filter!(&e, mode)
        }
        (Precision::IntBits(bits), ModeChoice::OpacityWeighted)
            if method.filter == FilterKind::TrilinearSum =>
        {
            let data = straight_u8(&prepared.rgba);
            let (m, f) = (OpacityWeighted, Trilinear::new());
            match bits {
                4 => int_build::<_, _, _, _, 4>(scene, &data, m, f, body),
                6 => int_build::<_, _, _, _, 6>(scene, &data, m, f, body),
                10 => int_build::<_, _, _, _, 10>(scene, &data, m, f, body),
                12 => int_build::<_, _, _, _, 12>(scene, &data, m, f, body),
                _ => Err(volsample::Error::InvalidClassifier),
            }
        }
        (Precision::IntTable(n), ModeChoice::ExtinctionWeighted)
            if method.filter == FilterKind::TrilinearSum =>
        {
            let e: Vec<_> = straight_u8(&prepared.rgba)
                .into_iter()
                .map(ExtinctionFx::from_straight_u8)
                .collect();
            macro_rules! table {
                ($n:literal) => {{
                    let tables = ExtinctionTables::<$n>::new();
                    let mode = IntExtinction::new(&tables, 1.0)?;
                    int_build::<_, _, _, _, INT_FRAC_BITS>(scene, &e, mode, Trilinear::new(), body)
                }};
            }
            match n {
                17 => table!(17),
                65 => table!(65),
                1025 => table!(1025),
                4097 => table!(4097),
                _ => Err(volsample::Error::InvalidClassifier),
            }
        }
        (Precision::Texture8, ModeChoice::Separate)
            if method.filter == FilterKind::TrilinearSum =>
        {
            texture_build(
                scene,
                &straight_u8(&prepared.rgba),
                Separate,
                Texels::Straight,
                body,
            )
        }
        (Precision::Texture8, ModeChoice::PreweightedU8)
            if method.filter == FilterKind::TrilinearSum =>
        {
            texture_build(
                scene,
                &associated_u8(&prepared.rgba),
                Preweighted,
                Texels::Premultiplied,
                body,
            )
        }
        _ => Err(volsample::Error::InvalidClassifier),
    }
}

struct TextureFrames<'v, V, M> {
    /// The core marcher whose sample ranges the shader takes.
    marcher: RayMarcher<'v, V, M, Nearest, FrontToBack>,
    shader: Shader<'v, V>,
    cam: Cam,
    image: [usize; 2],
}

impl<V: Voxel + Bytes, M: Mode<V>> Frames for TextureFrames<'_, V, M> {
    fn image(&self) -> [usize; 2] {
        self.image
    }

    fn frame(&self, pixels: &mut [Sample]) -> Result<(), volsample::Error> {
        let expected = self.image[0] * self.image[1];
        if pixels.len() != expected {
            return Err(volsample::Error::ImageSizeMismatch {
                expected,
                actual: pixels.len(),
            });
        }
        let (img, _) = self
            .shader
            .image(&self.cam, self.image, |r| self.marcher.sample_range(r));
        pixels.copy_from_slice(&img);
        Ok(())
    }

    fn samples(&self) -> u64 {
        self.shader
            .image(&self.cam, self.image, |r| self.marcher.sample_range(r))
            .1
    }
}

/// The GPU texture unit's pipeline ([`crate::texture_unit`]): the sample positions and the
/// opacity correction decision of the core marcher `RayMarcher::new(vol, mode, ..)`, the
/// texture unit's fetch, `f32` compositing.
fn texture_build<V: Voxel + Bytes, M: Mode<V>, T>(
    scene: &Scene,
    data: &[V],
    mode: M,
    texels: Texels,
    body: impl FnOnce(&dyn Frames) -> T,
) -> Result<T, volsample::Error> {
    let vol = Volume::new(data, scene.dims)?.with_reference_distance(scene.d_ref)?;
    let step = Step::new(scene.step)?.with_phase(scene.phase)?;
    let marcher = RayMarcher::new(vol, mode, Nearest, FrontToBack::new(), step)?;
    let shader = Shader {
        volume: vol,
        texels,
        d: step.d(),
        ratio: marcher.correction().map(|c| c.ratio()),
        a_stop: scene.a_stop,
        background: scene.background,
        quantize: true,
    };
    Ok(body(&TextureFrames {
        marcher,
        shader,
        cam: Cam::new(&scene.camera)?,
        image: scene.image,
    }))
}

/// Renders one frame of `scene` (already [`prepare`](Scene::prepare)d) with `method`; the
/// time is that of the frame only (building the pipeline is not timed).
///
/// # Errors
/// As [`with_pipeline`].
pub fn render(
    scene: &Scene,
    prepared: &Prepared,
    method: Method,
) -> Result<Rendered, volsample::Error> {
    with_pipeline(scene, prepared, method, |p| {
        let [w, h] = p.image();
        let mut pixels = vec![Sample::TRANSPARENT; w * h];
        let start = Instant::now();
        p.frame(&mut pixels)?;
        let seconds = start.elapsed().as_secs_f64();
        let samples = p.samples();
        Ok(Rendered {
            pixels,
            samples,
            seconds,
        })
    })?
}

/// Times `frames` frames of `scene` (already [`prepare`](Scene::prepare)d) with `method` on one
/// pipeline: each frame's wall time in seconds, and the samples a frame takes (counted once,
/// after the frames; building the pipeline and counting are not timed).
///
/// # Errors
/// As [`with_pipeline`].
pub fn time_frames(
    scene: &Scene,
    prepared: &Prepared,
    method: Method,
    frames: usize,
) -> Result<(Vec<f64>, u64), volsample::Error> {
    with_pipeline(scene, prepared, method, |p| {
        let [w, h] = p.image();
        let mut pixels = vec![Sample::TRANSPARENT; w * h];
        let mut seconds = Vec::with_capacity(frames);
        for _ in 0..frames {
            let start = Instant::now();
            p.frame(&mut pixels)?;
            seconds.push(start.elapsed().as_secs_f64());
        }
        Ok((seconds, p.samples()))
    })?
}
