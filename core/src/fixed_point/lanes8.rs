//! What the eight-lane integer kernel (`arch::avx2`, the `OpacityWeighted` trilinear pipeline
//! at `F = 8`) needs to know of an integer mode, as types: the mode names itself in
//! [`IntMode::lanes8`](super::IntMode::lanes8), so that no flag routes to the kernel.
//!
//! Not part of the public API: the traits are public only so that the public, sealed
//! [`IntMode`](super::IntMode) can name them, and their module is private.

use crate::mode::LaneVoxel;
use crate::voxel::Voxel;

/// An integer mode that the eight-lane kernel computes.
pub trait IntLaneMode {
    /// The voxel format the kernel reads.
    type Voxel: LaneVoxel;

    /// `data` as the kernel's voxel format ([`LaneVoxel::retype`]).
    #[inline(always)]
    fn voxels<V: Voxel>(data: &[V]) -> Option<&[Self::Voxel]> {
        Self::Voxel::retype(data)
    }
}

/// A computation over the lane kernel of an integer mode
/// ([`IntMode::lanes8`](super::IntMode::lanes8)).
pub trait IntLaneVisitor {
    /// Its result.
    type Out;
    /// Runs it for the mode `mode`, of type `K`.
    fn visit<K: IntLaneMode>(self, mode: &K) -> Self::Out;
}
