//! A whole mipmap chain in one caller-provided buffer.

use super::level::filter_level;
use super::{chain_len, level_count, level_dims, level_offset, voxel_count};
use super::{Filter4, Method, MipLevel, MAX_LEVELS};
use crate::error::Error;
use crate::volume::Volume;
use crate::voxel::Voxel;

/// Every level of a mipmap chain: level 0 (the caller's volume) and the coarser levels written
/// by [`build_chain`].
#[derive(Debug, Clone)]
pub struct MipChain<'a, V> {
    base: Volume<'a, V>,
    coarse: heapless::Vec<Volume<'a, V>, { MAX_LEVELS - 1 }>,
}

impl<'a, V: Voxel> MipChain<'a, V> {
    /// The number of levels, level 0 included ([`level_count`] of the base dimensions).
    pub fn len(&self) -> usize {
        self.coarse.len() + 1
    }

    /// Always `false`: a chain has at least level 0.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Level 0, the caller's volume.
    pub fn base(&self) -> Volume<'a, V> {
        self.base
    }

    /// Level `level` (0 is the base volume), or `None` past the last (`1 × 1 × 1`) level.
    pub fn level(&self, level: u32) -> Option<MipLevel<'a, V>> {
        let v = match level.checked_sub(1) {
            None => self.base,
            Some(i) => *self.coarse.get(usize::try_from(i).ok()?)?,
        };
        Some(MipLevel::new(v, level))
    }

    /// The level whose voxels are closest to `footprint` fine voxels wide (a minification of
    /// that size): `⌊log₂ footprint + ½⌋`, clamped to the chain; level 0 for a footprint below
    /// `√2` and for NaN.
    pub fn level_for_footprint(&self, footprint: f32) -> MipLevel<'a, V> {
        let l = libm::floorf(libm::log2f(footprint.max(1.0)) + 0.5);
        // `as` saturates and maps NaN to 0.
        let l = (l as usize).min(self.coarse.len());
        match l.checked_sub(1).and_then(|i| self.coarse.get(i)) {
            Some(v) => MipLevel::new(*v, l as u32),
            None => MipLevel::new(self.base, 0),
        }
    }
}

/// Builds the whole chain below `base` into `out`: level 1 from `base`, level 2 from level 1,
/// … down to `1 × 1 × 1`, level `ℓ` at [`level_offset`]`(dims, ℓ)` with
/// [`level_dims`]`(dims, ℓ)`. Each level is [`downsample_level`](super::downsample_level) of
/// the one before (bit-identical), with the base's reference distance in its own voxels.
///
/// A `1 × 1 × 1` base gives a chain of level 0 only and needs an empty buffer.
///
/// ```
/// use volsample::downsample::{build_chain, chain_len, ExtinctionBased, Filter4};
/// use volsample::{ExtinctionF32, Volume};
/// let v = ExtinctionF32 { c_tau: [0.5, 0.25, 0.0], tau: 0.5 };
/// let base = [v; 6 * 5 * 3];
/// let mut out = [ExtinctionF32::default(); chain_len([6, 5, 3])];
/// let chain = build_chain(ExtinctionBased, Filter4::quadratic(), Volume::new(&base, [6, 5, 3])?, &mut out)?;
/// assert_eq!(chain.len(), 4);
/// let top = chain.level(3).unwrap();
/// assert_eq!(top.volume().dims(), [1, 1, 1]);
/// // Constant data stays constant; τ per level voxel doubles per level.
/// assert_eq!(top.volume().data()[0], ExtinctionF32 { c_tau: [4.0, 2.0, 0.0], tau: 4.0 });
/// # Ok::<(), volsample::Error>(())
/// ```
///
/// Error bound: each level as [`downsample_level`](super::downsample_level), compounded as the
/// method states.
///
/// # Errors
/// [`Error::OutputLengthMismatch`] unless `out.len() == `[`chain_len`]`(base.dims())`.
pub fn build_chain<'a, M: Method>(
    method: M,
    filter: Filter4,
    base: Volume<'a, M::Voxel>,
    out: &'a mut [M::Voxel],
) -> Result<MipChain<'a, M::Voxel>, Error> {
    let _ = method;
    let dims = base.dims();
    let expected = chain_len(dims);
    if out.len() != expected {
        return Err(Error::OutputLengthMismatch {
            expected,
            actual: out.len(),
        });
    }
    let count = level_count(dims);
    let mismatch = Error::OutputLengthMismatch {
        expected,
        actual: out.len(),
    };
    // Write every level; level ℓ ≥ 2 reads level ℓ − 1 from the part of `out` already written.
    for level in 1..count {
        let off = level_offset(dims, level);
        let n = voxel_count(level_dims(dims, level));
        let (done, todo) = out.split_at_mut_checked(off).ok_or(mismatch)?;
        let dst = todo.get_mut(..n).ok_or(mismatch)?;
        if level == 1 {
            filter_level::<M>(filter, base.data(), dims, dst)?;
        } else {
            let prev = done.get(level_offset(dims, level - 1)..).ok_or(mismatch)?;
            filter_level::<M>(filter, prev, level_dims(dims, level - 1), dst)?;
        }
    }
    let out: &'a [M::Voxel] = out;
    let mut coarse = heapless::Vec::new();
    for level in 1..count {
        let off = level_offset(dims, level);
        let ld = level_dims(dims, level);
        let data = out.get(off..off + voxel_count(ld)).ok_or(mismatch)?;
        let vol = Volume::new(data, ld)?.with_reference_distance(base.reference_distance())?;
        coarse.push(vol).map_err(|_| Error::DimensionTooLarge)?;
    }
    Ok(MipChain { base, coarse })
}
