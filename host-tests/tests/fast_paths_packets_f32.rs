//! The packet kernels against single rays, and single rays against one sample at a time
//! (see `fast_paths.rs`), for the modes over `f32` voxels and scalars: `OpacityWeighted` and
//! `Separate` over `StraightF32`, `ExtinctionWeighted` over `ExtinctionF32`,
//! `PostClassified`. The modes over byte voxels are in `fast_paths_packets.rs`.
//!
//! `VOLSAMPLE_FAST_PATH_CASES` sets the number of random cases (default 2000; these tests
//! run an eighth of them).

mod fast_paths_common;
use fast_paths_common::*;

use volsample::{
    ControlPoint, ExtinctionWeighted, OpacityWeighted, PostClassified, Separate, TransferFunction,
    Volume,
};

/// As `packets_of_byte_voxels_are_bit_identical_to_single_rays` (`fast_paths_packets.rs`),
/// for every mode over `f32` voxels and scalars.
#[test]
fn packets_of_f32_voxels_are_bit_identical_to_single_rays() {
    assert_best_isa_detected();
    let tf = TransferFunction::<3>::new(&[
        ControlPoint {
            s: 0.0,
            c: [0.0; 3],
            a: 0.0,
        },
        ControlPoint {
            s: 0.4,
            c: [1.0, 0.5, 0.2],
            a: 0.3,
        },
        ControlPoint {
            s: 1.0,
            c: [1.0; 3],
            a: 0.9,
        },
    ])
    .unwrap();
    packet_cases(|c| {
        let (vf, vs) = (c.volume(&c.f32s), c.volume(&c.scalars));
        // The stored extinction needs no reference distance.
        let ve = Volume::new(&c.ext, c.dims).unwrap();
        all_filters(c, vf, OpacityWeighted, "OW f32");
        all_filters(c, vf, Separate, "Separate f32");
        all_filters(c, ve, ExtinctionWeighted, "Extinction");
        all_filters(c, vs, PostClassified::new(&tf), "PostClassified");
    });
}
