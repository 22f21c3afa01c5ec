//! The fuzz target `marcher_packets` holds the `f32` storage modes' images against the f64
//! reference renderer (`marcher_checks::against_reference`): every mode and filter/order it
//! maps to compares pixels (the oracle is not vacuous) and passes on a plain volume.

use volsample_host::marcher_checks::{against_reference, marcher_packets, MarcherInput};

/// A 4×4×4 volume of varied colours and opacities, a camera looking along `z` at its centre.
fn input(mode: u8, filter: u8, step: u8) -> MarcherInput {
    MarcherInput {
        dims: [3, 3, 3],
        mode,
        filter,
        // d′ = 0.25 + 96/128 = 1.
        d_ref: 96,
        step,
        phase: 64,
        stop: 250,
        rays: [[128, 128, 128, 140, 120, 255]; 9],
        camera: [128, 128, 128, 130, 126, 255],
        voxels: (0..=255u8).map(|b| b.wrapping_mul(37)).collect(),
    }
}

#[test]
fn every_float_mode_and_filter_is_compared_with_the_reference() {
    for mode in 4..8 {
        for filter in 0..5 {
            // Step 0.35 (corrected) and d = d′ = 1 (0.05 + 152/160).
            for step in [48, 152] {
                let inp = input(mode, filter, step);
                let compared = against_reference(&inp)
                    .unwrap_or_else(|e| panic!("mode {mode} filter {filter} step {step}: {e}"));
                // 5 × 3 pixels; at most a few are left out as ambiguous.
                assert!(
                    compared >= 12,
                    "mode {mode} filter {filter} step {step}: {compared} pixels compared"
                );
                marcher_packets(&inp)
                    .unwrap_or_else(|e| panic!("mode {mode} filter {filter}: {e}"));
            }
        }
    }
}

#[test]
fn the_byte_storage_modes_have_no_reference_image() {
    for mode in 0..4 {
        assert_eq!(against_reference(&input(mode, 0, 48)), Ok(0));
    }
}
