//! The integer kernels and downsampling, against values computed independently here.

use super::*;

// ---------------------------------------------------------------------------------------
// Fixed point

#[test]
fn integer_roundings_by_hand() {
    // ⌊n/d + ½⌋: 2.5 → 3, 2.33… → 2, 2.66… → 3; d = 0 gives 0.
    assert_eq!(round_half_up_div(5, 2), 3);
    assert_eq!(round_half_up_div(7, 3), 2);
    assert_eq!(round_half_up_div(8, 3), 3);
    assert_eq!(round_half_up_div(8, 0), 0);
    // ⌊n/2^s + ½⌋: 1.5 → 2, 1.25 → 1.
    assert_eq!(round_half_up_shift(6, 2), 2);
    assert_eq!(round_half_up_shift(5, 2), 1);
    assert_eq!(round_half_up_shift(5, 0), 5);
    // Nearest index ⌊raw/256 + ½⌋.
    assert_eq!(nearest_index::<8>(127), 0);
    assert_eq!(nearest_index::<8>(128), 1);
    assert_eq!(nearest_index::<8>(383), 1);
    assert_eq!(nearest_index::<8>(384), 2);
    assert_eq!(nearest_index::<8>(u32::MAX), 1 << 24);
}

#[test]
fn integer_trilinear_weights_are_the_exact_products() {
    let f = [64u32, 128, 192];
    let w = fixed_point::trilinear_weights::<8>(f);
    let mut sum = 0u64;
    for (i, &wi) in w.iter().enumerate() {
        let want: u64 = f
            .iter()
            .enumerate()
            .map(|(axis, &t)| {
                if (i >> axis) & 1 == 1 {
                    u64::from(t)
                } else {
                    256 - u64::from(t)
                }
            })
            .product();
        assert_eq!(wi, want, "w[{i}]");
        sum += wi;
    }
    assert_eq!(sum, 1 << 24);
    // By hand: the low corner (192·128·64) and the high one (64·128·192) are equal here.
    assert_eq!(w.first(), Some(&1_572_864));
    assert_eq!(w.last(), Some(&1_572_864));
}

#[test]
fn premultiplication_rounds_half_up() {
    // By hand: 100·51/255 = 20 exactly; 1·128/255 = 0.502 → 1; 1·127/255 = 0.498 → 0.
    assert_eq!(premultiply(100, 51), 20);
    assert_eq!(premultiply(1, 128), 1);
    assert_eq!(premultiply(1, 127), 0);
    assert_eq!(unpremultiply(20, 51), 100);
    assert_eq!(unpremultiply(9, 0), 0);
    assert_eq!(unpremultiply(60, 50), 255); // C̃ > α saturates
                                            // Against ⌊x + ½⌋ of the exact quotient in f64, on a grid of bytes.
    let round = |x: f64| libm::floor(x + 0.5) as u32;
    for c in (0..=255u8).step_by(15) {
        for a in (0..=255u8).step_by(5) {
            let p = premultiply(c, a);
            assert_eq!(u32::from(p), round(f64::from(c) * f64::from(a) / 255.0));
            if a > 0 {
                let u = round(255.0 * f64::from(p) / f64::from(a)).min(255);
                assert_eq!(u32::from(unpremultiply(p, a)), u, "c {c}, a {a}");
            }
        }
    }
}

/// The integer `OpacityWeighted` trilinear sample from its definition, in `u128`:
/// `α = ⌊256·S_α/2^24 + ½⌋`, `C̃ = ⌊256·S_c/(255·2^24) + ½⌋` with `S_α = Σ w·α`,
/// `S_c = Σ w·α·C` and `w` the products of `(256 − f, f)` per axis (F = 8); taps clamped to
/// the edge.
fn int_ow_model(vol: &[StraightU8], dims: [usize; 3], raw: [u32; 3]) -> ([u16; 3], u16) {
    let idx = raw.map(|r| (r >> 8) as usize);
    let frac = raw.map(|r| u128::from(r & 255));
    let (mut s_a, mut s_c) = (0u128, [0u128; 3]);
    for i in 0..8 {
        let mut w = 1u128;
        let mut at = [0usize; 3];
        for axis in 0..3 {
            let bit = (i >> axis) & 1;
            let (n, k, f) = (
                dims.get(axis).copied().unwrap_or(1),
                idx.get(axis).copied().unwrap_or(0),
                frac.get(axis).copied().unwrap_or(0),
            );
            if let Some(a) = at.get_mut(axis) {
                *a = (k + bit).min(n - 1);
            }
            w *= if bit == 1 { f } else { 256 - f };
        }
        let [nx, ny, _] = dims;
        let [x, y, z] = at;
        let [r, g, b, a] = vol.get(x + nx * (y + ny * z)).map_or([0; 4], |v| v.0);
        let omega = w * u128::from(a);
        s_a += omega;
        for (s, c) in s_c.iter_mut().zip([r, g, b]) {
            *s += omega * u128::from(c);
        }
    }
    let shift = 1u128 << 24;
    let alpha = (2 * 256 * s_a + shift) / (2 * shift);
    let color = s_c.map(|s| ((2 * 256 * s + 255 * shift) / (2 * 255 * shift)) as u16);
    (color, alpha as u16)
}

#[test]
fn integer_opacity_weighted_trilinear_is_its_definition() -> Result<(), Error> {
    let mut next = xorshift(0x2545_F491_4F6C_DD1D);
    let dims = [3usize, 3, 2];
    let mut voxels = [StraightU8([0; 4]); 18];
    for v in &mut voxels {
        let [r, g, b, a, ..] = next().to_le_bytes();
        *v = StraightU8([r, g, b, a]);
    }
    // The widest sums: every byte 255 in one corner of the grid.
    if let Some(v) = voxels.last_mut() {
        *v = StraightU8([255; 4]);
    }
    let vol = Volume::new(&voxels, dims)?;
    let sampler = IntSampler::new(vol, OpacityWeighted, Trilinear::new());
    let mut positions = [[0u32; 3]; 24];
    for p in positions.iter_mut() {
        *p = [
            next() as u32 % 768,
            next() as u32 % 768,
            next() as u32 % 512,
        ];
    }
    // Fractions 0, ½ and 255/256, the last voxel, and beyond the grid (clamped).
    let edges = [
        [0, 0, 0],
        [128, 128, 128],
        [255, 255, 255],
        [512, 512, 256],
        [767, 600, 400],
        [2000, 1, 1000],
    ];
    for raw in positions.iter().chain(edges.iter()) {
        let got = sampler.sample(IntPos::<8>::from_raw(*raw));
        let (c, a) = int_ow_model(&voxels, dims, *raw);
        assert_eq!((got.c(), got.a()), (c, a), "raw {raw:?}");
    }
    Ok(())
}

#[test]
fn integer_compositing_by_hand() -> Result<(), Error> {
    let half = IntSample::new([ONE / 2, ONE / 4, 0], ONE / 2)?;
    // From transparent, T = ONE: the sample itself.
    let one = fixed_point::front_to_back(IntSample::TRANSPARENT, half);
    assert_eq!(one, half);
    // T = ONE/2: A = ONE/2 + ⌊(ONE/2)²/ONE + ½⌋ = 32640 + 16320 = ¾·ONE exactly, and the
    // colors 32640 + 16320 and 16320 + 8160.
    let two = fixed_point::front_to_back(one, half);
    assert_eq!((two.c(), two.a()), ([48_960, 24_480, 0], 48_960));
    // Stopping at A ≥ 40000: after two samples.
    let (acc, used) = composite_front_to_back([half; 5], IntStop::new(40_000)?);
    assert_eq!((acc, used), (two, 2));
    let (acc, used) = composite_front_to_back([half; 3], IntStop::NEVER);
    assert_eq!(used, 3);
    // A: 1 − ⅛ of ONE = 57120; C: 48960 + 8160 and 24480 + 4080 (every quotient T·x/ONE
    // here is an integer, so each rounding is exact).
    assert_eq!((acc.c(), acc.a()), ([57_120, 28_560, 0], 57_120));
    // Behind α = ONE/3 (T = 43520), α = 100 adds ⌊66.67 + ½⌋ = 67 and α = 98 adds
    // ⌊65.33 + ½⌋ = 65 (round half up, not truncation).
    let third = fixed_point::front_to_back(IntSample::TRANSPARENT, IntSample::new([0; 3], 21_760)?);
    let s = fixed_point::front_to_back(third, IntSample::new([100, 98, 0], 100)?);
    assert_eq!((s.c(), s.a()), ([67, 65, 0], 21_827));
    assert_eq!(IntSample::new([1, 0, 0], 0), Err(Error::InvalidIntSample));
    // Bytes ⌊raw/256 + ½⌋: 223.125 → 223, 111.56 → 112.
    assert_eq!(acc.to_u8(), [223, 112, 0, 223]);
    Ok(())
}

#[test]
fn integer_marcher_is_within_its_bound_of_the_exact_composite() -> Result<(), Error> {
    // As the float column test: four samples at the voxel centres, each exactly the voxel
    // (α = 256·a, C̃ = ⌊256·a·C/255 + ½⌋); the composite within ½ LSB per step for A and 1
    // LSB per step for C of the exact one (`fixed_point::composite`).
    let vol = Volume::new(&COLUMN, [1, 1, 4])?;
    let m = IntRayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        Step::new(1.0)?,
    )?;
    let ray = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0])?;
    let (s, n) = m.cast_counted(&ray);
    assert_eq!(n, 4);
    let (c, a) = column_composite();
    let lsb = |x: u16| f64::from(x) / f64::from(ONE);
    let step = 1.0 / f64::from(ONE);
    assert!(
        (lsb(s.a()) - a).abs() <= 4.0 * 0.5 * step + 1e-12,
        "{}",
        s.a()
    );
    // The samples' own rounding (½ LSB each) adds at most 4·½ more to C.
    for (g, w) in s.c().iter().zip(c) {
        assert!((lsb(*g) - w).abs() <= 4.0 * 1.5 * step, "{g} vs {w}");
    }
    // Nine parallel rays across the column (x and y clamp to its one voxel, so each ray
    // composites the same four voxels): one packet of eight in AVX2 lanes where the
    // instruction set is available, and a tail; every instruction set gives `s`.
    let mut rays = [ray; 9];
    for (k, r) in rays.iter_mut().enumerate() {
        let off = k as f32 * 0.1 - 0.4;
        *r = Ray::new([off, -off, -1.0], [0.0, 0.0, 1.0])?;
    }
    for isa in Isa::available() {
        let mut out = [IntSample::TRANSPARENT; 9];
        m.clone().with_isa(isa).cast_rays(&rays, &mut out)?;
        assert_eq!(out, [s; 9], "{isa}");
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Downsampling

#[test]
fn pyramid_dimensions_by_hand() {
    assert_eq!(level_dims([5, 3, 1], 1), [3, 2, 1]);
    assert_eq!(level_dims([5, 3, 1], 3), [1, 1, 1]);
    assert_eq!(level_count([5, 3, 1]), 4); // 5 → 3 → 2 → 1
    assert_eq!(level_count([1, 1, 1]), 1);
    assert_eq!(level_offset([4, 4, 4], 1), 0);
    assert_eq!(level_offset([4, 4, 4], 2), 8);
    assert_eq!(chain_len([4, 4, 4]), 9); // 2³ + 1³
}

#[test]
fn opacity_based_levels_of_a_half_filled_cell() -> Result<(), Error> {
    // 2×2×2 → 1×1×1 with the 2-tap box: the mean of the eight voxels, then the doubled
    // length α′ = ᾱ·(2 − ᾱ), C̃′ = C̄·(2 − ᾱ). Four voxels at α = ½, C̃ = ¼, four empty:
    // ᾱ = ¼, C̄ = ⅛, so α′ = 7/16 and C̃′ = 7/32 (exact in f32).
    let full = AssociatedF32 {
        c: [0.25, 0.25, 0.0],
        a: 0.5,
    };
    let empty = AssociatedF32 {
        c: [0.0; 3],
        a: 0.0,
    };
    let fine = [full, empty, empty, full, full, empty, empty, full];
    let src = Volume::new(&fine, [2, 2, 2])?;
    let mut dst = [empty; 1];
    let coarse = downsample_level(OpacityBased, Filter4::box2(), &src, &mut dst)?;
    assert_eq!(coarse.dims(), [1, 1, 1]);
    assert_eq!(
        dst,
        [AssociatedF32 {
            c: [0.21875, 0.21875, 0.0],
            a: 0.4375
        }]
    );
    assert_eq!(
        downsample_level(OpacityBased, Filter4::box2(), &src, &mut [empty; 2]).err(),
        Some(Error::OutputLengthMismatch {
            expected: 1,
            actual: 2
        })
    );
    // Integer: four voxels (100, 50, 0, α 200), four empty: ᾱ = 100, C̄ = (50, 25, 0), then
    // α′ = ⌊ᾱ·(510 − ᾱ)/255 + ½⌋ = ⌊160.78 + ½⌋ = 161, C̃′ = ⌊C̄·(510 − ᾱ)/255 + ½⌋ = 80, 40, 0.
    let v = AssociatedU8([100, 50, 0, 200]);
    let z = AssociatedU8([0; 4]);
    let fine = [v, z, z, v, v, z, z, v];
    let mut dst = [z; 1];
    let dims = downsample_level_int(
        IntOpacityBased,
        IntFilter4::box2(),
        &fine,
        [2, 2, 2],
        &mut dst,
    )?;
    assert_eq!(dims, [1, 1, 1]);
    assert_eq!(dst, [AssociatedU8([80, 40, 0, 161])]);
    Ok(())
}
