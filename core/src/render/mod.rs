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
//! Stages a scene does not need cost it next to nothing: opacity correction is
//! [`Uncorrected`] by type for the extinction-based modes, and for the opacity-based ones
//! chosen once per marcher (none when `d = d′`: one predictable branch per sample or lane
//! packet, so that one march serves both and a firmware image links one), early termination is [`Never`](crate::composite::Never) unless a threshold is set, and the
//! background is applied once per ray.

use core::marker::PhantomData;
use core::ops::ControlFlow;

#[cfg(target_arch = "x86_64")]
use crate::arch::InAvx2;
use crate::arch::{in_isa, InIsa, Isa};
use crate::composite::{back_to_front, front_to_back, front_to_back_in, over, Order, Termination};
use crate::each::Each;
use crate::error::Error;
use crate::filter::Filter;
use crate::lanes::F32x4;
use crate::mode::{unpack_interp, Mode};
use crate::num::Num;
use crate::opacity::{Corrected, Correction, Uncorrected};
use crate::ray::{Camera, Ray};
use crate::sample::{Interp, Sample};
use crate::skip::{Emptiness, NoSkip, Occupancy, Skipping};
use crate::volume::Volume;
use crate::voxel::Voxel;

mod image;
mod int_marcher;
mod one_ray;
mod packets;
mod step;

pub(crate) use image::{check_len, render_band};
pub use int_marcher::IntRayMarcher;
pub use step::Step;

/// Most samples one ray may take (2²⁴, so every sample index is exact in `f32`).
pub const MAX_SAMPLES_PER_RAY: usize = 1 << 24;

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
    isa: Isa,
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
        let [nx, ny, nz] = volume.dims().each(|n| n as f32);
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
            isa: Isa::detect(),
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
            isa: self.isa,
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

    /// Runs the kernels in the instruction set `isa` instead of the best one this CPU has
    /// (what [`new`](RayMarcher::new) chose, [`Isa::detect`]): to compare instances, or to
    /// pin one. Every instance gives the same results, bit for bit. Only marchers whose types
    /// have an eight-lane AVX2 kernel (trilinear, `WeightedSum` order, with `OpacityWeighted`,
    /// `Separate`, `ExtinctionWeighted` or `ExtinctionWeightedU8`) have an AVX2 instance; the
    /// others run their portable instance under either [`Isa`] (see [`crate::arch`]).
    pub fn with_isa(mut self, isa: Isa) -> Self {
        self.isa = isa;
        self
    }

    /// The instruction set the kernels run in.
    pub fn isa(&self) -> Isa {
        self.isa
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
    /// color and opacity of a segment of length `d`. Inlined into the caller, in the caller's
    /// instruction set whatever the marcher's [`Isa`] (one sample is scalar code: the same
    /// `f32` operations in every instruction set, so the same bits). Entering the marcher's
    /// instruction set per call kept a caller's loop from overlapping the memory reads of
    /// consecutive positions, which is what random access waits on. Where the marcher corrects
    /// opacity (`d ≠ d′`), the sample is a call ([`correction`](Self::correction)): with the
    /// correction's code inlined beside it, the compiler packed the weighted sums of the
    /// common case `d = d′` into vector lanes, which made random access slower.
    #[inline]
    pub fn sample(&self, pos: [f32; 3]) -> Sample {
        match self.correction {
            None => self.sample_with(pos, &Uncorrected),
            Some(_) => self.sample_corrected(pos),
        }
    }

    /// [`sample`](Self::sample) of a marcher that corrects opacity, out of line.
    #[inline(never)]
    fn sample_corrected(&self, pos: [f32; 3]) -> Sample {
        self.sample_here(pos)
    }

    /// [`sample`](Self::sample) at each of `positions` into `out`, bit for bit: the batch form
    /// for random access, in the marcher's [`Isa`] (entered once) and prefetching the cell of
    /// the position eight on, so that reads from memory overlap further.
    ///
    /// # Errors
    /// [`Error::ImageSizeMismatch`] unless `out.len() == positions.len()`.
    pub fn sample_into(&self, positions: &[[f32; 3]], out: &mut [Sample]) -> Result<(), Error> {
        check_len(positions.len(), out.len())?;
        in_isa!(self, {
            for (k, (&p, o)) in positions.iter().zip(out.iter_mut()).enumerate() {
                if let Some(&ahead) = positions.get(k + PREFETCH_AHEAD) {
                    self.volume.prefetch_cell(ahead);
                }
                *o = self.sample_here(p);
            }
        });
        Ok(())
    }

    /// [`sample`](Self::sample) in the instruction set of the caller: each position of
    /// `sample_into` (inside the marcher's instruction set), and `sample` where the marcher
    /// corrects opacity.
    #[inline(always)]
    fn sample_here(&self, pos: [f32; 3]) -> Sample {
        if M::OPACITY_BASED {
            self.sample_with(pos, &self.correction)
        } else {
            self.sample_with(pos, &Uncorrected)
        }
    }

    #[inline(always)]
    fn sample_with<C: Correction>(&self, pos: [f32; 3], corr: &C) -> Sample {
        let i = F::interpolate(&self.mode, &self.volume, pos);
        corr.apply(self.mode.finish(i, self.step.d))
    }

    /// Integrates one ray and composites it over the background.
    ///
    /// Runs in the marcher's [`Isa`]. Front to back, where the eight-lane AVX2 kernel applies
    /// (an AVX2 [`Isa`] and the marchers of [`cast_rays`](Self::cast_rays)'s eight-ray
    /// packets), eight consecutive samples are computed at a time in its lanes and composited
    /// in order; elsewhere, on targets with 128-bit `f32` vector units (x86-64, AArch64,
    /// WebAssembly SIMD), four at a time in [`F32x4`] lanes (the samples after an early stop
    /// are computed and dropped). Either way each sample takes the same `f32` operations as
    /// one at a time, so the result is bit-identical (`tests/fast_paths.rs`), and the
    /// samples' chains of dependent operations overlap. The four lanes are not used for
    /// [`Nearest`](crate::Nearest), nor for the opacity-based trilinear kernels over
    /// [`Voxel::F32_CHANNELS`] formats, which ran as fast or faster one sample at a time, nor
    /// on a scalar FPU such as the Cortex-M4F's.
    #[inline]
    pub fn cast(&self, ray: &Ray) -> Sample {
        self.cast_counted(ray).0
    }

    /// [`cast`](Self::cast), also returning the number of samples taken (fewer than the
    /// ray's sample count when early termination stops it). Not inlined on x86-64, where each
    /// inlined copy would hold the march of every instruction set: one copy per instruction
    /// set serves `cast`, `cast_counted` and the pixel loop of
    /// [`render_into`](Self::render_into). Inlined elsewhere (one instruction set, and the
    /// smallest firmware images).
    #[cfg_attr(target_arch = "x86_64", inline(never))]
    #[cfg_attr(not(target_arch = "x86_64"), inline(always))]
    pub fn cast_counted(&self, ray: &Ray) -> (Sample, u32) {
        in_isa!(self, self.cast_counted_here(ray))
    }

    /// [`cast_counted`](Self::cast_counted) in the instruction set of the caller.
    #[inline(always)]
    fn cast_counted_here(&self, ray: &Ray) -> (Sample, u32) {
        let (acc, n) = if M::OPACITY_BASED {
            self.march(ray, &self.correction)
        } else {
            self.march(ray, &Uncorrected)
        };
        (over(acc, self.background), n)
    }

    /// The ray's sample range: the first sample's `t`, and the sample count. (On x86-64
    /// inlined, as [`Ray::clip`], into the instruction set of its caller; elsewhere out of
    /// line, for code size.)
    #[cfg_attr(target_arch = "x86_64", inline)]
    #[cfg_attr(not(target_arch = "x86_64"), inline(never))]
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

    /// Integrates four rays at once: entry `l` is `cast_counted(&rays[l])`, bit for bit.
    ///
    /// The packet kernel marches the four rays in lock step, one sample of each per step:
    /// positions, gathers and the compositing decisions per ray; the reconstruction weights,
    /// the mode's sums, its finish, the correction and the front-to-back step in four lanes
    /// ([`F32x4`]), so that the four rays' chains of dependent operations overlap (and the
    /// compiler may use vector instructions for the lanes). Each lane performs exactly the
    /// scalar kernel's `f32` operations in the same order, so the results are bit-identical
    /// (`tests/fast_paths.rs` in the host tests). A ray that ends or terminates early leaves
    /// its lane idle while the others go on, so packets of neighbouring rays (similar
    /// lengths) waste least. Back-to-front orders, and filters whose
    /// [`Filter::PACKETS`] is `false` ([`Nearest`](crate::Nearest)), cast the four rays one by
    /// one.
    ///
    /// ```
    /// # use volsample::{FrontToBack, OpacityWeighted, Ray, RayMarcher, Step, StraightU8, Trilinear, Volume};
    /// let voxels: Vec<StraightU8> = (0..64u8).map(|i| StraightU8([i, 2 * i, 3 * i, 4 * i])).collect();
    /// let vol = Volume::new(&voxels, [4, 4, 4])?;
    /// let m = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), FrontToBack::new(), Step::new(0.3)?)?;
    /// let rays = [0.2f32, 0.9, 1.7, 2.6].map(|x| Ray::new([x, 1.3, -1.0], [0.1, 0.05, 1.0]).unwrap());
    /// let four = m.cast4(&rays);
    /// for (ray, got) in rays.iter().zip(four) {
    ///     assert_eq!(got, m.cast_counted(ray));
    /// }
    /// # Ok::<(), volsample::Error>(())
    /// ```
    #[inline(never)]
    #[doc(hidden)]
    pub fn cast4(&self, rays: &[Ray; 4]) -> [(Sample, u32); 4] {
        in_isa!(self, self.cast4_here(rays))
    }

    /// [`cast4`](Self::cast4) in the instruction set of the caller.
    #[inline(always)]
    fn cast4_here(&self, rays: &[Ray; 4]) -> [(Sample, u32); 4] {
        if !O::FRONT_TO_BACK || !F::PACKETS {
            return rays.each_ref().each(|r| self.cast_counted_here(r));
        }
        let (acc, n) = if M::OPACITY_BASED {
            self.march4(rays, &self.correction)
        } else {
            self.march4(rays, &Uncorrected)
        };
        let mut out = [(Sample::TRANSPARENT, 0); 4];
        for ((o, a), k) in out.iter_mut().zip(acc).zip(n) {
            *o = (over(a, self.background), k);
        }
        out
    }

    /// Casts every ray of `rays` into `out` (`out[i]` is `cast(&rays[i])`, bit for bit), four
    /// at a time with [`cast4`](Self::cast4) — or eight at a time in AVX2 lanes where the
    /// marcher's [`Isa`] is AVX2 (the default on a CPU that has it) and the marcher is
    /// `OpacityWeighted`, `Separate` or `ExtinctionWeightedU8` over `StraightU8` (the first two
    /// also over `StraightF32`), or `ExtinctionWeighted` over `ExtinctionF32`,
    /// `Trilinear<WeightedSum>`, front to back,
    /// corrected or not, skipping or not ([`packet_width`](Self::packet_width) is then 8): in
    /// the `ray_march` bench that takes about a quarter to a third of `cast`'s time for
    /// `OpacityWeighted` (the README's performance section has the figures).
    ///
    /// Packets overlap the four rays' chains of dependent operations; so does
    /// [`cast`](Self::cast) with four consecutive samples of one ray in lanes, which wastes no
    /// lane on rays of different lengths. Since `cast` does that, packets no longer pay in the
    /// `ray_march` bench (coherent rays through 256³), so [`render_into`](Self::render_into)
    /// does not use them. They may still pay where `cast` runs one sample at a time (the
    /// opacity-based trilinear kernels over [`Voxel::F32_CHANNELS`] formats), and the
    /// eight-ray AVX2 packets do pay. Measure on your rays.
    ///
    /// # Errors
    /// [`Error::ImageSizeMismatch`] unless `out.len() == rays.len()`.
    pub fn cast_rays(&self, rays: &[Ray], out: &mut [Sample]) -> Result<(), Error> {
        check_len(rays.len(), out.len())?;
        in_isa!(self, self.cast_rays_here(rays, out));
        Ok(())
    }

    /// [`cast_rays`](Self::cast_rays) of as many rays as outputs, in the instruction set of
    /// the caller.
    #[inline(always)]
    fn cast_rays_here(&self, rays: &[Ray], out: &mut [Sample]) {
        let (rays, out) = self.cast_rays8(rays, out);
        let mut r4 = rays.chunks_exact(4);
        let mut o4 = out.chunks_exact_mut(4);
        for (r, o) in (&mut r4).zip(&mut o4) {
            if let (Ok(r), Ok(o)) = (<&[Ray; 4]>::try_from(r), <&mut [Sample; 4]>::try_from(o)) {
                *o = self.cast4_here(r).each(|x| x.0);
            }
        }
        for (r, o) in r4.remainder().iter().zip(o4.into_remainder()) {
            *o = self.cast_counted_here(r).0;
        }
    }

    /// How many rays [`cast_rays`](Self::cast_rays) marches at once in lanes: 8 where this
    /// marcher runs the eight-ray AVX2 kernel (its [`Isa`] is AVX2 and its mode, voxel
    /// format, filter, order and stages are those the kernel computes), else 4 (or 1 where
    /// its filter or order casts one ray at a time).
    pub fn packet_width(&self) -> usize {
        if self.eight_ray_packets() {
            8
        } else if O::FRONT_TO_BACK && F::PACKETS {
            4
        } else {
            1
        }
    }

    /// The number of samples a ray takes without early termination, and the distance `t` of
    /// the first one.
    pub fn sample_range(&self, ray: &Ray) -> (f32, u32) {
        self.samples(ray)
    }

    /// Renders a `width × height` image (row-major, row 0 at the top) into `image`, one ray at
    /// a time — or, where the eight-ray AVX2 kernel of [`cast_rays`](Self::cast_rays) applies
    /// ([`packet_width`](Self::packet_width) 8), eight pixels of a row at a time with it, for
    /// orthographic and perspective cameras alike; each in the marcher's [`Isa`]; every
    /// pixel is `cast` of its ray, bit for bit, either way. (The four-ray packets of other
    /// builds did not pay here, see `cast_rays`.)
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
        self.render_band(camera, (width, height), None, image)
    }

    /// Renders rows `first_row ..` of a `width × height` image into `rows` (a whole number of
    /// rows, row-major): each pixel exactly as [`render_into`](Self::render_into) renders it,
    /// so bands rendered in any order, on any thread, make the same image. The core has no
    /// threads; a host splits the image into bands and renders them in parallel.
    ///
    /// # Errors
    /// [`Error::EmptyImage`] for a zero width or height, [`Error::ImageSizeMismatch`] unless
    /// `rows.len()` is a multiple of `width`, [`Error::RowsOutsideImage`] unless the band lies
    /// in the image.
    pub fn render_rows_into<Cam: Camera>(
        &self,
        camera: &Cam,
        (width, height): (usize, usize),
        first_row: usize,
        rows: &mut [Sample],
    ) -> Result<(), Error> {
        self.render_band(camera, (width, height), Some(first_row), rows)
    }

    /// [`render_into`](Self::render_into) (`first_row: None`) and
    /// [`render_rows_into`](Self::render_rows_into).
    fn render_band<Cam: Camera>(
        &self,
        camera: &Cam,
        size: (usize, usize),
        first_row: Option<usize>,
        image: &mut [Sample],
    ) -> Result<(), Error> {
        let marcher = (self, self.eight_ray_packets());
        let casts = (Self::cast_rays8, Self::cast);
        render_band(marcher, (camera, size, first_row), image, casts)
    }
}

impl<V, M, F, O, S> InIsa for RayMarcher<'_, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
{
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn isa_of(&self) -> Isa {
        self.isa
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn in_avx2<R, G: FnOnce() -> R>(&self, cpu: crate::arch::avx2::Avx2, f: G) -> Result<R, G> {
        F::lanes8(&self.mode, InAvx2::new(cpu, f)).map_err(InAvx2::into_inner)
    }
}

/// How many positions ahead [`RayMarcher::sample_into`] and `IntRayMarcher::sample_into`
/// prefetch the cell of: enough for the reads of several samples to be on their way from
/// memory at once.
pub(crate) const PREFETCH_AHEAD: usize = 8;

/// Whether [`RayMarcher::cast`] marches front-to-back rays four consecutive samples at a time
/// in [`F32x4`] lanes (bit-identical to one at a time, `tests/fast_paths.rs`): on targets with
/// 128-bit `f32` vector units (SSE2, NEON, WebAssembly SIMD), where the four samples' weights
/// and sums share vector instructions and their chains of dependent operations overlap. A
/// scalar FPU (Cortex-M4F) gains nothing from the lanes but code and stack, so there each
/// sample runs on its own.
const SAMPLE_LANES: bool = cfg!(any(
    target_feature = "sse2",
    target_feature = "neon",
    target_feature = "simd128"
));

/// Whether [`RayMarcher::cast`] marches a front-to-back ray of this voxel format, mode and
/// filter four samples at a time ([`SAMPLE_LANES`]): not for [`Nearest`](crate::Nearest)
/// (one tap, [`Filter::PACKETS`]), nor for the opacity-based modes reading 8 taps of
/// [`Voxel::F32_CHANNELS`] formats, whose one-sample kernel already works on four-lane taps.
/// Measured with `volsample report` (both binaries run side by side, three times): in lanes
/// the B-spline methods took 0.47–0.70 and `Preweighted` over bytes 0.53 of the time, the
/// f32 extinction 0.95, `OpacityWeighted` over `StraightF32` 1.13.
const fn sample_lanes<V: Voxel, M: Mode<V>, F: Filter>() -> bool {
    SAMPLE_LANES && F::PACKETS && !(V::F32_CHANNELS && M::OPACITY_BASED && F::TAPS == 8)
}
