//! The kernel-family fuzz checks (`volsample_host::kernel_checks`) on hand-made inputs: every
//! mode, filter and `F` of `int_marcher`, the named and extreme filters of `downsample`, the
//! float filters at positions inside and outside the volume (`filters`) and the pre-passes on
//! extreme fields (`classify`) pass, and their comparisons ran (the checked-in corpora replay in `int_corpus_replay.rs`).

use volsample_host::kernel_checks::{
    classify, downsample, filters, ClassifyInput, DownsampleInput, FilterInput,
};
#[cfg(feature = "marcher-checks")]
use volsample_host::kernel_checks::{int_marcher, MarchMode, MarcherInput, RayInput};

/// A small deterministic byte stream.
fn bytes(seed: u64, n: usize) -> Vec<[u8; 4]> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 32).to_le_bytes()[..4].try_into().unwrap()
        })
        .collect()
}

#[cfg(feature = "marcher-checks")]
fn rays() -> Vec<RayInput> {
    let mut out = vec![
        // Down z through the middle, along a diagonal, grazing an edge, missing.
        RayInput {
            origin: [128, 96, -256],
            dir: [0, 0, 256],
            bits: None,
        },
        RayInput {
            origin: [-64, -64, -64],
            dir: [256, 200, 150],
            bits: None,
        },
        RayInput {
            origin: [-32, 0, -256],
            dir: [0, 0, 256],
            bits: None,
        },
        RayInput {
            origin: [-2000, 0, 0],
            dir: [0, 256, 0],
            bits: None,
        },
        // From inside, backwards; raw bits of an odd direction.
        RayInput {
            origin: [100, 100, 100],
            dir: [-30, -256, 7],
            bits: None,
        },
        RayInput {
            origin: [0; 3],
            dir: [0; 3],
            bits: Some([
                1.3f32.to_bits(),
                (-0.25f32).to_bits(),
                2.0f32.to_bits(),
                0.1f32.to_bits(),
                1.0f32.to_bits(),
                (-0.01f32).to_bits(),
            ]),
        },
    ];
    // Nine more parallel rays: a packet of eight and one more for `cast_rays`.
    for i in 0..9 {
        out.push(RayInput {
            origin: [16 * i, 40, -300],
            dir: [3, 5, 256],
            bits: None,
        });
    }
    out
}

#[cfg(feature = "marcher-checks")]
#[test]
fn int_marcher_every_mode_filter_and_frac_bits() {
    let mut total = 0;
    for (k, mode) in [
        MarchMode::OpacityWeighted,
        MarchMode::Separate,
        MarchMode::Preweighted,
        MarchMode::Extinction,
    ]
    .into_iter()
    .enumerate()
    {
        for trilinear in [false, true] {
            for frac_sel in 0..3u8 {
                for (d_ref, a_stop) in [(0u8, 0u16), (9, 40000), (30, 1)] {
                    let inp = MarcherInput {
                        dims: [4, 3, 5],
                        mode,
                        trilinear,
                        frac_sel,
                        step: 11 + 7 * frac_sel,
                        phase: 77,
                        d_ref,
                        a_stop,
                        background: [1000, 2000, 3000, 5000],
                        voxels: bytes(k as u64 * 7 + u64::from(frac_sel), 37),
                        rays: rays(),
                    };
                    let n = int_marcher(&inp).unwrap_or_else(|e| panic!("{e}"));
                    assert!(n > 0, "{inp:?}: no sample compared");
                    total += n;
                }
            }
        }
    }
    println!("int_marcher: {total} samples compared");
}

#[test]
fn downsample_named_and_extreme_filters() {
    let mut total = 0;
    for (i, a) in [0.0f32, 0.125, 0.2, 0.25, 0.5, 1e-30, 0.4999]
        .into_iter()
        .enumerate()
    {
        for (a_raw, dims) in [(0u16, [4u8, 6, 2]), (1, [8, 0, 3]), (32767, [0, 0, 0])] {
            let inp = DownsampleInput {
                dims,
                a_bits: a.to_bits(),
                a_raw,
                tau_sel: i as u8,
                depth_shift: 18 - i as u8,
                voxels: bytes(i as u64, 50),
            };
            let n = downsample(&inp).unwrap_or_else(|e| panic!("{e}"));
            assert!(n > 0 || dims == [0, 0, 0], "{inp:?}: nothing compared");
            total += n;
        }
    }
    // An `a` the API refuses falls back to one it accepts.
    for bits in [f32::NAN.to_bits(), (-0.1f32).to_bits(), 0.75f32.to_bits()] {
        let inp = DownsampleInput {
            dims: [2, 2, 2],
            a_bits: bits,
            voxels: bytes(9, 27),
            ..Default::default()
        };
        total += downsample(&inp).unwrap_or_else(|e| panic!("{e}"));
    }
    println!("downsample: {total} coarse voxels compared");
}

#[test]
fn filters_inside_outside_and_far() {
    let mut total = 0;
    for (i, pos) in [[0u16, 0, 0], [30000, 20000, 65535], [12345, 54321, 32768]]
        .into_iter()
        .enumerate()
    {
        for pos_bits in [None, Some([1e6f32, -3.5, 0.25].map(f32::to_bits))] {
            let inp = FilterInput {
                dims: [2 + i as u8, 4, 1],
                voxels: bytes(i as u64, 30)
                    .iter()
                    .map(|b| b.map(|x| u16::from(x) * 257))
                    .collect(),
                scalars: vec![0, 65535, 30000, 1],
                tf: vec![
                    [100, 65535, 0, 0, 40000],
                    [30000, 0, 65535, 0, 65535],
                    [0; 5],
                ],
                d_ref: 1000 * i as u16,
                d: 20000,
                pos,
                pos_bits,
            };
            total += filters(&inp).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    assert!(total >= 6 * 12);
    println!("filters: {total} samples compared");
}

#[test]
fn classify_extreme_fields_and_refused_parameters() {
    let mut total = 0;
    let fields = [
        vec![0u32],
        vec![
            1.0f32.to_bits(),
            3.0f32.to_bits(),
            (-2.0f32).to_bits(),
            0.5f32.to_bits(),
        ],
        vec![
            f32::MAX.to_bits(),
            (-f32::MAX).to_bits(),
            1,
            0x8000_0001,
            f32::NAN.to_bits(),
        ],
    ];
    for (i, field) in fields.into_iter().enumerate() {
        for iso in [
            [1.0f32, 0.8, 0.5].map(f32::to_bits),
            [0.0f32, 2.0, -1.0].map(f32::to_bits),
        ] {
            let inp = ClassifyInput {
                dims: [3, 2 + i as u8, 1],
                field: field.clone(),
                iso,
                light: [1.0f32, -2.0, 0.5, 0.1, 0.9].map(f32::to_bits),
                tf: vec![
                    [(-1.0f32).to_bits(), 0, 65535, 0, 0],
                    [2.0f32.to_bits(), 65535, 0, 30000, 65535],
                ],
            };
            total += classify(&inp).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    // A zero light direction is refused and replaced.
    total += classify(&ClassifyInput {
        dims: [1, 1, 1],
        light: [0; 5],
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(total > 0);
    println!("classify: {total} values compared");
}
