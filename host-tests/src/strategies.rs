//! proptest strategies for float cases, shared by the property tests and the error sweeps.

use proptest::prelude::*;
use volsample::{ControlPoint, Sample, StraightF32};

use crate::float_checks::FloatCase;

/// A unit-range value, with the ends `0` and `1` drawn often.
pub fn unit() -> impl Strategy<Value = f32> {
    prop_oneof![1 => Just(0.0f32), 1 => Just(1.0f32), 6 => 0.0f32..=1.0]
}

/// A straight voxel with opacity from [`unit()`].
pub fn voxel() -> impl Strategy<Value = StraightF32> {
    ([0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0], unit()).prop_map(|(c, a)| StraightF32 { c, a })
}

/// 1–5 control points with increasing `s` in `[0, 255)`.
pub fn transfer_function() -> impl Strategy<Value = Vec<ControlPoint>> {
    prop::collection::vec((0.0f32..255.0, [unit(), unit(), unit()], unit()), 1..6).prop_map(
        |mut pts| {
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            pts.dedup_by(|a, b| a.0 <= b.0 + 1e-3);
            pts.into_iter()
                .map(|(s, c, a)| ControlPoint { s, c, a })
                .collect()
        },
    )
}

prop_compose! {
    /// A volume of 1–5 voxels per axis in every storage form, with `d′` one voxel or random.
    pub fn float_case()(dims in [1usize..=5, 1usize..=5, 1usize..=5])
        (voxels in prop::collection::vec(voxel(), dims[0] * dims[1] * dims[2]),
         scalars in prop::collection::vec(0.0f32..=255.0, dims[0] * dims[1] * dims[2]),
         tf in transfer_function(),
         d_ref in prop_oneof![Just(1.0f32), 0.25f32..4.0],
         dims in Just(dims)) -> FloatCase {
        FloatCase { dims, voxels, scalars, tf, d_ref }
    }
}

prop_compose! {
    /// A case and a position in it, reaching one voxel past every face (clamp to edge).
    pub fn case_and_pos()(case in float_case())
        (pos in [-1.5f32..case.dims[0] as f32 + 0.5,
                 -1.5f32..case.dims[1] as f32 + 0.5,
                 -1.5f32..case.dims[2] as f32 + 0.5],
         case in Just(case)) -> (FloatCase, [f32; 3]) {
        (case, pos)
    }
}

/// A valid associated sample: straight color and opacity drawn independently.
pub fn sample() -> impl Strategy<Value = Sample> {
    ([0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0], unit())
        .prop_map(|(c, a)| Sample::clamped(c.map(|c| c * a), a))
}
