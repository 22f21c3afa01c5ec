//! Sampling one level of a mipmap chain in level-0 (fine) units.

use crate::each::Each;
use crate::filter::Filter;
use crate::mode::Mode;
use crate::opacity::correct;
use crate::render::Step;
use crate::sample::Sample;
use crate::volume::Volume;
use crate::voxel::Voxel;

/// One level of a mipmap chain: its volume (in its own voxel units) and its number `ℓ`, with
/// the conversions from level-0 units (see the [module docs](super)).
#[derive(Debug, Clone, Copy)]
pub struct MipLevel<'a, V> {
    volume: Volume<'a, V>,
    level: u32,
}

impl<'a, V: Voxel> MipLevel<'a, V> {
    /// Level `level` with volume `volume` (as [`downsample_level`](super::downsample_level) or
    /// [`build_chain`](super::build_chain) made it). A `level` of 128 or more is read as 127
    /// (`2^ℓ` must fit in `f32`).
    pub fn new(volume: Volume<'a, V>, level: u32) -> Self {
        Self {
            volume,
            level: level.min(127),
        }
    }

    /// The level's volume, in its own voxel units.
    pub fn volume(&self) -> Volume<'a, V> {
        self.volume
    }

    /// `ℓ`.
    pub fn level(&self) -> u32 {
        self.level
    }

    /// `2^ℓ`: fine voxels per level voxel (exact in `f32`).
    pub fn scale(&self) -> f32 {
        libm::ldexpf(1.0, self.level as i32)
    }

    /// The level position of the level-0 position `p`: `(p + ½)/2^ℓ − ½` per axis.
    ///
    /// Error bound: two roundings, within `ε·(|p|/2^ℓ + 1)` (`ε = 2⁻²³`).
    pub fn to_level(&self, p: [f32; 3]) -> [f32; 3] {
        let inv = libm::ldexpf(1.0, -(self.level as i32));
        p.each(|x| (x + 0.5) * inv - 0.5)
    }

    /// The level-0 position of the level position `q`: `(q + ½)·2^ℓ − ½` per axis.
    pub fn to_fine(&self, q: [f32; 3]) -> [f32; 3] {
        let s = self.scale();
        q.each(|x| (x + 0.5) * s - 0.5)
    }

    /// The level's reference distance in level-0 voxels: `2^ℓ·d′`.
    pub fn reference_distance_fine(&self) -> f32 {
        self.volume.reference_distance() * self.scale()
    }

    /// The level's step for a step of `step.d()` level-0 voxels: `d/2^ℓ` level voxels (the
    /// phase is kept). `None` if it underflows to 0.
    pub fn level_step(&self, step: Step) -> Option<Step> {
        let d = step.d() / self.scale();
        Step::new(d).ok()?.with_phase(step.phase()).ok()
    }

    /// The associated sample of this level at the level-0 position `pos`, for a segment of
    /// `step.d()` level-0 voxels, with `mode` and the reconstruction filter `F` (for example
    /// [`Trilinear`](crate::Trilinear) or [`TriquadraticBSpline`](crate::TriquadraticBSpline)).
    ///
    /// The position is converted with [`to_level`](Self::to_level) and the step to
    /// `d/2^ℓ` level voxels; extinction-based modes integrate over it, opacity-based modes
    /// are corrected from the level's reference distance `d′` (level voxels, i.e. `2^ℓ·d′`
    /// fine) to it, and skip the correction when the two are equal.
    ///
    /// Error bound: that of `mode` with `F` on the level's data (the sampling modes' doc
    /// comments), plus the position rounding of [`to_level`](Self::to_level) times the
    /// sample's gradient.
    pub fn sample<M: Mode<V>, F: Filter>(
        &self,
        mode: &M,
        _filter: F,
        pos: [f32; 3],
        step: Step,
    ) -> Sample {
        let q = self.to_level(pos);
        let d = step.d() / self.scale();
        let i = F::interpolate(mode, &self.volume, q);
        let s = mode.finish(i, d);
        let ratio = d / self.volume.reference_distance();
        if M::OPACITY_BASED && ratio != 1.0 {
            correct(s, ratio)
        } else {
            s
        }
    }
}
