//! Marching rays through a volume: the whole float pipeline.
//!
//! A [`RayMarcher`] fixes the volume, the [`Mode`], the [`Filter`], the compositing
//! [`Order`] and the [`Step`] by type and value; [`RayMarcher::cast`] integrates one ray
//! (for callers with their own pixel loop) and [`RayMarcher::render_into`] fills a
//! caller-provided image.
//!
//! Samples lie at `t_k = (k + phase)·d` for every integer `k` with `t0 ≤ t_k < t1`, where
//! `[t0, t1]` is the ray's intersection with the volume box ([`Ray::clip`]); phases are
//! anchored at the ray origin, so an orthographic camera samples on planes. Each sample
//! stands for a segment of length `d`.
//!
//! Stages a scene does not need are not in its inner loop: opacity correction is chosen by
//! type ([`Uncorrected`] when `d = d′` or the mode is extinction-based), early termination is
//! [`Never`](crate::composite::Never) unless a threshold is set, and the background is
//! applied once per ray.

use core::marker::PhantomData;

use crate::composite::{back_to_front, front_to_back, over, Order, Termination};
use crate::error::Error;
use crate::filter::Filter;
use crate::mode::Mode;
use crate::opacity::{Corrected, Correction, Uncorrected};
use crate::ray::{Camera, Ray};
use crate::sample::Sample;
use crate::skip::{Emptiness, NoSkip, Occupancy, Skipping};
use crate::volume::Volume;
use crate::voxel::Voxel;

/// Most samples one ray may take (2²⁴, so every sample index is exact in `f32`).
pub const MAX_SAMPLES_PER_RAY: usize = 1 << 24;

/// The sampling step `d` (voxel units) and the start phase in `[0, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Step {
    d: f32,
    phase: f32,
}

impl Step {
    /// Step `d`, phase 0.
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `d` is finite and positive.
    pub fn new(d: f32) -> Result<Self, Error> {
        if d.is_finite() && d > 0.0 {
            Ok(Self { d, phase: 0.0 })
        } else {
            Err(Error::InvalidStep)
        }
    }

    /// Sets the start phase (samples at `(k + phase)·d`).
    ///
    /// # Errors
    /// [`Error::InvalidPhase`] outside `[0, 1)`.
    pub fn with_phase(mut self, phase: f32) -> Result<Self, Error> {
        if (0.0..1.0).contains(&phase) {
            self.phase = phase;
            Ok(self)
        } else {
            Err(Error::InvalidPhase)
        }
    }

    /// `d`.
    pub fn d(&self) -> f32 {
        self.d
    }

    /// The phase.
    pub fn phase(&self) -> f32 {
        self.phase
    }
}

/// A configured float pipeline: volume, mode `M`, filter `F`, order `O`, step.
///
/// ```
/// use volsample::{
///     FrontToBack, Orthographic, OpacityWeighted, RayMarcher, Sample, Step, StraightU8,
///     Trilinear, Volume,
/// };
/// // A 4×4×4 volume: opaque white core in transparent black air.
/// let mut voxels = [StraightU8([0, 0, 0, 0]); 64];
/// for z in 1..3 { for y in 1..3 { for x in 1..3 {
///     voxels[x + 4 * (y + 4 * z)] = StraightU8([255, 255, 255, 255]);
/// }}}
/// let vol = Volume::new(&voxels, [4, 4, 4])?;
/// let marcher = RayMarcher::new(
///     vol, OpacityWeighted, Trilinear::new(), FrontToBack::new(), Step::new(0.5)?,
/// )?;
/// let mut image = [Sample::TRANSPARENT; 16];
/// marcher.render_into(&Orthographic::looking_down_z([4, 4, 4])?, 4, 4, &mut image)?;
/// assert!(image[5].a > 0.99);  // through the core
/// assert!(image[5].c[0] > 0.99);  // white, no darkening
/// assert_eq!(image[0].a, 0.0);  // through air at the corner
/// # Ok::<(), volsample::Error>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct RayMarcher<'v, V, M, F, O, S = NoSkip> {
    volume: Volume<'v, V>,
    mode: M,
    order: O,
    step: Step,
    background: Sample,
    correction: Option<Corrected>,
    skip: S,
    filter: PhantomData<F>,
}

impl<'v, V, M, F, O> RayMarcher<'v, V, M, F, O, NoSkip>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
{
    /// Builds the pipeline. Opacity correction is enabled exactly when the mode is
    /// opacity-based and `d ≠ d′`.
    ///
    /// # Errors
    /// [`Error::TooManySamples`] if a ray through the volume could take more than
    /// [`MAX_SAMPLES_PER_RAY`] samples at this step.
    pub fn new(
        volume: Volume<'v, V>,
        mode: M,
        _filter: F,
        order: O,
        step: Step,
    ) -> Result<Self, Error> {
        let [nx, ny, nz] = volume.dims().map(|n| n as f32);
        let diag = libm::sqrtf(nx * nx + ny * ny + nz * nz);
        if diag / step.d + 2.0 > MAX_SAMPLES_PER_RAY as f32 {
            return Err(Error::TooManySamples);
        }
        let ratio = step.d / volume.reference_distance();
        let correction = if M::OPACITY_BASED && ratio != 1.0 {
            Some(Corrected::new(ratio).ok_or(Error::InvalidStep)?)
        } else {
            None
        };
        Ok(Self {
            volume,
            mode,
            order,
            step,
            background: Sample::TRANSPARENT,
            correction,
            skip: NoSkip,
            filter: PhantomData,
        })
    }

    /// Enables empty-space skipping: builds an occupancy grid of this marcher's volume and
    /// mode with bricks of `2^log2` voxels into `buffer` (at least
    /// [`Occupancy::buffer_len`] bytes) and steps over the samples it proves transparent.
    /// Results, sample counts included, are bit-identical to the marcher without it (see
    /// [`skip`](crate::skip)); the grid costs one byte per brick and one lookup per sample.
    /// The skipping marcher is its own type, so a marcher without it has no test in its
    /// inner loop and no extra code.
    ///
    /// # Errors
    /// As [`Occupancy::build`].
    pub fn with_skipping<'g>(
        self,
        buffer: &'g mut [u8],
        log2: u32,
    ) -> Result<RayMarcher<'g, V, M, F, O, Occupancy<'g>>, Error>
    where
        'v: 'g,
        M: Emptiness<V>,
    {
        let grid = Occupancy::build(&self.volume, &self.mode, log2, buffer)?;
        Ok(RayMarcher {
            volume: self.volume,
            mode: self.mode,
            order: self.order,
            step: self.step,
            background: self.background,
            correction: self.correction,
            skip: grid,
            filter: PhantomData,
        })
    }
}

impl<'v, V, M, F, O> RayMarcher<'v, V, M, F, O, Occupancy<'v>> {
    /// The occupancy grid in use.
    pub fn occupancy(&self) -> Option<&Occupancy<'v>> {
        Some(&self.skip)
    }
}

impl<'v, V, M, F, O, S> RayMarcher<'v, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    /// Sets an associated background color, composited behind every ray.
    ///
    /// # Errors
    /// [`Error::InvalidBackground`] unless `bg` is finite with `0 ≤ C ≤ A ≤ 1`.
    pub fn with_background(mut self, bg: Sample) -> Result<Self, Error> {
        if !bg.is_valid() {
            return Err(Error::InvalidBackground);
        }
        self.background = bg;
        Ok(self)
    }

    /// The volume.
    pub fn volume(&self) -> &Volume<'v, V> {
        &self.volume
    }

    /// The step.
    pub fn step(&self) -> Step {
        self.step
    }

    /// The opacity correction in use (`None` when `d = d′` or for extinction modes).
    pub fn correction(&self) -> Option<Corrected> {
        self.correction
    }

    /// One sample at `pos` (voxel units), opacity-corrected for the step: the associated
    /// color and opacity of a segment of length `d`.
    #[inline]
    pub fn sample(&self, pos: [f32; 3]) -> Sample {
        match self.correction {
            Some(c) => self.sample_with(pos, &c),
            None => self.sample_with(pos, &Uncorrected),
        }
    }

    #[inline(always)]
    fn sample_with<C: Correction>(&self, pos: [f32; 3], corr: &C) -> Sample {
        let i = F::interpolate(&self.mode, &self.volume, pos);
        corr.apply(self.mode.finish(i, self.step.d))
    }

    /// Integrates one ray and composites it over the background.
    #[inline]
    pub fn cast(&self, ray: &Ray) -> Sample {
        self.cast_counted(ray).0
    }

    /// [`cast`](Self::cast), also returning the number of samples taken (fewer than the
    /// ray's sample count when early termination stops it). The count costs nothing when it
    /// is not used.
    #[inline(always)]
    pub fn cast_counted(&self, ray: &Ray) -> (Sample, u32) {
        let (acc, n) = match &self.correction {
            Some(c) => self.march(ray, c),
            None => self.march(ray, &Uncorrected),
        };
        (over(acc, self.background), n)
    }

    /// The ray's sample range: the first sample's `t`, and the sample count.
    fn samples(&self, ray: &Ray) -> (f32, u32) {
        let Some((t0, t1)) = ray.clip(self.volume.dims()) else {
            return (0.0, 0);
        };
        let Step { d, phase } = self.step;
        let k0 = libm::ceilf(t0 / d - phase);
        let k1 = libm::ceilf(t1 / d - phase);
        let n = (k1 - k0).clamp(0.0, MAX_SAMPLES_PER_RAY as f32) as u32;
        ((k0 + phase) * d, n)
    }

    #[inline(always)]
    fn march<C: Correction>(&self, ray: &Ray, corr: &C) -> (Sample, u32) {
        let (t_first, n) = self.samples(ray);
        let d = self.step.d;
        let mut acc = Sample::TRANSPARENT;
        if O::FRONT_TO_BACK {
            let term = self.order.termination();
            for j in 0..n {
                let p = ray.at(t_first + j as f32 * d);
                // A skipped sample is transparent, so `acc` and the termination test are
                // unchanged by it (and it was not done after the previous sample).
                if self.skip.empty(p) {
                    continue;
                }
                let s = self.sample_with(p, corr);
                acc = front_to_back(acc, s);
                if term.done(acc.a) {
                    return (acc, j + 1);
                }
            }
        } else {
            for j in (0..n).rev() {
                let p = ray.at(t_first + j as f32 * d);
                if self.skip.empty(p) {
                    continue;
                }
                let s = self.sample_with(p, corr);
                acc = back_to_front(acc, s);
            }
        }
        (acc, n)
    }

    /// The number of samples a ray takes without early termination, and the distance `t` of
    /// the first one.
    pub fn sample_range(&self, ray: &Ray) -> (f32, u32) {
        self.samples(ray)
    }

    /// Renders a `width × height` image (row-major, row 0 at the top) into `image`.
    ///
    /// # Errors
    /// [`Error::EmptyImage`] for a zero width or height, [`Error::ImageSizeMismatch`] unless
    /// `image.len() == width·height`.
    pub fn render_into<Cam: Camera>(
        &self,
        camera: &Cam,
        width: usize,
        height: usize,
        image: &mut [Sample],
    ) -> Result<(), Error> {
        trace_image(camera, width, height, image, |ray| self.cast(ray))
    }
}

/// Fills a `width × height` image (row-major, row 0 at the top) with `cast` of each pixel's
/// ray, after checking the image size: the pixel loop shared by the float and the integer
/// ray marchers.
///
/// # Errors
/// [`Error::EmptyImage`] for a zero width or height, [`Error::ImageSizeMismatch`] unless
/// `image.len() == width·height`.
pub(crate) fn trace_image<P, Cam: Camera>(
    camera: &Cam,
    width: usize,
    height: usize,
    image: &mut [P],
    cast: impl Fn(&Ray) -> P,
) -> Result<(), Error> {
    if width == 0 || height == 0 {
        return Err(Error::EmptyImage);
    }
    let expected = width.checked_mul(height).ok_or(Error::ImageSizeMismatch {
        expected: usize::MAX,
        actual: image.len(),
    })?;
    if image.len() != expected {
        return Err(Error::ImageSizeMismatch {
            expected,
            actual: image.len(),
        });
    }
    for (j, row) in image.chunks_exact_mut(width).enumerate() {
        for (i, px) in row.iter_mut().enumerate() {
            *px = cast(&camera.ray(i, j, width, height));
        }
    }
    Ok(())
}
