//! Small unit tests of the portable kernels, each against a value computed independently
//! here (by hand, or by a direct formula in `f64` or exact integers), small enough to run
//! under Miri in a few minutes (`cargo +nightly miri test -p volsample --lib`; README,
//! "Fuzzing"). The host tests hold the exhaustive and randomized comparisons with the f64
//! reference; these are the subset an interpreter can afford.
//!
//! On x86-64 the integer `OpacityWeighted` trilinear sample goes through the SSE2 kernel
//! (`arch::sse2`), so its test here also runs that kernel's `unsafe` entry under Miri.
// Tests may map arrays the standard way (`core/clippy.toml` is about the kernels' IR).
#![allow(clippy::disallowed_methods)]

use crate::arch::Isa;
use crate::composite::{back_to_front, front_to_back, over};
use crate::downsample::integer::{downsample_level_int, IntFilter4, IntOpacityBased};
use crate::downsample::{
    chain_len, downsample_level, level_count, level_dims, level_offset, Filter4, OpacityBased,
};
use crate::error::Error;
use crate::fixed_point::{
    self, composite_front_to_back, nearest_index, premultiply, round_half_up_div,
    round_half_up_shift, unpremultiply, IntPos, IntSample, IntSampler, IntStop, ONE,
};
use crate::lanes::{F32x4, Lanes};
use crate::opacity::{correct, phi};
use crate::ray::Ray;
use crate::render::{RayMarcher, Step};
use crate::sample::Sample;
use crate::volume::Volume;
use crate::voxel::{AssociatedF32, AssociatedU8, ExtinctionF32, StraightU8};
use crate::{
    BackToFront, ExtinctionWeighted, FrontToBack, IntRayMarcher, Nearest, OpacityWeighted,
    Separate, Threshold, Trilinear, TriquadraticBSpline,
};

/// xorshift64: deterministic test data from `seed` (not 0).
fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

/// `|got − want| ≤ tol` for `f32` results against `f64` values.
fn close(got: f32, want: f64, tol: f64) -> bool {
    (f64::from(got) - want).abs() <= tol
}

/// A byte as the unit-range value it stands for, in `f64`.
fn unit(n: u8) -> f64 {
    f64::from(n) / 255.0
}

// ---------------------------------------------------------------------------------------
// Float compositing

#[test]
fn front_to_back_and_back_to_front_steps_by_hand() {
    // Dyadic values, so every operation is exact and the results are the formulas'.
    let acc = Sample {
        c: [0.25, 0.125, 0.0],
        a: 0.5,
    };
    let s = Sample {
        c: [0.5, 0.25, 0.75],
        a: 0.75,
    };
    // C + (1 − A)·C̃_s, A + (1 − A)·α_s.
    assert_eq!(
        front_to_back(acc, s),
        Sample {
            c: [0.5, 0.25, 0.375],
            a: 0.875
        }
    );
    // `s` in front of `acc`: C̃_s + (1 − α_s)·C, α_s + (1 − α_s)·A.
    assert_eq!(
        back_to_front(acc, s),
        Sample {
            c: [0.5625, 0.28125, 0.75],
            a: 0.875
        }
    );
    assert_eq!(over(acc, s), front_to_back(acc, s));
    // Three samples in either order give the same composite (exact here).
    let t = Sample {
        c: [0.0, 0.5, 0.25],
        a: 0.5,
    };
    let f = front_to_back(front_to_back(front_to_back(Sample::TRANSPARENT, acc), s), t);
    let b = back_to_front(back_to_front(back_to_front(Sample::TRANSPARENT, t), s), acc);
    assert_eq!(f, b);
    // 1 − A is the product of the transmittances: (1 − ½)(1 − ¾)(1 − ½) = 1/16.
    assert_eq!(f.a, 1.0 - 0.0625);
}

#[test]
fn thresholds_and_clamps() {
    assert_eq!(Threshold::new(0.0), Err(Error::InvalidThreshold));
    assert_eq!(Threshold::new(1.5), Err(Error::InvalidThreshold));
    assert_eq!(Threshold::new(f32::NAN), Err(Error::InvalidThreshold));
    assert_eq!(Threshold::new(1.0).map(|t| t.a_stop()), Ok(1.0));
    // α into [0, 1], each channel into [0, α], NaN to 0.
    let s = Sample::clamped([f32::NAN, -0.5, 0.75], 0.5);
    assert_eq!(
        s,
        Sample {
            c: [0.0, 0.0, 0.5],
            a: 0.5
        }
    );
    assert_eq!(Sample::clamped([2.0; 3], 1.5).a, 1.0);
    assert_eq!(
        Sample {
            c: [0.25, 0.125, 0.0],
            a: 0.5
        }
        .straight_color(),
        [0.5, 0.25, 0.0]
    );
    assert_eq!(Sample::TRANSPARENT.straight_color(), [0.0; 3]);
}

// ---------------------------------------------------------------------------------------
// Lanes

#[test]
fn f32x4_lanes_are_the_scalar_operations() {
    let a = [1.5f32, -2.0, f32::NAN, 0.3];
    let b = [0.25f32, 3.0, 1.0, 0.7];
    let (x, y) = (F32x4::from_array(a), F32x4::from_array(b));
    let lane = |v: F32x4, l: usize| v.to_array().get(l).copied().unwrap_or(f32::NAN);
    let sum = x + y;
    let diff = x - y;
    let prod = x * y;
    let clamped = x.clamp_to(F32x4::splat(1.0));
    let less = x.lt(y);
    let sel = F32x4::select(less, x, y);
    // x.max(0).min(1) per lane: 1.5 → 1, −2 → 0, NaN → 0.
    let clamped_want = [1.0f32, 0.0, 0.0, 0.3];
    // The same bits, or NaN for NaN: Rust leaves a NaN result's sign and payload
    // unspecified (Miri picks them at random), so only NaN-ness can be compared.
    let same = |g: f32, w: f32| g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan());
    for (l, ((&p, &q), &c)) in a.iter().zip(b.iter()).zip(clamped_want.iter()).enumerate() {
        assert!(same(lane(sum, l), p + q), "lane {l}");
        assert!(same(lane(diff, l), p - q), "lane {l}");
        assert!(same(lane(prod, l), p * q), "lane {l}");
        assert_eq!(lane(clamped, l), c, "lane {l}");
        let m = less.get(l).copied().unwrap_or(true);
        assert_eq!(m, p < q, "lane {l}");
        let want = if p < q { p } else { q };
        assert!(same(lane(sel, l), want), "lane {l}");
    }
    assert!(!F32x4::all(less));
    assert!(F32x4::all(F32x4::splat(0.0).lt(F32x4::splat(1.0))));
    assert_eq!(
        F32x4::gather([1u8, 2, 3, 4], |n| f32::from(n) * 0.5).to_array(),
        [0.5, 1.0, 1.5, 2.0]
    );
}

// ---------------------------------------------------------------------------------------
// Volumes and float filters

#[test]
fn volume_validation_and_addressing() -> Result<(), Error> {
    let data: [StraightU8; 12] = core::array::from_fn(|i| StraightU8([i as u8, 0, 0, 255]));
    assert_eq!(
        Volume::new(&data, [3, 0, 4]).err(),
        Some(Error::ZeroDimension { axis: 1 })
    );
    assert_eq!(
        Volume::new(&data, [2, 2, 2]).err(),
        Some(Error::LengthMismatch {
            expected: 8,
            actual: 12
        })
    );
    let bad = [AssociatedU8([0, 0, 0, 0]), AssociatedU8([10, 0, 0, 5])];
    assert_eq!(
        Volume::new(&bad, [2, 1, 1]).err(),
        Some(Error::ColorExceedsOpacity { index: 1 })
    );
    // x fastest, then y, then z: (x, y, z) is voxel x + 3·(y + 2·z).
    let vol = Volume::new(&data, [3, 2, 2])?;
    let red = |v: Option<StraightU8>| v.map(|v| v.0[0]);
    assert_eq!(red(vol.get(2, 1, 1)), Some(11));
    assert_eq!(red(vol.get(1, 0, 1)), Some(7));
    assert_eq!(red(vol.get(3, 0, 0)), None);
    // Clamp to the edge.
    assert_eq!(vol.fetch_clamped(-4, 7, 1).0[0], 9);
    assert_eq!(vol.clamp_index([-1, 1, 9]), [0, 1, 1]);
    // Tap i at (x + (i & 1), y + ((i >> 1) & 1), z + (i >> 2)).
    let reds = |c: [StraightU8; 8]| c.map(|v| v.0[0]);
    assert_eq!(
        vol.cell(1, 0, 0).map(reds),
        Some([1, 2, 4, 5, 7, 8, 10, 11])
    );
    assert_eq!(vol.cell(2, 0, 0).map(reds), None);
    assert_eq!(reds(vol.cell_clamped(2, 1, 1)), [11; 8]);
    assert_eq!(reds(vol.cell_clamped(1, 0, 0)), [1, 2, 4, 5, 7, 8, 10, 11]);
    Ok(())
}

#[test]
fn float_trilinear_weights_are_the_products() {
    let f = [0.25f32, 0.5, 0.75];
    let w = crate::filter::trilinear_weights(f);
    let mut sum = 0.0;
    for (i, &wi) in w.iter().enumerate() {
        let pick = |axis: usize, bit: usize| {
            let t = f64::from(f.get(axis).copied().unwrap_or(0.0));
            if (i >> bit) & 1 == 1 {
                t
            } else {
                1.0 - t
            }
        };
        // Dyadic fractions: every weight is exact.
        assert_eq!(
            f64::from(wi),
            pick(0, 0) * pick(1, 1) * pick(2, 2),
            "w[{i}]"
        );
        sum += wi;
    }
    assert_eq!(sum, 1.0);
}

/// Eight straight voxels of a 2×2×2 cell with distinct colors and opacities.
const CELL: [StraightU8; 8] = [
    StraightU8([255, 0, 0, 255]),
    StraightU8([0, 255, 0, 128]),
    StraightU8([0, 0, 255, 64]),
    StraightU8([255, 255, 0, 0]),
    StraightU8([10, 20, 30, 200]),
    StraightU8([200, 100, 50, 32]),
    StraightU8([90, 180, 45, 16]),
    StraightU8([255, 255, 255, 255]),
];

/// The trilinear weight of tap `i` at fractions `f`, in `f64`.
fn weight(i: usize, f: [f64; 3]) -> f64 {
    f.iter()
        .enumerate()
        .map(|(axis, &t)| if (i >> axis) & 1 == 1 { t } else { 1.0 - t })
        .product()
}

#[test]
fn float_modes_sample_the_weighted_sums() -> Result<(), Error> {
    let vol = Volume::new(&CELL, [2, 2, 2])?;
    let step = Step::new(1.0)?; // d = d′: no correction
    let ow = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )?;
    let tree = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::tree(),
        FrontToBack::new(),
        step,
    )?;
    let sep = RayMarcher::new(vol, Separate, Trilinear::new(), FrontToBack::new(), step)?;
    for pos in [
        [0.25f32, 0.5, 0.75],
        [0.9, 0.1, 0.4],
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 0.5],
    ] {
        let f = pos.map(f64::from);
        // OpacityWeighted: ω = w·α, α = Σ ω, C̃ = Σ ω·C.
        let mut ow_a = 0.0;
        let mut ow_c = [0.0f64; 3];
        // Separate: α = Σ w·α, C = Σ w·C, C̃ = α·C.
        let mut sep_a = 0.0;
        let mut sep_c = [0.0f64; 3];
        for (i, v) in CELL.iter().enumerate() {
            let w = weight(i, f);
            let [r, g, b, a] = v.0;
            ow_a += w * unit(a);
            sep_a += w * unit(a);
            for ((o, s), c) in ow_c.iter_mut().zip(sep_c.iter_mut()).zip([r, g, b]) {
                *o += w * unit(a) * unit(c);
                *s += w * unit(c);
            }
        }
        let tol = 1.0e-6;
        for (m, name) in [(ow.sample(pos), "weighted sum"), (tree.sample(pos), "tree")] {
            assert!(close(m.a, ow_a, tol), "{pos:?} {name}: {} vs {ow_a}", m.a);
            for (got, want) in m.c.iter().zip(ow_c) {
                assert!(close(*got, want, tol), "{pos:?} {name}: {got} vs {want}");
            }
        }
        let s = sep.sample(pos);
        assert!(close(s.a, sep_a, tol), "{pos:?}: {} vs {sep_a}", s.a);
        for (got, want) in s.c.iter().zip(sep_c) {
            assert!(close(*got, sep_a * want, tol), "{pos:?}: {got}");
        }
    }
    Ok(())
}

#[test]
fn nearest_rounds_half_up_and_the_bspline_reproduces_constants() -> Result<(), Error> {
    let step = Step::new(1.0)?;
    let vol = Volume::new(&CELL, [2, 2, 2])?;
    let near = RayMarcher::new(vol, OpacityWeighted, Nearest, FrontToBack::new(), step)?;
    // ⌊x + ½⌋ per axis: (0.5, 0.49, 0.5) is voxel (1, 0, 1), index 5.
    let s = near.sample([0.5, 0.49, 0.5]);
    let want = Sample {
        c: [200.0 / 255.0, 100.0 / 255.0, 50.0 / 255.0].map(|c: f64| (c * 32.0 / 255.0) as f32),
        a: (32.0f64 / 255.0) as f32,
    };
    assert!(close(s.a, f64::from(want.a), 1.0e-7));
    for (g, w) in s.c.iter().zip(want.c) {
        assert!(close(*g, f64::from(w), 1.0e-7), "{g} vs {w}");
    }
    // Constant data: the 27 B-spline weights are an exact partition of unity.
    let same = [StraightU8([255, 0, 0, 255]); 27];
    let vol = Volume::new(&same, [3, 3, 3])?;
    let bs = RayMarcher::new(
        vol,
        OpacityWeighted,
        TriquadraticBSpline,
        FrontToBack::new(),
        step,
    )?;
    for pos in [[1.0f32, 1.0, 1.0], [0.3, 1.7, 2.2]] {
        assert_eq!(
            bs.sample(pos),
            Sample {
                c: [1.0, 0.0, 0.0],
                a: 1.0
            }
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Opacity correction and extinction

#[test]
fn opacity_correction_is_the_power_law() {
    // α_d = 1 − (1 − α)^r, C̃_d = C̃·α_d/α (the straight color kept), both paths of
    // `correct` (x = −r·ln(1 − α) below 1, and from 1 on).
    for (a, r) in [(0.25f64, 0.5f64), (0.5, 2.0), (0.9, 2.0), (0.01, 3.0)] {
        let s = Sample {
            c: [(a * 0.5) as f32, (a * 0.25) as f32, 0.0],
            a: a as f32,
        };
        let got = correct(s, r as f32);
        // From the `f32` input; within 8 ulp of 1 (times max(1, r) for C̃) by its doc.
        let a_d = 1.0 - libm::pow(1.0 - f64::from(s.a), r);
        let tol = 8.0 * f64::from(f32::EPSILON) * r.max(1.0);
        assert!(close(got.a, a_d, tol), "α {a}, r {r}: {} vs {a_d}", got.a);
        for (g, straight) in got.c.iter().zip([0.5, 0.25, 0.0]) {
            assert!(close(*g, straight * a_d, tol), "α {a}, r {r}: {g}");
        }
    }
    // The edges: transparent stays transparent, opaque stays opaque.
    assert_eq!(correct(Sample::TRANSPARENT, 2.0), Sample::TRANSPARENT);
    let opaque = Sample {
        c: [0.5, 0.0, 1.0],
        a: 1.0,
    };
    assert_eq!(correct(opaque, 0.5), opaque);
}

#[test]
fn phi_is_one_minus_exp_over_x() {
    for x in [1.0e-6f64, 1.0e-3, 0.5, 1.0, 3.0, 20.0] {
        let want = -libm::expm1(-x) / x;
        let got = phi(x as f32);
        assert!(
            close(got, want, 4.0 * f64::from(f32::EPSILON) * want),
            "φ({x}) = {got}, not {want}"
        );
    }
}

#[test]
fn extinction_step_of_a_constant_medium() {
    // One step of length d through constant τ and color C: α = 1 − e^(−τd), C̃ = C·α
    // (C^τ = τ·C), both sides of τd = 1.
    for (tau, d) in [(0.5f64, 0.5f64), (2.0, 0.75), (6.0, 1.0)] {
        let color = [0.5f64, 1.0, 0.25];
        let s = crate::mode::integrate_step(color.map(|c| (tau * c) as f32), tau as f32, d as f32);
        let a = -libm::expm1(-tau * d);
        assert!(close(s.a, a, 1.0e-6), "τ {tau}, d {d}: {} vs {a}", s.a);
        for (g, c) in s.c.iter().zip(color) {
            assert!(close(*g, c * a, 1.0e-6), "τ {tau}, d {d}: {g} vs {}", c * a);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Ray marching (float)

/// Four straight voxels along z, one per sample of the rays below.
const COLUMN: [StraightU8; 4] = [
    StraightU8([200, 100, 50, 64]),
    StraightU8([10, 250, 128, 128]),
    StraightU8([255, 0, 0, 32]),
    StraightU8([0, 0, 255, 255]),
];

/// The exact emission–absorption composite of `COLUMN`'s voxels in order, front to back:
/// `A = 1 − Π(1 − α_j)`, `C = Σ_j T_j·α_j·C_j` with `T_j = Π_(k<j)(1 − α_k)`.
fn column_composite() -> ([f64; 3], f64) {
    let mut t = 1.0;
    let mut c = [0.0f64; 3];
    for v in COLUMN {
        let [r, g, b, a] = v.0;
        for (acc, x) in c.iter_mut().zip([r, g, b]) {
            *acc += t * unit(a) * unit(x);
        }
        t *= 1.0 - unit(a);
    }
    (c, 1.0 - t)
}

#[test]
fn float_marcher_composites_the_column() -> Result<(), Error> {
    // A ray along z through the voxel centres of a 1×1×4 column: the box is z ∈ [−½, 3½],
    // so with d = 1 the samples are at z = 0, 1, 2, 3 (four consecutive samples: one
    // `F32x4` batch of `cast` on SIMD targets).
    let vol = Volume::new(&COLUMN, [1, 1, 4])?;
    let step = Step::new(1.0)?;
    let ray = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0])?;
    let (c, a) = column_composite();
    let ftb = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )?;
    let btf = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), BackToFront, step)?;
    assert_eq!(ftb.sample_range(&ray), (1.0, 4));
    let (f, n) = ftb.cast_counted(&ray);
    assert_eq!(n, 4);
    for got in [f, btf.cast(&ray)] {
        assert!(close(got.a, a, 1.0e-6), "{} vs {a}", got.a);
        for (g, w) in got.c.iter().zip(c) {
            assert!(close(*g, w, 1.0e-6), "{g} vs {w}");
        }
    }
    // Early termination: the first two samples reach A = 1 − (1 − 64/255)(1 − 128/255)
    // ≈ 0.627 ≥ 0.6, so the ray stops after two.
    let stop = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::with_threshold(0.6)?,
        step,
    )?;
    let (s, n) = stop.cast_counted(&ray);
    assert_eq!(n, 2);
    let two = 1.0 - (1.0 - unit(64)) * (1.0 - unit(128));
    assert!(close(s.a, two, 1.0e-6), "{} vs {two}", s.a);
    // Over a background B: C + (1 − A)·B.
    let bg = Sample {
        c: [0.0, 0.0, 0.5],
        a: 0.5,
    };
    let with_bg = ftb.with_background(bg)?.cast(&ray);
    assert!(close(with_bg.a, a + (1.0 - a) * 0.5, 1.0e-6));
    let blue = c.get(2).copied().unwrap_or(0.0) + (1.0 - a) * 0.5;
    assert!(close(with_bg.c[2], blue, 1.0e-6));
    Ok(())
}

#[test]
fn packets_are_single_rays_bit_for_bit() -> Result<(), Error> {
    // Five oblique rays through a 3×3×3 volume: one packet of four and a tail of one in
    // `cast_rays`, `cast4` on the first four; each must equal `cast` of its ray.
    let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
    let voxels: [StraightU8; 27] = core::array::from_fn(|_| {
        let [r, g, b, a, ..] = next().to_le_bytes();
        StraightU8([r, g, b, a])
    });
    let vol = Volume::new(&voxels, [3, 3, 3])?;
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.7)?,
    )?;
    let rays = [
        Ray::new([0.2, 0.1, -1.0], [0.1, 0.2, 1.0])?,
        Ray::new([1.0, 1.5, -1.0], [0.0, 0.0, 1.0])?,
        Ray::new([-1.0, 0.3, 0.9], [1.0, 0.3, 0.1])?,
        Ray::new([2.4, 2.1, 3.0], [-0.2, -0.5, -1.0])?,
        Ray::new([0.5, -1.0, 1.5], [0.05, 1.0, 0.2])?,
    ];
    let mut out = [Sample::TRANSPARENT; 5];
    m.cast_rays(&rays, &mut out)?;
    for (r, o) in rays.iter().zip(out) {
        assert_eq!(o, m.cast(r));
        assert!(o.is_valid());
    }
    // Every instruction set this machine has (under Miri: AVX2 where the run enables it)
    // gives the baseline's results.
    let base = m.with_isa(Isa::BASELINE);
    for isa in Isa::available() {
        let mut got = [Sample::TRANSPARENT; 5];
        m.with_isa(isa).cast_rays(&rays, &mut got)?;
        for (r, g) in rays.iter().zip(got) {
            assert_eq!(g, base.cast(r), "{isa}");
            assert_eq!(m.with_isa(isa).cast(r), g, "{isa}");
        }
    }
    let four = [rays[0], rays[1], rays[2], rays[3]];
    for (r, got) in four.iter().zip(m.cast4(&four)) {
        assert_eq!(got, m.cast_counted(r));
    }
    assert_eq!(
        m.cast_rays(&rays, &mut [Sample::TRANSPARENT; 4]),
        Err(Error::ImageSizeMismatch {
            expected: 5,
            actual: 4
        })
    );
    Ok(())
}

#[test]
fn extinction_marcher_of_a_constant_medium() -> Result<(), Error> {
    // Constant τ and C^τ = τ·C: the ray's composite is α = 1 − e^(−τ·n·d), C̃ = C·α, however
    // the steps split it.
    let (tau, color) = (0.8f32, [0.5f32, 0.25, 1.0]);
    let voxels = [ExtinctionF32 {
        c_tau: color.map(|c| tau * c),
        tau,
    }; 8];
    let vol = Volume::new(&voxels, [2, 2, 2])?;
    let m = RayMarcher::new(
        vol,
        ExtinctionWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.5)?,
    )?;
    let ray = Ray::new([0.5, 0.5, -1.0], [0.0, 0.0, 1.0])?;
    let (s, n) = m.cast_counted(&ray);
    assert_eq!(n, 4); // z ∈ [−½, 1½], d = ½: t = ½, 1, 1½, 2 (z = −½ … 1)
    let a = -libm::expm1(-f64::from(tau) * 0.5 * f64::from(n));
    assert!(close(s.a, a, 2.0e-6), "{} vs {a}", s.a);
    for (g, c) in s.c.iter().zip(color) {
        assert!(close(*g, f64::from(c) * a, 2.0e-6), "{g}");
    }
    Ok(())
}

/// The trilinear split's `⌊x⌋` (`filter::floor`, which replaced `libm::floorf` there) is
/// `libm::floorf` bit for bit at every `f32`: all 2³² bit patterns, signed zeros, subnormals,
/// infinities and NaNs included.
#[test]
#[cfg_attr(
    miri,
    ignore = "exhaustive (every f32): too slow for Miri; runs natively in `cargo test`"
)]
fn floor_is_floorf_at_every_f32() {
    let mismatches = (0..=u32::MAX)
        .filter(|&bits| {
            let x = f32::from_bits(bits);
            crate::filter::floor(x).to_bits() != libm::floorf(x).to_bits()
        })
        .count();
    assert_eq!(mismatches, 0);
}

mod integer;
