//! The packet kernels against single rays, and single rays against one sample at a time
//! (see `fast_paths.rs`), for the modes over byte voxels: `OpacityWeighted`, `Separate`,
//! `Preweighted`, `ExtinctionWeightedU8`, and empty-space skipping. The modes over `f32`
//! voxels are in `fast_paths_packets_f32.rs` (a binary of its own, compiled beside this one).
//!
//! `VOLSAMPLE_FAST_PATH_CASES` sets the number of random cases (default 2000; these tests
//! run an eighth of them).

mod fast_paths_common;
use fast_paths_common::*;

use volsample::composite::Termination;
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::{OpacityWeighted, Preweighted, RayMarcher, Sample, Separate, Trilinear};

/// The packet kernels (four rays in [`volsample::lanes::F32x4`] lanes, eight in AVX2 lanes)
/// are bit-identical to single rays, and single rays (consecutive samples in lanes, front to
/// back) to one sample at a time, for every mode over byte voxels, filter, order and stage:
/// opacity correction, early termination, a background, empty-space skipping, rays that
/// miss or end early.
#[test]
fn packets_of_byte_voxels_are_bit_identical_to_single_rays() {
    assert_best_isa_detected();
    let mut grid = vec![0u8; 4096];
    packet_cases(|c| {
        let (v8, va) = (c.volume(&c.u8s), c.volume(&c.assoc));
        all_filters(c, v8, OpacityWeighted, "OW u8");
        all_filters(c, v8, Separate, "Separate u8");
        all_filters(c, va, Preweighted, "Preweighted u8");
        let taus = TauTable::new(c.d_ref).unwrap();
        all_filters(c, v8, ExtinctionWeightedU8::new(&taus), "Extinction u8");

        // Empty-space skipping: lanes skip samples independently.
        let m = RayMarcher::new(v8, OpacityWeighted, Trilinear::new(), c.stop, c.step).unwrap();
        let skip = m.with_skipping(&mut grid, [0, 1, 2][c.case % 3]).unwrap();
        check_packets(&skip, &c.rays, "OW u8 skipping");
        let occ = *skip.occupancy().unwrap();
        let (done, empty) = (|a| c.stop.0.done(a), |p| occ.is_empty_at(p));
        let t = Sample::TRANSPARENT;
        check_sample_lanes(&skip, &c.rays, done, empty, t, "OW u8 skipping");
    });
}
