//! Empty-space skipping: a coarse occupancy grid that lets a ray marcher step over samples
//! that cannot contribute, without changing a single bit of the result.
//!
//! The volume is cut into bricks of `B³` voxels (`B = 2^log2`). A brick is **empty** when
//! every voxel in it and in a one-voxel apron below and a two-voxel apron above it (the
//! voxel range `[b·B − 1, b·B + B + 1]` per axis, clipped to the grid) is empty for the mode
//! ([`Emptiness`]). Every tap of a sample whose position floors (after clamping into the
//! grid) into brick `b` lies in that range, for each filter: nearest reads `x` or `x + 1`,
//! trilinear `x` and `x + 1`, the triquadratic B-spline `x − 1 ..= x + 2` (taps outside the
//! grid are clamped to its edge, which stays in the range). So a sample in an empty brick
//! interpolates empty taps only, which every [`Emptiness`] mode turns into exactly
//! [`Sample::TRANSPARENT`](crate::Sample::TRANSPARENT) (also after opacity correction), and
//! compositing a transparent sample is exactly the identity: skipping it changes nothing,
//! early termination and sample counts included. The tests hold this bit for bit.
//!
//! The grid lives in a caller-provided byte buffer ([`Occupancy::buffer_len`] bytes, one per
//! brick): no allocation. Building it reads every voxel once.
//!
//! ```
//! use volsample::skip::Occupancy;
//! use volsample::{FrontToBack, OpacityWeighted, RayMarcher, Step, StraightU8, Trilinear, Volume};
//! // 32³ of air with one opaque voxel.
//! let mut voxels = [StraightU8([0; 4]); 32 * 32 * 32];
//! voxels[4 + 32 * (4 + 32 * 4)] = StraightU8([255; 4]);
//! let vol = Volume::new(&voxels, [32; 3])?;
//! let plain = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), FrontToBack::new(), Step::new(0.5)?)?;
//! let mut grid = [0u8; Occupancy::buffer_len([32; 3], 3)];
//! let fast = plain.with_skipping(&mut grid, 3)?;
//! assert_eq!(fast.occupancy().map(|o| o.occupied_bricks()), Some(1));
//! let ray = volsample::Ray::new([4.0, 4.0, -1.0], [0.0, 0.0, 1.0])?;
//! assert!(plain.cast(&ray).a > 0.9);
//! assert_eq!(fast.cast_counted(&ray), plain.cast_counted(&ray));
//! # Ok::<(), volsample::Error>(())
//! ```

use core::ops::Range;

use crate::each::Each;
use crate::error::Error;
use crate::mode::{
    sealed, ExtinctionWeighted, ExtinctionWeightedU8, OpacityWeighted, Preweighted, Separate,
};
use crate::ray::Ray;
use crate::volume::Volume;
use crate::voxel::{AssociatedVoxel, ExtinctionVoxel, StraightU8, StraightVoxel, Voxel};

/// The largest brick size exponent: bricks of up to `256³` voxels.
pub const MAX_BRICK_LOG2: u32 = 8;

/// Modes for which a voxel can be empty: a sample whose taps are all empty is exactly
/// [`Sample::TRANSPARENT`](crate::Sample::TRANSPARENT), whatever the weights.
///
/// Implemented where that holds by construction: `OpacityWeighted` and `Separate` on straight
/// voxels (`α = 0`: every color is weighted by an opacity that is 0), `Preweighted` on
/// associated voxels (`α = 0`, hence `C̃ = 0`), `ExtinctionWeighted` (`τ = 0`, hence
/// `C^τ = 0`) and `ExtinctionWeightedU8` (an opacity byte whose `τ` is 0). Not for
/// `PostClassified`: interpolating two scalars that classify as transparent can land on one
/// that does not.
pub trait Emptiness<V: Voxel>: sealed::Sealed {
    /// Whether `v` contributes nothing wherever it is a tap.
    fn is_empty(&self, v: &V) -> bool;
}

impl<V: StraightVoxel> Emptiness<V> for OpacityWeighted {
    #[inline]
    fn is_empty(&self, v: &V) -> bool {
        v.straight::<f32>().1 == 0.0
    }
}

impl<V: StraightVoxel> Emptiness<V> for Separate {
    #[inline]
    fn is_empty(&self, v: &V) -> bool {
        v.straight::<f32>().1 == 0.0
    }
}

impl<V: AssociatedVoxel> Emptiness<V> for Preweighted {
    #[inline]
    fn is_empty(&self, v: &V) -> bool {
        v.associated::<f32>().1 == 0.0
    }
}

impl<V: ExtinctionVoxel> Emptiness<V> for ExtinctionWeighted {
    #[inline]
    fn is_empty(&self, v: &V) -> bool {
        v.extinction::<f32>().1 == 0.0
    }
}

impl Emptiness<StraightU8> for ExtinctionWeightedU8<'_> {
    #[inline]
    fn is_empty(&self, v: &StraightU8) -> bool {
        self.table().tau(v.0[3]) == 0.0
    }
}

/// How a ray marcher tests for empty space, chosen by type: [`NoSkip`] (the default, no test
/// and no code) or an [`Occupancy`] grid. Sealed.
pub trait Skipping: sealed::Sealed + Copy + core::fmt::Debug {
    /// Whether the sample at `pos` reads only empty voxels.
    fn empty(&self, pos: [f32; 3]) -> bool;

    /// The samples `j` of a ray's samples `t_first + j·d`, `j < n` (`samples` is
    /// `(t_first, n)`), outside which every sample is [`empty`](Self::empty): `0..n` for
    /// [`NoSkip`], [`Occupancy::occupied_samples`] for a grid.
    #[doc(hidden)]
    #[inline(always)]
    fn occupied(&self, ray: &Ray, samples: (f32, u32), d: f32) -> Range<u32> {
        let _ = (ray, d);
        0..samples.1
    }

    /// `false` for [`NoSkip`], whose [`empty`](Self::empty) is always `false`.
    #[doc(hidden)]
    const SKIPS: bool = true;
}

/// No empty-space skipping: the marchers' default.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoSkip;

impl sealed::Sealed for NoSkip {}

impl Skipping for NoSkip {
    const SKIPS: bool = false;

    #[inline(always)]
    fn empty(&self, _pos: [f32; 3]) -> bool {
        false
    }
}

impl sealed::Sealed for Occupancy<'_> {}

impl Skipping for Occupancy<'_> {
    #[inline(always)]
    fn empty(&self, pos: [f32; 3]) -> bool {
        self.is_empty_at(pos)
    }

    #[inline(always)]
    fn occupied(&self, ray: &Ray, samples: (f32, u32), d: f32) -> Range<u32> {
        self.occupied_samples(ray, samples, d)
    }
}

/// A built occupancy grid over a caller's buffer: one byte per brick, 1 where the brick (with
/// its apron) holds a non-empty voxel.
#[derive(Debug, Clone, Copy)]
pub struct Occupancy<'g> {
    flags: &'g [u8],
    dims: [usize; 3],
    bricks: [usize; 3],
    log2: u32,
}

/// Bricks along an axis of `n` voxels: `⌈n / 2^log2⌉`.
const fn bricks_along(n: usize, log2: u32) -> usize {
    let b = 1usize << log2;
    n / b + if n % b == 0 { 0 } else { 1 }
}

impl<'g> Occupancy<'g> {
    /// Bytes of buffer a grid over `dims` with bricks of `2^log2` voxels needs (saturating at
    /// `usize::MAX`; 0 for an unusable `log2`).
    pub const fn buffer_len(dims: [usize; 3], log2: u32) -> usize {
        if log2 > MAX_BRICK_LOG2 {
            return 0;
        }
        let [x, y, z] = dims;
        let (x, y, z) = (
            bricks_along(x, log2),
            bricks_along(y, log2),
            bricks_along(z, log2),
        );
        match x.checked_mul(y) {
            Some(xy) => match xy.checked_mul(z) {
                Some(n) => n,
                None => usize::MAX,
            },
            None => usize::MAX,
        }
    }

    /// Builds the grid of `vol` for `mode` into `buffer` (its first
    /// [`buffer_len`](Self::buffer_len) bytes).
    ///
    /// # Errors
    /// [`Error::InvalidBrickSize`] unless `log2 ≤` [`MAX_BRICK_LOG2`];
    /// [`Error::OutputLengthMismatch`] if `buffer` is shorter than needed.
    pub fn build<V: Voxel, M: Emptiness<V>>(
        vol: &Volume<'_, V>,
        mode: &M,
        log2: u32,
        buffer: &'g mut [u8],
    ) -> Result<Self, Error> {
        if log2 > MAX_BRICK_LOG2 {
            return Err(Error::InvalidBrickSize);
        }
        let dims = vol.dims();
        let need = Self::buffer_len(dims, log2);
        let actual = buffer.len();
        let flags = buffer.get_mut(..need).ok_or(Error::OutputLengthMismatch {
            expected: need,
            actual,
        })?;
        flags.fill(0);
        let bricks = dims.each(|n| bricks_along(n, log2));
        let [bx, by, _] = bricks;
        // The bricks whose apron range `[b·B − 1, b·B + B + 1]` holds voxel `v`:
        // `⌈(v − B − 1)/B⌉ ..= ⌊(v + 1)/B⌋`, i.e. `(v − 2)/B ..= (v + 1)/B` (clipped).
        let range = |v: usize, nb: usize| {
            let lo = v.saturating_sub(2) >> log2;
            let hi = ((v + 1) >> log2).min(nb - 1);
            lo..=hi
        };
        for (k, v) in vol.data().iter().enumerate() {
            if mode.is_empty(v) {
                continue;
            }
            let [nx, ny, _] = dims;
            let (x, y, z) = (k % nx, (k / nx) % ny, k / (nx * ny));
            for cz in range(z, bricks[2]) {
                for cy in range(y, by) {
                    for cx in range(x, bx) {
                        if let Some(f) = flags.get_mut(cx + bx * (cy + by * cz)) {
                            *f = 1;
                        }
                    }
                }
            }
        }
        Ok(Self {
            flags,
            dims,
            bricks,
            log2,
        })
    }

    /// Brick size exponent: bricks of `2^log2` voxels per axis.
    pub const fn brick_log2(&self) -> u32 {
        self.log2
    }

    /// Bricks per axis.
    pub const fn bricks(&self) -> [usize; 3] {
        self.bricks
    }

    /// The volume dimensions the grid was built for.
    pub const fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// How many bricks hold a non-empty voxel (in their apron range).
    pub fn occupied_bricks(&self) -> usize {
        self.flags.iter().filter(|&&f| f != 0).count()
    }

    /// Whether a sample at `pos` (voxel units) reads only empty voxels, for every filter of
    /// this crate. NaN coordinates read as 0, as the filters' clamps do.
    #[inline(always)]
    pub fn is_empty_at(&self, pos: [f32; 3]) -> bool {
        self.brick_empty(self.brick_of(pos))
    }

    /// The brick a sample at `pos` floors into, per axis, after clamping into the grid.
    #[inline(always)]
    fn brick_of(&self, [x, y, z]: [f32; 3]) -> [usize; 3] {
        let [nx, ny, nz] = self.dims;
        // `as usize` truncates toward zero and saturates (negatives and NaN to 0): for
        // `x ≥ 0` it is `⌊x⌋`, and for `x < 0` the clamped floor is 0 either way.
        let cell = |x: f32, n: usize| (x as usize).min(n - 1) >> self.log2;
        [cell(x, nx), cell(y, ny), cell(z, nz)]
    }

    /// Whether brick `[cx, cy, cz]` is empty.
    #[inline(always)]
    fn brick_empty(&self, [cx, cy, cz]: [usize; 3]) -> bool {
        let [bx, by, _] = self.bricks;
        // Out of range cannot happen for a grid built over these dims; reading it as
        // occupied keeps the marcher exact if it ever did.
        matches!(self.flags.get(cx + bx * (cy + by * cz)), Some(0))
    }

    /// The samples `lo..hi` of a ray outside which every sample is empty
    /// ([`is_empty_at`](Self::is_empty_at)): the ray's samples are at `ray.at(t_first + j·d)`
    /// for `j < n`, with `samples = (t_first, n)`, the positions a marcher computes; `lo` is
    /// the first sample in an occupied brick and `hi − 1` the last (`n..n` if there is none).
    /// A marcher that starts at `lo` and stops after `hi − 1` composites exactly what it
    /// would have composited from 0 to `n`: the samples it leaves out are transparent.
    ///
    /// It walks brick by brick, from each end: where the ray leaves an empty brick is
    /// estimated in `f32`, and the jump is taken only once the sample it lands on is found in
    /// the same brick. That suffices: every operation of `t_first + j·d` and of
    /// [`Ray::at`](crate::Ray::at) is monotone in `j` (rounding included), and so is the
    /// brick along each axis, so two samples in one brick have only samples of that brick
    /// between them. A jump that fails is halved, down to one sample.
    ///
    /// ```
    /// use volsample::skip::Occupancy;
    /// use volsample::{OpacityWeighted, Ray, StraightU8, Volume};
    /// // 32³ of air with one opaque voxel at (4, 4, 20).
    /// let mut voxels = [StraightU8([0; 4]); 32 * 32 * 32];
    /// voxels[4 + 32 * (4 + 32 * 20)] = StraightU8([255; 4]);
    /// let vol = Volume::new(&voxels, [32; 3])?;
    /// let mut grid = [0u8; Occupancy::buffer_len([32; 3], 3)];
    /// let occ = Occupancy::build(&vol, &OpacityWeighted, 3, &mut grid)?;
    /// let ray = Ray::new([4.0, 4.0, -1.0], [0.0, 0.0, 1.0])?;
    /// // Samples at z = 0.5 j: the brick z ∈ [16, 24) is the only occupied one.
    /// let (t_first, n) = (1.0, 64);
    /// let r = occ.occupied_samples(&ray, (t_first, n), 0.5);
    /// assert_eq!(r, 32..48);
    /// # Ok::<(), volsample::Error>(())
    /// ```
    pub fn occupied_samples(&self, ray: &Ray, (t_first, n): (f32, u32), d: f32) -> Range<u32> {
        let t = |j: u32| t_first + j as f32 * d;
        let walk = Walk {
            grid: self,
            ray,
            t: &t,
            d,
        };
        let mut lo = 0;
        while lo < n {
            let b = self.brick_of(ray.at(t(lo)));
            if !self.brick_empty(b) {
                break;
            }
            lo += 1 + walk.run(b, lo, n - 1 - lo, true);
        }
        let mut hi = n;
        while hi > lo {
            let j = hi - 1;
            let b = self.brick_of(ray.at(t(j)));
            if !self.brick_empty(b) {
                break;
            }
            hi = j - walk.run(b, j, j - lo, false);
        }
        lo..hi
    }
}

/// A ray's walk over the bricks of a grid ([`Occupancy::occupied_samples`]).
struct Walk<'a, 'g, T: Fn(u32) -> f32> {
    grid: &'a Occupancy<'g>,
    ray: &'a Ray,
    /// The distance of sample `j`.
    t: &'a T,
    d: f32,
}

impl<T: Fn(u32) -> f32> Walk<'_, '_, T> {
    /// How many samples after sample `j` (`forward`) or before it lie in brick `b` too, where
    /// sample `j` does, at most `room`: estimated from where the ray crosses the brick's next
    /// face in that direction, then halved until the sample it lands on is in `b` (0 at
    /// worst: no jump).
    fn run(&self, b: [usize; 3], j: u32, room: u32, forward: bool) -> u32 {
        let (o, dir) = (self.ray.origin(), self.ray.dir());
        let size = (1u64 << self.grid.log2) as f32;
        let tj = (self.t)(j);
        let mut steps = f32::INFINITY;
        for (((&o, &v), &c), &nb) in o.iter().zip(&dir).zip(&b).zip(&self.grid.bricks) {
            if v == 0.0 {
                continue;
            }
            // The face crossed next: below the brick where the walk goes down the axis, above
            // it where it goes up; none past the grid's first and last bricks, into which every
            // position beyond them clamps.
            let face = if (v > 0.0) == forward {
                if c + 1 >= nb {
                    continue;
                }
                (c + 1) as f32 * size
            } else {
                if c == 0 {
                    continue;
                }
                c as f32 * size
            };
            let t_face = (face - o) / v;
            let s = if forward { t_face - tj } else { tj - t_face } / self.d;
            steps = steps.min(s);
        }
        // One sample short of the estimate, in `0..=room` (NaN to 0).
        let mut k = (steps - 1.0).max(0.0).min(room as f32) as u32;
        while k > 0 {
            let jk = if forward { j + k } else { j - k };
            if self.grid.brick_of(self.ray.at((self.t)(jk))) == b {
                return k;
            }
            k /= 2;
        }
        0
    }
}
