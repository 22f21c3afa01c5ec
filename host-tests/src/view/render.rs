//! The fast renderer of the CLI: classified RGBA8 voxels, the library's fastest kernels
//! (eight-ray AVX2 packets where the CPU has them and no opacity correction applies, i.e. the
//! step equals the unit distance or the mode is extinction-based; otherwise four samples of a
//! ray in lanes), early termination, empty-space skipping (each ray marched only between its
//! first and last occupied samples, `Occupancy::occupied_samples`), and threads over bands of
//! image rows.
//!
//! The core is single-threaded; [`render`] splits the image into bands of [`BAND_ROWS`] rows
//! and renders them on a rayon pool with [`RayMarcher::render_rows_into`]. Every pixel is the
//! core's `cast` of its ray whatever the band, so the image is bit-identical for any number
//! of threads (`tests/view.rs`).
//!
//! Storage: [`Voxels::straight`] holds 4 bytes per voxel; with the scalars of an 8-bit file
//! (1 byte) kept for the post-classified mode, 5. Opacity-based modes read the bytes as they
//! are; `extinction` reads them through a 256-entry `τ` table ([`ExtinctionWeightedU8`]),
//! bit-identical to converting them to `(τ, C^τ)` first, without the 16 bytes per voxel.

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use volsample::fixed_point::{IntMode, IntSample, IntStop};
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::render::IntRayMarcher;
use volsample::skip::{Emptiness, Occupancy};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, ControlPoint, Filter, FrontToBack, Mode, Nearest, OpacityWeighted,
    PostClassified, Preweighted, RayMarcher, Sample, Separate, Step, StraightU8, TransferFunction,
    Trilinear, TriquadraticBSpline, Volume,
};

use super::Framed;
use crate::float_checks::FilterKind;
use crate::pipeline::{int_background, to_u8, Method, ModeChoice, Precision, INT_FRAC_BITS};

/// Rows per band of work: small enough to balance threads over images with empty margins,
/// large enough that a band is thousands of rays.
pub const BAND_ROWS: usize = 4;

/// Most pixels in one image (2²⁶: 8192 × 8192), so an image buffer is at most 1 GiB.
pub const MAX_PIXELS: usize = 1 << 26;

/// Most worker threads [`render`] starts.
pub const MAX_THREADS: usize = 1024;

/// Brick size exponent of the occupancy grid for empty-space skipping (8³-voxel bricks).
pub const SKIP_BRICK_LOG2: u32 = 3;

/// A classified volume: straight RGBA8 voxels, and the scalars with their transfer function
/// where the post-classified mode may run.
#[derive(Debug, Clone)]
pub struct Voxels {
    /// Dimensions.
    pub dims: [usize; 3],
    /// Straight RGBA8 voxels (classified, round half up).
    pub straight: Vec<StraightU8>,
    /// Scalars (as `f32`) and the transfer function, for `post-classified`.
    pub post: Option<(Vec<f32>, Vec<ControlPoint>)>,
}

/// Classifies `data` by the piecewise-linear transfer function `points` into straight RGBA8
/// (each channel round half up, [`to_u8`]), through `value` as `f32`; values of 8-bit data
/// through a 256-entry table (the same results, one evaluation per value).
///
/// # Errors
/// Invalid control points, as the core reports them.
pub fn classify<T: Copy + Sync>(
    data: &[T],
    points: &[ControlPoint],
    value: impl Fn(T) -> f32 + Sync,
) -> Result<Vec<StraightU8>, String> {
    let tf = TransferFunction::<64>::new(points).map_err(|e| format!("transfer function: {e}"))?;
    let one = |s: f32| {
        let (c, a) = tf.eval(s);
        StraightU8([to_u8(c[0]), to_u8(c[1]), to_u8(c[2]), to_u8(a)])
    };
    Ok(data.par_iter().map(|&v| one(value(v))).collect())
}

/// [`classify`] of bytes through a 256-entry table.
///
/// # Errors
/// As [`classify`].
pub fn classify_u8(data: &[u8], points: &[ControlPoint]) -> Result<Vec<StraightU8>, String> {
    let all: Vec<u8> = (0..=255).collect();
    let table = classify(&all, points, f32::from)?;
    Ok(data
        .par_iter()
        .map(|&v| table.get(usize::from(v)).copied().unwrap_or_default())
        .collect())
}

/// [`classify`] of integer samples through a table of every value of their type: `index`
/// maps a sample to its table entry, and entry `k` holds the classification of the value
/// `first + k` (`first` the type's smallest value); for 16-bit samples, 65 536 evaluations
/// instead of one per voxel.
///
/// # Errors
/// As [`classify`].
pub fn classify_table<T: Copy + Sync>(
    data: &[T],
    points: &[ControlPoint],
    index: impl Fn(T) -> usize + Sync,
    first: i64,
) -> Result<Vec<StraightU8>, String> {
    let entries = index_range(&index, data).map_or(0, |hi| hi + 1);
    let values: Vec<i64> = (0..entries as i64).map(|k| first + k).collect();
    let table = classify(&values, points, |v| v as f32)?;
    Ok(data
        .par_iter()
        .map(|&v| table.get(index(v)).copied().unwrap_or_default())
        .collect())
}

/// The largest table index among `data`.
fn index_range<T: Copy + Sync>(index: &(impl Fn(T) -> usize + Sync), data: &[T]) -> Option<usize> {
    data.par_iter().map(|&v| index(v)).max()
}

/// How to render.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Image width and height in pixels.
    pub size: [usize; 2],
    /// Step between samples, millimetres (world units).
    pub step_mm: f64,
    /// The distance the opacities hold for, millimetres.
    pub unit_mm: f64,
    /// Early termination: a ray stops once its opacity reaches this (1: only when opaque).
    pub a_stop: f32,
    /// Empty-space skipping (where the mode has an emptiness test).
    pub skip: bool,
    /// Worker threads (0: rayon's default, one per core).
    pub threads: usize,
    /// The associated background color.
    pub background: Sample,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// A rendered image with what it cost.
#[derive(Debug, Clone)]
pub struct Image {
    /// Associated pixels over the background, row-major, row 0 at the top.
    pub pixels: Vec<Sample>,
    /// Wall time of the ray marching, seconds.
    pub seconds: f64,
    /// The instruction set the kernels ran in.
    pub isa: volsample::Isa,
}

/// Renders `voxels` (placed in the world and seen as `framed` says) with `method`.
///
/// # Errors
/// As text: an image over [`MAX_PIXELS`], more than [`MAX_THREADS`] threads, a method the
/// voxels do not offer (post-classified without scalars, integer kernels of other modes and
/// filters), bad settings as the core reports them.
pub fn render(
    voxels: &Voxels,
    framed: &Framed,
    method: Method,
    settings: &Settings,
) -> Result<Image, String> {
    let [w, h] = settings.size;
    match w.checked_mul(h) {
        Some(n) if n > 0 && n <= MAX_PIXELS => {}
        _ => {
            return Err(format!(
                "image {w} x {h} must have between 1 and {MAX_PIXELS} pixels"
            ))
        }
    }
    if settings.threads > MAX_THREADS {
        return Err(format!(
            "{} threads: at most {MAX_THREADS} (0: one per core)",
            settings.threads
        ));
    }
    if !(settings.step_mm.is_finite() && settings.step_mm > 0.0) {
        return Err(format!("step must be positive, not {}", settings.step_mm));
    }
    if !(settings.unit_mm.is_finite() && settings.unit_mm > 0.0) {
        return Err(format!(
            "unit distance must be positive, not {}",
            settings.unit_mm
        ));
    }
    let job = Job {
        framed,
        settings,
        dims: voxels.dims,
        d: framed.index_length(settings.step_mm) as f32,
        d_ref: framed.index_length(settings.unit_mm) as f32,
    };
    let e = |e: volsample::Error| e.to_string();
    let data = &voxels.straight[..];
    macro_rules! float {
        ($data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => job.float($data, $mode, Nearest),
                FilterKind::BSpline => job.float($data, $mode, TriquadraticBSpline),
                FilterKind::TrilinearTree => job.float($data, $mode, Trilinear::tree()),
                FilterKind::TrilinearSum => job.float($data, $mode, Trilinear::new()),
            }
        };
    }
    macro_rules! int {
        ($data:expr, $mode:expr) => {
            match method.filter {
                FilterKind::Nearest => job.int($data, $mode, Nearest),
                FilterKind::TrilinearSum => job.int($data, $mode, Trilinear::new()),
                _ => Err(format!(
                    "{}: the integer kernels have nearest and trilinear filters",
                    method.label()
                )),
            }
        };
    }
    match (method.precision, method.mode) {
        (Precision::F32, ModeChoice::Separate) => float!(data, Separate),
        (Precision::F32, ModeChoice::OpacityWeighted) => float!(data, OpacityWeighted),
        (Precision::F32, ModeChoice::Preweighted | ModeChoice::PreweightedU8) => {
            float!(&associated(data), Preweighted)
        }
        (Precision::F32, ModeChoice::ExtinctionWeighted) => {
            let table = TauTable::new(job.d_ref).map_err(e)?;
            float!(data, ExtinctionWeightedU8::new(&table))
        }
        (Precision::F32, ModeChoice::PostClassified) => {
            let (s, points) = voxels
                .post
                .as_ref()
                .ok_or("post-classified needs a scalar volume with a transfer function")?;
            let tf = TransferFunction::<64>::new(points).map_err(e)?;
            let mode = PostClassified::new(&tf);
            match method.filter {
                FilterKind::Nearest => job.float_plain(s, mode, Nearest),
                FilterKind::BSpline => job.float_plain(s, mode, TriquadraticBSpline),
                FilterKind::TrilinearTree => job.float_plain(s, mode, Trilinear::tree()),
                FilterKind::TrilinearSum => job.float_plain(s, mode, Trilinear::new()),
            }
        }
        (Precision::Int8, ModeChoice::Separate) => int!(data, Separate),
        (Precision::Int8, ModeChoice::OpacityWeighted) => int!(data, OpacityWeighted),
        (Precision::Int8, ModeChoice::PreweightedU8) => int!(&associated(data), Preweighted),
        (Precision::Int8, m) => Err(format!(
            "{}: no integer kernel for {} here (separate, opacity-weighted, preweighted-u8)",
            method.label(),
            m.label()
        )),
        (p, _) => Err(format!(
            "{}: precision {} is one of the report's rows, not rendered here (valid: f32, int)",
            method.label(),
            p.label()
        )),
    }
}

/// Drebin-style associated bytes of straight bytes: `⌊α·C/255 + ½⌋` in exact integers
/// (round half up), each at most `α`.
fn associated(data: &[StraightU8]) -> Vec<AssociatedU8> {
    data.par_iter()
        .map(|StraightU8([r, g, b, a])| {
            let a16 = u32::from(*a);
            let m = |c: u8| ((2 * u32::from(c) * a16 + 255) / 510).min(a16) as u8;
            AssociatedU8([m(*r), m(*g), m(*b), *a])
        })
        .collect()
}

/// Renders a band of integer pixels (`render_rows_into` of an integer marcher).
type IntRows<'a> = dyn Fn(usize, &mut [IntSample]) -> Result<(), volsample::Error> + Sync + 'a;

/// Renders a band of pixels (`render_rows_into` of a float marcher, or of an integer one
/// converted).
type Rows<'a> = dyn Fn(usize, &mut [Sample]) -> Result<(), volsample::Error> + Sync + 'a;

/// One render's fixed inputs.
struct Job<'a> {
    framed: &'a Framed,
    settings: &'a Settings,
    dims: [usize; 3],
    /// Step and reference distance in index units along the view.
    d: f32,
    d_ref: f32,
}

impl Job<'_> {
    /// The float marcher of `mode` and `filter` over `data`, without skipping.
    fn marcher<'v, V, M, F>(
        &self,
        data: &'v [V],
        mode: M,
        filter: F,
    ) -> Result<RayMarcher<'v, V, M, F, FrontToBack<volsample::composite::Threshold>>, String>
    where
        V: Voxel,
        M: Mode<V>,
        F: Filter,
    {
        let e = |e: volsample::Error| e.to_string();
        let vol = Volume::new(data, self.dims)
            .and_then(|v| v.with_reference_distance(self.d_ref))
            .map_err(e)?;
        let step = Step::new(self.d).map_err(e)?;
        let order = FrontToBack::with_threshold(self.settings.a_stop).map_err(e)?;
        Ok(RayMarcher::new(vol, mode, filter, order, step)
            .and_then(|m| m.with_background(self.settings.background))
            .map_err(e)?
            .with_isa(crate::isa::chosen()))
    }

    /// Renders with the float marcher, skipping empty space where the settings ask.
    fn float<V, M, F>(&self, data: &[V], mode: M, filter: F) -> Result<Image, String>
    where
        V: Voxel + Sync,
        M: Mode<V> + Emptiness<V> + Sync,
        F: Filter + Sync,
    {
        let m = self.marcher(data, mode, filter)?;
        if self.settings.skip {
            let mut grid = vec![0u8; Occupancy::buffer_len(self.dims, SKIP_BRICK_LOG2)];
            let m = m
                .with_skipping(&mut grid, SKIP_BRICK_LOG2)
                .map_err(|e| e.to_string())?;
            self.bands(m.isa(), &|first, rows| {
                m.render_rows_into(&self.framed.voxel_camera(), self.size(), first, rows)
            })
        } else {
            self.bands(m.isa(), &|first, rows| {
                m.render_rows_into(&self.framed.voxel_camera(), self.size(), first, rows)
            })
        }
    }

    /// Renders with the float marcher of a mode that has no emptiness test.
    fn float_plain<V, M, F>(&self, data: &[V], mode: M, filter: F) -> Result<Image, String>
    where
        V: Voxel + Sync,
        M: Mode<V> + Sync,
        F: Filter + Sync,
    {
        let m = self.marcher(data, mode, filter)?;
        self.bands(m.isa(), &|first, rows| {
            m.render_rows_into(&self.framed.voxel_camera(), self.size(), first, rows)
        })
    }

    /// Renders with the integer marcher (`F = 8`), skipping empty space where the settings
    /// ask; pixels converted from U8.8 to `f32`.
    fn int<V, M, Fl>(&self, data: &[V], mode: M, filter: Fl) -> Result<Image, String>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Emptiness<V> + Sync,
        Fl: volsample::fixed_point::IntFilter + Sync,
    {
        let e = |e: volsample::Error| e.to_string();
        let vol = Volume::new(data, self.dims)
            .and_then(|v| v.with_reference_distance(self.d_ref))
            .map_err(e)?;
        let step = Step::new(self.d).map_err(e)?;
        let a = (f64::from(self.settings.a_stop.clamp(0.0, 1.0))
            * f64::from(volsample::fixed_point::ONE)
            + 0.5)
            .floor() as u16;
        let stop = IntStop::new(a).map_err(e)?;
        let m = IntRayMarcher::<_, _, _, INT_FRAC_BITS>::new(vol, mode, filter, stop, step)
            .map_err(e)?
            .with_background(int_background(self.settings.background).map_err(e)?)
            .with_isa(crate::isa::chosen());
        let size = self.size();
        let cam = self.framed.voxel_camera();
        let isa = m.isa();
        let run = |render: &IntRows<'_>| {
            self.bands(isa, &|first, rows: &mut [Sample]| {
                let mut tmp = vec![IntSample::TRANSPARENT; rows.len()];
                render(first, &mut tmp)?;
                for (o, t) in rows.iter_mut().zip(&tmp) {
                    *o = t.to_f32();
                }
                Ok(())
            })
        };
        if self.settings.skip {
            let mut grid = vec![0u8; Occupancy::buffer_len(self.dims, SKIP_BRICK_LOG2)];
            let ms = m.with_skipping(&mut grid, SKIP_BRICK_LOG2).map_err(e)?;
            run(&|first, rows| ms.render_rows_into(&cam, size, first, rows))
        } else {
            run(&|first, rows| m.render_rows_into(&cam, size, first, rows))
        }
    }

    fn size(&self) -> (usize, usize) {
        (self.settings.size[0], self.settings.size[1])
    }

    /// Fills the image band by band on the thread pool, with a progress bar over rows.
    /// (`fill` is a trait object: one instance of the pool's machinery for every marcher,
    /// for one indirect call per band of `BAND_ROWS` rows.)
    fn bands(&self, isa: volsample::Isa, fill: &Rows<'_>) -> Result<Image, String> {
        let (w, h) = self.size();
        let mut pixels = vec![Sample::TRANSPARENT; w * h];
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.settings.threads)
            .build()
            .map_err(|e| format!("thread pool: {e}"))?;
        let bar = if self.settings.progress {
            let bar = ProgressBar::new(h as u64);
            if let Ok(style) =
                ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {elapsed}")
            {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_message("rendering");
            Some(bar)
        } else {
            None
        };
        let start = std::time::Instant::now();
        pool.install(|| {
            pixels
                .par_chunks_mut(w * BAND_ROWS)
                .enumerate()
                .try_for_each(|(k, rows)| {
                    fill(k * BAND_ROWS, rows)?;
                    if let Some(bar) = &bar {
                        bar.inc((rows.len() / w) as u64);
                    }
                    Ok::<(), volsample::Error>(())
                })
        })
        .map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        Ok(Image {
            pixels,
            seconds,
            isa,
        })
    }
}
