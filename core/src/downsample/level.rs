//! One pyramid level: the separable 4-tap filter over a whole volume.

use super::{level_dims, voxel_count, Filter4, Method};
use crate::each::Each;
use crate::error::Error;
use crate::volume::Volume;
use crate::voxel::Voxel;

/// Downsamples `src` by one level with `filter` and `method` into `dst`, and returns `dst` as
/// a volume of [`level_dims`]`(src.dims(), 1)` with the same reference distance (in its own,
/// doubled, voxels; see the [module docs](super)).
///
/// Coarse voxel `(X, Y, Z)` is `Σ w_i w_j w_k v(2X − 1 + i, 2Y − 1 + j, 2Z − 1 + k)` over
/// `i, j, k ∈ 0..4` with `w = (a, b, b, a)` and clamp-to-edge reads, evaluated separably
/// (x, then y, then z, each with [`Filter4::combine`]) and finished by the method. Computed per
/// coarse voxel (64 reads, 21 combinations), it needs no scratch buffer and gives results
/// bit-identical to three separate passes.
///
/// Error bound: the method's ([`OpacityBased`](super::OpacityBased),
/// [`ExtinctionBased`](super::ExtinctionBased)); the three filter passes give each filtered
/// channel within `7.5ε·max` (`ε = 2⁻²³`) of exact filtering of the stored input.
///
/// # Errors
/// [`Error::OutputLengthMismatch`] unless `dst.len()` is the coarse voxel count.
pub fn downsample_level<'o, M: Method>(
    _method: M,
    filter: Filter4,
    src: &Volume<'_, M::Voxel>,
    dst: &'o mut [M::Voxel],
) -> Result<Volume<'o, M::Voxel>, Error> {
    let out_dims = filter_level::<M>(filter, src.data(), src.dims(), dst)?;
    Volume::new(&*dst, out_dims)?.with_reference_distance(src.reference_distance())
}

/// The four clamped fine indices `2j − 1 … 2j + 2` of coarse index `j` on an axis of `n`.
#[inline(always)]
fn axis_taps(j: usize, n: usize) -> [usize; 4] {
    let last = n.saturating_sub(1);
    let c = j.saturating_mul(2);
    [
        c.saturating_sub(1).min(last),
        c.min(last),
        c.saturating_add(1).min(last),
        c.saturating_add(2).min(last),
    ]
}

/// The kernel behind [`downsample_level`] and the chain: reads `src` (dimensions `dims`,
/// already validated), writes `dst`, returns the coarse dimensions.
pub(crate) fn filter_level<M: Method>(
    filter: Filter4,
    src: &[M::Voxel],
    dims: [usize; 3],
    dst: &mut [M::Voxel],
) -> Result<[usize; 3], Error> {
    let out_dims = level_dims(dims, 1);
    let expected = voxel_count(out_dims);
    if dst.len() != expected {
        return Err(Error::OutputLengthMismatch {
            expected,
            actual: dst.len(),
        });
    }
    let [nx, ny, nz] = dims;
    let [ox, oy, _] = out_dims;
    let fetch = |x: usize, y: usize, z: usize| -> [f32; 4] {
        // In range by the clamps in `axis_taps` and the validated length, so `get` hits.
        let v = src
            .get(x + nx * (y + ny * z))
            .copied()
            .unwrap_or(<M::Voxel as Voxel>::TRANSPARENT);
        M::channels(v)
    };
    for (row, out_row) in dst.chunks_exact_mut(ox.max(1)).enumerate() {
        let ys = axis_taps(row % oy.max(1), ny);
        let zs = axis_taps(row / oy.max(1), nz);
        for (x, out) in out_row.iter_mut().enumerate() {
            let xs = axis_taps(x, nx);
            let planes = zs
                .each(|z| filter.combine(ys.each(|y| filter.combine(xs.each(|x| fetch(x, y, z))))));
            *out = M::finish(filter.combine(planes));
        }
    }
    Ok(out_dims)
}
