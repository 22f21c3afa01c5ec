//! The integer pipeline: marching rays with integer samples, correction and compositing.
//!
//! [`IntRayMarcher`] follows the conventions of the float [`RayMarcher`](crate::RayMarcher):
//! samples at `t_k = (k + phase)·d` for every integer `k` with `t0 ≤ t_k < t1`, `[t0, t1]` the
//! ray's intersection with the box `[−½, n − ½]` per axis ([`Ray::clip`]), each sample
//! standing for a segment of length `d`. Only the sample positions are float: each is
//! **clamped** into `[0, n − 1]` per axis (exact under clamp-to-edge reconstruction, which
//! reads the edge voxel there anyway, for nearest and trilinear) and quantized with
//! [`IntPos::quantize`] (**round half up** to `F` fractional bits). Everything after that is
//! integer: the sample ([`IntSampler`]), the table-driven [`IntCorrection`] (only for the
//! opacity-based modes and only when `d ≠ d′`), and [`front_to_back`] compositing, which
//! stops before a sample once `A ≥ A_stop` ([`IntStop`]).
//!
//! [`IntRayMarcher::march_positions`] runs the same integer steps on sample positions given
//! directly as [`IntPos`] (a datapath that steps in fixed point; the hardware reference
//! vectors), with no float arithmetic per sample.
//!
//! Stages a scene does not use are not in the inner loop: the correction is chosen once per
//! ray by type, not per sample. Without empty-space skipping the loop is software-pipelined:
//! the voxels of sample `j + 1` are read before sample `j` is combined, so that their loads
//! are in flight while it computes (in the `ray_march` bench this took the portable integer
//! `cast` from 1.33 to 1.27 of the float `cast`'s time, and to 0.905 with the SSE2 kernel of
//! the feature `sse2`). The positions, taps and compositing order are those of one sample at
//! a time, so the results are too.

use super::{check_len, render_band, Step, MAX_SAMPLES_PER_RAY};
#[cfg(target_arch = "x86_64")]
use crate::arch::InAvx2;
use crate::arch::{in_isa, InIsa, Isa};
use crate::each::Each;
use crate::error::Error;
use crate::fixed_point::composite::{front_to_back, IntStop};
use crate::fixed_point::DEFAULT_FRAC_BITS;
use crate::fixed_point::{
    check_frac_bits, IntCorrection, IntFilter, IntMode, IntPos, IntSample, IntSampler,
};
use crate::ray::{Camera, Ray};
use crate::skip::{Emptiness, NoSkip, Occupancy, Skipping};
use crate::volume::Volume;
use crate::voxel::Voxel;
#[cfg(target_arch = "x86_64")]
mod lanes8;
mod one_ray;
#[cfg(target_arch = "x86_64")]
use lanes8::{OneRay, Reads};

/// The correction stage, chosen by type so that `d = d′` costs nothing per sample.
trait Stage {
    fn apply(&self, s: IntSample) -> IntSample;
}

/// No correction.
struct Identity;

impl Stage for Identity {
    #[inline(always)]
    fn apply(&self, s: IntSample) -> IntSample {
        s
    }
}

impl Stage for IntCorrection {
    #[inline(always)]
    fn apply(&self, s: IntSample) -> IntSample {
        IntCorrection::apply(self, s)
    }
}

/// A configured integer pipeline: volume, mode `M`, filter `Fl`, `F` fractional position
/// bits, step, early termination and background.
///
/// Error bound: per sample, that of the mode's kernel at the quantized position (plus that of
/// [`IntCorrection`] when `d ≠ d′`); per ray, the compositor's `n/2` (`A`) and `n` (`C`) LSB
/// over `n` samples ([`front_to_back`]). Against the float pipeline add the position
/// quantization (`2^−(F+1)` voxel per axis).
///
/// ```
/// use volsample::fixed_point::{IntSample, IntStop, ONE};
/// use volsample::render::IntRayMarcher;
/// use volsample::{OpacityWeighted, Orthographic, Step, StraightU8, Trilinear, Volume};
/// // A 4×4×4 volume: opaque white core in transparent black air.
/// let mut voxels = [StraightU8([0, 0, 0, 0]); 64];
/// for z in 1..3 { for y in 1..3 { for x in 1..3 {
///     voxels[x + 4 * (y + 4 * z)] = StraightU8([255, 255, 255, 255]);
/// }}}
/// let vol = Volume::new(&voxels, [4, 4, 4])?;
/// let marcher = IntRayMarcher::<_, _, _, 8>::new(
///     vol, OpacityWeighted, Trilinear::new(), IntStop::NEVER, Step::new(0.5)?,
/// )?;
/// let mut image = [IntSample::TRANSPARENT; 16];
/// marcher.render_into(&Orthographic::looking_down_z([4, 4, 4])?, 4, 4, &mut image)?;
/// assert_eq!(image[5].a(), ONE); // through the core: opaque
/// assert_eq!(image[5].c(), [ONE; 3]); // and white
/// assert_eq!(image[0].a(), 0); // through air at the corner
/// # Ok::<(), volsample::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct IntRayMarcher<'v, V, M, Fl, const F: u32 = DEFAULT_FRAC_BITS, S = NoSkip> {
    sampler: IntSampler<'v, V, M, Fl>,
    dims: [usize; 3],
    hi: [f32; 3],
    step: Step,
    stop: IntStop,
    background: IntSample,
    correction: Option<IntCorrection>,
    skip: S,
    isa: Isa,
}

impl<'v, V, M, Fl, const F: u32> IntRayMarcher<'v, V, M, Fl, F, NoSkip>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
{
    /// Builds the pipeline. The mode is configured for `d/d′` ([`IntMode::for_step_ratio`]);
    /// opacity correction is enabled exactly when the mode is opacity-based and `d ≠ d′`.
    ///
    /// # Errors
    /// [`Error::TooManySamples`] as for the float marcher; [`Error::DimensionTooLarge`] if a
    /// voxel coordinate times `2^F` does not fit in `u32`; [`Error::InvalidStep`] if `d/d′`
    /// is not below `2^32`.
    pub fn new(
        volume: Volume<'v, V>,
        mode: M,
        filter: Fl,
        stop: IntStop,
        step: Step,
    ) -> Result<Self, Error> {
        check_frac_bits!(F);
        let dims = volume.dims();
        let [nx, ny, nz] = dims.each(|n| n as f32);
        let diag = libm::sqrtf(nx * nx + ny * ny + nz * nz);
        if diag / step.d() + 2.0 > MAX_SAMPLES_PER_RAY as f32 {
            return Err(Error::TooManySamples);
        }
        if dims.iter().any(|&n| (n as u64) << F > u64::from(u32::MAX)) {
            return Err(Error::DimensionTooLarge);
        }
        let ratio = step.d() / volume.reference_distance();
        let mode = mode.for_step_ratio(ratio)?;
        let correction = if M::OPACITY_BASED && ratio != 1.0 {
            Some(IntCorrection::new(ratio)?)
        } else {
            None
        };
        Ok(Self {
            sampler: IntSampler::new(volume, mode, filter),
            dims,
            hi: dims.each(|n| (n - 1) as f32),
            step,
            stop,
            background: IntSample::TRANSPARENT,
            correction,
            skip: NoSkip,
            isa: Isa::detect(),
        })
    }

    /// Enables empty-space skipping, as the float
    /// [`RayMarcher::with_skipping`](crate::RayMarcher::with_skipping) does: an occupancy grid
    /// of this marcher's volume and mode (bricks of `2^log2` voxels) in `buffer`, and the
    /// samples it proves transparent stepped over. The quantized position may round up into
    /// the next voxel (by less than `2^−(F+1)`), whose taps the grid's apron still covers, so
    /// results and sample counts stay bit-identical. Offered for the opacity-based integer
    /// modes (not yet for the integer extinction mode).
    ///
    /// # Errors
    /// As [`Occupancy::build`].
    pub fn with_skipping<'g>(
        self,
        buffer: &'g mut [u8],
        log2: u32,
    ) -> Result<IntRayMarcher<'g, V, M, Fl, F, Occupancy<'g>>, Error>
    where
        'v: 'g,
        M: Emptiness<V>,
    {
        let grid = Occupancy::build(self.sampler.volume(), self.sampler.mode(), log2, buffer)?;
        Ok(IntRayMarcher {
            sampler: self.sampler,
            dims: self.dims,
            hi: self.hi,
            step: self.step,
            stop: self.stop,
            background: self.background,
            correction: self.correction,
            skip: grid,
            isa: self.isa,
        })
    }
}

impl<'v, V, M, Fl, const F: u32> IntRayMarcher<'v, V, M, Fl, F, Occupancy<'v>> {
    /// The occupancy grid in use.
    pub fn occupancy(&self) -> Option<&Occupancy<'v>> {
        Some(&self.skip)
    }
}

impl<'v, V, M, Fl, const F: u32, S> IntRayMarcher<'v, V, M, Fl, F, S>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
    S: Skipping,
{
    /// Sets a background, composited behind every ray with the same integer
    /// [`front_to_back`] step.
    pub fn with_background(mut self, bg: IntSample) -> Self {
        self.background = bg;
        self
    }

    /// Runs the kernels in the instruction set `isa` instead of the best one this CPU has
    /// (what `new` chose, [`Isa::detect`]): to compare instances, or to pin one. Every
    /// instance gives the same results, bit for bit. Only `OpacityWeighted` with trilinear
    /// filtering in the `WeightedSum` order (the eight-lane kernel's) has an AVX2 instance;
    /// the others run their portable instance under either [`Isa`].
    pub fn with_isa(mut self, isa: Isa) -> Self {
        self.isa = isa;
        self
    }

    /// The instruction set the kernels run in.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// The step.
    pub fn step(&self) -> Step {
        self.step
    }

    /// The opacity correction in use (`None` when `d = d′` or for the extinction mode).
    pub fn correction(&self) -> Option<&IntCorrection> {
        self.correction.as_ref()
    }

    /// The quantized position of a float sample position: clamped into `[0, n − 1]` per axis,
    /// then [`IntPos::quantize`]d (a NaN coordinate reads as 0). Never `None`: the
    /// constructor checked that `(n − 1)·2^F` fits in `u32`.
    #[inline]
    pub fn quantize(&self, pos: [f32; 3]) -> Option<IntPos<F>> {
        let [x, y, z] = pos;
        let [hx, hy, hz] = self.hi;
        // `max` returns the non-NaN operand, so NaN becomes 0.
        IntPos::quantize([x.max(0.0).min(hx), y.max(0.0).min(hy), z.max(0.0).min(hz)]).ok()
    }

    /// [`quantize`](Self::quantize), which never returns `None`, as a position.
    #[inline(always)]
    fn quantize_in_box(&self, pos: [f32; 3]) -> IntPos<F> {
        self.quantize(pos).unwrap_or_default()
    }

    /// One sample at `pos` (voxel units, clamped and quantized as [`quantize`](Self::quantize)
    /// does), opacity-corrected for the step. Inlined into the caller, in the caller's
    /// instruction set whatever the marcher's [`Isa`](crate::Isa) (integer arithmetic: the
    /// same bits in each), as [`RayMarcher::sample`](crate::RayMarcher::sample), and likewise a
    /// call where the marcher corrects opacity.
    #[inline]
    pub fn sample(&self, pos: [f32; 3]) -> IntSample {
        match self.correction {
            None => self.sample_with(pos, &Identity),
            Some(_) => self.sample_corrected(pos),
        }
    }

    /// [`sample`](Self::sample) of a marcher that corrects opacity, out of line.
    #[inline(never)]
    fn sample_corrected(&self, pos: [f32; 3]) -> IntSample {
        self.sample_here(pos)
    }

    /// [`sample`](Self::sample) at each of `positions` into `out` (the batch form for random
    /// access: the marcher's [`Isa`](crate::Isa) entered once, the cell of the position eight
    /// on prefetched), bit for bit.
    ///
    /// # Errors
    /// [`Error::ImageSizeMismatch`] unless `out.len() == positions.len()`.
    pub fn sample_into(&self, positions: &[[f32; 3]], out: &mut [IntSample]) -> Result<(), Error> {
        check_len(positions.len(), out.len())?;
        let vol = self.sampler.volume();
        in_isa!(self, {
            for (k, (&p, o)) in positions.iter().zip(out.iter_mut()).enumerate() {
                if let Some(&ahead) = positions.get(k + super::PREFETCH_AHEAD) {
                    vol.prefetch_cell(ahead);
                }
                *o = self.sample_here(p);
            }
        });
        Ok(())
    }

    /// [`sample`](Self::sample) in the instruction set of the caller.
    #[inline(always)]
    fn sample_here(&self, pos: [f32; 3]) -> IntSample {
        match &self.correction {
            Some(c) => self.sample_with(pos, c),
            None => self.sample_with(pos, &Identity),
        }
    }

    #[inline(always)]
    fn sample_with<C: Stage>(&self, pos: [f32; 3], corr: &C) -> IntSample {
        match self.quantize(pos) {
            Some(p) => corr.apply(self.sampler.sample(p)),
            None => IntSample::TRANSPARENT,
        }
    }

    /// The number of samples a ray takes without early termination, and the distance `t` of
    /// the first one (the float marcher's [`sample_range`](crate::RayMarcher::sample_range)).
    pub fn sample_range(&self, ray: &Ray) -> (f32, u32) {
        let Some((t0, t1)) = ray.clip(self.dims) else {
            return (0.0, 0);
        };
        let (d, phase) = (self.step.d(), self.step.phase());
        let k0 = libm::ceilf(t0 / d - phase);
        let k1 = libm::ceilf(t1 / d - phase);
        let n = (k1 - k0).clamp(0.0, MAX_SAMPLES_PER_RAY as f32) as u32;
        ((k0 + phase) * d, n)
    }

    /// Integrates one ray and composites it over the background.
    #[inline]
    pub fn cast(&self, ray: &Ray) -> IntSample {
        self.cast_counted(ray).0
    }

    /// [`cast`](Self::cast), also returning the number of samples composited (fewer than the
    /// ray's sample count when early termination stops it). Not inlined on x86-64, where each
    /// inlined copy would hold the march of every instruction set: one copy per instruction
    /// set serves `cast`, `cast_counted` and the pixel loop of
    /// [`render_into`](Self::render_into). Inlined elsewhere (one instruction set, and the
    /// smallest firmware images).
    #[cfg_attr(target_arch = "x86_64", inline(never))]
    #[cfg_attr(not(target_arch = "x86_64"), inline(always))]
    pub fn cast_counted(&self, ray: &Ray) -> (IntSample, u32) {
        in_isa!(self, self.cast_counted_here(ray))
    }

    /// [`cast_counted`](Self::cast_counted) in the instruction set of the caller.
    #[inline(always)]
    fn cast_counted_here(&self, ray: &Ray) -> (IntSample, u32) {
        let (acc, n) = match &self.correction {
            Some(c) => self.march(ray, c),
            None => self.march(ray, &Identity),
        };
        (front_to_back(acc, self.background), n)
    }

    /// [`cast_counted`](Self::cast_counted) with the sample positions given in the integer
    /// format instead of computed from a float ray: the samples at `positions`, in order,
    /// each opacity-corrected for the step when the pipeline corrects
    /// ([`correction`](Self::correction)), composited front to back ([`front_to_back`]) until
    /// `A ≥ A_stop` before a sample ([`IntStop`]), then over the background. Returns the
    /// composite and the number of samples composited.
    ///
    /// This is the entry point for a datapath that steps its positions in fixed point (the
    /// hardware reference vectors use it); a position outside the volume reads the edge
    /// voxels, as [`IntSampler::sample`] does. Positions after the stop are not read.
    ///
    /// Error bound: as [`cast_counted`](Self::cast_counted), without the position
    /// quantization.
    ///
    /// ```
    /// use volsample::fixed_point::{IntPos, IntStop, ONE};
    /// use volsample::render::IntRayMarcher;
    /// use volsample::{OpacityWeighted, Step, StraightU8, Trilinear, Volume};
    /// let voxels = [StraightU8([255, 0, 0, 100]); 8];
    /// let vol = Volume::new(&voxels, [2, 2, 2])?;
    /// let marcher = IntRayMarcher::<_, _, _, 8>::new(
    ///     vol, OpacityWeighted, Trilinear::new(), IntStop::new(ONE / 2)?, Step::new(1.0)?,
    /// )?;
    /// // Four samples along x; the stop is reached after the first two.
    /// let ray = (0..4).map(|k| IntPos::<8>::from_raw([64 * k, 128, 128]));
    /// let (s, taken) = marcher.march_positions(ray);
    /// assert_eq!(taken, 2);
    /// assert!(s.a() >= ONE / 2 && s.c()[1] == 0);
    /// # Ok::<(), volsample::Error>(())
    /// ```
    #[inline]
    pub fn march_positions<I: IntoIterator<Item = IntPos<F>>>(
        &self,
        positions: I,
    ) -> (IntSample, u32) {
        let positions = positions.into_iter();
        let (acc, n) = match &self.correction {
            Some(c) => self.march_int(positions, c),
            None => self.march_int(positions, &Identity),
        };
        (front_to_back(acc, self.background), n)
    }

    /// The steps of `march` over integer positions: the stop is tested before each position
    /// is read, so none is read after it; the count **saturates** at `u32::MAX`. (Its own
    /// loop: `march` over an iterator of samples cost 1–2 % more instructions per sample.
    /// `host-tests/tests/vectors.rs` checks that both give the same results.)
    #[inline(always)]
    fn march_int<C: Stage, I: Iterator<Item = IntPos<F>>>(
        &self,
        mut positions: I,
        corr: &C,
    ) -> (IntSample, u32) {
        let a_stop = self.stop.a_stop();
        let mut acc = IntSample::TRANSPARENT;
        let mut n = 0u32;
        while acc.a() < a_stop {
            let Some(p) = positions.next() else { break };
            acc = front_to_back(acc, corr.apply(self.sampler.sample(p)));
            n = n.saturating_add(1);
        }
        (acc, n)
    }

    /// Casts every ray of `rays` into `out`: `out[i]` is [`cast`](Self::cast)`(&rays[i])`,
    /// bit for bit. Where the marcher's [`Isa`] is AVX2 (the default on a CPU that has it)
    /// and the pipeline is `OpacityWeighted` trilinear over
    /// `StraightU8` at `F = 8` without correction (skipping or not), eight rays at a time in AVX2
    /// lanes (the same integer operations; rays of one direction also share the taps they
    /// read); otherwise, and for the rays beyond the last multiple of eight, one at a time.
    ///
    /// Error bound: that of [`cast`](Self::cast) (the same results).
    ///
    /// ```
    /// use volsample::fixed_point::{IntSample, IntStop};
    /// use volsample::render::IntRayMarcher;
    /// use volsample::{OpacityWeighted, Ray, Step, StraightU8, Trilinear, Volume};
    /// let voxels: Vec<StraightU8> =
    ///     (0..64u8).map(|i| StraightU8([i * 4, 255 - i, 7, i * 3])).collect();
    /// let vol = Volume::new(&voxels, [4, 4, 4])?;
    /// let marcher = IntRayMarcher::<_, _, _, 8>::new(
    ///     vol, OpacityWeighted, Trilinear::new(), IntStop::NEVER, Step::new(0.5)?,
    /// )?;
    /// let rays: Vec<Ray> = (0..11)
    ///     .map(|i| Ray::new([0.3 * i as f32, 1.4, -1.0], [0.0, 0.0, 1.0]))
    ///     .collect::<Result<_, _>>()?;
    /// let mut out = vec![IntSample::TRANSPARENT; rays.len()];
    /// marcher.cast_rays(&rays, &mut out)?;
    /// for (ray, got) in rays.iter().zip(&out) {
    ///     assert_eq!(*got, marcher.cast(ray));
    /// }
    /// # Ok::<(), volsample::Error>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::ImageSizeMismatch`] unless `out.len() == rays.len()`.
    pub fn cast_rays(&self, rays: &[Ray], out: &mut [IntSample]) -> Result<(), Error> {
        check_len(rays.len(), out.len())?;
        in_isa!(self, self.cast_rays_here(rays, out));
        Ok(())
    }

    /// [`cast_rays`](Self::cast_rays) of as many rays as outputs, in the instruction set of
    /// the caller.
    #[inline(always)]
    fn cast_rays_here(&self, rays: &[Ray], out: &mut [IntSample]) {
        let (rays, out) = self.cast_rays8(rays, out);
        for (r, o) in rays.iter().zip(out) {
            *o = self.cast_counted_here(r).0;
        }
    }

    /// Whether the eight-ray AVX2 kernel applies: an AVX2 [`Isa`] and an `OpacityWeighted` trilinear pipeline over straight RGBA8 voxels at `F = 8`
    /// without correction (skipping or not), over a volume the kernel can index.
    #[inline]
    pub(super) fn eight_ray_packets(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            F == 8
                && self.correction.is_none()
                && self.isa.avx2_token().is_some()
                && crate::arch::avx2::fits_int(self.sampler.volume())
                && Fl::lanes8(self.sampler.mode(), Reads(self.sampler.volume().data()))
                    .unwrap_or(false)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// Without the eight-ray kernel: all of `rays` are cast one at a time.
    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    fn cast_rays8<'r, 'o>(
        &self,
        rays: &'r [Ray],
        out: &'o mut [IntSample],
    ) -> (&'r [Ray], &'o mut [IntSample]) {
        (rays, out)
    }

    /// How many rays [`cast_rays`](Self::cast_rays) marches at once in lanes: 8 where this
    /// marcher runs the eight-ray AVX2 kernel, else 1.
    pub fn packet_width(&self) -> usize {
        if self.eight_ray_packets() {
            8
        } else {
            1
        }
    }

    /// Renders a `width × height` image (row-major, row 0 at the top) into `image`: each
    /// pixel [`cast`](Self::cast) of its ray — eight pixels of a row at a time with
    /// [`cast_rays`](Self::cast_rays) where its AVX2 kernel applies (the same results).
    ///
    /// # Errors
    /// [`Error::EmptyImage`] for a zero width or height, [`Error::ImageSizeMismatch`] unless
    /// `image.len() == width·height`.
    pub fn render_into<Cam: Camera>(
        &self,
        camera: &Cam,
        width: usize,
        height: usize,
        image: &mut [IntSample],
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
        rows: &mut [IntSample],
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
        image: &mut [IntSample],
    ) -> Result<(), Error> {
        let marcher = (self, self.eight_ray_packets());
        let casts = (Self::cast_rays8, Self::cast);
        render_band(marcher, (camera, size, first_row), image, casts)
    }
}

impl<V, M, Fl, const F: u32, S> InIsa for IntRayMarcher<'_, V, M, Fl, F, S>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
{
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn isa_of(&self) -> Isa {
        self.isa
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn in_avx2<R, G: FnOnce() -> R>(&self, cpu: crate::arch::avx2::Avx2, f: G) -> Result<R, G> {
        Fl::lanes8(self.sampler.mode(), InAvx2::new(cpu, f)).map_err(InAvx2::into_inner)
    }
}
