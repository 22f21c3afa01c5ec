//! Integer sampling kernels against their f64 models (bit for bit) and against the exact and
//! `f32` results of the same method (within the bounds of `tolerance::integer`), on random
//! inputs and on every extreme.

use volsample::fixed_point::{IntMode, IntPos, IntSampler, IntWeights, ONE};
use volsample::{
    AssociatedU8, OpacityWeighted, Preweighted, Separate, StraightU8, Trilinear, Volume,
};
use volsample_host::checks::{self, CellInput, IntKernel};

/// SplitMix64: a seeded generator so a failure reproduces (`VOLSAMPLE_SEED` overrides).
struct Rng(u64);
impl Rng {
    fn new() -> Self {
        let seed = std::env::var("VOLSAMPLE_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0x5eed_1234_u64);
        Rng(seed)
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
}

const KERNELS: [IntKernel; 3] = [
    IntKernel::OpacityWeighted,
    IntKernel::Separate,
    IntKernel::Preweighted,
];

fn iterations() -> usize {
    std::env::var("VOLSAMPLE_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000)
}

/// Worst error against the exact result, per kernel: (C̃, α).
fn worst(inputs: impl Iterator<Item = CellInput>) -> [(f64, f64); 3] {
    let mut w = [(0.0f64, 0.0f64); 3];
    for inp in inputs {
        checks::int_vs_float(&inp).unwrap_or_else(|e| panic!("{e}\ninput: {inp:?}"));
        let got = checks::sample(&inp).unwrap();
        let m = checks::model(&inp);
        let k = inp.kernel as usize;
        w[k].1 = w[k].1.max((f64::from(got.a()) - m.exact_a).abs());
        for c in 0..3 {
            w[k].0 = w[k].0.max((f64::from(got.c()[c]) - m.exact_c[c]).abs());
        }
    }
    w
}

#[test]
fn random_inputs_bit_exact_and_within_bounds() {
    let mut rng = Rng::new();
    let n = iterations();
    let inputs = (0..n).map(|i| {
        let mut voxels = [[0u8; 4]; 8];
        for v in &mut voxels {
            for b in v.iter_mut() {
                *b = rng.byte();
            }
            // Bias a quarter of the voxels to faint opacities, where rounding matters most.
            if rng.next() % 4 == 0 {
                v[3] %= 4;
            }
        }
        // Independent selectors (9 × 3 × 5 combinations in every 135 inputs): with `i % 9`,
        // `i % 3` and `i % 5` each kernel met only three of the nine `F`.
        CellInput {
            voxels,
            frac: [rng.next() as u32, rng.next() as u32, rng.next() as u32],
            frac_bits_sel: (i % 9) as u8,
            trilinear: (i / 27) % 5 != 0,
            kernel: KERNELS[(i / 9) % 3],
        }
    });
    let w = worst(inputs);
    for (k, (c, a)) in KERNELS.iter().zip(w) {
        let (bc, ba) = checks::kernel_bound(*k);
        println!("{k:?}: worst C̃ error {c:.4} LSB (bound {bc}), α {a:.4} LSB (bound {ba})");
    }
    // The bounds are nearly tight: the random inputs reach 90 % of each (80 % of Separate's
    // C̃ bound, whose three ½-LSB terms cannot all peak at once).
    for (k, (c, a)) in KERNELS.iter().zip(w) {
        let (bc, ba) = checks::kernel_bound(*k);
        let reach = if *k == IntKernel::Separate { 0.8 } else { 0.9 };
        assert!(
            c > reach * bc && a > 0.9 * ba,
            "{k:?}: bound {bc}/{ba} far from observed {c}/{a}"
        );
    }
}

#[test]
fn extremes_bit_exact_and_within_bounds() {
    let mut rng = Rng::new();
    let patterns: Vec<[[u8; 4]; 8]> = vec![
        [[0; 4]; 8],
        [[255; 4]; 8],
        [[255, 255, 255, 1]; 8],
        [[128, 127, 1, 1]; 8],
        std::array::from_fn(|i| if i % 2 == 0 { [255; 4] } else { [0; 4] }),
        std::array::from_fn(|i| {
            if i == 7 {
                [255, 0, 255, 1]
            } else {
                [0, 255, 0, 0]
            }
        }),
        std::array::from_fn(|i| if i == 0 { [255; 4] } else { [255, 0, 0, 1] }),
        std::array::from_fn(|_| [rng.byte(), rng.byte(), rng.byte(), 1]),
        std::array::from_fn(|_| [rng.byte(), rng.byte(), rng.byte(), 255]),
    ];
    let mut inputs = Vec::new();
    for sel in [0u8, 4, 8] {
        // F = 4, 8, 12
        let f = 4 + u32::from(sel);
        let max = (1u32 << f) - 1;
        let fracs = [0, 1, 1 << (f - 1), max];
        for voxels in &patterns {
            for fx in fracs {
                for fy in fracs {
                    for fz in fracs {
                        for kernel in KERNELS {
                            for trilinear in [false, true] {
                                inputs.push(CellInput {
                                    voxels: *voxels,
                                    frac: [fx, fy, fz],
                                    frac_bits_sel: sel,
                                    trilinear,
                                    kernel,
                                });
                            }
                        }
                    }
                }
            }
        }
    }
    worst(inputs.into_iter());
}

/// `combine_trilinear` (the SSE2 kernel with the feature `sse2` on x86-64) against
/// `combine` with the 64-bit trilinear weights (the portable kernel), bit for bit, for one `F`:
/// every fraction triple for `F ≤ 5` and a random sample of them above, on random cells
/// (a quarter of the bytes forced to 0 or 255) and on the all-255 cell.
fn combine_trilinear_matches_combine<const F: u32>(rng: &mut Rng, cells: usize) {
    let max = (1u32 << F) - 1;
    let mut compared = 0usize;
    for c in 0..cells {
        let taps: [StraightU8; 8] = if c == 0 {
            [StraightU8([255; 4]); 8]
        } else {
            std::array::from_fn(|_| {
                StraightU8(std::array::from_fn(|_| match rng.next() % 8 {
                    0 => 0,
                    1 => 255,
                    _ => rng.byte(),
                }))
            })
        };
        let mut check = |frac: [u32; 3]| {
            let want = OpacityWeighted.combine(&taps, &IntWeights::trilinear_frac::<F>(frac));
            let got = OpacityWeighted.combine_trilinear::<F>(&taps, frac);
            assert_eq!(got, want, "F = {F}, frac {frac:?}, taps {taps:?}");
            compared += 1;
        };
        if F <= 5 {
            for fz in 0..=max {
                for fy in 0..=max {
                    for fx in 0..=max {
                        check([fx, fy, fz]);
                    }
                }
            }
        } else {
            for _ in 0..4096 {
                let pick = |r: u64| match r % 8 {
                    0 => 0,
                    1 => max,
                    _ => (r >> 8) as u32 & max,
                };
                check([pick(rng.next()), pick(rng.next()), pick(rng.next())]);
            }
        }
    }
    assert!(compared >= cells * 4096, "{compared} comparisons");
}

#[test]
fn trilinear_kernel_is_bit_identical_to_the_weighted_sum() {
    // On x86-64 `combine_trilinear` is the SSE2 kernel (every x86-64 CPU has SSE2), the
    // portable `combine` elsewhere: this compares the two there.
    println!("SSE2 kernel: {}", cfg!(target_arch = "x86_64"));
    let mut rng = Rng::new();
    combine_trilinear_matches_combine::<4>(&mut rng, 16);
    combine_trilinear_matches_combine::<5>(&mut rng, 4);
    combine_trilinear_matches_combine::<6>(&mut rng, 64);
    combine_trilinear_matches_combine::<7>(&mut rng, 64);
    combine_trilinear_matches_combine::<8>(&mut rng, 256);
    combine_trilinear_matches_combine::<9>(&mut rng, 32);
    combine_trilinear_matches_combine::<10>(&mut rng, 32);
    combine_trilinear_matches_combine::<11>(&mut rng, 32);
    combine_trilinear_matches_combine::<12>(&mut rng, 64);
}

#[test]
fn widest_accumulators_at_f12() {
    // All bytes 255 at F = 12 and the fraction with the largest weight products: every sum
    // reaches its proven maximum, and the result is exactly opaque white.
    let voxels = [StraightU8([255; 4]); 8];
    let vol = Volume::new(&voxels, [2, 2, 2]).unwrap();
    for frac in [
        [0, 0, 0],
        [2048, 2048, 2048],
        [4095, 4095, 4095],
        [1, 4095, 2048],
    ] {
        let pos = IntPos::<12>::new([0, 0, 0], frac).unwrap();
        for s in [
            IntSampler::new(vol, OpacityWeighted, Trilinear::new()).sample(pos),
            IntSampler::new(vol, Separate, Trilinear::new()).sample(pos),
        ] {
            assert_eq!((s.c(), s.a()), ([ONE; 3], ONE));
        }
        let assoc = [AssociatedU8([255; 4]); 8];
        let vol = Volume::new(&assoc, [2, 2, 2]).unwrap();
        let s = IntSampler::new(vol, Preweighted, Trilinear::new()).sample(pos);
        assert_eq!((s.c(), s.a()), ([ONE; 3], ONE));
    }
}

#[test]
fn positions_validate_and_clamp() {
    assert!(IntPos::<8>::new([0, 0, 0], [256, 0, 0]).is_err());
    assert!(IntPos::<8>::new([u32::MAX, 0, 0], [0, 0, 0]).is_err());
    assert!(IntPos::<8>::quantize([-1.0, 0.0, 0.0]).is_err());
    assert!(IntPos::<8>::quantize([f32::NAN, 0.0, 0.0]).is_err());
    let p = IntPos::<8>::quantize([1.5, 0.25, 3.0]).unwrap();
    assert_eq!((p.index(), p.frac()), ([1, 0, 3], [128, 64, 0]));
    // Far outside the grid: clamps to the edge voxel like the float kernels.
    let voxels = [
        StraightU8([10, 20, 30, 40]),
        StraightU8([200, 100, 50, 255]),
    ];
    let vol = Volume::new(&voxels, [2, 1, 1]).unwrap();
    let far = IntPos::<8>::from_raw([u32::MAX; 3]);
    let s = IntSampler::new(vol, OpacityWeighted, Trilinear::new()).sample(far);
    assert_eq!(s.to_u8(), [200, 100, 50, 255]);
}
